#!/usr/bin/env python3
"""An independent trace of the phone lens (lens-data/library/phone-5.6mm-
f3.5-us7535658.json) in 40-digit arithmetic (mpmath): four rays at 25
degrees through the entrance pupil (the stop, at the first vertex), at the
d line (where each model glass's index is its nd), to the film. The numbers
it prints are those crates/lens/tests/library.rs checks the tracer against.

    python3 tools/phone_lens_mpmath.py
"""
import json
import mpmath as mp

mp.mp.dps = 40
d = json.load(open("lens-data/library/phone-5.6mm-f3.5-us7535658.json"))
S = d["surfaces"]
for s in S:
    if "glass" in s:
        s["ior"] = s.pop("glass")["nd"]
def sag_and_grad(s, x, y):
    c = mp.mpf(1)/mp.mpf(s['radius']) if 'radius' in s else mp.mpf(0)
    k = mp.mpf(s.get('conic', 0))
    r2 = x*x + y*y; r = mp.sqrt(r2)
    q = 1 - (1+k)*c*c*r2
    z = c*r2/(1+mp.sqrt(q))
    dz = c*r/mp.sqrt(q) if c != 0 else mp.mpf(0)
    for j, a in enumerate(s.get('odd_aspheric', []), start=1):
        a = mp.mpf(a)
        z += a * r**j
        dz += j * a * r**(j-1)
    # gradient of F = z - sag: (-dz x/r, -dz y/r, 1)
    if r == 0:
        return z, (mp.mpf(0), mp.mpf(0), mp.mpf(1))
    return z, (-dz*x/r, -dz*y/r, mp.mpf(1))
def trace(p, dvec):
    zv = mp.mpf(0); n1 = mp.mpf(1)
    for s in S:
        # local frame: vertex at zv
        pl = [p[0], p[1], p[2]-zv]
        t = -pl[2]/dvec[2]
        for _ in range(200):
            x = pl[0]+t*dvec[0]; y = pl[1]+t*dvec[1]; z = pl[2]+t*dvec[2]
            sg, g = sag_and_grad(s, x, y)
            F = z - sg
            Fp = g[0]*dvec[0] + g[1]*dvec[1] + g[2]*dvec[2]
            dt = F/Fp; t -= dt
            if abs(dt) < mp.mpf(10)**-35: break
        x = pl[0]+t*dvec[0]; y = pl[1]+t*dvec[1]; z = pl[2]+t*dvec[2]
        sg, g = sag_and_grad(s, x, y)
        nn = mp.sqrt(g[0]**2+g[1]**2+g[2]**2); N = [gi/nn for gi in g]
        n2 = mp.mpf(s.get('ior', 1.0))
        mu = n1/n2; cosi = sum(a*b for a,b in zip(dvec, N))
        kk = 1 - mu*mu*(1-cosi*cosi)
        gg = mp.sqrt(kk) - mu*cosi
        dvec = [mu*dvec[i] + gg*N[i] for i in range(3)]
        p = [x, y, z+zv]
        zv += mp.mpf(s['thickness']); n1 = n2
    # propagate to film plane z = zv
    t = (zv - p[2])/dvec[2]
    return p[1] + t*dvec[1]
th = mp.radians(25)
dv = [mp.mpf(0), mp.sin(th), mp.cos(th)]
# the entrance pupil's radius: the stop's semi-diameter (the stop is the first surface)
rep = mp.mpf(S[0]["semi_diameter"])
for py in [-0.5, 0, 0.5, 0.98]:
    o = [mp.mpf(0), py*rep - 5*dv[1], -5*dv[2]]
    print(py, mp.nstr(trace(o, dv), 17))
