# optiland 0.6.3's Monte Carlo tolerancing on the trial of
# lens-data/design/cooke-triplet.tolerance.json, for the time a trial takes
# (docs/performance.md): the Cooke triplet with its SCHOTT glasses,
# F, d, C; the six radius and six thickness tolerances (normal, sigma =
# plus_minus / 2); the back focus (the image surface's distance) as the
# compensator; the criterion operands the RMS spot radius at 0, 10 and 14
# degrees over all wavelengths. (The index, Abbe and element tolerances of
# our file are left out: optiland 0.6.3 perturbs them otherwise; this
# makes optiland's trial cheaper, not dearer.) optiland runs its trials
# one after another in Python.
#
#     python3 -W ignore tools/bench_optiland_tolerance.py [TRIALS]
import json, os, sys, time
from optiland import optic
from optiland.materials import Material
from optiland.physical_apertures import RadialAperture
from optiland.tolerancing.core import Tolerancing
from optiland.tolerancing.monte_carlo import MonteCarlo
from optiland.tolerancing.perturbation import DistributionSampler

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def build():
    p = json.load(open(os.path.join(ROOT, "lens-data", "cooke-triplet.json")))
    o = optic.Optic()
    o.add_surface(index=0, radius=float("inf"), thickness=float("inf"))
    for i, s in enumerate(p["surfaces"]):
        g = s.get("glass")
        kw = dict(index=i + 1, radius=s.get("radius", float("inf")), thickness=s["thickness"], is_stop=s.get("stop", False))
        if g:
            kw["material"] = Material(g.split(":")[1], "schott")
        kw["aperture"] = RadialAperture(r_max=s["semi_diameter"])
        o.add_surface(**kw)
    o.add_surface(index=len(p["surfaces"]) + 1)
    o.set_aperture(aperture_type="float_by_stop_size", value=2 * 10.3)
    o.set_field_type(field_type="angle")
    for f in (0.0, 10.0, 14.0):
        o.add_field(y=f)
    for w, primary in ((0.4861327, False), (0.5875618, True), (0.6562725, False)):
        o.add_wavelength(value=w, is_primary=primary)
    return o, p


def main():
    trials = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    o, p = build()
    tol = json.load(open(os.path.join(ROOT, "lens-data", "design", "cooke-triplet.tolerance.json")))
    t = Tolerancing(o)
    n = len(p["surfaces"])
    for hy in (0.0, 10.0 / 14.0, 1.0):
        t.add_operand("rms_spot_size", input_data={"optic": o, "surface_number": n + 1, "Hx": 0.0, "Hy": hy,
                                                    "num_rays": 6, "wavelength": "all", "distribution": "hexapolar"})
    for x in tol["tolerances"]:
        if x["type"] in ("radius", "thickness"):
            sampler = DistributionSampler("normal", loc=0.0, scale=x["plus_minus"] / 2.0, seed=1)
            t.add_perturbation(x["type"], sampler, surface_number=x["surface"])
    t.add_compensator("thickness", surface_number=n)
    mc = MonteCarlo(t)
    t0 = time.perf_counter()
    mc.run(trials)
    s = time.perf_counter() - t0
    print(f"optiland 0.6.3 Monte Carlo: {trials} trials in {s:.2f} s, {1e3 * s / trials:.0f} ms a trial")


if __name__ == "__main__":
    main()
