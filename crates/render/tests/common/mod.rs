//! Helpers shared by the render tests.
#![allow(dead_code)]

use render::Image;

/// Intensity-weighted centroid (pixels) and RMS radius about it, from the
/// red channel.
pub fn moments(img: &Image) -> (f64, f64, f64) {
    let (mut w, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (i, p) in img.pixels.iter().enumerate() {
        let (x, y) = ((i % img.width) as f64 + 0.5, (i / img.width) as f64 + 0.5);
        w += p.x;
        cx += p.x * x;
        cy += p.x * y;
    }
    let (cx, cy) = (cx / w, cy / w);
    let m2: f64 = img
        .pixels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (x, y) = ((i % img.width) as f64 + 0.5 - cx, (i / img.width) as f64 + 0.5 - cy);
            p.x * (x * x + y * y)
        })
        .sum::<f64>()
        / w;
    (cx, cy, m2.sqrt())
}

/// Diameter in pixels of a uniform bright disk from the intensity-weighted
/// second moment about its centroid (E[r^2] = D^2 / 8), which noise and
/// sparse sampling do not bias; `spread` is the diameter of what is blurred
/// (a lamp's own image), removed in quadrature.
pub fn disk_diameter(img: &Image, spread: f64) -> f64 {
    let (_, _, rms) = moments(img);
    (8.0 * rms * rms - spread * spread).max(0.0).sqrt()
}
