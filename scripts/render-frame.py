#!/usr/bin/python3
"""Draw one frame of an `elastopt run` as a PNG: the edges of the boundary triangles of
the deformed tet mesh (a 3D line plot with gnuplot), the rest shape in light grey.

    PYTHONPATH=python /usr/bin/python3 scripts/render-frame.py out/twist/frame_000050.vtu \
        docs/images/twist.png [--title TEXT] [--size 900,420] [--view 60,20]

Needs numpy, the elastopt package (python/, for its VTU reader) and gnuplot (gnuplot-nox:
pngcairo, else png). The README's picture is made by this script from examples/twist.json.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from elastopt.vtu import read_vtu  # noqa: E402  (the VTU reader needs no libelastopt)


def boundary_edges(tets):
    """Unique edges of the triangles used by exactly one tet."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]])
    key = np.sort(faces, axis=1)
    uniq, count = np.unique(key, axis=0, return_counts=True)
    tris = uniq[count == 1]
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]])
    return np.unique(np.sort(edges, axis=1), axis=0)


def write_edges(path, pts, edges):
    with open(path, "w") as f:
        for a, b in edges:
            f.write("%.9g %.9g %.9g\n%.9g %.9g %.9g\n\n\n" % (*pts[a], *pts[b]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("vtu")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    ap.add_argument("--size", default="900,420")
    ap.add_argument("--view", default="62,24")
    args = ap.parse_args()
    frame = read_vtu(args.vtu)
    x = frame["points"]
    rest = x - frame["point_data"]["displacement"]
    edges = boundary_edges(frame["cells"])
    lo = np.minimum(x.min(axis=0), rest.min(axis=0))
    hi = np.maximum(x.max(axis=0), rest.max(axis=0))
    with tempfile.TemporaryDirectory() as tmp:
        cur, ref = os.path.join(tmp, "frame.dat"), os.path.join(tmp, "rest.dat")
        write_edges(cur, x, edges)
        write_edges(ref, rest, edges)
        script = f"""
term = (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) ? "pngcairo" : "png"
if (term eq "pngcairo") set terminal pngcairo size {args.size} font "sans,10"; else set terminal png size {args.size}
set output "{args.png}"
set title "{args.title}"
set view {args.view}
set view equal xyz
set xrange [{lo[0]}:{hi[0]}]; set yrange [{lo[1]}:{hi[1]}]; set zrange [{lo[2]}:{hi[2]}]
set xyplane 0
set margins 0,0,0,0
unset border; unset tics; unset key
splot "{ref}" with lines lc rgb "#d0d0d0" lw 1, "{cur}" with lines lc rgb "#1f5fa8" lw 1.2
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)


if __name__ == "__main__":
    main()
