# Compares our renderer with Mitsuba 3 on a thin-lens scene, as in the
# sampling-bias study (issue: pixel and aperture strata paired by a fixed
# rule). Not part of the tests: needs `pip install mitsuba` (3.9 was used)
# and `cargo build --release`. Usage:
#
#   python3 tools/compare_mitsuba.py [SCENE.json] [--spp N] [--reference-spp M]
#
# SCENE (default lens-data/scenes/mitsuba-thin-lens.json) may hold spheres,
# planes (drawn as 2 km squares), quads and boxes with diffuse and emissive
# materials, point lights, a constant background and a pinhole or thin-lens
# camera; anything else is refused. The script renders
#   1. a Mitsuba reference at M spp (path tracer, independent sampler);
#   2. our render at M spp: the two images' mean relative difference and the
#      largest difference of any 8 x 8 block, with Mitsuba's own noise in
#      that block for scale;
#   3. both renderers at 1, 4, 16, ..., N spp, each timed, with its RMSE
#      against the reference, relative to its mean (the equal-error cost:
#      RMSE x sqrt(time)).
# It also averages 64 of our renders at 4 spp (seeds 1..64) and compares
# them with the reference along the image, where a biased stratification
# shows as a difference that more seeds do not shrink.
import json, os, subprocess, sys, tempfile, time
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = ROOT + "/target/release/lens"


def mitsuba_scene(path, spp):
    s = json.load(open(path))
    film, cam = s["film"], s["camera"]
    w, h = film["width"], film["height"]
    d = {"type": "scene", "integrator": {"type": "path", "max_depth": 33, "rr_depth": 4}}
    up = cam.get("up", [0, 1, 0])
    to_world = mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["look_at"], up=up)
    sensor = {
        "to_world": to_world,
        "fov": cam["fov_deg"],
        "fov_axis": "y",
        "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": "independent", "sample_count": spp},
    }
    if cam["type"] == "pinhole" or not cam.get("aperture"):
        sensor["type"] = "perspective"
    elif cam["type"] == "thin_lens" and "focal_length_mm" not in cam:
        sensor.update({"type": "thinlens", "aperture_radius": cam["aperture"] / 2, "focus_distance": cam["focus_distance"]})
    else:
        sys.exit("only pinhole and thin-lens cameras given by aperture (m) and focus distance (m)")
    if "aperture_shape" in cam and cam["aperture_shape"].get("shape", "circle") != "circle":
        sys.exit("Mitsuba's thin lens is round: use a circular aperture")
    d["sensor"] = sensor
    bg = s.get("background", {"type": "constant", "radiance": [0, 0, 0]})
    if bg["type"] != "constant":
        sys.exit("only a constant background")
    d["background"] = {"type": "constant", "radiance": {"type": "rgb", "value": bg["radiance"]}}
    mats = {}
    for name, m in s["materials"].items():
        if m["type"] == "diffuse":
            mats[name] = ({"type": "diffuse", "reflectance": {"type": "rgb", "value": m["color"]}}, None)
        elif m["type"] == "emissive":
            mats[name] = ({"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
                          {"type": "area", "radiance": {"type": "rgb", "value": m["radiance"]}})
        else:
            sys.exit(f"material {name}: only diffuse and emissive")
    for i, sh in enumerate(s["shapes"]):
        bsdf, emitter = mats[sh["material"]]
        if sh["type"] == "sphere":
            shape = {"type": "sphere", "center": sh["center"], "radius": sh["radius"]}
        elif sh["type"] in ("quad", "plane"):
            if sh["type"] == "quad":
                c, u, v = (np.array(sh[k], float) for k in ("corner", "u", "v"))
            else:
                n = np.array(sh["normal"], float)
                n /= np.linalg.norm(n)
                a = np.array([1.0, 0, 0]) if abs(n[0]) < 0.9 else np.array([0, 0, 1.0])
                u = np.cross(a, n)
                u *= 2000 / np.linalg.norm(u)
                v = np.cross(n, u)
                c = np.array(sh["point"], float) - (u + v) / 2
            n = np.cross(u, v)
            n /= np.linalg.norm(n)
            m = np.eye(4)
            m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = u / 2, v / 2, n, c + (u + v) / 2
            shape = {"type": "rectangle", "to_world": mi.ScalarTransform4f(m.tolist())}
        else:
            sys.exit(f"shape {i}: only spheres, planes and quads")
        shape["bsdf"] = bsdf
        if emitter:
            shape["emitter"] = emitter
        d[f"shape{i}"] = shape
    for i, l in enumerate(s.get("lights", [])):
        d[f"light{i}"] = {"type": "point", "position": l["position"],
                          "intensity": {"type": "rgb", "value": l["intensity"]}}
    return mi.load_dict(d), (w, h)


def mitsuba_render(path, spp, seed=0):
    scene, _ = mitsuba_scene(path, spp)
    t = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed))[:, :, :3]
    return img, time.perf_counter() - t


def ours(path, spp, seed=1):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "o.exr")
        t = time.perf_counter()
        subprocess.run([LENS, "render", path, "-o", out, "--spp", str(spp), "--seed", str(seed)],
                       check=True, stderr=subprocess.DEVNULL)
        dt = time.perf_counter() - t
        img = np.array(mi.Bitmap(out))[:, :, :3]
    return img, dt


def main():
    args = sys.argv[1:]
    path = next((a for a in args if a.endswith(".json")), ROOT + "/lens-data/scenes/mitsuba-thin-lens.json")
    opt = lambda name, default: int(args[args.index(name) + 1]) if name in args else default
    n, m = opt("--spp", 64), opt("--reference-spp", 4096)
    ref, ref_t = mitsuba_render(path, m)
    ref2, _ = mitsuba_render(path, m, seed=1)
    scale = ref.mean()
    print(f"# {os.path.basename(path)}: Mitsuba {mi.__version__} reference at {m} spp ({ref_t:.1f} s)\n")
    mine, _ = ours(path, m)
    diff = mine - ref
    print(f"our render at {m} spp against it: mean relative difference {diff.mean() / scale:+.2e}, "
          f"RMSE {np.sqrt((diff ** 2).mean()) / scale:.2e} of the mean; the reference's own noise "
          f"(two seeds) {np.sqrt(((ref - ref2) ** 2).mean() / 2) / scale:.2e}")
    hb, wb = ref.shape[0] // 8, ref.shape[1] // 8
    block = lambda x: x[: hb * 8, : wb * 8].reshape(hb, 8, wb, 8, 3).mean(axis=(1, 3, 4))
    worst = np.abs(block(mine) - block(ref)).max()
    noise = np.abs(block(ref) - block(ref2)).max() / np.sqrt(2)
    print(f"largest 8x8-block difference {worst / scale:.2e} of the mean (the reference's block noise {noise / scale:.2e})\n")
    print("| spp | ours (s) | ours relative RMSE | ours RMSE x sqrt(s) | Mitsuba (s) | Mitsuba relative RMSE | Mitsuba RMSE x sqrt(s) |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    spp = 1
    while spp <= n:
        a, ta = ours(path, spp)
        b, tb = mitsuba_render(path, spp, seed=7)
        ea = np.sqrt(((a - ref) ** 2).mean()) / scale
        eb = np.sqrt(((b - ref) ** 2).mean()) / scale
        print(f"| {spp} | {ta:.3f} | {ea:.4f} | {ea * np.sqrt(ta):.4f} | {tb:.3f} | {eb:.4f} | {eb * np.sqrt(tb):.4f} |")
        spp *= 4
    avg = np.mean([ours(path, 4, seed)[0] for seed in range(1, 65)], axis=0)
    d = block(avg) - block(ref)
    print(f"\nmean of 64 renders at 4 spp against the reference: mean relative difference "
          f"{(avg - ref).mean() / scale:+.2e}, largest 8x8-block difference {np.abs(d).max() / scale:.2e} of the mean")
    print("(our time includes the process and writing the EXR; Mitsuba's is the render call alone)")


if __name__ == "__main__":
    main()
