"""The speed-against-error benchmark (bench.h) run in this process, so that optimizers
registered from Python are timed beside the built-in ones."""
from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Union

from ._core import check, ctx, set_pending
from ._ffi import bench_lib, ffi, string


@dataclass
class BenchResult:
    """What eo_bench_run found and wrote."""
    out_dir: Path
    runs: int
    ref_failures: int
    nonfinite: int
    nan: int
    required_failures: int
    plots_made: int
    seconds: float
    scenes: list
    configs: list
    rows: list = field(default_factory=list)   # summary.csv, one dict per scene x config
    files: dict = field(default_factory=dict)  # name -> path of every output file

    def row(self, scene: str, config: str) -> Dict[str, str]:
        """The summary.csv row of one scene and configuration."""
        for r in self.rows:
            if r["scene"] == scene and r["config"] == config:
                return r
        raise KeyError((scene, config))


def _absolute_files(suite: dict, base: Union[str, Path]) -> dict:
    """Copy of a suite dict whose relative scene `file` entries are made absolute
    (relative to `base`), since the suite is written elsewhere."""
    s = json.loads(json.dumps(suite))
    for sc in s.get("scenes", []):
        if isinstance(sc, dict) and isinstance(sc.get("file"), str) and not os.path.isabs(sc["file"]):
            sc["file"] = str((Path(base) / sc["file"]).resolve())
    return s


def run_bench(suite: Union[str, "os.PathLike[str]", dict], out_dir: Union[str, "os.PathLike[str]"], *,
              repeats: int = 0, plots: Optional[bool] = False,
              progress: Optional[Callable[[dict], Any]] = None,
              base_dir: Union[str, "os.PathLike[str]", None] = None,
              clock: Optional[str] = None) -> BenchResult:
    """Run a benchmark suite: a suite file (bench/*.json) or a dict with the same keys
    (written to OUT_DIR/suite.json; relative scene files resolved against base_dir,
    default the current folder). repeats > 0 overrides the suite's repeats; plots:
    False (no gnuplot), True, or None (the suite's choice). clock: "cpu" (CPU seconds of
    the solving thread) or "wall" overrides the suite's clock (None: the suite's, default
    cpu). progress: fn(dict) with
    scene, config, phase, fraction, eta. Returns a BenchResult with the parsed
    summary.csv rows and the paths of curves.csv, summary.csv, trajectory.csv,
    reference.csv, report.md, plots/. ElastoptError for a bad suite (the library's
    message); an exception raised by progress or by a Python optimizer is re-raised.
    Uses the benchmark harness library installed with the package (pip) or built in the
    build tree."""
    b = bench_lib()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if isinstance(suite, dict):
        path = out / "suite.json"
        path.write_text(json.dumps(_absolute_files(suite, base_dir or os.getcwd()), indent=1))
    else:
        path = Path(suite)
    sp = ffi.new("eo_bench_suite **")
    check(b.eo_bench_suite_load(ctx, os.fsencode(str(path)), sp))
    try:
        s = sp[0]
        scenes = [string(b.eo_bench_suite_scene_name(s, i)) for i in range(b.eo_bench_suite_nscenes(s))]
        configs = [string(b.eo_bench_suite_config_name(s, i)) for i in range(b.eo_bench_suite_nconfigs(s))]
        o = ffi.new("eo_bench_run_opts *", b.eo_bench_run_opts_default())
        out_c = ffi.new("char[]", os.fsencode(str(out)))
        o.out_dir = out_c
        o.repeats = int(repeats)
        o.plots = -1 if plots is None else int(bool(plots))
        if clock is not None and clock not in ("cpu", "wall"):
            raise ValueError(f"clock {clock!r}: expected 'cpu' or 'wall'")
        clock_c = ffi.new("char[]", clock.encode()) if clock else ffi.NULL
        o.clock = clock_c
        cb = ffi.NULL
        if progress is not None:
            @ffi.callback("void(const eo_bench_progress *, void *)")
            def cb(p, user):
                try:
                    progress({"scene": string(p.scene_name), "config": string(p.config_name),
                              "phase": string(p.phase), "fraction": p.fraction, "eta": p.eta,
                              "elapsed": p.elapsed})
                except BaseException as e:  # reported after the run
                    set_pending(e)
        o.progress = cb
        sm = ffi.new("eo_bench_summary *")
        check(b.eo_bench_run(ctx, s, o, sm))
    finally:
        b.eo_bench_suite_destroy(sp)
    check(0)  # a progress callback's exception
    files = {p.name: p for p in out.iterdir()}
    rows = []
    if (out / "summary.csv").exists():
        with open(out / "summary.csv", newline="") as f:
            rows = list(csv.DictReader(f))
    return BenchResult(out, sm.runs, sm.ref_failures, sm.nonfinite, sm.nan, sm.required_failures,
                       sm.plots_made, sm.seconds, scenes, configs, rows, files)
