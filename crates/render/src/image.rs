//! The rendered image: linear RGB pixels, and writing them as PNG
//! (tone-mapped sRGB) or OpenEXR (linear float), by file extension.

use glam::DVec3;
use std::path::Path;

/// The most pixels an image read from a file may have: 2^25 (8192 x
/// 4096), 800 MB as linear RGB.
pub const MAX_READ_PIXELS: u64 = 1 << 25;

/// A linear-RGB image, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Pixels, row-major from the top left.
    pub pixels: Vec<DVec3>,
}

/// Why an image could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// Unknown extension or a format compiled out.
    #[error("{0}: choose an output ending in .png or .exr (and build with that feature)")]
    Format(String),
    /// The file could not be read or decoded.
    #[error("{path}: cannot read: {message}")]
    Read {
        /// The file.
        path: String,
        /// The cause.
        message: String,
    },
    /// The encoder failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// The cause.
        message: String,
    },
}

/// sRGB transfer function of a linear value in [0, 1].
pub fn srgb(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

impl Image {
    /// Root-mean-square difference from `other` (same size), over channels.
    pub fn rmse(&self, other: &Image) -> f64 {
        let n = (self.pixels.len() * 3).max(1) as f64;
        (self.pixels.iter().zip(&other.pixels).map(|(a, b)| (*a - *b).length_squared()).sum::<f64>() / n).sqrt()
    }

    /// The pixels as 8-bit sRGB, row by row: linear values times
    /// `exposure`, clamped to [0, 1], through the sRGB curve (what a PNG
    /// holds).
    pub fn to_srgb8(&self, exposure: f64) -> Vec<u8> {
        let mut buf = Vec::with_capacity(self.width * self.height * 3);
        for p in &self.pixels {
            for c in p.to_array() {
                buf.push((srgb(c * exposure) * 255.0).round() as u8);
            }
        }
        buf
    }

    /// Writes by extension: `.png` (exposure, clamp, sRGB) or `.exr`.
    pub fn save(&self, path: &Path, exposure: f64) -> Result<(), ImageError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let err = |m: String| ImageError::Write { path: path.display().to_string(), message: m };
        // never write an inf or NaN (nor a value a 32-bit float cannot hold)
        let bad = self.pixels.iter().filter(|p| !p.is_finite() || p.abs().max_element() > f32::MAX as f64).count();
        if bad > 0 {
            return Err(err(format!(
                "{bad} pixels are not finite numbers a 32-bit float can hold; nothing written (lower the lights' radiance)"
            )));
        }
        match ext.as_deref() {
            #[cfg(feature = "png")]
            Some("png") => {
                let buf = self.to_srgb8(exposure);
                let (w, h) = (self.width as u32, self.height as u32);
                lens::io::files::write_atomic(path, |out| {
                    image::write_buffer_with_format(out, &buf, w, h, image::ColorType::Rgb8, image::ImageFormat::Png)
                        .map_err(std::io::Error::other)
                })
                .map_err(|e| err(e.to_string()))
            }
            #[cfg(feature = "exr")]
            Some("exr") => {
                let px = |x: usize, y: usize| {
                    let p = self.pixels[y * self.width + x];
                    (p.x as f32, p.y as f32, p.z as f32)
                };
                use exr::prelude::*;
                let image = Image::from_channels(
                    (self.width, self.height),
                    SpecificChannels::rgb(|p: Vec2<usize>| px(p.x(), p.y())),
                );
                lens::io::files::write_atomic(path, |out| image.write().to_buffered(out).map_err(std::io::Error::other))
                    .map_err(|e| err(e.to_string()))
            }
            _ => Err(ImageError::Format(path.display().to_string())),
        }
    }

    /// Writes an OpenEXR file of the linear RGB pixels and the channels
    /// `extra` (a name and one value per pixel, row by row from the top:
    /// the render passes' `Z`, `P.x`, `N.x`, `CoC`...), every channel 32-bit
    /// float, losslessly compressed. Extra values may be infinite (a depth
    /// pass's background); the RGB pixels are checked as [`Self::save`]
    /// checks them.
    #[cfg(feature = "exr")]
    pub fn save_exr_with(&self, path: &Path, extra: &[(&str, Vec<f32>)]) -> Result<(), ImageError> {
        use exr::prelude::*;
        let err = |m: String| ImageError::Write { path: path.display().to_string(), message: m };
        let bad = self.pixels.iter().filter(|p| !p.is_finite() || p.abs().max_element() > f32::MAX as f64).count();
        if bad > 0 {
            return Err(err(format!(
                "{bad} pixels are not finite numbers a 32-bit float can hold; nothing written (lower the lights' radiance)"
            )));
        }
        let n = self.width * self.height;
        let mut channels = SmallVec::new();
        for (k, name) in ["R", "G", "B"].into_iter().enumerate() {
            let v: Vec<f32> = self.pixels.iter().map(|p| p[k] as f32).collect();
            channels.push(AnyChannel::new(name, FlatSamples::F32(v)));
        }
        for (name, v) in extra {
            if v.len() != n {
                return Err(err(format!("channel {name} has {} values for {n} pixels", v.len())));
            }
            channels.push(AnyChannel::new(*name, FlatSamples::F32(v.clone())));
        }
        let layer = Layer::new(
            (self.width, self.height),
            LayerAttributes::default(),
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(channels),
        );
        let image = exr::image::Image::from_layer(layer);
        lens::io::files::write_atomic(path, |out| image.write().to_buffered(out).map_err(std::io::Error::other))
            .map_err(|e| err(e.to_string()))
    }

    /// Reads a linear RGB OpenEXR file of at most [`MAX_READ_PIXELS`]
    /// pixels (its header is read first: a small file that declares a huge
    /// image is refused before anything is allocated).
    #[cfg(feature = "exr")]
    pub fn load_exr(path: &Path) -> Result<Image, ImageError> {
        use exr::prelude::read_first_rgba_layer_from_file;
        let err = |m: String| ImageError::Read { path: path.display().to_string(), message: m };
        let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| err(exr_reason(&e)))?;
        for h in &meta.headers {
            let has = |c: &str| h.channels.list.iter().any(|x| x.name.eq_case_insensitive(c));
            if !(has("R") && has("G") && has("B")) {
                let names: Vec<String> = h.channels.list.iter().map(|c| c.name.to_string()).collect();
                return Err(err(format!(
                    "the image has no R, G and B channels (its channels: {}): give an RGB or RGBA OpenEXR image \
                     (a one-channel image can be saved as RGB by any image editor)",
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                )));
            }
            let (w, hgt) = (h.layer_size.width(), h.layer_size.height());
            if (w as u64).saturating_mul(hgt as u64) > MAX_READ_PIXELS {
                return Err(err(format!(
                    "{w} x {hgt} pixels: at most {MAX_READ_PIXELS} (8192 x 4096) are read; scale the image down"
                )));
            }
        }
        let img = read_first_rgba_layer_from_file(
            path,
            |res, _| Image {
                width: res.width(),
                height: res.height(),
                pixels: vec![DVec3::ZERO; res.width() * res.height()],
            },
            |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                let w = img.width;
                img.pixels[pos.y() * w + pos.x()] = DVec3::new(r as f64, g as f64, b as f64);
            },
        )
        .map_err(|e| err(exr_reason(&e)))?;
        Ok(img.layer_data.channel_data.pixels)
    }
}

/// What is wrong with an OpenEXR file, in words, the decoder's own text
/// kept as the detail.
#[cfg(feature = "exr")]
fn exr_reason(e: &exr::error::Error) -> String {
    use exr::error::Error;
    match e {
        Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            format!("the file is empty or cut short, not a whole OpenEXR image ({e}); give a complete .exr file")
        }
        Error::Invalid(m) if m.contains("missing bytes") => {
            format!("the file is empty or cut short, not a whole OpenEXR image ({e}); give a complete .exr file")
        }
        Error::Invalid(_) => format!("not a readable OpenEXR image ({e}); give an RGB or RGBA .exr file"),
        Error::NotSupported(_) => format!(
            "an OpenEXR feature this reader does not support ({e}); save the image as plain scan-line RGB or RGBA"
        ),
        _ => format!("{e}; give an RGB or RGBA .exr file"),
    }
}

#[cfg(all(test, feature = "exr"))]
mod tests {
    /// An empty file and a one-channel image are refused saying what is
    /// wrong with them and what to give instead.
    #[test]
    fn unreadable_exrs_say_why() {
        use exr::prelude::*;
        let dir = std::env::temp_dir().join(format!("lens-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let empty = dir.join("empty.exr");
        std::fs::write(&empty, b"").unwrap();
        let e = super::Image::load_exr(&empty).unwrap_err().to_string();
        assert!(e.contains("empty or cut short") && e.contains("give a complete .exr file"), "{e}");
        let grey = dir.join("grey.exr");
        let y = AnyChannel::new("Y", FlatSamples::F32(vec![0.5; 4]));
        let mut channels = SmallVec::new();
        channels.push(y);
        let layer =
            Layer::new((2, 2), LayerAttributes::named("grey"), Encoding::default(), AnyChannels::sort(channels));
        exr::image::Image::from_layer(layer).write().to_file(&grey).unwrap();
        let e = super::Image::load_exr(&grey).unwrap_err().to_string();
        assert!(e.contains("no R, G and B channels (its channels: Y)") && e.contains("RGB or RGBA"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
