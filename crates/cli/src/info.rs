//! `lens info`: first-order properties of a prescription.

use crate::args::{JsonArgs, LensArgs, ObjectArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::aperture::clear_aperture_limit;
use lens::error::num;
use lens::error::Fixed;
use lens::paraxial::{imaging, FirstOrder, ObjectDistance};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    object: ObjectArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    #[command(flatten)]
    out: JsonArgs,
}

pub fn run(a: Args) -> CmdResult {
    let (_, p) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    let object = a.object.object(&p)?;
    let f = FirstOrder::of(&p)?;
    let limit = clear_aperture_limit(&p, &f);
    let img = imaging(&p, &f, object)?;
    if a.out.json {
        print_json(&lens::report::info(&p, object)?)?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!("{}", a.lens.name(&p));
    if let Some(s) = p.source() {
        outln!("  source: {s}");
    }
    outln!(
        "  {} surfaces, stop at surface {} (semi-diameter {:.4} mm)",
        p.surfaces().len(),
        p.stop_index() + 1,
        Fixed(p.stop_semi_diameter())
    );
    outln!("  z is measured from the first vertex, +z toward the image; mm");
    if p.is_tilted() {
        outln!("  surfaces are decentred or tilted: the first-order data are those of the co-axial system");
    }
    let row = |k: &str, v: String| -> Result<(), crate::StdoutError> {
        outln!("  {k:<28} {v}");
        Ok(())
    };
    row("effective focal length", format!("{:.6}", Fixed(f.efl)))?;
    row("back focal length", format!("{:.6}  (from the last vertex)", Fixed(f.bfl)))?;
    row("front focal point z", format!("{:.6}", Fixed(f.ffd)))?;
    row("front principal plane z", format!("{:.6}", Fixed(f.front_principal_plane)))?;
    row("back principal plane z", format!("{:.6}", Fixed(f.back_principal_plane)))?;
    row(
        "entrance pupil",
        format!("z {:.6}, diameter {:.6}", Fixed(f.entrance_pupil.z), Fixed(f.entrance_pupil.diameter)),
    )?;
    row(
        "exit pupil",
        match f.exit_pupil {
            Some(x) => format!("z {:.6}, diameter {:.6}", Fixed(x.z), Fixed(x.diameter)),
            None => "at infinity (telecentric in image space)".into(),
        },
    )?;
    row("f-number", format!("{:.4}", Fixed(f.f_number)))?;
    if let Some(l) = limit {
        let note = if l.f_number > f.f_number { "; the stop is larger than they let through" } else { "" };
        row(
            "clear apertures allow",
            format!(
                "f/{:.4} (surface {}, {}{note})",
                Fixed(l.f_number),
                l.surface + 1,
                lens::error::clear_aperture(l.semi_diameter)
            ),
        )?;
    }
    let obj = match object {
        ObjectDistance::Infinity => "infinity".to_string(),
        ObjectDistance::Finite(d) => format!("{} mm", lens::error::num(d)),
    };
    row("object distance", obj)?;
    row("image distance", format!("{:.6}  (from the last vertex)", Fixed(img.image_distance)))?;
    row("magnification", format!("{:.6}", Fixed(img.magnification)))?;
    row("working f-number", format!("{:.4}", Fixed(img.working_f_number)))?;
    row("film distance", format!("{:.6}  (last thickness)", Fixed(p.film_distance())))?;
    row("total track", format!("{:.6}", Fixed(f.total_track)))?;
    let primary = p.primary_wavelength_nm();
    let waves: Vec<String> = p
        .wavelengths_nm()
        .iter()
        .map(|w| if *w == primary { format!("{w} (primary)") } else { format!("{w}") })
        .collect();
    row("wavelengths, nm", waves.join(", "))?;
    if !p.fields_deg().is_empty() {
        let fields: Vec<String> = p.fields_deg().iter().map(|d| format!("{d}")).collect();
        row("design fields, degrees", fields.join(", "))?;
    }
    for (d, v) in p.fields_deg().iter().zip(p.vignetting_factors()).filter(|(_, v)| !v.is_none()) {
        row(
            &format!("vignetting at {} deg", num(*d)),
            format!(
                "decenter x {} y {}, compress x {} y {}",
                num(v.decenter_x),
                num(v.decenter_y),
                num(v.compress_x),
                num(v.compress_y)
            ),
        )?;
    }
    Ok(ExitCode::SUCCESS)
}
