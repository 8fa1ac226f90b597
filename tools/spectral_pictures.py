"""Renders the spectral demonstration scenes (tools/spectral_scenes.py)
with the release `lens` binary and composes the labelled pictures of
docs/pictures/: chromatic-bokeh-chart, wu-aberrations, lateral-colour,
prism. Needs Pillow (not used by the build or the tests).

    cargo build --release -p lens-cli
    python3 tools/spectral_pictures.py [--spp-scale 1.0]
"""
import argparse
import os
import subprocess
import tempfile

from PIL import Image, ImageDraw, ImageFont

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
LENS = os.path.join(ROOT, "target", "release", "lens")
SCENES = os.path.join(ROOT, "lens-data", "scenes")
OUT = os.path.join(ROOT, "docs", "pictures")


def render(scene, spp, tmp):
    out = os.path.join(tmp, scene.replace(".json", ".png"))
    subprocess.run([LENS, "render", os.path.join(SCENES, scene), "-o", out, "--spp", str(spp)], check=True)
    return Image.open(out).convert("RGB")


def label(img, text, size=22):
    """`img` with a black band above it holding `text`."""
    font = ImageFont.load_default(size=size)
    band = size + 14
    out = Image.new("RGB", (img.width, img.height + band), (0, 0, 0))
    out.paste(img, (0, band))
    ImageDraw.Draw(out).text((10, 6), text, fill=(235, 235, 235), font=font)
    return out


def stack(images):
    w = max(i.width for i in images)
    out = Image.new("RGB", (w, sum(i.height for i in images)), (0, 0, 0))
    y = 0
    for i in images:
        out.paste(i, (0, y))
        y += i.height
    return out


def side_by_side(images):
    out = Image.new("RGB", (sum(i.width for i in images), max(i.height for i in images)), (0, 0, 0))
    x = 0
    for i in images:
        out.paste(i, (x, 0))
        x += i.width
    return out


def save(img, name):
    # renders are noisy photographs: JPEG keeps them to a few hundred KB
    path = os.path.join(OUT, name)
    img.save(path, quality=90)
    print(path, os.path.getsize(path) // 1024, "KB")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp-scale", type=float, default=1.0)
    a = ap.parse_args()
    spp = lambda n: max(1, int(n * a.spp_scale))
    with tempfile.TemporaryDirectory() as tmp:
        rows = [
            ("chromatic-bokeh-singlet.json", "N-BK7 singlet, 100 mm f/5"),
            ("chromatic-bokeh-achromat.json", "F-C achromat (N-BK7 / SF5), 100 mm f/5"),
            ("chromatic-bokeh-double-gauss.json", "double Gauss, 50 mm f/2.8"),
        ]
        panels = [label(render(s, spp(512), tmp), t) for s, t in rows]
        title = label(Image.new("RGB", (960, 0)), "White lamps focused at 2 m; rows: 4 m (behind focus), 2 m, 1.25 m (in front)")
        save(stack([title] + panels), "chromatic-bokeh-chart.jpg")

        field = label(render("wu-aberrations-double-gauss.json", spp(512), tmp),
                      "double Gauss 50 mm f/2 at 0.8 m, lamps at 12 m: cat's eyes toward the edges", 20)
        front = label(render("wu-spherical-front.json", spp(1024), tmp), "plano-convex f/4: lamp in front of focus", 18)
        behind = label(render("wu-spherical-behind.json", spp(1024), tmp), "... and behind focus", 18)
        save(stack([field, side_by_side([front, behind])]), "wu-aberrations.jpg")

        edge = render("lateral-colour-edge.json", spp(256), tmp)
        corner = edge.crop((0, 0, 320, 160)).resize((960, 480), Image.NEAREST)
        save(stack([label(edge, "landscape singlet (stop in front), backlit target: lateral colour", 20),
                    label(corner, "top-left corner, 3x: the blue image is the smaller, fringes blue toward the centre", 20)]),
             "lateral-colour.jpg")

        save(label(render("prism.json", spp(1024), tmp),
                   "a white slit seen directly (left) and through a 60-degree N-SF11 prism (right)", 20), "prism.jpg")


if __name__ == "__main__":
    main()
