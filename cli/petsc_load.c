/* Loading the PETSc / MPI backend module (petsc_load.h).
 *
 * Why dlopen with RTLD_DEEPBIND instead of linking: libelastopt links Ipopt, and Debian's
 * Ipopt links the sequential MUMPS (libdmumps_seq), which defines dmumps_c and the other
 * MUMPS entry points under the same names as the parallel MUMPS (libdmumps) that PETSc
 * uses, and also MPI_Init, MPI_Comm_rank, mpi_allreduce_ ... as stubs. In one global
 * symbol scope one of the two MUMPS (and the MPI stubs) would serve both callers. The
 * module is therefore not linked against libelastopt or Ipopt, and is opened with
 * RTLD_LOCAL | RTLD_DEEPBIND: PETSc, parallel MUMPS and Open MPI's Fortran bindings
 * resolve inside the module's own dependency tree first (where the sequential MUMPS is
 * absent), while Ipopt keeps resolving to the sequential MUMPS in the global scope. The
 * eo_* symbols the module uses come from the libelastopt already loaded by the CLI.
 * (Sanitizer runtimes refuse RTLD_DEEPBIND: a sanitizer build's CLI does not load the
 * module, and the backend's test skips.) */
#define _GNU_SOURCE
#include "petsc_load.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "eo_build_config.h"
#include "elastopt/config.h"
#include "elastopt/plugin.h"
#include "petsc/petsc_options.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define EO_NO_DEEPBIND 1 /* the sanitizer runtimes refuse RTLD_DEEPBIND */
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define EO_NO_DEEPBIND 1
#endif
#endif

static int g_rank = 0, g_size = 1;
static int (*g_agree)(int);
static void (*g_attach)(eo_ctx *);
static const char *(*g_mesh_note)(void);
static int (*g_nv_global)(void);
static int (*g_gather)(const double *, int, double *);
static unsigned long long (*g_layout_id)(void);
static int (*g_owned_sum)(const double *, double *);

int eo_cli_rank(void) { return g_rank; }
void eo_cli_petsc_attach(eo_ctx *ctx)
{
    if (g_attach) g_attach(ctx);
}
const char *eo_cli_mesh_note(void)
{
    const char *n = g_mesh_note ? g_mesh_note() : NULL;
    return n && *n ? n : NULL;
}
int eo_cli_size(void) { return g_size; }
int eo_cli_dist_nv(void) { return g_nv_global && g_size > 1 ? g_nv_global() : -1; }
int eo_cli_dist_gather(const double *local, int width, double *out)
{
    return g_gather ? g_gather(local, width, out) : -1;
}
int eo_cli_agree(int ok) { return g_agree ? g_agree(ok) : ok; }
unsigned long long eo_cli_dist_layout_id(void) { return g_layout_id && g_size > 1 ? g_layout_id() : 0; }
int eo_cli_dist_owned_sum(const double *local, double *out)
{
    return g_owned_sum && g_size > 1 ? g_owned_sum(local, out) : -1;
}

#if EO_HAVE_PETSC && !defined(EO_NO_DEEPBIND)

/* The module: $ELASTOPT_PETSC_MODULE, else beside the build tree's CLI
 * (build/cli/elastopt -> build/petsc/), else the installed one. */
static int module_path(char *out, size_t n)
{
    const char *env = getenv("ELASTOPT_PETSC_MODULE");
    if (env) {
        snprintf(out, n, "%s", env);
        return *env != 0;
    }
    char exe[4096];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) {
        exe[len] = 0;
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = 0;
            snprintf(out, n, "%s/../petsc/elastopt_petsc.so", exe);
            if (access(out, R_OK) == 0) return 1;
        }
    }
    snprintf(out, n, "%s/elastopt_petsc.so", EO_PETSC_MODULE_DIR);
    return access(out, R_OK) == 0;
}

/* Does text name a method of the backend? */
static int mentions(const char *text)
{
    return strstr(text, "petsc") || strstr(text, "snes_") || strstr(text, "tao_");
}

static int file_mentions(const char *path)
{
    struct stat st;
    char run[4200];
    if (stat(path, &st) != 0) return 0;
    if (S_ISDIR(st.st_mode)) { /* --restart DIR: the run's configuration */
        snprintf(run, sizeof run, "%s/run.json", path);
        path = run;
        if (stat(path, &st) != 0) return 0;
    }
    if (!S_ISREG(st.st_mode) || (size_t)st.st_size > 2 * EO_CFG_MAX_BYTES) return 0;
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    char *buf = malloc((size_t)st.st_size + 1);
    size_t n = buf ? fread(buf, 1, (size_t)st.st_size, f) : 0;
    fclose(f);
    if (!buf) return 0;
    buf[n] = 0;
    int m = mentions(buf) != 0;
    free(buf);
    return m;
}

/* Loading PETSc and its libraries costs about 0.3 s, so the module is loaded only when
 * it can be used: under an MPI launcher, for `list` and `help` (they show its methods),
 * when ELASTOPT_PETSC=1, or when an argument or a file named on the command line (scene,
 * suite, --restart folder) mentions petsc, snes_ or tao_. */
static int wanted(int argc, char **argv)
{
    const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "MPI_LOCALNRANKS", NULL};
    for (int i = 0; vars[i]; i++)
        if (getenv(vars[i])) return 1;
    const char *force = getenv("ELASTOPT_PETSC");
    if (force && *force) return strcmp(force, "0") != 0;
    if (argc > 1 && (strcmp(argv[1], "list") == 0 || strcmp(argv[1], "help") == 0)) return 1;
    for (int i = 1; i < argc; i++)
        if (mentions(argv[i]) || eo_petsc_option_word(argv[i]) || file_mentions(argv[i])) return 1;
    return 0;
}

#endif

int eo_cli_petsc_load(eo_ctx *ctx, int *argc, char **argv)
{
#if EO_HAVE_PETSC && !defined(EO_NO_DEEPBIND)
    char path[4200];
    if (!wanted(*argc, argv)) return 0;
    if (!module_path(path, sizeof path)) return 0; /* not installed: no backend */
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
    if (!h) {
        fprintf(stderr, "elastopt: error: cannot load the PETSc backend %s: %s\n", path, dlerror());
        return 2;
    }
    int (*init)(eo_ctx *, int);
    int (*start)(int *, char **, int *, int *);
    *(void **)(&init) = dlsym(h, EO_PLUGIN_SYMBOL);
    *(void **)(&start) = dlsym(h, "eo_petsc_cli_start");
    *(void **)(&g_agree) = dlsym(h, "eo_petsc_cli_agree");
    *(void **)(&g_attach) = dlsym(h, "eo_petsc_cli_attach");
    *(void **)(&g_mesh_note) = dlsym(h, "eo_petsc_cli_mesh_note");
    *(void **)(&g_nv_global) = dlsym(h, "eo_petsc_cli_nv_global");
    *(void **)(&g_gather) = dlsym(h, "eo_petsc_cli_gather");
    *(void **)(&g_layout_id) = dlsym(h, "eo_petsc_cli_layout_id");
    *(void **)(&g_owned_sum) = dlsym(h, "eo_petsc_cli_owned_sum");
    if (!init || !start || !g_agree || !g_attach || !g_mesh_note || !g_nv_global || !g_gather || !g_layout_id ||
        !g_owned_sum) {
        fprintf(stderr, "elastopt: error: %s is not the PETSc backend module\n", path);
        g_agree = NULL;
        g_attach = NULL;
        g_mesh_note = NULL;
        return 2;
    }
    if (init(ctx, EO_ABI_VERSION) < 0) {
        fprintf(stderr, "elastopt: error: PETSc backend %s: %s\n", path, eo_ctx_message(ctx));
        g_agree = NULL;
        g_attach = NULL;
        g_mesh_note = NULL;
        return 2;
    }
    if (start(argc, argv, &g_rank, &g_size) < 0) {
        fprintf(stderr, "elastopt: error: the PETSc backend could not start MPI\n");
        return 2;
    }
    if (g_rank != 0) { /* one voice: rank 0 prints */
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) return 2;
    }
#else
    (void)ctx, (void)argc, (void)argv;
#endif
    return 0;
}
