#!/usr/bin/env bash
# elastopt bench on bench/smoke.json (suite 'bench-smoke'): exit status 0, every output
# file, the CSV columns, a status and reason for every configuration, no NaN anywhere,
# every reference step converged, Newton's relative energy error down to <= 1e-6 on
# every step, plots when gnuplot is installed (an SVG beside each PNG, one panel per
# measured step, no gnuplot message), and a bad suite refused with exit 2.
set -u
EXE="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
SRC="${EO_SOURCE_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}"
OUT="${EO_BUILD_ROOT:-/tmp}/testtmp/bench_smoke"
rm -rf "$OUT"
mkdir -p "$OUT"
fail=0
pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*" >&2; fail=$((fail + 1)); }

start=$(date +%s)
"$EXE" bench "$SRC/bench/smoke.json" --out "$OUT/run" > "$OUT/stdout.txt" 2> "$OUT/stderr.txt"
rc=$?
end=$(date +%s)
[ $rc -eq 0 ] && ok || { bad "bench exited $rc"; cat "$OUT/stdout.txt" "$OUT/stderr.txt" >&2; }
echo "smoke suite ran in $((end - start)) s"
for f in curves.csv summary.csv reference.csv trajectory.csv report.md; do
  [ -s "$OUT/run/$f" ] && ok || bad "missing $f"
done
grep -q "config 1/" "$OUT/stderr.txt" && grep -q "left ~" "$OUT/stderr.txt" && ok || bad "no progress on stderr"

if python3 - "$OUT/run" <<'EOF'
import csv, math, os, sys
d = sys.argv[1]
def rows(name):
    with open(os.path.join(d, name), newline="") as f:
        return list(csv.DictReader(f))
curves, summary, ref, traj = rows("curves.csv"), rows("summary.csv"), rows("reference.csv"), rows("trajectory.csv")
need = {"curves.csv": (curves, ["scene", "step", "config", "iteration", "time", "time_min", "time_max", "g",
                                "rel_energy_err", "rel_pos_err", "grad_norm", "reason"]),
        "summary.csv": (summary, ["scene", "config", "baseline", "status", "reason", "t_1e-06_median",
                                  "t_1e-06_min", "t_1e-06_max", "ratio_1e-06", "traj_converged", "traj_max_dist"]),
        "reference.csv": (ref, ["scene", "step", "iterations", "reason", "converged", "g0", "gstar"]),
        "trajectory.csv": (traj, ["scene", "config", "step", "iterations", "reason", "dist_rms"])}
for name, (rs, cols) in need.items():
    assert rs, name + " is empty"
    missing = [c for c in cols if c not in rs[0]]
    assert not missing, "%s lacks columns %s" % (name, missing)
    for r in rs:
        for k, v in r.items():
            assert v is None or v.lower() not in ("nan", "-nan"), "%s: NaN in %s: %s" % (name, k, r)
for r in summary:
    assert r["status"] in ("converged", "elsewhere", "stopped", "non-finite"), r
    assert r["reason"], "no reason for %s on %s" % (r["config"], r["scene"])
    assert r["status"] != "non-finite", "non-finite: %s" % r
for r in ref:
    assert r["converged"] == "1", "reference did not converge: %s" % r
# the baseline is the first configuration and Newton: every step's curve reaches <= 1e-6
last = {}
for r in curves:
    if r["config"] == "newton-clamp-backtracking":
        last[(r["scene"], r["step"])] = r
assert last, "no Newton curve"
for key, r in last.items():
    e = float(r["rel_energy_err"])
    assert e <= 1e-6, "Newton stops at relative error %g on %s" % (e, key)
    assert r["reason"] == "reached_target", r
# errors decrease along Newton's curves (monotone line search)
prev = {}
for r in curves:
    if r["config"] != "newton-clamp-backtracking":
        continue
    k = (r["scene"], r["step"])
    e = float(r["rel_energy_err"])
    if k in prev:
        assert e <= prev[k] + 1e-12, "Newton error rose on %s: %g -> %g" % (k, prev[k], e)
    prev[k] = e
# the M-norm position error is recorded (first timed repeat) on every Newton iterate:
# 1 at the start guess, below 1e-3 where the energy error is below 1e-8
for r in curves:
    if r["config"] != "newton-clamp-backtracking":
        continue
    assert r["rel_pos_err"] not in ("", None), "no position error: %s" % r
    pe, e = float(r["rel_pos_err"]), float(r["rel_energy_err"])
    if r["iteration"] == "0":
        assert pe == 1.0, "position error at x0 is %g, not 1: %s" % (pe, r)
    elif abs(e) < 1e-8:
        assert pe < 1e-3, "energy error %g but position error %g: %s" % (e, pe, r)
# the trajectory covers the whole scene: the converging baseline has skip + steps frames
frames = {}
for r in traj:
    if r["config"] == "newton-clamp-backtracking":
        frames[r["scene"]] = frames.get(r["scene"], 0) + 1
assert frames.get("twist") == 6, "twist trajectory has %s frames, expected 5 skipped + 1" % frames.get("twist")
base = [r for r in summary if r["baseline"] == "1"]
assert base and all(r["config"] == "newton-clamp-backtracking" for r in base)
assert all(float(r["ratio_1e-06"]) == 1.0 for r in base)
print("csv checks passed: %d curve rows, %d summary rows" % (len(curves), len(summary)))
EOF
then ok; else bad "CSV checks"; fi

grep -q "^## Headline" "$OUT/run/report.md" && grep -q "^## Machine and build" "$OUT/run/report.md" &&
  grep -q "git " "$OUT/run/report.md" && ok || bad "report.md sections"
if command -v gnuplot > /dev/null 2>&1; then
  n=$(ls "$OUT/run/plots/"*.png 2> /dev/null | wc -l)
  [ "$n" -ge 2 ] && ok || bad "expected PNG plots, found $n"
  grep -q "plots/pareto.png" "$OUT/run/report.md" && ok || bad "report does not link the Pareto chart"
  # an SVG beside every PNG, and gnuplot said nothing (its log is kept only when not empty)
  for png in "$OUT/run/plots/"*.png; do
    [ -s "${png%.png}.svg" ] && grep -q "</svg>" "${png%.png}.svg" && ok || bad "no SVG beside $png"
  done
  logs=$(ls "$OUT/run/plots/"*.log 2> /dev/null)
  [ -z "$logs" ] && ok || { bad "gnuplot wrote messages: $logs"; cat $logs >&2; }
  # the scene plots: one panel per measured step (cantilever-snh has 2), one legend
  [ "$(grep -c '^# panel ' "$OUT/run/plots/cantilever-snh.gp")" -eq 4 ] && ok || bad "cantilever-snh.gp: not 2 panels x 2 terminals"
fi

# a bad suite: exit 2, nothing written, the message lists the valid keys
printf '{"scenes": [{"name": "a", "scene": "cantilever"}], "configs": [{"name": "n"}], "repeatz": 1}\n' > "$OUT/bad.json"
"$EXE" bench "$OUT/bad.json" --out "$OUT/bad" > /dev/null 2> "$OUT/bad.txt"
rc=$?
[ $rc -eq 2 ] && ok || bad "bad suite exited $rc"
grep -q "valid keys here" "$OUT/bad.txt" && ok || bad "bad suite message: $(cat "$OUT/bad.txt")"
[ ! -e "$OUT/bad" ] && ok || bad "bad suite wrote output"
"$EXE" bench > /dev/null 2>&1
[ $? -eq 2 ] && ok || bad "no suite should exit 2"
# a scene with an explicit integrator: nothing to minimize, refused at load (exit 2)
printf '{"scenes": [{"name": "a", "scene": "cantilever", "set": {"time.integrator": "rk4"}}], "configs": [{"name": "n"}]}\n' > "$OUT/explicit.json"
"$EXE" bench "$OUT/explicit.json" --out "$OUT/explicit" > /dev/null 2> "$OUT/explicit.txt"
rc=$?
[ $rc -eq 2 ] && ok || bad "explicit suite exited $rc"
grep -q "rk4 is explicit" "$OUT/explicit.txt" && ok || bad "explicit suite message: $(cat "$OUT/explicit.txt")"
[ ! -e "$OUT/explicit" ] && ok || bad "explicit suite wrote output"

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
