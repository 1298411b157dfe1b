/* Sizes and field offsets of the C structs the Python package (python/elastopt/_ffi.py)
 * declares again for cffi's ABI mode, as the C compiler lays them out: one line
 * "struct field offset" per field and "struct - sizeof" per struct. The Python test
 * compares them with cffi's layout, so a header change not made in _ffi.py fails. */
#include <stddef.h>
#include <stdio.h>

#include "bench.h"
#include "elastopt/callback.h"
#include "elastopt/ctx.h"
#include "elastopt/mesh.h"
#include "elastopt/sim.h"

#define S(T) printf("%s - %zu\n", #T, sizeof(T));
#define F(T, f) printf("%s %s %zu\n", #T, #f, offsetof(T, f));

int main(void)
{
    S(eo_errloc) F(eo_errloc, line) F(eo_errloc, kind) F(eo_errloc, index)
    S(eo_csc) F(eo_csc, nnz) F(eo_csc, colptr) F(eo_csc, rowind) F(eo_csc, val) F(eo_csc, ctx)
    S(eo_objective_ops) F(eo_objective_ops, hessian) F(eo_objective_ops, metric_diag)
    F(eo_objective_ops, inverted_count) F(eo_objective_ops, element_residual)
    F(eo_objective_ops, rounding_scale) F(eo_objective_ops, max_step) F(eo_objective_ops, characteristic)
    F(eo_objective_ops, rounding_scale) F(eo_objective_ops, split_adjoint)
    F(eo_objective_ops, rounding_scale) F(eo_objective_ops, vertex_blocks) F(eo_objective_ops, vertex_block) F(eo_objective_ops, split_assemble)
    S(eo_objective) F(eo_objective, ops) F(eo_objective, data) F(eo_objective, n_value)
    F(eo_objective, n_hessian) F(eo_objective, space)
    S(eo_method_info) F(eo_method_info, summary) F(eo_method_info, params_size) F(eo_method_info, flags)
    S(eo_iter_info) F(eo_iter_info, time) F(eo_iter_info, decrement) F(eo_iter_info, alpha)
    F(eo_iter_info, ls_evals) F(eo_iter_info, shift) F(eo_iter_info, projected)
    F(eo_iter_info, inverted) F(eo_iter_info, reason) F(eo_iter_info, x) F(eo_iter_info, cpu_time)
    S(eo_stop_info) F(eo_stop_info, g) F(eo_stop_info, grad_norm0) F(eo_stop_info, decrement)
    F(eo_stop_info, tol) F(eo_stop_info, measure) F(eo_stop_info, g0) F(eo_stop_info, floor_grad) F(eo_stop_info, g_scale)
    F(eo_stop_info, grad_char)
    S(eo_stop_type) F(eo_stop_type, check) F(eo_stop_type, needs_direction)
    S(eo_ls_extra) F(eo_ls_extra, have_grad) F(eo_ls_extra, c2) F(eo_ls_extra, grad_first)
    S(eo_linesearch_type) F(eo_linesearch_type, search)
    S(eo_solver_ctx) F(eo_solver_ctx, linear) F(eo_solver_ctx, hessfix) F(eo_solver_ctx, stop)
    F(eo_solver_ctx, stop_params) F(eo_solver_ctx, tol) F(eo_solver_ctx, max_iters)
    F(eo_solver_ctx, time_budget) F(eo_solver_ctx, on_iter) F(eo_solver_ctx, user)
    F(eo_solver_ctx, optimizer) F(eo_solver_ctx, stop_state)
    S(eo_solve_result) F(eo_solve_result, g) F(eo_solve_result, decrement) F(eo_solve_result, time)
    F(eo_solve_result, n_factor) F(eo_solve_result, status) F(eo_solve_result, n_fallback)
    F(eo_solve_result, projected) F(eo_solve_result, n_not_pd)
    F(eo_solve_result, projected) F(eo_solve_result, cpu_time) F(eo_solve_result, c_gradient)
    S(eo_solver_opts) F(eo_solver_opts, linear) F(eo_solver_opts, tol) F(eo_solver_opts, max_iters)
    F(eo_solver_opts, time_budget) F(eo_solver_opts, backend)
    S(eo_callback_optimizer_def) F(eo_callback_optimizer_def, needs_hessian)
    F(eo_callback_optimizer_def, minimize) F(eo_callback_optimizer_def, direction)
    F(eo_callback_optimizer_def, user) F(eo_callback_optimizer_def, newton_decrement)
    S(eo_step_stats) F(eo_step_stats, max_disp) F(eo_step_stats, inverted) F(eo_step_stats, kinetic)
    F(eo_step_stats, gravity) F(eo_step_stats, contact) F(eo_step_stats, potential)
    F(eo_step_stats, work_prescribed) F(eo_step_stats, total_energy)
    S(eo_sim_step_result) F(eo_sim_step_result, t) F(eo_sim_step_result, grad_norm)
    F(eo_sim_step_result, n_value) F(eo_sim_step_result, n_factor) F(eo_sim_step_result, stats)
    F(eo_sim_step_result, rejected) F(eo_sim_step_result, min_substep)
    F(eo_sim_step_result, n_not_pd)
    F(eo_sim_step_result, rejected) F(eo_sim_step_result, min_substep) F(eo_sim_step_result, cpu_time)
    printf("eo_mesh_head nv %zu\neo_mesh_head nt %zu\neo_mesh_head X %zu\neo_mesh_head tets %zu\n",
           offsetof(eo_mesh, nv), offsetof(eo_mesh, nt), offsetof(eo_mesh, X), offsetof(eo_mesh, tets));
    S(eo_bench_progress) F(eo_bench_progress, scene_name) F(eo_bench_progress, phase)
    F(eo_bench_progress, elapsed) F(eo_bench_progress, eta)
    S(eo_bench_run_opts) F(eo_bench_run_opts, repeats) F(eo_bench_run_opts, plots)
    F(eo_bench_run_opts, progress) F(eo_bench_run_opts, user) F(eo_bench_run_opts, clock)
    F(eo_bench_run_opts, owned_sum)
    S(eo_bench_summary) F(eo_bench_summary, plots_made) F(eo_bench_summary, seconds)
    return 0;
}
