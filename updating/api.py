"""The updating run as library calls: what ``vtcr localise`` and ``vtcr update`` do, without
the printing (``docs/api.md``).

>>> import assembly, updating
>>> case = assembly.load_case("cases/four_plates.toml")   # doctest: +SKIP
>>> result = updating.update_case(case)                    # doctest: +SKIP
>>> sorted(result.intervals)                               # doctest: +SKIP
['G1', 'G2', 'G4']

Both run the description's guard rails first (:func:`solver.guards.check_description`, through
:class:`updating.inverse.cost.ModifiedProblem`) and, without measurements, simulate the experiment the
description states (``[truth]``, ``[measurement]``), as the commands do.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from updating.data.measurements import Measurements, simulate_measurements
from updating.inverse.cost import ModifiedProblem
from updating.inverse.strategy import Step, UpdateResult, localise, update_joints

if TYPE_CHECKING:
    from assembly import Case
    from updating.executor import Executor

__all__ = ["localise_case", "update_case"]


def _problem(case: Case, measurements: Measurements | None,
             executor: Executor | None) -> ModifiedProblem:
    measurements = simulate_measurements(case, executor=executor) if measurements is None \
        else measurements
    return ModifiedProblem(case, measurements, executor=executor, estimate=True)


def localise_case(case: Case, measurements: Measurements | None = None,
                  executor: Executor | None = None) -> Step:
    """The first localisation of ``case``: every joint's residual, floor and threshold at the
    model's parameters (:func:`updating.inverse.strategy.localise`), against ``measurements``
    (:class:`updating.data.measurements.Measurements`; default the simulated experiment), with the
    description's stated noise and ``[updating]`` settings."""
    problem = _problem(case, measurements, executor)
    return localise(problem, problem.initial_parameters(), noise=case.measurement.noise,
                    settings=case.updating)


def update_case(case: Case, measurements: Measurements | None = None,
                executor: Executor | None = None,
                on_step: Callable[[Step], object] | None = None) -> UpdateResult:
    """The localisation–correction loop on ``case`` (:func:`updating.inverse.strategy.update_joints`)
    with the description's ``[updating]`` settings and stated noise, against ``measurements``
    (default the simulated experiment); ``on_step(step)`` after each finished step."""
    problem = _problem(case, measurements, executor)
    return update_joints(problem, case.updating, noise=case.measurement.noise, on_step=on_step)
