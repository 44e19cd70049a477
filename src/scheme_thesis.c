/* scheme_thesis.c: placeholder until the scheme lands (frame commit only). */
#include "rod.h"

#include <stdio.h>
#include <stdlib.h>

static void *create(const rod_model *m, char *err, size_t errlen)
{
    (void)m;
    snprintf(err, errlen, "scheme 'thesis' is not implemented yet");
    return NULL;
}

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt, rod_report *r)
{
    (void)work; (void)m; (void)s; (void)dt;
    snprintf(r->message, sizeof r->message, "scheme 'thesis' is not implemented yet");
    return ROD_FAILED;
}

static void destroy(void *work) { free(work); }

const rod_scheme_ops rod_scheme_thesis = {"thesis", create, step, destroy, NULL};
