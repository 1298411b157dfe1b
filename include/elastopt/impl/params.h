/// @file impl/params.h
/// The parameter structs of the built-in methods that more than one file fills directly
/// (the shift safeguard shared by the Hessian fixes and the PETSc Newton, the Wolfe and
/// non-monotone searches driven by the tests). Every other method's parameter struct is
/// private to its file; a configuration sets them all through the JSON config and each
/// method's descriptor (`elastopt help <name>`).
#ifndef ELASTOPT_IMPL_PARAMS_H
#define ELASTOPT_IMPL_PARAMS_H

#include "../export.h"
#include "../params.h"

#ifdef __cplusplus
extern "C" {
#endif


/// Parameters of the c·I shift (config `solver.shift.*`, also `solver.clamp.*` and
/// `solver.abs.*` for their safeguard). Scale s = mean |H_ii| (1 if that is 0).
typedef struct eo_hessfix_shift_params {
    double shift_init;   ///< first non-zero shift, relative to s (default 1e-8)
    double shift_grow;   ///< factor on each retry: c = max(c_min, grow·c) (default 10)
    double shift_shrink; ///< after a success the next iteration starts at c/shrink,
                         ///< or at 0 when that is below c_min (default 10)
    double shift_max;    ///< give up (EO_DIVERGED_NOT_PD) above this, relative to s (1e12)
} eo_hessfix_shift_params;
/// Descriptor of eo_hessfix_shift_params (shared by shift, clamp, abs).
EO_API extern const eo_param_desc eo_hessfix_shift_params_desc[];

/// Wolfe line search (config `solver.wolfe.*`).
typedef struct eo_wolfe_params {
    double c1;           ///< sufficient decrease constant (1e-4)
    double c2;           ///< curvature constant |φ'(α)| ≤ c2|φ'(0)|, c1 < c2 < 1; 0 = the
                         ///< optimizer's preference (lbfgs 0.9, ncg 0.1), else 0.9 (0)
    int max_evals;       ///< trials (value+gradient each) before giving up (40)
    double noise;        ///< relative resolution of g: values within noise·|g(x)| of each
                         ///< other are equal and the approximate Wolfe test (Hager–Zhang)
                         ///< on φ' decides (1e-10)
} eo_wolfe_params;

/// Backtracking (config `solver.backtracking.*`).
typedef struct eo_backtracking_params {
    double c1;           ///< Armijo constant (1e-4)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
} eo_backtracking_params;

/// Non-monotone backtracking (config `solver.nonmonotone.*`): Armijo against a reference
/// R ≥ g(x_k) from the earlier iterates' values (eo_ls_extra.g_hist).
typedef struct eo_nonmonotone_params {
    double c1;           ///< sufficient decrease constant (1e-4)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
    char reference[16];  ///< "max" (Grippo–Lampariello–Lucidi: max of the last memory+1
                         ///< values) or "average" (Zhang–Hager C_k) (default "max")
    int memory;          ///< max: M earlier values (10)
    double eta;          ///< average: Zhang–Hager weight η (0.85)
} eo_nonmonotone_params;
#ifdef __cplusplus
}
#endif
#endif
