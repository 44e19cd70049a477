/* stepping.c: steps no longer than dt over a stretch (see stepping.h). */
#include "api/stepping.h"

#include <math.h>

double stepping_count(double interval, double dt)
{
    double n = ceil(interval / dt * (1.0 - STEPPING_SLACK));
    return n < 1.0 ? 1.0 : n;
}
