"""lens.render: a scene into numpy, with the CLI's overrides."""

import numpy as np

import lens


def test_render_into_numpy():
    img = lens.render("lens-data/scenes/bokeh-thin-circle.json", width=48, height=32, spp=2, threads=2)
    assert img.shape == (32, 48, 3) and img.dtype == np.float32
    assert np.isfinite(img).all() and img.max() > 0
    again = lens.render("lens-data/scenes/bokeh-thin-circle.json", width=48, height=32, spp=2, threads=1)
    assert np.array_equal(img, again)
    other = lens.render("lens-data/scenes/bokeh-thin-circle.json", width=48, height=32, spp=2, seed=7)
    assert not np.array_equal(img, other)


def test_real_lens_with_an_f_number():
    img = lens.render("lens-data/scenes/bokeh-double-gauss.json", width=40, height=24, spp=2, f_number=2.8)
    assert img.shape == (24, 40, 3) and np.isfinite(img).all()


def test_one_side_keeps_the_scenes_aspect():
    # the scene's film is 480 x 300; the width alone scales the height
    img = lens.render("lens-data/scenes/bokeh-double-gauss.json", width=96, spp=1)
    assert img.shape == (60, 96, 3)


def test_focus_on_a_pixel():
    # autofocus on a ball in the foreground: another picture than the far focus;
    # a pixel on the background and an unknown name are refused by field
    near = lens.render("lens-data/scenes/dof-study.json", width=32, height=18, spp=1, focus_on=(16, 10))
    far = lens.render("lens-data/scenes/dof-study.json", width=32, height=18, spp=1, focus_distance=30.0)
    assert near.shape == (18, 32, 3) and not np.array_equal(near, far)
    for bad in [(16, 0), "no such shape"]:
        try:
            lens.render("lens-data/scenes/dof-study.json", width=32, height=18, spp=1, focus_on=bad)
        except lens.RenderError as e:
            assert "camera.focus_on" in str(e)
        else:
            raise AssertionError(f"focus_on={bad!r} was rendered")
    try:
        lens.render("lens-data/scenes/dof-study.json", focus_on=(1, 2), focus_distance=3.0)
    except ValueError as e:
        assert "not both" in str(e)
    else:
        raise AssertionError("both were taken")


def test_flare_diffraction_and_coating_overrides():
    # the sun through a wide angle: ghosts add light off the sun's image,
    # bare glass makes them brighter, diffraction moves light without
    # making any; bad values are refused by name
    scene = "lens-data/scenes/flare-sun-wide-angle.json"
    kw = dict(width=96, spp=2, threads=2)
    off = lens.render(scene, flare="off", **kw)
    ghosts = lens.render(scene, flare="ghosts", **kw)
    bare = lens.render(scene, flare="ghosts", coating="none", **kw)
    layers = lens.render(scene, flare="ghosts", coating=[(1.38, 99.6)], **kw)
    assert np.isfinite(ghosts).all() and not np.array_equal(off, ghosts)
    halo = lambda img: float(np.abs(img - off).sum())  # noqa: E731
    assert halo(bare) > 2 * halo(ghosts) > 0
    assert 0.5 < halo(layers) / halo(ghosts) < 2.0
    spread = lens.render(scene, flare="off", diffraction=True, **kw)
    assert not np.array_equal(off, spread)
    assert abs(spread.sum() / off.sum() - 1.0) < 0.02
    assert np.array_equal(lens.render(scene, flare="off", diffraction="off", **kw), off)
    for bad in [dict(flare="lots"), dict(diffraction="maybe"), dict(coating="gold"),
                dict(coating=[{"index": 0.5, "thickness_nm": 100.0}])]:
        try:
            lens.render(scene, **kw, **bad)
        except ValueError as e:
            assert list(bad)[0] in str(e)
        else:
            raise AssertionError(f"{bad!r} was rendered")
