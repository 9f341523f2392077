"""The settings of a description: how it is discretised (``[discretisation]``), measured
(``[measurement]``), updated (``[updating]``) and computed (``[compute]``), and the joints of
its simulated experiment (``[truth]``); the assembly itself is in :mod:`assembly.models`
(``docs/description.md``).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, Union

from pydantic import AfterValidator, Field, Strict

from .joints import MemberLossFactor, MemberStiffness
from .types import (
    Count,
    FrozenDict,
    FrozenModel,
    NonNegative,
    Positive,
    Real,
    check_bounds,
    check_identify,
    freeze,
)

__all__ = ["PlateDiscretisation", "Discretisation", "PointMeasurement", "Measurement",
           "Updating", "Compute", "JointTruth", "Truth", "default_spacing",
           "DEFAULT_GRID_FRACTION"]


class PlateDiscretisation(FrozenModel):
    """Per-plate ray counts overriding the automatic rule; omitted counts stay automatic.

    Parameters
    ----------
    interior : int, optional
        Number of interior (propagating) ray sectors, >= 4.
    edge_propagating : int, optional
        Propagating edge-ray sectors per edge (both signs of beta together), >= 0.
    edge_evanescent : int, optional
        Evanescent (boundary-layer) edge-ray sectors per edge, >= 0.
    corner : int, optional
        Corner-ray sectors per corner, >= 0.
    edge_wavenumber_ratio : float, optional
        The plate's own :math:`\tau_{max} > 1` (``[discretisation]`` ``edge_wavenumber_ratio``
        elsewhere): its edge rays span ``|beta| <= tau_max * kappa0``, and its joints' counts
        follow the smallest of their plates' (``docs/accuracy.md`` section 8: the plates next
        to a point force that lies close to a joint).
    """

    interior: Annotated[int, Strict(), Field(ge=4)] | None = None
    edge_propagating: Count | None = None
    edge_evanescent: Count | None = None
    corner: Count | None = None
    edge_wavenumber_ratio: Annotated[float, Strict(), Field(gt=1)] | None = None


class Discretisation(FrozenModel):
    """Ray discretisation settings (``[discretisation]``).

    Parameters
    ----------
    resolution : float, optional
        Multiplier (> 0) on the automatic ray-count rule.  Default 1.0.
    quadrature_per_sector : int, optional
        Gauss-Legendre points per ray sector, >= 2.  Default 8.
    edge_wavenumber_ratio : float, optional
        :math:`\\tau_{max} > 1`: edge rays span ``|beta| <= tau_max * kappa0``.  Default 2.5.
    interface_functions : int, optional
        Number of functions per interface unknown (>= 1); None (default) = automatic.
    tolerance : float, optional
        Largest accepted estimated relative L2 error on any plate, of ``w`` or of the
        displacement ``(u, v, w)`` where larger (0 < tolerance < 1): ``solve``, the updating
        commands and the simulated experiment (to 0.3 of it) raise the resolution until the
        a-posteriori estimate is below it, or stop naming the plate that cannot reach it.
        None (default): solve at ``resolution`` and report the estimate.
    plates : mapping of str to PlateDiscretisation, optional
        Per-plate overrides, ``[discretisation.plates.P1]``.
    """

    resolution: Positive = 1.0
    quadrature_per_sector: Annotated[int, Strict(), Field(ge=2)] = 8
    edge_wavenumber_ratio: Annotated[float, Strict(), Field(gt=1)] = 2.5
    interface_functions: Annotated[int, Strict(), Field(ge=1)] | None = None
    tolerance: Annotated[float, Strict(), Field(gt=0, lt=1)] | None = None
    plates: Annotated[dict[str, PlateDiscretisation], AfterValidator(freeze)] = Field(
        default_factory=FrozenDict
    )

    def for_plate(self, plate_id: str) -> PlateDiscretisation:
        """Return the overrides of one plate (all None when it has none)."""
        return self.plates.get(plate_id, PlateDiscretisation())

    def edge_ratio(self, plate_id: str) -> float:
        """The ``edge_wavenumber_ratio`` of one plate: its own, else the description's."""
        own = self.for_plate(plate_id).edge_wavenumber_ratio
        return self.edge_wavenumber_ratio if own is None else own


class PointMeasurement(FrozenModel):
    """One measurement point.

    Parameters
    ----------
    plate : str
        Plate id.
    at : tuple of float, shape (2,)
        ``[x, y]`` in plate-local m, on the plate (edges allowed).
    """

    plate: str
    at: tuple[Real, Real]


DEFAULT_GRID_FRACTION = 0.2
"""Default measurement spacing, as a fraction of the largest plate side of the assembly."""


def default_spacing(plates) -> float | None:
    """:data:`DEFAULT_GRID_FRACTION` times the largest side of ``plates`` (None without any)."""
    sides = [max(plate.size) for plate in plates.values() if plate is not None]
    return DEFAULT_GRID_FRACTION * max(sides) if sides else None


class Measurement(FrozenModel):
    """Measurement grid of a (simulated) experiment (``[measurement]``).

    The grid of a measured plate of size ``Lx x Ly`` consists of the centres of a uniform
    mesh of about `spacing`: ``nx = max(1, round(Lx / spacing))`` cells, points
    ``x_i = (i + 1/2) Lx / nx`` for ``i = 0 .. nx - 1`` (likewise in y).  See
    :meth:`assembly.case.Case.measurement_points`.

    Parameters
    ----------
    spacing : float, optional
        Grid spacing in m, > 0.  Default: a fifth of the largest plate side of the assembly
        (0.1 m for 0.5 m plates, the paper's grid), so that a description in other consistent
        units (mm) gets the same grid.
    plates : tuple of str, optional
        Plates carrying the grid; None (default) = every plate; ``[]`` = no grid (only
        `points`).
    noise : float, optional
        Relative noise amplitude (fraction, >= 0) of a simulated experiment.  Default 0.
    seed : int, optional
        Seed (>= 0) of the noise generator.  Default 1.
    resolution : float, optional
        Discretisation multiplier (> 0) used to simulate the experiment, finer than the
        model's so that the simulation is not the model itself.  Default 1.6.
    points : tuple of PointMeasurement, optional
        Extra measurement points ``{plate, at = [x, y]}``.  Default none.
    """

    spacing: Positive | None = None
    plates: tuple[str, ...] | None = None
    noise: NonNegative = 0.0
    seed: Count = 1
    resolution: Positive = 1.6
    points: tuple[PointMeasurement, ...] = ()


def _check_r(value: float | str) -> float | str:
    if value != "auto" and not 0.0 < value <= 1.0:
        raise ValueError(f"must be > 0 and <= 1, or \"auto\", got {value:g}; e.g. r = 0.8, "
                         "or r = \"auto\" (the scale-free weights)")
    return value


class Updating(FrozenModel):
    """Localisation--correction settings (``[updating]``).

    Parameters
    ----------
    r : float or "auto", optional
        Weight of the measurement term in ``E_mod^2 = (1 - r) E_int^2 + r E_mes^2``,
        in (0, 1], or ``"auto"`` (default): weights that do not depend on the size of the
        structure (``updating.inverse.weights``: each joint's law weighed by the energy of its own
        plates, each plate's data by its own stated noise, at the fixed `balance`).
    alpha : mapping of str to float, optional
        Joint weights ``alpha_i >= 0`` of the interface error.  Joints not listed weigh 1;
        the weights are normalised to sum 1.  In a validated :class:`~assembly.case.Case` this
        holds every joint, normalised; None (default) = equal weights ``1 / N_joints``.  With
        ``r = "auto"`` they multiply the scale-free weights (equal: those alone).
    balance : float, optional
        With ``r = "auto"``: the weight of a joint's law relative to the data around it,
        ``beta`` in ``beta e_j^2 / E_j`` against the noise-whitened misfit of its plates
        (``E_j`` the energy of the joint's plates), > 0.  Default 2000.
    bounds : tuple of float, shape (2,), optional
        ``[lo, hi]`` on ``log10_stiffness``, lo < hi.  Default [-3, 7].
    identify : tuple of {"stiffness", "damping", "mass"}, optional
        Joint parameters to identify: ``log10_stiffness``, ``loss_factor`` and/or ``mass``.
        Default ("stiffness",).
    max_steps : int, optional
        Maximum number of correction steps, >= 1.  Default 8.
    stop_ratio : float, optional
        A joint is selected for correction only if its residual exceeds `stop_ratio` times
        its floor (the residual a right model shows on average); > 1.  Default 3.0.
    significance : float, optional
        ... and the residual a right model exceeds at any of the joints with probability
        `significance` (familywise: among hundreds of joints, some stand several times above
        their floors by noise alone), in (0, 0.5).  Default 0.05.
    min_decrease : float, optional
        Smallest relative decrease of ``E_mod`` for a correction to count, in [0, 1).
        Default 0.01.
    confidence : float, optional
        Level of the confidence interval reported for every corrected joint, in (0, 1).
        Default 0.9.
    misfit : {"global", "per_plate"}, optional
        Normalisation of ``E_mes^2``: the whole data's squared norm (``"global"``, the
        paper's), or the mean over the measured points of each plate's misfit relative to its
        own data (``"per_plate"``: under relative noise, plates far from the load count as
        much as the loaded ones).  Default: ``"per_plate"`` with ``r = "auto"``, ``"global"``
        with a number.
    """

    r: Annotated[Union[Annotated[float, Strict()], Literal["auto"]],
                 AfterValidator(_check_r)] = "auto"
    alpha: Annotated[dict[str, NonNegative], AfterValidator(freeze)] | None = None
    bounds: Annotated[tuple[Real, Real], AfterValidator(check_bounds)] = (-3.0, 7.0)
    identify: Annotated[
        tuple[Literal["stiffness", "damping", "mass"], ...], AfterValidator(check_identify)
    ] = ("stiffness",)
    max_steps: Annotated[int, Strict(), Field(ge=1)] = 8
    stop_ratio: Annotated[float, Strict(), Field(gt=1)] = 3.0
    significance: Annotated[float, Strict(), Field(gt=0, lt=0.5)] = 0.05
    min_decrease: Annotated[float, Strict(), Field(ge=0, lt=1)] = 0.01
    confidence: Annotated[float, Strict(), Field(gt=0, lt=1)] = 0.9
    misfit: Literal["global", "per_plate"] | None = None
    balance: Annotated[float, Strict(), Field(gt=0)] = 2000.0

    @property
    def automatic(self) -> bool:
        """Whether the weights are the scale-free ones (``r = "auto"``)."""
        return self.r == "auto"

    @property
    def misfit_kind(self) -> str:
        """``misfit`` as given, else the default of the weights (``per_plate`` with
        ``r = "auto"``, ``global`` with a number)."""
        return self.misfit or ("per_plate" if self.automatic else "global")


class Compute(FrozenModel):
    """Where independent tasks (frequencies, noise realisations) run (``[compute]``).

    The command-line options ``--workers`` and ``--scheduler`` override these.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (>= 1), one BLAS thread each.  Default 1: this process.
    scheduler : str, optional
        Address of a running Dask distributed scheduler, e.g. ``"tcp://node1:8786"`` (the
        ``distributed`` extra); its workers run the tasks and ``workers`` is ignored.
    """

    workers: Annotated[int, Strict(), Field(ge=1)] = 1
    scheduler: Annotated[str, Field(min_length=1)] | None = None


class JointTruth(FrozenModel):
    """The "true" parameters of one joint, used to simulate an experiment.

    Parameters
    ----------
    log10_stiffness : float or mapping of str to float, optional
        True :math:`\\log_{10} k`; None keeps the model value.  For a junction, one value for
        every member or a table by member plate (``inf``: rigid), like the joint itself.
    loss_factor : float or mapping of str to float, optional
        True :math:`\\zeta \\ge 0`; None keeps the model value (a table for a junction).
    mass : float, optional
        True line mass in kg/m (coplanar joints only); None keeps the model value.
    """

    log10_stiffness: MemberStiffness | None = None
    loss_factor: MemberLossFactor | None = None
    mass: NonNegative | None = None

    def changes(self) -> dict[str, Any]:
        """Return the parameters that are given, ``{name: value}``."""
        return {k: getattr(self, k) for k in ("log10_stiffness", "loss_factor", "mass")
                if getattr(self, k) is not None}


class Truth(FrozenModel):
    """True joint parameters of a simulated experiment (``[truth.joints.ID]``).

    Parameters
    ----------
    joints : mapping of str to JointTruth, optional
        Per joint; joints not listed keep their model values.
    """

    joints: Annotated[dict[str, JointTruth], AfterValidator(freeze)] = Field(
        default_factory=FrozenDict
    )
