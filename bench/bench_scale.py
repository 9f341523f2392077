"""Scaling of vtcr on N x N grids of plates, and the stiff grid against Argyris finite elements.

For each N in ``--sizes`` the bench generates (``assembly.generate.plate_grid``) the N x N grid
of steel plates 0.5 x 0.4 m, h = 1 mm, eta = 0.01, outer edges simply supported, 1 N in P1_1 at
(0.17, 0.13), every joint modelled at log10 k = 2 and three of them wrong in the simulated
experiment, and measures:

1. ``vtcr check | solve | localise | update`` on it, each a separate process
   (``python -m updating``, one BLAS thread): wall time and peak memory (max RSS), with the
   plates, joints, ray and interface unknowns; ``localise`` and ``update`` simulate their
   measurements themselves (no ``--measurements``), and their times include that simulation;
2. the growth exponents of the time and memory of ``solve`` and ``localise`` against the
   number of plates P, fitted over the sizes N >= 4;
3. one cost evaluation during a correction (``ModifiedProblem.correction(...).cost``, else a
   full ``ModifiedProblem.cost``), in a process of its own: median over values of log10 k
   spread over the bounds, and the one-off set-up of the correction;
4. the same (commands, exponents, one evaluation) on stiffened panels of ``--panels`` bays
   (``assembly.generate.stiffened_panel``: a skin of n bays 0.5 x 0.4 m with a 2 mm, 0.15 m
   stiffener welded on each inner bay line, 2n - 1 plates and n - 1 junction lines, model weld
   log10 k = 3.5, three welds wrong), so that bays and stiffeners grow together; exponents
   fitted over n >= 8;
5. the stiff grid (every joint log10 k = 6: one simply supported (0.5 N) x (0.4 N) m plate)
   solved by the VTCR and by scikit-fem's Argyris element at the same accuracy: the VTCR
   error against the Navier series is the target of the coarsest accurate near-square mesh.
   Timed on both sides, best of ``--repeats`` in a process of its own: the VTCR's end-to-end
   ``solver.solve_case`` and the FE's mesh, basis, matrices, load, constraints and sparse LU
   (``fem_argyris.solve_fem``); evaluating w at the points is timed for neither.

Run: ``pip install -e '.[bench]' && python bench/bench_scale.py [--sizes 2 3 4 6 8 10]``
(about 16 min with the defaults; ``--sizes 2 3 --fem-sizes 2 --panels 4`` in about half a
minute).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

THREADS = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
os.environ.update(THREADS)  # before numpy loads, in this process and (inherited) its children

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench"), str(ROOT / "tests")]

COMMANDS = ("check", "solve", "localise", "update")
FIT_FROM = 4  # the growth exponents are fitted over the sizes N >= FIT_FROM
STIFF_LOG10_K = 6.0  # practically rigid: D kappa is about 1e3 N at 250 Hz
CORRECTED_JOINT = "H1_1"  # the joint of the loaded plate P1_1 whose correction is timed
PANEL_FIT_FROM = 8  # the panels' growth exponents are fitted over n >= PANEL_FIT_FROM bays
PANEL_WELD_LOG10_K = 3.5  # the model's welds (as cases/stiffened_panel.toml)
PANEL_CORRECTED_JOINT = "W1.T1"  # the weld next to the loaded bay, whose correction is timed
PROBE_FRACTIONS = (np.arange(4) + 0.5) / 4  # 4 x 4 interior points per plate (plate-local)
NAVIER_TERMS_PER_PLATE = 160  # Navier terms each way per plate of the grid's side
COARSE_STEP, FINE_STEP = 0.25, 0.02  # FE mesh search: intervals per bending wavelength


# ---------------------------------------------------------------------------------------------
# Cases
# ---------------------------------------------------------------------------------------------


def wrong_joints(n):
    """``{joint: true log10 k}`` of the simulated experiment on the n x n grid (model: 2.0).

    The first horizontal joint (on the loaded plate), the vertical joint above the loaded
    plate, and a horizontal joint mid-grid (``H1_2`` on the 2 x 2 grid, which has no other).
    """
    middle = max(2, (n + 1) // 2)
    return {"H1_1": 0.5, "V1_1": 4.0, f"H{min(middle, n - 1)}_{middle}": 3.5}


def _with_misfit(description, misfit):
    """``description`` with ``[updating] misfit`` set, or the generators' default (the
    per-plate misfit of the scale-free weights) for None."""
    if misfit is not None:
        description["updating"] = {**description["updating"], "misfit": misfit}
    return description


def write_cases(n, frequency, stiff_frequency, directory, misfit=None):
    """Write the n x n grid with wrong joints (its ``[updating] misfit`` set when given) and
    the stiff grid; return their paths."""
    from assembly.generate import description_toml, plate_grid

    grid = directory / f"grid_{n}x{n}.toml"
    grid.write_text(description_toml(
        _with_misfit(plate_grid(n, n, frequency=frequency, truth=wrong_joints(n)), misfit),
        header=f"bench_scale.py: {n} x {n} grid, wrong joints {wrong_joints(n)}"))
    stiff = directory / f"stiff_{n}x{n}.toml"
    stiff.write_text(description_toml(
        plate_grid(n, n, frequency=stiff_frequency, log10_stiffness=STIFF_LOG10_K),
        header=f"bench_scale.py: {n} x {n} grid, every joint log10 k = {STIFF_LOG10_K}"))
    return grid, stiff


def wrong_welds(n):
    """``{weld: true log10 k of its stiffener}`` of the n-bay panel (model: 3.5): the weld
    next to the loaded bay, one mid-panel and the last (one weld for 2 and 3 bays)."""
    return {f"W{i}": 2.0 for i in sorted({1, max(1, n // 2), n - 1})}


def write_panel(n, frequency, directory, misfit=None):
    """Write the n-bay stiffened panel with wrong welds; return its path."""
    from assembly.generate import description_toml, stiffened_panel

    panel = directory / f"panel_{n}.toml"
    panel.write_text(description_toml(
        _with_misfit(stiffened_panel(n, log10_stiffness=PANEL_WELD_LOG10_K,
                                     truth=wrong_welds(n), frequency=frequency), misfit),
        header=f"bench_scale.py: {n}-bay stiffened panel, wrong welds {wrong_welds(n)}"))
    return panel


def problem_size(case):
    """Plates, joints, ray and interface unknowns of a case, counted from its description."""
    from solver.sizing import estimate_size

    size = estimate_size(case)
    return {"plates": size.plates, "joints": size.joints, "ray_unknowns": size.ray_unknowns,
            "interface_unknowns": size.interface_unknowns}


def probe_points(case):
    """The stiff grid's evaluation points: ``({plate: local points}, global points (n, 2))``.

    Every plate gets the same interior grid (:data:`PROBE_FRACTIONS` of its sides); the global
    points follow the plates' order and origins.
    """
    local = {}
    for pid, plate in case.plates.items():
        x, y = np.meshgrid(PROBE_FRACTIONS * plate.size[0], PROBE_FRACTIONS * plate.size[1])
        local[pid] = np.column_stack([x.ravel(), y.ravel()])
    return local, np.vstack([local[pid] + np.asarray(plate.origin, dtype=float)
                             for pid, plate in case.plates.items()])


def single_plate(case):
    """The single simply supported plate that the stiff grid ``case`` stands for.

    Returns keyword arguments of ``fem_argyris.solve_fem`` (all but the points and the mesh).
    """
    plates = list(case.plates.values())
    materials = {(p.material, p.thickness) for p in plates}
    if len(materials) != 1 or len(case.loads) != 1:
        raise ValueError("the stiff grid must have one material, one thickness and one load")
    material = case.materials[plates[0].material]
    corners = np.array([[p.origin[0] + p.size[0], p.origin[1] + p.size[1]] for p in plates])
    load = case.loads[0]
    origin = case.plates[load.plate].origin
    return {"Lx": float(corners[:, 0].max()), "Ly": float(corners[:, 1].max()),
            "E": material.young_modulus, "nu": material.poisson_ratio, "rho": material.density,
            "h": plates[0].thickness, "eta": material.loss_factor,
            "frequency": case.frequencies[0],
            "force_at": (origin[0] + load.at[0], origin[1] + load.at[1]),
            "force": complex(load.amplitude).real}


def navier(plate, points, n_terms):
    """Navier series of the single plate at ``points`` with ``n_terms`` terms each way."""
    from exact import complex_rigidity, navier_point_force

    d = complex_rigidity(plate["E"], plate["h"], plate["nu"], plate["eta"])
    return navier_point_force(plate["Lx"], plate["Ly"], d, plate["rho"] * plate["h"],
                              2 * np.pi * plate["frequency"], *plate["force_at"],
                              plate["force"], points[:, 0], points[:, 1], n_terms=n_terms)


# ---------------------------------------------------------------------------------------------
# Measured subprocesses
# ---------------------------------------------------------------------------------------------


@dataclass
class Measured:
    """One subprocess: wall time (s), peak memory (MB, max RSS) and outcome.

    ``status`` is ``"ok"``, ``"timeout"`` or ``"exit CODE"`` (negative: killed by that signal);
    ``detail`` the last line of its standard error when it failed.
    """

    seconds: float
    peak_mb: float
    status: str
    detail: str = ""
    stdout: str = field(default="", repr=False)

    @property
    def ok(self):
        """Whether the process finished with exit status 0."""
        return self.status == "ok"

    def record(self):
        """The measurement as a dictionary for the JSON output (without the output)."""
        return {"wall_s": self.seconds, "peak_mb": self.peak_mb, "status": self.status,
                "detail": self.detail}

    def brief(self):
        """One line for the progress log."""
        return (f"{self.status}, {self.seconds:.2f} s, {self.peak_mb:.0f} MB"
                + (f" ({self.detail})" if self.detail else ""))


#: The launcher's program: for each request (one JSON line on standard input), run ``argv``
#: in ``cwd`` with its output in the files ``stdout`` and ``stderr``, time it with
#: ``time.perf_counter`` around ``Popen`` and ``os.wait4``, kill it after ``timeout`` seconds
#: (waiting on a pidfd; the process is not reaped yet, so its pid is still its own), and
#: answer one JSON line with the time, the exit status and ``ru_maxrss`` (KiB on Linux).
LAUNCHER = r"""
import json, os, select, subprocess, sys, time
for line in sys.stdin:
    request = json.loads(line)
    with open(request["stdout"], "wb") as out, open(request["stderr"], "wb") as err:
        start = time.perf_counter()
        proc = subprocess.Popen(request["argv"], stdout=out, stderr=err, cwd=request["cwd"])
        pidfd = os.pidfd_open(proc.pid)
        finished = bool(select.select([pidfd], [], [], request["timeout"])[0])
        if not finished:
            proc.kill()
        _, status, usage = os.wait4(proc.pid, 0)
        seconds = time.perf_counter() - start
        os.close(pidfd)
    proc.returncode = os.waitstatus_to_exitcode(status)
    print(json.dumps({"seconds": seconds, "finished": finished, "exit": proc.returncode,
                      "maxrss_kib": usage.ru_maxrss}), flush=True)
"""


class Runner:
    """Runs the measured processes in ``workdir`` through a small launcher process.

    On Linux a child's max RSS starts at the peak RSS of the memory map it was forked (or
    vforked) from: a child of this bench would count the bench's own peak (the Navier
    references, the loaded descriptions). The launcher, a bare interpreter of about 12 MB
    started before any of that, starts them instead. They inherit the one-thread BLAS
    environment (:data:`THREADS`).
    """

    def __init__(self, workdir, timeout):
        self.workdir, self.timeout = workdir, timeout
        self.launcher = subprocess.Popen([sys.executable, "-c", LAUNCHER], text=True,
                                         stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         env=dict(os.environ, **THREADS))

    def close(self):
        """End the launcher (it exits at the end of its input)."""
        self.launcher.stdin.close()
        self.launcher.wait()

    def run(self, argv):
        """Run ``argv``: its :class:`Measured` time, peak memory and outcome."""
        out, err = self.workdir / "stdout.txt", self.workdir / "stderr.txt"
        request = {"argv": argv, "cwd": str(self.workdir), "stdout": str(out),
                   "stderr": str(err), "timeout": self.timeout}
        self.launcher.stdin.write(json.dumps(request) + "\n")
        self.launcher.stdin.flush()
        answer = json.loads(self.launcher.stdout.readline())
        stdout = out.read_text(errors="replace")
        errors = err.read_text(errors="replace").strip().splitlines()
        seconds, peak_mb = answer["seconds"], answer["maxrss_kib"] * 1024 / 1e6
        if not answer["finished"]:
            return Measured(seconds, peak_mb, "timeout", f"killed after {self.timeout:g} s",
                            stdout)
        if answer["exit"]:
            return Measured(seconds, peak_mb, f"exit {answer['exit']}",
                            errors[-1] if errors else "", stdout)
        return Measured(seconds, peak_mb, "ok", "", stdout)

    def command(self, command, case):
        """``vtcr COMMAND CASE``; ``localise`` and ``update`` also write their JSON."""
        extra = {"solve": ["--max-rows", "0"],
                 "localise": ["--json", str(self.workdir / f"{case.stem}.localise.json")],
                 "update": ["--json", str(self.workdir / f"{case.stem}.update.json"),
                            "--run", str(self.workdir / f"{case.stem}.run.json")]}
        return self.run([sys.executable, "-m", "updating", command, str(case),
                         *extra.get(command, [])])

    def hidden(self, mode):
        """This script in a hidden mode (``mode`` is its argument list).

        Returns ``(Measured, dict or None)``: the mode prints its results as JSON on its last
        line.
        """
        run = self.run([sys.executable, str(Path(__file__).resolve()), *mode])
        lines = run.stdout.strip().splitlines()
        return run, (json.loads(lines[-1]) if run.ok and lines else None)


def update_summary(run, workdir, case):
    """Phases and outcome of a finished ``vtcr update``, from its output and its JSON."""
    text = " ".join(run.stdout.split())
    phases = re.search(r"set-up ([\d.]+) s, updating ([\d.]+) s", text)
    evaluations = re.search(r"solve \(\d+ frequenc\w+\): ([\d.]+) ms, during a correction of "
                            r"\S+: ([\d.]+) ms", text)
    result = json.loads((workdir / f"{case.stem}.update.json").read_text())
    return {
        "setup_s": float(phases[1]) if phases else None,
        "updating_s": float(phases[2]) if phases else None,
        "full_evaluation_ms": float(evaluations[1]) if evaluations else None,
        "correction_evaluation_ms": float(evaluations[2]) if evaluations else None,
        "steps": len(result["steps"]) - 1,
        "status": result["status"],
        "identified": {j: v["log10_stiffness"] for j, v in result.get("identified", {}).items()},
    }


def localise_summary(workdir, case):
    """The three joints with the largest residual in ``vtcr localise``'s JSON."""
    step = json.loads((workdir / f"{case.stem}.localise.json").read_text())
    residuals = step["joints"]
    ranked = sorted(residuals, key=lambda j: residuals[j]["residual_percent"], reverse=True)
    return {"largest_residuals": ranked[:3]}


# ---------------------------------------------------------------------------------------------
# Hidden modes (each run in a process of its own; results as JSON on the last line)
# ---------------------------------------------------------------------------------------------


def evaluation_mode(case_path, joint, count):
    """Time cost evaluations during a correction of ``joint`` on the grid ``case_path``.

    The updating problem is built as ``vtcr update`` builds it (simulated measurements); one
    full evaluation at the initial parameters precedes the correction, as a localisation does
    during the update, so that the correction's set-up is its condensation alone.
    """
    from assembly import load_case
    from updating.data.measurements import simulate_measurements
    from updating.inverse import cost

    case = load_case(case_path)
    t0 = time.perf_counter()
    measurements = simulate_measurements(case)
    t1 = time.perf_counter()
    problem = cost.ModifiedProblem(case, measurements)
    t2 = time.perf_counter()
    parameters = problem.initial_parameters()
    problem.cost(parameters)
    t3 = time.perf_counter()
    if hasattr(problem, "correction"):
        correction = problem.correction(parameters, joint)
        setup, method = time.perf_counter() - t3, "correction.cost"

        def evaluate(value):
            return correction.cost(log10_stiffness=value)
    else:
        setup, method = None, "problem.cost (full)"

        def evaluate(value):
            return problem.cost(cost.with_joint(parameters, joint, log10_stiffness=value))
    seconds, values = [], []
    for value in np.linspace(*case.updating.bounds, count):
        start = time.perf_counter()
        values.append(float(evaluate(float(value))))
        seconds.append(time.perf_counter() - start)
    return {"method": method, "joint": joint, "simulation_s": t1 - t0,
            "problem_setup_s": t2 - t1, "full_evaluation_s": t3 - t2,
            "correction_setup_s": setup, "median_evaluation_s": statistics.median(seconds),
            "min_evaluation_s": min(seconds), "max_evaluation_s": max(seconds),
            "evaluations": count, "e_mod": values}


def vtcr_stiff_mode(case_path, repeats, w_path):
    """Best-of-``repeats`` solves of the stiff grid; w at the probe points to ``w_path``.

    Timed twice: the field alone (``solve_case(..., residuals=False)``, compared with the FE)
    and as ``vtcr solve`` does it, with the reference energy and the joint residuals (their
    memory is the same).
    """
    from assembly import load_case

    case = load_case(case_path)
    seconds, timings, _ = best_solve(case, repeats, residuals=False)
    with_residuals, _, solution = best_solve(case, repeats, residuals=True)
    local, _ = probe_points(case)
    np.save(w_path, np.concatenate([solution.w(pid, points) for pid, points in local.items()]))
    return {"seconds": seconds, "seconds_with_residuals": with_residuals, "timings": timings,
            "unknowns": solution.n_unknowns}


def best_solve(case, repeats, residuals):
    """``(best time, its solver timings, last solution)`` of ``repeats`` ``solve_case`` calls."""
    from solver import solve_case

    best, timings, solution = float("inf"), {}, None
    for _ in range(repeats):
        solution = None  # the previous solution is freed before the next solve
        start = time.perf_counter()
        solution = solve_case(case, case.frequencies[0], residuals=residuals)
        seconds = time.perf_counter() - start
        if seconds < best:
            best, timings = seconds, dict(solution.timings)
    return best, timings, solution


def fem_search_mode(plate, points_path, reference_path, target):
    """The coarsest near-square Argyris mesh whose error at the points is below ``target``.

    Densities (mesh intervals per bending wavelength) in steps of :data:`COARSE_STEP` bracket
    the first accurate mesh; then every mesh in the bracket is tried in increasing order
    (steps of :data:`FINE_STEP`, which see every mesh, as ``fem_until_accurate``'s default).
    """
    from fem_argyris import bending_wavelength, fem_until_accurate, mesh_intervals

    points, reference = np.load(points_path), np.load(reference_path)
    start = time.perf_counter()
    coarse = np.arange(1.0, 16.001, COARSE_STEP)
    result, table = fem_until_accurate(reference, points, **plate, target=target,
                                       per_wavelength=tuple(coarse))
    wavelength = bending_wavelength(plate["E"], plate["nu"], plate["rho"], plate["h"],
                                    plate["frequency"])
    meshes = [mesh_intervals(plate["Lx"], plate["Ly"], wavelength, d) for d in coarse]
    upper = meshes.index((result.n_x, result.n_y))
    fine = np.arange(coarse[max(upper - 1, 0)], coarse[upper] + 1e-9, FINE_STEP)
    result, fine_table = fem_until_accurate(reference, points, **plate, target=target,
                                            per_wavelength=tuple(fine))
    return {"mesh": [result.n_x, result.n_y], "n_dofs": result.n_dofs,
            "error": fine_table[-1].error, "meshes_tried": len(table) + len(fine_table),
            "search_s": time.perf_counter() - start}


def fem_mode(plate, points_path, mesh, repeats, w_path):
    """Best-of-``repeats`` Argyris solve on ``mesh``; w at the points to ``w_path``."""
    from fem_argyris import solve_fem

    points = np.load(points_path)
    best = None
    for _ in range(repeats):
        result = solve_fem(**plate, points=points, n_x=mesh[0], n_y=mesh[1])
        if best is None or result.t_assembly + result.t_solve < best.t_assembly + best.t_solve:
            best = result
    np.save(w_path, best.w)
    return {"seconds": best.t_assembly + best.t_solve, "t_assembly": best.t_assembly,
            "t_solve": best.t_solve, "n_dofs": best.n_dofs}


def imports_mode(side):
    """Import what one side of the stiff comparison imports, and nothing else."""
    if side == "vtcr":
        import assembly  # noqa: F401
        import solver  # noqa: F401
    else:
        import fem_argyris  # noqa: F401
    return {"side": side}


# ---------------------------------------------------------------------------------------------
# The bench
# ---------------------------------------------------------------------------------------------


def measure_commands(n, case, commands, runner, log):
    """The CLI commands on a case (``n`` names it in the log): ``{command: measurement (and
    summary)}``."""
    out = {}
    for command in commands:
        run = runner.command(command, case)
        log(f"{n}: {command} {run.brief()}")
        out[command] = run.record()
        if command == "update" and run.status == "exit 3":
            # the loop stopped without converging (its JSON says which status): a finished
            # run whose time and outcome count like any other
            out[command]["status"] = "ok"
        if out[command]["status"] == "ok" and command == "update":
            out[command]["summary"] = update_summary(run, runner.workdir, case)
        if run.ok and command == "localise":
            out[command]["summary"] = localise_summary(runner.workdir, case)
    return out


def measure_evaluation(n, case, count, runner, log, joint=CORRECTED_JOINT):
    """The cost evaluation during a correction of ``joint``, in a process of its own."""
    run, result = runner.hidden(["--evaluation", str(case), "--count", str(count),
                                 "--joint", joint])
    log(f"{n}: cost evaluation {run.brief()}")
    return dict(run.record(), **(result or {}))


def reference_field(plate, points, n):
    """Navier reference at the points, and its change from the series with half the terms."""
    n_terms = NAVIER_TERMS_PER_PLATE * n
    half = navier(plate, points, n_terms)
    reference = navier(plate, points, 2 * n_terms)
    change = relative_error(half, reference)
    return reference, {"terms": 2 * n_terms, "change_from_half": change}


def measure_stiff(n, case_path, with_fem, repeats, runner, log):
    """The stiff grid by the VTCR and, if ``with_fem``, by Argyris FE at the same accuracy."""
    from assembly import load_case

    case = load_case(case_path)
    plate = single_plate(case)
    _, points = probe_points(case)
    reference, navier_check = reference_field(plate, points, n)
    paths = {name: runner.workdir / f"{name}_{n}.npy"
             for name in ("points", "reference", "vtcr", "fem")}
    np.save(paths["points"], points)
    np.save(paths["reference"], reference)
    out = {"frequency": plate["frequency"], "plate": [plate["Lx"], plate["Ly"]],
           "points": len(points), "navier": navier_check, **problem_size(case)}

    run, result = runner.hidden(["--vtcr-stiff", str(case_path), "--repeats", str(repeats),
                                 "--w", str(paths["vtcr"])])
    log(f"N = {n}: stiff grid VTCR {run.brief()}")
    out["vtcr"] = dict(run.record(), **(result or {}))
    if result:
        out["vtcr"]["error"] = relative_error(np.load(paths["vtcr"]), reference)
    if with_fem and result:
        out.update(measure_fem(n, plate, out["vtcr"]["error"], paths, repeats, runner, log))
    return out


def measure_fem(n, plate, target, paths, repeats, runner, log):
    """The Argyris mesh search for ``target``, then the measured solve on the mesh found.

    Returns ``{"fem_search": ..., "fem": ...}`` (no ``"fem"`` if the search failed).
    """
    spec = json.dumps(plate)
    run, search = runner.hidden(["--fem-search", spec, "--points", str(paths["points"]),
                                 "--reference", str(paths["reference"]),
                                 "--target", repr(target)])
    log(f"N = {n}: FE mesh search {run.brief()}")
    out = {"fem_search": dict(run.record(), **(search or {}))}
    if not search:
        return out
    run, result = runner.hidden(["--fem", spec, "--points", str(paths["points"]),
                                 "--mesh", *map(str, search["mesh"]), "--repeats", str(repeats),
                                 "--w", str(paths["fem"])])
    log(f"N = {n}: stiff plate FE {run.brief()}")
    out["fem"] = dict(run.record(), mesh=search["mesh"], **(result or {}))
    if result:
        out["fem"]["error"] = relative_error(np.load(paths["fem"]), np.load(paths["reference"]))
    return out


def relative_error(w, reference):
    """Relative L2 error ``||w - reference|| / ||reference||``."""
    return float(np.linalg.norm(w - reference) / np.linalg.norm(reference))


def import_baselines(runner):
    """Peak memory (MB) of a process that only imports each side's modules."""
    return {side: runner.hidden(["--imports", side])[0].peak_mb for side in ("vtcr", "fem")}


def growth_exponents(rows, fit_from=FIT_FROM):
    """Least-squares slopes of log(time) and log(memory) on log(plates), over n >= fit_from.

    Returns ``{"solve time": (slope or None, sizes used), ...}`` (at least two sizes needed).
    """
    fits = {}
    for command in ("solve", "localise"):
        for quantity, key in (("time", "wall_s"), ("memory", "peak_mb")):
            used = [r for r in rows if r["n"] >= fit_from
                    and r["commands"].get(command, {}).get("status") == "ok"]
            slope = None
            if len(used) >= 2:
                x = np.log([r["size"]["plates"] for r in used])
                y = np.log([r["commands"][command][key] for r in used])
                slope = float(np.polyfit(x, y, 1)[0])
            fits[f"{command} {quantity}"] = (slope, [label(r) for r in used])
    return fits


def machine():
    """The conditions of the run: processor, cores, memory, threads, versions."""
    model = next((line.split(":", 1)[1].strip() for line in
                  Path("/proc/cpuinfo").read_text().splitlines()
                  if line.startswith("model name")), platform.processor())
    memory = next(int(line.split()[1]) * 1024 / 1e9 for line in
                  Path("/proc/meminfo").read_text().splitlines()
                  if line.startswith("MemTotal"))
    blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    return {"cpu": model, "cores": os.cpu_count(), "usable_cores": len(os.sched_getaffinity(0)),
            "memory_gb": round(memory, 1), "blas": f"{blas['name']} {blas['version']}",
            "threads": THREADS, "python": platform.python_version(), "numpy": np.__version__,
            "scipy": metadata.version("scipy"), "scikit-fem": metadata.version("scikit-fem"),
            "platform": platform.platform()}


# ---------------------------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------------------------


def table(headers, rows):
    """Lines of a right-aligned text table (first column left-aligned)."""
    cells = [headers] + [[str(c) for c in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    lines = []
    for k, row in enumerate(cells):
        lines.append("  ".join(c.ljust(w) if i == 0 else c.rjust(w)
                               for i, (c, w) in enumerate(zip(row, widths, strict=True))))
        if k == 0:
            lines.append("-" * len(lines[0]))
    return lines


def cell(mapping, key, form, scale=1.0):
    """``mapping[key] * scale`` formatted, or ``-`` where it is missing."""
    value = (mapping or {}).get(key)
    return "-" if value is None else format(value if scale == 1.0 else value * scale, form)


def label(row):
    """The first cell of a row: the grid size, or the panel's bays."""
    return f"{row['n']} bays" if row.get("panel") else f"{row['n']} x {row['n']}"


def note(text):
    """A note below a table, wrapped to 100 columns: a list of lines."""
    return textwrap.wrap(text, 100, initial_indent="  ", subsequent_indent="    ")


def failures(where, entries):
    """Note lines for the failed runs among ``{name: measurement}`` of the row ``where``."""
    return [line for name, e in entries.items() if e and e["status"] != "ok"
            for line in note(f"{where}: {name}: {e['status']}: {e['detail']}")]


def scaling_lines(rows, commands):
    """The table of sizes, times and peak memories of the CLI commands."""
    headers = ["N", "plates", "joints", "ray unk.", "intf. unk."]
    for command in commands:
        headers += [f"{command} [s]", f"{command} [MB]"]
    body, notes = [], []
    for r in rows:
        line = [label(r)] + [r["size"][key] for key in
                                  ("plates", "joints", "ray_unknowns", "interface_unknowns")]
        for command in commands:
            entry = r["commands"][command]
            if entry["status"] == "ok":
                line += [cell(entry, "wall_s", ".2f"), cell(entry, "peak_mb", ".0f")]
            else:
                line += [entry["status"], "-"]
        body.append(line)
        notes += failures(label(r), r["commands"])
    return table(headers, body) + (["failures:"] + notes if notes else [])


def update_lines(rows):
    """Phases and outcome of ``update`` and the ranking of ``localise``."""
    body = []
    for r in rows:
        update = r["commands"].get("update", {}).get("summary")
        localise = r["commands"].get("localise", {}).get("summary")
        if not (update or localise):
            continue
        identified = (update or {}).get("identified", {})
        body.append([label(r),
                     ", ".join(localise["largest_residuals"]) if localise else "-",
                     cell(update, "setup_s", ".2f"), cell(update, "updating_s", ".2f"),
                     cell(update, "full_evaluation_ms", ".1f"),
                     cell(update, "correction_evaluation_ms", ".2f"), cell(update, "steps", ""),
                     cell(update, "status", ""),
                     ", ".join(f"{j} {v:.2f}" for j, v in sorted(identified.items())) or "-"])
    if not body:
        return []
    return table(["N", "localise: largest E_G^2", "set-up [s]", "updating [s]",
                  "full eval [ms]", "corr. eval [ms]", "steps", "loop status",
                  "update: identified log10 k"],
                 body)


def evaluation_lines(rows):
    """The cost evaluation during a correction."""
    body, notes = [], []
    for r in rows:
        e = r.get("evaluation")
        if e is None:
            continue
        notes += failures(label(r), {"cost evaluation": e})
        if e["status"] != "ok":
            body.append([label(r), e["status"]] + ["-"] * 7)
            continue
        body.append([label(r), e["method"], e["joint"], cell(e, "problem_setup_s", ".2f"),
                     cell(e, "full_evaluation_s", ".3f"),
                     cell(e, "correction_setup_s", ".1f", 1e3),
                     cell(e, "median_evaluation_s", ".3f", 1e3),
                     cell(e, "min_evaluation_s", ".3f", 1e3) + "-"
                     + cell(e, "max_evaluation_s", ".3f", 1e3),
                     cell(e, "peak_mb", ".0f")])
    if not body:
        return []
    return table(["N", "method", "joint", "problem set-up [s]", "full eval [s]",
                  "corr. set-up [ms]", "median eval [ms]", "range [ms]", "peak [MB]"],
                 body) + notes


def fit_lines(fits):
    """The growth exponents and the sizes that entered each fit."""
    lines = []
    for name, (slope, used) in fits.items():
        sizes = ", ".join(used) or "none"
        value = f"P^{slope:.2f}" if slope is not None else "no fit (fewer than 2 sizes)"
        lines.append(f"  {name:<16} {value:<30} sizes: {sizes}")
    return lines


def stiff_row(n, s):
    """One row of the stiff-grid table: the VTCR's and the FE's error, time and memory."""
    v, f = s["vtcr"], s.get("fem")
    line = [label({"n": n}), f"{s['frequency']:g}", f"{s['plate'][0]:g} x {s['plate'][1]:g}",
            f"{s['ray_unknowns']} + {s['interface_unknowns']}"]
    if v["status"] == "ok":
        line += [cell(v, "error", ".2e"), cell(v, "seconds", ".3f"),
                 cell(v, "seconds_with_residuals", ".3f"), cell(v, "peak_mb", ".0f")]
    else:
        line += [v["status"], "-", "-", "-"]
    if f and f["status"] == "ok":
        return line + [f"{f['mesh'][0]} x {f['mesh'][1]}", f["n_dofs"], cell(f, "error", ".2e"),
                       cell(f, "seconds", ".3f"), cell(f, "peak_mb", ".0f"),
                       f"{f['seconds'] / v['seconds']:.1f}",
                       f"{f['peak_mb'] / v['peak_mb']:.1f}"]
    failed = f or s.get("fem_search")
    return line + [failed["status"] if failed else "skipped"] + ["-"] * 6


def stiff_notes(n, s):
    """Notes below the stiff-grid table: failures, the reference's convergence, the phases."""
    v, f = s["vtcr"], s.get("fem")
    notes = failures(label({"n": n}), {"VTCR": v, "FE": f or s.get("fem_search")})
    check = s["navier"]
    errors = [e["error"] for e in (v, f) if e and "error" in e]
    converged = "" if not errors or check["change_from_half"] < 1e-2 * min(errors) else (
        ", NOT converged well below the errors")
    text = (f"N = {n}: Navier reference {check['terms']}^2 terms (change from half as many "
            f"{check['change_from_half']:.1e}{converged}), {s['points']} points")
    if v["status"] == "ok":
        text += "; VTCR phases [s]: " + ", ".join(f"{k} {t:.3f}" for k, t in v["timings"].items())
    if f and f["status"] == "ok":
        search = s["fem_search"]
        text += (f"; FE: assembly {f['t_assembly']:.3f} s, solve {f['t_solve']:.3f} s, mesh "
                 f"found in {search['search_s']:.1f} s over {search['meshes_tried']} meshes")
    return notes + note(text)


def stiff_lines(rows):
    """The stiff grid: VTCR against Argyris FE at the same accuracy."""
    stiff = [(r["n"], r["stiff"]) for r in rows if "stiff" in r]
    if not stiff:
        return []
    return table(["N", "f [Hz]", "plate [m]", "VTCR unk. (ray + intf.)", "VTCR err",
                  "VTCR [s]", "+ resid. [s]", "VTCR [MB]", "FE mesh", "FE dofs", "FE err",
                  "FE [s]", "FE [MB]", "time FE/VTCR", "mem. FE/VTCR"],
                 [stiff_row(n, s) for n, s in stiff]) + [
        line for n, s in stiff for line in stiff_notes(n, s)]


def say(text):
    """Print prose wrapped to 100 columns (the tables are not wrapped)."""
    print(textwrap.fill(text, 100, subsequent_indent="  "))


def report(result, commands):
    """Print the whole result."""
    m, settings = result["machine"], result["settings"]
    say(f"machine: {m['cpu']}, {m['cores']} cores ({m['usable_cores']} usable), "
        f"{m['memory_gb']} GB; {m['platform']}")
    say(f"software: Python {m['python']}, NumPy {m['numpy']}, SciPy {m['scipy']}, scikit-fem "
        f"{m['scikit-fem']}, BLAS {m['blas']}; every process on one BLAS thread ("
        + ", ".join(f"{k}={v}" for k, v in m["threads"].items()) + ")")
    say(f"grids: N x N plates 0.5 x 0.4 m, h 1 mm, at {settings['frequency']:g} Hz, model "
        f"log10 k = 2, misfit {settings.get('misfit') or 'per_plate (the default)'}; wrong "
        "joints (true log10 k): "
        + "; ".join(
            f"N = {r['n']}: " + ", ".join(f"{j} {v}" for j, v in r["wrong_joints"].items())
            for r in result["rows"]))
    say(f"each run is a fresh process, timeout {settings['timeout']:g} s; peak memory = max "
        f"RSS, including the interpreter and imports")
    if commands:
        print()
        say("vtcr commands on the N x N grid (wall time, peak memory; localise and update "
            "include simulating their measurements):")
        print("\n".join(scaling_lines(result["rows"], commands)))
    lines = update_lines(result["rows"])
    if lines:
        print()
        say("update phases (from its output) and outcome; localise's ranking:")
        print("\n".join(lines))
    if commands:
        print()
        say(f"growth exponents against the number of plates P (least squares of log t on "
            f"log P, N >= {FIT_FROM}):")
        print("\n".join(fit_lines(result["fits"])))
    lines = evaluation_lines(result["rows"])
    if lines:
        print()
        say(f"one cost evaluation during a correction, in a process of its own (median of "
            f"{settings['evaluations']} values of log10 k over the bounds; set-up: after a "
            f"full evaluation at the same parameters):")
        print("\n".join(lines))
    panels = result.get("panel_rows")
    if panels:
        print()
        say(f"stiffened panels of n bays (2n - 1 plates, n - 1 junction lines; model welds "
            f"log10 k = {PANEL_WELD_LOG10_K:g}; wrong welds: true log10 k 2.0 at "
            + "; ".join(f"{r['n']} bays: " + ", ".join(r["wrong_joints"]) for r in panels)
            + "):")
        if commands:
            print("\n".join(scaling_lines(panels, commands)))
        for lines in (update_lines(panels), evaluation_lines(panels)):
            if lines:
                print("\n".join(lines))
        if commands:
            say(f"growth exponents of the panels against P (n >= {PANEL_FIT_FROM} bays):")
            print("\n".join(fit_lines(result["panel_fits"])))
    lines = stiff_lines(result["rows"])
    if lines:
        baseline = result["import_baselines"]
        print()
        say(f"stiff grid (every joint log10 k = {STIFF_LOG10_K:g}) = one simply supported "
            f"plate: VTCR against Argyris FE at the VTCR's error (relative L2 of w against "
            f"the Navier series); times best of {settings['repeats']} in one process: VTCR "
            f"solver.solve_case end to end, for the field alone (+ resid.: with the joint "
            f"residuals and reference energy, as vtcr solve), FE solve_fem's assembly + "
            f"solve; evaluating w is timed for neither; memory: peak RSS of each side's "
            f"process (imports alone: VTCR {baseline['vtcr']:.0f} MB, FE "
            f"{baseline['fem']:.0f} MB)")
        print("\n".join(lines))


def bench(args, log):
    """Run every measurement; return the result dictionary."""
    from assembly import load_case

    stiff_frequencies = dict(args.fem_frequency)
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_scale_") as tmp:
        runner = Runner(Path(tmp), args.timeout)
        try:
            baselines = import_baselines(runner) if args.stiff else {}
            for n in args.sizes:
                grid, stiff = write_cases(n, args.frequency,
                                          stiff_frequencies.get(n, args.frequency), runner.workdir,
                                          args.misfit)
                row = {"n": n, "wrong_joints": wrong_joints(n),
                       "size": problem_size(load_case(grid)),
                       "commands": measure_commands(f"N = {n}", grid, args.commands, runner,
                                                    log)}
                if args.evaluations:
                    row["evaluation"] = measure_evaluation(f"N = {n}", grid, args.evaluations,
                                                           runner, log)
                if args.stiff:
                    row["stiff"] = measure_stiff(n, stiff, n in args.fem_sizes, args.repeats,
                                                 runner, log)
                rows.append(row)
            panel_rows = [measure_panel(n, args, runner, log) for n in args.panels]
        finally:
            runner.close()
    return {"machine": machine(),
            "settings": {"sizes": args.sizes, "frequency": args.frequency,
                         "stiff_frequencies": {n: stiff_frequencies.get(n, args.frequency)
                                               for n in args.sizes},
                         "fem_sizes": args.fem_sizes, "commands": args.commands,
                         "timeout": args.timeout, "evaluations": args.evaluations,
                         "repeats": args.repeats, "misfit": args.misfit},
            "rows": rows, "fits": growth_exponents(rows), "import_baselines": baselines,
            "panel_rows": panel_rows, "panel_fits": growth_exponents(panel_rows, PANEL_FIT_FROM)}


def measure_panel(n, args, runner, log):
    """The commands and one correction's evaluation on the n-bay stiffened panel."""
    from assembly import load_case

    panel = write_panel(n, args.frequency, runner.workdir, args.misfit)
    row = {"n": n, "panel": True, "wrong_joints": wrong_welds(n),
           "size": problem_size(load_case(panel)),
           "commands": measure_commands(f"{n} bays", panel, args.commands, runner, log)}
    if args.evaluations:
        row["evaluation"] = measure_evaluation(f"{n} bays", panel, args.evaluations, runner,
                                               log, PANEL_CORRECTED_JOINT)
    return row


def size_frequency(text):
    """``N:F`` -> ``(N, F)``, for ``--fem-frequency``."""
    n, _, frequency = text.partition(":")
    return int(n), float(frequency)


def parse_args(argv=None):
    """The command line: the bench's options and the hidden modes' (not in ``--help``)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[2, 3, 4, 6, 8, 10],
                        help="grid sizes N (N x N plates, N >= 2)")
    parser.add_argument("--panels", type=int, nargs="*", default=[4, 8, 16, 32, 50],
                        help="stiffened panels of this many bays (n >= 2; none: skip)")
    parser.add_argument("--commands", nargs="*", choices=COMMANDS, default=list(COMMANDS),
                        help="vtcr commands to measure (default: all)")
    parser.add_argument("--frequency", type=float, default=250.0,
                        help="frequency of the grids (Hz), and of the stiff grids not in "
                             "--fem-frequency")
    parser.add_argument("--timeout", type=float, default=600.0,
                        help="seconds allowed to each measured process")
    parser.add_argument("--evaluations", type=int, default=20,
                        help="cost evaluations timed during a correction (0: skip)")
    parser.add_argument("--no-stiff", dest="stiff", action="store_false",
                        help="skip the stiff grid and the FE comparison")
    parser.add_argument("--fem-sizes", type=int, nargs="*", default=[6, 10],
                        help="sizes N whose stiff grid is also solved by FE (those among "
                             "--sizes)")
    parser.add_argument("--fem-frequency", type=size_frequency, nargs="*",
                        default=[(6, 140.0)], metavar="N:F",
                        help="frequency (Hz) of the stiff grid of size N (default 6:140; "
                             "other sizes: --frequency)")
    parser.add_argument("--repeats", type=int, default=3,
                        help="stiff grid and FE: best of this many solves per process")
    parser.add_argument("--misfit", choices=("global", "per_plate"),
                        help="[updating] misfit of the grids and panels (default: the "
                             "description's, per_plate with the scale-free weights)")
    parser.add_argument("--json", metavar="OUT", help="also save the results as JSON")
    hidden = argparse.SUPPRESS
    parser.add_argument("--evaluation", metavar="CASE", help=hidden)
    parser.add_argument("--count", type=int, default=20, help=hidden)
    parser.add_argument("--joint", default=CORRECTED_JOINT, help=hidden)
    parser.add_argument("--vtcr-stiff", metavar="CASE", help=hidden)
    parser.add_argument("--fem-search", metavar="SPEC", help=hidden)
    parser.add_argument("--fem", metavar="SPEC", help=hidden)
    parser.add_argument("--imports", choices=("vtcr", "fem"), help=hidden)
    parser.add_argument("--points", help=hidden)
    parser.add_argument("--reference", help=hidden)
    parser.add_argument("--target", type=float, help=hidden)
    parser.add_argument("--mesh", type=int, nargs=2, help=hidden)
    parser.add_argument("--w", help=hidden)
    args = parser.parse_args(argv)
    if min(args.sizes) < 2:
        parser.error("--sizes: every N must be at least 2 (a grid needs joints)")
    if args.panels and min(args.panels) < 2:
        parser.error("--panels: every panel needs at least 2 bays (one weld)")
    return args


def hidden_mode(args):
    """The result of the hidden mode ``args`` asks for, or None for a normal run."""
    if args.evaluation:
        return evaluation_mode(args.evaluation, args.joint, args.count)
    if args.vtcr_stiff:
        return vtcr_stiff_mode(args.vtcr_stiff, args.repeats, args.w)
    if args.fem_search:
        return fem_search_mode(json.loads(args.fem_search), args.points, args.reference,
                               args.target)
    if args.fem:
        return fem_mode(json.loads(args.fem), args.points, args.mesh, args.repeats, args.w)
    if args.imports:
        return imports_mode(args.imports)
    return None


def main(argv=None):
    """Run the bench (or one hidden mode), print the tables, save the JSON."""
    args = parse_args(argv)
    result = hidden_mode(args)
    if result is not None:
        print(json.dumps(result))
        return

    def log(line):
        print(line, file=sys.stderr, flush=True)

    result = bench(args, log)
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1) + "\n")
    report(result, args.commands)


if __name__ == "__main__":
    main()
