#!/usr/bin/env python3
"""The scaling model of docs/scaling.md, fitted to bench/petsc_scaling/run.sh's rows.

usage: model.py DIR      (DIR holds scaling-gamg-strong.csv and scaling-gamg-weak.csv)

Fits, each from the measured rows only (printed with the points they rest on and the
model's value at every measured point):
  memory per rank, P >= 2      M = a + b n            (n = tets of the rank's part)
  memory, one rank             M = a1 + b1 N
  CG iterations per solve      its = c N^e            (one rank; the same bar refined)
  CPU per Newton iteration     T = k its n            (one rank: work per tet and CG iteration)
  bytes sent per CG iteration  B = beta g its         (weak series, P >= 2; g = interface
                                                       unknowns of a part)
Then projects 1e7 - 1e9 tets on 10 - 1000 ranks with the assumptions printed. No
third-party packages (the standard library only)."""
import csv
import math
import sys

VPT = 25284 / 108160  # vertices per tet of the generated bars
SOLVES_PER_IT = 1.5    # the runs: 2 Newton iterations, 3 solves (one step, capped)
LATENCY = 2e-6         # assumed network: s per message
BANDWIDTH = 10e9       # assumed network: bytes per s per rank
NEIGHBOURS = 6         # assumed: face neighbours of an interior cube-shaped part
MSG_PER_NEIGHBOUR = None  # fitted below (messages per CG iteration and neighbour)


def rows(path):
    with open(path) as f:
        return [r for r in csv.DictReader(f) if r["exit"] == "0"]


def lsq(xs, ys):
    """least squares y = a + b x"""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return my - b * mx, b


def slab_interface(cells_yz, p, rank_count):
    """interface unknowns per rank of the weak series' slabs: 2 faces inside, 1 at the ends"""
    face = (cells_yz[0] + 1) * (cells_yz[1] + 1) * 3
    if p == 1:
        return 0.0
    return face * (2 * (p - 2) + 2) / p


def main(d):
    strong = rows(d + "/scaling-gamg-strong.csv")
    weak = rows(d + "/scaling-gamg-weak.csv")
    allr = strong + weak
    # memory per rank on >= 2 ranks against the part's tets
    multi = [r for r in allr if int(r["ranks"]) >= 2]
    xs = [int(r["tets"]) / int(r["ranks"]) for r in multi]
    ys = [float(r["rss_mb_max"]) for r in multi]
    a, b = lsq(xs, ys)
    print("memory per rank, P >= 2: M = %.0f MB + %.2f KB per tet of the part" % (a, b * 1e3))
    for r, x, y in zip(multi, xs, ys):
        print("   %-6s %8s tets %d ranks: measured %5.0f MB, model %5.0f MB (%+.0f %%)"
              % (r["kind"], r["tets"], int(r["ranks"]), y, a + b * x, 100 * (a + b * x - y) / y))
    one = [r for r in strong if int(r["ranks"]) == 1]
    a1, b1 = lsq([int(r["tets"]) for r in one], [float(r["rss_mb_max"]) for r in one])
    print("memory, one rank: M = %.0f MB + %.2f KB per tet" % (a1, b1 * 1e3))
    # CG iterations per solve (one rank, the same bar refined)
    ln = [(math.log(int(r["tets"])), math.log(int(r["cg_its"]) / int(r["ksp_solves"]))) for r in one]
    lc, e = lsq([p[0] for p in ln], [p[1] for p in ln])
    c = math.exp(lc)
    print("CG iterations per solve (one rank, bar refined): its = %.3g N^%.3f" % (c, e))
    for r in one:
        its = int(r["cg_its"]) / int(r["ksp_solves"])
        print("   %8s tets: measured %.1f, model %.1f" % (r["tets"], its, c * int(r["tets"]) ** e))
    ws = [int(r["cg_its"]) / int(r["ksp_solves"]) for r in weak]
    print("   weak series (bar lengthened, h fixed): %s per solve on 1/2/4/8 ranks (flat)"
          % " / ".join("%.0f" % w for w in ws))
    # CPU per Newton iteration per tet and CG iteration (one rank)
    ks = [float(r["cpu_s_max"]) / int(r["newton_its"]) / int(r["tets"])
          / (int(r["cg_its"]) / int(r["ksp_solves"])) for r in one]
    k = sum(ks) / len(ks)
    print("CPU per Newton iteration: T = %.3g us x its x n (one rank; per point %s)"
          % (k * 1e6, ", ".join("%.3g" % (x * 1e6) for x in ks)))
    # bytes and messages per CG iteration on the weak series
    betas, msgs = [], []
    for r in weak:
        p = int(r["ranks"])
        if p < 2:
            continue
        g = slab_interface((16, 16), p, p)
        its = int(r["cg_its"])
        betas.append(float(r["msg_mb"]) * 1e6 / p / its / g)
        msgs.append(float(r["msgs"]) / p / its / (2 * (p - 1) / p))
    beta = sum(betas) / len(betas)
    mpn = sum(msgs) / len(msgs)
    print("bytes sent per rank and CG iteration: %.0f B x interface unknowns (per point %s)"
          % (beta, ", ".join("%.0f" % x for x in betas)))
    print("messages per rank, CG iteration and neighbour: %.1f (per point %s)"
          % (mpn, ", ".join("%.1f" % x for x in msgs)))
    # strong-scaling check of the time model on several ranks (CPU per rank)
    print("CPU per rank, model (compute only) against measured (oversubscribed above 2 ranks):")
    over = []
    for r in strong:
        p, n = int(r["ranks"]), int(r["tets"]) / int(r["ranks"])
        its = int(r["cg_its"]) / int(r["ksp_solves"])
        t = k * its * n * int(r["newton_its"])
        if p >= 2:
            over.append(float(r["cpu_s_max"]) / t)
        print("   %8s tets %d ranks: measured %6.2f s, model %6.2f s" % (r["tets"], p, float(r["cpu_s_max"]), t))
    over.sort()
    ov = over[len(over) // 2]
    print("   on >= 2 ranks measured / model: median %.2f [%.2f, %.2f] (the slowest rank's waits, polled "
          "as CPU, and the ghost work): the projection multiplies the compute by it" % (ov, over[0], over[-1]))

    print()
    print("| N tets | P ranks | tets/rank | memory/rank (model) | CG its/solve, refined / h fixed "
          "| interface unknowns/rank | MB sent/rank per Newton it | s per Newton it: compute + network |")
    print("|---|---|---|---|---|---|---|---|")
    its_weak = sum(ws[1:]) / len(ws[1:])
    for N in (1e7, 1e8, 1e9):
        for P in (10, 100, 1000):
            n = N / P
            s = (VPT * n) ** (1 / 3)
            g = 18 * s * s
            its = c * N ** e
            mem = a + b * n
            cg_per_it = SOLVES_PER_IT * its
            sent = beta * g * cg_per_it
            t_comp = k * its * n * (ov if P > 1 else 1)
            t_net = sent / BANDWIDTH + cg_per_it * (mpn * NEIGHBOURS + 3 * math.log2(P)) * LATENCY
            print("| %.0e | %d | %.0e | %.2f GB | %.0f / %.0f | %.3g k | %.0f | %.3g + %.2g |"
                  % (N, P, n, mem / 1e3, its, its_weak, g / 1e3, sent / 1e6, t_comp, t_net))
    print()
    print("assumptions: %.3f vertices per tet; interior cube-shaped parts (18 s^2 interface "
          "unknowns, s = vertices a side), %d face neighbours; %.1f solves per Newton "
          "iteration; network %.0f us latency, %.0f GB/s per rank (not measured here); CPU per "
          "tet and CG iteration of this machine's 1-rank runs times the measured multi-rank factor; CG iterations from the refined-bar "
          "fit (pessimistic: at fixed h they were flat)" % (VPT, NEIGHBOURS, SOLVES_PER_IT,
                                                             LATENCY * 1e6, BANDWIDTH / 1e9))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
