"""Throughput of a study: cases per minute with 1 and 2 workers, and their ratio (goal >= 1.7x).

The same study (default 16 cases: SCalf, family joint-6, Ipopt, gait periods from 0.40 s in
steps of 0.02 s) runs, without cache, on (a) the local process pool, the default backend, with 1
and then 2 worker processes, and (b) a Dask LocalCluster with 1 and then 2 worker processes (the
cluster's start is not timed). The pool starts fresh worker interpreters (their imports are in
the time). The machine's load average is printed before and after: on a shared machine other
jobs take cores away.

    python benchmarks/bench_sweep.py [--cases N]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scalf_opt.studies.progress import Progress
from scalf_opt.studies.runner import _pool, choose_runner, run_study
from scalf_opt.studies.study_file import read_study


def study_file(folder: Path, cases: int) -> Path:
    periods = ", ".join(f"{0.40 + 0.02 * i:.2f}" for i in range(cases))
    path = folder / "bench.toml"
    path.write_text(
        f'[study]\nrobot = "scalf"\nfamily = "joint-6"\n[sweep]\n"gait.period_s" = [{periods}]\n'
    )
    return path


def timed(study, runner) -> float:
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        result = run_study(study, out, runner, Progress(len(study.cases), enabled=False))
        elapsed = time.perf_counter() - start
    assert not result.failed, [r["error"] for r in result.failed]
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=16)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        study = read_study(study_file(Path(folder), args.cases))
    n = len(study.cases)
    print(f"{n} cases (SCalf, joint-6, Ipopt), no cache; load average {os.getloadavg()[0]:.2f}")
    rows = []
    for workers in (1, 2):
        rows.append(("process pool", workers, timed(study, _pool(workers))))
    from dask.distributed import LocalCluster

    for workers in (1, 2):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster:
            runner = choose_runner(scheduler=cluster.scheduler_address)
            rows.append(("Dask LocalCluster", workers, timed(study, runner)))
    print(f"load average after: {os.getloadavg()[0]:.2f} (2 cores)")
    print(f"{'backend':18s} {'workers':>7s} {'time [s]':>9s} {'cases/min':>10s} {'ratio':>6s}")
    for backend, workers, elapsed in rows:
        one = next(e for b, w, e in rows if b == backend and w == 1)
        print(
            f"{backend:18s} {workers:7d} {elapsed:9.1f} {60 * n / elapsed:10.1f} "
            f"{one / elapsed:5.2f}x"
        )


if __name__ == "__main__":
    main()
