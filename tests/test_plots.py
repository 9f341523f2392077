"""Figures of an updating run (``--plot DIR``, optional extra ``vtcr[plot]``).

The figures are checked as files (PNG signature, size, not blank) and through the data
functions behind them (what is drawn equals what the run computed); the core must neither
import matplotlib nor need it.
"""

import subprocess
import sys
import textwrap

import numpy as np
import pytest
from support import ROOT, STEEL

from assembly import load_case_text
from solver import solve_case
from updating.cli import main
from updating.data.measurements import simulate_measurements
from updating.figures.curves import cost_curve_data
from updating.figures.field_data import field_map_data
from updating.figures.figure_tools import MISSING_MATPLOTLIB
from updating.figures.residuals import residual_bars_data
from updating.forward.sweep import frequency_band, frequency_response_data, spatial_rms
from updating.inverse.cost import ModifiedProblem, cost_curve
from updating.inverse.strategy import update_joints

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# Two small plates (108 ray unknowns), a point force, the joint modelled 2 decades too stiff:
# one correction step, about 0.1 s of updating.
SMALL = ('''
name = "small-pair"
frequency = 120.0

''' + STEEL + '''
[plates.P1]
material = "steel"
thickness = 0.001
size = [0.3, 0.25]

[plates.P2]
material = "steel"
thickness = 0.001
size = [0.3, 0.25]
origin = [0.3, 0.0]

[joints.G1]
between = ["P1.right", "P2.left"]
kind = "coplanar"
log10_stiffness = 2.5

[[boundaries]]
edge = "P2.right"
condition = "clamped"

[[boundaries]]
edge = "P1.left"
condition = "simply_supported"

[[loads]]
kind = "point_force"
plate = "P1"
at = [0.11, 0.07]
amplitude = 1.0

[measurement]
spacing = 0.05
noise = 0.02
seed = 1

[updating]
bounds = [-1.0, 5.0]

[truth.joints.G1]
log10_stiffness = 0.5
''')


@pytest.fixture(scope="module")
def run():
    """Run the small case: its simulated measurements, modified problem and result."""
    case = load_case_text(SMALL)
    measurements = simulate_measurements(case)
    problem = ModifiedProblem(case, measurements)
    result = update_joints(problem, case.updating, noise=case.measurement.noise)
    assert [s.selected for s in result.steps] == [None, "G1"]
    return case, measurements, problem, result


def _check_png(path):
    matplotlib_image = pytest.importorskip("matplotlib.image")
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE, path
    assert len(data) > 20_000, f"{path.name}: only {len(data)} bytes"
    pixels = matplotlib_image.imread(path)
    assert pixels.ndim == 3 and min(pixels.shape[:2]) > 300, pixels.shape
    assert float(pixels[..., :3].std()) > 0.05, f"{path.name} looks blank"


def test_update_plot_writes_the_figures(tmp_path, monkeypatch):
    """``vtcr update --plot DIR`` writes readable PNGs atomically (no temporary left)."""
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)  # side files of the run (run file) stay in tmp_path
    case_file = tmp_path / "small.toml"
    case_file.write_text(SMALL)
    out = tmp_path / "figures" / "nested"  # created if needed
    assert main(["update", str(case_file), "--plot", str(out), "--quiet"]) == 0
    expected = {"residuals.png", "cost_G1.png", "field_120Hz.png", "frf.png"}
    assert {p.name for p in out.iterdir()} == expected  # nothing half-written left over
    for name in sorted(expected):
        _check_png(out / name)


def test_curve_plot_writes_the_joint_figure(tmp_path, monkeypatch):
    """``vtcr curve --plot DIR`` writes the joint's cost curve."""
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    case_file = tmp_path / "small.toml"
    case_file.write_text(SMALL)
    status = main(["curve", str(case_file), "--joint", "G1", "--samples", "13", "--plot",
                   str(tmp_path / "out"), "--quiet"])
    assert status == 0
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["cost_G1.png"]
    _check_png(tmp_path / "out" / "cost_G1.png")


def test_field_map_data_measured_panel_is_the_measurements(run):
    """The field maps draw the measurements and the models' responses on one colour scale.

    The measured panel is |w~| at the measurement points; the model panels are the model's
    own response at the initial and at the identified joints.
    """
    case, measurements, problem, result = run
    frequency = case.frequencies[0]
    data = field_map_data(case, problem, measurements, frequency,
                          problem.initial_parameters(), result.parameters)
    for pid, (points, values) in measurements.data[frequency].items():
        drawn_points, drawn = data.measured[pid]
        np.testing.assert_array_equal(drawn_points, points)
        np.testing.assert_array_equal(drawn, np.abs(values))
        # the simulated grid is cell-centred: drawn as cells covering the plate
        x_edges, y_edges = data.cells[pid]
        assert (x_edges[0], x_edges[-1]) == (0.0, case.plates[pid].size[0])
        assert (y_edges[0], y_edges[-1]) == (0.0, case.plates[pid].size[1])
    # P2 lies right of P1 in the assembly plane
    np.testing.assert_allclose(data.grids["P2"][0].min(), 0.3)
    np.testing.assert_allclose(data.measured_global["P2"][:, 0],
                               measurements.data[frequency]["P2"][0][:, 0] + 0.3)
    # one colour scale, the measured field's: the data use all of it
    assert data.limits == (0.0, max(float(v.max()) for _, v in data.measured.values()))
    # the loads are marked in the assembly plane
    forces, edges = data.loads
    for load in case.loads:
        if load.kind == "point_force":
            at = case.plates[load.plate].to_global([load.at[0]], [load.at[1]])
            assert np.any(np.all(np.isclose(forces, np.ravel(at)), axis=1))
    assert len(forces) + len(edges) == len(case.loads) > 0
    # the initial model (joint 2 decades too stiff) misses the measurements; the updated
    # one agrees with them to the 2 % noise
    assert data.misfit[0] > 0.1 and data.misfit[1] < 0.03, data.misfit
    # model panel = direct solve of the description with the identified joints
    updated_case = case.with_joint_parameters(result.parameters)
    gx, gy = data.grids["P1"]
    corner = np.array([[gx[3, 5], gy[3, 5]]])  # P1 sits at the origin: local = global
    expected = abs(solve_case(updated_case, frequency).w("P1", corner)[0])
    np.testing.assert_allclose(data.updated["P1"][3, 5], expected, rtol=1e-8)


def test_field_map_data_modified_source_uses_the_modified_problem(run):
    """``source="modified"`` draws the minimiser of E_mod^2: its misfit is sqrt(E_mes^2)."""
    case, measurements, problem, result = run
    frequency = case.frequencies[0]
    data = field_map_data(case, problem, measurements, frequency,
                          problem.initial_parameters(), result.parameters, quantity="real",
                          source="modified")
    evaluation = problem.evaluate(result.parameters)
    # the misfit of the modified field at the measurement points, relative to the whole data,
    # from E_mes^2's parts: each plate's squared misfit is its part times its norm
    # (E_mes^2 is a quadratic form z^H G z: a few digits go to cancellation)
    freq = problem.frequencies[frequency]
    squared = sum(evaluation.misfits[p] * n for p, n in zip(freq.plates, freq.norms()))
    whole = sum(float(np.vdot(v, v).real) for v in freq.data)
    np.testing.assert_allclose(data.misfit[1], np.sqrt(squared / whole), rtol=1e-6)
    assert data.limits[0] == -data.limits[1] < 0
    with pytest.raises(ValueError, match="source"):
        field_map_data(case, problem, measurements, frequency, result.parameters,
                       result.parameters, source="other")


def test_residual_bars_data_are_the_step_residuals(run):
    """The bars are the steps' E_Gamma^2, thresholds and E_mod^2, in %."""
    case, _, _, result = run
    data = residual_bars_data(result, stop_ratio=case.updating.stop_ratio)
    assert data.labels == ("initial", "step 1") and data.joints == ("G1",)
    np.testing.assert_array_equal(
        data.residuals, [[100 * s.residuals["G1"]] for s in result.steps])
    np.testing.assert_array_equal(data.thresholds, [[100 * s.thresholds["G1"]]
                                                    for s in result.steps])
    assert all(s.thresholds["G1"] >= case.updating.stop_ratio * s.floors["G1"]
               for s in result.steps)
    np.testing.assert_array_equal(data.e_mod, [100 * s.e_mod for s in result.steps])
    assert data.selected == (None, 0)
    assert data.log10_k[1, 0] == result.parameters["G1"]["log10_stiffness"]


def test_cost_curve_data_sorts_and_marks_the_minimum(run):
    """Rows in any order give sorted curves; the minimum of E_mod^2 is marked by default."""
    _case, _, problem, result = run
    rows = cost_curve(problem, result.parameters, "G1", [3.0, -1.0, 0.5, 1.5])
    data = cost_curve_data(rows, "G1", true=0.5)
    np.testing.assert_array_equal(data.log10_k, [-1.0, 0.5, 1.5, 3.0])
    by_k = {row[0]: row for row in rows}
    np.testing.assert_array_equal(data.e_mod, [by_k[k][1] for k in data.log10_k])
    np.testing.assert_array_equal(data.e_joint, [by_k[k][4] for k in data.log10_k])
    assert data.identified == min(rows, key=lambda r: r[1])[0] == 0.5
    assert data.identified_label == "minimum"
    assert data.true == 0.5


def test_frequency_response_equals_direct_solves(run):
    """A system shared by the parameter sets gives the field of ``solve_case``, at the
    requested frequencies and at those the refinement added between them.

    One system per frequency, then a reduced solve per parameter set: the same field as
    solving the description with those joints.
    """
    case, measurements, problem, result = run
    frequency = case.frequencies[0]
    points = {pid: p for pid, (p, _) in measurements.data[frequency].items()}
    sets = {"initial": problem.initial_parameters(), "updated": result.parameters}
    requested = [0.97 * frequency, frequency]
    data = frequency_response_data(case, sets, requested, points)
    assert set(requested) < set(data.frequencies) and np.all(np.diff(data.frequencies) > 0)
    for label, parameters in sets.items():
        for i, f in enumerate(data.frequencies):
            solution = solve_case(case.with_joint_parameters(parameters), f)
            expected = spatial_rms(solution.w(pid, p) for pid, p in points.items())
            np.testing.assert_allclose(data.curves[label][i], expected, rtol=1e-8)


def test_frf_plot_writes_the_response_and_the_power_flow(tmp_path):
    """``vtcr frf --plot DIR`` writes ``frf.png`` and ``power.png``."""
    pytest.importorskip("matplotlib")
    case_file = tmp_path / "small.toml"
    case_file.write_text(SMALL)
    out = tmp_path / "sweep"
    assert main(["frf", str(case_file), "--band", "110", "130", "--start-frequencies", "5",
                 "--sampling-tolerance", "0.5", "--plot", str(out), "--quiet"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["frf.png", "power.png"]
    for name in ("frf.png", "power.png"):
        _check_png(out / name)


def test_frequency_band_contains_the_analysed_frequencies():
    """The band is uniform around the analysed frequencies and passes through them."""
    band = frequency_band((309.4,), width=0.2, points=60)
    assert 309.4 in band and len(band) == 61
    np.testing.assert_allclose((band[0], band[-1]), (0.8 * 309.4, 1.2 * 309.4))
    assert np.all(np.diff(band) > 0)


def _python(code):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=ROOT,
                          capture_output=True, text=True, timeout=120, check=False)


def test_core_does_not_import_matplotlib():
    """``import updating.cli``, ``updating.figures.plots`` and ``vtcr check`` leave matplotlib out."""
    done = _python("""
        import sys
        import updating.cli
        import updating.figures.plots  # the data layer and the module itself import it lazily
        status = updating.cli.main(["check", "cases/single_plate.toml", "--quiet"])
        assert status == 0, status
        print("matplotlib" in sys.modules)
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


@pytest.mark.parametrize("command", [["update"], ["curve", "--joint", "G1"],
                                     ["frf", "--band", "150", "160"]])
def test_plot_without_matplotlib_is_a_one_line_error(tmp_path, command):
    """``--plot`` without matplotlib: exit 2, one line, before any work and any file."""
    done = _python(f"""
        import sys
        sys.modules["matplotlib"] = None  # as if it were not installed
        from updating.cli import main
        sys.exit(main([{command[0]!r}, "cases/two_plates.toml", *{command[1:]!r},
                       "--plot", {str(tmp_path / "out")!r}]))
    """)
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines() == [f"vtcr: {MISSING_MATPLOTLIB}"]
    assert not (tmp_path / "out").exists()


def test_framed_assembly_field_map_is_drawn_in_space(tmp_path):
    """A stiffened panel (every plate framed): the field map's grids are placed in space by
    the frames (the stiffener's surface stands on its weld line, the skin lies at z = 0) and
    the figure is drawn in 3D."""
    pytest.importorskip("matplotlib")
    from assembly import parse_case
    from assembly.generate import stiffened_panel
    from updating.figures.fields import draw_field_maps

    case = parse_case(stiffened_panel(2, truth={"W1": 1.0}, spacing=0.2))
    measurements = simulate_measurements(case)
    problem = ModifiedProblem(case, measurements)
    parameters = problem.initial_parameters()
    data = field_map_data(case, problem, measurements, case.frequencies[0], parameters,
                          parameters)
    x, y, z = data.space.surfaces["T1"]
    assert np.allclose(x, 0.5) and z.min() == 0.0 and z.max() == pytest.approx(0.15)
    assert np.allclose(data.space.surfaces["B2"][2], 0.0)
    assert set(data.space.measured) == {"B1", "B2"}
    assert np.allclose(data.space.joints["W1"][:, 0], 0.5)
    figure = draw_field_maps(data, "panel")
    assert sum(ax.name == "3d" for ax in figure.axes) == 3
    path = tmp_path / "field.png"
    figure.savefig(path, dpi=120)
    _check_png(path)


def _synthetic_step(case, ratios, corrected=()):
    """A Step whose joints stand at ``ratios`` (default 0.5) of thresholds 1e-3."""
    from updating.inverse.strategy import Step

    joints = list(case.updatable_joints())
    parameters = case.updatable_parameters()
    residuals = {j: 1e-3 * ratios.get(j, 0.5) for j in joints}
    return Step(1, corrected[0] if corrected else None, parameters, residuals,
                dict.fromkeys(joints, 1e-4), 1.0, 1.0, 1.0,
                also={j: (0.0, 1.0) for j in corrected[1:]},
                thresholds=dict.fromkeys(joints, 1e-3))


def test_residual_map_places_each_joint_on_its_edge_and_colours_it_by_its_excess(tmp_path):
    """A 4 x 4 grid (24 joints, above MAP_JOINTS): each joint's segment is the shared edge of
    its two plates, its ratio its residual over its threshold, the joint that stands out most
    is named; the map draws to a PNG."""
    from assembly import parse_case
    from assembly.generate import plate_grid
    from updating.figures.figure_tools import new_figure, save_figure_atomic
    from updating.figures.residual_map import MAP_JOINTS, draw_residual_map, residual_map_data

    case = parse_case(plate_grid(4, 4))
    assert len(case.joints) > MAP_JOINTS
    data = residual_map_data(case, _synthetic_step(case, {"H2_3": 40.0, "V1_1": 3.0},
                                                   ("H2_3",)), case.updating.stop_ratio)
    np.testing.assert_allclose(data.segments["H2_3"], [[1.0, 0.8], [1.0, 1.2]])
    np.testing.assert_allclose(data.segments["V1_1"], [[0.5, 0.4], [0.0, 0.4]])
    assert data.ratios["H2_3"] == pytest.approx(40.0) and data.most == "H2_3"
    assert data.corrected == {"H2_3": 2.0} and data.dimension == 2
    pytest.importorskip("matplotlib")
    path = save_figure_atomic(draw_residual_map(data, new_figure(figsize=(9.0, 7.0)), "grid"),
                              tmp_path / "map.png")
    _check_png(path)


def test_residual_map_draws_junction_members_inside_their_own_plates():
    """The stiffened panel (plates with frames: a 3D map): weld W2's member T2 is drawn on the
    stiffener, MEMBER_OFFSET of its height above the skin, parallel to the weld line."""
    from assembly import load_case
    from updating.figures.residual_map import MEMBER_OFFSET, residual_map_data

    case = load_case(ROOT / "cases" / "stiffened_panel.toml")
    data = residual_map_data(case, _synthetic_step(case, {"W2.T2": 9.0}),
                             case.updating.stop_ratio)
    segment = data.segments["W2.T2"]
    assert data.dimension == 3 and data.most == "W2.T2"
    height = MEMBER_OFFSET * min(case.plates["T2"].size)
    np.testing.assert_allclose(segment[:, 0], 1.0)  # on the line x = 1.0 of the weld
    np.testing.assert_allclose(segment[:, 2], height)  # inside the stiffener, above the skin
    np.testing.assert_allclose(sorted(segment[:, 1]), [0.0, 0.4])
