"""Joint updating: the modified error, the localisation–correction loop, its intervals and plan,
measured and simulated data, reports and the command line (``docs/api.md``).

The names below are loaded on first use, so that ``import updating.cli`` (the ``vtcr``
command) loads no numpy before it has set its BLAS threads.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "update_case": "updating.api",
    "localise_case": "updating.api",
    "ModifiedProblem": "updating.inverse.cost",
    "localise": "updating.inverse.strategy",
    "update_joints": "updating.inverse.strategy",
    "Step": "updating.inverse.strategy",
    "UpdateResult": "updating.inverse.strategy",
    "Measurements": "updating.data.measurements",
    "simulate_measurements": "updating.data.measurements",
    "read_measurements": "updating.data.measurements",
    "identifiability_plan": "updating.inverse.plan",
    "frequency_sweep": "updating.forward.sweep",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'updating' has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
