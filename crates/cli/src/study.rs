//! `lens study`: a grid of renders of one scene, rows and columns changing
//! its settings, labelled and written as one picture.

use crate::outputs::{self, Output};
use crate::CmdResult;
use ::render::study::Study;
use ::render::{render, Options};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Study file (JSON; docs/scene-format.md).
    study: PathBuf,
    /// Output picture (.png).
    #[arg(short, long)]
    output: PathBuf,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Every cell's film (overrides the study's and the scene's).
    #[command(flatten)]
    film: crate::args::FilmArgs,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    glass_range: crate::args::GlassRangeArgs,
}

/// Space between cells, pixels.
const GAP: u32 = 6;
/// Label font sizes and bands, pixels.
const TITLE: (f64, u32) = (22.0, 46);
const LABEL: (f64, u32) = (15.0, 30);

pub fn run(a: Args) -> CmdResult {
    let overrides = a.film.overrides(&a.glass_range);
    let study = Study::load_with(&a.study, &overrides)?;
    outputs::check(&[Output { path: &a.output, flag: "-o", extensions: &["png"] }], &study.inputs)?;
    for cell in &study.cells {
        for w in &cell.glass_warnings {
            crate::warnings::glass_range(w);
        }
        for w in &cell.warnings {
            crate::warnings::warn("scene", w);
        }
    }
    let pool = crate::render::pool(a.threads)?;
    let total: u64 = study.cells.iter().map(|s| s.film.height as u64).sum();
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} rows of the study, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let images: Vec<_> = pool.install(|| {
        study.cells.iter().map(|s| render(s, Options { spp: s.film.spp, seed: a.seed }, &|_| bar.inc(1)).0).collect()
    });
    bar.finish_and_clear();
    let (nr, nc) = (study.rows.len(), study.columns.len());
    let col_w: Vec<u32> =
        (0..nc).map(|c| (0..nr).map(|r| images[r * nc + c].width as u32).max().unwrap_or(0)).collect();
    let row_h: Vec<u32> =
        (0..nr).map(|r| (0..nc).map(|c| images[r * nc + c].height as u32).max().unwrap_or(0)).collect();
    let chars = |s: &String| s.chars().count() as f64;
    let row_label_w = study.rows.iter().map(chars).fold(0.0, f64::max) * LABEL.0 * 0.62 + 24.0;
    let row_label_w = row_label_w.clamp(60.0, 400.0) as u32;
    let grid_w = col_w.iter().sum::<u32>() + GAP * (nc as u32 + 1);
    // the title must fit too
    let title_w = (chars(&study.title) * TITLE.0 * 0.6 + 40.0) as u32;
    let width = (row_label_w + grid_w).max(title_w);
    let height = TITLE.1 + LABEL.1 + row_h.iter().sum::<u32>() + GAP * (nr as u32 + 1);
    let mut canvas = image::RgbImage::from_pixel(width, height, image::Rgb([255, 255, 255]));
    let paste = |canvas: &mut image::RgbImage, png: Vec<u8>, x: u32, y: u32| -> CmdResult {
        let img = image::load_from_memory(&png)?.to_rgb8();
        image::imageops::overlay(canvas, &img, x as i64, y as i64);
        Ok(ExitCode::SUCCESS)
    };
    paste(&mut canvas, plot::raster::label_png(&study.title, width, TITLE.1, TITLE.0)?, 0, 0)?;
    let mut x = row_label_w + GAP;
    for (c, label) in study.columns.iter().enumerate() {
        let w = col_w[c].max((chars(label) * LABEL.0 * 0.6) as u32);
        paste(&mut canvas, plot::raster::label_png(label, w.min(col_w[c] + GAP), LABEL.1, LABEL.0)?, x, TITLE.1)?;
        x += col_w[c] + GAP;
    }
    let mut y = TITLE.1 + LABEL.1 + GAP;
    for (r, label) in study.rows.iter().enumerate() {
        paste(&mut canvas, plot::raster::label_png(label, row_label_w, row_h[r], LABEL.0)?, 0, y)?;
        let mut x = row_label_w + GAP;
        for (c, w) in col_w.iter().enumerate() {
            let k = r * nc + c;
            let img = &images[k];
            let px = img.to_srgb8(study.cells[k].film.exposure);
            let cell = image::RgbImage::from_raw(img.width as u32, img.height as u32, px)
                .ok_or("a cell's image has the wrong size")?;
            image::imageops::overlay(&mut canvas, &cell, x as i64, y as i64);
            x += w + GAP;
        }
        y += row_h[r] + GAP;
    }
    lens::io::files::write_atomic(&a.output, |out| {
        canvas.write_to(out, image::ImageFormat::Png).map_err(std::io::Error::other)
    })
    .map_err(|e| format!("{}: cannot write: {e}", a.output.display()))?;
    eprintln!("{} x {} cells of {} in {width} x {height} px", nr, nc, a.study.display());
    Ok(ExitCode::SUCCESS)
}
