"""A fixed-grid sweep of ``cases/four_plates.toml`` in this process, on local worker processes,
and on a Dask cluster (if ``distributed`` is installed): wall time, speed-up, identical results,
and the per-task overhead of each executor.

Run (one BLAS thread per process, as the CLI sets it)::

    OPENBLAS_NUM_THREADS=1 python bench/bench_sweep.py --points 400 --workers 2

The sweep is ``updating.forward.sweep.frequency_sweep`` with ``max_points`` equal to the grid, so every
executor solves the same frequencies (no refinement), the probes being the measurement grid.
The overhead is the time of mapping ``--overhead-tasks`` empty tasks, per task.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
import time

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import numpy as np  # noqa: E402

from assembly import load_case  # noqa: E402
from solver import field_grid  # noqa: E402
from updating.executor import Executor  # noqa: E402
from updating.forward.sweep import frequency_sweep  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


def _nothing(item):
    return item


def overhead(executor, tasks):
    """Seconds per task of mapping empty tasks (one task per chunk: the executor's cost)."""
    t0 = time.perf_counter()
    executor.map(_nothing, range(tasks))
    return (time.perf_counter() - t0) / tasks


class _cluster_executor:
    """An Executor on a LocalCluster of its own, both closed on exit."""

    def __init__(self, local_cluster, workers):
        self.cluster = local_cluster(n_workers=workers, threads_per_worker=1, processes=True,
                                     dashboard_address=None)
        self.executor = Executor(scheduler=self.cluster.scheduler_address)

    def __enter__(self):
        return self.executor.__enter__()

    def __exit__(self, *exc):
        self.executor.__exit__(*exc)
        self.cluster.close()
        return False


def timed_sweep(case, points, band, count, executor):
    t0 = time.perf_counter()
    sweep = frequency_sweep(case, band, points, count=count, max_points=count, executor=executor)
    return time.perf_counter() - t0, sweep


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", default=str(ROOT / "cases" / "four_plates.toml"))
    parser.add_argument("--band", nargs=2, type=float, default=[200.0, 260.0])
    parser.add_argument("--points", type=int, default=400)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--overhead-tasks", type=int, default=200)
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask cluster")
    args = parser.parse_args(argv)
    case = load_case(args.case)
    points = {pid: field_grid(case, pid, case.measurement.spacing) for pid in case.plates}
    print(f"{case.name}: {args.points} frequencies over {args.band[0]:g}-{args.band[1]:g} Hz, "
          f"{sum(len(p) for p in points.values())} probes, {os.cpu_count()} cores, "
          f"Python {sys.version.split()[0]}")
    rows, reference = [], None
    runs = [("serial", Executor), (f"{args.workers} local processes",
                                    lambda: Executor(args.workers))]
    if not args.no_dask:
        try:
            from distributed import LocalCluster
        except ImportError:
            print("distributed not installed: no Dask run (pip install 'vtcr[distributed]')")
        else:
            runs.append((f"Dask LocalCluster, {args.workers} workers",
                         lambda: _cluster_executor(LocalCluster, args.workers)))
    for name, make in runs:
        # each executor exists only during its own run: idle Dask workers beside the other
        # runs cost them about 20 % of their speed here
        with make() as executor:
            cost = overhead(executor, args.overhead_tasks)
            seconds, sweep = timed_sweep(case, points, tuple(args.band), args.points, executor)
        values = np.concatenate([np.concatenate(list(v.values())) for v in sweep.values])
        same = reference is None or np.array_equal(values, reference)
        reference = values if reference is None else reference
        rows.append((name, seconds, cost, same))
    serial = rows[0][1]
    print(f"{'executor':<34} {'wall s':>8} {'speed-up':>9} {'per-task overhead':>18} "
          f"{'same results':>13}")
    for name, seconds, cost, same in rows:
        print(f"{name:<34} {seconds:8.1f} {serial / seconds:9.2f} {1e3 * cost:15.2f} ms "
              f"{'yes' if same else 'NO':>13}")
    print(f"one frequency in this process: {1e3 * serial / args.points:.0f} ms")


if __name__ == "__main__":
    main()
