"""Real camera lenses from Python: prescriptions, exact ray tracing,
paraxial and wave optics, and renders through real lenses, numpy in and
out.

Every number comes from the Rust library behind the ``lens`` command; the
analyses return the dicts its ``--json`` prints (numeric lists as numpy
arrays). Lengths in prescriptions are mm, in scenes metres; wavelengths nm.

>>> import lens
>>> p = lens.load("lens-data/double-gauss-50mm.json")   # doctest: +SKIP
>>> round(p.info()["efl"], 3)                           # doctest: +SKIP
50.0
"""

import enum

from ._lens import (
    STATUS_NAMES,
    Glass,
    GlassError,
    LensError,
    OpticsError,
    Prescription,
    PrescriptionError,
    RenderError,
    chromatic,
    coc,
    fan,
    glass,
    load,
    mtf,
    psf,
    render,
    spot,
    trace,
    validate_file,
    wavefront,
)
from ._tolerance import tolerance



class Status(enum.IntEnum):
    """The status codes of :func:`trace`, one per ray (``STATUS_NAMES`` by
    value): ``status == lens.Status.REACHED`` picks the rays on the film."""

    REACHED = 0
    MISSED = 1
    BLOCKED = 2
    TOTAL_INTERNAL_REFLECTION = 3
    NOT_CONVERGED = 4


__all__ = [
    "STATUS_NAMES",
    "Status",
    "Glass",
    "GlassError",
    "LensError",
    "OpticsError",
    "Prescription",
    "PrescriptionError",
    "RenderError",
    "chromatic",
    "coc",
    "fan",
    "glass",
    "load",
    "mtf",
    "psf",
    "render",
    "spot",
    "tolerance",
    "trace",
    "validate_file",
    "wavefront",
]
