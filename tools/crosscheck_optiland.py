# Cross-check of first-order numbers against optiland (pip install optiland).
# Not part of the test suite (the tests need no Python); run after
# `cargo build --release`: python3 -W ignore tools/crosscheck_optiland.py
import glob, json, os, subprocess
import numpy as np
from optiland import optic
from optiland.materials import IdealMaterial
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target/release/lens")
rows = []
for path in sorted(glob.glob(os.path.join(ROOT, "lens-data/*.json"))):
    d = json.load(open(path))
    o = optic.Optic()
    o.add_surface(index=0, radius=np.inf, thickness=np.inf)
    for i, s in enumerate(d["surfaces"]):
        kw = dict(index=i + 1, radius=s.get("radius") or np.inf, thickness=s["thickness"],
                  material=IdealMaterial(n=s.get("ior", 1.0)), is_stop=s.get("stop", False))
        o.add_surface(**kw)
    o.add_surface(index=len(d["surfaces"]) + 1)
    stop = [s for s in d["surfaces"] if s.get("stop")][0]
    o.set_aperture(aperture_type="float_by_stop_size", value=2 * stop["semi_diameter"])
    o.set_field_type(field_type="angle")
    o.add_field(y=0)
    o.add_wavelength(value=0.5876, is_primary=True)
    ours = json.loads(subprocess.check_output([LENS, "info", path, "--json"]))
    p = o.paraxial
    z_img = sum(s["thickness"] for s in d["surfaces"])
    z_last = z_img - d["surfaces"][-1]["thickness"]
    theirs = {
        "efl": float(np.ravel(p.f2())[0]),
        "bfl": float(np.ravel(p.F2())[0]) + z_img - z_last,  # optiland: F2 from the image plane
        "ep_z": float(np.ravel(p.EPL())[0]),
        "ep_d": float(np.ravel(p.EPD())[0]),
        "xp_z": float(np.ravel(p.XPL())[0]) + z_img,
        "xp_d": float(np.ravel(p.XPD())[0]),
        "fno": float(np.ravel(p.FNO())[0]),
    }
    mine = {"efl": ours["efl"], "bfl": ours["bfl"], "ep_z": ours["entrance_pupil"]["z"], "ep_d": ours["entrance_pupil"]["diameter"],
            "xp_z": ours["exit_pupil"]["z"], "xp_d": ours["exit_pupil"]["diameter"], "fno": ours["f_number"]}
    for k in mine:
        if theirs.get(k) is None: continue
        rel = abs(mine[k] - theirs[k]) / max(abs(theirs[k]), 1e-300)
        rows.append((path.split("/")[-1], k, mine[k], theirs[k], rel))
w = max(len(r[0]) for r in rows)
for r in rows:
    print(f"{r[0]:<{w}} {r[1]:<5} ours {r[2]: .12f} optiland {r[3]: .12f} rel {r[4]:.1e}")
print("max rel diff:", max(r[4] for r in rows))
