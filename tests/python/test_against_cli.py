"""The package against the CLI's --json on every shipped lens: the same
keys and the same numbers to the last bit (the same library calls build
both), or the same error where the CLI refuses."""

import numpy as np
import pytest

import lens
from conftest import SHIPPED, cli, cli_json


def plain(v):
    """A package result as JSON-like Python values (arrays to lists)."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, dict):
        return {k: plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [plain(x) for x in v]
    return v


def check(py_call, *cli_args):
    """The package's call and the CLI's JSON agree, or both refuse with
    the same message."""
    expected, stderr = cli_json(*cli_args)
    if expected is None:
        with pytest.raises(lens.LensError) as e:
            py_call()
        assert str(e.value) in stderr, (str(e.value), stderr)
        return None
    got = plain(py_call())
    assert got == expected
    return got


def name(p):
    return p.relative_to(p.parents[1]).as_posix()


@pytest.mark.parametrize("path", SHIPPED, ids=name)
def test_info(path):
    p = lens.load(path)
    check(lambda: p.info(), "info", str(path))
    check(lambda: p.info(wavelength_nm=486.1327, object_distance_mm=2000.0),
          "info", str(path), "--wavelength-nm", "486.1327", "--object-distance", "2000")


@pytest.mark.parametrize("path", SHIPPED, ids=name)
def test_fan_and_spot(path):
    p = lens.load(path)
    field = p.fields_deg[-1] / 2 if p.fields_deg else 5.0
    check(lambda: lens.fan(p, field_deg=field, points=11), "fan", str(path), "--field-deg", repr(field), "--points", "11")
    check(lambda: lens.spot(p, field_deg=field), "spot", str(path), "--field-deg", repr(field))
    check(lambda: lens.spot(p, wavelength_nm=656.2725, pattern="hexapolar", n=6, film="paraxial"),
          "spot", str(path), "--wavelength-nm", "656.2725", "--pattern", "hexapolar", "--n", "6", "--film", "paraxial")


@pytest.mark.parametrize("path", SHIPPED, ids=name)
def test_wave(path):
    p = lens.load(path)
    got = check(lambda: lens.wavefront(p, grid=32), "wavefront", str(path), "--grid", "32")
    if got is not None:
        assert len(got["zernike_fringe"]) == 37
    check(lambda: lens.mtf(p, [10.0, 20.0]), "mtf", str(path), "--frequencies", "10,20")


def test_off_axis_wave_and_polychromatic_mtf():
    path = "lens-data/double-gauss-50mm.json"
    p = lens.load(path)
    check(lambda: lens.wavefront(p, field_deg=10.0, aim="real", samples=True),
          "wavefront", path, "--field-deg", "10", "--aim", "real", "--samples")
    check(lambda: lens.mtf(p, [10.0, 30.0], field_deg=14.0, polychromatic=True),
          "mtf", path, "--frequencies", "10,30", "--field-deg", "14", "--polychromatic")


def test_fields_in_x_are_the_cli_flag():
    # a lens with an element decentred: x fields differ from y fields there
    import json, os, tempfile
    spec = json.load(open("lens-data/cooke-triplet.json"))
    spec["elements"] = [{"surfaces": [3, 4], "decenter_mm": [0.1, -0.05], "tilt_deg": [0.2, 0.1]}]
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "moved.json")
        json.dump(spec, open(path, "w"))
        p = lens.load(path)
        args = ("--field-x-deg", "6", "--field-deg", "-4")
        got = check(lambda: lens.fan(p, field_deg=-4.0, field_x_deg=6.0, points=7), "fan", path, "--points", "7", *args)
        assert got["field_x_deg"] == 6.0
        check(lambda: lens.spot(p, field_deg=-4.0, field_x_deg=6.0), "spot", path, *args)
        check(lambda: lens.wavefront(p, field_deg=-4.0, field_x_deg=6.0), "wavefront", path, *args)
        check(lambda: lens.mtf(p, [20.0], field_deg=-4.0, field_x_deg=6.0), "mtf", path, "--frequencies", "20", *args)
        with pytest.raises(ValueError, match="field_x_deg=95"):
            lens.spot(p, field_x_deg=95.0)


def test_with_f_number_is_the_cli_flag():
    path = "lens-data/double-gauss-50mm.json"
    p = lens.load(path).with_f_number(4.0)
    check(lambda: p.info(), "info", path, "--f-number", "4")


def test_validate_file_and_findings():
    path = "lens-data/double-gauss-50mm.json"
    expected, _ = cli_json("validate", path)
    assert lens.validate_file(path) == expected
    assert lens.load(path).validate() == expected["findings"]


def test_glass_index_is_the_cli():
    g = lens.glass("SCHOTT:N-BK7")
    for nm in (404.6561, 587.5618, 1013.98):
        expected, _ = cli_json("glass", "SCHOTT:N-BK7", "--wavelength-nm", repr(nm))
        assert g.index(nm) == expected["n"]
    assert (g.nd, g.vd, g.name) == (expected["nd"], expected["vd"], "SCHOTT:N-BK7")
    nm = np.linspace(400.0, 700.0, 301)
    n = g.index(nm)
    assert n.shape == nm.shape and n.dtype == np.float64
    assert all(n[i] == g.index(float(nm[i])) for i in range(0, 301, 30))
    assert g.index(nm.reshape(7, 43)).shape == (7, 43)


@pytest.mark.parametrize("path", SHIPPED, ids=name)
def test_coc_and_chromatic(path):
    p = lens.load(path)
    check(lambda: lens.coc(p, 2000.0, [1000.0, 5000.0, float("inf")]),
          "coc", str(path), "--focus-mm", "2000", "--distances", "1000,5000,inf")
    check(lambda: lens.chromatic(p), "chromatic", str(path))


def test_psf_fft_huygens_polychromatic():
    path = "lens-data/double-gauss-50mm.json"
    p = lens.load(path)
    for call, args in [
        (lambda: lens.psf(p, field_deg=10.0), ("--field-deg", "10")),
        (lambda: lens.psf(p, method="huygens", pixels=32, grid=48), ("--method", "huygens", "--pixels", "32", "--grid", "48")),
        (lambda: lens.psf(p, field_deg=5.0, polychromatic=True, pad=3), ("--field-deg", "5", "--polychromatic", "--pad", "3")),
    ]:
        result = call()
        image = result.pop("intensity")
        assert image.shape == (result["size"], result["size"]) and image.dtype == np.float64
        assert image.max() == result["peak"]
        check(lambda: result, "psf", path, *args)
    with pytest.raises(lens.OpticsError, match="FFT"):
        lens.psf(p, method="huygens", polychromatic=True)
    with pytest.raises(lens.OpticsError, match="2 to 64"):
        lens.psf(p, pad=1)


def test_threads_do_not_change_a_bit():
    p = lens.load("lens-data/double-gauss-50mm.json")
    one = plain(lens.wavefront(p, field_deg=10.0, threads=1))
    assert plain(lens.wavefront(p, field_deg=10.0, threads=2)) == one
    assert plain(lens.mtf(p, [10.0, 40.0], field_deg=10.0, threads=1)) == plain(lens.mtf(p, [10.0, 40.0], field_deg=10.0, threads=2))
    assert plain(lens.spot(p, field_deg=10.0, threads=1)) == plain(lens.spot(p, field_deg=10.0, threads=2))


def test_zemax_files_load(tmp_path):
    zmx = tmp_path / "double-gauss.zmx"
    assert cli("convert", "lens-data/double-gauss-50mm.json", "-o", str(zmx)).returncode == 0
    p = lens.load(zmx)
    check(lambda: p.info(), "info", str(zmx))
    check(lambda: lens.spot(p, field_deg=7.0), "spot", str(zmx), "--field-deg", "7.0")
