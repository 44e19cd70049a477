/* needle_grasp.h: the needle handed between instruments (scene
 * [needle_grasp]). Before the first grasp the needle holder with
 * needle = yes holds the needle at its jaws' tip; from a grasp's time t the
 * named instrument's jaws hold it, keeping the needle's pose relative to
 * them as it was at t (the needle's pose continuous, the scene's paths
 * bring the jaws onto it). The thread's tip, the needle's back, follows
 * the needle: the model's tip_motion is handed over (sim/path.h). */
#ifndef RODSIM_SIM_NEEDLE_GRASP_H
#define RODSIM_SIM_NEEDLE_GRASP_H

#include <stddef.h>

#include "base/ini.h"
#include "sim/rod_types.h"

/* Reads [needle_grasp] (repeatable: t, s; instrument, NAME) after
 * [instrument]: the names known, the needle held by a needle = yes holder,
 * times increasing after its path's start, each handing the needle to other
 * jaws than hold it; hands the model's tip_motion over at each (none when
 * [ends] tip_motion gave the needle's path whole: needle_path_given). rod: the
 * rod read (several rods; NULL for a bare [rod]): a rod whose tip no
 * holder's needle is on takes no grasps when another rod's is. 0, or -1
 * with "file:line: [needle_grasp] key = value: ..." naming what is accepted. */
int needle_grasp_read(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen);

/* After the start is known (rod_model_derive): refuses a grasp whose jaws'
 * tip is farther than a jaw length from the needle at its time (the
 * needle's arc: [render] needle_arc, 3/8 or 1/2 of a circle); none when
 * the needle's path is given whole. */
int needle_grasp_check(ini_doc *doc, const rod_model *m, char *err, size_t errlen);

/* The distance (m) from instrument k's jaws' tip to the needle at time t:
 * the needle's arc (arc of a circle of m->needle_radius from the back, the
 * thread's tip, along d3 bending toward d1: render/glyphs.c's) with the
 * tip's frame R(t) tip0 (tip0: the thread's tip frame at the start,
 * row-major, R(t) the tip_motion's rotation); arc: the needle's arc as a
 * fraction of its circle (0.375 or 0.5). */
double needle_grasp_distance(const rod_model *m, const double tip0[9], double arc, int k,
                             double t);

/* 1 when instrument k's jaws hold the needle, not the thread, at time t
 * (they touch no thread): the needle = yes holder and an instrument a
 * [needle_grasp] names from its grasp on, 0 otherwise. Jaws that have
 * handed the needle to others, not taken it back, are ordinary jaws (they
 * touch the thread) from their first close (opening below ROD_JAW_CLOSED)
 * after they have opened (rod_needle_grasp freed); before it the needle's
 * back, the thread's tip, lies between them or their opening tips. */
int needle_grasp_jaws_on_needle(const rod_model *m, int k, double t);
/* 1 when instrument k's jaws closing at time t take no thread: the
 * needle = yes holder and every instrument a [needle_grasp] names, until
 * they have handed the needle on and opened and closed again since (that
 * close takes the thread as any jaws' do), 0 otherwise. */
int needle_grasp_takes_needle(const rod_model *m, int k, double t);

#endif
