#!/usr/bin/env bash
# CPU time (user + sys, /usr/bin/time) of whole runs of each configuration, 3 repeats:
# twist (20 steps), inverted (10 steps), the IPC bunny twisted (2 steps, if
# ../shared/meshes is present). Every configuration: solver.tol = 1e-6 (its own measure:
# Newton's decrement ratio, the metric gradient ratio for the others), no fallback chain.
# lbfgs-wolfe is this library's L-BFGS (H0 = the PD matrix L^-1: BCQN's beta = 0 end);
# lbfgs-identity the paper's L-BFGS baseline (H0 = gamma I); sobolev the preconditioned
# gradient -L^-1 grad g (BCQN's beta = 1 end, the proxy of AQP without its acceleration).
# Usage: bash bench/results/bcqn/cpu.sh [build/cli/elastopt] > bench/results/bcqn/cpu.txt
set -u
cd "$(dirname "$0")/../../.."
exe=${1:-build/cli/elastopt}
tmp=$(mktemp -d)
configs=("newton:-o solver.optimizer=newton -o solver.hessian_fix=clamp -o solver.linesearch=backtracking"
         "lbfgs-wolfe:-o solver.optimizer=lbfgs -o solver.linesearch=wolfe"
         "lbfgs-identity:-o solver.optimizer=lbfgs -o solver.linesearch=wolfe -o solver.lbfgs.h0=scaled_identity"
         "sobolev:-o solver.optimizer=bcqn -o solver.bcqn.blend=sobolev"
         "bcqn:-o solver.optimizer=bcqn"
         "bcqn-backtracking:-o solver.optimizer=bcqn -o solver.linesearch=backtracking")
scenes=("twist:--scene twist -o time.steps=20" "inverted:--scene inverted -o time.steps=10")
[ -f ../shared/meshes/ipc_bunny.msh ] && scenes+=("bunny-twist:bench/real/bunny-twist.json -o time.steps=2")
echo "# $(date -u +%F) $(uname -m), load $(cut -d' ' -f1-3 /proc/loadavg); $("$exe" --version 2>/dev/null | head -1)"
echo "scene config cpu_median cpu_min cpu_max steps_converged steps iterations"
for sc in "${scenes[@]}"; do
  sname=${sc%%:*}; sargs=${sc#*:}
  for cf in "${configs[@]}"; do
    cname=${cf%%:*}; cargs=${cf#*:}
    ts=()
    for r in 1 2 3; do
      /usr/bin/time -f "%U %S" -o "$tmp/t" $exe run $sargs $cargs -o solver.tol=1e-6 -o solver.max_iters=20000 \
        -o 'solver.fallback=[]' --out "$tmp/o" --force --quiet 2>/dev/null
      ts+=("$(tail -n 1 "$tmp/t" | awk '{printf "%.3f", $1 + $2}')")
    done
    stats=$(printf '%s\n' "${ts[@]}" | sort -g | awk '{a[NR]=$1} END {printf "%s %s %s", a[2], a[1], a[3]}')
    runs=$(python3 -c "
import csv; r = list(csv.DictReader(open('$tmp/o/steps.csv')))
print(sum(1 for x in r if x['reason'].startswith('converged')), len(r), sum(int(x['iterations']) for x in r))")
    echo "$sname $cname $stats $runs"
  done
done
rm -rf "$tmp"
