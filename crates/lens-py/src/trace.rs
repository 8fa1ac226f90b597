//! `lens.trace`: rays from numpy through a prescription to its film, on
//! the batch tracer, in blocks on all cores (or `threads`), the GIL
//! released. Rays cross as (N, 6) float64 arrays [x y z dx dy dz] in the
//! lens frame (mm, z from the first vertex, +z toward the image); each
//! block is laid out for the tracer inside its own task, so nothing is
//! copied on the Python side or by one thread alone.

use crate::errors::OrPyErr;
use crate::prescription::Prescription;
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;

/// The status codes of [`trace`], by value: 0 reached the film, 1 missed a
/// surface, 2 blocked by a clear aperture or the stop, 3 total internal
/// reflection, 4 an asphere's intersection did not converge.
pub const STATUS_NAMES: [&str; 5] = ["reached", "missed", "blocked", "total_internal_reflection", "not_converged"];

/// What [`trace`] returns: where each ray ended, and its status code.
type Traced<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<u8>>);

/// Rays a task traces at once.
const BLOCK: usize = 4096;

/// What the rays are traced at: one prescription's wavelength, or each
/// ray its own.
enum Light<'a> {
    One(lens::Tracer),
    Each(lens::Tracer, &'a [f64]),
}

/// Traces `rays` ((N, 6) float64, C-contiguous: x y z dx dy dz, mm, in
/// the lens frame; directions need not be unit, they are normalised)
/// through `prescription` to its film. `wavelength_nm`: None (the
/// prescription's wavelength), a number, or an (N,) float64 array, each
/// ray its own. Returns `(out, status)`: out (N, 6) where each ray ended
/// (on the film for status 0; where it stopped otherwise) and its unit
/// direction, status (N,) uint8 codes (`lens.STATUS_NAMES`); with `out`
/// = (an (N, 6) float64 array, an (N,) uint8 array), written into those
/// and returned (no new memory: for repeated traces of many rays).
#[pyfunction]
#[pyo3(signature = (prescription, rays, wavelength_nm=None, threads=None, out=None))]
pub fn trace<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    rays: &Bound<'py, PyAny>,
    wavelength_nm: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    out: Option<(Bound<'py, PyAny>, Bound<'py, PyAny>)>,
) -> PyResult<Traced<'py>> {
    let rays = float_array::<numpy::Ix2>(rays, "rays", "(N, 6)")?;
    let ro = rays.readonly();
    if ro.shape()[1] != 6 {
        return Err(PyValueError::new_err(format!(
            "rays: expected shape (N, 6) [x y z dx dy dz], got {:?}",
            ro.shape()
        )));
    }
    // a Fortran-ordered array is contiguous too, but its rows are not rays
    let input = ro.as_slice().ok().filter(|_| rays.is_c_contiguous()).ok_or_else(|| {
        PyValueError::new_err("rays: expected a C-contiguous array (np.ascontiguousarray(rays) makes one)")
    })?;
    let n = input.len() / 6;
    // the wavelength: the prescription's, one, or one per ray
    let per_ray = match wavelength_nm {
        Some(w) if w.cast::<numpy::PyUntypedArray>().is_ok() => {
            Some(float_array::<numpy::Ix1>(w, "wavelength_nm", "(N,)")?.readonly())
        }
        _ => None,
    };
    let one = match (wavelength_nm, &per_ray) {
        (Some(w), None) => Some(w.extract::<f64>().map_err(|_| {
            PyTypeError::new_err("wavelength_nm: expected None, a number (nm) or a float64 array of shape (N,)")
        })?),
        _ => None,
    };
    let p = prescription.at(py, one)?;
    let each = match &per_ray {
        Some(w) => {
            let w = w.as_slice().map_err(|_| PyValueError::new_err("wavelength_nm: expected a C-contiguous array"))?;
            if w.len() != n {
                return Err(PyValueError::new_err(format!(
                    "wavelength_nm: expected one wavelength per ray, shape ({n},), got ({},)",
                    w.len()
                )));
            }
            if let Some(i) = w.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(PyValueError::new_err(format!(
                    "wavelength_nm[{i}] = {}: give positive wavelengths in nm",
                    w[i]
                )));
            }
            let lo = w.iter().fold(f64::INFINITY, |a, b| a.min(*b));
            let hi = w.iter().fold(0.0f64, |a, b| a.max(*b));
            crate::prescription::warn_range(py, &p, &[lo, hi])?;
            Some(w)
        }
        None => None,
    };
    let light = match each {
        Some(w) => Light::Each(lens::Tracer::forward(&p), w),
        None => Light::One(lens::Tracer::forward(&p)),
    };
    let pool = pool(threads)?;
    let bad_ray = |i: usize| {
        PyValueError::new_err(format!(
            "rays[{i}] = {:?}: every coordinate must be finite and the direction (dx, dy, dz) not zero",
            &input[i * 6..i * 6 + 6]
        ))
    };
    let failed = |f: Failure| match f {
        Failure::Optics(e) => Err::<(), _>(e).py(),
        Failure::BadRay(i) => Err(bad_ray(i)),
    };
    if let Some((to, codes)) = out {
        // the caller's arrays, written in place and handed back
        let to = float_array::<numpy::Ix2>(&to, "out[0]", &format!("({n}, 6)"))?;
        let codes = codes.cast::<PyArray1<u8>>().map_err(|_| {
            PyTypeError::new_err(format!("out[1]: expected a uint8 numpy array of shape ({n},) for the statuses"))
        })?;
        {
            let shared = |what: &str| {
                PyValueError::new_err(format!("{what} shares memory with rays or wavelength_nm: give a separate array"))
            };
            let mut w = to.try_readwrite().map_err(|_| shared("out[0]"))?;
            let mut c = codes.try_readwrite().map_err(|_| shared("out[1]"))?;
            let c_order = to.is_c_contiguous();
            let (ends, status) = match (w.as_slice_mut(), c.as_slice_mut()) {
                (Ok(e), Ok(s)) if c_order && e.len() == n * 6 && s.len() == n => (e, s),
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "out: expected C-contiguous arrays of shapes ({n}, 6) float64 and ({n},) uint8"
                    )))
                }
            };
            if let Err(f) = py.detach(|| pool.install(|| run(input, &light, ends, status))) {
                failed(f)?;
            }
        }
        return Ok((to, codes.clone()));
    }
    let mut ends = vec![0.0; n * 6];
    huge_pages(&mut ends);
    let mut status = vec![0u8; n];
    if let Err(f) = py.detach(|| pool.install(|| run(input, &light, &mut ends, &mut status))) {
        failed(f)?;
    }
    let ends = Array2::from_shape_vec((n, 6), ends).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((ends.into_pyarray(py), Array1::from_vec(status).into_pyarray(py)))
}

/// Every block traced into `out` and `status` (n x 6 and n); a bad ray (a
/// coordinate not finite, a zero direction) is reported by its index, the
/// first of all.
fn run(input: &[f64], light: &Light, out: &mut [f64], status: &mut [u8]) -> Result<(), Failure> {
    let failures: Vec<Failure> = out
        .par_chunks_mut(BLOCK * 6)
        .zip(status.par_chunks_mut(BLOCK))
        .zip(input.par_chunks(BLOCK * 6))
        .enumerate()
        .map_init(Scratch::default, |scratch, (k, ((out, status), rays))| {
            trace_block(scratch, k * BLOCK, rays, light, out, status).err()
        })
        .flatten()
        .collect();
    let first = failures.into_iter().min_by_key(|f| match f {
        Failure::BadRay(i) => *i,
        Failure::Optics(_) => usize::MAX,
    });
    match first {
        Some(f) => Err(f),
        None => Ok(()),
    }
}

/// Asks Linux to back a large output array, not yet written, with huge
/// pages where its transparent huge pages are on request: a million rays'
/// 48 MB would otherwise take some 12,000 page faults as the blocks first
/// write it, a fifth of the trace's time. Elsewhere, and on refusal,
/// nothing changes.
fn huge_pages(v: &mut [f64]) {
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let bytes = std::mem::size_of_val(v);
        if bytes >= 2 * HUGE {
            let start = v.as_mut_ptr() as usize;
            let aligned = start.next_multiple_of(HUGE);
            let len = (start + bytes - aligned) / HUGE * HUGE;
            // SAFETY: the range lies inside `v`'s allocation; MADV_HUGEPAGE
            // is advice about backing, never changing its contents.
            unsafe {
                libc::madvise(aligned as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
            }
        }
    }
}

/// Why a trace failed.
enum Failure {
    /// The ray of this index has a coordinate that is not finite or a
    /// zero direction.
    BadRay(usize),
    /// The tracer refused (a wavelength outside a glass's formula).
    Optics(lens::OpticsError),
}

/// Each task's buffers between its blocks.
#[derive(Default)]
struct Scratch {
    /// The statuses of a block traced from its rows.
    status: Vec<u64>,
    /// A block of rays of mixed wavelengths, laid out for the tracer.
    batch: lens::trace::SpectralBatch,
}

/// One block, its first ray the input's `first`: at one wavelength traced
/// straight from its rows into the output's ([`lens::Tracer::trace_rows`]),
/// each ray at its own wavelength laid out for the tracer first
/// (directions normalised alike), traced, written back.
fn trace_block(
    scratch: &mut Scratch,
    first: usize,
    rays: &[f64],
    light: &Light,
    out: &mut [f64],
    status: &mut [u8],
) -> Result<(), Failure> {
    let m = rays.len() / 6;
    if let Light::One(t) = light {
        scratch.status.resize(m, 0);
        t.trace_rows(rays, out, &mut scratch.status).map_err(|i| Failure::BadRay(first + i))?;
        for (s, st) in status.iter_mut().zip(&scratch.status) {
            *s = (st & 7) as u8;
        }
        return Ok(());
    }
    let batch = &mut scratch.batch;
    let b = &mut batch.rays;
    for v in [&mut b.x, &mut b.y, &mut b.z, &mut b.dx, &mut b.dy, &mut b.dz, &mut b.opl] {
        v.clear();
        v.resize(m, 0.0);
    }
    b.status.clear();
    b.status.resize(m, 0);
    let mut bad = false;
    let points = b.x.iter_mut().zip(b.y.iter_mut()).zip(b.z.iter_mut());
    let dirs = b.dx.iter_mut().zip(b.dy.iter_mut()).zip(b.dz.iter_mut());
    for ((((x, y), z), ((dx, dy), dz)), r) in points.zip(dirs).zip(rays.chunks_exact(6)) {
        let d = glam::DVec3::new(r[3], r[4], r[5]);
        bad |= !(r[0].is_finite() && r[1].is_finite() && r[2].is_finite() && d.is_finite()) || d == glam::DVec3::ZERO;
        let d = d.normalize();
        (*x, *y, *z, *dx, *dy, *dz) = (r[0], r[1], r[2], d.x, d.y, d.z);
    }
    if bad {
        let at = rays
            .chunks_exact(6)
            .position(|r| !r.iter().all(|v| v.is_finite()) || (r[3] == 0.0 && r[4] == 0.0 && r[5] == 0.0));
        return Err(Failure::BadRay(first + at.unwrap_or(0)));
    }
    if let Light::Each(t, w) = light {
        batch.wavelength_nm.clear();
        batch.wavelength_nm.extend_from_slice(&w[first..first + m]);
        t.trace_spectral(batch).map_err(Failure::Optics)?
    }
    let b = &batch.rays;
    let ends = b.x.iter().zip(&b.y).zip(&b.z).zip(b.dx.iter().zip(&b.dy).zip(&b.dz));
    for ((o, s), ((((x, y), z), ((dx, dy), dz)), st)) in
        out.chunks_exact_mut(6).zip(status.iter_mut()).zip(ends.zip(&b.status))
    {
        o.copy_from_slice(&[*x, *y, *z, *dx, *dy, *dz]);
        *s = (st & 7) as u8;
    }
    Ok(())
}

/// `v` as a float64 numpy array of dimension D, or a TypeError naming
/// `what` and the expected `shape`.
pub(crate) fn float_array<'py, D: numpy::ndarray::Dimension>(
    v: &Bound<'py, PyAny>,
    what: &str,
    shape: &str,
) -> PyResult<Bound<'py, numpy::PyArray<f64, D>>> {
    if let Ok(a) = v.cast::<numpy::PyArray<f64, D>>() {
        return Ok(a.clone());
    }
    let described = match v.cast::<numpy::PyUntypedArray>() {
        Ok(a) => {
            let dims: Vec<String> = a.shape().iter().map(usize::to_string).collect();
            format!("an array of dtype {} and shape ({})", a.dtype(), dims.join(", "))
        }
        Err(_) => format!("a {}", v.get_type().name().map(|n| n.to_string()).unwrap_or_default()),
    };
    Err(PyTypeError::new_err(format!(
        "{what}: expected a float64 numpy array of shape {shape}, got {described} (np.asarray(x, dtype=np.float64) converts)"
    )))
}

/// A pool of `threads` threads, or the global one's size where None.
pub(crate) fn pool(threads: Option<usize>) -> PyResult<rayon::ThreadPool> {
    let n = match threads {
        Some(0) => return Err(PyValueError::new_err("threads=0: give at least 1, or None for every core")),
        Some(n) => n,
        None => rayon::current_num_threads(),
    };
    rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| PyValueError::new_err(e.to_string()))
}
