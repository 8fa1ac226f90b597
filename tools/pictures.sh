#!/usr/bin/env bash
# Regenerates every picture in docs/pictures/ with the release build of the
# `lens` command: the analysis plots, the studies (lens-data/studies/), the
# star bokeh render, the focus pull and the spectral pictures (the last needs Pillow, as
# tools/spectral_pictures.py says). Takes about ten minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p lens-cli
lens=target/release/lens
out=docs/pictures
bash tools/analysis-pictures.sh
$lens chromatic lens-data/achromat-fc-100mm.json --plot $out/chromatic-achromat-fc.png > /dev/null
# the original study's comparisons, each one study; the montages of
# renders are kept as JPEG (noisy photographs: a few hundred KB)
tmp=$(mktemp -d)
jpeg() { python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).convert('RGB').save(sys.argv[2], quality=88)" "$1" "$2"; }
for s in dof-apertures:dof-apertures dof-samples:dof-samples focus-shift:focus-shift \
         real-lenses:dof-real-lenses aperture-shapes:bokeh-chart portrait:portrait; do
  $lens study "lens-data/studies/${s%%:*}.json" -o "$tmp/${s##*:}.png"
  jpeg "$tmp/${s##*:}.png" "$out/${s##*:}.jpg"
done
$lens render lens-data/scenes/phone-aspheric.json -o "$tmp/phone-aspheric.png"
jpeg "$tmp/phone-aspheric.png" "$out/phone-aspheric.jpg"
$lens render lens-data/scenes/portrait-cine-prime.json -o "$tmp/portrait-cine-prime.png"
jpeg "$tmp/portrait-cine-prime.png" "$out/portrait-cine-prime.jpg"
$lens render lens-data/scenes/ultrawide-aspheric.json -o "$tmp/ultrawide-aspheric.png"
jpeg "$tmp/ultrawide-aspheric.png" "$out/ultrawide-aspheric.jpg"
$lens render lens-data/scenes/aspheric-35mm.json -o "$tmp/aspheric-35mm.png"
jpeg "$tmp/aspheric-35mm.png" "$out/aspheric-35mm.jpg"
rm -r "$tmp"
# a layout of every lens in the library (docs/lenses.md)
for f in lens-data/library/*.json; do
  b=$(basename "$f" .json)
  case $b in phone*) fields=0,15,30 ;; petzval*) fields=0,5,10 ;; master-prime*) fields=0,5,8.9 ;; double-gauss-100mm*) fields=0,6,12 ;; nikkor-z-14*) fields=0,40,57.68 ;; kit-zoom*) fields=0,25,37.5 ;; nikkor-28mm*) fields=0,20,37 ;; fisheye-16mm*) fields=0,40,80 ;; nikkor-85mm*) fields=0,7,14 ;; canon-35mm*) fields=0,16,32 ;; micro-nikkor-105mm*) fields=0,6,11.7 ;; sony-planar-50mm*) fields=0,12,23.4 ;; tronnier*) fields=0,11,22 ;; zoom-80-200mm*at-80mm*) fields=0,8,15 ;; zoom-80-200mm*at-200mm*) fields=0,3,6 ;; *) fields=0,10,20 ;; esac
  $lens layout "$f" --fields $fields -o "$out/lenses/$b.png"
done
for b in achromat-doublet-100mm:0,1,2 cooke-triplet:0,10,20 double-gauss-50mm:0,10,20 fisheye-10mm:0,40,75 \
         telephoto-250mm:0,3,5 wide-angle-22mm:0,20,38; do
  $lens layout "lens-data/${b%%:*}.json" --fields "${b##*:}" -o "$out/lenses/${b%%:*}.png"
done
$lens render lens-data/scenes/bokeh-thin-star.json -o $out/bokeh-star.png --width 960 --height 600
# the focus pull's first, middle and last frames side by side (Pillow)
pull=$(mktemp -d)
$lens animate lens-data/scenes/focus-pull-portrait.json -o "$pull/f%d.png" --spp 32 --frames 3 2> /dev/null
python3 - "$pull" "$out/focus-pull.png" <<'PY'
import sys
from PIL import Image
frames = [Image.open(f"{sys.argv[1]}/f{k}.png").convert("RGB") for k in range(3)]
w, h = frames[0].size
strip = Image.new("RGB", (3 * w + 8, h), "white")
for k, f in enumerate(frames):
    strip.paste(f, (k * (w + 4), 0))
strip.save(sys.argv[2])
PY
rm -rf "$pull"
# error against run time of the three cameras (docs/render-report/)
for c in pinhole thin-lens real-lens; do
  $lens render lens-data/scenes/report-$c.json -o docs/render-report/$c-reference.png --spp 64 \
    --report docs/render-report/$c.md 2> /dev/null
done
python3 tools/spectral_pictures.py
