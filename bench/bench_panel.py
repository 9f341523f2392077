"""vtcr on ``cases/stiffened_panel.toml`` (moving junction lines) against the independent
finite-element reference ``bench/fem_panel.py``: per plate, the relative L2 error of ``w`` and
of ``(u, v)`` against the finest FE level, vtcr's own estimate (``solver.estimate``) and the
ratio estimate / error, by resolution and frequency; then the held-line model (``held = true``
on W1..W3) against the same FE fields, to show how much the moving lines matter here.

Errors are relative L2 over the 225 points ``fem_folded.inner_grid(L_p, 0.4)`` of each plate
(15 x 15, 2 % in from the edges); vtcr's estimate is over the whole plate (its Gauss rule).
The case's model is solved (its ``[truth]`` is the updating's, left out here).

Run ``OPENBLAS_NUM_THREADS=1 python bench/fem_panel.py`` first (it saves the FE fields to
``/tmp/fem_panel/fields_panel_<freq>.npz``), then ``OPENBLAS_NUM_THREADS=1 python
bench/bench_panel.py [--resolutions 1.25 1.5 2.25 3.4]``. Measured: ``bench/README.md``.
"""

from __future__ import annotations

import argparse
import copy
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from fem_folded import relative  # noqa: E402

from assembly import parse_case  # noqa: E402
from solver.estimate import estimate_error  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

CASE = ROOT / "cases" / "stiffened_panel.toml"
FE_FIELDS = Path("/tmp/fem_panel")
RESOLUTIONS = (1.25, 1.5, 2.25, 3.4)


def description(resolution: float, held: bool = False) -> dict:
    """The case's toml as a dict at ``resolution``, its welds held if ``held``, no truth."""
    data = tomllib.loads(CASE.read_text())
    data = copy.deepcopy(data)
    data.pop("truth", None)
    data["discretisation"]["resolution"] = resolution
    for joint in data["joints"].values():
        joint["held"] = held
    return data


def fe_fields(frequency: float, level: int | None = None) -> dict:
    """The FE fields of ``fem_panel.save`` at ``frequency``: its finest level's, or
    ``level``'s (to see how the comparison depends on the reference)."""
    fe = dict(np.load(FE_FIELDS / f"fields_panel_{frequency:g}.npz"))
    if level is not None:
        for p in ("B1", "B2", "B3", "B4", "T1", "T2", "T3"):
            fe[f"w_{p}"], fe[f"uv_{p}"] = fe[f"w_{p}_n{level}"], fe[f"uv_{p}_n{level}"]
        fe["finest"] = level
    return fe


NEAR = 0.05  # m: points closer than this to a line are left out of the "away" error


def line_edges(case, plate: str) -> list[float]:
    """The local ``x`` of the plate's edges on a weld (left: 0, right: its length)."""
    length = case.plates[plate].size[0]
    edges = [e for joint in case.joints.values() for e in joint.between]
    return [0.0 if e.endswith(".left") else length
            for e in map(str, edges) if e.split(".")[0] == plate]


def errors(solution, fe: dict, case) -> dict[str, tuple[float, float, float]]:
    """``{plate: (error of w, error of (u, v), error of (u, v) at the points at least NEAR
    from the plate's lines)}`` of ``solution`` against the FE fields."""
    out = {}
    for p in case.plates:
        points = fe[f"points_{p}"]
        w = solution.plates[p].field(points)["w"]
        uv = solution.in_plane(p, points)
        away = np.min([np.abs(points[:, 0] - x) for x in line_edges(case, p)], axis=0) >= NEAR
        out[p] = (relative(w, fe[f"w_{p}"]), relative(uv, fe[f"uv_{p}"]),
                  relative(uv[away], fe[f"uv_{p}"][away]))
    return out


FRAMES = {"skin": np.eye(3), "stiffener": np.array([[0, 0, 1.0], [0, 1.0, 0], [-1.0, 0, 0]])}
"""Rows ``e_x, e_y, e_z`` (the toml's frames: bays in the x-y plane, stiffeners along +z)."""


def tie_mismatch(solution, case, n: int = 201) -> dict[str, float]:
    """vtcr's own ties, per weld: the largest 3D displacement difference between a member
    and the first along the weld (``n`` points), relative to the largest 3D displacement of
    the pair on the weld (the line's own, often far below the plates' field)."""
    y = np.linspace(0.0, 0.4, n)
    out = {}
    for name, joint in case.joints.items():
        sides = []
        for edge in map(str, joint.between):
            plate, side = edge.split(".")
            x = 0.0 if side == "left" else case.plates[plate].size[0]
            points = np.column_stack([np.full(n, x), y])
            uvw = np.column_stack([solution.in_plane(plate, points),
                                   solution.plates[plate].field(points)["w"]])
            sides.append(uvw @ FRAMES["skin" if plate.startswith("B") else "stiffener"])
        worst = 0.0
        for other in sides[1:]:
            d = np.linalg.norm(other - sides[0], axis=1).max()
            scale = max(np.linalg.norm(s, axis=1).max() for s in (sides[0], other))
            worst = max(worst, d / scale)
        out[name] = worst
    return out


def compare(frequency: float, resolution: float, fe: dict, held: bool = False,
            estimate: bool = True) -> None:
    """One solve against the FE: a row per plate, and the worst plate."""
    case = parse_case(description(resolution, held))
    plates = list(case.plates)
    t0 = time.perf_counter()
    solution = solve_assembly(case, frequency, residuals=False)
    t_solve = time.perf_counter() - t0
    found = errors(solution, fe, case)
    est = estimate_error(case, solution) if estimate else None
    label = "held" if held else "moving"
    print(f"\n{frequency:g} Hz, resolution {resolution:g}, {label} lines: solve {t_solve:.1f} s"
          + (f", estimate {est.seconds:.1f} s" if est else "")
          + ("" if held else "; its ties (3D) " + ", ".join(
              f"{k} {v:.1e}" for k, v in tie_mismatch(solution, case).items())))
    print(f"  {'plate':5} {'err w':>8} {'err uv':>8} {'uv away':>8}" + (
        f" {'est w':>8} {'est uv':>8} {'est/err w':>9} {'est/err uv':>10}" if est else ""))
    for p in plates:
        w, uv, away = found[p]
        row = f"  {p:5} {w:8.1e} {uv:8.1e} {away:8.1e}"
        if est:
            ew, euv = est.plates[p], est.in_plane.get(p, float("nan"))
            row += f" {ew:8.1e} {euv:8.1e} {ew / w:9.2f} {euv / uv:10.2f}"
        print(row)
    worst = [max(plates, key=lambda p: found[p][i]) for i in range(3)]
    print(f"  worst: w {worst[0]} {found[worst[0]][0]:.1e}, (u, v) {worst[1]} "
          f"{found[worst[1]][1]:.1e}, (u, v) away from the lines {worst[2]} "
          f"{found[worst[2]][2]:.1e}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--resolutions", type=float, nargs="+", default=list(RESOLUTIONS))
    parser.add_argument("--frequencies", type=float, nargs="+",
                        default=tomllib.loads(CASE.read_text())["frequencies"])
    parser.add_argument("--held-resolution", type=float, default=2.25)
    parser.add_argument("--fe-level", type=int, default=None,
                        help="compare with this saved FE level instead of the finest")
    args = parser.parse_args()
    for frequency in args.frequencies:
        fe = fe_fields(frequency, args.fe_level)
        print(f"\n=== {frequency:g} Hz: FE level {int(fe['finest'])} (levels "
              f"{[int(n) for n in fe['levels']]}); the finest's last change per plate, w | (u, v): "
              + ", ".join(f"{p} {float(fe[f'change_w_{p}']):.1e}|"
                          f"{float(fe[f'change_uv_{p}']):.1e}"
                          for p in ("B1", "B2", "B3", "B4", "T1", "T2", "T3")))
        for resolution in args.resolutions:
            compare(frequency, resolution, fe)
        compare(frequency, args.held_resolution, fe, held=True, estimate=False)


if __name__ == "__main__":
    main()
