#!/usr/bin/env bash
# Strong and weak scaling of the distributed path (docs/scaling.md): the generated twist,
# one step capped at two Newton iterations (the first Hessian, the preconditioner setup,
# two solves), solver.backend=petsc with petsc_ksp (PC=gamg: CG + GAMG, the default here;
# PC=mumps). Per run and rank: peak RSS and processor time (user + system, /usr/bin/time),
# and from PETSc's -log_view (rank 0's summary of all ranks): MPI messages, bytes and
# reductions in total, KSPSolve calls and CG iterations (-ksp_converged_reason).
# Every rank exits 0 (the step is not converged after two iterations: that is the point;
# a nonzero exit would make mpirun kill the other ranks before their times are written).
# Processor time includes Open MPI's polling while a rank waits (mpi_yield_when_idle 1
# lowers it); on a machine with fewer cores than ranks the runs are oversubscribed, which
# leaves memory, message counts and bytes meaningful, and processor time an upper bound.
# usage: [PC=gamg|mumps] bench/petsc_scaling/run.sh ELASTOPT OUTDIR strong|strong-1m|weak
#   strong: 108k, 400k and 980k tets on 1, 2, 4, 8 ranks (strong-1m: the 980k rows alone)
#   weak:   51.2k tets per rank (cells [40 P, 16, 16]) on 1, 2, 4, 8 ranks
# Writes OUTDIR/scaling-<pc>.csv (one row per run) and prints it.
set -u
E=$1; out=$2; what=$3
pc=${PC:-gamg}
mkdir -p "$out"
csv=$out/scaling-$pc-$what.csv
mpi=(mpirun --oversubscribe --mca mpi_yield_when_idle 1)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
echo "kind,cells,tets,ranks,pc,newton_its,ksp_solves,cg_its,rss_mb_max,rss_mb_mean,cpu_s_max,cpu_s_sum,msgs,msg_mb,reductions,exit" > "$csv"
run() { # cells ranks
    local cells=$1 p=$2 tag
    tag=$(echo "$cells" | tr ',' 'x')-$pc-$p
    rm -f "$out"/t-"$tag".*
    PETSC_OPTIONS="-log_view :$out/logview-$tag.txt -ksp_converged_reason" \
    "${mpi[@]}" -n "$p" bash -c '/usr/bin/time -f "%M %U %S" -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"; exit 0' \
        "$out/t-$tag" "$E" run --scene twist -o "mesh.generate.cells=[$cells]" -o time.steps=1 -o solver.max_iters=2 \
        -o output.vtu=false -o "solver.fallback=[]" -o solver.backend=petsc -o solver.petsc_ksp.pc=$pc \
        $([ "$pc" = gamg ] && echo "-o solver.petsc_ksp.ksp=cg") --out "$out/run-$tag" --force -q -v > "$out/log-$tag" 2>&1
    local rc=$?
    /usr/bin/python3 - "$out" "$tag" "$cells" "$p" "$pc" "$rc" "$what" >> "$csv" <<'PY'
import glob, json, re, sys
out, tag, cells, p, pc, rc, what = sys.argv[1:]
c = [int(v) for v in cells.split(",")]
tets = 5 * c[0] * c[1] * c[2]
rss, cpu = [], []
for f in sorted(glob.glob(f"{out}/t-{tag}.*")):
    line = [l for l in open(f) if re.match(r"^\d+ [\d.]+ [\d.]+$", l.strip())]
    if line:
        m, u, s = line[-1].split()
        rss.append(int(m) / 1024)
        cpu.append(float(u) + float(s))
try:
    its = json.load(open(f"{out}/run-{tag}/summary.json"))["total_iterations"]
except Exception:
    its = ""
log = open(f"{out}/log-{tag}", errors="replace").read()
cg = [int(x) for x in re.findall(r"solve converged due to \w+ iterations (\d+)", log)]
msgs = mlen = red = ""
try:
    lv = open(f"{out}/logview-{tag}.txt").read()
    def tot(name):
        m = re.search(name + r":\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", lv)
        return float(m.group(4)) if m else float("nan")
    msgs = "%.0f" % tot(r"MPI Msg Count") if "MPI Msg Count" in lv else "%.0f" % tot(r"MPI Messages")
    mlen = "%.2f" % (tot(r"MPI Msg Len \(bytes\)") / 1e6) if "MPI Msg Len" in lv else "%.2f" % (tot(r"MPI Message Lengths") / 1e6)
    m = re.search(r"MPI Reductions:\s+(\S+)", lv)
    red = "%.0f" % float(m.group(1)) if m else ""
except Exception:
    pass
mean = sum(rss) / len(rss) if rss else float("nan")
print(f"{what},{cells.replace(',', 'x')},{tets},{p},{pc},{its},{len(cg)},{sum(cg)},{max(rss) if rss else ''},"
      f"{mean:.0f},{max(cpu) if cpu else ''},{sum(cpu):.1f},{msgs},{mlen},{red},{rc}")
PY
    tail -1 "$csv"
}
case "$what" in
  strong)
    for cells in 128,13,13 200,20,20; do for p in 1 2 4 8; do run $cells $p; done; done
    for p in 1 2 4 8; do run 250,28,28 $p; done ;;
  strong-1m) # the 980k rows alone
    for p in 1 2 4 8; do run 250,28,28 $p; done ;;
  weak)
    for p in 1 2 4 8; do run $((40 * p)),16,16 $p; done ;;
  *) echo "usage: [PC=gamg|mumps] $0 ELASTOPT OUTDIR strong|strong-1m|weak" >&2; exit 2 ;;
esac
