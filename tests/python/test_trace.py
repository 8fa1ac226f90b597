"""lens.trace: numpy in and out, per-ray wavelengths, threads, statuses
and the errors a wrong array gets."""

import json

import numpy as np
import pytest

import lens

DG = "lens-data/double-gauss-50mm.json"


def fan_of_rays(n=1001, angle_deg=5.0):
    """Parallel rays across the pupil at a field angle, from z = -20 mm."""
    t = np.radians(angle_deg)
    rays = np.zeros((n, 6))
    rays[:, 1] = np.linspace(-20.0, 20.0, n)
    rays[:, 2] = -20.0
    rays[:, 4] = np.sin(t)
    rays[:, 5] = np.cos(t)
    return rays


def test_shapes_dtypes_and_statuses():
    p = lens.load(DG)
    out, status = lens.trace(p, fan_of_rays())
    assert out.shape == (1001, 6) and out.dtype == np.float64
    assert status.shape == (1001,) and status.dtype == np.uint8
    reached = status == 0
    # the middle of the pupil passes, its rims are blocked by the apertures
    assert reached[500] and not reached[0] and not reached[-1]
    assert set(np.unique(status)) <= {0, 1, 2}
    assert lens.STATUS_NAMES[2] == "blocked"
    assert [s.name.lower() for s in lens.Status] == lens.STATUS_NAMES
    assert (status == lens.Status.BLOCKED).sum() == (status == 2).sum()
    # reached rays end on the film plane, with unit directions
    z_film = p.info()["total_track"]
    assert np.allclose(out[reached, 2], out[reached, 2][0])
    assert np.allclose(np.linalg.norm(out[:, 3:], axis=1), 1.0)
    assert z_film > 0


def test_threads_and_blocks_do_not_change_a_bit():
    p = lens.load(DG)
    rays = fan_of_rays(20000)
    a, sa = lens.trace(p, rays, threads=1)
    b, sb = lens.trace(p, rays, threads=2)
    assert np.array_equal(a, b) and np.array_equal(sa, sb)
    c, _ = lens.trace(p, rays[7:9000])
    assert np.array_equal(c, a[7:9000])


def test_per_ray_wavelengths_match_one_wavelength_each():
    p = lens.load(DG)
    rays = fan_of_rays(3000)
    nm = np.where(np.arange(3000) % 2 == 0, 486.1327, 656.2725)
    mixed, ms = lens.trace(p, rays, wavelength_nm=nm)
    for w in (486.1327, 656.2725):
        one, os_ = lens.trace(p, rays, wavelength_nm=w)
        pick = nm == w
        assert np.array_equal(mixed[pick], one[pick]) and np.array_equal(ms[pick], os_[pick])
    # the prescription's own wavelength is the default
    d, _ = lens.trace(p, rays)
    e, _ = lens.trace(p, rays, wavelength_nm=np.full(3000, p.wavelength_nm))
    assert np.array_equal(d, e)


def test_directions_are_normalised():
    p = lens.load(DG)
    rays = fan_of_rays(11)
    scaled = rays.copy()
    scaled[:, 3:] *= 3.0
    a, _ = lens.trace(p, rays)
    b, _ = lens.trace(p, scaled)
    assert np.allclose(a, b, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "rays, error, words",
    [
        (np.zeros((4, 6), dtype=np.float32), TypeError, "float64"),
        ([[0.0] * 6], TypeError, "float64 numpy array"),
        (np.zeros((4, 5)), ValueError, "(N, 6)"),
        (np.zeros((4, 12))[:, ::2], ValueError, "C-contiguous"),
        (np.asfortranarray(np.ones((4, 6))), ValueError, "C-contiguous"),
        (np.array([[0.0, 0.0, -10.0, 0.0, 0.0, 0.0]]), ValueError, "not zero"),
        (np.array([[np.nan, 0.0, -10.0, 0.0, 0.0, 1.0]]), ValueError, "finite"),
    ],
)
def test_bad_rays_are_refused_clearly(rays, error, words):
    p = lens.load(DG)
    with pytest.raises(error) as e:
        lens.trace(p, rays)
    assert words in str(e.value)


def test_bad_wavelengths_and_threads():
    p = lens.load(DG)
    rays = fan_of_rays(4)
    with pytest.raises(ValueError, match="one wavelength per ray"):
        lens.trace(p, rays, wavelength_nm=np.full(3, 550.0))
    with pytest.raises(ValueError, match="positive"):
        lens.trace(p, rays, wavelength_nm=np.array([550.0, -1.0, 550.0, 550.0]))
    with pytest.raises(ValueError, match="positive"):
        lens.trace(p, rays, wavelength_nm=0.0)
    with pytest.raises(ValueError, match="threads=0"):
        lens.trace(p, rays, threads=0)
    # outside the glasses' data: extrapolated, as Zemax does, with a warning
    with pytest.warns(RuntimeWarning, match="outside its data"):
        lens.trace(p, rays, wavelength_nm=np.full(4, 3000.0))


def test_out_arrays_are_written_in_place():
    p = lens.load(DG)
    rays = fan_of_rays(5000)
    fresh, fresh_status = lens.trace(p, rays)
    ends, codes = np.full((5000, 6), np.nan), np.full(5000, 255, dtype=np.uint8)
    got, got_status = lens.trace(p, rays, out=(ends, codes))
    assert got is ends and got_status is codes
    assert np.array_equal(ends, fresh) and np.array_equal(codes, fresh_status)
    with pytest.raises(ValueError, match="shapes"):
        lens.trace(p, rays, out=(np.zeros((10, 6)), codes))
    with pytest.raises(TypeError, match="uint8"):
        lens.trace(p, rays, out=(ends, np.zeros(5000)))
    with pytest.raises(ValueError, match="shapes"):
        lens.trace(p, rays, out=(np.asfortranarray(ends), codes))
    with pytest.raises(ValueError, match="shares memory"):
        lens.trace(p, rays, out=(rays, codes))


def test_decentred_and_tilted_lenses(tmp_path):
    """A moved element is traced (a whole lens decentred lands rays that
    much over), kept by to_json, said by info; the analyses that assume a
    symmetric lens raise OpticsError naming themselves."""
    spec = json.load(open(DG))
    n = len(spec["surfaces"])
    spec["elements"] = [{"surfaces": [1, n], "decenter_mm": [0.3, -0.2]}]
    path = tmp_path / "moved.json"
    path.write_text(json.dumps(spec))
    straight, moved = lens.load(DG), lens.load(path)
    assert moved.info()["tilted"] and not straight.info()["tilted"]
    assert json.loads(moved.to_json())["elements"] == spec["elements"]
    rays = fan_of_rays(201, 3.0)
    shifted = rays.copy()
    shifted[:, 0] -= 0.3
    shifted[:, 1] += 0.2
    a, sa = lens.trace(straight, shifted)
    b, sb = lens.trace(moved, rays)
    ok = (sa == 0) & (sb == 0)
    assert ok.sum() > 100
    np.testing.assert_allclose(b[ok, 0] - a[ok, 0], 0.3, atol=1e-11)
    np.testing.assert_allclose(b[ok, 1] - a[ok, 1], -0.2, atol=1e-11)
    lens.fan(moved, field_deg=5)
    with pytest.raises(lens.OpticsError, match="symmetric about its axis"):
        lens.coc(moved, focus_mm=2000.0, distances=[1000.0])
