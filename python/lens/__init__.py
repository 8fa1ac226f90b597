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

__all__ = [
    "STATUS_NAMES",
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
    "trace",
    "validate_file",
    "wavefront",
]
