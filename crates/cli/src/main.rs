//! `lens`: the command line over the `lens` library. Parses flags, calls the
//! library, prints. Exit codes: 0 success, 1 a finding or computation error,
//! 2 bad usage.

/// `println!` that hands back a failed write to standard output (a full
/// disk, a file that cannot grow) as an error instead of panicking.
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($t)*).map_err($crate::StdoutError)?
    }};
}

/// `print!` likewise.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($t)*).map_err($crate::StdoutError)?
    }};
}

mod animate;
mod args;
mod bench;
mod chromatic;
mod coc;
mod convergence;
mod convert;
mod fan;
mod field;
mod focus;
mod ghosts;
mod glass;
mod info;
mod layout;
mod mtf;
mod optimize;
mod outputs;
mod psf;
mod render;
mod spot;
mod study;
mod tolerance;
mod validate;
mod warnings;
mod wavefront;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "lens", version, about = "Real camera lenses: prescriptions, exact ray tracing, paraxial optics")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// First-order properties: focal lengths, principal planes, pupils, f-number.
    Info(info::Args),
    /// Check prescription files and list every finding.
    Validate(validate::Args),
    /// Film distance that focuses an object: paraxial and real-ray best focus.
    Focus(focus::Args),
    /// Convert a prescription (e.g. a pbrt .dat file) to the JSON format.
    Convert(convert::Args),
    /// Tangential and sagittal ray fans at a field.
    Fan(fan::Args),
    /// Spot diagram statistics at a field.
    Spot(spot::Args),
    /// Wavefront error at a field: OPD to the exit pupil's reference sphere, RMS, P-V, Strehl, Zernike fits.
    Wavefront(wavefront::Args),
    /// Diffraction MTF at a field: at chosen frequencies, against frequency, image height or focus.
    Mtf(mtf::Args),
    /// Point spread function at a field (FFT or Huygens): Strehl, encircled energy, image.
    Psf(psf::Args),
    /// Real circles of confusion beside the thin-lens formula.
    Coc(coc::Args),
    /// Distortion, field curvature, spherical aberration, vignetting.
    Field(field::Args),
    /// Colour: focal shift, lateral colour, polychromatic spot, fans per wavelength.
    Chromatic(chromatic::Args),
    /// Ghost reflections between surface pairs: paraxial focus, height, blur and irradiance.
    Ghosts(ghosts::Args),
    /// A glass's index, nd, vd and range; its dispersion or the glass map as a plot.
    Glass(glass::Args),
    /// Draw the lens cross-section with ray bundles.
    Layout(layout::Args),
    /// Optimise a design file's variables against its merit function (damped least squares).
    Optimize(optimize::Args),
    /// Tolerancing: sensitivity table and Monte Carlo yield (shares and their merge for clusters).
    Tolerance(tolerance::Args),
    /// Error against run time of the pupil-sampled statistics (markdown).
    Convergence(convergence::Args),
    /// Render a scene through a pinhole, thin lens or real lens.
    Render(render::Args),
    /// Render a frame sequence: a scene's keyframed focus, f-number, pose
    /// and focal length, one file per frame.
    Animate(animate::Args),
    /// Render a grid of one scene varying its camera and film settings, labelled.
    Study(study::Args),
    /// Time the batch ray tracer on one core.
    Bench(bench::Args),
}

fn main() -> ExitCode {
    restore_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => info::run(a),
        Command::Validate(a) => validate::run(a),
        Command::Focus(a) => focus::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Fan(a) => fan::run(a),
        Command::Spot(a) => spot::run(a),
        Command::Wavefront(a) => wavefront::run(a),
        Command::Mtf(a) => mtf::run(a),
        Command::Psf(a) => psf::run(a),
        Command::Coc(a) => coc::run(a),
        Command::Field(a) => field::run(a),
        Command::Chromatic(a) => chromatic::run(a),
        Command::Ghosts(a) => ghosts::run(a),
        Command::Glass(a) => glass::run(a),
        Command::Layout(a) => layout::run(a),
        Command::Convergence(a) => convergence::run(a),
        Command::Optimize(a) => optimize::run(a),
        Command::Tolerance(a) => tolerance::run(a),
        Command::Render(a) => render::run(a),
        Command::Study(a) => study::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Bench(a) => bench::run(a),
    };
    // what is still buffered must reach its file too
    let result = result.and_then(|code| {
        use std::io::Write as _;
        std::io::stdout().flush().map_err(StdoutError)?;
        Ok(code)
    });
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

/// Output piped into a program that stops reading (`lens info X | head`)
/// should end the process quietly, as for other command-line tools, not
/// make `println!` panic: restore the default SIGPIPE action Rust masks.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to its default at start-up,
    // before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Errors a command reports (already formatted by the library).
type CmdResult = Result<ExitCode, Box<dyn std::error::Error>>;

/// Prints a JSON value on one line, with the command's warnings so far
/// under `"warnings"` when it has any ([`warnings`]).
fn print_json(v: &serde_json::Value) -> Result<(), StdoutError> {
    use std::io::Write as _;
    let v = warnings::attach(v.clone());
    writeln!(std::io::stdout().lock(), "{v}").map_err(StdoutError)
}

/// Standard output could not be written.
#[derive(Debug)]
pub struct StdoutError(std::io::Error);

impl std::fmt::Display for StdoutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot write to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {}
