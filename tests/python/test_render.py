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
