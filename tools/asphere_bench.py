#!/usr/bin/env python3
"""The aspheric step's cost against a sphere step's (docs/performance.md).

Writes variants of shipped lenses into a temporary folder, runs
`lens bench FILE --json` on each in turn (ROUNDS rounds, alternating the
lenses so that all see the same machine) and prints the time per step:

- a sphere step, from the double Gauss with ten weak spheres added (five
  menisci before the film) against the double Gauss as shipped;
- a plane step likewise, from ten plane plates (twenty planes) added;
- an aspheric step, from each aspheric lens against the same lens with its
  conic and polynomial terms removed (the same base spheres): the extra time
  a ray spends, divided by the number of aspheres, plus a sphere step; where
  the base spheres are not a valid lens (the phone lens's are smaller than
  their apertures), from the whole lens: its time a ray less the chunk's and
  the film's own work (the double Gauss's time less its ten sphere steps and
  its stop plane) and its plane steps, divided by the number of aspheres.

- an aspheric step of one lens's asphere alone (the Canon 35 mm's, the
  Sony 50 mm's rear one), precisely: twenty copies of
  the surface (pairs 1 mm apart around a plate of index 1.001) behind a
  plano-convex singlet, against the same stack of its base spheres, the
  extra time a ray spends divided by twenty, plus a sphere step (a whole
  lens's single asphere is a small difference of two large times, some
  tenths of a nanosecond noisy).

Fastest pass of each run (the bench's headline figure), median over rounds.

Usage: tools/asphere_bench.py [LENS_BINARY] [ROUNDS]
"""

import copy
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LENS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "release", "lens")
ROUNDS = int(sys.argv[2]) if len(sys.argv) > 2 else 3


def load(path):
    with open(os.path.join(ROOT, path)) as f:
        return json.load(f)


def spherical(lens):
    """The lens with every conic and polynomial term removed."""
    out = copy.deepcopy(lens)
    for s in out["surfaces"]:
        s.pop("conic", None)
        s.pop("aspheric", None)
        s.pop("odd_aspheric", None)
    return out


def planes(lens):
    return sum(1 for s in lens["surfaces"] if s.get("radius") in (None, 0))


def with_curved(lens, extra):
    """The lens's curved surfaces given `extra` (conic, aspheric terms)."""
    out = copy.deepcopy(lens)
    for s in out["surfaces"]:
        if s.get("radius") not in (None, 0):
            s.update(extra)
    return out


def stacked(surface, spherical_base):
    """Twenty copies of `surface` behind a plano-convex singlet (its
    conic and polynomial terms dropped if `spherical_base`)."""
    shape = {k: v for k, v in surface.items() if k in ("radius", "conic", "aspheric", "semi_diameter")}
    if spherical_base:
        shape.pop("conic", None)
        shape.pop("aspheric", None)
    out = [
        {"radius": 51.68, "thickness": 4.0, "ior": 1.5168, "semi_diameter": 12.7, "stop": True},
        {"thickness": 5.0, "semi_diameter": 12.7},
    ]
    for i in range(10):
        out.append(dict(shape, thickness=1.0, ior=1.001))
        out.append(dict(shape, thickness=1.0 if i < 9 else 80.0))
    return {"name": "stack", "units": "mm", "surfaces": out}


def aspheres(lens):
    return sum(1 for s in lens["surfaces"] if "conic" in s or "aspheric" in s or "odd_aspheric" in s)


def main():
    dg = load("lens-data/double-gauss-50mm.json")
    dg20 = copy.deepcopy(dg)
    last = dg20["surfaces"][-1]
    back = last["thickness"]
    last["thickness"] = 1.0
    for i in range(5):
        dg20["surfaces"].append({"radius": 2000.0, "thickness": 0.5, "glass": {"nd": 1.5, "vd": 60}, "semi_diameter": 30})
        dg20["surfaces"].append(
            {"radius": 2100.0, "thickness": 0.5 if i < 4 else back - 5.0, "semi_diameter": 30}
        )
    dgp = copy.deepcopy(dg)
    dgp["surfaces"][-1]["thickness"] = 1.0
    for i in range(10):
        dgp["surfaces"].append({"thickness": 0.5, "glass": {"nd": 1.5, "vd": 60}, "semi_diameter": 30})
        dgp["surfaces"].append({"thickness": 0.5 if i < 9 else back - 10.0, "semi_diameter": 30})
    cases = {
        "double Gauss, 10 mild aspheres": with_curved(dg, {"conic": -0.01, "aspheric": [0, 1e-9, 1e-13]}),
        "double Gauss, 10 pure conics": with_curved(dg, {"conic": -0.01}),
        "Canon 35 mm f/2 (1 asphere)": load("lens-data/library/canon-35mm-f2-is-aspheric-us20150205081.json"),
        "Sony 50 mm f/1.4 (2 aspheres)": load("lens-data/library/sony-planar-50mm-f1.4-aspheric-us20140071331.json"),
        "phone 5.6 mm (8 aspheres, odd terms)": load("lens-data/library/phone-5.6mm-f3.5-us7535658.json"),
    }
    canon = cases["Canon 35 mm f/2 (1 asphere)"]
    surface = next(s for s in canon["surfaces"] if "aspheric" in s)
    sony = cases["Sony 50 mm f/1.4 (2 aspheres)"]
    sony_surface = next(s for s in sony["surfaces"] if "conic" in s and "aspheric" in s)
    stacks = {
        "Canon 35 mm asphere, 20 stacked": (surface, stacked(surface, False)),
        "Sony 50 mm rear asphere, 20 stacked": (sony_surface, stacked(sony_surface, False)),
    }
    files = {}
    tmp = tempfile.mkdtemp(prefix="asphere-bench-")
    base = {}
    for name, lens in [("sphere", dg), ("sphere+10", dg20), ("plane+20", dgp)] + [
        (k, v) for name, lens in cases.items() for k, v in [(name, lens), (name + " [base]", spherical(lens))]
    ] + [(k, v) for name, (surf, lens) in stacks.items() for k, v in [(name, lens), (name + " [base]", stacked(surf, True))]]:
        path = os.path.join(tmp, f"{len(files)}.json")
        with open(path, "w") as f:
            json.dump(lens, f)
        if name.endswith("[base]") and name[: -len(" [base]")] in cases:
            base[name] = "sphere"
            if subprocess.run([LENS, "info", path], capture_output=True).returncode != 0:
                base[name] = "none"
                continue
        files[name] = path
    per_ray = {k: [] for k in files}
    for _ in range(ROUNDS):
        for name, path in files.items():
            out = subprocess.run([LENS, "bench", path, "--json"], check=True, capture_output=True, text=True).stdout
            per_ray[name].append(1e9 / json.loads(out)["rays_per_second"])
    ns = {k: statistics.median(v) for k, v in per_ray.items()}
    sphere = (ns["sphere+10"] - ns["sphere"]) / 10
    spread = [(b - a) / 10 for a, b in zip(per_ray["sphere"], per_ray["sphere+10"])]
    plane = (ns["plane+20"] - ns["sphere"]) / 20
    print(f"sphere step: {sphere:.2f} ns (rounds {', '.join(f'{x:.2f}' for x in spread)}); plane step {plane:.2f} ns")
    print(f"the chunk's and the film's own work: {ns['sphere'] - 10 * sphere - plane:.2f} ns a ray")
    for name, lens in cases.items():
        k = aspheres(lens)
        kind = base[name + " [base]"]
        if kind == "sphere":
            steps = [sphere + (a - b) / k for a, b in zip(per_ray[name], per_ray[name + " [base]"])]
        else:
            rest = ns["sphere"] - 10 * sphere - plane
            steps = [(a - rest - planes(lens) * plane) / k for a in per_ray[name]]
        step = statistics.median(steps)
        print(
            f"{name}: {ns[name]:.2f} ns a ray"
            + (f" against {ns[name + ' [base]']:.2f} with spheres; " if kind == "sphere" else " (whole lens); ")
            + 
            f"aspheric step {step:.2f} ns (rounds {', '.join(f'{x:.2f}' for x in steps)}): "
            f"{100 * sphere / step:.0f}% of a sphere step's speed"
        )

    for name in stacks:
        steps = [sphere + (a - b) / 20 for a, b in zip(per_ray[name], per_ray[name + " [base]"])]
        step = statistics.median(steps)
        print(
            f"{name}: {ns[name]:.2f} ns a ray against {ns[name + ' [base]']:.2f} with spheres; "
            f"aspheric step {step:.2f} ns (rounds {', '.join(f'{x:.2f}' for x in steps)}): "
            f"{100 * sphere / step:.0f}% of a sphere step's speed"
        )


if __name__ == "__main__":
    main()
