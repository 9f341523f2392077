"""The measurement grid of a plate: the cell centres of a grid of ``spacing`` on its
rectangle, the one rule that every reader of ``[measurement] spacing`` follows.
"""

from __future__ import annotations

__all__ = ["grid_shape", "grid_points", "on_grid"]


def grid_shape(size: tuple[float, float], spacing: float) -> tuple[int, int]:
    """``(nx, ny)`` cells of the measurement grid of a plate."""
    return max(1, round(size[0] / spacing)), max(1, round(size[1] / spacing))


def grid_points(size: tuple[float, float], spacing: float) -> list[tuple[float, float]]:
    """Cell centres of the measurement grid of a plate, ordered by x, then y (m)."""
    (lx, ly), (nx, ny) = size, grid_shape(size, spacing)
    return [((i + 0.5) * lx / nx, (j + 0.5) * ly / ny) for i in range(nx) for j in range(ny)]


def on_grid(size: tuple[float, float], spacing: float, x: float, y: float) -> bool:
    """Tell whether a point is a cell centre of the plate's measurement grid (to 1e-9 m)."""
    (lx, ly), (nx, ny) = size, grid_shape(size, spacing)
    i, j = round(x * nx / lx - 0.5), round(y * ny / ly - 0.5)
    return (0 <= i < nx and 0 <= j < ny and abs((i + 0.5) * lx / nx - x) <= 1e-9
            and abs((j + 0.5) * ly / ny - y) <= 1e-9)
