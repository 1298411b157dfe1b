/* The PETSc backend module (petsc_backend.h): plug-in entry point, PETSc start and end,
 * the shared parameters and the KSP configuration, and the functions the CLI finds with
 * dlsym (eo_petsc_cli_start, eo_petsc_cli_agree, eo_petsc_cli_attach: the mesh source of
 * mesh_bcast.c on the command's context, eo_petsc_cli_mesh_note).
 *
 * PETSc is started (PetscInitialize, which starts MPI unless the host already did) when
 * the CLI runs under an MPI launcher, else at the first minimization that needs it (an
 * MPI singleton); it is finalized at exit. PETSc's error handler is replaced by the
 * returning one: errors come back as eo statuses with a message, nothing is printed
 * except what PETSc options ask for (-log_view, -ksp_monitor, ...). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/plugin.h"
#include "petsc_backend.h"
#include "petsc_options.h"

static const char *const ksp_names[] = {"preonly", "cg", "minres", "gmres", NULL};
static const char *const pc_names[] = {"mumps", "gamg", "hypre", "bjacobi_icc", "jacobi", "cholmod", NULL};

#define PP_STR(field) .size = sizeof(((eo_petsc_params *)0)->field)
const eo_param_desc eo_petsc_params_desc[] = {
    {.key = "ksp", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_petsc_params, ksp), PP_STR(ksp),
     .def.s = "preonly", .choices = ksp_names,
     .help = "Krylov method of the Newton system (PETSc KSP): preonly (with pc = mumps: a direct solve), cg, "
             "minres, gmres"},
    {.key = "pc", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_petsc_params, pc), PP_STR(pc), .def.s = "mumps",
     .choices = pc_names,
     .help = "preconditioner: mumps (MUMPS Cholesky/LDL^T, direct), gamg (aggregation AMG, unsmoothed, with the "
             "rigid-body modes), hypre (BoomerAMG), bjacobi_icc (block Jacobi, ICC(0) per rank), jacobi"},
    {.key = "rtol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_petsc_params, rtol), .def.d = 1e-10, .min = 0,
     .max = 1, .range = EO_RANGE_OPEN, .help = "relative residual tolerance of an iterative Newton solve"},
    {.key = "max_lin_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_petsc_params, max_lin_iters),
     .def.i = 10000, .min = 1, .max = 100000000, .range = EO_RANGE_CLOSED,
     .help = "iteration cap of an iterative Newton solve"},
    {.key = "options", .kind = EO_PARAM_STRING, .offset = offsetof(eo_petsc_params, options), PP_STR(options),
     .def.s = "", .help = "PETSc options for experts, e.g. \"-ksp_monitor -log_view\" (also PETSC_OPTIONS and "
                          "the command line)"},
    {0},
};

/* ---------------------------------------------------------------- start / end */

static int g_started;               /* we called PetscInitialize */
static char g_options[4096];        /* PETSc options from the command line */

static void finalize(void)
{
    if (g_started) {
        PetscFinalize();
        g_started = 0;
    }
}

int eo_petsc_fail(eo_ctx *ctx, PetscErrorCode ierr, const char *what)
{
    const char *text = NULL;
    PetscErrorMessage(ierr, &text, NULL);
    return eo_error(ctx, EO_ERR_LINSOLVE, "petsc: %s failed: %s (PETSc error %d)", what, text ? text : "?",
                    (int)ierr);
}

static int start(void)
{
    PetscBool on = PETSC_FALSE;
    PetscInitialized(&on);
    if (on) return 0;
    /* the command line's PETSc options go in as PetscInitialize's argv, so that the ones
     * read at start-up (-log_view, -malloc_debug, ...) take effect */
    static char buf[sizeof g_options], *args[256];
    int argc = 0;
    args[argc++] = "elastopt";
    snprintf(buf, sizeof buf, "%s", g_options);
    for (char *save = NULL, *tok = strtok_r(buf, " ", &save); tok && argc < 255; tok = strtok_r(NULL, " ", &save))
        args[argc++] = tok;
    args[argc] = NULL;
    char **argv = args;
    if (PetscInitialize(&argc, &argv, NULL, NULL)) return -1;
    g_started = 1;
    atexit(finalize);
    PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
    return 0;
}

int eo_petsc_ensure(eo_ctx *ctx)
{
    if (start() < 0) return eo_error(ctx, EO_ERR_UNSUPPORTED, "petsc: PetscInitialize failed (MPI could not start)");
    return EO_OK;
}

/* ---------------------------------------------------------------- KSP */

int eo_petsc_ksp_configure(eo_ctx *ctx, KSP ksp, const eo_petsc_params *p, eo_dist *d, const char *prefix)
{
    (void)d;
    int rc = EO_OK;
    PC pc;
    if (p->options[0]) {
        EO_PC(PetscOptionsInsertString(NULL, p->options));
        /* -log_view is read at PetscInitialize; given here (after it), logging must be
         * started now, or PetscFinalize fails on the view and MPI is never finalized */
        PetscBool lv = PETSC_FALSE;
        EO_PC(PetscOptionsHasName(NULL, NULL, "-log_view", &lv));
        if (lv) EO_PC(PetscLogDefaultBegin());
    }
    if (prefix) EO_PC(KSPSetOptionsPrefix(ksp, prefix));
    EO_PC(KSPGetPC(ksp, &pc));
    const int direct = strcmp(p->pc, "mumps") == 0;
    if (strcmp(p->ksp, "preonly") == 0 && !direct)
        return eo_error(ctx, EO_ERR_INVALID, "petsc: ksp = preonly needs pc = mumps (a direct solve); pc = %s is a "
                        "preconditioner: use ksp = cg, minres or gmres", p->pc);
    EO_PC(KSPSetType(ksp, strcmp(p->ksp, "cg") == 0       ? KSPCG
                          : strcmp(p->ksp, "minres") == 0 ? KSPMINRES
                          : strcmp(p->ksp, "gmres") == 0  ? KSPGMRES
                                                          : KSPPREONLY));
    if (direct) {
        EO_PC(PCSetType(pc, PCCHOLESKY));
        EO_PC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
        /* the global inertia of the factor (newton.c: a negative pivot = not positive
         * definite, as CHOLMOD says) needs the root node factored without ScaLAPACK */
        char key[96];
        PetscBool set = PETSC_FALSE;
        snprintf(key, sizeof key, "-%smat_mumps_icntl_13", prefix ? prefix : "");
        EO_PC(PetscOptionsHasName(NULL, NULL, key, &set));
        if (!set) EO_PC(PetscOptionsSetValue(NULL, key, "1"));
    } else if (strcmp(p->pc, "gamg") == 0) {
        EO_PC(PCSetType(pc, PCGAMG));
        /* the Newton matrices of one minimization share their pattern and change slowly:
         * keep the prolongators between setups (measured on the 108k-tet twist, 1 rank:
         * setups were 3/4 of the time, 9 s each under load) */
        EO_PC(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
        /* Chebyshev smoothing with a 1.3 safety factor on the eigenvalue estimate
         * (PETSc's 1.1 made the preconditioner indefinite on the inverted scene; CG then
         * stops with DIVERGED_INDEFINITE_PC and the solve is redone with GMRES).
         * Unsmoothed aggregation (agg_nsmooths 0): with the six rigid-body modes the
         * smoothed prolongator made the Galerkin products the largest memory of a rank,
         * and more per rank on 2 ranks than the whole on one (108k-tet twist: 944 MB on 1
         * rank, 1072-1092 MB per rank on 2; unsmoothed: 428-430 MB per rank on 2, the
         * step's CPU 18.8 -> 7.9 s; docs/petsc.md, memory per rank) */
        static const char *const def[][2] = {{"mg_levels_ksp_chebyshev_esteig", "0,0.1,0,1.3"},
                                             {"pc_gamg_agg_nsmooths", "0"}};
        for (size_t i = 0; i < sizeof def / sizeof def[0]; i++) {
            char key[96];
            PetscBool set = PETSC_FALSE;
            snprintf(key, sizeof key, "-%s%s", prefix ? prefix : "", def[i][0]);
            EO_PC(PetscOptionsHasName(NULL, NULL, key, &set));
            if (!set) EO_PC(PetscOptionsSetValue(NULL, key, def[i][1]));
        }
        /* on several ranks the Galerkin products P^T A P of the MPIAIJ levels "all at
         * once" (no explicit transpose of P, no A·P kept beside the product): 400k-tet
         * twist, 4 ranks, 473 -> 343 MB per rank, CPU +14 %. Global (MatPtAP reads no
         * prefix here); not on one rank, where the sequential PtAP has no such algorithm. */
        PetscMPIInt size = 1;
        MPI_Comm_size(PetscObjectComm((PetscObject)ksp), &size);
        PetscBool set = PETSC_FALSE;
        EO_PC(PetscOptionsHasName(NULL, NULL, "-matptap_via", &set));
        if (size > 1 && !set) EO_PC(PetscOptionsSetValue(NULL, "-matptap_via", "allatonce"));
    } else if (strcmp(p->pc, "hypre") == 0) {
        EO_PC(PCSetType(pc, PCHYPRE));
        EO_PC(PCHYPRESetType(pc, "boomeramg"));
    } else if (strcmp(p->pc, "bjacobi_icc") == 0) {
        EO_PC(PCSetType(pc, PCBJACOBI));
        PetscBool set = PETSC_FALSE;
        char key[64];
        snprintf(key, sizeof key, "-%ssub_pc_type", prefix ? prefix : "");
        EO_PC(PetscOptionsHasName(NULL, NULL, key, &set));
        if (!set) EO_PC(PetscOptionsSetValue(NULL, key, "icc"));
    } else {
        EO_PC(PCSetType(pc, PCJACOBI));
    }
    EO_PC(KSPSetTolerances(ksp, p->rtol, 1e-300, 1e10, p->max_lin_iters));
    EO_PC(KSPSetErrorIfNotConverged(ksp, PETSC_FALSE));
    EO_PC(KSPSetFromOptions(ksp)); /* experts' -ksp_type, -pc_type, ... win */
fail:
    return rc;
}

/* ---------------------------------------------------------------- CLI helpers */

/* Is this process started by an MPI launcher? */
static int launched(void)
{
    const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "MPI_LOCALNRANKS", NULL};
    for (int i = 0; vars[i]; i++)
        if (getenv(vars[i])) return 1;
    return 0;
}


/* Remove PETSc options (-ksp_*, -pc_*, -log_view, ... and a value that follows one)
 * from argv, keep them for PetscInitialize; start PETSc now under an MPI launcher.
 * rank/size: of PETSC_COMM_WORLD (0/1 when not launched). Returns 0 or -1 (cannot start). */
__attribute__((visibility("default"))) int eo_petsc_cli_start(int *argc, char **argv, int *rank, int *size)
{
    int out = 1;
    size_t len = strlen(g_options);
    for (int i = 1; i < *argc; i++) {
        if (eo_petsc_option_word(argv[i])) {
            len += (size_t)snprintf(g_options + len, len < sizeof g_options ? sizeof g_options - len : 0, " %s",
                                    argv[i]);
            if (i + 1 < *argc && (argv[i + 1][0] != '-' || strtod(argv[i + 1], NULL) != 0))
                len += (size_t)snprintf(g_options + len, len < sizeof g_options ? sizeof g_options - len : 0, " %s",
                                        argv[++i]);
            continue;
        }
        argv[out++] = argv[i];
    }
    *argc = out;
    argv[out] = NULL;
    *rank = 0;
    *size = 1;
    if (!launched() && !g_options[0]) return 0;
    if (start() < 0) return -1;
    MPI_Comm_rank(PETSC_COMM_WORLD, rank);
    MPI_Comm_size(PETSC_COMM_WORLD, size);
    return 0;
}

/* 1 if ok on every rank (collective when PETSc runs on more than one rank). */
__attribute__((visibility("default"))) int eo_petsc_cli_agree(int ok)
{
    PetscBool on = PETSC_FALSE;
    PetscInitialized(&on);
    int size = 1;
    if (on) MPI_Comm_size(PETSC_COMM_WORLD, &size);
    if (size == 1) return ok;
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    return all;
}

/* The context a CLI command runs with: meshes read on rank 0 and broadcast (under
 * mpirun with several ranks). */
__attribute__((visibility("default"))) void eo_petsc_cli_attach(eo_ctx *ctx) { eo_petsc_dist_install(ctx); }

/* The distributed run's vertex counts: global (input) vertices, or -1 if the last scene
 * was not distributed. */
__attribute__((visibility("default"))) int eo_petsc_cli_nv_global(void)
{
    const eo_petsc_layout *L = eo_petsc_layout_get();
    return L ? L->nv_global : -1;
}

/* A per-vertex array of width doubles gathered to rank 0 in the input vertex order
 * (collective; 0 or -1). */
__attribute__((visibility("default"))) int eo_petsc_cli_gather(const double *local, int width, double *out)
{
    return eo_petsc_gather_vertices(local, width, out);
}

/* An identity of this rank's part of the distributed mesh (0 when the last scene was not
 * distributed): FNV-1a 64 over the rank count, this rank, the global and local vertex and
 * tet counts, and each local vertex's input number and ownership. A restart of a
 * distributed run compares it with the one recorded in its per-rank restart file. */
__attribute__((visibility("default"))) unsigned long long eo_petsc_cli_layout_id(void)
{
    const eo_petsc_layout *L = eo_petsc_layout_get();
    if (!L) return 0;
    int rank = 0, size = 1;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    unsigned long long h = 1469598103934665603ULL;
#define MIX(v)                                                                   \
    do {                                                                         \
        unsigned long long w_ = (unsigned long long)(v);                         \
        for (int b_ = 0; b_ < 8; b_++, w_ >>= 8) h = (h ^ (w_ & 0xff)) * 1099511628211ULL; \
    } while (0)
    MIX(size);
    MIX(rank);
    MIX(L->nv_global);
    MIX(L->nt_global);
    MIX(L->nv);
    MIX(L->nt);
    MIX(L->nown);
    for (int q = 0; q < L->nv; q++) {
        MIX(L->gid[q]);
        MIX(L->owned[q]);
    }
#undef MIX
    return h ? h : 1;
}

/* A per-vertex value of the last distributed scene summed over the ranks that hold the
 * vertex (e.g. its lumped mass, a sum over its tets), on the rank that owns it; 0 on the
 * others (a sum over the ranks then counts every vertex once). Collective; 0 or -1 (not
 * distributed, out of memory, an SF failure). */
__attribute__((visibility("default"))) int eo_petsc_cli_owned_sum(const double *local, double *out)
{
    const eo_petsc_layout *L = eo_petsc_layout_get();
    if (!L) return -1;
    double *root = malloc(((size_t)L->nv + 1) * sizeof *root);
    int bad = !root;
    if (root) {
        memcpy(root, local, (size_t)L->nv * sizeof *root);
        /* the ghosts' values onto their owners' */
        bad = PetscSFReduceBegin(L->vsf, MPI_DOUBLE, local, root, MPI_SUM) != 0;
        bad |= PetscSFReduceEnd(L->vsf, MPI_DOUBLE, local, root, MPI_SUM) != 0;
        for (int q = 0; q < L->nv; q++) out[q] = L->owned[q] ? root[q] : 0.0;
    }
    free(root);
    return bad ? -1 : 0;
}

/* What the last mesh read did under MPI ("" if nothing was broadcast). */
__attribute__((visibility("default"))) const char *eo_petsc_cli_mesh_note(void) { return eo_petsc_mesh_note(); }

/* ---------------------------------------------------------------- registration */

EO_PLUGIN_ENTRY(ctx)
{
    int lrc = eo_register(ctx, EO_KIND_LINSOLVE, &eo_linsolve_petsc_ksp);
    if (lrc < 0) return lrc;
    const eo_optimizer_type *all[] = {&eo_optimizer_snes_newtonls,
                                      &eo_optimizer_snes_newtontr, &eo_optimizer_tao_nls,
                                      &eo_optimizer_tao_ntr, &eo_optimizer_tao_lmvm,
                                      &eo_optimizer_tao_bqnls, NULL};
    for (int i = 0; all[i]; i++) {
        int rc = eo_register(ctx, EO_KIND_OPTIMIZER, all[i]);
        if (rc < 0) return rc;
    }
    return EO_OK;
}
