"""How well ``vtcr check`` foresees a solve's time: the estimate of ``solver.sizing`` against
the measured time, on the cases its plate constants were fitted to.

For each case, at the frequency given: the orders of the dense matrices the build factorises
(bending + in-plane, one per group of identical plates), the plate blocks' time of one solve
(``timings["plates"]``) and the whole solve's (plates, interface rows, interface solve;
processor time, best of three) against ``SizeEstimate.plate_seconds`` and ``solve_seconds``;
and the solve's peak memory above the start-up (numpy's arrays, traced) against
``solve_bytes`` less ``START_UP_BYTES``, with the build's part ``build_bytes``.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_sizing.py`` (about a minute).
"""

from __future__ import annotations

import sys
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "bench")]

import bench_moving_lines as panel  # noqa: E402
from support import folded_description  # noqa: E402
from test_moving_lines import LY, SHAPES  # noqa: E402

from assembly import load_case, parse_case  # noqa: E402
from assembly.generate import plate_grid  # noqa: E402
from solver.sizing import START_UP_BYTES, estimate_size  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402


def cases():
    """``(label, case, frequency)``: every case of ``cases/`` at its highest frequency, a few
    at higher ones, two grids, the L fold and the T junction of ``tests/test_moving_lines.py``
    with mixed ends moved (``simply_supported`` + ``roller``, ``held = false``: the rule of
    ``docs/method.md`` section 10.4, not in the fit), and the stiffened panel of
    ``bench_moving_lines.py``, moving and held, widened to 6 and 12 bays."""
    for path in sorted((ROOT / "cases").glob("*.toml")):
        case = load_case(path)
        yield path.stem, case, max(case.frequencies)
    yield "single_plate", load_case(ROOT / "cases" / "single_plate.toml"), 1000.0
    yield "single_plate", load_case(ROOT / "cases" / "single_plate.toml"), 3000.0
    yield "four_plates", load_case(ROOT / "cases" / "four_plates.toml"), 2000.0
    for n in (4, 6):
        case = parse_case(plate_grid(n, n))
        yield f"grid {n} x {n}", case, max(case.frequencies)
    for frequency in (600.0, 2500.0):
        for held in (False, True):
            yield (f"panel, {'held' if held else 'moving'}",
                   parse_case(panel.description([frequency], held)), frequency)
    for shape, frequency in (("L", 300.0), ("L", 1000.0), ("T", 1000.0), ("T", 3000.0)):
        description = folded_description(*SHAPES[shape], frequency, False, LY, 1.5,
                                         ends="roller")
        yield f"{shape}, mixed ends moved", parse_case(description), frequency
    for bays in (6, 12):
        plates, lines = panel.wider_panel(bays)
        for held in (False, True):
            yield (f"panel of {bays} bays, {'held' if held else 'moving'}",
                   parse_case(folded_description(plates, lines, panel.LOAD, 2500.0, held,
                                                 panel.LY)), 2500.0)


def main() -> None:
    print(f"{'case':30} {'f [Hz]':>7} {'plates':>6} {'orders':>14} {'plates [s]':>17} "
          f"{'solve [s]':>17} {'peak above start-up':>32}   (measured / estimated, then "
          "estimated / measured)")
    ratios = []
    for label, case, frequency in cases():
        size = estimate_size(case, frequency)
        plates = solve = float("inf")
        for _ in range(3):
            start = time.process_time()
            solution = solve_assembly(case, frequency, residuals=False)
            solve = min(solve, time.process_time() - start)
            plates = min(plates, solution.timings["plates"])
        tracemalloc.start()
        solve_assembly(case, frequency, residuals=False)
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        memory = (size.solve_bytes - START_UP_BYTES) / 1e6
        bending, in_plane = size.factorised
        ratios.append((size.plate_seconds / plates, size.solve_seconds / solve, memory / peak))
        print(f"{label:30} {frequency:7.0f} {len(case.plates):6d} "
              f"{f'{len(bending)}+{len(in_plane)}, max {max(bending + in_plane)}':>14} "
              f"{plates:6.3f} / {size.plate_seconds:5.3f} {ratios[-1][0]:4.2f} "
              f"{solve:6.3f} / {size.solve_seconds:5.3f} {ratios[-1][1]:4.2f} "
              f"{peak:5.0f} / {memory:5.0f} MB (build {size.build_bytes / 1e6:4.0f}) "
              f"{ratios[-1][2]:4.2f}", flush=True)
    for name, column in (("plates", 0), ("solve", 1), ("memory", 2)):
        values = [ratio[column] for ratio in ratios]
        print(f"estimate / measured, {name}: {min(values):.2f} to {max(values):.2f}")


if __name__ == "__main__":
    main()
