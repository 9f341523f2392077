r"""VTCR against finite elements on moving-line folds and junctions, at the same accuracy.

Structures of ``tests/test_moving_lines.py``, 1 N on the first plate, at 300, 1000 and
3000 Hz:

* ``L``: the L fold, 2 mm steel, plates A (0.4 m) and B (0.3 m), both 0.5 m long, a rigid
  fold free in translation, far edges simply supported and fixed in plane, shear-diaphragm
  ends;
* ``T``: the T junction, a 1 mm skin of S1 (0.4 m) and S2 (0.35 m) with a 2 mm stiffener T1
  (0.1 m, its top free) on a rotational spring of log10 k = 2.5, the line free in
  translation, shear-diaphragm ends;
* ``L-mixed``: the L fold with mixed ends (simply supported, in-plane rollers), moved with
  ``held = false`` (its line's loads log-singular at its ends; ``docs/method.md`` section
  10.4), at 300 and 1000 Hz only.

The error is the relative L2 error of ``w`` over 15 x 15 interior points of each plate, the
worst plate's, against the exact prismatic solution (``tests/support.folded_reference``, 600
harmonics), or for ``L-mixed``, which has none, against the finest finite elements of
``tests/data/fem_fold_mixed_ends.npz`` (``fem_folded.py`` level 8, about 3e-8 from the truth,
far below the errors compared).

* **VTCR**: ``solver.solve_case``, the field alone, at each of ``--resolutions``.
* **Finite elements** (``bench/fem_folded.py`` and ``bench/fem_junction.py``, written apart
  from the solver: Argyris ``w``, P5 ``(u, v)``, the line exact through master-slave
  relations): the cheapest mesh whose error is at most the VTCR's. The search covers squares
  of side ``0.05 / n``, ``n = 0.5, 1, 1.5, ...`` up to ``--max-density`` (for the T, at
  ``n`` not an integer, near-squares that keep the line and T1's top on the grid:
  ``fem_junction.segment_mesh``). Each bending
  mesh is either uniform or graded towards the force (:data:`MESHES`). With diaphragm ends
  the fields are smooth where the line meets the ends, so the references' grading there is
  left out; with mixed ends they are not, and the reference's family, graded towards the
  force and the line's ends, is tried beside the force-graded mesh. At integer ``n`` the T
  keeps its reference's coarser membrane cells (up to four times coarser away from the line,
  at even ``n``), graded towards the line; the L, and the T at other ``n``, carry ``(u, v)``
  on the bending grid, as the L's reference does. The search stops at the first density
  where a mesh meets the finest VTCR error. Their time is the set-up (mesh, bases, matrices,
  constraints) plus the solve (SuperLU). The solve alone is what a sweep pays per frequency
  once the matrices are built; it is printed too.

Every measurement runs in a process of its own, with one BLAS thread, and times the first
solve of its process: the VTCR's, as the finite elements', pays what a process does once
(caches, the first call of each kernel). ``bench_scale.Runner``'s small launcher starts it
and reads its peak memory (``os.wait4``'s ``ru_maxrss``, MB), printed above the peak of a
process that imports what that measurement imports and does nothing else.

``OPENBLAS_NUM_THREADS=1 python bench/bench_fold_fe.py`` (about twenty minutes).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TIMEOUT = 600.0  # s, for one measured process
FREQUENCIES = (300.0, 1000.0, 3000.0)
RESOLUTIONS = (1.0, 1.25)
ENDS = {"L": "diaphragm", "T": "diaphragm", "L-mixed": "roller"}
"""Each structure's ends (``tests/support.FOLD_ENDS``, ``fem_folded.ENDS``)."""


# ---------------------------------------------------------------------------------------------
# The measured processes (``--child KIND ...``): each prints one JSON line
# ---------------------------------------------------------------------------------------------
STRUCTURES = ("L", "T", "L-mixed")
DENSITY_STEP = 0.5  # the step of the density n of the meshes (cells of 0.05 / n m)
MAX_DENSITY = {"L": 3.0, "T": 4.0, "L-mixed": 3.0}  # the T's thinner skin has shorter waves
MESHES = {"L": ("uniform", "force"), "T": ("uniform", "force"),
          "L-mixed": ("force", "force and ends")}
"""The finite-element meshes tried at each density: uniform, graded towards the force, or
towards the force and the line's ends (the reference's family, for the log-singular fields of
mixed ends)."""
MIXED_REFERENCE = ROOT / "tests" / "data" / "fem_fold_mixed_ends.npz"
MIXED_FREQUENCIES = (300.0, 1000.0)  # those of MIXED_REFERENCE


def _references(structure: str):
    """The finite-element module of ``structure`` and the structure as
    ``tests/test_moving_lines.py`` describes it (``(plates, lines, load)``)."""
    sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "bench")]
    if structure != "T":
        import fem_folded
        return fem_folded, fem_folded.L_FOLD
    import fem_junction
    from test_moving_lines import T_JUNCTION
    return fem_junction, T_JUNCTION


def _errors(fem, w: dict, workdir: Path, structure: str, frequency: float) -> dict[str, float]:
    """Relative L2 error of ``w`` on each plate against the saved exact field."""
    import numpy as np
    exact = np.load(workdir / f"exact_{structure}_{frequency:g}.npz")
    return {plate: float(np.linalg.norm(w[plate] - exact[plate]) / np.linalg.norm(exact[plate]))
            for plate in fem.LENGTHS}


def child_reference(structure: str, frequency: float, workdir: Path) -> dict:
    """The reference ``w`` at the points of comparison, saved for the other children: the exact
    prismatic solution, or for the mixed ends the finest finite elements of
    :data:`MIXED_REFERENCE` (``fem_folded.py`` level 8, within about 3e-8 of the truth)."""
    import numpy as np
    fem, _ = _references(structure)
    if structure == "L":
        w, _ = fem.exact_fields(frequency, ENDS[structure])
    elif structure == "L-mixed":
        fields = np.load(MIXED_REFERENCE)
        w = {plate: fields[f"w_{plate}_{frequency:g}"] for plate in fem.LENGTHS}
    else:
        fields = fem.exact_fields(frequency, "free")
        w = {plate: fields[f"w_{plate}"] for plate in fem.LENGTHS}
    np.savez(workdir / f"exact_{structure}_{frequency:g}.npz", **w)
    return {}


def _vtcr_imports():
    """What a VTCR child imports besides its structure: ``(folded_description, parse_case,
    solve_case)``."""
    from support import folded_description

    from assembly import parse_case
    from solver import solve_case
    return folded_description, parse_case, solve_case


def child_vtcr(structure: str, frequency: float, resolution: float, workdir: Path) -> dict:
    """One VTCR solve, the first of its process as the finite elements' is, and its errors."""
    fem, shape = _references(structure)
    folded_description, parse_case, solve_case = _vtcr_imports()
    # held = false: the mixed ends (simply supported, in-plane rollers) move only when asked
    case = parse_case(folded_description(*shape, frequency, False, fem.LY, resolution,
                                         ends=ENDS[structure]))
    start = time.process_time()
    solution = solve_case(case, frequency, residuals=False)
    seconds = time.process_time() - start
    w = {plate: solution.w(plate, fem.inner_grid(length)) for plate, length in fem.LENGTHS.items()}
    return {"seconds": seconds, "unknowns": solution.n_unknowns,
            "errors": _errors(fem, w, workdir, structure, frequency)}


def child_fem(structure: str, frequency: float, density: float, mesh: str,
              workdir: Path) -> dict:
    """One finite-element set-up and solve on squares of ``0.05 / density`` m, graded as
    ``mesh`` (:data:`MESHES`) says, and its errors."""
    fem, _ = _references(structure)
    start = time.process_time()
    if structure == "T":
        model = fem.JunctionModel(density, "load" if mesh == "force" else "none")
        constraints = (model.reduced(ENDS[structure], "free"),)
    else:
        level = (fem.MeshLevel.of(density) if mesh == "force and ends"
                 else fem.MeshLevel.plain(density, mesh == "force"))
        model = fem.FoldModel(level, ENDS[structure])
        constraints = ()
    setup = time.process_time() - start
    start = time.process_time()
    x = model.solve(frequency, *constraints)
    solve = time.process_time() - start
    if structure == "T":
        w, _ = model.fields(x)
    else:
        w = {name: plate.values(part, fem.inner_grid(plate.length))["w"]
             for name, (plate, part) in model.plate_parts(x).items()}
    dofs = constraints[0].shape[1] if constraints else model.n_dofs
    return {"setup": setup, "solve": solve, "dofs": dofs,
            "errors": _errors(fem, w, workdir, structure, frequency)}


def child_imports(structure: str, side: str) -> dict:
    """Import what a child of ``side`` on ``structure`` imports, and nothing else: the floor of
    its peak memory (the VTCR side reads the structure's geometry and points of comparison
    through :func:`_references` too)."""
    _references(structure)
    if side == "vtcr":
        _vtcr_imports()
    return {}


def run_child(argv: list[str]) -> None:
    kind, *args = argv
    if kind == "reference":
        result = child_reference(args[0], float(args[1]), Path(args[2]))
    elif kind == "vtcr":
        result = child_vtcr(args[0], float(args[1]), float(args[2]), Path(args[3]))
    elif kind == "fem":
        result = child_fem(args[0], float(args[1]), float(args[2]), args[3], Path(args[4]))
    else:
        result = child_imports(args[0], args[1])
    print(json.dumps(result))


# ---------------------------------------------------------------------------------------------
# The bench
# ---------------------------------------------------------------------------------------------
def measure(runner, *args: object) -> dict:
    """Run ``--child args`` in a fresh process with one BLAS thread, through ``runner``
    (``bench_scale.Runner``: a small launcher process starts it, so that its peak memory does
    not start from this process's): its JSON result, with its peak memory ``peak_mb``."""
    run = runner.run([sys.executable, str(Path(__file__).resolve()), "--child",
                      *map(str, args)])
    if not run.ok:
        raise SystemExit(f"the measured process {' '.join(map(str, args))} failed: "
                         f"{run.brief()}")
    return json.loads(run.stdout.strip().splitlines()[-1]) | {"peak_mb": run.peak_mb}


def densities(step: float, largest: float) -> list[float]:
    """``step, 2 step, ...`` up to ``largest``."""
    return [k * step for k in range(1, int(largest / step) + 1)]


def worst(run: dict) -> float:
    return max(run["errors"].values())


def cheapest_meeting(runs: list[dict], target: float) -> dict | None:
    """The finite-element run of least set-up and solve time whose error is at most
    ``target``, if any."""
    meeting = [run for run in runs if worst(run) <= target]
    return min(meeting, key=lambda run: run["setup"] + run["solve"]) if meeting else None


def mesh_name(run: dict) -> str:
    return f"n = {run['density']:g}, {run['mesh']}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--structures", nargs="+", choices=STRUCTURES, default=list(STRUCTURES))
    parser.add_argument("--frequencies", type=float, nargs="+", default=list(FREQUENCIES))
    parser.add_argument("--resolutions", type=float, nargs="+", default=list(RESOLUTIONS))
    parser.add_argument("--max-density", type=float,
                        help="finest finite-element mesh tried: squares of 0.05 / n m "
                             "(default 3 for the L and L-mixed, 4 for the T)")
    args = parser.parse_args()
    if args.max_density is not None and not DENSITY_STEP <= args.max_density < 100:
        parser.error(f"--max-density must be at least {DENSITY_STEP:g} (and below 100)")

    from bench_scale import Runner, machine  # the measured processes, the run's conditions

    print(", ".join(f"{key} {value}" for key, value in machine().items()))
    with tempfile.TemporaryDirectory() as directory:
        runner = Runner(Path(directory), TIMEOUT)
        try:
            compare(runner, directory, args)
        finally:
            runner.close()


def compare(runner, directory: str, args: argparse.Namespace) -> None:
    """The imports' floors, then per structure and frequency a table row per resolution; last,
    every finite-element mesh tried."""
    floor = {(structure, side): measure(runner, "imports", structure, side)["peak_mb"]
             for structure in args.structures for side in ("vtcr", "fem")}
    print("peak memory of the imports alone (the columns below are above these): "
          + ", ".join(f"{structure} {side} {peak:.0f} MB"
                      for (structure, side), peak in floor.items()))
    print("| structure | f [Hz] | VTCR resolution | VTCR error | unknowns | time [s] "
          "| memory [MB] | FE mesh | FE error | FE unknowns | set-up + solve [s] | solve [s] "
          "| memory [MB] | time ratio (solve alone) | memory ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    searches = []
    for structure in args.structures:
        for frequency in args.frequencies:
            if structure == "L-mixed" and frequency not in MIXED_FREQUENCIES:
                searches.append(f"L-mixed at {frequency:g} Hz: skipped, its reference is at "
                                "300 and 1000 Hz only")
                continue
            measure(runner, "reference", structure, frequency, directory)
            vtcr = {r: measure(runner, "vtcr", structure, frequency, r, directory)
                    for r in args.resolutions}
            fem_runs = fem_search(runner, directory, structure, frequency,
                                  min(worst(run) for run in vtcr.values()),
                                  args.max_density or MAX_DENSITY[structure])
            searches.append(f"{structure} at {frequency:g} Hz: " + "; ".join(
                f"{mesh_name(run)} {worst(run):.1e} ({run['dofs']}, "
                f"{run['setup'] + run['solve']:.2f} s)" for run in fem_runs))
            for resolution, run in vtcr.items():
                print(row(f"| {structure} | {frequency:g} | {resolution:g} ", run, fem_runs,
                          floor[structure, "vtcr"], floor[structure, "fem"]), flush=True)
    print("\nthe finite-element meshes tried (error, unknowns, set-up and solve):")
    for line in searches:
        print(f"  {line}")


def fem_search(runner, directory: str, structure: str, frequency: float, target: float,
               largest: float) -> list[dict]:
    """The finite-element runs of :data:`MESHES` at each density up to ``largest``, until one
    meets ``target`` (a graded mesh only where its grading refines something)."""
    runs = []
    for density in densities(DENSITY_STEP, largest):
        coarse, fine = [measure(runner, "fem", structure, frequency, density, mesh, directory)
                        | {"density": density, "mesh": mesh} for mesh in MESHES[structure]]
        runs.append(coarse)
        if fine["dofs"] != coarse["dofs"]:  # else the grading refined nothing
            runs.append(fine)
        if min(worst(coarse), worst(fine)) <= target:
            break
    return runs


def row(start: str, vtcr: dict, fem_runs: list[dict], vtcr_floor: float,
        fem_floor: float) -> str:
    """One line of the table after ``start``: a VTCR run and the cheapest finite-element run as
    accurate, their peak memory above the floors of their imports."""
    memory = vtcr["peak_mb"] - vtcr_floor
    left = (f"{start}| {worst(vtcr):.1e} | {vtcr['unknowns']} | {vtcr['seconds']:.3f} "
            f"| {memory:.0f} ")
    fem = cheapest_meeting(fem_runs, worst(vtcr))
    mesh = "" if fem else f"not reached by n = {fem_runs[-1]['density']:g}; the best: "
    fem = fem or min(fem_runs, key=worst)  # then slower and still less accurate
    total = fem["setup"] + fem["solve"]
    fem_memory = fem["peak_mb"] - fem_floor
    return left + (f"| {mesh}{mesh_name(fem)} | {worst(fem):.1e} | {fem['dofs']} "
                   f"| {total:.2f} | {fem['solve']:.2f} | {fem_memory:.0f} "
                   f"| {total / vtcr['seconds']:.0f}x ({fem['solve'] / vtcr['seconds']:.0f}x) "
                   f"| {fem_memory / max(memory, 1.0):.0f}x |")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        run_child(sys.argv[2:])
    else:
        main()
