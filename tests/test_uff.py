"""Measured data from measurement systems: UFF dataset 58 (ASCII) and 58b (binary) through a
node map, read with pyuff (optional extra ``vtcr[uff]``).

The round trip simulates the paper's two-plate experiment (``cases/two_plates.toml``, true
log10 k = 1.5, +-10 % noise, the model starting at 2.5), writes it with pyuff as FRFs on nine
frequency lines around 155 Hz, reads it back through the map, and identifies the joint.
"""

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from support import CASES

from assembly import load_case
from updating.cli import main
from updating.data.measurements import simulate_measurements
from updating.data.uff import _pick_line, read_uff
from updating.data.uff_map import read_uff_map
from updating.errors import InputError
from updating.inverse.cost import ModifiedProblem
from updating.inverse.strategy import update_joints

pyuff = pytest.importorskip("pyuff")

F0 = 155.0
LINES = F0 + 0.5 * np.arange(-4, 5)  # 153-157 Hz, 0.5 Hz resolution, 155 Hz on a line
QUANTITY = {"displacement": 8, "velocity": 11, "acceleration": 12}
# ASCII dataset 58 keeps 12 significant digits (E20.12 double precision, pyuff writes %20.11e):
# each part of a value is rounded by at most 5e-12 of itself, so |dw| <= 7.1e-12 |w|.
ASCII_RTOL = 1e-11
# 58b stores IEEE doubles: only the unit conversion (one multiply/divide by omega^2) rounds.
BINARY_RTOL = 1e-14


@pytest.fixture(scope="module")
def experiment(tmp_path_factory):
    """Case file (model log10 k 2.5, truth 1.5, noise 0.1), its simulated data and node map."""
    folder = tmp_path_factory.mktemp("uff")
    text = (CASES / "two_plates.toml").read_text()
    model = text.replace("log10_stiffness = 1.5             # log k",
                         "log10_stiffness = 2.5             # log k")
    model = model.replace("noise = 0.2 ", "noise = 0.1 ")
    assert model.count("log10_stiffness = 2.5") == 1 and "noise = 0.1 " in model
    case_file = folder / "two_plates.toml"
    case_file.write_text(model)
    case = load_case(case_file)
    measured = simulate_measurements(case)
    nodes = []  # (node, plate, x, y, w) in map order
    for plate, (points, values) in measured.data[F0].items():
        for (x, y), w in zip(points, values):
            nodes.append((101 + len(nodes), plate, float(x), float(y), complex(w)))
    map_file = folder / "map.csv"
    map_file.write_text("node,plate,x,y\n" + "".join(
        f"{n},{p},{x!r},{y!r}\n" for n, p, x, y, _ in nodes))
    return {"folder": folder, "case_file": case_file, "case": case, "measured": measured,
            "nodes": nodes, "map": map_file}


def line_values(w):
    """The FRF on all LINES: ``w`` at 155 Hz, distinct values on the other lines."""
    d = LINES - F0
    return w * (1.0 + 0.3 * d) * np.exp(0.2j * d)


def dataset(node, values, quantity="displacement", binary=0, direction=3, x=LINES, **extra):
    omega = 2 * np.pi * x
    data = {"displacement": values, "velocity": 1j * omega * values,
            "acceleration": -omega**2 * values}[quantity]
    fields = dict(binary=binary, func_type=4, rsp_node=node, rsp_dir=direction, ref_node=1,
                  ref_dir=3, data=np.asarray(data, dtype=complex), x=np.asarray(x, dtype=float),
                  id1="vtcr test", rsp_ent_name="PT", ref_ent_name="SHAKER",
                  abscissa_spacing=1, abscissa_spec_data_type=18,
                  ordinate_spec_data_type=QUANTITY[quantity], orddenom_spec_data_type=13)
    fields.update(extra)
    return pyuff.prepare_58(**fields)


def write(path, datasets):
    # pyuff's 58b writer reopens the file in binary mode without closing the text handle;
    # CPython reports the leak as a ResourceWarning, which pytest's filterwarnings=error would
    # turn into a failure of the test that happens to collect it. Its mode="overwrite" also
    # truncates a 58b dataset's own ASCII header when it reopens the file ("wb"), so the file
    # is removed and written in mode "add".
    Path(path).unlink(missing_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        pyuff.UFF(str(path)).write_sets(datasets, mode="add")
    return path


def experiment_file(experiment, name, quantity="displacement", binary=0):
    sets = [dataset(n, line_values(w), quantity, binary) for n, _, _, _, w in experiment["nodes"]]
    return write(experiment["folder"] / name, sets)


def assert_same(measurements, reference, rtol):
    assert measurements.frequencies == (F0,)
    for plate, (points, values) in reference.data[F0].items():
        got_points, got = measurements.data[F0][plate]
        np.testing.assert_array_equal(got_points, points)
        error = np.abs(got - values) / np.abs(values)
        assert error.max() <= rtol, f"{plate}: relative error {error.max():.2e} > {rtol:.0e}"


@pytest.mark.parametrize("binary", [0, 1], ids=["ascii58", "binary58b"])
@pytest.mark.parametrize("quantity", ["displacement", "velocity", "acceleration"])
def test_round_trip_equals_simulated_values(experiment, quantity, binary):
    """Written as FRFs of displacement / velocity / acceleration, read back as w: w = d,
    v / (j omega), -a / omega^2 (exp(+j omega t)), the 155 Hz line picked among nine."""
    path = experiment_file(experiment, f"m_{quantity}_{binary}.uff", quantity, binary)
    measurements = read_uff(path, experiment["case"], experiment["map"])
    assert_same(measurements, experiment["measured"], BINARY_RTOL if binary else ASCII_RTOL)


@pytest.mark.parametrize("binary", [0, 1], ids=["ascii58", "binary58b"])
def test_identification_from_uff(experiment, binary):
    """From the UFF file, the loop finds the true joint (1.5) from 2.5 within 0.1 decade: by
    the command line (ASCII accelerations) and by the library (58b displacements)."""
    case = experiment["case"]
    if binary:
        path = experiment_file(experiment, "ident.58", "displacement", 1)
        problem = ModifiedProblem(case, read_uff(path, case, experiment["map"]))
        result = update_joints(problem, case.updating, noise=case.measurement.noise)
        final = result.parameters["G1"]["log10_stiffness"]
    else:
        path = experiment_file(experiment, "ident.unv", "acceleration", 0)
        out = experiment["folder"] / "ident.json"
        assert main(["update", str(experiment["case_file"]), "--measurements", str(path),
                     "--uff-map", str(experiment["map"]), "--json", str(out), "--quiet"]) == 0
        steps = json.loads(out.read_text())["steps"]
        assert steps[0]["joints"]["G1"]["log10_stiffness"] == 2.5
        final = steps[-1]["joints"]["G1"]["log10_stiffness"]
    assert abs(final - 1.5) < 0.1, final


def test_vendor_quirks(experiment, tmp_path):
    """What measurement systems write besides clean FRFs, all read to the same field:
    a units dataset 164 in millimetres and a geometry dataset 15 (ignored), accelerations in
    "g", -Z directions (sign flipped), in-plane directions, coherences and unmapped nodes
    (ignored), a node
    named in the entity-name field (node number 0), an over-long entity name that shifts the
    record-6 columns (ladisk/pyuff#21), zero padding beyond num_pts (ladisk/pyuff#22)."""
    nodes = experiment["nodes"]
    sets = [pyuff.prepare_15(node_nums=[1, 2], def_cs=[0, 0], disp_cs=[0, 0], color=[1, 1],
                             x=[0.0, 1.0], y=[0.0, 0.0], z=[0.0, 0.0]),
            pyuff.prepare_164(units_code=5, units_description="mm (milli newton)", temp_mode=1,
                              length=1000.0, force=1000.0, temp=1.0, temp_offset=273.15)]
    for k, (n, _, _, _, w) in enumerate(nodes):
        mm = 1000.0 * line_values(w) / 1000.0  # mm per mN = (1000 mm/m) / (1000 mN/N)
        direction = -3 if k % 3 == 0 else 3
        if k == 5:
            sets.append(dataset(0, mm, rsp_ent_name="A106"))
        elif k % 4 == 1:
            # g per mN: "g" is absolute (no length factor), the force factor still applies
            g = -(2 * np.pi * LINES) ** 2 * line_values(w) / 9.80665 / 1000.0
            sets.append(dataset(n, g, "displacement", ordinate_spec_data_type=12,
                                ordinate_axis_units_lab="g"))
        else:
            sets.append(dataset(n, np.sign(direction) * mm, direction=direction))
        if k % 7 == 0:
            sets.append(dataset(n, 0.5 * mm, direction=1))  # in-plane: ignored
        if k % 5 == 2:  # the coherence of the same node and direction: skipped
            sets.append(dataset(n, mm, func_type=6, data=np.full(len(LINES), 0.98),
                                ordinate_spec_data_type=0, orddenom_spec_data_type=0))
    sets.append(dataset(999, np.ones(len(LINES)) * 7.0))  # not in the map: ignored
    path = write(tmp_path / "quirks.uff", sets)
    text = path.read_text()
    # node 103: an entity name of 11 characters shifts the node and direction fields right
    assert text.count("         PT       103   3") == 2  # its FRF, then its coherence
    text = text.replace("         PT       103   3", " PT-LONG-NM1       103   3", 1)
    path.write_text(text)
    map_text = experiment["map"].read_text().replace("\n106,", "\nA106,")
    map_file = tmp_path / "map.csv"
    map_file.write_text(map_text)
    measurements = read_uff(path, experiment["case"], map_file)
    assert_same(measurements, experiment["measured"], ASCII_RTOL)


def test_binary_58b_with_stray_line_end(experiment):
    """Exporters that end the binary data of a 58b dataset with CR/LF before the closing
    '    -1' (ladisk/pyuff#38, #88) still read to the same field."""
    path = experiment_file(experiment, "crlf.uff", "acceleration", 1)
    parts = path.read_bytes().split(b"    -1\n")  # '', set, '', set, ..., ''
    assert len(parts) == 2 * len(experiment["nodes"]) + 1
    path.write_bytes(b"".join(part + (b"\r\n" if i % 2 else b"") + b"    -1\n"
                              for i, part in enumerate(parts[:-1])) + parts[-1])
    measurements = read_uff(path, experiment["case"], experiment["map"])
    assert_same(measurements, experiment["measured"], BINARY_RTOL)


def test_padding_beyond_num_pts_is_dropped(experiment, tmp_path):
    """Some exporters fill the last record with zeros (ladisk/pyuff#22), which pyuff returns as
    extra lines. They are dropped: node 102's lines stop at 154.5 Hz, and its zero padding
    would otherwise be read as a 155 Hz line."""
    nodes = experiment["nodes"][:2]
    below = np.arange(153.0, 154.6, 0.5)  # 153-154.5 Hz; the padding would sit at 155 Hz
    sets = [dataset(nodes[0][0], line_values(nodes[0][4])),
            dataset(nodes[1][0], np.ones(len(below)) * 1e-6, x=below)]
    path = write(tmp_path / "pad.uff", sets)
    blocks = path.read_text().split("    -1\n")  # '', set 1, '', set 2, ''
    padding = f"{0.0:20.11e}{0.0:20.11e}\n"
    path.write_text("    -1\n".join([blocks[0], blocks[1] + padding, blocks[2],
                                     blocks[3] + padding, blocks[4]]))
    assert len(pyuff.UFF(str(path)).read_sets(0)["data"]) == len(LINES) + 1  # pyuff keeps it
    rows = "node,plate,x,y\n" + "".join(f"{n},{p},{x!r},{y!r}\n" for n, p, x, y, _ in nodes)
    (tmp_path / "map.csv").write_text(rows)
    with pytest.raises(InputError) as caught:
        read_uff(path, experiment["case"], tmp_path / "map.csv")
    assert caught.value.lines == [f"{path}: dataset 2: 155 Hz is outside the measured band "
                                  "153-154.5 Hz; set the description's frequencies inside it or "
                                  "export that band"]
    (tmp_path / "map.csv").write_text(rows.rsplit("\n", 2)[0] + "\n")  # node 101 alone
    measurements = read_uff(path, experiment["case"], tmp_path / "map.csv")
    got = np.concatenate([w for _, w in measurements.data[F0].values()])
    np.testing.assert_allclose(got, [nodes[0][4]], rtol=ASCII_RTOL)


# ---------------------------------------------------------------------------------------------
# bad input: exit 2, one line per problem naming the file and the fix
# ---------------------------------------------------------------------------------------------

def run(args, capsys):
    status = main(args)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return status, err.strip().splitlines()


def test_missing_pyuff_one_line(experiment, tmp_path):
    """Without pyuff (simulated: ``sys.modules['pyuff'] = None``) a UFF file is refused in one
    line that says how to install the extra; CSV measurements do not need it."""
    code = ("import sys; sys.modules['pyuff'] = None; from updating.cli import main; "
            f"sys.exit(main(['localise', {str(experiment['case_file'])!r}, '--measurements', "
            f"{str(tmp_path / 'm.uff')!r}, '--uff-map', {str(experiment['map'])!r}]))")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          timeout=60)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert lines == [f"vtcr: {tmp_path / 'm.uff'}: reading UFF needs pyuff: "
                     "pip install 'pyuff>=2.4' (the extra uff of vtcr)"], done.stderr


def test_bad_map_rows_all_reported(experiment, tmp_path, capsys):
    """Unknown plate, point outside its plate, non-numeric coordinate, duplicate node, two
    nodes at one point (which would weigh that point twice), and a node that the UFF file
    lacks: all reported in one run."""
    path = experiment_file(experiment, "bad_map.uff")
    good = experiment["map"].read_text().splitlines()
    bad = good + ["102,P9,0.1,0.1", "555,P1,0.6,0.1", "556,P1,abc,0.1", "557,P2,0.1,0.1"]
    bad[2] = "101," + bad[2].split(",", 1)[1]  # node 101 twice
    node_3 = bad[3].split(",", 1)[0]
    bad[3] = node_3 + "," + bad[1].split(",", 1)[1]  # two nodes at one point
    map_file = tmp_path / "map.csv"
    map_file.write_text("\n".join(bad) + "\n")
    status, err = run(["localise", str(experiment["case_file"]), "--measurements", str(path),
                       "--uff-map", str(map_file)], capsys)
    assert status == 2
    text = "\n".join(err)
    assert f"{map_file}: row 3, column 'node': node 101 is already placed on row 2" in text
    assert "plate 'P9' is not in the assembly" in text
    assert "point (0.6, 0.1) is outside plate P1" in text
    assert "column 'x': 'abc' is not a number" in text
    assert "node 557 has no dataset 58 in direction +Z or -Z" in text
    assert f"row 4: node {node_3} is placed at the point of node 101 (row 2" in text
    assert len(err) == 6, err
    with pytest.raises(InputError, match="already placed"):
        read_uff_map(map_file, experiment["case"])


def test_uff_needs_a_map_and_map_needs_uff(experiment, capsys):
    path = experiment_file(experiment, "nomap.uff")
    case = str(experiment["case_file"])
    status, err = run(["update", case, "--measurements", str(path)], capsys)
    assert status == 2 and len(err) == 1 and "needs --uff-map MAP.csv" in err[0]
    status, err = run(["curve", case, "--joint", "G1", "--uff-map", str(experiment["map"])],
                      capsys)
    assert status == 2 and len(err) == 1 and "only used with a UFF measurement file" in err[0]


def corrupt(path, value, replacement):
    """Replace the written text of one value (as pyuff formats it, %20.11e)."""
    text = path.read_text()
    token = f"{value:20.11e}"
    assert text.count(token) == 1, token
    path.write_text(text.replace(token, f"{replacement:>20}"))


def test_corrupted_dataset_named(experiment, tmp_path, capsys):
    """A value that is not a number breaks pyuff's parse of that dataset: the message names
    the file, the dataset's position, node and direction; a NaN at the used line is named too."""
    nodes = experiment["nodes"][:8]
    sets = [dataset(n, line_values(w)) for n, *_, w in nodes]
    sets[6]["data"][0] = 1.23456789012e-7 + 0j
    sets[3]["data"][4] = 9.87654321098e-7 + 0j  # the 155 Hz line of node 104
    path = write(tmp_path / "corrupt.uff", sets)
    corrupt(path, 1.23456789012e-7, "1.2345X789012e-07")
    corrupt(path, 9.87654321098e-7, "nan")
    rows = "node,plate,x,y\n" + "".join(f"{n},{p},{x!r},{y!r}\n" for n, p, x, y, _ in nodes)
    (tmp_path / "map.csv").write_text(rows)
    status, err = run(["localise", str(experiment["case_file"]), "--measurements", str(path),
                       "--uff-map", str(tmp_path / "map.csv")], capsys)
    assert status == 2 and len(err) == 2, err
    assert err[0].startswith(f"vtcr: {path}: dataset 4 (node 104, direction +Z): the value at "
                             "155 Hz is (nan+0j)")
    assert err[1].startswith(f"vtcr: {path}: dataset 7 (node 107, direction +Z): pyuff cannot "
                             "read the data values; fix them (ASCII")


def test_frequency_not_on_a_measured_line(experiment, tmp_path, capsys):
    """155 Hz outside a 100-120 Hz band (one message for all the datasets concerned); between
    two lines of an uneven abscissa (150, 160 Hz) farther than half the spacing (2.5 Hz) of the
    nearest line. Nothing is interpolated."""
    nodes = experiment["nodes"][:4]
    band = np.linspace(100.0, 120.0, 5)
    uneven = np.array([140.0, 145.0, 150.0, 160.0, 165.0])
    sets = [dataset(nodes[0][0], np.ones(5) * 1e-6, x=band),
            dataset(nodes[1][0], np.ones(5) * 1e-6, x=uneven, abscissa_spacing=0),
            dataset(nodes[2][0], np.ones(5) * 1e-6, x=band),
            dataset(nodes[3][0], np.ones(9) * 1e-6)]
    path = write(tmp_path / "band.uff", sets)
    rows = "node,plate,x,y\n" + "".join(f"{n},{p},{x!r},{y!r}\n" for n, p, x, y, _ in nodes)
    (tmp_path / "map.csv").write_text(rows)
    with pytest.raises(InputError) as caught:
        read_uff(path, experiment["case"], tmp_path / "map.csv")
    lines = caught.value.lines
    assert len(lines) == 2, lines
    assert f"{path}: datasets 1, 3: 155 Hz is outside the measured band 100-120 Hz" in lines[0]
    assert f"{path}: dataset 2: 155 Hz lies between the lines 150 and 160 Hz" in lines[1]


def test_line_picking_rule():
    """Nearest line within half the smaller spacing around it; a single line must match to the
    six significant digits of the E13.5 abscissa; outside the band is named as such."""
    lines = np.array([150.0, 154.0, 155.0, 155.5, 160.0])
    assert _pick_line(lines, 155.0) == (2, None)
    assert _pick_line(lines, 155.2) == (2, None)  # spacing 0.5 around 155
    index, reason = _pick_line(lines, 154.6)  # 0.4 from 155, whose smaller spacing is 0.5
    assert index is None and "between the lines 154 and 155 Hz" in reason
    assert _pick_line(lines, 150.4) == (0, None)  # the first line's spacing is 4 Hz
    assert "outside the measured band" in _pick_line(lines, 163.0)[1]
    assert _pick_line(np.array([155.0]), 155.0005) == (0, None)
    assert "not the single line 155.03 Hz" in _pick_line(np.array([155.03]), 155.0)[1]


@pytest.mark.parametrize("content, says", [
    (b"plate,x,y,re,im\nP1,0.1,0.1,1,0\n", "its first line is 'plate,x,y,re,im'"),
    (bytes(range(256)) * 8, "it starts with binary data"),
    (b"", "it is empty"),
    (None, "is a directory, not a file"),
], ids=["csv-content", "binary", "empty", "directory"])
def test_a_file_that_is_not_uff_is_named_as_such(experiment, tmp_path, capsys, content, says):
    """Not blamed on the node map (which is fine here): the file itself is named."""
    path = tmp_path / "data.uff"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    status, err = run(["localise", str(experiment["case_file"]), "--measurements", str(path),
                       "--uff-map", str(experiment["map"])], capsys)
    assert status == 2 and len(err) == 1, err
    assert err[0].startswith(f"vtcr: {path}: ") and says in err[0], err
