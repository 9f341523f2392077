"""Fixtures shared by the test modules.

The descriptions they are built from, and the helpers, live in the support modules
(``support.py``, ``exact.py``, ``exact_junction.py``, ``exact_prismatic.py``); test modules
import those and never each other. A ``Case`` is immutable, so one loaded per session is shared
by every test that reads it.
"""

from __future__ import annotations

import pytest
from support import CASES, TWO_PLATES

from assembly import Case, load_case, parse_case


@pytest.fixture(scope="session")
def four_plates_case() -> Case:
    """``cases/four_plates.toml``: the paper's four plates (Tables 3 and 4)."""
    return load_case(CASES / "four_plates.toml")


@pytest.fixture(scope="session")
def two_plates_case() -> Case:
    """:data:`support.TWO_PLATES`: two plates, one coplanar joint, a point force."""
    return parse_case(TWO_PLATES)
