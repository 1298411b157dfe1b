# Shared set-up of the PETSc / MPI shell tests (sourced; $1 = elastopt, $2 = the backend
# module): skip (77) without the module or mpirun, the mpirun command line (root needs
# --allow-run-as-root), a temp folder with $TMPDIR inside it (where the ranks other than 0
# keep their scratch folders), check().
. "$(dirname "$0")/petsc_require.sh"
# mpirun's options (root needs --allow-run-as-root: CI runs as root)
mpi_opts=(--oversubscribe --mca mpi_yield_when_idle 1)
[ "$(id -u)" -eq 0 ] && mpi_opts+=(--allow-run-as-root)
mpi_n() { # mpi_n N: the mpirun command line for N ranks, into the array mpi
    mpi=(mpirun -n "$1" "${mpi_opts[@]}")
}
mpi_n 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scratch"
export TMPDIR=$tmp/scratch
fail=0
check() { if "$@"; then :; else echo "FAIL: $*"; fail=1; fi; }
# no scratch folder of a rank left in $TMPDIR
no_scratch() { [ "$(ls -A "$TMPDIR" | wc -l)" -eq 0 ]; }
# steps.csv of two runs equal but for the timings (solve_time, wall_time, solve_cpu_time)
same_steps() { cmp -s <(cut -d, -f1-5,8-31 "$1/steps.csv") <(cut -d, -f1-5,8-31 "$2/steps.csv"); }
# iterations.csv equal but for the time column
same_iters() { cmp -s <(cut -d, -f1-2,4- "$1/iterations.csv") <(cut -d, -f1-2,4- "$2/iterations.csv"); }
# a summary.json field, printed
sfield() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1/summary.json" "$2"; }
# rank_wrap: a script that runs its arguments as one rank under mpirun, writes the
# command's pid to $WD/pid.R and its exit status to $WD/rc.R (R = the rank), and forwards
# SIGINT / SIGTERM sent to it (by mpirun) to the command
rank_wrap=$tmp/rank_wrap.sh
cat > "$rank_wrap" <<'WRAP'
#!/bin/bash
r=${OMPI_COMM_WORLD_RANK:-$PMIX_RANK}
"$@" &
child=$!
echo $child > "$WD/pid.$r"
trap 'kill -INT $child' INT
trap 'kill -TERM $child' TERM
while :; do wait $child; rc=$?; kill -0 $child 2> /dev/null || break; done
echo $rc > "$WD/rc.$r"
exit $rc
WRAP
chmod +x "$rank_wrap"
# wait_steps DIR N: until DIR/steps.csv holds N completed steps (at most 60 s)
wait_steps() {
    for _ in $(seq 1 300); do
        [ -s "$1/steps.csv" ] && [ "$(($(wc -l < "$1/steps.csv") - 1))" -ge "$2" ] && return 0
        sleep 0.2
    done
    return 1
}
