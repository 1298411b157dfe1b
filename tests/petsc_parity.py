#!/usr/bin/env python3
"""Iteration parity of two elastopt runs (steps.csv of each output folder).

usage: petsc_parity.py DIR_SERIAL DIR_MPI SLACK [LABEL]
Every step of the serial run must be converged in both runs and the MPI run's Newton
iteration count of each step must lie within SLACK of the serial one. Exits 1 otherwise."""
import csv
import sys


def rows(d):
    with open(d + "/steps.csv") as f:
        return list(csv.DictReader(f))


def main():
    a, b, slack = sys.argv[1], sys.argv[2], int(sys.argv[3])
    label = sys.argv[4] if len(sys.argv) > 4 else b
    ra, rb = rows(a), rows(b)
    ia = [int(r["iterations"]) for r in ra]
    ib = [int(r["iterations"]) for r in rb]
    print("%s: serial %s" % (label, " ".join(map(str, ia))))
    print("%s: mpi    %s" % (label, " ".join(map(str, ib))))
    ok = len(ra) == len(rb) and len(ra) > 0
    for r, s in zip(ra, rb):
        if r["converged"] != "1" or s["converged"] != "1":
            print("%s: step %s not converged (serial %s, mpi %s)" % (label, r["step"], r["reason"], s["reason"]))
            ok = False
        if abs(int(r["iterations"]) - int(s["iterations"])) > slack:
            print("%s: step %s: %s vs %s iterations" % (label, r["step"], r["iterations"], s["iterations"]))
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
