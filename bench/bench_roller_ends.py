"""Moving lines whose ends mix the halves of a plane of symmetry (in-plane ``roller`` ends
simply supported in bending, say; ``docs/method.md`` section 10.4): the measurements behind the
diagnosis and behind the rule (the logarithmic corner functions at such ends,
``solver.line_ends.singular_end_corners``, three times the reach,
``solver.line_ends.SINGULAR_END_REACH``, and the logarithmic terms of the line's load
functions, ``solver.joint_rules.load_function_values``), on the L fold of
``tests/test_moving_lines.py`` (plates A 0.4 m and B 0.3 m, 2 mm steel, 0.5 m long line, both
members rigid, simply supported ends, 1 N on A), the in-plane condition of the end edges
``roller`` or ``diaphragm``, ``held = false``. :func:`end_treatment` switches the rule's three
parts for a run.

* **refinement, the rays alone with the usual reach** (as before the rule): the relative L2
  differences of ``w`` and ``(u, v)`` on each plate between resolutions 1 -> 1.5 -> 2.25 -> 3.4;
* **reach of the rays** (the same): at resolution 1.5 with the line's functions fixed at 30
  (``interface_functions``), ``edge_wavenumber_ratio`` (the edge waves' reach, in bending
  wavenumbers) raised from 2.5 to 20, with ``w`` of plate B at the line's ends (a simply
  supported corner: 0 exactly) relative to B's largest ``w``; ``--quick`` stops at 10;
* **refinement with the rule**: roller ends, 1.5 -> 2.25 -> 3.4;
* **planes of symmetry** (``--symmetry`` alone, about two minutes): the same fold with the end
  edges' bending and in-plane conditions in each pair of the method's table (a plane of
  symmetry, ``symmetric`` with ``roller``; of antisymmetry, ``simply_supported`` with
  ``diaphragm``; and their mixes), the largest change over the plates between resolutions 1.5
  -> 2.25 -> 3.4 at 300 Hz and 1 kHz, the rays alone, then the mixes under the rule; and the
  three-bay stiffened panel of ``bench/bench_moving_lines.py`` with both ends planes of
  symmetry or shear diaphragms, 1 -> 1.5 -> 2.25 -> 3.4 at 1 and 2.5 kHz, with the time of
  each solve;
* **logarithmic families** (``--log-families`` alone, about three minutes): ``simply_supported``
  + ``roller`` ends, the usual reach (``--reach 3``: the rule's), with and without the rule's
  families, the line's functions Legendre alone (as when the families were measured); the L
  fold, 1.5 -> 2.25 -> 3.4 at 300 Hz, 1 and 3 kHz, and the three-bay panel at 1 and 2.5 kHz;
* **a member hanging on the line** (``--hanging`` alone, about six minutes): the same ends;
  the L fold with B's far edge ``roller`` in-plane (B held across the line in its plane) or
  ``diaphragm`` (B held by the line alone: it hangs), and the T junction of the tests with its
  stiffener's top simply supported and fixed or free (it hangs); 1.5 -> 2.25 -> 3.4 at 300 Hz,
  1 and 3 kHz, then the L fold's last change at five frequencies between; with the families
  and the usual reach, then under the rule;
* **what the rule costs** (``--rule`` alone, about five minutes): one solve at resolution 1.5
  moving under the rule and held, on the L fold, the T junction and the panel, then the
  panel's refinement under the rule;
* **the floor of the line's Legendre functions** (``--floor`` alone, about twenty minutes;
  needs the ``bench`` extra): the L fold with roller ends from 60 to 500 Hz and the T junction
  at 300 Hz against finite elements (``fem_folded.py``, ``fem_junction.py``, level 6), with
  the floor of ``solver.joint_rules.mixed_end_legendre_count`` and without it, the estimate's
  ratio to each error; then the three-bay panel's refinement with roller ends, with and
  without it;
* **against finite elements** (``--fem`` alone, fifteen to thirty minutes, 7 GB; needs the
  ``bench`` extra, scikit-fem): the L fold with roller ends under the rule against
  ``bench/fem_folded.py``'s independent solution, by resolution, by the line's count of
  Legendre functions, and on Legendre functions alone (as before the logarithmic ones), and
  with ``symmetric`` + ``diaphragm`` ends; then the T junction against
  ``bench/fem_junction.py``'s, at its finest mesh.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_roller_ends.py [--quick]`` (the full run takes
about fifteen minutes on two cores, most of it at the largest reaches).
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "bench")]

from support import folded_description, inner_grid  # noqa: E402
from test_moving_lines import L_FOLD, LY, SHAPES  # noqa: E402

import solver.line_ends  # noqa: E402
import solver.problems  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.line_ends import SINGULAR_END_REACH
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


def panel_fields(frequency: float, ends: str, resolution: float,
                 supports: tuple[str, str] | None = None) -> tuple[dict, float]:
    """The three-bay panel of ``bench_moving_lines.py`` with both ends ``ends``
    (``support.FOLD_ENDS``), its lines moving by default, or with the end edges' ``(bending,
    in-plane)`` conditions ``supports`` and its lines moving (``held = false``): per plate
    ``(w, (u, v))`` on a 15 x 15 grid, and the solve's time (s)."""
    from bench_moving_lines import LOAD as PANEL_LOAD
    from bench_moving_lines import MODEL_LOG_K, lines
    from bench_moving_lines import PLATES as PANEL

    description = folded_description(PANEL, lines(MODEL_LOG_K), PANEL_LOAD, frequency,
                                     None if supports is None else False, LY, resolution,
                                     ends=ends)
    if supports is not None:
        for boundary in description["boundaries"]:
            if boundary["edge"].endswith(("bottom", "top")):
                boundary["condition"], boundary["in_plane"] = supports
    case = parse_case(description)
    assert case.moving_lines() == ("W1", "W2")
    start = time.perf_counter()
    solution = solve_assembly(case, frequency, residuals=False)
    seconds = time.perf_counter() - start
    return {name: (solution.plates[name].field(inner_grid(length, LY))["w"],
                   solution.in_plane(name, inner_grid(length, LY)))
            for name, (length, *_) in PANEL.items()}, seconds


def symmetry_mixed(condition: str, in_plane: str) -> bool:
    """Whether an end edge with these conditions mixes the halves of a plane of symmetry."""
    from assembly.lines import symmetry_halves

    return symmetry_halves((condition, in_plane)) == 1


def planes_of_symmetry() -> None:
    """The end edges' conditions by pairs, the rays alone with the usual reach, then the rule
    at the mixed ends (module notes)."""
    pairs = (("symmetric", "roller"), ("simply_supported", "diaphragm"),
             ("simply_supported", "fixed"), ("simply_supported", "roller"),
             ("symmetric", "diaphragm"), ("symmetric", "fixed"), ("clamped", "roller"),
             ("clamped", "fixed"))
    for label, treatment in (("the rays alone, usual reach",
                              lambda: end_treatment(1.0, False, False)),
                             ("the rule at mixed ends", contextlib.nullcontext)):
        print(f"planes of symmetry: the L fold, {label}, largest change of w, then of (u, v), "
              "over the plates (resolution 1.5 -> 2.25 -> 3.4)")
        with treatment():
            for condition, ends in pairs:
                if label.startswith("the rule") and not symmetry_mixed(condition, ends):
                    continue
                cells = []
                for frequency in (300.0, 1000.0):
                    fields = [fold_fields(frequency, ends, r, condition=condition)[0]
                              for r in (1.5, 2.25, 3.4)]
                    steps = list(zip(fields[1:], fields))
                    cells.append(f"{frequency:.0f} Hz: w " + ", ".join(
                        f"{largest_change(a, b, 0):.1e}" for a, b in steps) + "; (u, v) "
                        + ", ".join(f"{largest_change(a, b, 1):.1e}" for a, b in steps))
                print(f"  {condition} + {ends}: " + " | ".join(cells), flush=True)
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


@contextlib.contextmanager
def end_treatment(reach: float, families: bool = True, load_functions: bool = True,
                  floor: bool = True):
    """Within the block, the members of lines with mixed ends reach ``reach`` times the usual
    (``solver.line_ends.SINGULAR_END_REACH``), carry the logarithmic families at those ends
    (``solver.line_ends.singular_end_corners``) only if ``families``, the line's load
    functions have their logarithmic terms there (``solver.joint_rules.load_function_values``)
    only if ``load_functions``, and at least ``solver.joint_rules.mixed_end_legendre_count``
    Legendre functions only if ``floor`` (else the count of the line's wavenumbers alone): the
    rule's four parts switched one at a time."""
    import assembly.case
    import solver.in_plane
    import solver.layout

    reach_before = solver.line_ends.SINGULAR_END_REACH
    corners = solver.line_ends.singular_end_corners
    line_ends = assembly.case.Case.singular_line_ends
    count_floor = solver.layout.legendre_count_floor
    solver.line_ends.SINGULAR_END_REACH = reach
    if not families:
        solver.problems.singular_end_corners = solver.in_plane.singular_end_corners = (
            lambda case, plate_id: ())
    if not load_functions:
        assembly.case.Case.singular_line_ends = lambda case, joint_id: (False, False)
    if not floor:
        solver.layout.legendre_count_floor = lambda ends: 0
    try:
        yield
    finally:
        solver.line_ends.SINGULAR_END_REACH = reach_before
        solver.problems.singular_end_corners = solver.in_plane.singular_end_corners = corners
        assembly.case.Case.singular_line_ends = line_ends
        solver.layout.legendre_count_floor = count_floor


def log_families(reach: float = 1.0) -> None:
    """The L fold and the three-bay panel with ``simply_supported`` + ``roller`` ends, the edge
    waves of the members reaching ``reach`` times the usual, with and without the two
    logarithmic families (module notes)."""
    print(f"logarithmic families: simply supported + roller ends, reach x {reach:g}; change of "
          "w, then of (u, v), on each plate between resolutions 1.5 -> 2.25 -> 3.4")
    for label, frequencies in (("L fold", (300.0, 1000.0, 3000.0)),
                               ("panel", (1000.0, 2500.0))):
        for frequency in frequencies:
            for on in (False, True):
                with end_treatment(reach, on, load_functions=False):
                    previous, cells = None, []
                    for resolution in (1.5, 2.25, 3.4):
                        if label == "L fold":
                            fields, seconds, _ = fold_fields(frequency, "roller", resolution)
                        else:
                            fields, seconds = panel_fields(
                                frequency, "diaphragm", resolution,
                                ("simply_supported", "roller"))
                        if previous is not None:
                            cells.append(f"{differences(previous, fields)} ({seconds:.1f} s)")
                        previous = fields
                print(f"  {label} {frequency:6.0f} Hz, {'with' if on else 'without'}: "
                      + " | ".join(cells), flush=True)


def hanging_fields(shape: str, far: tuple[str, str] | None, frequency: float,
                   resolution: float) -> dict:
    """Per plate ``(w, (u, v))`` on a 15 x 15 grid of the L fold (``shape`` "L") or the T
    junction ("T") of ``tests/test_moving_lines.py`` with ``simply_supported`` + ``roller``
    ends and its line moving; ``far``: the ``(bending, in-plane)`` conditions of the far edge
    of the member that may hang (B of the L, the stiffener T1 of the T; ``None``: as the
    shape has it, a free top on T1)."""
    plates, lines, load = SHAPES[shape]
    hanging = {"L": "B", "T": "T1"}[shape]
    if far is not None:
        plates = dict(plates)
        plates[hanging] = plates[hanging][:4] + (far[0],)
    description = folded_description(plates, lines, load, frequency, False, LY, resolution)
    for boundary in description["boundaries"]:
        if boundary["edge"].endswith(("bottom", "top")):
            boundary["condition"], boundary["in_plane"] = "simply_supported", "roller"
        elif far is not None and boundary["edge"] == f"{hanging}.right":
            boundary["in_plane"] = far[1]
    solution = solve_assembly(parse_case(description), frequency, residuals=False)
    return {name: (solution.plates[name].field(inner_grid(length, LY))["w"],
                   solution.in_plane(name, inner_grid(length, LY)))
            for name, (length, *_) in plates.items()}


def hanging() -> None:
    """Mixed ends with and without a member that hangs on the line (``docs/method.md`` section
    10.4): the L fold with B's far edge held across the line in B's plane (``roller``) or not
    (``diaphragm``), both simply supported; the T junction with its stiffener's top simply
    supported and fixed, or free (as in the tests). ``simply_supported`` + ``roller`` ends;
    the logarithmic families with the usual reach, then the rule (the families and three
    times the reach); largest change of ``w``, then of ``(u, v)``, over the plates between
    resolutions 1.5 -> 2.25 -> 3.4, and the time of the finest solve."""
    cases = (("L", ("simply_supported", "roller"), "L fold, B's far edge roller (held)"),
             ("L", ("simply_supported", "diaphragm"), "L fold, B's far edge diaphragm (hangs)"),
             ("T", ("simply_supported", "fixed"), "T junction, T1's top fixed (held)"),
             ("T", None, "T junction, T1's top free (hangs)"))
    for label, treatment in (("the families, usual reach", lambda: end_treatment(1.0)),
                             ("the rule", contextlib.nullcontext)):
        print(f"a member hanging on the line, {label}: simply supported + roller ends; largest "
              "change of w, then (u, v), resolutions 1.5 -> 2.25 -> 3.4", flush=True)
        with treatment():
            for shape, far, case in cases:
                cells = []
                for frequency in (300.0, 1000.0, 3000.0):
                    fields = []
                    for resolution in (1.5, 2.25, 3.4):
                        start = time.perf_counter()
                        fields.append(hanging_fields(shape, far, frequency, resolution))
                        seconds = time.perf_counter() - start
                    steps = list(zip(fields[1:], fields))
                    cells.append(f"{frequency:.0f} Hz: w " + ", ".join(
                        f"{largest_change(a, b, 0):.1e}" for a, b in steps) + "; (u, v) "
                        + ", ".join(f"{largest_change(a, b, 1):.1e}" for a, b in steps)
                        + f" ({seconds:.1f} s)")
                print(f"  {case}: " + " | ".join(cells), flush=True)
            print("  the L fold across the band, change of w from 2.25 to 3.4, B's far edge "
                  "roller / diaphragm:", flush=True)
            for frequency in (600.0, 800.0, 1200.0, 1500.0, 2000.0):
                cells = []
                for far in ("roller", "diaphragm"):
                    coarse, fine = (hanging_fields("L", ("simply_supported", far), frequency, r)
                                    for r in (2.25, 3.4))
                    cells.append(f"{largest_change(fine, coarse, 0):.1e}")
                print(f"    {frequency:6.0f} Hz: " + " / ".join(cells), flush=True)


def best_time(solve, repeats: int = 3) -> float:
    """The best of ``repeats`` processor times of ``solve()`` (s)."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        solve()
        times.append(time.process_time() - start)
    return min(times)


def rule_cost() -> None:
    """What the rule costs (``--rule``): one solve at resolution 1.5 with the line moving
    under the rule and held (``held = true``), processor time, best of three, on the L fold,
    the T junction and the three-bay panel with ``simply_supported`` + ``roller`` ends; then the
    panel's refinement under the rule, 1.5 -> 2.25 -> 3.4."""
    def fold(shape, frequency, held):
        plates, lines, load = SHAPES[shape]
        description = folded_description(plates, lines, load, frequency, held, LY, 1.5)
        for boundary in description["boundaries"]:
            if boundary["edge"].endswith(("bottom", "top")):
                boundary["condition"], boundary["in_plane"] = "simply_supported", "roller"
        return parse_case(description)

    def panel(frequency, held):
        from bench_moving_lines import LOAD as PANEL_LOAD
        from bench_moving_lines import MODEL_LOG_K, lines
        from bench_moving_lines import PLATES as PANEL

        description = folded_description(PANEL, lines(MODEL_LOG_K), PANEL_LOAD, frequency,
                                         held, LY, 1.5)
        for boundary in description["boundaries"]:
            if boundary["edge"].endswith(("bottom", "top")):
                boundary["condition"], boundary["in_plane"] = "simply_supported", "roller"
        return parse_case(description)

    print("the rule's cost: one solve at resolution 1.5, moving under the rule / held "
          "(processor time, best of three)", flush=True)
    for label, build, frequencies in (("L fold", lambda f, h: fold("L", f, h), (300.0, 1000.0,
                                                                                 3000.0)),
                                      ("T junction", lambda f, h: fold("T", f, h), (1000.0,
                                                                                     3000.0)),
                                      ("panel", panel, (1000.0, 2500.0))):
        for frequency in frequencies:
            seconds = [best_time(lambda: solve_assembly(build(frequency, held), frequency,
                                                        residuals=False))
                       for held in (False, True)]
            print(f"  {label} {frequency:6.0f} Hz: {seconds[0]:.2f} / {seconds[1]:.2f} s "
                  f"({seconds[0] / seconds[1]:.0f}x)", flush=True)
    print("the panel under the rule, largest change of w, then (u, v), resolutions 1.5 -> 2.25 "
          "-> 3.4 (the time of each solve)", flush=True)
    for frequency in (1000.0, 2500.0):
        previous, cells = None, []
        for resolution in (1.5, 2.25, 3.4):
            fields, seconds = panel_fields(frequency, "diaphragm", resolution,
                                           ("simply_supported", "roller"))
            if previous is not None:
                cells.append(f"w {largest_change(fields, previous, 0):.1e} (u, v) "
                             f"{largest_change(fields, previous, 1):.1e} ({seconds:.1f} s)")
            previous = fields
        print(f"  {frequency:6.0f} Hz: " + "; ".join(cells), flush=True)


def against_finite_elements(level: int = 6) -> None:
    """The L fold with ``simply_supported`` + ``roller`` ends under the rule against the
    independent finite elements of ``bench/fem_folded.py`` (mesh ``level``; its fields change
    by 1e-8 to 6e-7 from level 4 to 6, and with shear-diaphragm ends it meets the exact
    prismatic solution to 1e-9 to 3e-8): relative L2 difference of ``w`` and ``(u, v)`` per
    plate, at resolutions 1.5, 2.25 and 3.4; at resolution 2.25 with the line's Legendre
    functions set to 30, 40 and 50 (``interface_functions``, the logarithmic ones added), then
    on Legendre functions alone (as before them) at their usual count and at 30 to 60; the
    same with shear-diaphragm ends at resolution 2.25, where both are exact to 1e-8; and the
    other mixes the finite elements take, ``symmetric`` + ``diaphragm`` and ``symmetric`` +
    ``fixed`` ends (no logarithmic load functions under the rule), at resolutions 1.5, 2.25
    and 3.4."""
    from fem_folded import folded_fields as finite_element_fields

    def cells(fields: dict, w_fe: dict, uv_fe: dict) -> str:
        return "; ".join(
            f"{name}: w {np.linalg.norm(fields[name][0] - w_fe[name]) / np.linalg.norm(w_fe[name]):.1e}"
            f" (u, v) {np.linalg.norm(fields[name][1] - uv_fe[name]) / np.linalg.norm(uv_fe[name]):.1e}"
            for name in fields)

    print(f"against the finite elements of fem_folded.py (level {level}): the L fold, relative "
          "L2 difference per plate", flush=True)
    for frequency in (300.0, 1000.0):
        w_fe, uv_fe = finite_element_fields(frequency, "roller", level)
        for resolution in (1.5, 2.25, 3.4):
            fields, seconds, _ = fold_fields(frequency, "roller", resolution)
            print(f"  roller {frequency:6.0f} Hz, resolution {resolution:4.2f} ({seconds:.1f} s):"
                  f" {cells(fields, w_fe, uv_fe)}", flush=True)
        for functions in (30, 40, 50):
            fields, _, _ = fold_fields(frequency, "roller", 2.25,
                                       {"interface_functions": functions})
            print(f"  roller {frequency:6.0f} Hz, resolution 2.25, {functions} Legendre "
                  f"functions: {cells(fields, w_fe, uv_fe)}", flush=True)
        with end_treatment(SINGULAR_END_REACH, load_functions=False):
            for functions in (None, 30, 40, 50, 60):
                fields, _, _ = fold_fields(frequency, "roller", 2.25,
                                           {"interface_functions": functions} if functions
                                           else {})
                print(f"  roller {frequency:6.0f} Hz, resolution 2.25, Legendre functions alone"
                      f" ({functions or 'the usual count'}): {cells(fields, w_fe, uv_fe)}",
                      flush=True)
        w_fe, uv_fe = finite_element_fields(frequency, "diaphragm", level)
        fields, _, _ = fold_fields(frequency, "diaphragm", 2.25)
        print(f"  diaphragm {frequency:6.0f} Hz, resolution 2.25: {cells(fields, w_fe, uv_fe)}",
              flush=True)
        for in_plane in ("diaphragm", "fixed"):
            w_fe, uv_fe = finite_element_fields(frequency, f"symmetric_{in_plane}", level)
            for resolution in (1.5, 2.25, 3.4):
                fields, _, _ = fold_fields(frequency, in_plane, resolution,
                                           condition="symmetric")
                print(f"  symmetric + {in_plane} {frequency:6.0f} Hz, resolution "
                      f"{resolution:4.2f}: {cells(fields, w_fe, uv_fe)}", flush=True)


def junction_against_finite_elements(level: int = 8) -> None:
    """The T junction of the tests with ``simply_supported`` + ``roller`` ends, its stiffener's
    top simply supported and fixed or free (it hangs), under the rule and on Legendre load
    functions alone, against the independent finite elements of ``bench/fem_junction.py``
    (mesh ``level``; estimated error 6e-9 to 2e-8 in ``w`` at 1 kHz, 6e-7 to 9e-7 at 3 kHz at
    level 8): the largest relative L2 difference of ``w``, then of ``(u, v)``, over the three
    plates at resolutions 1.5, 2.25 and 3.4."""
    from fem_junction import junction_fields

    print(f"against the finite elements of fem_junction.py (level {level}): the T junction, "
          "largest relative L2 difference over the plates, resolutions 1.5, 2.25, 3.4",
          flush=True)
    for top, far in (("fixed", ("simply_supported", "fixed")), ("free", None)):
        for frequency in (1000.0, 3000.0):
            w_fe, uv_fe = junction_fields(frequency, "roller", top, level)
            reference = {name: (w_fe[name], uv_fe[name]) for name in w_fe}
            for label, treatment in (
                    ("the rule", contextlib.nullcontext),
                    ("Legendre load functions alone",
                     lambda: end_treatment(SINGULAR_END_REACH, load_functions=False))):
                with treatment():
                    fields = [hanging_fields("T", far, frequency, resolution)
                              for resolution in (1.5, 2.25, 3.4)]
                print(f"  T1's top {top}, {frequency:6.0f} Hz, {label}: w "
                      + ", ".join(f"{largest_change(f, reference, 0):.1e}" for f in fields)
                      + "; (u, v) "
                      + ", ".join(f"{largest_change(f, reference, 1):.1e}" for f in fields),
                      flush=True)


def floor_rows(label: str, case_of, reference: tuple[dict, dict],
               resolutions: tuple[float, ...], frequency: float) -> None:
    """One line per resolution: the line's Legendre count and, per plate, the relative L2
    error of ``w`` against ``reference`` (``({plate: w}, {plate: (u, v)})``) with the
    estimate's ratio to it in brackets, then that of ``(u, v)``, with the floor and without
    (:func:`end_treatment`)."""
    from solver.estimate import estimate_error
    from solver.layout import interface_layout

    w_reference, uv_reference = reference
    for resolution in resolutions:
        cells = []
        for floor in (True, False):
            with end_treatment(SINGULAR_END_REACH, floor=floor):
                case = case_of(resolution)
                solution = solve_assembly(case, frequency)
                estimate = estimate_error(case, solution)
                problems = {p: solution.plates[p].problem for p in solution.plates}
                count = max(interface_layout(case, problems).counts.values())
            errors = []
            for name, w in w_reference.items():
                points = inner_grid(case.plates[name].size[0], LY)
                w_error = (np.linalg.norm(solution.plates[name].field(points)["w"] - w)
                           / np.linalg.norm(w))
                uv = uv_reference[name]
                uv_error = (np.linalg.norm(solution.in_plane(name, points) - uv)
                            / np.linalg.norm(uv))
                errors.append(f"{name} {w_error:.1e} ({estimate.plates[name] / w_error:.2f})"
                              f" / {uv_error:.1e}")
            cells.append(f"{count} functions: " + ", ".join(errors))
        print(f"  {label} {frequency:5.0f} Hz, resolution {resolution:4.2f}: with the floor "
              f"{cells[0]} | without {cells[1]}", flush=True)


def floor_on_the_panel() -> None:
    """The three-bay panel of ``bench_moving_lines.py`` with roller ends simply supported,
    its lines moving (``held = false``; its stiffeners hang on them), at 300 and 600 Hz:
    the largest change of ``w`` and ``(u, v)`` over the plates between resolutions 1.5 ->
    2.25 -> 3.4, with the floor of the line's Legendre functions and without. There is no
    independent solution of it: the changes are not its error."""
    print("the panel with roller ends, refinement 1.5 -> 2.25 -> 3.4 (largest change over "
          "the plates)", flush=True)
    for frequency in (300.0, 600.0):
        for floor in (True, False):
            with end_treatment(SINGULAR_END_REACH, floor=floor):
                fields = [panel_fields(frequency, "roller", resolution,
                                       ("simply_supported", "roller"))[0]
                          for resolution in (1.5, 2.25, 3.4)]
            changes = [", ".join(f"{largest_change(fine, coarse, component):.1e}"
                                 for coarse, fine in itertools.pairwise(fields))
                       for component in (0, 1)]
            print(f"  {frequency:5.0f} Hz, {'with' if floor else 'without'} the floor: w "
                  f"{changes[0]}; (u, v) {changes[1]}", flush=True)


def legendre_floor(level: int = 6) -> None:
    """The floor of a mixed-end line's Legendre functions
    (``solver.joint_rules.mixed_end_legendre_count``) against the finite elements of
    ``fem_folded.py`` and ``fem_junction.py`` at mesh ``level`` (computed here): the L fold
    with ``simply_supported`` + ``roller`` ends at 60, 100, 200, 300 and 500 Hz, resolutions 1
    to 3.4, and the T junction with the same ends at 300 Hz, its stiffener's top free (it
    hangs) or fixed, resolutions 1 to 2.25 (:func:`floor_rows`: per plate the error of ``w``,
    the estimate over it, and the error of ``(u, v)``; the counts include the four
    logarithmic functions)."""
    from fem_folded import folded_fields as fold_finite_elements
    from fem_junction import junction_fields

    def roller(plates, lines, load, frequency):
        def case_of(resolution: float):
            return parse_case(folded_description(plates, lines, load, frequency, False, LY,
                                                 resolution, ends="roller"))
        return case_of

    print(f"the floor of the line's Legendre functions against finite elements (level {level})"
          ": per plate the relative L2 error of w (the estimate over it) / that of (u, v)",
          flush=True)
    for frequency in (60.0, 100.0, 200.0, 300.0, 500.0):
        floor_rows("L fold", roller(PLATES, LINES, LOAD, frequency),
                   fold_finite_elements(frequency, "roller", level),
                   (1.0, 1.5, 2.25, 3.4), frequency)
    plates, lines, load = SHAPES["T"]
    for top in ("free", "fixed"):
        if top == "fixed":
            plates = {**plates, "T1": plates["T1"][:4] + ("simply_supported",)}
        floor_rows(f"T, top {top}", roller(plates, lines, load, 300.0),
                   junction_fields(300.0, "roller", top, level),
                   (1.0, 1.5, 2.25), 300.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--symmetry", action="store_true", help="the planes of symmetry only")
    parser.add_argument("--log-families", action="store_true",
                        help="the logarithmic families of a mixed end only")
    parser.add_argument("--hanging", action="store_true",
                        help="mixed ends with and without a member hanging on the line only")
    parser.add_argument("--fem", action="store_true",
                        help="the L fold against the finite elements of fem_folded.py only")
    parser.add_argument("--floor", action="store_true",
                        help="the floor of the line's Legendre functions against finite "
                             "elements only")
    parser.add_argument("--rule", action="store_true",
                        help="the rule's cost against held lines, and the panel under it, only")
    parser.add_argument("--reach", type=float, default=1.0,
                        help="with --log-families: the members' edge waves' reach, times the "
                             "usual (default 1)")
    args = parser.parse_args()
    if args.log_families:
        log_families(args.reach)
        return
    if args.hanging:
        hanging()
        return
    if args.rule:
        rule_cost()
        return
    if args.floor:
        legendre_floor()
        floor_on_the_panel()
        return
    if args.fem:
        against_finite_elements()
        junction_against_finite_elements()
        return
    planes_of_symmetry()
    if args.symmetry:
        return
    with end_treatment(1.0, families=False, load_functions=False):
        print("refinement, the rays alone with the usual reach (resolution 1 -> 1.5 -> 2.25 "
              "-> 3.4)")
        for ends in ("diaphragm", "roller"):
            for frequency in (300.0, 1000.0):
                refinement(ends, frequency, (1.0, 1.5, 2.25, 3.4))
        print("reach of the edge waves, the rays alone (resolution 1.5, 30 line functions)")
        reaches = (2.5, 5.0, 10.0) if args.quick else (2.5, 5.0, 10.0, 15.0, 20.0)
        for ends, frequency in (("diaphragm", 1000.0), ("roller", 1000.0), ("roller", 2500.0)):
            previous = None
            for tau in reaches:
                fields, seconds, corner = fold_fields(
                    frequency, ends, 1.5,
                    {"edge_wavenumber_ratio": tau, "interface_functions": 30})
                change = "" if previous is None else differences(previous, fields)
                print(f"  {ends:9s} {frequency:6.0f} Hz  tau {tau:4.1f}  {seconds:5.1f} s  "
                      f"w_B(end)/max {corner:.1e}  {change}", flush=True)
                previous = fields
    print(f"refinement with the rule (the logarithmic families, reach x "
          f"{solver.line_ends.SINGULAR_END_REACH:g}; resolution 1.5 -> 2.25 -> 3.4)")
    for frequency in (300.0, 1000.0):
        refinement("roller", frequency, (1.5, 2.25, 3.4))


if __name__ == "__main__":
    main()
