/* Re-execution with OPENBLAS_CORETYPE when OpenBLAS runs a generic core (blas_fix.h).
 *
 * OpenBLAS built with DYNAMIC_ARCH picks its kernels once, when it is loaded: from
 * OPENBLAS_CORETYPE if set, else from cpuid. A CPU newer than the OpenBLAS (Debian 12's
 * 0.3.21 on Intel family 6 model 207) gets the Prescott (SSE3) kernels; a 108k-tet
 * CHOLMOD factorization ran 2.1x faster with SkylakeX. Nothing can swap the kernels of a
 * loaded OpenBLAS, so the program executes itself again, same argv, with
 * OPENBLAS_CORETYPE = the core eo_blas_is_fallback recommends and
 * ELASTOPT_BLAS_FIXED_FROM = the core it left (the loop guard, and what the reports
 * print as "(fixed from Prescott)"). It happens before anything else (no file opened, no
 * output written), at most once. */
#define _GNU_SOURCE /* setenv, unsetenv */
#include "blas_fix.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "elastopt/machine.h"
#include "elastopt/status.h"

static int env_on(const char *name)
{
    const char *v = getenv(name);
    return v && *v && strcmp(v, "0") != 0;
}

void eo_cli_blas_fix(char **argv, int no_fix)
{
    if (no_fix || env_on("ELASTOPT_NO_BLAS_FIX")) return;
    if (getenv("ELASTOPT_BLAS_FIXED_FROM")) return; /* this process is the re-execution */
    const char *user = getenv("OPENBLAS_CORETYPE");
    const char *mode = getenv("ELASTOPT_BLAS_FIX");
    if (user && *user && !(mode && strcmp(mode, "force") == 0)) return; /* the user's choice */
    const char *pre = getenv("LD_PRELOAD");
    if (pre && strstr(pre, "vgpreload")) return; /* valgrind would not follow the exec */
    eo_blas_info b;
    eo_blas_get(&b);
    if (!b.fallback || !b.recommended) return;
    char *old = user ? strdup(user) : NULL;
    if (setenv("OPENBLAS_CORETYPE", b.recommended, 1) == 0 && setenv("ELASTOPT_BLAS_FIXED_FROM", b.core, 1) == 0) {
        fflush(NULL);
        execv("/proc/self/exe", argv);
    }
    int err = errno;
    unsetenv("ELASTOPT_BLAS_FIXED_FROM");
    if (old) setenv("OPENBLAS_CORETYPE", old, 1);
    else unsetenv("OPENBLAS_CORETYPE");
    free(old);
    fprintf(stderr,
            "%s: warning: OpenBLAS runs its generic %s kernels on this CPU and re-executing with "
            "OPENBLAS_CORETYPE=%s failed (%s); set OPENBLAS_CORETYPE=%s for its faster kernels\n",
            argv[0] ? argv[0] : "elastopt", b.core, b.recommended, strerror(err), b.recommended);
}

static char g_note[160];

const char *eo_cli_blas_threads_note(void) { return g_note; }

int eo_cli_blas_threads(void)
{
    static const char *const vars[] = {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS",
                                       "BLIS_NUM_THREADS", "MKL_NUM_THREADS", NULL};
    for (const char *const *v = vars; *v; v++) {
        const char *e = getenv(*v);
        if (e && *e) { /* the user's choice */
            snprintf(g_note, sizeof g_note, "%s=%s (user)", *v, e);
            return 0;
        }
    }
    if (eo_blas_set_threads(1) != EO_OK) {
        snprintf(g_note, sizeof g_note, "the BLAS's own (not settable)");
        return 0;
    }
    snprintf(g_note, sizeof g_note, "1 (elastopt's default; OPENBLAS_NUM_THREADS=N for more)");
    return 1;
}
