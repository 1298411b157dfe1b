#!/usr/bin/env bash
# Refinement sweep for the AQP claim (Kovalsky, Galun & Lipman 2016: iteration counts
# nearly independent of mesh resolution): iterations of the first step of the cantilever
# (E = 1e7) and the twisting bar (stable_neo_hookean) to solver.tol = 1e-6 under the
# default convergence measure (relative_decrement: metric gradient ratio for first-order
# methods, Newton-decrement ratio for newton) on mesh.generate.cells [10,1,1], [20,2,2],
# [40,4,4] (and the static cantilever, no inertia: the regime of the paper), for aqp, aqp without momentum, lbfgs (Wolfe), L-BFGS-PD and newton; plus
# admm_pd. CPU time of each run (user + sys of the process, GNU time) over 3 repeats:
# median [min, max]. Usage: bash bench/admm_aqp_sweep.sh [elastopt] > results.csv
set -euo pipefail
exe=${1:-build/cli/elastopt}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "scene,cells,config,iterations,reason,cpu_median_s,cpu_min_s,cpu_max_s"
for scene in cantilever twist cantilever_static; do
  for cells in 10,1,1 20,2,2 40,4,4; do
    for cfg in aqp aqp-plain lbfgs pd-lbfgs5 newton admm_pd; do
      case $cfg in
        aqp) o=(-o solver.optimizer=aqp) ;;
        aqp-plain) o=(-o solver.optimizer=aqp -o solver.aqp.accelerate=false) ;;
        lbfgs) o=(-o solver.optimizer=lbfgs -o solver.linesearch=wolfe) ;;
        pd-lbfgs5) o=(-o solver.optimizer=projective_dynamics -o solver.projective_dynamics.lbfgs_history=5) ;;
        newton) o=(-o solver.optimizer=newton -o solver.hessian_fix=clamp) ;;
        admm_pd) o=(-o solver.optimizer=admm_pd) ;;
      esac
      times=()
      it=; reason=
      for rep in 1 2 3; do
        rm -rf "$tmp/out"
        /usr/bin/time -f "%U %S" -o "$tmp/time" "$exe" run --scene $scene --out "$tmp/out" --quiet \
          -o "mesh.generate.cells=[$cells]" -o material.model=stable_neo_hookean -o material.E=1e7 \
          -o time.steps=1 -o solver.tol=1e-6 -o solver.max_iters=20000 -o solver.fallback=[] "${o[@]}" || true
        read -r u s < <(tail -1 "$tmp/time")
        times+=("$(echo "$u + $s" | bc -l)")
        it=$(awk -F, 'NR == 2 {print $3}' "$tmp/out/steps.csv")
        reason=$(awk -F, 'NR == 2 {print $4}' "$tmp/out/steps.csv")
      done
      sorted=$(printf '%s\n' "${times[@]}" | sort -g)
      med=$(echo "$sorted" | sed -n 2p); mn=$(echo "$sorted" | sed -n 1p); mx=$(echo "$sorted" | sed -n 3p)
      echo "$scene,[$cells],$cfg,$it,$reason,$med,$mn,$mx"
    done
  done
done
