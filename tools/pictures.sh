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
# the original study's comparisons, each one study
$lens study lens-data/studies/dof-apertures.json -o $out/dof-apertures.png
$lens study lens-data/studies/dof-samples.json -o $out/dof-samples.png
$lens study lens-data/studies/focus-shift.json -o $out/focus-shift.png
$lens study lens-data/studies/real-lenses.json -o $out/dof-real-lenses.png
$lens study lens-data/studies/aperture-shapes.json -o $out/bokeh-chart.png
$lens render lens-data/scenes/bokeh-thin-star.json -o $out/bokeh-star.png
# the portrait at 960 x 540 a cell, kept as JPEG (a noisy photograph)
tmp=$(mktemp -d)
$lens study lens-data/studies/portrait.json -o "$tmp/portrait.png"
python3 -c "import sys; from PIL import Image; Image.open(sys.argv[1]).convert('RGB').save(sys.argv[2], quality=88)" "$tmp/portrait.png" $out/portrait.jpg
rm -r "$tmp"
python3 tools/spectral_pictures.py
