#!/usr/bin/python3
"""Peer comparison: elastopt against FEniCSx (dolfinx + PETSc SNES + MUMPS) on the cantilever.

  bench/peers/run.py [--elastopt PATH] [--sizes 20k,100k] [--problems static,backward_euler]
                     [--repeats 3] [--config NAME='-o k=v -o k=v' ...] [--out bench/results/peers]

For every bar size the same tet mesh (`elastopt convert gen:...`, a TetGen pair) is read by
both codes. Per repeat, every case runs every elastopt configuration and FEniCSx in turn
(interleaved). Times are CPU seconds of the solve: elastopt's `--profile` ("CPU s in the
solver", the solving thread; the BLAS runs one thread) and FEniCSx's time.process_time()
around snes.solve() (the whole process, after a warm-up). Answers: the FEniCSx solution is
the reference; every elastopt run's tip (mean displacement of the free end face) and
largest vertex difference are measured against it. Writes report.md, runs.csv (every run)
and summary.csv (median [min, max] per case) into --out.

The elastopt binary: --elastopt, else $ELASTOPT, else ./build/cli/elastopt.
Without dolfinx the run is skipped with a message and exit status --skip-status (0; the
meson benchmark passes 77).
"""
import argparse
import csv
import json
import os
import platform
import re
import resource
import shlex
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PY = '/usr/bin/python3'
FENICSX = os.path.join(HERE, 'fenicsx_cantilever.py')
sys.path.insert(0, HERE)
from fenicsx_cantilever import read_vtu, tip  # noqa: E402  (numpy only at import)

# bars of the built-in scene's shape (1 x 0.1 x 0.1 m), 5 tets per hexahedral cell
SIZES = {'20k': (80, 7, 7), '100k': (120, 13, 13), '5k': (50, 5, 5), '1k': (20, 3, 3)}
# elastopt configurations: name -> list of -o overrides; 'scene' keeps the built-in scene's
# solver section, every other one starts from elastopt's defaults (the scene's solver
# section removed) and adds its overrides
CONFIGS = [
    ('scene', None),
    ('defaults', []),
    ('full-step', ['solver.linesearch=none']),
    ('metis', ['solver.cholmod.ordering=metis']),
    ('pcg-ew2', ['solver.linear=pcg', 'solver.pcg.preconditioner=cholmod_reuse', 'solver.newton.forcing=ew2']),
]
FENICSX_CONFIGS = [('fenicsx-lu', ['--pc', 'lu']), ('fenicsx-cholesky', ['--pc', 'cholesky'])]


def sh(cmd, env=None):
    """Run, return (completed process, CPU seconds of the child from rusage)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return p, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def scene_json(problem, mesh, keep_solver):
    """The built-in scene (examples/*.json are the same text) on the mesh file, neo_hookean."""
    name = 'cantilever_static.json' if problem == 'static' else 'cantilever.json'
    with open(os.path.join(ROOT, 'examples', name)) as f:
        d = json.load(f)
    d['mesh'] = {'file': mesh}
    d['material']['model'] = 'neo_hookean'
    d['output'] = {'every': 1, 'vtu': True}
    if problem == 'backward_euler':
        d['time'] = {'integrator': 'backward_euler', 'dt': 0.01, 'steps': 1}
    if not keep_solver:
        d.pop('solver', None)
    return d


def run_elastopt(exe, scene, overrides, out, env):
    cmd = [exe, 'run', scene, '--out', out, '--force', '--profile']
    for o in overrides:
        cmd += ['-o', o]
    p, child_cpu = sh(cmd, env)
    if p.returncode not in (0, 1):
        raise RuntimeError(f'{" ".join(cmd)} failed ({p.returncode}):\n{p.stderr}')
    m = re.search(r'profile \S+: (\d+) minimizations, (\d+) iterations, ([0-9.eE+-]+) CPU s in the solver', p.stdout + p.stderr)
    if not m:
        raise RuntimeError(f'no profile line in the output of {" ".join(cmd)}:\n{p.stdout}{p.stderr}')
    with open(os.path.join(out, 'summary.json')) as f:
        s = json.load(f)
    st = s['steps'][-1]
    _, U = read_vtu(os.path.join(out, 'frame_000001.vtu'))
    X, _ = read_vtu(os.path.join(out, 'frame_000000.vtu'))
    return {'iterations': s['total_iterations'], 'factorizations': st['evaluations']['factor'],
            'converged': s['all_converged'], 'reason': st['reason'], 'cpu_time': float(m.group(3)),
            'wall_time': s['total_solve_time'], 'process_cpu': child_cpu, 'grad_norm': st['grad_norm'],
            'blas': s['blas'], 'X': X, 'U': U, 'cmd': ' '.join(shlex.quote(c) for c in cmd)}


def run_fenicsx(mesh, problem, extra, out, env):
    os.makedirs(out, exist_ok=True)
    js, npz = os.path.join(out, 'fenicsx.json'), os.path.join(out, 'fenicsx.npz')
    cmd = [PY, FENICSX, '--mesh', mesh, '--problem', problem, '--dt', '0.01', '--linesearch', 'basic',
           '--json', js, '--save', npz] + extra
    p, child_cpu = sh(cmd, env)
    if p.returncode != 0:
        raise RuntimeError(f'{" ".join(cmd)} failed ({p.returncode}):\n{p.stderr[-3000:]}')
    with open(js) as f:
        r = json.load(f)
    z = np.load(npz)
    return {'iterations': r['iterations'], 'factorizations': r['iterations'], 'converged': r['reason'] > 0,
            'reason': r['reason'], 'cpu_time': r['cpu_time'], 'wall_time': r['wall_time'],
            'process_cpu': child_cpu, 'grad_norm': r['residual_norms'][-1], 'blas': r['blas'],
            'X': z['X'], 'U': z['U'], 'cmd': ' '.join(shlex.quote(c) for c in cmd),
            'versions': f"dolfinx {r['dolfinx']}, PETSc {r['petsc']}"}


def agreement(X, U, Xr, Ur):
    from scipy.spatial import cKDTree
    dist, idx = cKDTree(Xr).query(X)
    if dist.max() > 1e-9:
        raise RuntimeError(f'the meshes differ (a node {dist.max():g} m from the nearest reference node)')
    t, _ = tip(X, U)
    tr, _ = tip(Xr, Ur)
    d = np.linalg.norm(U - Ur[idx], axis=1)
    return float(np.linalg.norm(t - tr) / np.linalg.norm(tr)), float(d.max()), float(d.max() / np.linalg.norm(Ur, axis=1).max())


def machine():
    model = '?'
    try:
        out = subprocess.run(['lscpu'], stdout=subprocess.PIPE, text=True).stdout
        m = re.search(r'Model name:\s*(.+)', out)
        model = m.group(1).strip() if m else model
    except OSError:
        pass
    return {'cpu': model, 'cores': os.cpu_count(), 'kernel': platform.release()}


def fmt_t(v):
    return f'{statistics.median(v):.3f} [{min(v):.3f}, {max(v):.3f}]'


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--elastopt', default=os.environ.get('ELASTOPT', os.path.join(ROOT, 'build', 'cli', 'elastopt')))
    ap.add_argument('--sizes', default='20k,100k', help=f'comma list of {",".join(SIZES)}')
    ap.add_argument('--problems', default='static,backward_euler')
    ap.add_argument('--repeats', type=int, default=3)
    ap.add_argument('--config', action='append', default=[],
                    help="extra elastopt configuration NAME='-o k=v -o k=v' (from elastopt's defaults)")
    ap.add_argument('--only-configs', help='comma list of the elastopt configurations to run (default all)')
    ap.add_argument('--no-fenicsx-cholesky', action='store_true', help='run FEniCSx with MUMPS LU only')
    ap.add_argument('--out', default=os.path.join(ROOT, 'bench', 'results', 'peers'))
    ap.add_argument('--work', default='/tmp/elastopt-peers', help='meshes and run folders (not committed)')
    ap.add_argument('--skip-status', type=int, default=0)
    ap.add_argument('--agree-tol', type=float, default=1e-6, help='largest relative static tip difference accepted before timing')
    a = ap.parse_args()

    chk = subprocess.run([PY, '-c', 'import dolfinx, petsc4py, scipy'], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if chk.returncode != 0:
        print('peers: FEniCSx (dolfinx) is not installed for /usr/bin/python3: apt-get install -y python3-dolfinx;'
              ' skipped')
        sys.exit(a.skip_status)
    if not os.access(a.elastopt, os.X_OK):
        print(f'peers: no elastopt executable at {a.elastopt} (--elastopt or ELASTOPT)', file=sys.stderr)
        sys.exit(2)
    a.elastopt = os.path.abspath(a.elastopt)

    configs = list(CONFIGS)
    for c in a.config:
        name, _, opts = c.partition('=')
        ov = shlex.split(opts)
        configs.append((name, [ov[i + 1] for i in range(len(ov)) if ov[i] == '-o']))
    if a.only_configs:
        keep = a.only_configs.split(',')
        configs = [c for c in configs if c[0] in keep]
    fcfgs = FENICSX_CONFIGS[:1] if a.no_fenicsx_cholesky else FENICSX_CONFIGS

    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1', OMP_NUM_THREADS='1')
    sizes = a.sizes.split(',')
    problems = a.problems.split(',')
    load0 = os.getloadavg()
    t0 = time.time()

    cases = []   # (size, problem, mesh, scenes)
    for sz in sizes:
        nx, ny, nz = SIZES[sz]
        mesh = os.path.join(a.work, f'bar{sz}.node')
        subprocess.run([a.elastopt, 'convert', f'gen:1,0.1,0.1:{nx},{ny},{nz}:5', mesh], check=True,
                       stdout=subprocess.DEVNULL, env=env)
        for pr in problems:
            scenes = {}
            for keep in (True, False):
                path = os.path.join(a.work, f'{pr}-{sz}-{"scene" if keep else "defaults"}.json')
                with open(path, 'w') as f:
                    json.dump(scene_json(pr, mesh, keep), f, indent=1)
                scenes[keep] = path
            cases.append((sz, pr, mesh, scenes))

    # the BLAS kernels: the Python side gets the core elastopt runs (elastopt replaces a
    # generic core itself, docs/blas.md); checked per run below
    rows = []
    blas = {}
    fenv = dict(env)
    for rep in range(a.repeats):
        for sz, pr, mesh, scenes in cases:
            order = [('e', c) for c in configs] + [('f', c) for c in fcfgs]
            if rep % 2:
                order.reverse()
            for kind, (name, ov) in order:
                out = os.path.join(a.work, f'{pr}-{sz}-{name}')
                if kind == 'e':
                    r = run_elastopt(a.elastopt, scenes[ov is None], ov or [], out, env)
                    b = r['blas']
                    blas['elastopt'] = b['line']
                    if b.get('fixed_from') and 'OPENBLAS_CORETYPE' not in fenv:
                        fenv['OPENBLAS_CORETYPE'] = b['core']
                    core = b['core']
                else:
                    r = run_fenicsx(mesh, pr, ov, out, fenv)
                    b = r['blas']
                    blas['fenicsx'] = f"{b.get('config')}, core {b.get('core')}, {b.get('threads')} thread(s); " \
                                      f"{', '.join(os.path.basename(l) for l in b['libraries'])}"
                    blas['versions'] = r['versions']
                    core = b.get('core')
                r.update(size=sz, problem=pr, config=name, code='elastopt' if kind == 'e' else 'fenicsx',
                         repeat=rep, core=core)
                rows.append(r)
                print(f'[{rep}] {pr:15s} {sz:5s} {name:18s} it {r["iterations"]:3d}  cpu {r["cpu_time"]:8.3f} s'
                      f'  converged {r["converged"]}  core {core}', flush=True)
        if rep == 0:
            # the answers must agree before the timings mean anything
            for sz, pr, _, _ in cases:
                ref = next(r for r in rows if r['size'] == sz and r['problem'] == pr and r['config'] == fcfgs[0][0])
                for r in rows:
                    if r['size'] == sz and r['problem'] == pr:
                        r['tip_rel'], r['max_diff'], r['max_diff_rel'] = agreement(r['X'], r['U'], ref['X'], ref['U'])
                        print(f'    agreement {pr} {sz} {r["config"]}: tip {r["tip_rel"]:.2e}, max vertex {r["max_diff"]:.2e} m')
                        if pr == 'static' and r['tip_rel'] > a.agree_tol:
                            print(f'peers: {r["config"]} disagrees with FEniCSx on the static {sz} tip by {r["tip_rel"]:.2e}'
                                  f' (> {a.agree_tol:g}); stopping before the timings', file=sys.stderr)
                            sys.exit(1)
    for r in rows:
        if 'tip_rel' not in r:
            ref = next(q for q in rows if q['size'] == r['size'] and q['problem'] == r['problem']
                       and q['config'] == fcfgs[0][0] and q['repeat'] == 0)
            r['tip_rel'], r['max_diff'], r['max_diff_rel'] = agreement(r['X'], r['U'], ref['X'], ref['U'])
    load1 = os.getloadavg()
    cores = {r['core'] for r in rows}

    # files
    fields = ['size', 'problem', 'code', 'config', 'repeat', 'iterations', 'factorizations', 'converged', 'reason',
              'cpu_time', 'wall_time', 'process_cpu', 'grad_norm', 'tip_z', 'tip_rel', 'max_diff', 'max_diff_rel', 'core']
    with open(os.path.join(a.out, 'runs.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(fields)
        for r in rows:
            r['tip_z'] = float(tip(r['X'], r['U'])[0][2])
            w.writerow([r[k] if not isinstance(r[k], float) else f'{r[k]:.6g}' for k in fields])
    summ = []
    keys = []
    for r in rows:
        k = (r['size'], r['problem'], r['code'], r['config'])
        if k not in keys:
            keys.append(k)
    for k in keys:
        rs = [r for r in rows if (r['size'], r['problem'], r['code'], r['config']) == k]
        fx = [r['cpu_time'] for r in rows if (r['size'], r['problem'], r['config']) == (k[0], k[1], fcfgs[0][0])]
        tc = [r['cpu_time'] for r in rs]
        summ.append({'size': k[0], 'problem': k[1], 'code': k[2], 'config': k[3], 'tets': None,
                     'iterations': rs[0]['iterations'], 'iterations_all_equal': len({r['iterations'] for r in rs}) == 1,
                     'converged': all(r['converged'] for r in rs), 'cpu_median': statistics.median(tc),
                     'cpu_min': min(tc), 'cpu_max': max(tc), 'cpu_per_iteration': statistics.median(tc) / max(rs[0]['iterations'], 1),
                     'tip_z': rs[0]['tip_z'], 'tip_rel_diff': max(r['tip_rel'] for r in rs),
                     'max_vertex_diff': max(r['max_diff'] for r in rs),
                     'ratio_to_fenicsx_lu': statistics.median(tc) / statistics.median(fx), 'repeats': len(rs)})
    sf = ['size', 'problem', 'code', 'config', 'iterations', 'converged', 'cpu_median', 'cpu_min', 'cpu_max',
          'cpu_per_iteration', 'tip_z', 'tip_rel_diff', 'max_vertex_diff', 'ratio_to_fenicsx_lu', 'repeats']
    with open(os.path.join(a.out, 'summary.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(sf)
        for s in summ:
            w.writerow([s[k] if not isinstance(s[k], float) else f'{s[k]:.6g}' for k in sf])

    mc = machine()
    nverts = {}
    for sz, _, mesh, _ in cases:
        with open(mesh) as f:
            for line in f:
                if not line.startswith('#'):
                    nverts[sz] = int(line.split()[0])
                    break
    L = []
    L.append('# Peer comparison: elastopt and FEniCSx on the cantilever\n')
    L.append(f'Generated by `bench/peers/run.py` on {time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t0))}, '
             f'{a.repeats} repeats interleaved, {time.time() - t0:.0f} s in all. What is compared and how: docs/peers.md.\n')
    L.append('## Machine, BLAS\n')
    L.append(f'- CPU: {mc["cpu"]}, {mc["cores"]} cores (shared), Linux {mc["kernel"]}; load average '
             f'{load0[0]:.2f} at the start, {load1[0]:.2f} at the end')
    L.append(f'- elastopt: `{a.elastopt}`; {blas.get("elastopt")}')
    L.append(f'- FEniCSx: {blas.get("versions")}; {blas.get("fenicsx")}')
    L.append(f'- OpenBLAS cores of all runs: {", ".join(sorted(str(c) for c in cores))}'
             + (' (the same kernels)' if len(cores) == 1 else ' — **differ: the times are not comparable**'))
    L.append('- OPENBLAS_NUM_THREADS=1, OMP_NUM_THREADS=1 for both; one MPI rank\n')
    L.append('## Configurations\n')
    L.append('- `scene`: elastopt on the built-in scene as it is (its solver section: newton, hessian_fix clamp, tol 1e-10)')
    for name, ov in configs:
        if ov is not None:
            L.append(f'- `{name}`: elastopt defaults (the scene\'s solver section removed)'
                     + (''.join(f' `-o {o}`' for o in ov) if ov else ''))
    L.append('- `fenicsx-lu`: dolfinx, PETSc SNES newtonls, line search basic (full Newton steps), KSP preonly + '
             'MUMPS LU, converged at ||R|| <= 1e-9 ||R_0|| or ||dx|| <= 1e-8 ||x|| (PETSc\'s stol); the reference for the answers and the ratios')
    if len(fcfgs) > 1:
        L.append('- `fenicsx-cholesky`: the same with MUMPS Cholesky')
    L.append('\nCPU = CPU seconds of the solve, median [min, max] over the repeats (elastopt: `--profile`, '
             'the solver\'s thread; FEniCSx: time.process_time() around snes.solve()). tip rel = |tip - tip_ref| / '
             '|tip_ref| with tip the mean displacement of the free end face; max diff = the largest vertex '
             'displacement difference to fenicsx-lu; ratio = CPU median / fenicsx-lu\'s.\n')
    for sz, pr, _, _ in cases:
        L.append(f'## {pr}, {sz} ({SIZES[sz][0]}x{SIZES[sz][1]}x{SIZES[sz][2]} cells x 5 = '
                 f'{5 * SIZES[sz][0] * SIZES[sz][1] * SIZES[sz][2]} tets, {nverts[sz]} vertices)\n')
        L.append('| configuration | iterations | converged | CPU s | s / iteration | tip z (m) | tip rel | max diff (m) | ratio |')
        L.append('|---|---:|---|---|---:|---:|---:|---:|---:|')
        for s in summ:
            if (s['size'], s['problem']) != (sz, pr):
                continue
            tc = [r['cpu_time'] for r in rows if (r['size'], r['problem'], r['config']) == (sz, pr, s['config'])]
            L.append(f'| {s["config"]} | {s["iterations"]}{"" if s["iterations_all_equal"] else "*"} | '
                     f'{"yes" if s["converged"] else "NO"} | {fmt_t(tc)} | {s["cpu_per_iteration"]:.3f} | '
                     f'{s["tip_z"]:.9f} | {s["tip_rel_diff"]:.1e} | {s["max_vertex_diff"]:.1e} | '
                     f'{s["ratio_to_fenicsx_lu"]:.2f} |')
        L.append('')
    c0 = cases[-1]
    L.append(f'Commands of the last repeat for {c0[1]} {c0[0]} (the other cases differ in the file names):\n')
    for r in rows:
        if r['repeat'] == a.repeats - 1 and (r['size'], r['problem']) == (c0[0], c0[1]):
            L.append(f'- `{r["cmd"]}`')
    with open(os.path.join(a.out, 'report.md'), 'w') as f:
        f.write('\n'.join(L) + '\n')
    print(f'peers: wrote {a.out}/report.md, summary.csv, runs.csv')


if __name__ == '__main__':
    main()
