# Designs lens-data/achromat-fc-100mm.json: a cemented N-BK7 / SF5 doublet
# of 100 mm focal length whose F and C paraxial foci coincide (the classic
# achromat), from the thin-lens achromat condition f1 V1 + f2 V2 = 0 with an
# equiconvex crown, then the rear radius refined on the thick lens (by
# bisection, with `lens info --wavelength-nm`) until the F and C back focal
# lengths agree to 1e-9 mm, and the whole scaled to EFL 100 mm at d. Run
# after `cargo build --release`: python3 tools/design_achromat.py
import json, os, subprocess
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target/release/lens")
F, D, C = 486.1327, 587.5618, 656.2725

def glass(name):
    return json.loads(subprocess.check_output([LENS, "glass", name, "--json"]))

def lens(r1, r2, r3, t1, t2, bfl):
    return {"name": "Cemented achromat f=100mm f/5, F and C foci together",
            "source": "designed here (tools/design_achromat.py): SCHOTT N-BK7 / SF5, thin-lens achromat condition, rear radius refined on the thick lens until the F and C paraxial foci coincide; film at the d focus",
            "units": "mm",
            "surfaces": [
                {"radius": r1, "thickness": t1, "glass": "SCHOTT:N-BK7", "semi_diameter": 10.0, "stop": True},
                {"radius": r2, "thickness": t2, "glass": "SCHOTT:SF5", "semi_diameter": 10.0},
                {"radius": r3, "thickness": bfl, "semi_diameter": 10.0}]}

def info(d, nm):
    path = "/tmp/achromat-design.json"
    json.dump(d, open(path, "w"))
    return json.loads(subprocess.check_output([LENS, "info", path, "--wavelength-nm", str(nm), "--json"]))

crown, flint = glass("SCHOTT:N-BK7"), glass("SCHOTT:SF5")
v1, v2 = crown["vd"], flint["vd"]
phi = 0.01
phi1, phi2 = phi * v1 / (v1 - v2), -phi * v2 / (v1 - v2)
r = 2 * (crown["nd"] - 1) / phi1
r3 = 1.0 / (-phi2 / (flint["nd"] - 1) - 1.0 / r)
t1, t2 = 5.0, 2.5
def colour(d, r3):
    e = json.loads(json.dumps(d)); e["surfaces"][2]["radius"] = r3
    return info(e, F)["bfl"] - info(e, C)["bfl"]

def unite_f_and_c(d, lo, hi):
    # the rear radius, by bisection, at which the F and C foci coincide
    assert colour(d, lo) * colour(d, hi) < 0, (colour(d, lo), colour(d, hi))
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if colour(d, lo) * colour(d, mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)

r3 = unite_f_and_c(lens(r, -r, r3, t1, t2, 100.0), r3 * 1.3, r3 * 0.7)
s = 100.0 / info(lens(r, -r, r3, t1, t2, 100.0), D)["efl"]
d = lens(round(r * s, 4), round(-r * s, 4), r3 * s, round(t1 * s, 4), round(t2 * s, 4), 100.0)
# rear radius again after rounding the others, then the film at the d focus
r3 = d["surfaces"][2]["radius"]
d["surfaces"][2]["radius"] = round(unite_f_and_c(d, r3 * 1.01, r3 * 0.99), 6)
d["surfaces"][2]["thickness"] = round(info(d, D)["bfl"], 6)
out = os.path.join(ROOT, "lens-data/achromat-fc-100mm.json")
with open(out, "w") as f:
    f.write(json.dumps(d, indent=2) + "\n")
print(out, "F-C focus difference", colour(d, d["surfaces"][2]["radius"]), "mm; efl", info(d, D)["efl"])
