"""Stubs of the native module ``lens._lens`` (hand-written; checked by
``mypy.stubtest`` in the tests)."""

import os
from typing import Any, Optional, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "LensError",
    "PrescriptionError",
    "GlassError",
    "OpticsError",
    "RenderError",
    "Prescription",
    "Glass",
    "load",
    "validate_file",
    "trace",
    "glass",
    "fan",
    "spot",
    "wavefront",
    "mtf",
    "psf",
    "coc",
    "chromatic",
    "render",
    "_tolerance_share",
    "_tolerance_summary",
    "STATUS_NAMES",
]

STATUS_NAMES: list[str]

class LensError(Exception): ...
class PrescriptionError(LensError): ...
class GlassError(LensError): ...
class OpticsError(LensError): ...
class RenderError(LensError): ...

_Path = Union[str, "os.PathLike[str]"]
_Film = Union[None, str, float]

@final
class Prescription:
    """A lens prescription (lengths in mm), validated, at one wavelength."""

    @property
    def name(self) -> str: ...
    @property
    def wavelength_nm(self) -> float: ...
    @property
    def wavelengths_nm(self) -> list[float]: ...
    @property
    def primary_wavelength_nm(self) -> float: ...
    @property
    def fields_deg(self) -> list[float]: ...
    @property
    def surface_count(self) -> int: ...
    @property
    def film_distance_mm(self) -> float: ...
    def info(
        self, wavelength_nm: Optional[float] = None, object_distance_mm: Optional[float] = None
    ) -> dict[str, Any]: ...
    def validate(self) -> list[dict[str, Any]]: ...
    def with_f_number(self, f_number: float) -> Prescription: ...
    def at_wavelength(self, wavelength_nm: float) -> Prescription: ...
    def to_json(self) -> str: ...

@final
class Glass:
    """A catalogue glass."""

    @property
    def name(self) -> str: ...
    @property
    def nd(self) -> float: ...
    @property
    def vd(self) -> float: ...
    @property
    def range_nm(self) -> tuple[float, float]: ...
    def index(self, wavelength_nm: Union[float, npt.NDArray[np.float64]], strict: bool = False) -> Any: ...

def load(path: _Path) -> Prescription: ...
def validate_file(path: _Path) -> dict[str, Any]: ...
def glass(name: str) -> Glass: ...
def trace(
    prescription: Prescription,
    rays: npt.NDArray[np.float64],
    wavelength_nm: Union[None, float, npt.NDArray[np.float64]] = None,
    threads: Optional[int] = None,
    out: Optional[tuple[npt.NDArray[np.float64], npt.NDArray[np.uint8]]] = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint8]]: ...
def fan(
    prescription: Prescription,
    field_deg: float = 0.0,
    points: int = 21,
    wavelength_nm: Optional[float] = None,
    aim: str = "auto",
    film: _Film = None,
    threads: Optional[int] = None,
    field_x_deg: float = 0.0,
) -> dict[str, Any]: ...
def spot(
    prescription: Prescription,
    field_deg: float = 0.0,
    pattern: str = "gauss",
    n: int = 12,
    wavelength_nm: Optional[float] = None,
    aim: str = "auto",
    film: _Film = None,
    threads: Optional[int] = None,
    field_x_deg: float = 0.0,
) -> dict[str, Any]: ...
def wavefront(
    prescription: Prescription,
    field_deg: float = 0.0,
    wavelength_nm: Optional[float] = None,
    aim: str = "auto",
    film: _Film = None,
    grid: Optional[int] = None,
    samples: bool = False,
    threads: Optional[int] = None,
    field_x_deg: float = 0.0,
) -> dict[str, Any]: ...
def mtf(
    prescription: Prescription,
    frequencies: list[float],
    field_deg: float = 0.0,
    wavelength_nm: Optional[float] = None,
    polychromatic: bool = False,
    aim: str = "auto",
    film: _Film = None,
    threads: Optional[int] = None,
    field_x_deg: float = 0.0,
) -> dict[str, Any]: ...
def psf(
    prescription: Prescription,
    field_deg: float = 0.0,
    wavelength_nm: Optional[float] = None,
    method: str = "fft",
    pad: int = 4,
    pixels: int = 64,
    grid: Optional[int] = None,
    polychromatic: bool = False,
    aim: str = "auto",
    film: _Film = None,
    threads: Optional[int] = None,
    field_x_deg: float = 0.0,
) -> dict[str, Any]: ...
def coc(
    prescription: Prescription,
    focus_mm: float,
    distances: list[float],
    wavelength_nm: Optional[float] = None,
    threads: Optional[int] = None,
) -> dict[str, Any]: ...
def chromatic(
    prescription: Prescription,
    field_deg: float = 0.0,
    max_field_deg: Optional[float] = None,
    aim: str = "auto",
    threads: Optional[int] = None,
) -> dict[str, Any]: ...
def render(
    scene: _Path,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    seed: int = 1,
    camera: Optional[str] = None,
    f_number: Optional[float] = None,
    aperture: Optional[float] = None,
    focal_length_mm: Optional[float] = None,
    focus_distance: Optional[float] = None,
    focus_shift: Optional[float] = None,
    aperture_shape: Optional[str] = None,
    prescription: Optional[_Path] = None,
    threads: Optional[int] = None,
    focus_on: Optional[Union[str, Tuple[float, float]]] = None,
    flare: Optional[str] = None,
    diffraction: Optional[Union[str, bool]] = None,
    coating: Optional[Union[str, list[Union[dict[str, float], Tuple[float, float]]]]] = None,
) -> npt.NDArray[np.float32]: ...
def _tolerance_share(
    spec: str,
    seed: int,
    trials: int,
    shard: int,
    shards: int,
    threads: Optional[int] = None,
) -> str: ...
def _tolerance_summary(spec: str, shares: list[str], seconds: float) -> dict[str, Any]: ...
