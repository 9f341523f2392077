"""``cases/box_with_wall.toml`` (its model, not its truth) against the independent finite
elements of ``bench/fem_box.py``: per plate, the relative L2 error of ``w`` and of ``(u, v)``
on the plate's 15 x 15 inner grid against the FE's finest level (``/tmp/fem_box/fields.npz``,
written by ``python bench/fem_box.py``), the worst plate, and vtcr's own estimate
(``solver.estimate.estimate_error``) over that error.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_box.py [--resolutions 1.5 2.25 3.4]
[--frequencies 189.6 277.5] [--reference /tmp/fem_box/fields.npz]``.
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from fem_folded import inner_grid, relative  # noqa: E402

from assembly import load_case  # noqa: E402
from solver.estimate import estimate_error  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

CASE = ROOT / "cases" / "box_with_wall.toml"
REFERENCE = Path("/tmp/fem_box/fields.npz")


def compare(case, frequency: float, resolution: float, reference) -> tuple[dict, float]:
    """Per plate ``(error w, estimate w, error uv, estimate uv)`` and the seconds of the solve
    with its estimate."""
    start = time.perf_counter()
    solution = solve_assembly(case, frequency, resolution, residuals=False)
    estimate = estimate_error(case, solution, resolution)
    seconds = time.perf_counter() - start
    rows = {}
    for name, plate in case.plates.items():
        points = inner_grid(*plate.size)
        w = solution.plates[name].field(points)["w"]
        uv = np.asarray(solution.in_plane(name, points))
        rows[name] = (relative(w, reference[f"w_{name}_{frequency:g}"]), estimate.plates[name],
                      relative(uv, reference[f"uv_{name}_{frequency:g}"]),
                      estimate.in_plane[name])
    return rows, seconds


def print_rows(frequency: float, resolution: float, rows: dict, seconds: float,
               change: dict) -> None:
    print(f"\n{frequency:g} Hz, resolution {resolution:g} ({seconds:.1f} s, peak memory "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6:.2f} GB)")
    print(f"  {'plate':8s} {'err w':>8} {'est/err':>7} {'err uv':>8} {'est/err':>7}"
          f" {'FE chg w':>8} {'FE chg uv':>9}")
    for name, (ew, sw, euv, suv) in rows.items():
        cw, cuv = change.get(name, (np.nan, np.nan))
        print(f"  {name:8s} {ew:8.1e} {sw / ew:7.2f} {euv:8.1e} {suv / euv:7.2f}"
              f" {cw:8.1e} {cuv:9.1e}")
    worst_w = max(rows, key=lambda p: rows[p][0])
    worst_uv = max(rows, key=lambda p: rows[p][2])
    ratios_w = [r[1] / r[0] for r in rows.values()]
    ratios_uv = [r[3] / r[2] for r in rows.values()]
    print(f"  worst w {rows[worst_w][0]:.1e} ({worst_w}), est/err {min(ratios_w):.2f} to "
          f"{max(ratios_w):.2f}; worst (u, v) {rows[worst_uv][2]:.1e} ({worst_uv}), est/err "
          f"{min(ratios_uv):.2f} to {max(ratios_uv):.2f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolutions", nargs="*", type=float, default=[1.5, 2.25])
    parser.add_argument("--frequencies", nargs="*", type=float, default=[189.6, 277.5])
    parser.add_argument("--reference", type=Path, default=REFERENCE)
    args = parser.parse_args()
    reference = np.load(args.reference)
    case = load_case(CASE)
    names = list(case.plates)
    levels = reference["levels"].tolist() if "levels" in reference else "?"
    print(f"box_with_wall against fem_box (levels {levels}, {args.reference}); FE chg: the "
          "FE's last level change per plate (its convergence level)")
    for frequency in args.frequencies:
        change = {}
        if f"change_w_{frequency:g}" in reference:
            cw, cuv = reference[f"change_w_{frequency:g}"], reference[f"change_uv_{frequency:g}"]
            change = dict(zip(FE_ORDER, zip(cw, cuv)))
        for resolution in args.resolutions:
            rows, seconds = compare(case, frequency, resolution, reference)
            print_rows(frequency, resolution, {n: rows[n] for n in names}, seconds, change)


# the order of fem_box.PLATES (the npz's change arrays), written out: this script does not
# import the FE
FE_ORDER = ("Top1", "Top2", "Bottom1", "Bottom2", "Front1", "Front2", "Back1", "Back2", "Left",
            "Right", "Wall")

if __name__ == "__main__":
    main()
