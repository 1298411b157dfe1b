/* Integrator and scene registries (one line per method), and the public by-kind entry
 * points of registry.h: this is the top layer of the library, the one place that knows
 * every kind's registry (each defined by the layer that owns the kind). */
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/step.h"
#include "../materials/material_registry.h"
#include "../solvers/solver_registry.h"
#include "problem_registry.h"
#include "term.h"

#include <stddef.h>
#include <string.h>

extern const eo_integrator_type eo_integrator_newmark, eo_integrator_backward_euler,
    eo_integrator_static, eo_integrator_forward_euler, eo_integrator_symplectic_euler,
    eo_integrator_heun, eo_integrator_midpoint, eo_integrator_rk4, eo_integrator_verlet,
    eo_integrator_leapfrog;
extern const eo_integrator_type eo_integrator_symplectic_euler_x;
extern const eo_integrator_type eo_integrator_implicit_midpoint;
extern const eo_integrator_type eo_integrator_bdf2;
extern const eo_integrator_type eo_integrator_generalized_alpha;
extern const eo_scene_type eo_scene_cantilever, eo_scene_cantilever_static, eo_scene_twist,
    eo_scene_stretch, eo_scene_freefall, eo_scene_inverted, eo_scene_drop;
extern const eo_scene_type eo_scene_cloth;

const void *const eo_registry_integrator[] = {
    &eo_integrator_newmark,
    &eo_integrator_backward_euler,
    &eo_integrator_static,
    &eo_integrator_forward_euler,
    &eo_integrator_symplectic_euler,
    &eo_integrator_heun,
    &eo_integrator_midpoint,
    &eo_integrator_rk4,
    &eo_integrator_verlet,
    &eo_integrator_leapfrog,
    &eo_integrator_symplectic_euler_x,
    &eo_integrator_implicit_midpoint,
    &eo_integrator_bdf2,
    &eo_integrator_generalized_alpha,
    NULL,
};

const void *const eo_registry_scene[] = {
    &eo_scene_cantilever,
    &eo_scene_cantilever_static,
    &eo_scene_twist,
    &eo_scene_stretch,
    &eo_scene_freefall,
    &eo_scene_inverted,
    &eo_scene_drop,
    &eo_scene_cloth,
    NULL,
};

/* The terms of the step problem, in the order they are summed into g (inertia first;
 * a new force is one line here, before `linear`'s or after it). */
const void *const eo_registry_term[] = {
    &eo_term_type_inertia,
    &eo_term_type_elastic,
    &eo_term_type_spring,
    &eo_term_type_collision,
    &eo_term_type_damping,
    &eo_term_type_friction,
    &eo_term_type_gravity,
    &eo_term_type_linear,
    &eo_term_type_traction,
    NULL,
};

static int check_integrator(eo_ctx *ctx, const void *type)
{
    const eo_integrator_type *t = type;
    if (!t->explicit_step && !(t->weight && t->predict && t->velocity) &&
        !(t->accel && t->accel_weight && t->accel_theta && t->accel_predict && t->accel_velocity))
        return eo_error(ctx, EO_ERR_INVALID,
                        "register integrator '%s': explicit_step, or weight + predict + velocity, or accel with "
                        "accel_weight + accel_theta + accel_predict + accel_velocity, required",
                        t->info.name);
    if (t->accel && (t->history || t->explicit_step || t->force_n))
        return eo_error(ctx, EO_ERR_INVALID,
                        "register integrator '%s': accel excludes history, explicit_step and force_n", t->info.name);
    if (t->info.params && !t->info.params_size)
        return eo_error(ctx, EO_ERR_INVALID, "register integrator '%s': params without params_size", t->info.name);
    if (t->history != 0 && (t->history != 1 || !t->weight_history || !t->predict_history || !t->velocity_history))
        return eo_error(ctx, EO_ERR_INVALID,
                        "register integrator '%s': history must be 0, or 1 with weight/predict/velocity_history",
                        t->info.name);
    if (t->theta < 0 || t->theta > 1)
        return eo_error(ctx, EO_ERR_INVALID, "register integrator '%s': theta outside [0, 1]", t->info.name);
    if (t->explicit_step && t->work_vectors < 0)
        return eo_error(ctx, EO_ERR_INVALID, "register integrator '%s': work_vectors < 0", t->info.name);
    return EO_OK;
}

static int check_scene(eo_ctx *ctx, const void *type)
{
    const eo_scene_type *t = type;
    if (!t->json) return eo_error(ctx, EO_ERR_INVALID, "register scene '%s': json is required", t->info.name);
    return EO_OK;
}

static int check_term(eo_ctx *ctx, const void *type)
{
    const eo_term_type *t = type;
    if (!t->create) return eo_error(ctx, EO_ERR_INVALID, "register term '%s': create is required", t->info.name);
    if (t->info.params && !t->info.params_size && !t->load)
        return eo_error(ctx, EO_ERR_INVALID, "register term '%s': params without params_size or load", t->info.name);
    if ((t->info.params || t->load) && !t->section)
        return eo_error(ctx, EO_ERR_INVALID, "register term '%s': params or load without a section", t->info.name);
    if (t->section) {
        for (const char *c = t->section; *c; c++)
            if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '_'))
                return eo_error(ctx, EO_ERR_INVALID, "register term '%s': section '%s' is not a lower-case word",
                                t->info.name, t->section);
        for (const void *const *o = eo_registry_types(&eo_reg_term); o && *o; o++) {
            const eo_term_type *u = *o;
            if (u != t && u->section && strcmp(u->section, t->section) == 0)
                return eo_error(ctx, EO_ERR_INVALID, "register term '%s': section '%s' is term '%s''s",
                                t->info.name, t->section, u->info.name);
        }
    }
    const unsigned once = EO_TERM_INERTIA | EO_TERM_FORCE_N | EO_TERM_DAMPING | EO_TERM_LAGGED | EO_TERM_GRAVITY;
    if (t->flags & once)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register term '%s': the roles inertia, force_n, damping, lagged and gravity belong to the "
                        "built-in terms", t->info.name);
    return EO_OK;
}

eo_registry eo_reg_integrator = EO_REGISTRY_INIT(EO_KIND_INTEGRATOR, eo_registry_integrator, check_integrator);
eo_registry eo_reg_scene = EO_REGISTRY_INIT(EO_KIND_SCENE, eo_registry_scene, check_scene);
eo_registry eo_reg_term = EO_REGISTRY_INIT(EO_KIND_TERM, eo_registry_term, check_term);

static eo_registry *const kind_registry[EO_KIND_COUNT] = {
    [EO_KIND_MATERIAL] = &eo_reg_material,
    [EO_KIND_OPTIMIZER] = &eo_reg_optimizer,
    [EO_KIND_HESSFIX] = &eo_reg_hessfix,
    [EO_KIND_LINESEARCH] = &eo_reg_linesearch,
    [EO_KIND_STOP] = &eo_reg_stop,
    [EO_KIND_LINSOLVE] = &eo_reg_linsolve,
    [EO_KIND_INTEGRATOR] = &eo_reg_integrator,
    [EO_KIND_SCENE] = &eo_reg_scene,
    [EO_KIND_ELEMENT] = &eo_reg_element,
    [EO_KIND_TERM] = &eo_reg_term,
};

eo_registry *eo_registry_of(eo_kind kind)
{
    return (unsigned)kind < EO_KIND_COUNT ? kind_registry[kind] : NULL;
}

const void *const *eo_registry_list(eo_kind kind) { return eo_registry_types(eo_registry_of(kind)); }

void eo_registry_names(eo_kind kind, char *buf, size_t n) { eo_registry_name_list(eo_registry_of(kind), buf, n); }

int eo_registry_find(eo_ctx *ctx, eo_kind kind, const char *name, const void **out)
{
    return eo_registry_lookup(ctx, eo_registry_of(kind), name, out);
}

int eo_register(eo_ctx *ctx, eo_kind kind, const void *type)
{
    eo_registry *r = eo_registry_of(kind);
    if (!r) return eo_error(ctx, EO_ERR_INVALID, "register: invalid kind %d", (int)kind);
    return eo_registry_add(ctx, r, type);
}

int eo_unregister(eo_kind kind, const void *type) { return eo_registry_remove(eo_registry_of(kind), type); }
