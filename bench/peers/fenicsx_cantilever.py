#!/usr/bin/python3
"""The elastopt cantilever in FEniCSx (dolfinx 0.5.2): the same tet mesh, clamp, material,
gravity and mass, solved by PETSc SNES newtonls with a direct MUMPS factorization.

  fenicsx_cantilever.py --mesh BAR.node --problem static|backward_euler [--dt 0.01]
                        [--E 1e7 --nu 0.3 --density 1000 --gravity 0,0,-9.81]
                        [--mass consistent|lumped] [--pc lu|cholesky] [--rtol 1e-10]
                        [--linesearch basic] [--compare FRAME.vtu] [--json OUT.json] [--save OUT.npz]

Problem (displacement u, P1 vector field, X the rest position):
  psi(F) = mu/2 (I_C - 3) - mu log J + lambda/2 (log J)^2     (elastopt's neo_hookean)
  mu = E / (2(1+nu)),  lambda = E nu / ((1+nu)(1-2nu))        (materials/params.c)
  static:          min  int psi dx - int rho g.u dx
  backward_euler:  min  1/(2h^2) int rho |u - h v0|^2 dx + int psi dx - int rho g.u dx
                   (one step from rest: x_n = X, v_n = 0, so u = x - X and v0 = 0)
The clamp is u = 0 on the vertices with X_x <= 0 (elastopt's box [[-1,-1,-1],[0,1,1]]).
Quadrature: the elastic term with one point (psi is constant on a P1 tet, so exact, as in
elastopt); the consistent mass with degree 2 (exact); the lumped mass with the vertex rule
(rho V/4 per vertex, elastopt's mass = "lumped").

Timed: snes.solve() alone (time.process_time: every thread of the process, and wall),
on a fresh Function, matrix and SNES, after a warm-up solve of the same code on a tiny bar
(JIT, MUMPS and PETSc loading are outside). The timed span includes what elastopt's solver
time includes: residual and Jacobian assembly, MUMPS analysis + factorization, solves and
the line search. Iterations = SNES Newton iterations (one Jacobian + factorization each).
"""
import argparse
import ctypes
import json
import os
import sys
import time

import numpy as np


def read_tetgen(path):
    """TetGen .node/.ele pair (1- or 0-based, comments allowed) -> points (n,3), tets (m,4) 0-based."""
    base = path[:-5] if path.endswith(('.node')) else path[:-4] if path.endswith('.ele') else path

    def rows(fn):
        with open(fn) as f:
            out = []
            for line in f:
                line = line.split('#', 1)[0].split()
                if line:
                    out.append(line)
        return out

    nr = rows(base + '.node')
    n, dim = int(nr[0][0]), int(nr[0][1])
    assert dim == 3, 'only 3D .node files'
    pts = np.array([[float(v) for v in r[1:4]] for r in nr[1:1 + n]])
    first = int(nr[1][0])
    er = rows(base + '.ele')
    m, k = int(er[0][0]), int(er[0][1])
    assert k == 4, 'only 4-node tets'
    tets = np.array([[int(v) for v in r[1:5]] for r in er[1:1 + m]], dtype=np.int64) - first
    return pts, tets


def read_vtu(path):
    """elastopt's VTU (appended raw, UInt64 headers): rest points (n,3) and displacement (n,3)."""
    import re
    with open(path, 'rb') as f:
        data = f.read()
    head, _, app = data.partition(b'<AppendedData encoding="raw">')
    app = app[app.index(b'_') + 1:]
    types = {'Float64': np.float64, 'Int64': np.int64, 'UInt8': np.uint8}
    arrays = {}
    for m in re.finditer(rb'<DataArray type="(\w+)" Name="(\w+)"[^>]*offset="(\d+)"', head):
        t, name, off = m.group(1).decode(), m.group(2).decode(), int(m.group(3))
        nbytes = int(np.frombuffer(app, np.uint64, 1, off)[0])
        arrays[name] = np.frombuffer(app, types[t], nbytes // np.dtype(types[t]).itemsize, off + 8)
    u = arrays['displacement'].reshape(-1, 3)
    x = arrays['Points'].reshape(-1, 3)   # the deformed positions
    return x - u, u


def blas_info():
    """The BLAS the process runs: every loaded BLAS/LAPACK library and OpenBLAS's own core/threads."""
    libs = set()
    with open('/proc/self/maps') as f:
        for line in f:
            p = line.split()[-1]
            if p.startswith('/') and any(s in os.path.basename(p) for s in ('blas', 'lapack', 'mumps')):
                libs.add(os.path.realpath(p))
    info = {'libraries': sorted(libs), 'core': None, 'config': None, 'threads': None}
    for p in sorted(libs):
        if 'openblas' in p:
            try:
                lib = ctypes.CDLL(p)
                lib.openblas_get_corename.restype = ctypes.c_char_p
                lib.openblas_get_config.restype = ctypes.c_char_p
                info['core'] = lib.openblas_get_corename().decode()
                info['config'] = lib.openblas_get_config().decode()
                info['threads'] = lib.openblas_get_num_threads()
                info['library'] = p
                break
            except (OSError, AttributeError):
                pass
    return info


def bar_mesh(nx, ny, nz, size=(1.0, 0.1, 0.1)):
    """A small 5-tet-per-cell box mesh for the warm-up (any valid tet mesh would do)."""
    xs = [np.linspace(0, s, n + 1) for s, n in zip(size, (nx, ny, nz))]
    P = np.array([[x, y, z] for z in xs[2] for y in xs[1] for x in xs[0]])
    idx = lambda i, j, k: i + (nx + 1) * (j + (ny + 1) * k)
    T = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                c = [idx(i + a, j + b, k + d) for d in (0, 1) for b in (0, 1) for a in (0, 1)]
                T += [[c[0], c[1], c[2], c[4]], [c[1], c[3], c[2], c[7]], [c[1], c[4], c[5], c[7]],
                      [c[2], c[4], c[7], c[6]], [c[1], c[2], c[4], c[7]]]
    return P, np.array(T, dtype=np.int64)


class Cantilever:
    """Forms and SNES for one mesh (built once; solve() makes fresh matrix/vectors/SNES)."""

    def __init__(self, pts, tets, a):
        from mpi4py import MPI
        import ufl
        from dolfinx import fem, mesh as dmesh
        self.fem = fem
        domain = ufl.Mesh(ufl.VectorElement('Lagrange', ufl.tetrahedron, 1))
        self.mesh = dmesh.create_mesh(MPI.COMM_WORLD, tets, pts, domain)
        V = fem.VectorFunctionSpace(self.mesh, ('Lagrange', 1))
        self.V = V
        self.u = fem.Function(V)
        v = ufl.TestFunction(V)
        du = ufl.TrialFunction(V)
        E, nu, rho = a.E, a.nu, a.density
        mu = E / (2 * (1 + nu))
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        g = fem.Constant(self.mesh, np.array(a.gravity, dtype=np.float64))
        u = self.u
        d = len(u)
        F = ufl.variable(ufl.Identity(d) + ufl.grad(u))
        C = F.T * F
        Ic = ufl.tr(C)
        J = ufl.det(F)
        psi = (mu / 2) * (Ic - 3) - mu * ufl.ln(J) + (lam / 2) * ufl.ln(J) ** 2
        dx1 = ufl.dx(metadata={'quadrature_degree': 1})
        Pi = psi * dx1 - rho * ufl.dot(g, u) * dx1
        if a.problem == 'backward_euler':
            h = a.dt
            # one step from rest: x_tilde = x_n + h v_n = X, so the inertia is rho/(2h^2)|u|^2
            if a.mass == 'lumped':
                dxm = ufl.dx(metadata={'quadrature_rule': 'vertex', 'quadrature_degree': 1})
            else:
                dxm = ufl.dx(metadata={'quadrature_degree': 2})
            Pi = Pi + rho / (2 * h * h) * ufl.dot(u, u) * dxm
        R = ufl.derivative(Pi, u, v)
        self.L = fem.form(R)
        self.a = fem.form(ufl.derivative(R, u, du))
        x = self.mesh.geometry.x
        hmin = 1e-9 * float(np.max(x.max(axis=0) - x.min(axis=0)))
        dofs = fem.locate_dofs_geometrical(V, lambda X: X[0] <= hmin)
        self.n_clamped = len(dofs)
        self.bcs = [fem.dirichletbc(np.zeros(3, dtype=np.float64), dofs, V)]
        self.args = a

    def solve(self):
        from petsc4py import PETSc
        import dolfinx.fem.petsc as fp
        fem, a = self.fem, self.args
        t_setup = time.process_time()
        self.u.x.array[:] = 0.0
        A = fp.create_matrix(self.a)
        b = fp.create_vector(self.L)
        x = self.u.vector.copy()
        snes = PETSc.SNES().create(self.mesh.comm)
        snes.setType('newtonls')
        snes.setFunction(self._F, b)
        snes.setJacobian(self._J, A)
        # converged when ||R|| <= rtol ||R_0|| or ||dx|| <= stol ||x|| (PETSc's default stol);
        # no absolute test. rtol 1e-10 is below the round-off floor of the assembled residual
        # at 100k tets (||R|| stalls at 2e-10 ||R_0||), hence 1e-9 by default.
        snes.setTolerances(rtol=a.rtol, atol=1e-300, stol=a.stol, max_it=a.max_it)
        ksp = snes.getKSP()
        ksp.setType('preonly')
        pc = ksp.getPC()
        pc.setType(a.pc)
        pc.setFactorSolverType('mumps')
        opts = PETSc.Options()
        opts['snes_linesearch_type'] = a.linesearch   # petsc4py 3.18 has no getLineSearch()
        norms = []
        snes.setMonitor(lambda s, it, rn: norms.append(float(rn)))
        snes.setFromOptions()
        x.set(0.0)
        setup = time.process_time() - t_setup
        c0, w0 = time.process_time(), time.perf_counter()
        EVENTS = ('SNESFunctionEval', 'SNESJacobianEval', 'SNESLineSearch', 'KSPSolve', 'PCSetUp', 'MatLUFactorSym',
                  'MatLUFactorNum', 'MatCholFctrSym', 'MatCholFctrNum', 'MatSolve')
        if a.log:
            PETSc.Log.begin()
            before = {ev: PETSc.Log.Event(ev).getPerfInfo() for ev in EVENTS}
        snes.solve(None, x)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        x.copy(self.u.vector)
        self.u.x.scatter_forward()
        log = {}
        if a.log:   # PETSc's event log of the timed solve alone (wall seconds, calls)
            for ev in EVENTS:
                info = PETSc.Log.Event(ev).getPerfInfo()
                n = info.get('count', 0) - before[ev].get('count', 0)
                if n:
                    log[ev] = {'time': info['time'] - before[ev].get('time', 0), 'count': n}
        out = {'petsc_log': log, 'iterations': snes.getIterationNumber(), 'reason': int(snes.getConvergedReason()),
               'cpu_time': cpu, 'wall_time': wall, 'setup_cpu': setup,
               'residual_norms': norms,
               'function_evals': snes.getFunctionEvaluations() if hasattr(snes, 'getFunctionEvaluations') else None}
        for o in (snes, A, b, x):
            o.destroy()
        return out

    def _F(self, snes, x, b):
        from petsc4py import PETSc
        import dolfinx.fem.petsc as fp
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(self.u.vector)
        self.u.vector.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        with b.localForm() as bl:
            bl.set(0.0)
        fp.assemble_vector(b, self.L)
        fp.apply_lifting(b, [self.a], bcs=[self.bcs], x0=[x], scale=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fp.set_bc(b, self.bcs, x, -1.0)

    def _J(self, snes, x, A, P):
        import dolfinx.fem.petsc as fp
        A.zeroEntries()
        fp.assemble_matrix(A, self.a, bcs=self.bcs)
        A.assemble()

    def nodes(self):
        """Rest coordinates (n,3) and displacement (n,3) of the P1 nodes."""
        X = self.V.tabulate_dof_coordinates()
        return X, self.u.x.array.reshape(-1, 3)


def compare(X, U, Xe, Ue):
    """Match the two node sets by rest position; max |u - u_e| and the matched arrays."""
    from scipy.spatial import cKDTree
    dist, idx = cKDTree(Xe).query(X)
    assert dist.max() < 1e-9, f'meshes differ: node {int(dist.argmax())} is {dist.max():g} from the nearest elastopt node'
    diff = np.linalg.norm(U - Ue[idx], axis=1)
    return float(diff.max()), idx


def tip(X, U):
    """Mean displacement of the vertices of the free end face (X_x = max)."""
    xmax = X[:, 0].max()
    sel = X[:, 0] >= xmax - 1e-9 * xmax
    return U[sel].mean(axis=0), int(sel.sum())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--mesh', required=True, help='TetGen .node/.ele base (elastopt convert OUT.node)')
    ap.add_argument('--problem', choices=['static', 'backward_euler'], default='static')
    ap.add_argument('--dt', type=float, default=0.01)
    ap.add_argument('--E', type=float, default=1e7)
    ap.add_argument('--nu', type=float, default=0.3)
    ap.add_argument('--density', type=float, default=1000.0)
    ap.add_argument('--gravity', default='0,0,-9.81')
    ap.add_argument('--mass', choices=['consistent', 'lumped'], default='consistent')
    ap.add_argument('--pc', choices=['lu', 'cholesky'], default='lu', help='MUMPS factorization (default lu, the FEniCSx demos\' choice)')
    ap.add_argument('--linesearch', default='basic', help='SNES line search: basic = full Newton steps (as dolfinx\'s own NewtonSolver); PETSc\'s newtonls default bt stalled on the 20k static bar (200 iterations)')
    ap.add_argument('--rtol', type=float, default=1e-9, help='SNES relative residual tolerance')
    ap.add_argument('--stol', type=float, default=1e-8, help='SNES relative step tolerance (PETSc default)')
    ap.add_argument('--max-it', type=int, default=50, help='SNES iteration cap')
    ap.add_argument('--compare', help="elastopt's frame VTU of the same problem")
    ap.add_argument('--json', help='write the results here')
    ap.add_argument('--save', help='write the rest node positions X and displacements U here (.npz)')
    ap.add_argument('--no-warmup', action='store_true')
    ap.add_argument('--log', action='store_true', help="PETSc's event log of the timed solve (wall s per phase) in the JSON")
    a = ap.parse_args()
    a.gravity = [float(v) for v in a.gravity.split(',')]

    try:
        import dolfinx  # noqa: F401
    except ImportError:
        print('fenicsx_cantilever: dolfinx is not installed (apt-get install python3-dolfinx); skipped')
        sys.exit(77)

    import dolfinx
    from petsc4py import PETSc
    if not a.no_warmup:
        P, T = bar_mesh(4, 1, 1)
        Cantilever(P, T, a).solve()
    pts, tets = read_tetgen(a.mesh)
    c0 = time.process_time()
    prob = Cantilever(pts, tets, a)
    build_cpu = time.process_time() - c0
    r = prob.solve()
    X, U = prob.nodes()
    t, nt = tip(X, U)
    res = {'code': 'fenicsx', 'dolfinx': dolfinx.__version__,
           'petsc': '.'.join(map(str, PETSc.Sys.getVersion())),
           'mesh': os.path.abspath(a.mesh), 'vertices': int(len(pts)), 'tets': int(len(tets)),
           'clamped_vertices': prob.n_clamped, 'problem': a.problem, 'mass': a.mass, 'pc': a.pc,
           'linesearch': a.linesearch, 'rtol': a.rtol, 'stol': a.stol, 'build_cpu': build_cpu,
           'tip': t.tolist(), 'tip_vertices': nt, 'max_disp': float(np.linalg.norm(U, axis=1).max()),
           'blas': blas_info(), **r}
    if a.save:
        np.savez(a.save, X=X, U=U)
    if a.compare:
        Xe, Ue = read_vtu(a.compare)
        d, idx = compare(X, U, Xe, Ue)
        te, _ = tip(Xe, Ue)
        res['elastopt_tip'] = te.tolist()
        res['max_vertex_diff'] = d
        res['max_vertex_diff_rel'] = d / float(np.linalg.norm(Ue, axis=1).max())
        res['tip_rel_diff'] = float(np.linalg.norm(t - te) / np.linalg.norm(te))
    txt = json.dumps(res, indent=1)
    if a.json:
        with open(a.json, 'w') as f:
            f.write(txt + '\n')
    print(txt)
    if r['reason'] <= 0:
        sys.exit(1)


if __name__ == '__main__':
    main()
