"""tyreroad from Python: the multipoint tyre/road contact model, NumPy in and out.

Every quantity is in SI units (m, N, Pa, s) and every array is float64 unless
said otherwise. Height maps are ``(ny, nx)`` arrays: row ``j`` at
``y = j * dy``, column ``i`` at ``x = i * dx``. See docs/python.md.
"""

from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy as np

from ._tyreroad import (
    Asperity,
    BemError,
    CoreError,
    Error,
    FidelityError,
    FilmError,
    GeometryError,
    InputError,
    LawError,
    Material,
    RollingError,
    ScenarioError,
    Solution,
    SolveError,
    TextureError,
    analyse_film,
    bem_solve,
    compare_texture,
    mean_profile_depth,
    read_texture,
    run_scenario,
    segment,
    self_affine,
    solve,
    texture_spectrum,
)

__all__ = [
    "Asperity",
    "BemError",
    "CoreError",
    "Error",
    "FidelityError",
    "FilmError",
    "GeometryError",
    "InputError",
    "LawError",
    "Material",
    "RollingError",
    "ScenarioError",
    "Solution",
    "SolveError",
    "TextureError",
    "analyse_film",
    "bem_solve",
    "compare_texture",
    "height_map",
    "mean_profile_depth",
    "read_texture",
    "run_scenario",
    "segment",
    "self_affine",
    "solve",
    "texture_spectrum",
]


def height_map(
    surface: Any, dx: Optional[float] = None, dy: Optional[float] = None
) -> Tuple[np.ndarray, float, float]:
    """``(heights (ny, nx), dx, dy)`` from an array and its spacing, or from any
    object with ``heights()`` and ``physical_sizes`` (SurfaceTopography's
    ``Topography``, whose ``heights()`` is indexed ``[x, y]``: transposed here).

    An array that is already float64 and C-contiguous is passed through as a
    view; a topography's transposed heights are copied once to C order.
    """
    if hasattr(surface, "heights") and hasattr(surface, "physical_sizes"):
        h = np.asarray(surface.heights(), dtype=np.float64)
        if h.ndim != 2:
            raise InputError(f"surface: a 2-D topography is needed, got {h.ndim}-D")
        sx, sy = surface.physical_sizes
        nx, ny = h.shape
        return np.ascontiguousarray(h.T), float(sx) / nx, float(sy) / ny
    if dx is None:
        raise InputError("dx: the spacing (m) is needed with a plain array")
    return surface, float(dx), float(dx if dy is None else dy)
