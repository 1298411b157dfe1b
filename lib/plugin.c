/* Plug-in loading (plugin.h): dlopen the shared object, find its entry point, call it
 * with the library's ABI version. Objects stay loaded for the life of the process (their
 * method tables are registered, borrowed by the registries). */
#include "elastopt/plugin.h"

#include <dlfcn.h>
#include <stdio.h>

int eo_abi_version(void) { return EO_ABI_VERSION; }

int eo_plugin_load(eo_ctx *ctx, const char *path)
{
    if (!path || !*path) return eo_error(ctx, EO_ERR_INVALID, "plug-in: empty file name");
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *msg = dlerror();
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot load plug-in: %s",
                           msg ? msg : "unknown error");
    }
    int (*init)(eo_ctx *, int);
    /* POSIX: the object pointer returned by dlsym converts to a function pointer */
    *(void **)(&init) = dlsym(h, EO_PLUGIN_SYMBOL);
    if (!init) {
        dlclose(h);
        return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_FILE(path, -1),
                           "not an elastopt plug-in: no function %s (declare it with EO_PLUGIN_ENTRY)",
                           EO_PLUGIN_SYMBOL);
    }
    int rc = init(ctx, EO_ABI_VERSION);
    if (rc < 0) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", eo_ctx_message(ctx));
        return eo_error_at(ctx, rc, EO_ERRLOC_FILE(path, -1), "plug-in failed to register: %s", msg);
    }
    return EO_OK; /* never dlclose: the registered tables live in the object */
}
