# Times lens.trace from numpy against `lens bench` in the same run: the
# same double Gauss, one thread, 1,000,000 rays each pass, fastest of
# several passes, as time per ray. The rays are those of lens bench's
# workload (parallel beams over the entrance pupil, fields up to 10 deg,
# the same low-discrepancy sequence) so both trace the same paths. Needs the package installed
# (pip install .) and target/release/lens. Not part of the tests:
#     python3 tools/bench_python.py
import json, os, subprocess, time
import numpy as np
import lens

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DG = os.path.join(ROOT, "lens-data/double-gauss-50mm.json")
N = 1_000_000
PASSES = 9

p = lens.load(DG)
info = p.info()
ep_r, ep_z = info["entrance_pupil"]["diameter"] / 2, info["entrance_pupil"]["z"]
k = np.arange(N)
g = 1.2207440846057595
u = np.stack([(0.5 + k / g**i) % 1.0 for i in (1, 2, 3)])
r, phi, theta = ep_r * np.sqrt(u[0]), 2 * np.pi * u[1], np.radians(10.0 * u[2])
d = np.stack([np.zeros(N), np.sin(theta), np.cos(theta)], axis=1)
z_start = min(ep_z, 0.0) - 10.0
aim = np.stack([r * np.cos(phi), r * np.sin(phi), np.full(N, ep_z)], axis=1)
origin = aim - d * ((ep_z - z_start) / d[:, 2])[:, None]
rays = np.ascontiguousarray(np.hstack([origin, d]))

times = []
for _ in range(PASSES):
    t = time.perf_counter()
    out, status = lens.trace(p, rays, threads=1)
    times.append(time.perf_counter() - t)
ours = min(times)
reuse = []
ends, codes = np.empty((N, 6)), np.empty(N, dtype=np.uint8)
for _ in range(PASSES):
    t = time.perf_counter()
    lens.trace(p, rays, threads=1, out=(ends, codes))
    reuse.append(time.perf_counter() - t)
reused = min(reuse)
# numpy's own price for a fresh result of that size: a copy of the rays
# into a new (N, 6) array, page faults and the kernel's zeroing included
fresh = []
for _ in range(PASSES):
    t = time.perf_counter()
    rays.copy()
    fresh.append(time.perf_counter() - t)
copy = min(fresh)
bench = json.loads(subprocess.check_output([os.path.join(ROOT, "target/release/lens"), "bench", DG, "--json"]))
per_ray_bench = 1.0 / bench["rays_per_second"]
print(f"lens.trace, 1,000,000 rays from numpy, one thread: {ours * 1e3:.1f} ms fastest (slowest {max(times) * 1e3:.1f}), "
      f"{ours / N * 1e9:.1f} ns a ray, {(status == 0).mean():.1%} reach the film")
print(f"the same into arrays reused between calls (out=): {reused * 1e3:.1f} ms fastest (slowest {max(reuse) * 1e3:.1f}), {reused / N * 1e9:.1f} ns a ray")
print(f"lens bench, one thread: {per_ray_bench * 1e9:.1f} ns a ray (fastest pass); ratio {ours / N / per_ray_bench:.3f}, "
      f"with out= {reused / N / per_ray_bench:.3f}")
print(f"numpy's rays.copy() (a fresh 48 MB array): {copy * 1e3:.1f} ms, {copy / N * 1e9:.1f} ns a ray; "
      f"lens.trace less the out= time: {(ours - reused) / N * 1e9:.1f} ns a ray")
