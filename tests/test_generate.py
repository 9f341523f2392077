"""Generated descriptions: plate grids and chains, and their TOML text."""

from __future__ import annotations

import tomllib

import pytest

from assembly import load_case_text, parse_case
from assembly.generate import description_toml, grid_joint_ids, plate_grid


@pytest.mark.parametrize("n_x, n_y, joints", [(2, 1, 1), (12, 1, 11), (3, 2, 7), (10, 10, 180)])
def test_grid_counts_and_names(n_x, n_y, joints):
    case = parse_case(plate_grid(n_x, n_y))
    assert len(case.plates) == n_x * n_y and len(case.joints) == joints
    assert list(case.joints) == grid_joint_ids(n_x, n_y)
    # every outer edge supported, every inner edge joined: each plate edge is used once
    used = [e for j in case.joints.values() for e in j.between] + [b.edge for b in case.boundaries]
    assert sorted(used) == sorted(f"{p}.{e}" for p in case.plates
                                  for e in ("left", "right", "bottom", "top"))


def test_toml_round_trip_and_header():
    data = plate_grid(3, 2, truth={"H1_1": 0.5, "V2_1": 4.0}, resolution=1.25)
    text = description_toml(data, "a grid\nof six plates")
    assert text.startswith("# a grid\n# of six plates\n")
    assert tomllib.loads(text) == data
    case = load_case_text(text)
    assert case.true_case().joints["V2_1"].log10_stiffness == 4.0


def test_bad_grids_are_refused():
    with pytest.raises(ValueError, match="H9_9"):
        plate_grid(2, 2, truth={"H9_9": 1.0})
    with pytest.raises(ValueError, match="two plates"):
        plate_grid(1, 1)
