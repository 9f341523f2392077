"""Moving lines with free ends (``docs/method.md`` section 10.4): what the members' longer edge
reach (``solver.line_ends.FREE_END_REACH``, growing with the resolution from
``REACH_GROWTH_FROM``) buys and costs, on the bracket of ``tests/test_free_ends.py`` (2 mm
steel legs 0.4 and 0.3 m folded at 90 degrees, a lossy weld, far edges simply supported, ends
free, 1 N on the first leg).

* **refinement**: the worst plate's relative L2 change of ``w`` and of ``(u, v)`` on a 15 x 15
  grid between resolutions 1.5 and 2.25, with the rule and with the usual reach
  (``FREE_END_REACH`` = 1, not growing), and for the held line;
* **cost**: one solve at resolution 1.5 (processor time of one BLAS thread, best of three) and
  its unknowns, with the rule, with the usual reach and held;
* **finite elements** (``--finite-elements``): the bracket with a rigid line at 300 Hz and
  1 kHz against ``tests/data/fem_fold_free_ends.npz``, worst plate's error of ``w``, the error
  estimate over it on every plate and the time, by resolution: the rule (the reach growing,
  the line's count at least ``solver.joint_rules.end_layer_count``), the reach growing without
  that floor (2026-11-27 evening), the reach fixed at three times with the line's Legendre
  count following it (earlier that day), and the count stopped at the usual reach too (until
  then); about seven minutes;
* **sliding ends** (``--sliding-ends``): the same with the fold's ends simply supported and free
  in plane (``tests/test_free_ends.sliding_fold``), each member pinned at its corners by the
  other's supports (``assembly.lines.pinned_ends``), against
  ``tests/data/fem_fold_sliding_ends.npz``: the rule (logarithmic families at the pinned
  ends, the reach capped at ``solver.line_ends.PINNED_END_REACH``, the line's count of
  ``solver.joint_rules.pinned_line_count``), the same with the usual count and its floors (as
  until 0.3.14), and without the families (the free end's rule alone, until 2026-11-28); the
  error and estimate of ``(u, v)`` too; about twelve minutes;
* **pinned stiffener** (``--pinned-stiffener``): the same three on the T junction whose
  stiffener's ends and top are free (``tests/test_held_ends.pinned_stiffener``), against
  ``tests/data/fem_junction_stiffener_free.npz`` (``bench/fem_junction.py``);
* **pinned stiffener over a band** (``--pinned-band``): the same T junction's refinement without
  a reference, largest change over the plates of ``w`` and of ``(u, v)`` between resolutions
  1.5, 2.25 and 3.375, at 2, 2.5, 3 and 3.5 kHz, then at 3 kHz with five times the loss factor
  (5 %), with the stiffener's in-plane RMS displacement at resolution 3.375 beside; with the
  usual count (before ``solver.joint_rules.pinned_line_count``) the refinement stalled from
  2.5 kHz on, most where the stiffener, which hangs on its line, is near a resonance of its
  in-plane motion (its amplitude about inversely proportional to the loss factor); about
  twenty-five minutes;
* **the pinned stiffener's count** (``--pinned-counts``): the same T junction against its finite
  elements at 300 Hz and 1 kHz, resolutions 1, 1.5 and 2.25, with the line's Legendre count
  fixed at 1 to 3 times the usual count; then with the floor raised from the free end's
  4 sqrt(kappa_a L) (``solver.joint_rules.end_layer_count``) to ``PINNED_COUNT_FACTOR``
  sqrt(kappa_a L), with the estimate over the error; about ten minutes;
* **the sliding fold's count** (``--sliding-factors``): the fold with sliding ends against
  its finite elements at 300 Hz and 1 kHz, resolutions 1.5, 2.25 and 3.375, with its line's
  count c sqrt(kappa_a L) for each factor of ``SLIDING_FACTORS``, with the estimates
  over the errors; about ten minutes;
* **sliding channel** (``--sliding-channel``): the U channel with its ends simply supported
  and free in plane (``tests/test_free_ends.sliding_channel``; its web hangs on both lines),
  no reference: the worst plate's change of ``w`` and of ``(u, v)`` between resolutions 1.5,
  2.25 and 3.375 at 300 Hz and 1 kHz, and the largest estimates at each, with the rule's
  count (7 sqrt(kappa_a L): no member hangs on either line alone), with the hanging factor
  8.5 and with the usual count; about eight minutes;
* **channel** (``--channel``): the U channel of ``tests/test_free_ends.channel`` (a web and two
  flanges, two rigid lines free at both ends) against ``tests/data/fem_channel.npz``
  (``bench/fem_channel.py``), by resolution with the count's floor and without it, then at
  resolution 1.5 the error by the lines' count: a third structure for the floor.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_free_ends.py [--quick | --finite-elements |
--sliding-ends | --pinned-stiffener | --pinned-band | --pinned-counts | --sliding-factors |
--sliding-channel | --channel]`` (about two minutes; ``--quick`` stops at 1 kHz).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import inner_grid  # noqa: E402
from test_free_ends import (  # noqa: E402
    CHANNEL_PLATES,
    LY,
    PLATES,
    _bracket,
    channel,
    sliding_channel,
    sliding_fold,
)
from test_held_ends import pinned_stiffener  # noqa: E402
from test_moving_lines import T_JUNCTION  # noqa: E402

import solver.joint_rules  # noqa: E402
import solver.layout  # noqa: E402
import solver.line_ends  # noqa: E402
import solver.problems  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.estimate import estimate_error  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

RULE = (solver.line_ends.FREE_END_REACH, solver.line_ends.REACH_GROWTH_FROM)
MODELS = {"rule": (RULE, None), "usual reach": ((1.0, math.inf), None), "held": (RULE, True)}


def solution_fields(solution, plates: dict = PLATES) -> dict:
    """Per plate of ``plates`` ``(w, (u, v))`` of ``solution`` on its 15 x 15 grid."""
    out = {}
    for name, (length, *_) in plates.items():
        points = inner_grid(length, LY)
        out[name] = (solution.plates[name].field(points)["w"], solution.in_plane(name, points))
    return out


def plate_fields(description: dict, frequency: float, plates: dict = PLATES) -> dict:
    """:func:`solution_fields` of a solve of ``description``."""
    return solution_fields(solve_assembly(parse_case(description), frequency, residuals=False),
                           plates)


def fields(frequency: float, resolution: float, held: bool | None) -> dict:
    """The bracket's :func:`plate_fields`."""
    return plate_fields(_bracket(frequency, resolution, held), frequency)


def change(a: dict, b: dict, component: int) -> float:
    """The worst plate's relative L2 difference of one component (0: w, 1: (u, v))."""
    worst = 0.0
    for name in a:
        norm = np.linalg.norm(b[name][component])
        if norm > 0.0:
            worst = max(worst, np.linalg.norm(a[name][component] - b[name][component]) / norm)
    return worst


FINITE_ELEMENT_RUNS = {300.0: (1.0, 1.5, 2.25, 3.375, 5.0), 1000.0: (1.0, 1.5, 2.25, 3.375)}
"""Per frequency of the finite-element reference, the resolutions compared."""


def rigid_bracket(frequency: float, resolution: float) -> dict:
    """The bracket with a rigid line, the finite elements' (``fem_fold_free_ends.npz``)."""
    description = _bracket(frequency, resolution)
    description["joints"]["F"] = description["joints"]["F"] | {
        "log10_stiffness": {"A": float("inf"), "B": float("inf")}}
    del description["joints"]["F"]["loss_factor"]
    return description


ErrorRow = tuple[float, float | None, float | None]
"""The worst plate's error, and the estimate over the error on every plate (smallest and
largest; None where the estimate was not made, or not asked)."""


def solve_errors(description: dict, frequency: float, reference: dict, plates: dict = PLATES,
                 suffix: str | None = None, estimated: bool = True
                 ) -> tuple[ErrorRow, ErrorRow, float]:
    """One solve of a fold ``description`` at ``frequency`` against the finite elements
    ``reference``: the :data:`ErrorRow` of ``w``, that of ``(u, v)``, and the seconds of the
    solve with its estimate. The reference's keys end with ``suffix`` (by default none at
    300 Hz and ``_1000`` at 1 kHz, as the fold's files have them)."""
    suffix = ("" if frequency == 300.0 else f"_{frequency:g}") if suffix is None else suffix
    case = parse_case(description)
    start = time.perf_counter()
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution) if estimated else None
    seconds = time.perf_counter() - start
    rows = []
    for key in ("w", "uv"):
        errors = {}
        for name, (length, *_) in plates.items():
            points = inner_grid(length, LY)
            field = (solution.in_plane(name, points) if key == "uv"
                     else solution.plates[name].field(points)["w"])
            exact = reference[f"{key}_{name}{suffix}"]
            errors[name] = float(np.linalg.norm(field - exact) / np.linalg.norm(exact))
        if estimate is None or estimate.total is None:  # not asked, or beyond its time limit
            rows.append((max(errors.values()), None, None))
            continue
        estimates = estimate.in_plane if key == "uv" else estimate.plates
        ratios = [estimates[name] / errors[name] for name in plates]
        rows.append((max(errors.values()), min(ratios), max(ratios)))
    return rows[0], rows[1], seconds


def finite_elements() -> None:
    """The rigid bracket against the finite elements, by resolution: the members' reach
    growing with the resolution (:data:`solver.line_ends.REACH_GROWTH_FROM`), as today; the
    reach fixed at three times, the line's count following it (2026-11-27); and the count
    stopped at the usual reach too (until then)."""
    reference = np.load(ROOT / "tests" / "data" / "fem_fold_free_ends.npz")
    print("against finite elements (rigid line): worst plate's error of w; estimate / error "
          "over the plates; seconds of the solve and its estimate")
    growing, following = solver.line_ends.REACH_GROWTH_FROM, solver.layout.answered_wavenumber
    floor = solver.joint_rules.END_LAYER_FROM
    models = {"rule": (growing, following, floor),
              "no floor": (growing, following, math.inf),
              "reach fixed": (math.inf, following, math.inf),
              "usual count": (math.inf, lambda case, jid, problems, resolution=None:
                              solver.layout.members_wavenumber(case, jid, problems), math.inf)}
    for frequency, resolutions in FINITE_ELEMENT_RUNS.items():
        for label, (start, answered, floor_from) in models.items():
            solver.line_ends.REACH_GROWTH_FROM = start
            solver.layout.answered_wavenumber = answered
            solver.joint_rules.END_LAYER_FROM = floor_from
            for resolution in resolutions:
                (error, low, high), _, seconds = solve_errors(
                    rigid_bracket(frequency, resolution), frequency, reference)
                ratios = "not estimated" if low is None else f"{low:.2f} to {high:.2f}"
                print(f"  {frequency:6.0f} Hz  {label:11s} {resolution:5.3g}: {error:.1e}; "
                      f"{ratios}; {seconds:.1f} s", flush=True)
    solver.line_ends.REACH_GROWTH_FROM = growing
    solver.layout.answered_wavenumber = following
    solver.joint_rules.END_LAYER_FROM = floor


SLIDING_RUNS = {300.0: (1.0, 1.5, 2.25, 3.375, 5.0), 1000.0: (1.0, 1.5, 2.25, 3.375, 5.0625)}
"""Per frequency of the sliding-ends reference, the resolutions compared."""

PINNED_RUNS = {300.0: (1.0, 1.5, 2.25, 3.375), 1000.0: (1.0, 1.5, 2.25, 3.375)}
"""Per frequency of the pinned stiffener's reference, the resolutions compared."""


def without_families(case, joint_id: str, meeting=None) -> set:
    """:func:`solver.line_ends.singular_end_edges` as it was until 2026-11-28: the mixed ends
    alone, a pinned end getting no logarithmic families and the free end's reach."""
    return set(case.singular_ends(joint_id))


def pinned_ends(label: str, description, reference: dict, plates: dict, runs: dict,
                suffix) -> None:
    """A structure with pinned ends against its finite elements, by resolution: the rule (the
    logarithmic families at its pinned ends, the reach capped at
    :data:`solver.line_ends.PINNED_END_REACH`, the line's count of
    :func:`solver.joint_rules.pinned_line_count`), the same with the usual count and its
    floors (as until 0.3.13 on a line on which a member hangs, until 0.3.14 on the others),
    and without the families, the free end's rule alone (until 2026-11-28)."""
    print(f"{label} against finite elements: worst plate's error of w, then of (u, v); estimate "
          "/ error over the plates; seconds of the solve and its estimate")
    rule, pinned_lines = solver.line_ends.singular_end_edges, solver.layout.pinned_lines
    models = (("rule", rule, pinned_lines), ("usual count", rule, lambda case: {}),
              ("no families", without_families, pinned_lines))
    try:
        for frequency, resolutions in runs.items():
            for model, edges, lines in models:
                solver.line_ends.singular_end_edges, solver.layout.pinned_lines = edges, lines
                for resolution in resolutions:
                    (w, low, high), (uv, uv_low, uv_high), seconds = solve_errors(
                        description(frequency, resolution), frequency, reference, plates,
                        suffix(frequency))
                    estimated = (f"({low:.2f} to {high:.2f})",
                                 f"({uv_low:.2f} to {uv_high:.2f})"
                                 ) if low is not None else ("(not estimated)", "")
                    print(f"  {frequency:6.0f} Hz  {model:11s} {resolution:6.4g}: w {w:.1e} "
                          f"{estimated[0]}; (u, v) {uv:.1e} {estimated[1]}; {seconds:.1f} s",
                          flush=True)
    finally:
        solver.line_ends.singular_end_edges, solver.layout.pinned_lines = rule, pinned_lines


BAND_RUNS = ((2000.0, 0.01), (2500.0, 0.01), (3000.0, 0.01), (3500.0, 0.01), (3000.0, 0.05))
"""The pinned stiffener's frequencies and loss factors of ``--pinned-band``."""


def stiffener_fields(frequency: float, resolution: float, loss_factor: float) -> dict:
    """Per plate of the pinned stiffener's T junction ``(w, (u, v))`` on its inner grid, every
    plate of ``loss_factor``."""
    description = pinned_stiffener(frequency, resolution)
    description["materials"] = {name: {**material, "loss_factor": loss_factor}
                                for name, material in description["materials"].items()}
    return plate_fields(description, frequency, T_JUNCTION[0])


def pinned_band() -> None:
    """The pinned stiffener's refinement over a band (:data:`BAND_RUNS`), without a reference:
    the largest change over the plates of ``w`` and of ``(u, v)`` between resolutions 1.5, 2.25
    and 3.375, and the stiffener's in-plane RMS displacement (over its grid and both components, at
    3.375)."""
    print("pinned stiffener over a band: largest change of w, then of (u, v), between "
          "resolutions 1.5 -> 2.25 -> 3.375; the stiffener's in-plane RMS displacement")
    for frequency, loss_factor in BAND_RUNS:
        steps = [stiffener_fields(frequency, r, loss_factor) for r in (1.5, 2.25, 3.375)]
        w, uv = (", ".join(f"{change(a, b, c):.1e}" for a, b in zip(steps, steps[1:]))
                 for c in (0, 1))
        rms = float(np.sqrt(np.mean(np.abs(steps[-1]["T1"][1]) ** 2)))
        print(f"  {frequency:6.0f} Hz, loss factor {loss_factor:.2f}: w {w}; (u, v) {uv}; "
              f"T1 (u, v) {rms:.2e} m", flush=True)


COUNT_MULTIPLES = (1.0, 1.5, 2.0, 2.5, 3.0)
"""The line's counts of ``--pinned-counts``, in multiples of the usual count's (without
``solver.joint_rules.pinned_line_count``, as measured before it was the rule)."""
PINNED_COUNT_FACTOR = 7.0
r"""The factor :math:`c` of the floor :math:`c\sqrt{\kappa_aL}` tried in ``--pinned-counts``."""


def pinned_counts() -> None:
    """The pinned stiffener against its finite elements with the line's count fixed at
    :data:`COUNT_MULTIPLES` of the usual count, then with, instead of the pinned line's count,
    the floor of the free end's count raised to :data:`PINNED_COUNT_FACTOR`
    :math:`\\sqrt{\\kappa_aL}` (worst plate's ``w``, the estimate of ``w`` over its error on
    every plate): the measurements behind :func:`solver.joint_rules.pinned_line_count`."""
    reference = np.load(ROOT / "tests" / "data" / "fem_junction_stiffener_free.npz")
    pinned_lines = solver.layout.pinned_lines
    solver.layout.pinned_lines = lambda case: {}  # the usual count
    try:
        _pinned_count_scan(reference)
    finally:
        solver.layout.pinned_lines = pinned_lines


def _pinned_count_scan(reference) -> None:
    """:func:`pinned_counts` with the pinned line's count off."""
    print("pinned stiffener against finite elements by the line's count: worst plate's w")
    for frequency in (300.0, 1000.0):
        suffix = f"_{frequency:g}"
        for resolution in (1.0, 1.5, 2.25):
            rule = line_counts(pinned_stiffener(frequency, resolution), frequency)["W"]
            cells = []
            for multiple in COUNT_MULTIPLES:
                description = pinned_stiffener(frequency, resolution)
                count = round(multiple * rule)
                description["discretisation"]["interface_functions"] = count
                (w, *_), _, _ = solve_errors(description, frequency, reference, T_JUNCTION[0],
                                             suffix, False)
                cells.append(f"{count} {w:.1e}")
            print(f"  {frequency:6.0f} Hz {resolution:5.3g}: " + ", ".join(cells), flush=True)
    print(f"with a floor of {PINNED_COUNT_FACTOR:g} sqrt(kappa_a L): worst plate's w (estimate / "
          "error), the count")
    floor = solver.layout.end_layer_count

    def raised(answered: float, length: float, resolution: float, tau: float = 2.5) -> int:
        return max(floor(answered, length, resolution, tau),
                   math.ceil(PINNED_COUNT_FACTOR * math.sqrt(answered * length)))

    solver.layout.end_layer_count = raised
    try:
        for frequency in (300.0, 1000.0):
            for resolution in (1.0, 1.5, 2.25):
                description = pinned_stiffener(frequency, resolution)
                (w, low, high), _, _ = solve_errors(description, frequency, reference,
                                                    T_JUNCTION[0], f"_{frequency:g}")
                count = line_counts(description, frequency)["W"]
                print(f"  {frequency:6.0f} Hz {resolution:5.3g}: {w:.1e} ({low:.2f} to "
                      f"{high:.2f}); {count}", flush=True)
    finally:
        solver.layout.end_layer_count = floor


SLIDING_FACTORS = (5.5, 6.5, 7.0, 7.5, 8.5)
r"""The factors :math:`c` of the sliding fold's count :math:`c\sqrt{\kappa_aL}` tried in
``--sliding-factors``."""


def sliding_factors() -> None:
    """The fold with sliding ends against its finite elements with the line's count
    :func:`solver.joint_rules.pinned_line_count` at each factor of :data:`SLIDING_FACTORS` (no
    member hangs on its line: :data:`solver.joint_rules.PINNED_LINE_FACTOR` patched), at
    300 Hz and 1 kHz and resolutions 1.5, 2.25, 3.375: the measurements behind that factor."""
    reference = np.load(ROOT / "tests" / "data" / "fem_fold_sliding_ends.npz")
    print("sliding fold against finite elements by the factor of its line's count: worst "
          "plate's w, then (u, v), each with the estimate / error over the plates; the count")
    factor = solver.joint_rules.PINNED_LINE_FACTOR
    try:
        for frequency in (300.0, 1000.0):
            for value in SLIDING_FACTORS:
                solver.joint_rules.PINNED_LINE_FACTOR = value
                for resolution in (1.5, 2.25, 3.375):
                    description = sliding_fold(frequency, resolution)
                    (w, low, high), (uv, uv_low, uv_high), _ = solve_errors(
                        description, frequency, reference)
                    count = line_counts(description, frequency)["F"]
                    print(f"  {frequency:6.0f} Hz  c = {value:3.1f}  {resolution:5.4g}: w {w:.1e} "
                          f"({low:.2f} to {high:.2f}); (u, v) {uv:.1e} ({uv_low:.2f} to "
                          f"{uv_high:.2f}); {count}", flush=True)
    finally:
        solver.joint_rules.PINNED_LINE_FACTOR = factor


def sliding_channel_refinement() -> None:
    """The sliding channel's refinement (module notes), the three counts in turn: the rule's,
    the hanging factor's (:data:`solver.joint_rules.PINNED_LINE_FACTOR` patched to
    :data:`solver.joint_rules.HANGING_LINE_FACTOR`) and the usual count's
    (:func:`solver.line_ends.pinned_lines` off)."""
    print("sliding channel: worst plate's change of w, then of (u, v), between resolutions "
          "1.5 -> 2.25 -> 3.375; the largest estimates of w and (u, v) at each; the count")
    factor, lines = solver.joint_rules.PINNED_LINE_FACTOR, solver.layout.pinned_lines
    models = (("rule", factor, lines),
              ("factor 8.5", solver.joint_rules.HANGING_LINE_FACTOR, lines),
              ("usual count", factor, lambda case: {}))
    try:
        for frequency in (300.0, 1000.0):
            for label, value, pinned in models:
                solver.joint_rules.PINNED_LINE_FACTOR, solver.layout.pinned_lines = value, pinned
                steps, estimates, counts = [], [], []
                for resolution in (1.5, 2.25, 3.375):
                    description = sliding_channel(frequency, resolution)
                    case = parse_case(description)
                    solution = solve_assembly(case, frequency)
                    estimate = estimate_error(case, solution)
                    steps.append(solution_fields(solution, CHANNEL_PLATES))
                    estimates.append(f"{max(estimate.plates.values()):.1e} / "
                                     f"{max(estimate.in_plane.values()):.1e}")
                    counts.append(line_counts(description, frequency)["AB"])
                w, uv = (", ".join(f"{change(a, b, k):.1e}" for a, b in zip(steps, steps[1:]))
                         for k in (0, 1))
                print(f"  {frequency:6.0f} Hz  {label:11s}: w {w}; (u, v) {uv}; estimates "
                      f"{'; '.join(estimates)}; counts {counts}", flush=True)
    finally:
        solver.joint_rules.PINNED_LINE_FACTOR, solver.layout.pinned_lines = factor, lines


CHANNEL_RUNS = {300.0: (1.0, 1.5, 2.25, 3.375), 1000.0: (1.0, 1.5, 2.25)}
"""Per frequency of the channel's reference, the resolutions compared."""
CHANNEL_COUNTS = tuple(range(12, 57, 4))
"""The Legendre counts of the channel's lines scanned at resolution 1.5."""


def line_counts(description: dict, frequency: float) -> dict[str, int]:
    """The Legendre count of each line that the solver's rule gives ``description``."""
    case = parse_case(description)
    problems = solver.problems.plate_problems(case, frequency)
    return solver.layout.interface_layout(case, problems).counts


def channel_ends() -> None:
    """The U channel (``tests/test_free_ends.channel``: two lines, free at both ends) against
    ``tests/data/fem_channel.npz``, by resolution, with the count's floor
    (:func:`solver.joint_rules.end_layer_count`) and without it; then, at resolution 1.5, the
    error by the lines' count (both alike), beside the count each rule gives: a third
    structure for the floor, which two folds and a corner set."""
    reference = np.load(ROOT / "tests" / "data" / "fem_channel.npz")
    print("U channel, free ends, against finite elements: worst plate's error of w, then of "
          "(u, v); estimate / error over the plates; the lines' count; seconds of the solve and "
          "its estimate")
    floor = solver.joint_rules.END_LAYER_FROM
    for frequency, resolutions in CHANNEL_RUNS.items():
        suffix = f"_{frequency:g}"
        for label, floor_from in (("rule", floor), ("no floor", math.inf)):
            solver.joint_rules.END_LAYER_FROM = floor_from
            for resolution in resolutions:
                description = channel(frequency, resolution)
                (w, low, high), (uv, uv_low, uv_high), seconds = solve_errors(
                    description, frequency, reference, CHANNEL_PLATES, suffix)
                count = line_counts(description, frequency)["AB"]
                print(f"  {frequency:6.0f} Hz  {label:8s} {resolution:5.3g}: w {w:.1e} "
                      f"({low:.2f} to {high:.2f}); (u, v) {uv:.1e} ({uv_low:.2f} to "
                      f"{uv_high:.2f}); {count} functions; {seconds:.1f} s", flush=True)
    solver.joint_rules.END_LAYER_FROM = floor
    print("at resolution 1.5, by the lines' count: worst plate's error of w, of (u, v)")
    for frequency in CHANNEL_RUNS:
        suffix = f"_{frequency:g}"
        rule = line_counts(channel(frequency, 1.5), frequency)["AB"]
        solver.joint_rules.END_LAYER_FROM = math.inf
        usual = line_counts(channel(frequency, 1.5), frequency)["AB"]
        solver.joint_rules.END_LAYER_FROM = floor
        print(f"  {frequency:6.0f} Hz (the rule {rule}, the wavenumbers' count {usual}):",
              flush=True)
        for count in sorted({*CHANNEL_COUNTS, rule, usual}):
            description = channel(frequency, 1.5)
            description["discretisation"]["interface_functions"] = count
            (w, *_), (uv, *_), _ = solve_errors(description, frequency, reference,
                                                CHANNEL_PLATES, suffix, False)
            print(f"    {count:3d}: w {w:.1e}, (u, v) {uv:.1e}", flush=True)


def main() -> None:
    studies = {
        "finite_elements": finite_elements,
        "sliding_ends": lambda: pinned_ends(
            "sliding ends (rigid line)", sliding_fold,
            np.load(ROOT / "tests" / "data" / "fem_fold_sliding_ends.npz"), PLATES, SLIDING_RUNS,
            lambda frequency: "" if frequency == 300.0 else f"_{frequency:g}"),
        "pinned_stiffener": lambda: pinned_ends(
            "stiffener free at its ends", pinned_stiffener,
            np.load(ROOT / "tests" / "data" / "fem_junction_stiffener_free.npz"),
            T_JUNCTION[0], PINNED_RUNS, lambda frequency: f"_{frequency:g}"),
        "pinned_band": pinned_band,
        "pinned_counts": pinned_counts,
        "sliding_factors": sliding_factors,
        "sliding_channel": sliding_channel_refinement,
        "channel": channel_ends,
    }
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    choice = parser.add_mutually_exclusive_group()
    choice.add_argument("--quick", action="store_true")
    for name in studies:
        choice.add_argument("--" + name.replace("_", "-"), action="store_true")
    args = parser.parse_args()
    for name, study in studies.items():
        if getattr(args, name):
            return study()
    frequencies = (300.0, 1000.0) if args.quick else (300.0, 1000.0, 3000.0)
    print("refinement: worst plate's change of w ; (u, v) between resolutions 1.5 and 2.25")
    for frequency in frequencies:
        for label, (reach, held) in MODELS.items():
            solver.line_ends.FREE_END_REACH, solver.line_ends.REACH_GROWTH_FROM = reach
            steps = [fields(frequency, r, held) for r in (1.5, 2.25)]
            w = ", ".join(f"{change(a, b, 0):.1e}" for a, b in zip(steps, steps[1:]))
            uv = ("" if held else "; " + ", ".join(f"{change(a, b, 1):.1e}"
                                                    for a, b in zip(steps, steps[1:])))
            print(f"  {frequency:6.0f} Hz  {label:12s} {w}{uv}", flush=True)
    print("cost: one solve at resolution 1.5 (processor time, best of three; unknowns)")
    for frequency in frequencies:
        row = []
        for label, (reach, held) in MODELS.items():
            solver.line_ends.FREE_END_REACH, solver.line_ends.REACH_GROWTH_FROM = reach
            case = parse_case(_bracket(frequency, 1.5, held))
            times = []
            for _ in range(3):
                start = time.process_time()
                solution = solve_assembly(case, frequency, residuals=False)
                times.append(time.process_time() - start)
            row.append((label, min(times), solution.n_unknowns))
        ratios = (f"rule / usual {row[0][1] / row[1][1]:.1f}x, "
                  f"rule / held {row[0][1] / row[2][1]:.1f}x")
        print(f"  {frequency:6.0f} Hz  " + "; ".join(f"{label} {t:.2f} s ({n})"
                                                    for label, t, n in row) + f"; {ratios}",
              flush=True)
    solver.line_ends.FREE_END_REACH, solver.line_ends.REACH_GROWTH_FROM = RULE


if __name__ == "__main__":
    main()
