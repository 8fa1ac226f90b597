# Cross-check of colour against optiland (pip install optiland): for every
# shipped lens with glasses, EFL and BFL at several wavelengths (optiland's
# primary set to each), and the tangential and sagittal fans of
# `lens fan --wavelength-nm W --json` (rays of W from the d-line entrance
# pupil onto the d-line paraxial image plane) traced by optiland at W.
# Catalogue glasses come from optiland's own copy of the refractiveindex.info
# database (the file of that exact name); model glasses (nd, vd) are given to optiland as the index our
# formula gives at each wavelength. Not part of the tests; run after
# `cargo build --release`: python3 -W ignore tools/crosscheck_optiland_glass.py
import glob, json, os, subprocess
import numpy as np
from optiland import optic
import optiland
from optiland.materials import IdealMaterial, MaterialFile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target/release/lens")
D, F, C = 587.5618, 486.1327, 656.2725
WAVELENGTHS = [450.0, F, 546.074, D, C, 700.0]


def model_index(nd, vd, nm):
    # docs/glass.md: n = nd + B (1/l^2 - 1/ld^2), B = (nd - 1) / (vd (1/lF^2 - 1/lC^2)), l in um
    inv = lambda w: 1.0 / ((w * 1e-3) ** 2)
    b = (nd - 1.0) / (vd * (inv(F) - inv(C)))
    return nd + b * (inv(nm) - inv(D))


def material(s, nm):
    g = s.get("glass")
    if g is None:
        return IdealMaterial(n=s.get("ior", 1.0))
    if isinstance(g, dict):
        return IdealMaterial(n=model_index(g["nd"], g["vd"], nm))
    # the exact file: optiland's search by name takes SF5 for N-SF5
    vendor, name = g.split(":")
    db = os.path.join(os.path.dirname(optiland.__file__), "database/data-nk/glass")
    return MaterialFile(os.path.join(db, vendor.lower(), name + ".yml"))


def build(d, primary_nm, last_thickness=None, fields=(0.0,)):
    o = optic.Optic()
    o.add_surface(index=0, radius=np.inf, thickness=np.inf)
    n = len(d["surfaces"])
    for i, s in enumerate(d["surfaces"]):
        t = s["thickness"] if (i < n - 1 or last_thickness is None) else last_thickness
        o.add_surface(index=i + 1, radius=s.get("radius") or np.inf, thickness=t,
                      material=material(s, primary_nm), is_stop=s.get("stop", False))
    o.add_surface(index=n + 1)
    stop = [s for s in d["surfaces"] if s.get("stop")][0]
    o.set_aperture(aperture_type="float_by_stop_size", value=2 * stop["semi_diameter"])
    o.set_field_type(field_type="angle")
    for f in fields:
        o.add_field(y=f)
    o.add_wavelength(value=primary_nm * 1e-3, is_primary=True)
    return o


worst = {"efl": 0.0, "bfl": 0.0, "fan": 0.0}
for path in sorted(glob.glob(os.path.join(ROOT, "lens-data/*.json"))):
    d = json.load(open(path))
    if not any("glass" in s for s in d["surfaces"]):
        continue
    name = os.path.basename(path)
    models = any(isinstance(s.get("glass"), dict) for s in d["surfaces"])
    z_last = sum(s["thickness"] for s in d["surfaces"][:-1])
    for nm in WAVELENGTHS:
        ours = json.loads(subprocess.check_output([LENS, "info", path, "--wavelength-nm", str(nm), "--json"]))
        o = build(d, nm)
        efl = float(np.ravel(o.paraxial.f2())[0])
        bfl = float(np.ravel(o.paraxial.F2())[0]) + d["surfaces"][-1]["thickness"]
        e = (abs(ours["efl"] - efl) / abs(efl), abs(ours["bfl"] - bfl) / abs(bfl))
        worst["efl"], worst["bfl"] = max(worst["efl"], e[0]), max(worst["bfl"], e[1])
        print(f"{name:<28} {nm:8.3f} nm  efl {ours['efl']:.9f} vs {efl:.9f} (rel {e[0]:.1e})  bfl {ours['bfl']:.9f} vs {bfl:.9f} (rel {e[1]:.1e})")
        if models and nm != D:
            # optiland takes one index per surface: a model glass at another
            # wavelength than the primary cannot be traced there
            continue
        for field in [0.0, 5.0]:
            fan = json.loads(subprocess.check_output(
                [LENS, "fan", path, "--field-deg", str(field), "--points", "11", "--wavelength-nm", str(nm), "--json"]))
            o = build(d, D, fan["image_z"] - z_last, fields=(0.0, field) if field > 0 else (0.0,))
            o.add_wavelength(value=nm * 1e-3)
            hy = 1.0 if field > 0 else 0.0
            for row in fan["tangential"] + fan["sagittal"]:
                if row["y"] is None:
                    continue
                px, py = row.get("px", 0.0), row.get("py", 0.0)
                r = o.trace_generic(Hx=0.0, Hy=hy, Px=px, Py=py, wavelength=nm * 1e-3)
                diff = max(abs(float(np.ravel(r.y)[0]) - row["y"]), abs(float(np.ravel(r.x)[0]) - row["x"]))
                worst["fan"] = max(worst["fan"], diff)
                if diff > 1e-9:
                    print(f"  {name} {nm} nm field {field}: pupil ({px}, {py}) differs by {diff:.2e} mm")
print("worst: efl rel {efl:.1e}, bfl rel {bfl:.1e}, fan abs {fan:.1e} mm".format(**worst))
