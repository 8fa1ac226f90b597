#!/usr/bin/env python3
"""Independent traces of library lenses in 40-digit arithmetic (mpmath), at
the d line (where each model glass's index is its nd): the numbers
crates/lens/tests/library.rs checks the tracer against.

    python3 tools/mpmath_trace.py phone       # the phone lens, four rays at 25 degrees
    python3 tools/mpmath_trace.py wide-zoom   # the 14.42 mm zoom end's chief ray at 57.68 degrees

Surfaces: conic plus even (`aspheric`: r^2, r^4, ...) or odd (`odd_aspheric`:
r^1, r^2, ...) polynomial terms, intersected by Newton's method to 1e-35 mm
and refracted by the vector Snell law at the exact normal.
"""
import json
import sys

import mpmath as mp

mp.mp.dps = 40


def load(path):
    surfaces = json.load(open(path))["surfaces"]
    for s in surfaces:
        if "glass" in s:
            s["ior"] = s.pop("glass")["nd"]
    return surfaces


def terms(s):
    """The polynomial's (power, coefficient) pairs."""
    even = [(2 * j, a) for j, a in enumerate(s.get("aspheric", []), start=1)]
    odd = [(j, a) for j, a in enumerate(s.get("odd_aspheric", []), start=1)]
    return even + odd


def sag_and_grad(s, x, y):
    c = mp.mpf(1) / mp.mpf(s["radius"]) if "radius" in s else mp.mpf(0)
    k = mp.mpf(s.get("conic", 0))
    r2 = x * x + y * y
    r = mp.sqrt(r2)
    q = 1 - (1 + k) * c * c * r2
    z = c * r2 / (1 + mp.sqrt(q))
    dz = c * r / mp.sqrt(q) if c != 0 else mp.mpf(0)
    for p, a in terms(s):
        a = mp.mpf(a)
        z += a * r**p
        dz += p * a * r ** (p - 1)
    # gradient of F = z - sag: (-dz x/r, -dz y/r, 1)
    if r == 0:
        return z, (mp.mpf(0), mp.mpf(0), mp.mpf(1))
    return z, (-dz * x / r, -dz * y / r, mp.mpf(1))


def trace(surfaces, p, dvec, film=None):
    """The ray from point p along unit dvec through every surface to the
    film plane, `film` mm behind the last vertex (default: its thickness):
    the point there and the direction."""
    zv = mp.mpf(0)
    n1 = mp.mpf(1)
    for s in surfaces:
        pl = [p[0], p[1], p[2] - zv]
        t = -pl[2] / dvec[2]
        for _ in range(200):
            x, y, z = (pl[i] + t * dvec[i] for i in range(3))
            sg, g = sag_and_grad(s, x, y)
            dt = (z - sg) / (g[0] * dvec[0] + g[1] * dvec[1] + g[2] * dvec[2])
            t -= dt
            if abs(dt) < mp.mpf(10) ** -35:
                break
        x, y, z = (pl[i] + t * dvec[i] for i in range(3))
        sg, g = sag_and_grad(s, x, y)
        nn = mp.sqrt(g[0] ** 2 + g[1] ** 2 + g[2] ** 2)
        n = [gi / nn for gi in g]
        n2 = mp.mpf(s.get("ior", 1.0))
        mu = n1 / n2
        cosi = sum(a * b for a, b in zip(dvec, n))
        gg = mp.sqrt(1 - mu * mu * (1 - cosi * cosi)) - mu * cosi
        dvec = [mu * dvec[i] + gg * n[i] for i in range(3)]
        p = [x, y, z + zv]
        zv += mp.mpf(s["thickness"])
        n1 = n2
    if film is not None:
        zv += mp.mpf(film) - mp.mpf(surfaces[-1]["thickness"])
    t = (zv - p[2]) / dvec[2]
    return [p[i] + t * dvec[i] for i in range(3)], dvec


def phone():
    surfaces = load("lens-data/library/phone-5.6mm-f3.5-us7535658.json")
    th = mp.radians(25)
    dv = [mp.mpf(0), mp.sin(th), mp.cos(th)]
    # the entrance pupil's radius: the stop's semi-diameter (the stop is the first surface)
    rep = mp.mpf(surfaces[0]["semi_diameter"])
    for py in [-0.5, 0, 0.5, 0.98]:
        o = [mp.mpf(0), py * rep - 5 * dv[1], -5 * dv[2]]
        print(py, mp.nstr(trace(surfaces, o, dv)[0][1], 17))


def wide_zoom():
    # the real chief ray at 57.68 degrees as the tracer's real aiming starts
    # it (test the_wide_zoom_traces_as_rayoptics_does), to the plane 21.36 mm
    # behind the last vertex
    surfaces = load("lens-data/library/nikkor-z-14-30mm-f4-wide-jp2019008031.json")
    o = [mp.mpf(0), mp.mpf("-31.814060035868994"), mp.mpf(-1)]
    dv = [mp.mpf(0), mp.mpf("0.8450752575720964"), mp.mpf("0.5346473688698513")]
    p, d = trace(surfaces, o, dv, film="21.36")
    print("y", mp.nstr(p[1], 20), "direction", mp.nstr(d[1], 20), mp.nstr(d[2], 20))


if __name__ == "__main__":
    {"phone": phone, "wide-zoom": wide_zoom}[sys.argv[1] if len(sys.argv) > 1 else "phone"]()
