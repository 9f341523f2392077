"""Why a moving line with in-plane ``roller`` ends does not converge (``docs/method.md``
section 10.4): the measurements behind the diagnosis, on the L fold of
``tests/test_moving_lines.py`` (plates A 0.4 m and B 0.3 m, 2 mm steel, 0.5 m long line, both
members rigid, simply supported ends, 1 N on A), the in-plane condition of the end edges
``roller`` or ``diaphragm``, ``held = false``.

* **refinement with the usual reach** (``solver.problems.SINGULAR_END_REACH`` set to 1, as
  before the rule): the relative L2 differences of ``w`` and ``(u, v)`` on each plate between
  resolutions 1 -> 1.5 -> 2.25 -> 3.4;
* **reach of the rays** (the same): at resolution 1.5 with the line's functions fixed at 30
  (``interface_functions``), ``edge_wavenumber_ratio`` (the edge waves' reach, in bending
  wavenumbers) raised from 2.5 to 20, with ``w`` of plate B at the line's ends (a simply
  supported corner: 0 exactly) relative to B's largest ``w``; ``--quick`` stops at 10;
* **refinement with the rule** (``SINGULAR_END_REACH`` = 6): roller ends, 1.5 -> 2.25 -> 3.4;
* **planes of symmetry** (``docs/method.md`` section 10.4, the usual reach): the same fold with
  the end edges' bending and in-plane conditions in each pair of the method's table (a plane of
  symmetry, ``symmetric`` with ``roller``; of antisymmetry, ``simply_supported`` with
  ``diaphragm``; and their mixes), the largest change over the plates between resolutions 1.5
  -> 2.25 -> 3.4 at 300 Hz and 1 kHz; and the three-bay stiffened panel of
  ``bench/bench_moving_lines.py`` with both ends planes of symmetry or shear diaphragms, 1 ->
  1.5 -> 2.25 -> 3.4 at 1 and 2.5 kHz, with the time of each solve. ``--symmetry`` runs this
  part alone (about a minute).

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_roller_ends.py [--quick]`` (the full run takes
about fifteen minutes on two cores, most of it at the largest reaches).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "bench")]

from support import folded_description, inner_grid  # noqa: E402
from test_moving_lines import L_FOLD, LY  # noqa: E402

import solver.problems  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

PLATES, LINES, LOAD = L_FOLD


def fold_fields(frequency: float, ends: str, resolution: float,
                settings: dict | None = None,
                condition: str = "simply_supported") -> tuple[dict[str, tuple[np.ndarray,
                                                                               np.ndarray]],
                                                              float, float]:
    """Per plate ``(w, (u, v))`` on a 15 x 15 grid, the solve's time (s), and ``|w|`` of B at
    the line's ends over B's largest ``|w|`` on the grid; the end edges ``condition`` in
    bending and ``ends`` in-plane."""
    description = folded_description(PLATES, LINES, LOAD, frequency, False, LY, resolution)
    for boundary in description["boundaries"]:
        if "in_plane" in boundary:
            boundary["condition"], boundary["in_plane"] = condition, ends
    description["discretisation"].update(settings or {})
    start = time.perf_counter()
    solution = solve_assembly(parse_case(description), frequency, residuals=False)
    seconds = time.perf_counter() - start
    fields = {}
    for name, (length, *_) in PLATES.items():
        points = inner_grid(length, LY)
        fields[name] = (solution.plates[name].field(points)["w"],
                        solution.in_plane(name, points))
    ends_w = solution.plates["B"].field(np.array([[0.0, 0.0], [0.0, LY]]))["w"]
    return fields, seconds, float(np.abs(ends_w).max() / np.abs(fields["B"][0]).max())


def differences(a: dict, b: dict) -> str:
    """``plate: w d_w u d_u`` relative L2 differences of two :func:`fold_fields`."""
    return "; ".join(
        f"{name}: w {np.linalg.norm(a[name][0] - b[name][0]) / np.linalg.norm(b[name][0]):.1e}"
        f" u {np.linalg.norm(a[name][1] - b[name][1]) / np.linalg.norm(b[name][1]):.1e}"
        for name in a)


def refinement(ends: str, frequency: float, resolutions: tuple[float, ...]) -> None:
    """Print the differences between successive resolutions (:func:`differences`)."""
    previous = None
    for resolution in resolutions:
        fields, seconds, corner = fold_fields(frequency, ends, resolution)
        if previous is not None:
            print(f"  {ends:9s} {frequency:6.0f} Hz  {resolution:4.2f}  {seconds:5.1f} s  "
                  f"w_B(end)/max {corner:.1e}  {differences(previous, fields)}", flush=True)
        previous = fields


def largest_change(a: dict, b: dict, component: int) -> float:
    """The largest relative L2 difference over the plates of two field dicts (``component`` 0:
    ``w``, 1: ``(u, v)``), against ``b``."""
    return max(np.linalg.norm(a[name][component] - b[name][component])
               / np.linalg.norm(b[name][component]) for name in a)


def panel_fields(frequency: float, ends: str, resolution: float) -> tuple[dict, float]:
    """The three-bay panel of ``bench_moving_lines.py`` with both ends ``ends``
    (``support.FOLD_ENDS``), its lines moving by default: per plate ``(w, (u, v))`` on a 15 x
    15 grid, and the solve's time (s)."""
    from bench_moving_lines import LOAD as PANEL_LOAD
    from bench_moving_lines import MODEL_LOG_K
    from bench_moving_lines import PLATES as PANEL
    from bench_moving_lines import lines

    case = parse_case(folded_description(PANEL, lines(MODEL_LOG_K), PANEL_LOAD, frequency, None,
                                         LY, resolution, ends=ends))
    assert case.moving_lines() == ("W1", "W2")
    start = time.perf_counter()
    solution = solve_assembly(case, frequency, residuals=False)
    seconds = time.perf_counter() - start
    return {name: (solution.plates[name].field(inner_grid(length, LY))["w"],
                   solution.in_plane(name, inner_grid(length, LY)))
            for name, (length, *_) in PANEL.items()}, seconds


def planes_of_symmetry() -> None:
    """The end edges' conditions by pairs, the usual reach (module notes)."""
    rule = solver.problems.SINGULAR_END_REACH
    solver.problems.SINGULAR_END_REACH = 1.0
    print("planes of symmetry: the L fold, usual reach, largest change of w, then of (u, v), "
          "over the plates (resolution 1.5 -> 2.25 -> 3.4)")
    for condition, ends in (("symmetric", "roller"), ("simply_supported", "diaphragm"),
                            ("simply_supported", "fixed"), ("simply_supported", "roller"),
                            ("symmetric", "diaphragm"), ("symmetric", "fixed"),
                            ("clamped", "roller"), ("clamped", "fixed")):
        cells = []
        for frequency in (300.0, 1000.0):
            fields = [fold_fields(frequency, ends, r, condition=condition)[0]
                      for r in (1.5, 2.25, 3.4)]
            steps = list(zip(fields[1:], fields))
            cells.append(f"{frequency:.0f} Hz: w " + ", ".join(
                f"{largest_change(a, b, 0):.1e}" for a, b in steps) + "; (u, v) " + ", ".join(
                f"{largest_change(a, b, 1):.1e}" for a, b in steps))
        print(f"  {condition} + {ends}: " + " | ".join(cells), flush=True)
    solver.problems.SINGULAR_END_REACH = rule
    print("the three-bay panel, lines moving by default (resolution 1 -> 1.5 -> 2.25 -> 3.4; "
          "the time of each solve)")
    for frequency in (1000.0, 2500.0):
        for ends in ("symmetric", "diaphragm"):
            previous, cells = None, []
            for resolution in (1.0, 1.5, 2.25, 3.4):
                fields, seconds = panel_fields(frequency, ends, resolution)
                if previous is not None:
                    cells.append(f"w {largest_change(fields, previous, 0):.1e} (u, v) "
                                 f"{largest_change(fields, previous, 1):.1e} ({seconds:.2f} s)")
                previous = fields
            print(f"  {ends:9s} {frequency:6.0f} Hz: " + "; ".join(cells), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--symmetry", action="store_true", help="the planes of symmetry only")
    args = parser.parse_args()
    planes_of_symmetry()
    if args.symmetry:
        return
    rule = solver.problems.SINGULAR_END_REACH
    solver.problems.SINGULAR_END_REACH = 1.0
    print("refinement with the usual reach (resolution 1 -> 1.5 -> 2.25 -> 3.4)")
    for ends in ("diaphragm", "roller"):
        for frequency in (300.0, 1000.0):
            refinement(ends, frequency, (1.0, 1.5, 2.25, 3.4))
    print("reach of the edge waves (resolution 1.5, 30 line functions)")
    reaches = (2.5, 5.0, 10.0) if args.quick else (2.5, 5.0, 10.0, 15.0, 20.0)
    for ends, frequency in (("diaphragm", 1000.0), ("roller", 1000.0), ("roller", 2500.0)):
        previous = None
        for tau in reaches:
            fields, seconds, corner = fold_fields(
                frequency, ends, 1.5, {"edge_wavenumber_ratio": tau, "interface_functions": 30})
            change = "" if previous is None else differences(previous, fields)
            print(f"  {ends:9s} {frequency:6.0f} Hz  tau {tau:4.1f}  {seconds:5.1f} s  "
                  f"w_B(end)/max {corner:.1e}  {change}", flush=True)
            previous = fields
    solver.problems.SINGULAR_END_REACH = rule
    print(f"refinement with the rule (reach x {rule:g}; resolution 1.5 -> 2.25 -> 3.4)")
    for frequency in (300.0, 1000.0):
        refinement("roller", frequency, (1.5, 2.25, 3.4))


if __name__ == "__main__":
    main()
