"""Moving lines that meet at junction points: the refinement study of ``cases/box_with_wall.toml``
with its folds held (``held = true``, as the case was made) and its four welds moving (``held =
false``), whose ends meet at the wall's corners (``docs/method.md`` sections 6.4 and 10.4).

Per plate, the relative L2 difference of ``w`` on a 15 x 15 grid between resolutions 1, 1.5
and the finest (2.25, or 3.375 with ``--finest 3.375``), and how far the moving welds move the
field from the held ones (at the finest resolution).

With ``--folds``, the case as it is, its 16 folds moving too (a hinge between framed plates
moves as a line of two members, the first rigid and the second on the hinge's spring), against
the same box with its folds held; and the moving folds' own refinement 1.5 -> the finest.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_junction_points.py [frequencies] [--folds]``
(default: the case's frequencies and 600 Hz; about a minute per frequency at 2.25).
"""

from __future__ import annotations

import argparse

import numpy as np

from assembly import Case, parse_case
from assembly.generate import box_with_wall
from solver.substructure import solve_assembly

WELDS = ("W_top", "W_bottom", "W_front", "W_back")
CASE_FREQUENCIES = [189.6, 268.0, 277.5, 282.75]


def box(held_welds: bool | None, held_folds: bool) -> Case:
    """box_with_wall as its case file describes it, the welds ``held_welds`` (None: the
    default, moving), the folds held or moving."""
    description = box_with_wall(truth={"W_top": 1.0}, resolution=1.5,
                                frequency=CASE_FREQUENCIES, held_folds=held_folds)
    for weld in WELDS:
        description["joints"][weld]["held"] = held_welds
    return parse_case(description)


def fields(case: Case, frequency: float, resolution: float) -> dict[str, np.ndarray]:
    """Per plate, ``w`` on a 15 x 15 grid of its interior."""
    solution = solve_assembly(case, frequency, resolution, residuals=False)
    out = {}
    for pid, plate in case.plates.items():
        lx, ly = plate.size
        x, y = np.meshgrid(np.linspace(0.02, 0.98, 15) * lx, np.linspace(0.02, 0.98, 15) * ly)
        out[pid] = solution.plates[pid].field(np.column_stack([x.ravel(), y.ravel()]))["w"]
    return out


def differences(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> dict[str, float]:
    """Per plate, :math:`\\|a - b\\| / \\|b\\|`."""
    return {p: float(np.linalg.norm(a[p] - b[p]) / np.linalg.norm(b[p])) for p in a}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("frequencies", nargs="*", type=float,
                        default=[*CASE_FREQUENCIES, 600.0])
    parser.add_argument("--finest", type=float, default=2.25)
    parser.add_argument("--folds", action="store_true",
                        help="the case (its folds moving too) against the box with held folds")
    args = parser.parse_args()
    if args.folds:
        return moving_folds(args.frequencies, args.finest)
    moving, held = box(False, held_folds=True), box(True, held_folds=True)
    for frequency in args.frequencies:
        finest = fields(moving, frequency, args.finest)
        coarse = {r: differences(fields(moving, frequency, r), finest) for r in (1.0, 1.5)}
        moved = differences(fields(held, frequency, args.finest), finest)
        print(f"{frequency} Hz: plate, |r=1 - r={args.finest}|, |r=1.5 - r={args.finest}|, "
              "|held - moving|")
        for pid in moving.plates:
            print(f"  {pid:8s} {coarse[1.0][pid]:.2e} {coarse[1.5][pid]:.2e} {moved[pid]:.2e}")
        print(f"  worst    {max(coarse[1.0].values()):.2e} {max(coarse[1.5].values()):.2e} "
              f"{max(moved.values()):.2e}")


def moving_folds(frequencies: list[float], finest: float) -> None:
    """Per plate, how far the box with held folds is from the case's moving ones (at
    ``finest``), and the moving folds' change from resolution 1.5 to ``finest``."""
    folds, held_folds = box(None, held_folds=False), box(None, held_folds=True)
    print(f"the folds moving: {len(folds.moving_lines())} moving lines against "
          f"{len(held_folds.moving_lines())} (the welds)")
    for frequency in frequencies:
        finest_fields = fields(folds, frequency, finest)
        held = differences(fields(held_folds, frequency, finest), finest_fields)
        refined = differences(fields(folds, frequency, 1.5), finest_fields)
        print(f"{frequency} Hz: |held folds - moving folds| worst {max(held.values()):.2f}, "
              f"median {np.median(list(held.values())):.2f} (by plate: "
              + ", ".join(f"{p} {v:.2f}" for p, v in held.items())
              + f"); moving folds |r=1.5 - r={finest}| worst {max(refined.values()):.1e}",
              flush=True)


if __name__ == "__main__":
    main()
