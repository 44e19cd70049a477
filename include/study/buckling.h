/* buckling.h: loss of stability of the straight rod under axial tip loads,
 * found from the static scheme's tangent stiffness (scheme_static.h). */
#ifndef RODSIM_BUCKLING_H
#define RODSIM_BUCKLING_H

#include <stddef.h>

#include "sim/rod.h"

/* Raises the load factor lambda (the model's tip force and moment, times lambda) from 0
 * until the straight rod stops being stable (static equilibrium loses stability: the
 * tangent stiffness at the straight state becomes singular), by bracketing then bisection
 * to `relative_tolerance`. Needs a scene whose straight state is an equilibrium (axial force,
 * axial twisting moment). Returns 0 with *lambda, or -1 with a message (e.g. no loss of
 * stability up to lambda_max). The model must be derived; its profile is ignored (the
 * tip_force and tip_moment fields are the load at lambda = 1). */
int rod_buckling_factor(const rod_model *m, double lambda_max, double relative_tolerance,
                        double *lambda, char *err, size_t errlen);

#endif
