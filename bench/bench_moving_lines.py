"""Moving against held lines on a stiffened panel: what the model costs, and what it changes
for an identification.

The panel (issue 33): a 1 mm steel skin of three bays 0.4 x 0.5 m, two stiffeners 8 cm / 1.5 mm
(T1) and 10 cm / 2 mm (T2) welded on the inner bay lines, shear diaphragms on the ends y = 0 and
y = 0.5 m (``simply_supported`` with ``in_plane = "diaphragm"``), the skin's outer edges simply
supported and fixed in-plane, the stiffeners' tops free, 1 N on bay B1.

* **Cost**: one solve with moving lines and one with held lines, at the same resolution:
  processor time (best of three), unknowns and peak memory (numpy's arrays, traced); and the
  time each takes to meet ``--tolerance 1e-3`` (``solve_to_tolerance``), at 600 and 2500 Hz;
  the two models' solves alternating in one process (``alternating``: a steadier ratio on a
  noisy machine);
  and each model's time and error against its own exact solution by resolution (at the same
  accuracy), and the smallest resolution of each that reaches 1e-3 to 1e-7, the two timed
  alternately (``matched_accuracy``, ``--matched`` alone); and where one solve's time goes, by
  part of the build; and one solve of the panel widened to 6, 12 and 24 bays (its two
  stiffeners alternating), where the ratio grows.
* **Identification**: the "measured" field is the exact prismatic folded plate of
  ``tests/exact_prismatic.py`` (bending and in-plane motion, lines free in translation) with
  the weld W2.T2 at log10 k = 2.0 (the model says 3.5), sampled on the skin only (0.1 m cell
  centres, a vibrometer's face), +-5 % uniform noise; ``vtcr update`` corrects W2.T2 with
  moving lines, then with ``held = true``.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_moving_lines.py`` (about three minutes);
``--instructions 600`` counts the instructions of one solve of each model instead
(``instructions``: valgrind's callgrind, a yardstick that a busy machine does not move).
"""

from __future__ import annotations

import argparse
import cProfile
import math
import os
import pstats
import re
import shutil
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import folded_description, folded_reference, folded_w, inner_grid  # noqa: E402

from assembly import parse_case  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402
from solver.tolerance import solve_to_tolerance  # noqa: E402
from updating.api import update_case  # noqa: E402
from updating.data.measurements import Measurements, add_noise  # noqa: E402

LY, BAY = 0.5, 0.4
ALONG_X, UP = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
# name: (length, origin, x_axis, thickness, right edge)
PLATES = {"B1": (BAY, (0.0, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "B2": (BAY, (BAY, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "B3": (BAY, (2 * BAY, 0.0, 0.0), ALONG_X, 0.001, "simply_supported"),
          "T1": (0.08, (BAY, 0.0, 0.0), UP, 0.0015, "free"),
          "T2": (0.10, (2 * BAY, 0.0, 0.0), UP, 0.002, "free")}
MODEL_LOG_K, TRUE_LOG_K = 3.5, 2.0
LOAD = ("B1", 0.17, 0.13)


def lines(weak: float) -> dict[str, dict[str, tuple[str, float]]]:
    return {"W1": {"B1": ("right", math.inf), "B2": ("left", math.inf),
                   "T1": ("left", MODEL_LOG_K)},
            "W2": {"B2": ("right", math.inf), "B3": ("left", math.inf), "T2": ("left", weak)}}


def description(frequencies: list[float], held: bool, resolution: float = 1.5,
                noise: float = 0.05) -> dict:
    """The panel's description, the skin measured (0.1 m grid, ``noise``)."""
    return folded_description(PLATES, lines(MODEL_LOG_K), LOAD, frequencies, held, LY,
                              resolution) | {
        "measurement": {"plates": ["B1", "B2", "B3"], "spacing": 0.1, "noise": noise}}


def exact_field(frequency: float):
    """The exact panel, lines moving, weld W2.T2 at its true stiffness."""
    return folded_reference(PLATES, lines(TRUE_LOG_K), LOAD, frequency, False, LY, 800)


def best_solve(case, frequency: float, repeats: int = 3):
    """``(seconds, solution)``: the best processor time of ``repeats`` solves (the machine's
    noise is 10-20 %) and the last solution."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        solution = solve_assembly(case, frequency, residuals=False)
        times.append(time.process_time() - start)
    return min(times), solution


def peak_memory(case, frequency: float) -> float:
    """The peak of a solve's memory (MB), numpy's arrays traced."""
    tracemalloc.start()
    solve_assembly(case, frequency, residuals=False)
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    return peak


def cost(frequencies: list[float]) -> None:
    print("cost: one solve at resolution 1.5 (best of three), and to --tolerance 1e-3 "
          "(moving / held; processor time, one BLAS thread: other work on the machine does "
          "not count)")
    for frequency in frequencies:
        row = []
        for held in (False, True):
            case = parse_case(description([frequency], held))
            once, solution = best_solve(case, frequency)
            peak = peak_memory(case, frequency)
            start = time.process_time()
            _, estimate = solve_to_tolerance(case, frequency, 1e-3)
            row.append((once, time.process_time() - start, solution.n_unknowns, estimate.total,
                        peak))
        (m1, m2, mn, me, mp), (h1, h2, hn, he, hp) = row
        print(f"  {frequency:6.0f} Hz: solve {m1:.2f} / {h1:.2f} s ({m1 / h1:.1f}x; "
              f"{mn} / {hn} unknowns; peak memory {mp:.0f} / {hp:.0f} MB, {mp / hp:.1f}x); "
              f"to 1e-3 {m2:.2f} / {h2:.2f} s ({m2 / h2:.1f}x; estimates {me:.1e} / {he:.1e})")


def alternating(frequencies: list[float], pairs: dict[float, int]) -> None:
    """The two models' solves one after the other in one process, ``pairs[frequency]`` times:
    the ratio of their fastest and of their median processor times. A burst of other work on
    the machine then slows both models alike, where best-of-three runs of one model after the
    other gave ratios from 1.7x to 2.9x on a noisy machine (2026-11-28)."""
    print("cost, alternating: moving and held solves in turn at resolution 1.5 (processor "
          "time; fastest, median)")
    for frequency in frequencies:
        cases = {held: parse_case(description([frequency], held)) for held in (False, True)}
        times = {held: [] for held in cases}
        for case in cases.values():  # the first solve of a process also pays for its imports
            solve_assembly(case, frequency, residuals=False)
        for _ in range(pairs[frequency]):
            for held, case in cases.items():
                start = time.process_time()
                solve_assembly(case, frequency, residuals=False)
                times[held].append(time.process_time() - start)
        (m_min, m_med), (h_min, h_med) = ((min(t), float(np.median(t)))
                                          for t in times.values())
        print(f"  {frequency:6.0f} Hz, {pairs[frequency]} pairs: moving {m_min:.3f} / "
              f"{m_med:.3f} s, held {h_min:.3f} / {h_med:.3f} s: {m_min / h_min:.2f}x fastest, "
              f"{m_med / h_med:.2f}x median")


# The parts of a solve, by the function that builds each (cumulative time in a profile).
PARTS = {"bending blocks": "plate_admissibility", "in-plane blocks": "membrane_blocks",
         "line rows": "junction_line", "interface solve": "solve_interface"}


def parts(frequencies: list[float]) -> None:
    """Where one solve's time goes: the processor time of each part of the build
    (:data:`PARTS`) in a profiled solve, the best of three per part."""
    print("where one solve's time goes (resolution 1.5; processor time in a profile, best of "
          "three per part, the profile's overhead included)")
    for frequency in frequencies:
        for held in (False, True):
            case = parse_case(description([frequency], held))
            best = dict.fromkeys(["total", *PARTS], math.inf)
            for _ in range(3):
                profile = cProfile.Profile(time.process_time)
                profile.enable()
                solve_assembly(case, frequency, residuals=False)
                profile.disable()
                stats = pstats.Stats(profile).stats  # (file, line, name): (.., cumulative, ..)
                by_name = {}
                for (_, _, name), (*_, cumulative, _) in stats.items():
                    by_name[name] = by_name.get(name, 0.0) + cumulative
                best["total"] = min(best["total"], by_name["solve_assembly"])
                for part, function in PARTS.items():
                    best[part] = min(best[part], by_name.get(function, 0.0))
            print(f"  {frequency:6.0f} Hz {'held  ' if held else 'moving'}: "
                  + ", ".join(f"{part} {seconds:.2f} s" for part, seconds in best.items()))


def wider_panel(n_bays: int) -> tuple[dict, dict]:
    """The bench panel widened to ``n_bays`` bays: :data:`PLATES`' bays repeated, its two
    stiffeners alternating on the inner lines (so that a wide panel has two kinds of each, as
    a real one would), every weld at the model's stiffness."""
    plates, lines_of = {}, {}
    for i in range(1, n_bays + 1):
        right = "simply_supported" if i == n_bays else "free"
        plates[f"B{i}"] = (BAY, ((i - 1) * BAY, 0.0, 0.0), ALONG_X, 0.001, right)
    for i in range(1, n_bays):
        height, _, _, thickness, top = PLATES["T1" if i % 2 else "T2"]
        plates[f"T{i}"] = (height, (i * BAY, 0.0, 0.0), UP, thickness, top)
        lines_of[f"W{i}"] = {f"B{i}": ("right", math.inf), f"B{i + 1}": ("left", math.inf),
                             f"T{i}": ("left", MODEL_LOG_K)}
    return plates, lines_of


def wider(bays: list[int], frequency: float) -> None:
    """One solve of wider panels, moving and held: the cost ratio grows with the number of
    bays, because a held panel's bays are all alike (its blocks are shared) while each moving
    line has twice the interface unknowns of a held one and couples them densely."""
    print(f"wider panels at {frequency:.0f} Hz: one solve at resolution 1.5 (moving / held; "
          "processor time, best of three), unknowns (interface unknowns), peak memory of "
          "numpy's arrays")
    for n_bays in bays:
        plates, lines_of = wider_panel(n_bays)
        row = []
        for held in (False, True):
            case = parse_case(folded_description(plates, lines_of, LOAD, frequency, held, LY))
            seconds, solution = best_solve(case, frequency)
            row.append((seconds, solution.n_unknowns, solution.system.n_s,
                        peak_memory(case, frequency)))
        (mt, mn, ms, mp), (ht, hn, hs, hp) = row
        print(f"  {n_bays:2d} bays: {mt:.2f} / {ht:.2f} s ({mt / ht:.1f}x); {mn} ({ms}) / "
              f"{hn} ({hs}) unknowns; {mp:.0f} / {hp:.0f} MB ({mp / hp:.1f}x)")


def worst_error(solution, exact) -> float:
    """The worst plate's relative L2 error of ``w`` against the exact folded plate ``exact``, on
    each plate's 15 x 15 inner grid."""
    return max(np.linalg.norm(w - reference) / np.linalg.norm(reference)
               for name, w in folded_w(solution, PLATES, LY).items()
               for reference in [exact.w(name, *inner_grid(PLATES[name][0], LY).T)])


def same_accuracy(frequencies: list[float]) -> None:
    """Each model against its own exact solution (the exact folded plate with lines moving, or
    held), by resolution: the time of one solve and the worst plate's relative L2 error of w
    on a 15 x 15 grid, so that the two can be compared where their errors match."""
    print("at the same accuracy: one solve (processor time, best of three) and the worst "
          "plate's error of w against each model's exact solution")
    for frequency in frequencies:
        for held in (False, True):
            exact = folded_reference(PLATES, lines(MODEL_LOG_K), LOAD, frequency, held, LY, 800)
            cells = []
            for resolution in (1.0, 1.25, 1.5):
                seconds, solution = best_solve(
                    parse_case(description([frequency], held, resolution)), frequency)
                cells.append(f"{resolution}: {seconds:.2f} s, {worst_error(solution, exact):.1e}")
            print(f"  {frequency:6.0f} Hz {'held' if held else 'moving'}: " + "; ".join(cells))


def matched_accuracy(frequencies: list[float],
                     targets: tuple[float, ...] = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7),
                     rounds: dict[float, int] | None = None) -> None:
    """The cost at the same accuracy. Each model against its own exact solution at resolutions
    1 to 1.5 in steps of 0.05 (the worst plate's error of w, one solve each: the errors do not
    depend on the machine); per target, the smallest resolution of each model that reaches
    it; then the chosen solves timed in turn in one process, ``rounds[frequency]`` rounds
    (default 15 at 600 Hz, 7 above), and the ratio of their fastest and of their median
    processor times. Timed one model after the other (the fastest of five solves each, until
    2026-11-28), the ratios moved by up to 1.5x between runs on a busy machine; alternating,
    a burst of other work slows both models alike."""
    print("at the same accuracy: the smallest resolution in 1, 1.05, ..., 1.5 that reaches each "
          "target, moving / held, timed alternately (processor time; fastest, median)")
    resolutions = [round(1.0 + 0.05 * i, 2) for i in range(11)]
    for frequency in frequencies:
        picks = {}
        for held in (False, True):
            exact = folded_reference(PLATES, lines(MODEL_LOG_K), LOAD, frequency, held, LY, 800)
            errors = [(resolution, worst_error(solve_assembly(
                parse_case(description([frequency], held, resolution)), frequency,
                residuals=False), exact)) for resolution in resolutions]
            picks[held] = [next((r for r, e in errors if e <= target), None)
                           for target in targets]
        chosen = {(held, r) for held in picks for r in picks[held] if r is not None}
        cases = {key: parse_case(description([frequency], *key)) for key in sorted(chosen)}
        times = {key: [] for key in cases}
        for key, case in cases.items():  # the first solve of a process also pays for imports
            solve_assembly(case, frequency, residuals=False)
        for _ in range((rounds or {}).get(frequency, 15 if frequency < 1000.0 else 7)):
            for key, case in cases.items():
                start = time.process_time()
                solve_assembly(case, frequency, residuals=False)
                times[key].append(time.process_time() - start)
        cells = []
        for target, moving, held in zip(targets, picks[False], picks[True]):
            if moving is None or held is None:
                cells.append(f"{target:.0e}: not reached")
                continue
            m, h = times[False, moving], times[True, held]
            cells.append(f"{target:.0e}: {moving} / {held}, {min(m):.3f} / {min(h):.3f} s "
                         f"({min(m) / min(h):.2f}x; median {np.median(m) / np.median(h):.2f}x)")
        print(f"  {frequency:6.0f} Hz: " + "; ".join(cells), flush=True)


def identification(frequencies: list[float], seed: int) -> None:
    print(f"identification of W2.T2 (true {TRUE_LOG_K}, model {MODEL_LOG_K}) from the exact "
          "moving-line field on the skin, +-5 % noise")
    moving = parse_case(description(frequencies, False))
    rng = np.random.default_rng(seed)
    data = {}
    for frequency in frequencies:
        field = exact_field(frequency)
        data[frequency] = {}
        for plate in ("B1", "B2", "B3"):
            points = np.array([[x, y] for p, x, y in moving.measurement_points() if p == plate])
            data[frequency][plate] = (points, add_noise(field.w(plate, *points.T), 0.05, rng))
    measured = Measurements(data)
    for held in (False, True):
        case = parse_case(description(frequencies, held))
        start = time.perf_counter()
        result = update_case(case, measured)
        identified = result.parameters["W2.T2"]["log10_stiffness"]
        interval = result.intervals.get("W2.T2")
        shown = f"[{interval.low:.2f}, {interval.high:.2f}]" if interval else "none"
        print(f"  {'held' if held else 'moving'}: W2.T2 log10 k = {identified:.2f}, 90 % "
              f"interval {shown} ({interval.method if interval else ''}), W1.T1 "
              f"{result.parameters['W1.T1']['log10_stiffness']:.2f}, status {result.status} "
              f"({time.perf_counter() - start:.0f} s)")


def counted_solve(model: str, frequency: float) -> None:
    """One solve of ``model`` (``moving`` or ``held``) after a first, with valgrind's callgrind
    instrumenting the second alone (this process runs under it: :func:`instructions`)."""
    case = parse_case(description([frequency], model == "held"))
    solve_assembly(case, frequency, residuals=False)  # imports, first-use caches
    subprocess.run(["callgrind_control", "--instr=on", str(os.getpid())], check=True,
                   capture_output=True)
    solve_assembly(case, frequency, residuals=False)
    subprocess.run(["callgrind_control", "--instr=off", str(os.getpid())], check=True,
                   capture_output=True)


def instructions(frequency: float) -> None:
    """The instructions of one moving and one held solve at resolution 1.5, counted by
    valgrind's callgrind (both at once, a process each, string hashing seeded: about four
    minutes at 600 Hz, forty at 2500 Hz). A count repeats whatever else the machine does,
    where processor times move by 10 % from run to run on a shared machine: the yardstick for
    an A/B of a change, beside the times it does not replace."""
    if shutil.which("valgrind") is None:
        print("instructions: valgrind is not installed (Debian's package valgrind)")
        return
    runs = {model: subprocess.Popen(
        ["valgrind", "--tool=callgrind", "--instr-atstart=no", "--callgrind-out-file=/dev/null",
         sys.executable, __file__, "--counted-solve", model, str(frequency)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        env=os.environ | {"OPENBLAS_NUM_THREADS": "1", "PYTHONHASHSEED": "0"})
        for model in ("moving", "held")}
    counts = {}
    for model, run in runs.items():
        _, log = run.communicate()
        found = re.search(r"Collected : (\d+)", log)
        if run.returncode != 0 or found is None:
            print(f"instructions: the {model} run failed (exit {run.returncode})")
            return
        counts[model] = int(found.group(1))
    print(f"instructions of one solve at {frequency:.0f} Hz, resolution 1.5 (callgrind): moving "
          f"{counts['moving']:.4g}, held {counts['held']:.4g}: "
          f"{counts['moving'] / counts['held']:.2f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--matched", action="store_true",
                        help="only the cost at the same accuracy (matched_accuracy), five minutes")
    parser.add_argument("--instructions", type=float, metavar="HZ",
                        help="only the instructions of one solve of each model at HZ, counted by "
                             "valgrind's callgrind (instructions)")
    parser.add_argument("--counted-solve", nargs=2, metavar=("MODEL", "HZ"),
                        help=argparse.SUPPRESS)  # the inside of --instructions
    args = parser.parse_args()
    if args.counted_solve:
        counted_solve(args.counted_solve[0], float(args.counted_solve[1]))
        return
    if args.instructions:
        instructions(args.instructions)
        return
    if args.matched:
        matched_accuracy([600.0, 2500.0])
        return
    cost([600.0, 2500.0])
    alternating([600.0, 2500.0], {600.0: 25, 2500.0: 10})
    parts([600.0, 2500.0])
    same_accuracy([600.0, 2500.0])
    matched_accuracy([600.0, 2500.0])
    wider([3, 6, 12, 24], 2500.0)
    identification([600.0, 800.0, 1000.0], args.seed)


if __name__ == "__main__":
    main()
