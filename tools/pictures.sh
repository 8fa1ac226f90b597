#!/usr/bin/env bash
# Regenerates every picture in docs/pictures/ with the release build of the
# `lens` command: the analysis plots, the studies (lens-data/studies/), the
# star bokeh render and the spectral pictures (the last needs Pillow, as
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
rm -r "$tmp"
$lens render lens-data/scenes/bokeh-thin-star.json -o $out/bokeh-star.png --width 960 --height 600
# error against run time of the three cameras (docs/render-report/)
for c in pinhole thin-lens real-lens; do
  $lens render lens-data/scenes/report-$c.json -o docs/render-report/$c-reference.png --spp 64 \
    --report docs/render-report/$c.md 2> /dev/null
done
python3 tools/spectral_pictures.py
