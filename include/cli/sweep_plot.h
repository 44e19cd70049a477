/* sweep_plot.h: the figure of a sweep (--plot X:Y --png/--svg): a measure
 * against a varied key, one curve per combination of the other varied
 * keys' values, with its data beside it (FILE.png -> FILE.csv); and the
 * figures of `rodsim figure` drawn from several sweeps with their reference
 * curves (figure.h: figure_spec). */
#ifndef RODSIM_SWEEP_PLOT_H
#define RODSIM_SWEEP_PLOT_H

#include <stddef.h>

#include "cli/sweep_spec.h"
#include "study/figure.h"

/* One curve per combination of the other varied keys' values (in point
 * order), the points that are ok, sorted by x; the PNG and/or SVG of
 * parts[0] and its data (curve,X,Y) beside it. With a figure (fig not
 * NULL) the curves of all parts, with the figure's title and labels, values
 * scaled to its units, each curve's reference line beside its points (the
 * data get a reference column, part_reference[k][point]), its own marks,
 * and a ratio figure when it has one. fig and part_reference may be NULL.
 * Written through outfile.h (the caller's transaction). 0, or -1 with a
 * message. */
int sweep_plot_write(const sweep *const *parts, const sweep_point_result *const *part_rows,
                     int part_count, const figure_spec *fig,
                     const double *const *part_reference, char *err, size_t errlen);

/* A figure's ratio figure beside FILE.png: FILE_ratio.png (or .svg). */
void sweep_ratio_path(const char *figure, char *out, size_t n);

#endif
