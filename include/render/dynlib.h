/* dynlib.h: opening a shared library at run time (dlopen), for the
 * libraries only drawing needs (EGL, OSMesa, libav*): a start that does not
 * draw does not pay for loading them. Messages name the library and the Debian
 * package that provides it. */
#ifndef RODSIM_DYNLIB_H
#define RODSIM_DYNLIB_H

#include <stddef.h>

/* Opens the first of `sonames` (NULL-terminated, most wanted first) that
 * loads. NULL with a message naming them, the loader's reason and
 * `package` (the Debian package to install). Never closed: the libraries
 * stay for the life of the process. */
void *dynlib_open(const char *const *sonames, const char *package, char *err, size_t errlen);

/* The address of `symbol` in lib, as a function pointer (cast it to the
 * function's type); NULL with a message naming it and `soname`. */
typedef void (*dynlib_function)(void);
dynlib_function dynlib_symbol(void *lib, const char *soname, const char *symbol, char *err,
                              size_t errlen);

#endif
