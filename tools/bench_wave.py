# Times the wave analyses of one field of the double Gauss (0 and 10 deg,
# the d line) against optiland 0.6.3 in the same run: ours is the library's
# time (`lens bench --wave DEG`, fastest of repeated runs; optiland's
# likewise excludes its import and the lens's set-up), and at 10 deg also
# the whole process
# of `lens wavefront --json` on the grid it picks for this field (RMS,
# P-V, Strehl, 37-term Fringe and Standard fits) plus `lens mtf
# --frequencies 10,20,40 --json` (T and S), the fastest of several runs;
# optiland's is its OPD on the same N x N uniform grid (RMS), its FFT PSF
# (Strehl) and FFT MTF from N rays across on a 2N grid, timed inside
# Python after the lens is built. Also the
# MTF-against-image-height chart (11 fields x 2 frequencies, with its
# plot). Not part of the tests: python3 -W ignore tools/bench_wave.py
import json, os, subprocess, time, sys
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = ROOT + "/target/release/lens"
DG = ROOT + "/lens-data/double-gauss-50mm.json"
RUNS = 7
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def best(f, runs=RUNS):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times), max(times)


def run(args):
    subprocess.run([LENS] + args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


GRID = json.loads(subprocess.check_output([LENS, "wavefront", DG, "--field-deg", "10", "--aim", "paraxial", "--json"]))["pupil_samples"]


def ours_field():
    run(["wavefront", DG, "--field-deg", "10", "--grid", str(GRID), "--aim", "paraxial", "--json"])
    run(["mtf", DG, "--field-deg", "10", "--frequencies", "10,20,40", "--aim", "paraxial", "--json"])


def ours_library(deg):
    v = json.loads(subprocess.check_output([LENS, "bench", DG, "--wave", str(deg), "--json"]))
    return v["seconds_fastest"], v["seconds_median"], v["pupil_samples"], v["seconds_fastest_without_zernike"], v["seconds_median_parts"]


src = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "crosscheck_optiland_wave.py")).read()
exec(src.split("class Points")[0])
from optiland.wavefront import OPD
from optiland.psf import FFTPSF
from optiland.mtf import FFTMTF
d = json.load(open(DG))
o = build(d, D, 10.0)


def theirs_field(hy, grid):
    opd = OPD(o, (0.0, hy), "primary", num_rays=grid, distribution="uniform")
    opd.rms()
    psf = FFTPSF(o, (0.0, hy), "primary", num_rays=grid, grid_size=2 * grid)
    psf.strehl_ratio()
    FFTMTF(o, fields=[(0.0, hy)], wavelength="primary", num_rays=grid, grid_size=2 * grid)


for deg, hy in [(0.0, 0.0), (10.0, 1.0)]:
    fastest, median, grid, bare, parts = ours_library(deg)
    theirs_t = best(lambda: theirs_field(hy, grid))
    print(f"{deg:4.1f} deg, {grid} x {grid} pupil samples, library time: RMS, Strehl, T and S MTF at 3 frequencies "
          f"ours {bare*1e3:.1f} ms against optiland {theirs_t[0]*1e3:.1f} ms (slowest {theirs_t[1]*1e3:.1f}): "
          f"ratio {theirs_t[0]/bare:.1f}; with both 37-term Zernike fits ours {fastest*1e3:.1f} ms (median {median*1e3:.1f}): "
          f"ratio {theirs_t[0]/fastest:.1f}; our median parts (ms) " + ", ".join(f"{k} {v*1e3:.1f}" for k, v in parts.items()))
ours_t = best(ours_field)
theirs_t = best(lambda: theirs_field(1.0, GRID))
print(f"10.0 deg as two whole processes (lens wavefront + lens mtf): ours {ours_t[0]*1e3:.1f} ms (slowest {ours_t[1]*1e3:.1f}), "
      f"optiland {theirs_t[0]*1e3:.1f} ms: ratio {theirs_t[0]/ours_t[0]:.1f}")
chart = best(lambda: run(["mtf", DG, "--vs-field", "--frequencies", "10,30", "--plot", "/tmp/bench-wave-mtf.png"]))
print(f"MTF against image height (11 fields x 2 frequencies, with the plot): {chart[0]:.3f} s (slowest {chart[1]:.3f})")
