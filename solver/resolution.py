"""The resolution factor of a plate or a joint in a solve: the description's, or the one a
solve asks for (the error estimate's enriched solve refines every plate, a tolerance's
refinement some of them)."""

from __future__ import annotations

from collections.abc import Mapping

from assembly.case import Case

__all__ = ["joint_resolution", "plate_resolution"]


def plate_resolution(case: Case, plate_id: str,
                     resolution: float | Mapping[str, float] | None = None) -> float:
    """The resolution factor of one plate: ``resolution`` is None (the description's), one
    number for every plate, or a mapping by plate (plates it lacks: the description's)."""
    if resolution is None:
        return case.discretisation.resolution
    if isinstance(resolution, Mapping):
        return float(resolution.get(plate_id, case.discretisation.resolution))
    return float(resolution)


def joint_resolution(case: Case, joint_id: str,
                     resolution: float | Mapping[str, float] | None = None) -> float:
    """The resolution factor of a joint: the finest of its plates' (:func:`plate_resolution`)."""
    return max(plate_resolution(case, plate, resolution)
               for plate in case.joints[joint_id].plates)
