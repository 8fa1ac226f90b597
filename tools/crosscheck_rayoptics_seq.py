# Cross-check of CODE V .seq files against rayoptics (pip install rayoptics;
# not part of the tests): every shipped lens that `lens convert -o X.seq`
# writes is read by rayoptics' CODE V reader, and rayoptics' own sample
# .seq files of co-axial lenses are read by ours; the effective focal
# length and the back focus of both readings are compared.
#     python3 -W ignore tools/crosscheck_rayoptics_seq.py
import glob, json, os, subprocess, sys, tempfile
import rayoptics.codev.reader  # noqa: F401 (rayoptics' CODE V support)
from rayoptics.environment import open_model

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target", "release", "lens")
SAMPLES = os.path.join(os.path.dirname(rayoptics.__file__), "codev", "tests")


def ours(path):
    out = subprocess.run([LENS, "info", path, "--json"], capture_output=True, text=True)
    return json.loads(out.stdout) if out.returncode == 0 else out.stderr.strip().splitlines()[-1]


def theirs(path):
    try:
        opm = open_model(path, info=False)
    except Exception as e:  # rayoptics' own failures (its glass lookup)
        return f"rayoptics cannot read it: {type(e).__name__}: {e}"
    opm.update_model()
    fod = opm["analysis_results"]["parax_data"].fod
    return fod.efl, fod.bfl


worst, rows = 0.0, []
with tempfile.TemporaryDirectory() as d:
    for lens_file in sorted(glob.glob(os.path.join(ROOT, "lens-data", "*.json")) + glob.glob(os.path.join(ROOT, "lens-data", "library", "*.json"))):
        seq = os.path.join(d, os.path.basename(lens_file).replace(".json", ".seq"))
        w = subprocess.run([LENS, "convert", lens_file, "-o", seq], capture_output=True, text=True)
        if w.returncode != 0:
            rows.append((os.path.basename(lens_file), "not written: " + w.stderr.strip().splitlines()[-1]))
            continue
        a, t = ours(seq), theirs(seq)
        if isinstance(t, str) or isinstance(a, str):
            rows.append((os.path.basename(lens_file), t if isinstance(t, str) else a))
            continue
        efl, bfl = t
        rel = abs(a["efl"] - efl) / abs(efl)
        worst = max(worst, rel)
        rows.append((os.path.basename(lens_file), f"EFL {a['efl']:.9f} vs rayoptics {efl:.9f} (rel {rel:.1e}), BFL {a['bfl']:.6f} vs {bfl:.6f}"))
for name in ["ag_dblgauss.seq", "singlet.seq", "landscape_lens.seq", "asp46.seq", "paraboloid_f8.seq"]:
    path = os.path.join(SAMPLES, name)
    a = ours(path)
    if isinstance(a, str):
        rows.append(("rayoptics " + name, "refused: " + a))
        continue
    t = theirs(path)
    if isinstance(t, str):
        rows.append(("rayoptics " + name, t))
        continue
    efl, bfl = t
    rel = abs(a["efl"] - efl) / abs(efl)
    worst = max(worst, rel)
    rows.append(("rayoptics " + name, f"EFL {a['efl']:.9f} vs rayoptics {efl:.9f} (rel {rel:.1e}), BFL {a['bfl']:.6f} vs {bfl:.6f}"))
for r in rows:
    print(f"{r[0]:<52} {r[1]}")
print(f"largest relative EFL difference: {worst:.1e}")
sys.exit(0 if worst < 1e-6 else 1)
