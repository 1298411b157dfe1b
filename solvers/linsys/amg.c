/* Internal: BoomerAMG preconditioner for pcg (see amg.h for the method). hypre is
 * built with MPI in Debian; everything here runs on MPI_COMM_SELF. MPI is initialized
 * on first use if the host has not done it (MPI_Init_thread, thread level SINGLE) and
 * left initialized (a host that uses MPI itself initializes and finalizes it). */
#include "amg.h"

#include <math.h>
#include <mpi.h>
#include <string.h>
#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>

struct eo_amg {
    eo_amg_opts o;
    int n, nv;
    eo_csc_full *F;    /* full matrix = CSR of the symmetric matrix */
    HYPRE_Int *rows, *ncols, *cols; /* hypre index arrays (HYPRE_Int may differ from int) */
    double *modes;     /* 3 n rigid-body rotations */
    HYPRE_IJMatrix ij;
    HYPRE_IJVector ib, ix, im[3];
    HYPRE_ParVector pb, px, pm[3];
    HYPRE_Solver amg;
};

static int mpi_ready(void)
{
    int flag = 0;
    MPI_Initialized(&flag);
    if (!flag) {
        int prov;
        if (MPI_Init_thread(NULL, NULL, MPI_THREAD_SINGLE, &prov) != MPI_SUCCESS) return 0;
        HYPRE_Init();
    }
    return 1;
}

static void vec_create(int n, HYPRE_IJVector *v, HYPRE_ParVector *p)
{
    HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, v);
    HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(*v);
    HYPRE_IJVectorAssemble(*v);
    void *obj;
    HYPRE_IJVectorGetObject(*v, &obj);
    *p = obj;
}

static void free_hypre(eo_amg *a)
{
    if (a->amg) HYPRE_BoomerAMGDestroy(a->amg);
    if (a->ij) HYPRE_IJMatrixDestroy(a->ij);
    a->amg = NULL;
    a->ij = NULL;
}

void eo_amg_destroy(eo_ctx *ctx, eo_amg **amg)
{
    if (!amg || !*amg) return;
    eo_amg *a = *amg;
    free_hypre(a);
    if (a->ib) HYPRE_IJVectorDestroy(a->ib);
    if (a->ix) HYPRE_IJVectorDestroy(a->ix);
    for (int k = 0; k < 3; k++)
        if (a->im[k]) HYPRE_IJVectorDestroy(a->im[k]);
    eo_csc_full_destroy(&a->F);
    eo_free(ctx, a->rows);
    eo_free(ctx, a->ncols);
    eo_free(ctx, a->cols);
    eo_free(ctx, a->modes);
    eo_free(ctx, a);
    *amg = NULL;
}

int eo_amg_create(eo_ctx *ctx, const eo_csc *A, const eo_amg_opts *o, eo_amg **out)
{
    *out = NULL;
    if (!mpi_ready()) return eo_error(ctx, EO_ERR_LINSOLVE, "pcg amg: MPI_Init_thread failed (hypre needs MPI)");
    eo_amg *a = eo_calloc(ctx, 1, sizeof *a);
    if (!a) return eo_error(ctx, EO_ERR_NOMEM, "pcg amg: out of memory");
    a->o = *o;
    a->n = A->n;
    int rc = eo_csc_full_create(ctx, A, &a->F);
    if (rc < 0) {
        eo_amg_destroy(ctx, &a);
        return rc;
    }
    size_t n = (size_t)(A->n ? A->n : 1), nnz = (size_t)(a->F->nnz ? a->F->nnz : 1);
    a->rows = eo_malloc(ctx, n * sizeof(HYPRE_Int));
    a->ncols = eo_malloc(ctx, n * sizeof(HYPRE_Int));
    a->cols = eo_malloc(ctx, nnz * sizeof(HYPRE_Int));
    if (A->n % 3 == 0) a->modes = eo_malloc(ctx, 3 * n * sizeof(double));
    if (!a->rows || !a->ncols || !a->cols || (A->n % 3 == 0 && !a->modes)) {
        eo_amg_destroy(ctx, &a);
        return eo_error(ctx, EO_ERR_NOMEM, "pcg amg: out of memory (n=%d)", A->n);
    }
    for (int i = 0; i < A->n; i++) {
        a->rows[i] = i;
        a->ncols[i] = a->F->colptr[i + 1] - a->F->colptr[i];
    }
    for (int q = 0; q < a->F->nnz; q++) a->cols[q] = a->F->rowind[q];
    if (A->n > 0) {
        vec_create(A->n, &a->ib, &a->pb);
        vec_create(A->n, &a->ix, &a->px);
    }
    *out = a;
    return EO_OK;
}

void eo_amg_set_coordinates(eo_amg *a, int nv, const double *xyz)
{
    const int n = a->n;
    a->nv = 0;
    if (3 * nv != n || !a->modes || nv == 0) return;
    double c[3] = {0, 0, 0};
    for (int i = 0; i < nv; i++)
        for (int d = 0; d < 3; d++) c[d] += xyz[3 * i + d] / nv;
    for (int i = 0; i < nv; i++) {
        double x = xyz[3 * i] - c[0], y = xyz[3 * i + 1] - c[1], z = xyz[3 * i + 2] - c[2];
        double *m0 = a->modes + 3 * i, *m1 = m0 + n, *m2 = m1 + n;
        m0[0] = 0, m0[1] = -z, m0[2] = y;
        m1[0] = z, m1[1] = 0, m1[2] = -x;
        m2[0] = -y, m2[1] = x, m2[2] = 0;
    }
    a->nv = nv;
}

int eo_amg_setup(eo_amg *a, const eo_csc *A, eo_ctx *ctx)
{
    const int n = a->n;
    free_hypre(a);
    if (n == 0) return EO_OK;
    eo_csc_full_fill(a->F, A);
    HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, n - 1, 0, n - 1, &a->ij);
    HYPRE_IJMatrixSetObjectType(a->ij, HYPRE_PARCSR);
    HYPRE_IJMatrixSetRowSizes(a->ij, a->ncols);
    HYPRE_IJMatrixInitialize(a->ij);
    HYPRE_IJMatrixSetValues(a->ij, n, a->ncols, a->rows, a->cols, a->F->val);
    HYPRE_IJMatrixAssemble(a->ij);
    void *obj;
    HYPRE_IJMatrixGetObject(a->ij, &obj);
    HYPRE_ParCSRMatrix pA = obj;

    HYPRE_BoomerAMGCreate(&a->amg);
    HYPRE_BoomerAMGSetPrintLevel(a->amg, 0);
    HYPRE_BoomerAMGSetMaxIter(a->amg, 1); /* one V-cycle per application */
    HYPRE_BoomerAMGSetTol(a->amg, 0.0);
    HYPRE_BoomerAMGSetRelaxType(a->amg, 6); /* hybrid symmetric Gauss–Seidel */
    HYPRE_BoomerAMGSetStrongThreshold(a->amg, a->o.strong_threshold);
    const int systems = n % 3 == 0;
    if (systems) {
        HYPRE_BoomerAMGSetNumFunctions(a->amg, 3);
        HYPRE_BoomerAMGSetNodal(a->amg, 1);
    }
    if (systems && a->o.rbm && a->nv > 0) {
        for (int k = 0; k < 3; k++) {
            if (!a->im[k]) vec_create(n, &a->im[k], &a->pm[k]);
            HYPRE_IJVectorSetValues(a->im[k], n, a->rows, a->modes + (size_t)k * n);
        }
        HYPRE_BoomerAMGSetInterpVecVariant(a->amg, 2);
        HYPRE_BoomerAMGSetInterpVectors(a->amg, 3, a->pm);
    }
    HYPRE_ParVectorSetConstantValues(a->px, 0.0);
    HYPRE_ParVectorSetConstantValues(a->pb, 0.0);
    HYPRE_Int err = HYPRE_BoomerAMGSetup(a->amg, pA, a->pb, a->px);
    if (err) {
        HYPRE_ClearAllErrors();
        free_hypre(a);
        return eo_error(ctx, EO_ERR_LINSOLVE, "pcg amg: HYPRE_BoomerAMGSetup failed (hypre error %d)", (int)err);
    }
    return EO_OK;
}

void eo_amg_apply(const void *pc, const double *r, double *z)
{
    const eo_amg *a = pc;
    void *obj;
    HYPRE_IJMatrixGetObject(a->ij, &obj);
    HYPRE_IJVectorSetValues(a->ib, a->n, a->rows, r);
    HYPRE_ParVectorSetConstantValues(a->px, 0.0);
    HYPRE_BoomerAMGSolve(a->amg, obj, a->pb, a->px);
    HYPRE_IJVectorGetValues(a->ix, a->n, a->rows, z);
    HYPRE_ClearAllErrors(); /* "not converged" after one cycle is the intent */
}
