"""The Legendre count of a moving line held in its plane at its ends (``docs/method.md`` section
10.4, *Ends held in their plane* and *The count*): its members reach twice as far from
resolution 1.5 on (``solver.line_ends.HELD_END_REACH``), and its count follows that reach only
where the usual cap would stop it below the wavenumbers' count at 1.5
(``solver.layout._held_count_follows``: a skin and its stiffeners, not two like plates).

On the L fold and the T junction of ``tests/test_moving_lines.py`` with fixed ends, against
their independent finite elements (``tests/data/fem_fold_fixed_ends.npz``,
``fem_junction_fixed.npz``, the T's stiffener top fixed), worst plate's relative L2 error of
``(u, v)`` and of ``w`` by resolution, at 300 Hz and 1 kHz, for three counts:

* **rule**: the code as it is;
* **following**: the count follows the doubled reach on every such line (0.3.5);
* **usual**: the count stays at the usual cap on every such line.

``--estimate`` adds the error estimate over the error of ``(u, v)`` on every plate;
``--condition`` the condition number of the (equilibrated) square interface system, dense,
and its smallest singular value over its largest; ``--rank-tolerance`` and
``--membrane-tolerance`` set the plates' ``solver.dense.RANK_TOLERANCE`` (bending, 1e-14) and
``MEMBRANE_RANK_TOLERANCE`` (in-plane, 1e-16), to see how much the figures move with them;
``--plain-loads`` leaves out the singular terms of the lines' loads at the held ends and the
members' corner functions of their degrees (``solver.line_ends.held_end_exponents``, 0.3.8):
the model of 0.3.7. With them the T junction's count is the usual one whatever the rule (the
three counts agree), and the L fold, whose line no exponent loads, is unchanged.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_held_counts.py [--estimate] [--condition]
[--rank-tolerance 1e-16] [--membrane-tolerance 1e-14] [--plain-loads]`` (about a minute and a half;
``--estimate`` three times that).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import scipy.linalg

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import folded_description  # noqa: E402
from test_held_ends import FINITE_ELEMENT_FOLD, FINITE_ELEMENT_JUNCTION, PLATES  # noqa: E402
from test_moving_lines import L_FOLD, LY, T_JUNCTION, _finite_element_errors  # noqa: E402

import solver.admissibility  # noqa: E402
import solver.dense  # noqa: E402
import solver.interface  # noqa: E402
import solver.layout  # noqa: E402
import solver.line_ends  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.estimate import estimate_error  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

STRUCTURES = {  # name: (plates, lines, load, finite elements, key of a frequency)
    "L fold": (*L_FOLD, FINITE_ELEMENT_FOLD, lambda f: "" if f == 300.0 else f"_{f:.0f}"),
    "T junction": (PLATES, T_JUNCTION[1], T_JUNCTION[2], FINITE_ELEMENT_JUNCTION,
                   lambda f: f"_{f:.0f}"),
}
RULE = solver.layout._held_count_follows
COUNTS = {"rule": RULE, "following": lambda *_: True, "usual": lambda *_: False}
RESOLUTIONS = (1.5, 2.25, 3.4)


class SquareSystem:
    """The last dense square interface system LAPACK factorised (the forward solve of a small
    assembly: ``solver.interface._determined_solution``), kept to measure its condition."""

    matrix: np.ndarray | None = None
    factorise = staticmethod(scipy.linalg.lu_factor)

    @classmethod
    def keep(cls, matrix, *args, **kwargs):
        cls.matrix = np.array(matrix)
        return cls.factorise(matrix, *args, **kwargs)


def condition() -> str:
    """The condition number of :attr:`SquareSystem.matrix` and its smallest singular value
    over its largest."""
    if SquareSystem.matrix is None:
        return "no dense square system"
    singular = np.linalg.svd(SquareSystem.matrix, compute_uv=False)
    return (f"{len(singular)} unknowns, condition {singular[0] / singular[-1]:.1e}, smallest "
            f"{singular[-1] / singular[0]:.1e}")


def run(structure: str, frequency: float, count: str, with_estimate: bool,
        with_condition: bool) -> None:
    plates, lines, load, path, key = STRUCTURES[structure]
    reference = np.load(path)
    solver.layout._held_count_follows = COUNTS[count]
    try:
        for resolution in RESOLUTIONS:
            case = parse_case(folded_description(plates, lines, load, frequency, None, LY,
                                                 resolution, ends="fixed"))
            SquareSystem.matrix = None
            solution = solve_assembly(case, frequency, residuals=False)
            errors = _finite_element_errors(solution, plates, reference, key(frequency))
            row = (f"  {structure}, {frequency:.0f} Hz, {count:9s} {resolution:4}: (u, v) "
                   f"{max(uv for _, uv in errors.values()):.1e}, w "
                   f"{max(w for w, _ in errors.values()):.1e}")
            if with_estimate:
                estimate = estimate_error(case, solution)
                row += "; estimate / error of (u, v) " + ", ".join(
                    f"{p} {estimate.in_plane[p] / uv:.2f}" for p, (_, uv) in errors.items())
            if with_condition:
                row += "; " + condition()
            print(row, flush=True)
    finally:
        solver.layout._held_count_follows = RULE


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--estimate", action="store_true")
    parser.add_argument("--condition", action="store_true")
    parser.add_argument("--rank-tolerance", type=float, default=solver.dense.RANK_TOLERANCE)
    parser.add_argument("--membrane-tolerance", type=float,
                        default=solver.dense.MEMBRANE_RANK_TOLERANCE)
    parser.add_argument("--plain-loads", action="store_true",
                        help="the lines' Legendre functions alone, without the singular terms "
                             "t^(lambda - 1) and their corner functions (0.3.7)")
    args = parser.parse_args()
    if args.plain_loads:
        solver.line_ends.line_loading_exponents = lambda *_: ()
    solver.dense.RANK_TOLERANCE = args.rank_tolerance
    # the builders read the in-plane tolerance from their own import of it
    solver.admissibility.MEMBRANE_RANK_TOLERANCE = args.membrane_tolerance
    if args.condition:
        solver.interface.scipy.linalg.lu_factor = SquareSystem.keep
    print(f"worst plate's error against finite elements (plates' rank tolerances: bending "
          f"{args.rank_tolerance:.0e}, in-plane {args.membrane_tolerance:.0e})")
    for structure in STRUCTURES:
        for frequency in (300.0, 1000.0):
            for count in COUNTS:
                run(structure, frequency, count, args.estimate, args.condition)


if __name__ == "__main__":
    main()
