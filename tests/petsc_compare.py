#!/usr/bin/env python3
"""Compare the positions of two elastopt runs (restart.dat of each output folder).

usage: petsc_compare.py DIR_A DIR_B TOL [LABEL]
Prints max|x_A - x_B| relative to max|x_A| (positions) and to the largest displacement
max|x_A - x_A(t=0)| (stricter), and exits 1 if the latter exceeds TOL."""
import struct
import sys


def read_restart(path):
    with open(path, "rb") as f:
        data = f.read()
    pos, arrays, step = 0, {}, None
    while pos < len(data):
        end = data.index(b"\n", pos)
        line = data[pos:end].decode()
        pos = end + 1
        words = line.split()
        if not words:
            continue
        if words[0] == "step":
            step = int(words[1])
        if words[0] == "array":
            n = int(words[2])
            arrays[words[1]] = struct.unpack("<%dd" % n, data[pos:pos + 8 * n])
            pos += 8 * n
    return step, arrays


def main():
    a, b, tol = sys.argv[1], sys.argv[2], float(sys.argv[3])
    label = sys.argv[4] if len(sys.argv) > 4 else b
    sa, xa = read_restart(a + "/restart.dat")
    sb, xb = read_restart(b + "/restart.dat")
    if sa != sb or len(xa["x"]) != len(xb["x"]):
        print("%s: different runs (steps %s vs %s)" % (label, sa, sb))
        return 1
    xa, xb = xa["x"], xb["x"]
    diff = max(abs(p - q) for p, q in zip(xa, xb))
    scale = max(abs(p) for p in xa)
    print("%s: step %d, max |dx| = %.3g m, relative to max |x| %.2g" % (label, sa, diff, diff / scale))
    return 0 if diff <= tol * scale else 1


if __name__ == "__main__":
    sys.exit(main())
