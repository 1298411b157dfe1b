#!/usr/bin/env python3
"""Interleaved CPU-time comparison of solver configurations on one scene, run by the CLI.

usage: compare_configs.py ELASTOPT SCENE REPS NAME=key=value;key=value ... [--base=key=value;...]

SCENE is a scene file (.json) or a built-in scene name; each NAME=... is a configuration
(its -o overrides, ';'-separated; empty = the defaults; an item exe=PATH runs that elastopt
binary instead of ELASTOPT, e.g. a build of an earlier commit), --base= overrides every run. The
configurations run interleaved REPS times (rep 0: all of them, rep 1: all, ...), each into
$TMPDIR/compare_configs_<scene>_<NAME> (replaced). Per run: the solving thread's CPU seconds
(summary.json total_solve_cpu_time) and the wall-clock solve time, Newton iterations,
factor calls, converged steps, the largest position difference to the first
configuration's first run over the largest per-step motion (restart.dat), exit status and
peak resident memory (wait4). Summary: CPU median [min, max] and the per-repeat speedup
over the first configuration. Used for docs/defaults.md (the linear solver policy)."""
import json, os, subprocess, sys, statistics, struct, tempfile
exe, scene, reps = sys.argv[1], sys.argv[2], int(sys.argv[3])
base = []
cfgs = []
for a in sys.argv[4:]:
    if a.startswith('--base='): base = [o for o in a[7:].split(';') if o]; continue
    name, _, ov = a.partition('=')
    cfgs.append((name, [o for o in ov.split(';') if o]))
def xfinal(d):
    b = open(os.path.join(d, 'restart.dat'), 'rb').read()
    i = b.find(b'array x ')
    j = b.find(b'\n', i)
    n = int(b[i+8:j])
    return struct.unpack('<%dd' % n, b[j+1:j+1+8*n])
res = {c[0]: [] for c in cfgs}
ref = None
tag = os.path.basename(scene).replace('.json', '')
for r in range(reps):
    for name, ov in cfgs:
        out = os.path.join(tempfile.gettempdir(), f'compare_configs_{tag}_{name}')
        run_exe = next((o[4:] for o in ov if o.startswith('exe=')), exe)
        cmd = [run_exe, 'run'] + (['--scene', scene] if not scene.endswith('.json') else [scene])
        for o in base + ov:
            if not o.startswith('exe='): cmd += ['-o', o]
        cmd += ['--out', out, '--force']
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        rss = ru.ru_maxrss / 1024 / 1024
        s = json.load(open(out + '/summary.json'))
        x = xfinal(out)
        if ref is None: ref = x
        motion = max(st['max_disp'] for st in s['steps'])
        err = max(abs(a - b) for a, b in zip(x, ref)) / motion
        fac = sum(st['evaluations']['factor'] for st in s['steps'])
        res[name].append(dict(cpu=s['total_solve_cpu_time'], it=s['total_iterations'], conv=s['step_counts']['converged'],
                              steps=s['steps_run'], err=err, fac=fac, rc=p.returncode, rss=rss))
        print(f'rep {r} {name:14s} cpu {s["total_solve_cpu_time"]:8.3f} wall {s["total_solve_time"]:8.3f} it {s["total_iterations"]:4d} fac {fac:4d} conv {s["step_counts"]["converged"]}/{s["steps_run"]} err {err:.2e} rc {p.returncode} rss {rss:.2f} GB', flush=True)
print('\nsummary (CPU s median [min, max]; ratio to the first configuration per repeat)')
first = cfgs[0][0]
for name, _ in cfgs:
    c = [v['cpu'] for v in res[name]]
    ratio = [res[first][i]['cpu'] / res[name][i]['cpu'] for i in range(reps)]
    print(f'{name:14s} cpu {statistics.median(c):8.3f} [{min(c):.3f}, {max(c):.3f}]  speedup vs {first} {statistics.median(ratio):.2f} [{min(ratio):.2f}, {max(ratio):.2f}]  it {res[name][0]["it"]} fac {res[name][0]["fac"]} err {max(v["err"] for v in res[name]):.1e} rss {max(v["rss"] for v in res[name]):.2f} GB')
