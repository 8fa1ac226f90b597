#!/usr/bin/env bash
# Regenerates the analysis pictures of docs/pictures/ (SVG and PNG) from the
# double Gauss, with the release build of the `lens` command.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p lens-cli
lens=target/release/lens
dg=lens-data/double-gauss-50mm.json
out=docs/pictures
for ext in svg png; do
  $lens layout $dg --fields 0,10,20 -o $out/double-gauss-layout.$ext
  $lens fan $dg --field-deg 0 --plot-fields 0,10,20 --plot $out/double-gauss-fan.$ext > /dev/null
  $lens spot $dg --field-deg 0 --plot-fields 0,10,20 --plot $out/double-gauss-spot.$ext > /dev/null
  $lens coc $dg --focus-mm 2000 --distances 1000,1500,1800,2500,5000,10000,inf --plot $out/double-gauss-coc.$ext > /dev/null
  $lens field $dg --plot $out/double-gauss-field.$ext > /dev/null
done
# wave optics: the wavefront maps on axis and at 14 degrees, the MTF at 10
# degrees, against image height and through focus (PNG only: the maps'
# SVGs run to megabytes)
$lens wavefront $dg --field-deg 0 --plot $out/double-gauss-wavefront-0.png > /dev/null
$lens wavefront $dg --field-deg 14 --plot $out/double-gauss-wavefront-14.png > /dev/null
$lens mtf $dg --field-deg 10 --plot $out/double-gauss-mtf-10.png > /dev/null
$lens mtf $dg --vs-field --frequencies 10,30 --plot $out/double-gauss-mtf-field.png > /dev/null
$lens mtf $dg --through-focus 0.2 --frequencies 10,30 --plot $out/double-gauss-mtf-focus.png > /dev/null
$lens psf $dg --field-deg 0 --plot $out/double-gauss-psf-0.png > /dev/null
$lens psf $dg --field-deg 10 --plot $out/double-gauss-psf-10.png > /dev/null
