//! `lens focus`: the film distance that focuses an object, or the object
//! in focus for a film distance.

use crate::args::{JsonArgs, LensArgs, ObjectArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::error::num;
use lens::error::Fixed;
use lens::paraxial::ObjectDistance;
use serde_json::json;
use std::process::ExitCode;

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("what").required(true).args(["object_distance", "film_distance"]))]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    object: ObjectArgs,
    /// The inverse: which object is in focus on a film this many mm behind
    /// the last vertex.
    #[arg(long, value_name = "MM", allow_hyphen_values = true, conflicts_with = "object_distance")]
    film_distance: Option<f64>,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    #[command(flatten)]
    out: JsonArgs,
}

pub fn run(a: Args) -> CmdResult {
    let (_, p) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    if let Some(film) = a.film_distance {
        let d = match lens::paraxial::object_distance_in_focus(&p, film)? {
            ObjectDistance::Infinity => None,
            ObjectDistance::Finite(d) => Some(d),
        };
        if a.out.json {
            print_json(&json!({"film_distance": film, "object_distance": d}))?;
        } else {
            match d {
                Some(d) => outln!(
                    "a film {} mm behind the last vertex is in focus for an object {} mm in front of the first vertex",
                    num(film),
                    num(d)
                ),
                None => outln!("a film {} mm behind the last vertex is in focus at infinity", num(film)),
            }
        }
        return Ok(ExitCode::SUCCESS);
    }
    let object = a.object.object(&p)?;
    let f = lens::analysis::focus::focus(&p, object)?;
    if a.out.json {
        print_json(&json!({
            "object_distance": a.object.object_distance.filter(|d| d.is_finite()),
            "film_distance": f.film_distance,
            "best_focus_film_distance": f.best_focus_film_distance,
            "rms_radius_at_paraxial_focus": f.rms_radius_at_paraxial_focus,
            "rms_radius_at_best_focus": f.rms_radius_at_best_focus,
            "pupil_fill": f.pupil_fill,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    match object {
        ObjectDistance::Infinity => outln!("object distance        infinity"),
        ObjectDistance::Finite(d) => outln!("object distance        {} mm in front of the first vertex", num(d)),
    }
    outln!("film distance          {:.9} mm behind the last vertex (paraxial)", Fixed(f.film_distance));
    outln!(
        "best focus (real rays) {:.9} mm ({:+.6} mm from paraxial)",
        Fixed(f.best_focus_film_distance),
        Fixed(f.best_focus_film_distance - f.film_distance)
    );
    outln!(
        "RMS spot radius        {:.6} mm at paraxial focus, {:.6} mm at best focus",
        Fixed(f.rms_radius_at_paraxial_focus),
        Fixed(f.rms_radius_at_best_focus)
    );
    if f.pupil_fill < 1.0 {
        outln!("on-axis bundle fills   {:.4} of the entrance pupil radius (vignetted)", Fixed(f.pupil_fill));
    }
    Ok(ExitCode::SUCCESS)
}
