"""Writes the spectral demonstration scenes into lens-data/scenes/:

- chromatic-bokeh-{singlet,achromat,double-gauss}.json: rows of small white
  lamps in front of focus, at focus and behind it, through an N-BK7
  singlet, the F-C achromat (both 100 mm f/5) and the double Gauss (50 mm
  at f/2.8): the chromatic bokeh chart;
- wu-aberrations-double-gauss.json: lamps across the whole frame behind
  focus, the double Gauss wide open (coma, cat's eye, astigmatism,
  chromatic rims: after Wu et al. 2010 and 2013);
- wu-spherical-{front,behind}.json: one lamp in front of and behind focus
  through a fast plano-convex singlet (bright rim on one side, bright core
  on the other);
- lateral-colour-edge.json: a black-and-white chart filling the frame of
  the landscape singlet (lateral colour grows toward the corners);
- prism.json: a white slit seen through a 60-degree prism of SCHOTT N-SF11
  beside the slit seen directly.

Positions are computed from each lens's focal length and sensor so the
lamps land where the picture wants them. Scenes are in metres.

    python3 tools/spectral_scenes.py
"""
import json
import math
import os

OUT = os.path.join(os.path.dirname(__file__), "..", "lens-data", "scenes")


def write(name, scene):
    with open(os.path.join(OUT, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def lens_scene(name, lens, focus, sensor, size, spp, radiance, shapes, f_number=None, background=0.002):
    """A scene of white lamps (`shapes`, material "lamp") seen through the
    real lens `lens` focused at `focus` m, on a dark background."""
    write(
        name,
        {
            "camera": {
                "type": "lens",
                "prescription": "../" + lens,
                "f_number": f_number,
                "focus_distance": focus,
                "sensor_mm": sensor,
                "position": [0, 0, 0],
                "look_at": [0, 0, 1],
            },
            "film": {"width": size[0], "height": size[1], "spp": spp, "exposure": 1.0},
            "background": {"type": "constant", "radiance": [background] * 3},
            "materials": {"lamp": {"type": "emissive", "radiance": [radiance] * 3}},
            "shapes": shapes,
        },
    )


def lamp_rows(f_mm, sensor, focus, rows, radius_px, px_mm, radiance):
    """Lamps on rows of the frame: each row (v, distance m, count) puts
    `count` lamps across the frame at film height v (fraction of the
    half-height, + up) at `distance` metres; each lamp's image is
    `radius_px` pixels in radius (before blur)."""
    shapes = []
    for v, dist, count in rows:
        y_film = v * sensor[1] / 2
        for k in range(count):
            u = -0.8 + 1.6 * k / max(count - 1, 1)
            x_film = u * sensor[0] / 2
            # the lens maps angle to film height by about f tan(angle)
            x = dist * x_film / f_mm
            y = dist * y_film / f_mm
            r = dist * radius_px * px_mm / f_mm
            shapes.append({"type": "sphere", "center": [x, y, dist], "radius": r, "material": "lamp"})
    return shapes


def chart(lens, f_mm, f_number, name):
    width, height = 960, 360
    sensor = [9.6 * f_mm / 100.0, 3.6 * f_mm / 100.0]
    px = sensor[0] / width
    focus = 2.0
    rows = [(0.55, 4.0, 5), (0.0, focus, 5), (-0.55, 1.25, 5)]
    shapes = lamp_rows(f_mm, sensor, focus, rows, 9.0, px, None)
    lens_scene(name, lens, focus, sensor, (width, height), 256, 9, shapes, f_number)


def wu_field():
    f_mm, width, height = 50.36, 960, 640
    sensor = [36.0, 24.0]
    px = sensor[0] / width
    focus = 0.8
    shapes = []
    for j in range(5):
        v = -0.9 + 1.8 * j / 4
        for k in range(7):
            u = -0.92 + 1.84 * k / 6
            d = 12.0
            x = d * u * sensor[0] / 2 / f_mm
            y = d * v * sensor[1] / 2 / f_mm
            shapes.append({"type": "sphere", "center": [x, y, d], "radius": d * 4.0 * px / f_mm, "material": "lamp"})
    lens_scene("wu-aberrations-double-gauss.json", "double-gauss-50mm.json", focus, sensor, (width, height), 256, 16,
               shapes)


def wu_spherical():
    for side, dist in [("front", 0.5), ("behind", 3.0)]:
        lamp = {"type": "sphere", "center": [0, 0, dist], "radius": 0.0012 * dist, "material": "lamp"}
        lens_scene(f"wu-spherical-{side}.json", "plano-convex-n-bk7-50mm.json", 1.0, [1.8, 1.8], (480, 480), 256, 20,
                   [lamp], f_number=4.0, background=0.0)


def lateral_edge():
    """A backlit target 2 m away filling the frame of the landscape
    singlet: white squares on black, so every edge is a high-contrast one
    and only the lens makes noise."""
    d = 2.0
    f_mm = 100.0
    sensor = [24.0, 16.0]
    half_w = d * sensor[0] / 2 / f_mm * 1.1
    half_h = d * sensor[1] / 2 / f_mm * 1.1
    nx, ny = 9, 6
    cw, ch = 2 * half_w / nx, 2 * half_h / ny
    shapes = []
    for j in range(ny):
        for i in range(nx):
            if (i + j) % 2:
                continue
            shapes.append({
                "type": "quad",
                "corner": [-half_w + i * cw, -half_h + j * ch, d],
                "u": [0, ch, 0],
                "v": [cw, 0, 0],
                "material": "white",
            })
    write(
        "lateral-colour-edge.json",
        {
            "camera": {
                "type": "lens",
                "prescription": "../landscape-n-bk7-100mm.json",
                "focus_distance": d,
                "sensor_mm": sensor,
                "position": [0, 0, 0],
                "look_at": [0, 0, 1],
            },
            "film": {"width": 960, "height": 640, "spp": 64, "exposure": 1.0},
            "background": {"type": "constant", "radiance": [0.0, 0.0, 0.0]},
            "materials": {"white": {"type": "emissive", "radiance": [0.8, 0.8, 0.8]}},
            "shapes": shapes,
        },
    )


def refract2(d, n, eta):
    """2-D Snell: direction d through a surface of unit normal n (facing
    the incoming side), index ratio eta = n1 / n2."""
    cos_i = -(d[0] * n[0] + d[1] * n[1])
    k = 1 - eta * eta * (1 - cos_i * cos_i)
    c = eta * cos_i - math.sqrt(k)
    return (eta * d[0] + c * n[0], eta * d[1] + c * n[1])


def prism():
    """A 60-degree N-SF11 prism (axis vertical) 1 m in front of a pinhole,
    turned to minimum deviation at the d line for the camera's central
    ray; a white slit 2 m beyond it along the deviated ray (turned 1.5
    degrees, so the spectrum sits in the middle of the face), facing it;
    a second slit beside the prism, seen directly."""
    nd = 1.78472  # SCHOTT N-SF11 at the d line
    apex = math.radians(60)
    deviation = 2 * math.asin(nd * math.sin(apex / 2)) - apex
    incidence = (deviation + apex) / 2
    side, centre, height = 0.3, (0.0, 1.0), 0.3
    # equilateral triangle in (x, z); first face normal (outward, toward
    # the camera) at `incidence` from -z, the base toward +x
    def rot(v, a):
        return (v[0] * math.cos(a) - v[1] * math.sin(a), v[0] * math.sin(a) + v[1] * math.cos(a))
    r = side / math.sqrt(3)
    # vertices of a triangle whose face between v0, v1 faces -z, the apex
    # v2 toward -x, turned by the incidence angle
    base = [(r * math.cos(a), r * math.sin(a)) for a in (math.radians(30), math.radians(150), math.radians(270))]
    # face v0-v1 lies at z = +r/2 facing +z: flip to face -z
    base = [(x, -z) for x, z in base]
    verts = [rot(v, -incidence) for v in base]
    verts = [(x + centre[0], z + centre[1]) for x, z in verts]
    # the central ray through both faces (in the (x, z) plane)
    def normal(a, b):
        # outward normal of edge a-b of a triangle whose centroid is `centre`
        ex, ez = b[0] - a[0], b[1] - a[1]
        nx, nz = ez, -ex
        l = math.hypot(nx, nz)
        nx, nz = nx / l, nz / l
        mx, mz = (a[0] + b[0]) / 2 - centre[0], (a[1] + b[1]) / 2 - centre[1]
        return (nx, nz) if nx * mx + nz * mz > 0 else (-nx, -nz)
    n1 = normal(verts[0], verts[1])
    d = refract2((0.0, 1.0), n1, 1 / nd)
    faces = [(verts[1], verts[2]), (verts[2], verts[0])]
    # the exit face is the one the inner ray meets; try both
    exit_dir = None
    for a, b in faces:
        n2 = normal(a, b)
        if d[0] * n2[0] + d[1] * n2[1] > 0:
            try:
                out = refract2(d, (-n2[0], -n2[1]), nd)
            except ValueError:
                continue
            if exit_dir is None or abs(out[0]) > abs(exit_dir[0]):
                exit_dir = out
    l = math.hypot(*exit_dir)
    exit_dir = rot((exit_dir[0] / l, exit_dir[1] / l), math.radians(1.5))
    slit_c = (centre[0] + 2.0 * exit_dir[0], centre[1] + 2.0 * exit_dir[1])
    # the slit faces back along the ray: u vertical, v across
    across = (-exit_dir[1], exit_dir[0])
    w = 0.025
    u = [0, height * 1.2, 0]
    v = [across[0] * w, 0, across[1] * w]
    corner = [slit_c[0] - v[0] / 2, -height * 0.6, slit_c[1] - v[2] / 2]
    # front side = u x v must face the prism (against exit_dir)
    ux = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    if ux[0] * exit_dir[0] + ux[2] * exit_dir[1] > 0:
        u, v = v, u
    os.makedirs(os.path.join(OUT, "meshes"), exist_ok=True)
    with open(os.path.join(OUT, "meshes", "prism.obj"), "w") as f:
        f.write("# a 60-degree prism, axis vertical (tools/spectral_scenes.py)\n")
        for y in (-height / 2, height / 2):
            for x, z in verts:
                f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        # faces wound so that their normals point out of the prism
        def tri(a, b, c):
            f.write(f"f {a} {b} {c}\n")
        tri(1, 3, 2)
        tri(4, 5, 6)
        for i in range(3):
            j = (i + 1) % 3
            a, b, c, e = i + 1, j + 1, j + 4, i + 4
            tri(a, b, c)
            tri(a, c, e)
    write(
        "prism.json",
        {
            "camera": {"type": "pinhole", "position": [0, 0, 0], "look_at": [0.1, 0, 1], "fov_deg": 20},
            "film": {"width": 960, "height": 540, "spp": 256, "exposure": 1.0},
            "background": {"type": "constant", "radiance": [0.0, 0.0, 0.0]},
            "materials": {
                "slit": {"type": "emissive", "radiance": [3.0, 3.0, 3.0]},
                "glass": {"type": "dielectric", "glass": "SCHOTT:N-SF11"},
            },
            "shapes": [
                {"type": "mesh", "obj": "meshes/prism.obj", "material": "glass"},
                {"type": "quad", "corner": corner, "u": u, "v": v, "material": "slit"},
                {"type": "quad", "corner": [0.34, -height * 0.6, 1.6], "u": [0, height * 1.2, 0], "v": [w / 2, 0, 0],
                 "material": "slit"},
            ],
        },
    )


if __name__ == "__main__":
    chart("singlet-n-bk7-100mm.json", 100.0, None, "chromatic-bokeh-singlet.json")
    chart("achromat-fc-100mm.json", 100.0, None, "chromatic-bokeh-achromat.json")
    chart("double-gauss-50mm.json", 50.36, 2.8, "chromatic-bokeh-double-gauss.json")
    wu_field()
    wu_spherical()
    lateral_edge()
    prism()
