# Times each analysis command of `lens` on the double Gauss (whole process,
# the fastest of several runs, after `cargo build --release`) and, in the
# same run, optiland's time for the same computation where it has one: a
# spot diagram of the same rays (1 million random rays, and the default
# pattern's ray count as hexapolar rings) and the two ray fans. optiland is
# timed inside Python after the lens is built (its import and set-up are
# not counted). Not part of the tests: pip install optiland, then
#   python3 tools/bench_analyses.py
import json, os, subprocess, time
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = ROOT + "/target/release/lens"
DG = ROOT + "/lens-data/double-gauss-50mm.json"
RUNS = 7


def ours(args):
    best = float("inf")
    for _ in range(RUNS):
        t = time.perf_counter()
        subprocess.run([LENS] + args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        best = min(best, time.perf_counter() - t)
    return best


def best_of(f, runs=RUNS):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def optiland_lens():
    from optiland import optic
    from optiland.materials import IdealMaterial
    d = json.load(open(DG))
    o = optic.Optic()
    o.add_surface(index=0, radius=np.inf, thickness=np.inf)
    info = json.loads(subprocess.check_output([LENS, "info", DG, "--json"]))
    z_last = sum(x["thickness"] for x in d["surfaces"][:-1])
    for i, s in enumerate(d["surfaces"]):
        t = s["thickness"] if i < len(d["surfaces"]) - 1 else info["bfl"]
        o.add_surface(index=i + 1, radius=s.get("radius") or np.inf, thickness=t,
                      material=IdealMaterial(n=s.get("ior", 1.0)), is_stop=s.get("stop", False))
    o.add_surface(index=len(d["surfaces"]) + 1)
    stop = [s for s in d["surfaces"] if s.get("stop")][0]
    o.set_aperture(aperture_type="float_by_stop_size", value=2 * stop["semi_diameter"])
    o.set_field_type(field_type="angle")
    o.add_field(y=0.0)
    o.add_field(y=10.0)
    o.add_wavelength(value=0.5876, is_primary=True)
    return o


rows = [
    ("info", ["info", DG, "--json"], None),
    ("focus (paraxial and real-ray best focus)", ["focus", DG, "--object-distance", "2000", "--json"], None),
    ("fan, 21 points, 10 deg", ["fan", DG, "--field-deg", "10", "--json"], "fan"),
    ("spot, default (Gauss 12 rings, 624 rays), 10 deg", ["spot", DG, "--field-deg", "10", "--json"], "spot624"),
    ("spot, 1,000,000 random rays, 10 deg", ["spot", DG, "--field-deg", "10", "--pattern", "random", "--n", "1000000", "--json"], "spot1M"),
    ("coc, 7 distances", ["coc", DG, "--focus-mm", "2000", "--distances", "1000,1500,1800,2500,5000,10000,inf", "--json"], None),
    ("field, 11 fields", ["field", DG, "--json"], None),
    ("layout, 3 fields (PNG)", ["layout", DG, "--fields", "0,10,20", "-o", "/tmp/bench-layout.png"], None),
    ("convergence (spot and CoC tables)", ["convergence", DG, "-o", "/tmp/bench-conv.md"], None),
    ("bench workload: batch trace of 1,000,000 rays (one pass, in-process)", None, None),
]

o = optiland_lens()
theirs = {
    "fan": lambda: [o.trace_generic(Hx=0.0, Hy=1.0, Px=np.zeros(21), Py=np.linspace(-1, 1, 21), wavelength=0.5876),
                    o.trace_generic(Hx=0.0, Hy=1.0, Px=np.linspace(-1, 1, 21), Py=np.zeros(21), wavelength=0.5876)],
    "spot624": lambda: o.trace(Hx=0.0, Hy=1.0, wavelength=0.5876, num_rays=12, distribution="hexapolar"),
    "spot1M": lambda: o.trace(Hx=0.0, Hy=1.0, wavelength=0.5876, num_rays=1_000_000, distribution="random"),
}
bench = json.loads(subprocess.check_output([LENS, "bench", DG, "--rays", "1000000", "--json"]))
print("| command | lens (ms) | optiland (ms) |")
print("|---|---:|---:|")
for name, args, key in rows:
    if args is None:
        print(f"| {name} | {1e3 / bench['rays_per_second'] * 1e6:.1f} | |")
        continue
    t = ours(args)
    o_t = f"{best_of(theirs[key], 3) * 1e3:.1f}" if key else ""
    print(f"| {name} | {t * 1e3:.1f} | {o_t} |")
