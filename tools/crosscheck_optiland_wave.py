# Cross-check of the wavefront (OPD to the exit pupil's reference sphere)
# against optiland 0.6.3 (pip install optiland==0.6.3): for each shipped
# lens of constant indices or model glasses, on and off axis, every sample
# of `lens wavefront --json --samples` (paraxial aiming, the prescription's
# image surface, object at infinity, clear apertures as optiland
# RadialApertures) is traced by optiland's chief-ray wavefront strategy
# through the same normalised pupil points and the OPDs compared, as are
# the rays each vignettes. Not part of the tests; run after
# `cargo build --release`: python3 -W ignore tools/crosscheck_optiland_wave.py
import glob, json, os, subprocess, sys
import numpy as np
from optiland import optic
from optiland.materials import IdealMaterial
from optiland.physical_apertures import RadialAperture
from optiland.distribution import BaseDistribution
from optiland.wavefront import Wavefront

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target/release/lens")
D, F, C = 587.5618, 486.1327, 656.2725


def model_index(nd, vd, nm):
    # docs/glass.md: n = nd + B (1/l^2 - 1/ld^2), B = (nd - 1) / (vd (1/lF^2 - 1/lC^2)), l in um
    inv = lambda w: 1.0 / ((w * 1e-3) ** 2)
    b = (nd - 1.0) / (vd * (inv(F) - inv(C)))
    return nd + b * (inv(nm) - inv(D))


def build(d, nm, field):
    o = optic.Optic()
    o.add_surface(index=0, radius=np.inf, thickness=np.inf)
    for i, s in enumerate(d["surfaces"]):
        g = s.get("glass")
        n = model_index(g["nd"], g["vd"], nm) if isinstance(g, dict) else s.get("ior", 1.0)
        kw = dict(index=i + 1, radius=s.get("radius") or np.inf, thickness=s["thickness"],
                  material=IdealMaterial(n=n), is_stop=s.get("stop", False))
        if "semi_diameter" in s:
            kw["aperture"] = RadialAperture(r_max=s["semi_diameter"])
        o.add_surface(**kw)
    o.add_surface(index=len(d["surfaces"]) + 1)
    stop = [s for s in d["surfaces"] if s.get("stop")][0]
    o.set_aperture(aperture_type="float_by_stop_size", value=2 * stop["semi_diameter"])
    o.set_field_type(field_type="angle")
    o.add_field(y=0.0)
    if field > 0:
        o.add_field(y=field)
    o.add_wavelength(value=nm * 1e-3, is_primary=True)
    return o


class Points(BaseDistribution):
    def __init__(self, x, y):
        super().__init__()
        self.x, self.y = np.asarray(x), np.asarray(y)

    def generate_points(self, num_points):
        pass


worst_opd, worst_rel, mismatched = 0.0, 0.0, 0
for path in sorted(glob.glob(os.path.join(ROOT, "lens-data/*.json"))):
    d = json.load(open(path))
    if any(isinstance(s.get("glass"), str) for s in d["surfaces"]) or any("conic" in s or "aspheric" in s for s in d["surfaces"]):
        continue  # catalogue glasses and aspheres: other scripts
    for field in [0.0, 5.0, 10.0]:
        try:
            ours = json.loads(subprocess.check_output(
                [LENS, "wavefront", path, "--field-deg", str(field), "--aim", "paraxial", "--json", "--samples"],
                stderr=subprocess.DEVNULL))
        except subprocess.CalledProcessError:
            print(f"{os.path.basename(path)} {field} deg: ours refused"); continue
        s = ours["samples"]
        o = build(d, ours["wavelength_nm"], field)
        hy = 1.0 if field > 0 else 0.0
        w = Wavefront(o, fields=[(0.0, hy)], wavelengths=[ours["wavelength_nm"] * 1e-3], distribution=Points(s["px"], s["py"]))
        data = w.get_data((0.0, hy), ours["wavelength_nm"] * 1e-3)
        theirs = np.asarray(data.opd)
        alive = np.asarray(data.intensity) > 0
        mine = np.array([np.nan if v is None else v for v in s["opd_waves"]])
        both = alive & np.isfinite(mine)
        vig = int(np.sum(alive != np.isfinite(mine)))
        if vig: print("   ours only blocked", int(np.sum(alive & ~np.isfinite(mine))), "optiland only blocked", int(np.sum(~alive & np.isfinite(mine))))
        diff = np.max(np.abs(mine[both] - theirs[both])) if both.any() else 0.0
        span = np.ptp(mine[both]) if both.any() else 1.0
        worst_opd = max(worst_opd, diff); worst_rel = max(worst_rel, diff / max(span, 1e-12)); mismatched += vig
        print(f"{os.path.basename(path):<34} {field:4.1f} deg: {both.sum():5d} rays, P-V {span:9.5f} waves, "
              f"largest |W ours - optiland| {diff:.2e} waves, vignetting differs at {vig} rays")
print(f"worst OPD difference {worst_opd:.2e} waves ({worst_rel:.1e} of the P-V); rays vignetted by one only: {mismatched}")

# Statistics against optiland's own (hexapolar rings, unweighted: its rings
# hold 6k rays at radius k/n, about uniform in area): RMS about the mean
# (optiland's OPD.rms() keeps the piston: printed too), P-V, and the
# Standard (Noll) Zernike terms of ZernikeOPD; optiland's spread over its
# ring counts is the tolerance.
from optiland.wavefront import OPD, ZernikeOPD
print()
print("statistics: ours (auto grid) against optiland at 24 / 48 / 96 rings")
for name, field in [("double-gauss-50mm.json", 0.0), ("double-gauss-50mm.json", 5.0), ("wide-angle-22mm.json", 10.0),
                    ("telephoto-250mm.json", 0.0), ("fisheye-10mm.json", 10.0)]:
    path = os.path.join(ROOT, "lens-data", name)
    d = json.load(open(path))
    ours = json.loads(subprocess.check_output([LENS, "wavefront", path, "--field-deg", str(field), "--aim", "paraxial", "--json"]))
    nm = ours["wavelength_nm"]
    o = build(d, nm, field)
    hy = 1.0 if field > 0 else 0.0
    rows = []
    for rings in [24, 48, 96]:
        opd = OPD(o, (0.0, hy), nm * 1e-3, num_rays=rings)
        data = opd.get_data((0.0, hy), nm * 1e-3)
        z = np.asarray(data.opd)[np.asarray(data.intensity) > 0]
        z_fit = ZernikeOPD(o, (0.0, hy), nm * 1e-3, num_rings=rings, zernike_type="noll", num_terms=37)
        rows.append((float(np.std(z)), float(np.ptp(z)), float(opd.rms()), np.asarray(z_fit.coeffs, dtype=float)))
    rms = [r[0] for r in rows]; pv = [r[1] for r in rows]
    zs = np.array([r[3] for r in rows])
    mine_z = np.array(ours["zernike_standard"])
    print(f"{name:<24} {field:4.1f} deg: RMS ours {ours['rms_waves']:.5f}, optiland {' / '.join(f'{v:.5f}' for v in rms)}"
          f" (its rms() with piston {rows[-1][2]:.5f}); P-V ours {ours['pv_waves']:.5f}, optiland {' / '.join(f'{v:.5f}' for v in pv)}")
    for j in [4, 7, 8, 11, 22]:
        print(f"      Noll Z{j:<2} ours {mine_z[j-1]: .5f}, optiland {' / '.join(f'{v: .5f}' for v in zs[:, j-1])}")

# The MTF against optiland's FFT MTF (1024 grid, 128 rays across, read
# between its bins by linear interpolation: its own error) and its
# SampledMTF (a 37-term Fringe fit of the wavefront, autocorrelated at the
# frequency): on axis, where the two conventions of the frequency scale meet
# (our cutoff from the real marginal ray is its FFT's max_freq).
from optiland.mtf import SampledMTF, FFTMTF
print()
print("MTF on axis: ours against optiland's FFT MTF (interpolated) and SampledMTF")
for name in ["double-gauss-50mm.json", "wide-angle-22mm.json", "telephoto-250mm.json"]:
    path = os.path.join(ROOT, "lens-data", name)
    d = json.load(open(path))
    ours = json.loads(subprocess.check_output(
        [LENS, "mtf", path, "--aim", "paraxial", "--frequencies", "10,20,40,80", "--json"]))
    o = build(d, ours["wavelength_nm"], 0.0)
    sampled = SampledMTF(o, (0.0, 0.0), "primary", num_rays=128).calculate_mtf([(0.0, f) for f in ours["frequencies_per_mm"]])
    fft = FFTMTF(o, fields=[(0.0, 0.0)], wavelength="primary", num_rays=128, grid_size=1024)
    ft, mt = np.asarray(fft.freq_tang[0]), np.asarray(fft.mtf[0][0])
    print(f"{name}: cutoff ours {ours['cutoff_per_mm']:.4f}, optiland FFT max_freq {float(fft.max_freq):.4f} cycles/mm")
    for i, f in enumerate(ours["frequencies_per_mm"]):
        print(f"  {f:5.0f} c/mm: ours {ours['tangential'][i]:.5f}, optiland FFT {np.interp(f, ft, mt):.5f}, "
              f"SampledMTF {float(np.ravel(sampled[i])[0]):.5f}")

# The Strehl ratio against optiland's FFT PSF's (its array maximum over the
# aberration-free peak, on its grid: below an off-grid peak by up to the
# grid's step), at the same pupil sampling
from optiland.psf import FFTPSF
print()
print("Strehl: ours (off-grid peak) against optiland's FFT PSF (64 rays across, grid 256 / 512)")
for name, field in [("double-gauss-50mm.json", 0.0), ("wide-angle-22mm.json", 0.0), ("wide-angle-22mm.json", 10.0), ("telephoto-250mm.json", 0.0)]:
    path = os.path.join(ROOT, "lens-data", name)
    d = json.load(open(path))
    ours = json.loads(subprocess.check_output([LENS, "wavefront", path, "--field-deg", str(field), "--aim", "paraxial", "--json"]))
    o = build(d, ours["wavelength_nm"], field)
    hy = 1.0 if field > 0 else 0.0
    theirs = [float(FFTPSF(o, (0.0, hy), "primary", num_rays=ours["pupil_samples"], grid_size=g).strehl_ratio()) for g in (256, 512)]
    print(f"{name:<24} {field:4.1f} deg: ours {ours['strehl']:.5f}, optiland {theirs[0]:.5f} / {theirs[1]:.5f}")
