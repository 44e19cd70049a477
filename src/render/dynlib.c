/* dynlib.c: dlopen with messages for people (see dynlib.h). */
#include "render/dynlib.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

void *dynlib_open(const char *const *sonames, const char *package, char *err, size_t errlen)
{
    char tried[256] = "", reason[512] = "";
    for (int i = 0; sonames[i]; i++) {
        /* RTLD_LOCAL: its symbols serve only the pointers we take from it */
        void *lib = dlopen(sonames[i], RTLD_NOW | RTLD_LOCAL);
        if (lib) return lib;
        if (i == 0) snprintf(reason, sizeof reason, "%s", dlerror());
        size_t used = strlen(tried);
        snprintf(tried + used, sizeof tried - used, "%s%s", i ? ", " : "", sonames[i]);
    }
    snprintf(err, errlen, "cannot load %s (%s); install the Debian package %s", tried, reason,
             package);
    return NULL;
}

dynlib_function dynlib_symbol(void *lib, const char *soname, const char *symbol, char *err,
                              size_t errlen)
{
    void *address = dlsym(lib, symbol);
    if (!address) {
        snprintf(err, errlen, "%s has no %s (a different version?)", soname, symbol);
        return NULL;
    }
    /* POSIX guarantees the conversion; memcpy keeps ISO C (-Wpedantic) quiet */
    _Static_assert(sizeof(dynlib_function) == sizeof address, "function pointers as wide as data pointers");
    dynlib_function function;
    memcpy(&function, &address, sizeof function);
    return function;
}
