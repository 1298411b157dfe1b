#!/usr/bin/env python3
"""Digest of an `elastopt bench` results folder (its summary.csv), in Markdown.

    python3 scripts/bench-digest.py bench/results/standard [--scenes PATTERN] [--fixed] [--all]
                                       [--vs CONFIG[,CONFIG...]] [--profile]

Prints, per configuration: the scenes on which it reached each accuracy (1e-2 and 1e-6, or every
threshold of the suite with --all or when those two are not both measured)
and the median, min and max over those scenes of its time to that accuracy divided by the
baseline's time measured in the same run (ratio < 1: faster than the baseline); then, per
scene, the fastest configuration at 1e-2 and at 1e-6 with its time, the next best and the
ratio between them (with "sep." when the min-max spreads of the two do not overlap), and
the baseline's time. With --fixed, also the per-frame time and distance at each fixed
iteration budget (fixed_<k>_* columns). With --vs, the ratios are to each configuration named
(one table each) instead of the baseline; each ratio compares the two CPU medians on a scene
both reached. With --profile, the performance-profile headline of every configuration from
perf_profile.csv: per stratum and accuracy, rho(1) (share of the instances on which it was the
fastest) and rho(2) (share solved within 2x the best time). Nothing here re-measures: it only reads the CSV
the benchmark wrote, so that docs/benchmark.md quotes the committed numbers.
"""
import csv
import re
import statistics
import sys


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    folder = argv[1]
    pat = None
    fixed = "--fixed" in argv
    if "--scenes" in argv:
        pat = re.compile(argv[argv.index("--scenes") + 1])
    rows = list(csv.DictReader(open(folder + "/summary.csv", newline="")))
    if pat:
        rows = [r for r in rows if pat.search(r["scene"])]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    base = next((r["config"] for r in rows if r.get("baseline") == "1"), configs[0])
    by = {(r["scene"], r["config"]): r for r in rows}
    have = [m.group(1) for k in rows[0] for m in [re.match(r"t_(.+)_median$", k)] if m]
    accs = [a for a in ("1e-02", "1e-06") if a in have]
    if "--all" in argv or len(accs) < 2:
        accs = have  # e.g. liu2017: 1e-2, 1e-3, 1e-4
    vs = [base]
    if "--vs" in argv:
        vs = argv[argv.index("--vs") + 1].split(",")
        for v in vs:
            if v not in configs:
                print(f"bench-digest: --vs {v}: not a configuration of {folder}", file=sys.stderr)
                return 2
    print(f"{folder}: {len(scenes)} scenes x {len(configs)} configurations; baseline {base}\n")
    for v in vs:
        what = "baseline" if v == base else v
        print("| configuration | " + " | ".join(
            f"reached {a} | ratio to {what} at {a}: median [min, max] (scenes)" for a in accs) + " |")
        print("|---|" + "---|---|" * len(accs))
        for c in configs:
            cells = []
            for a in accs:
                reached, ratios = 0, []
                for s in scenes:
                    r = by.get((s, c))
                    b = by.get((s, v))
                    t = num(r and r[f"t_{a}_median"])
                    tb = num(b and b[f"t_{a}_median"])
                    if t is not None:
                        reached += 1
                        if tb:
                            ratios.append(t / tb)
                if ratios:
                    cells += [f"{reached}/{len(scenes)}", f"{statistics.median(ratios):.2f} "
                              f"[{min(ratios):.2f}, {max(ratios):.2f}] ({len(ratios)})"]
                else:
                    cells += [f"{reached}/{len(scenes)}", "-"]
            print(f"| {c} | " + " | ".join(cells) + " |")
        print()
    if "--profile" in argv:
        prof = {}
        for r in csv.DictReader(open(folder + "/perf_profile.csv", newline="")):
            key = (r["stratum"], r["threshold"], r["config"])
            tau = float(r["tau"])
            if tau in (1.0, 2.0):
                prof.setdefault(key, {})[tau] = (float(r["fraction"]), int(r["instances"]))
        strata = list(dict.fromkeys(k[0] for k in prof))
        levels = list(dict.fromkeys(k[1] for k in prof))
        print("| stratum | configuration | " + " | ".join(f"rho(1) at {a} | rho(2) at {a}" for a in levels) +
              " |")
        print("|---|---|" + "---|---|" * len(levels))
        for st in strata:
            for c in configs:
                cells = []
                for a in levels:
                    p = prof.get((st, a, c), {})
                    n = (p.get(2.0) or p.get(1.0) or (0, 0))[1]
                    cells += [f"{p[t][0]:.2f}" if t in p else "-" for t in (1.0, 2.0)]
                print(f"| {st} ({n}) | {c} | " + " | ".join(cells) + " |")
        print()
    print("| scene | accuracy | fastest | ms | next best | ms | ratio | baseline ms |")
    print("|---|---|---|---|---|---|---|---|")
    for s in scenes:
        for a in accs:
            cand = []
            for c in configs:
                r = by.get((s, c))
                t = num(r and r[f"t_{a}_median"])
                if t is not None:
                    cand.append((t, c, num(r[f"t_{a}_min"]), num(r[f"t_{a}_max"])))
            cand.sort()
            b = by.get((s, base))
            tb = num(b and b[f"t_{a}_median"])
            tbs = f"{tb * 1e3:.4g}" if tb else "not reached"
            if not cand:
                print(f"| {s} | {a} | none | | | | | {tbs} |")
                continue
            t0, c0, lo0, hi0 = cand[0]
            if len(cand) > 1:
                t1, c1, lo1, hi1 = cand[1]
                sep = " sep." if (hi0 is not None and lo1 is not None and hi0 < lo1) else ""
                print(f"| {s} | {a} | {c0} | {t0 * 1e3:.4g} | {c1} | {t1 * 1e3:.4g} | "
                      f"{t1 / t0:.2f}x{sep} | {tbs} |")
            else:
                print(f"| {s} | {a} | {c0} | {t0 * 1e3:.4g} | - | | | {tbs} |")
    if fixed:
        ks = sorted({int(m.group(1)) for k in rows[0] for m in [re.match(r"fixed_(\d+)_time_per_frame", k)] if m})
        print()
        for k in ks:
            print(f"\nfixed budget {k} it/frame: ms per frame (relative distance to the reference motion)\n")
            print("| scene | " + " | ".join(configs) + " |")
            print("|---|" + "---|" * len(configs))
            for s in scenes:
                cells = []
                for c in configs:
                    r = by.get((s, c))
                    t = num(r and r.get(f"fixed_{k}_time_per_frame"))
                    d = num(r and r.get(f"fixed_{k}_rel_dist"))
                    cells.append(f"{t * 1e3:.4g} ({d:.2g})" if t is not None and d is not None else "")
                print(f"| {s} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
