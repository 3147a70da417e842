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
    view; a topography's transposed heights are copied once to C order (float32
    heights widened to float64; complex or integer heights refused, as are
    ``dx``/``dy`` given with a topography, which has its own).
    """
    if hasattr(surface, "heights") and hasattr(surface, "physical_sizes"):
        if dx is not None or dy is not None:
            raise InputError(
                "dx, dy: a topography carries its own spacing (physical_sizes); "
                "give them only with a plain array"
            )
        raw = np.asarray(surface.heights())
        if raw.dtype.kind != "f":
            raise InputError(f"surface: heights must be real floats, got dtype {raw.dtype}")
        h = raw.astype(np.float64, copy=False)
        if h.ndim != 2:
            raise InputError(f"surface: a 2-D topography is needed, got {h.ndim}-D")
        sizes = tuple(surface.physical_sizes)
        if len(sizes) != 2:
            raise InputError(f"surface: physical_sizes must be (sx, sy), got {sizes}")
        sx, sy = sizes
        nx, ny = h.shape
        return np.ascontiguousarray(h.T), float(sx) / nx, float(sy) / ny
    if dx is None:
        raise InputError("dx: the spacing (m) is needed with a plain array")
    return surface, float(dx), float(dx if dy is None else dy)
