#!/usr/bin/python3
"""Compare hobak.sh's result.txt (rest x y z, displacement per vertex) with a FEniCSx solution
(.npz of fenicsx_cantilever.py --save): tip (mean displacement of the free end face) and the
largest vertex difference, nodes matched by rest position.

  bench/peers/hobak_compare.py /tmp/hobak-peers/result.txt /tmp/elastopt-peers/static-20k-fenicsx-lu/fenicsx.npz
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fenicsx_cantilever import tip  # noqa: E402

h = np.loadtxt(sys.argv[1])
z = np.load(sys.argv[2])
Xh, Uh = h[:, :3], h[:, 3:]
d, idx = cKDTree(Xh).query(z['X'])
if d.max() > 1e-9:
    sys.exit(f'hobak_compare: the meshes differ (a node {d.max():g} m from the nearest HOBAK node)')
Uh = Uh[idx]
t, _ = tip(z['X'], Uh)
tr, _ = tip(z['X'], z['U'])
print(f'tip_z {t[2]:.9f} reference {tr[2]:.9f} tip_rel {np.linalg.norm(t - tr) / np.linalg.norm(tr):.2e} '
      f'max_vertex_diff {np.linalg.norm(Uh - z["U"], axis=1).max():.2e} m')
