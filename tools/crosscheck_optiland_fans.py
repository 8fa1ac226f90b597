# Cross-check of ray fans against optiland (pip install optiland): every ray of
# `lens fan --json` (paraxial aiming, the prescription's image surface, object
# at infinity; lenses of constant indices)
# is traced by optiland and the image positions compared. Not part of the
# tests; run after `cargo build --release`.
import json, subprocess, glob, os, sys
import numpy as np
from optiland import optic
from optiland.materials import IdealMaterial
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."); LENS = ROOT + "/target/release/lens"
worst = 0.0
for path in sorted(glob.glob(ROOT + "/lens-data/*.json")):
    d = json.load(open(path))
    if any("glass" in s for s in d["surfaces"]):
        continue  # constant indices only: optiland's IdealMaterial
    for field in [0.0, 5.0, 10.0]:
        fan = json.loads(subprocess.check_output([LENS, "fan", path, "--field-deg", str(field), "--points", "11", "--json"]))
        o = optic.Optic()
        o.add_surface(index=0, radius=np.inf, thickness=np.inf)
        for i, s in enumerate(d["surfaces"]):
            z_last = sum(x["thickness"] for x in d["surfaces"][:-1])
            t = s["thickness"] if i < len(d["surfaces"]) - 1 else fan["image_z"] - z_last
            o.add_surface(index=i + 1, radius=s.get("radius") or np.inf, thickness=t,
                          material=IdealMaterial(n=s.get("ior", 1.0)), is_stop=s.get("stop", False))
        o.add_surface(index=len(d["surfaces"]) + 1)
        stop = [s for s in d["surfaces"] if s.get("stop")][0]
        o.set_aperture(aperture_type="float_by_stop_size", value=2 * stop["semi_diameter"])
        o.set_field_type(field_type="angle")
        o.add_field(y=0.0)
        if field > 0: o.add_field(y=field)
        o.add_wavelength(value=0.5876, is_primary=True)
        hy = 1.0 if field > 0 else 0.0
        for row in fan["tangential"]:
            if row["y"] is None: continue
            rays = o.trace_generic(Hx=0.0, Hy=hy, Px=0.0, Py=row["py"], wavelength=0.5876)
            y = float(np.ravel(rays.y)[0]); x = float(np.ravel(rays.x)[0])
            diff = max(abs(y - row["y"]), abs(x - row["x"]))
            worst = max(worst, diff)
            if diff > 1e-9: print(os.path.basename(path), field, "py", row["py"], row["y"], y, diff)
        for row in fan["sagittal"]:
            if row["x"] is None: continue
            rays = o.trace_generic(Hx=0.0, Hy=hy, Px=row["px"], Py=0.0, wavelength=0.5876)
            y = float(np.ravel(rays.y)[0]); x = float(np.ravel(rays.x)[0])
            diff = max(abs(y - row["y"]), abs(x - row["x"]))
            worst = max(worst, diff)
            if diff > 1e-9: print(os.path.basename(path), field, "px", row["px"], row["x"], x, diff)
print("worst abs difference (mm):", worst)
