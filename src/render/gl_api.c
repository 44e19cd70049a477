/* gl_api.c: the table of GL function pointers (see gl_api.h). */
#include "render/gl_api.h"

#include <stdio.h>

gl_functions gl_fn;

int gl_functions_load(gl_proc (*get_proc)(const char *name), char *err, size_t errlen)
{
    gl_functions loaded;
#define GL_FUNCTION_LOAD(type, name)                                                          \
    if (!(loaded.name = (type)get_proc("gl" #name))) {                                        \
        snprintf(err, errlen, "gl: the OpenGL library has no gl%s", #name);                  \
        return -1;                                                                            \
    }
    GL_FUNCTIONS(GL_FUNCTION_LOAD)
#undef GL_FUNCTION_LOAD
    gl_fn = loaded;
    return 0;
}
