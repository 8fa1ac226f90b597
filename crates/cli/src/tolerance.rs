//! `lens tolerance`: the sensitivity table and Monte Carlo statistics of a
//! tolerance file; shares of the trials (`--shard I/N -o share.json`) and
//! their merge (`lens tolerance merge SPEC SHARE...`).

use crate::args::GlassArgs;
use crate::{print_json, CmdResult};
use lens::error::num;
use lens::tolerance::{Share, Statistics, Tolerancing};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// The tolerance file (JSON; docs/tolerancing.md), or `merge` followed
    /// by the tolerance file and the shares to join.
    #[arg(required = true, num_args = 1..)]
    inputs: Vec<PathBuf>,
    /// Monte Carlo trials.
    #[arg(long, default_value_t = 1000)]
    trials: u64,
    /// The random seed: trial k draws from a stream made from (seed, k).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Run share I of N (the trials k with k mod N = I - 1), written with
    /// -o for `lens tolerance merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    shard: Option<[u64; 2]>,
    /// Write the trials' results (a share, or the whole run) as JSON here.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
    /// Write the histogram and cumulative yield picture (.svg or .png).
    #[arg(long, value_name = "OUT")]
    plot: Option<PathBuf>,
    #[command(flatten)]
    catalogs: GlassArgs,
    /// Print JSON (one object on one line) instead of tables.
    #[arg(long)]
    json: bool,
}

fn parse_shard(s: &str) -> Result<[u64; 2], String> {
    let bad = || format!("\"{s}\": give I/N, share I of N, 1 <= I <= N (1/4 to 4/4)");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if n == 0 || i == 0 || i > n {
        return Err(bad());
    }
    Ok([i, n])
}

pub fn run(args: Args) -> CmdResult {
    let merging = args.inputs[0].as_os_str() == "merge";
    let (spec, shares_in) = if merging {
        match args.inputs.get(1) {
            Some(s) if args.inputs.len() >= 3 => (s.clone(), args.inputs[2..].to_vec()),
            _ => {
                return Err(
                    "lens tolerance merge SPEC.json SHARE.json...: give the tolerance file and its shares".into()
                )
            }
        }
    } else {
        if args.inputs.len() > 1 {
            return Err(format!(
                "one tolerance file, not {}: to join shares, `lens tolerance merge SPEC SHARE...`",
                args.inputs.len()
            )
            .into());
        }
        (args.inputs[0].clone(), Vec::new())
    };
    let mut outs = Vec::new();
    if let Some(o) = &args.output {
        outs.push(crate::outputs::Output { path: o, flag: "-o", extensions: &["json"] });
    }
    if let Some(p) = &args.plot {
        outs.push(crate::outputs::Output { path: p, flag: "--plot", extensions: &["svg", "png"] });
    }
    let inputs: Vec<PathBuf> = args.inputs.iter().filter(|p| p.as_os_str() != "merge").cloned().collect();
    crate::outputs::check(&outs, &inputs)?;
    if args.shard.is_some() && args.output.is_none() {
        return Err("--shard writes a share for `lens tolerance merge`: give -o SHARE.json".into());
    }
    if args.trials == 0 && !merging {
        return Err("--trials: give 1 or more".into());
    }
    let tol = Tolerancing::load(&spec, args.catalogs.user_catalogs()?)?;
    let t0 = Instant::now();
    let share = if merging {
        let shares = shares_in.iter().map(|p| read_share(p)).collect::<Result<Vec<_>, _>>()?;
        let merged = lens::tolerance::merge(&shares)?;
        if merged.digest != tol.digest {
            return Err(format!(
                "the shares are of another analysis than {} (digest {}, the file's {}): merge them with the tolerance file that made them",
                spec.display(),
                merged.digest,
                tol.digest
            )
            .into());
        }
        merged
    } else {
        tol.run(args.seed, args.trials, args.shard.unwrap_or([1, 1]))?
    };
    let seconds = t0.elapsed().as_secs_f64();
    if let Some(path) = &args.output {
        let text = serde_json::to_string(&share)? + "\n";
        lens::io::files::write_bytes_atomic(path, text.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    if let Some([i, n]) = args.shard.filter(|s| s[1] > 1) {
        // a share alone has no statistics of the run
        if args.json {
            print_json(&json!({"shard": [i, n], "trials": share.results.len(), "seconds": seconds}))?;
        } else {
            outln!(
                "share {i}/{n}: {} of {} trials in {seconds:.3} s, written for `lens tolerance merge`",
                share.results.len(),
                share.trials
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let stats = tol.statistics(std::slice::from_ref(&share))?;
    if let Some(p) = &args.plot {
        let values: Vec<f64> = share.results.iter().filter_map(|r| r.value).collect();
        let title = format!("Monte Carlo: {} trials, seed {}, {}", share.trials, share.seed, spec.display());
        plot::save(
            &plot::tolerance::histogram_chart(&values, share.trials as usize, tol.threshold, &title, &unit(&tol)),
            p,
        )?;
    }
    if args.json {
        print_json(&lens::report::tolerance(&tol, &share, &stats, seconds))?;
        return Ok(ExitCode::SUCCESS);
    }
    print_text(&tol, &share, &stats, seconds)?;
    Ok(ExitCode::SUCCESS)
}

fn read_share(p: &Path) -> Result<Share, String> {
    let bytes = lens::io::files::read_bounded(p, lens::io::files::MAX_TEXT_BYTES).map_err(|e| e.to_string())?;
    serde_json::from_slice(&bytes).map_err(|e| format!("{}: not a share of `lens tolerance --shard`: {e}", p.display()))
}

fn unit(tol: &Tolerancing) -> String {
    match tol.criterion.kind.as_str() {
        "rms_spot" => "RMS spot radius (mm)".into(),
        "rms_wavefront" => "RMS wavefront (waves)".into(),
        _ => "MTF".into(),
    }
}

fn print_text(tol: &Tolerancing, share: &Share, s: &Statistics, seconds: f64) -> Result<(), crate::StdoutError> {
    outln!("{} over fields {:?} deg; nominal {}", unit(tol), tol.criterion.fields_deg, num(share.nominal));
    outln!("sensitivity (each tolerance alone, compensated), worst first:");
    outln!("  {:<28} {:>12} {:>14} {:>14} {:>14}", "tolerance", "+-", "at +", "at -", "worse by");
    let mut rows: Vec<_> = share.sensitivity.iter().collect();
    rows.sort_by(|a, b| b.change.unwrap_or(f64::INFINITY).total_cmp(&a.change.unwrap_or(f64::INFINITY)));
    let f = |x: Option<f64>| x.map_or("failed".to_string(), |v| format!("{v:.6e}"));
    for r in rows {
        outln!(
            "  {:<28} {:>12} {:>14} {:>14} {:>14}",
            r.tolerance,
            num(r.plus_minus),
            f(r.plus),
            f(r.minus),
            f(r.change)
        );
    }
    outln!(
        "Monte Carlo: {} trials (seed {}) in {seconds:.3} s ({:.3} ms a trial); {} judged, {} invalid, {} unmeasured",
        s.trials,
        share.seed,
        1e3 * seconds / s.trials.max(1) as f64,
        s.judged,
        s.invalid,
        s.unmeasured
    );
    outln!("  mean {:.6e}, std {:.6e}", s.mean, s.std);
    let p = &s.percentiles;
    outln!("  percentiles: 10% {:.6e}, 50% {:.6e}, 90% {:.6e}, 98% {:.6e}", p.p10, p.p50, p.p90, p.p98);
    if let (Some(t), Some(y)) = (s.threshold, s.yield_fraction) {
        outln!(
            "  yield {:.2}% (criterion {} {})",
            100.0 * y,
            if tol.criterion.lower_is_better() { "<=" } else { ">=" },
            num(t)
        );
    }
    for w in &s.worst {
        outln!("  worst: trial {} at {:.6e}", w.trial, w.value);
    }
    for f in &s.failures {
        outln!("  failed: {f}");
    }
    Ok(())
}
