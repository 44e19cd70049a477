/* static_load.h: internal to the static scheme's room (static_internal.h).
 * The load a continuation follows at a time, and in words. */
#ifndef RODSIM_STATIC_LOAD_H
#define RODSIM_STATIC_LOAD_H

#include <stddef.h>

#include "sim/static/static_internal.h"

/* The loads and the held ends' poses at time t (s). */
void static_target_load(const static_work *w, const rod_model *m, double t, static_load *load);

/* The load in words, for messages, into text (length bytes). */
void static_describe_load(const rod_model *m, const static_load *load, char *text, size_t length);

#endif
