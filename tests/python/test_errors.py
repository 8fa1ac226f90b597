"""Errors are lens.LensError subclasses carrying the library's message."""

import numpy as np
import pytest

import lens


def test_hierarchy():
    for e in (lens.PrescriptionError, lens.GlassError, lens.OpticsError, lens.RenderError):
        assert issubclass(e, lens.LensError)
    assert issubclass(lens.LensError, Exception)


def test_messages_say_what_to_change(tmp_path):
    with pytest.raises(lens.PrescriptionError, match="cannot read"):
        lens.load(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"surfaces": [{"radius": 10, "thickness": -5, "semi_diameter": 3}]}')
    with pytest.raises(lens.PrescriptionError):
        lens.load(bad)
    with pytest.raises(lens.GlassError, match="did you mean"):
        lens.glass("SCHOTT:N-BK77")
    p = lens.load("lens-data/double-gauss-50mm.json")
    with pytest.raises(lens.OpticsError, match="cutoff"):
        lens.mtf(p, [5000.0])
    with pytest.raises(ValueError, match="field_deg"):
        lens.fan(p, field_deg=95.0)
    with pytest.raises(ValueError, match="film"):
        lens.spot(p, film="somewhere")
    with pytest.raises(ValueError, match="aim"):
        lens.spot(p, aim="sideways")
    with pytest.raises(lens.OpticsError):
        p.with_f_number(-2.0)
    with pytest.raises(ValueError, match="positive"):
        lens.glass("SCHOTT:N-BK7").index(np.array([500.0, -3.0]))
    with pytest.raises(lens.RenderError):
        lens.render(tmp_path / "nothing.json")
