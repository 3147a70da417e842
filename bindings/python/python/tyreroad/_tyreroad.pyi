# Type stubs of the Rust extension (bindings/python/src). SI units throughout.
from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]

class Error(Exception): ...
class InputError(Error): ...
class CoreError(Error): ...
class GeometryError(Error): ...
class LawError(Error): ...
class SolveError(Error): ...
class TextureError(Error): ...
class BemError(Error): ...
class FilmError(Error): ...
class RollingError(Error): ...
class ScenarioError(Error): ...
class FidelityError(Error): ...

class Material:
    """Elastic half-space: Young's modulus E (Pa), Poisson's ratio nu."""
    def __init__(self, youngs_modulus: float, poisson_ratio: float) -> None: ...
    @property
    def youngs_modulus(self) -> float: ...
    @property
    def poisson_ratio(self) -> float: ...
    @property
    def reduced_modulus(self) -> float:
        """E* = E / (1 - nu^2) (Pa)."""

class Asperity:
    """A rigid asperity and its potential contact law P(delta) (N)."""
    @staticmethod
    def sphere(radius: float, material: Material, constant: Optional[float] = None) -> Asperity: ...
    @staticmethod
    def cone(half_angle: float, material: Material, constant: Optional[float] = None) -> Asperity: ...
    @staticmethod
    def ellipsoid(
        radius_x: float, radius_y: float, material: Material, constant: Optional[float] = None
    ) -> Asperity: ...
    @staticmethod
    def mesh(
        vertices: F64, faces: npt.NDArray[np.integer[Any]], material: Material, constant: float = 0.36
    ) -> Asperity: ...
    def cap(self, depths: F64) -> Dict[str, F64]:
        """volume Omega (m^3), base_area Sigma (m^2), perimeter Gamma (m), d_base_area, d_perimeter."""
    def force(self, depths: F64) -> F64:
        """P(delta) (N) at each depth (m)."""
    def stiffness(self, depths: F64) -> F64:
        """k(delta) = dP/d(delta) (N/m)."""
    def potential(self, depths: F64) -> F64:
        """U(delta) (J)."""
    @property
    def constant(self) -> float: ...
    @property
    def kind(self) -> str: ...

class Solution:
    @property
    def forces(self) -> F64: ...
    @property
    def depths(self) -> F64: ...
    @property
    def radii(self) -> F64: ...
    @property
    def approach(self) -> float: ...
    @property
    def iterations(self) -> int: ...
    @property
    def residual(self) -> float: ...
    @property
    def total_force(self) -> float: ...
    @property
    def contact_count(self) -> int: ...
    @property
    def convergence(self) -> str: ...
    @property
    def recovery(self) -> str: ...
    def pressure_map(
        self, nx: int, ny: int, dx: float, dy: float, origin: Tuple[float, float] = (0.0, 0.0)
    ) -> F64:
        """Two-scale pressure map (Pa), shape (ny, nx)."""

def solve(
    positions: F64,
    heights: F64,
    asperities: Union[Asperity, Sequence[Asperity]],
    material: Material,
    *,
    load: Optional[float] = None,
    approach: Optional[float] = None,
    tolerance: Optional[float] = None,
) -> Solution: ...
def read_texture(path: Union[str, PathLike[str]]) -> Tuple[F64, float, float]: ...
def mean_profile_depth(
    heights: F64, dx: float, dy: float, baseline: Optional[float] = None
) -> Dict[str, Any]: ...
def texture_spectrum(heights: F64, dx: float, dy: float) -> Dict[str, F64]: ...
def segment(
    heights: F64, dx: float, dy: float, min_prominence: float, min_area: float = 0.0
) -> Dict[str, Any]: ...
def self_affine(
    nx: int,
    ny: int,
    dx: float,
    dy: float,
    rms: float,
    hurst: float,
    lambda_long: float,
    lambda_short: float,
    seed: int = 0,
) -> Tuple[F64, float, float]: ...
def bem_solve(
    heights: F64,
    dx: float,
    dy: float,
    material: Material,
    *,
    load: Optional[float] = None,
    approach: Optional[float] = None,
    tolerance: float = 1e-8,
    max_iterations: int = 5000,
    periodic: bool = False,
) -> Dict[str, Any]: ...
def compare_texture(
    heights: F64,
    dx: float,
    dy: float,
    material: Material,
    loads: Sequence[float],
    *,
    rungs: Optional[Sequence[str]] = None,
    min_prominence: float = 0.2e-3,
    min_area: float = 2e-6,
    max_cap_width: Optional[float] = None,
) -> Dict[str, Any]: ...
def analyse_film(
    grey: F64,
    pixel_size: float,
    curve: str = "B",
    threshold_grey: Optional[float] = None,
    min_pixels: int = 20,
) -> Dict[str, Any]: ...
def run_scenario(
    scenario: Union[str, PathLike[str], Dict[str, Any]],
    base_dir: Optional[Union[str, PathLike[str]]] = None,
    progress: Optional[Callable[[int, int], Optional[bool]]] = None,
    checkpoint_dir: Optional[Union[str, PathLike[str]]] = None,
) -> Dict[str, Any]: ...
