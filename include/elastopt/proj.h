/// @file proj.h
/// Per-element Hessian projection: the one enum shared by materials (which project
/// their element Hessians), objectives (which assemble with a projection) and the
/// Hessian fixes of solver.h (which choose it). Compiles alone.
///
/// ```c
/// eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);   // every element Hessian clamped
/// ```
#ifndef ELASTOPT_PROJ_H
#define ELASTOPT_PROJ_H

#ifdef __cplusplus
extern "C" {
#endif

/// Per-element Hessian projection. An element Hessian K_e = Q Λ Qᵀ becomes Q f(Λ) Qᵀ.
typedef enum eo_proj {
    EO_PROJ_NONE = 0,   ///< true Hessian, f(λ) = λ
    EO_PROJ_CLAMP = 1,  ///< negative eigenvalues set to 0, f(λ) = max(λ, 0)
    EO_PROJ_ABS = 2     ///< eigenvalues replaced by their absolute value, f(λ) = |λ|
} eo_proj;

#ifdef __cplusplus
}
#endif
#endif
