//! Tracing many rays at once. On x86-64 with AVX2 and FMA the rays go a
//! chunk at a time: structure of arrays, surfaces in the outer loop, the
//! chunk's vectors in the inner loop (eight rays a vector where the CPU also
//! has AVX-512F and VL, four elsewhere), every lane computed without
//! masking and stopped rays set aside on a rare path. Elsewhere each ray
//! takes the one-ray path. Either way the results are bit-for-bit those of
//! [`Tracer::trace`]: all run the same per-surface kernel, written once
//! over the lane type of `lanes.rs`.
//!
//! Longer than most files (about 1100 lines, 70 of them tests) on purpose:
//! the batch's data (`RayBatch`), its chunk buffers, the two AVX2 drivers
//! (structure of arrays, slice of rays; the first also with each ray's own
//! indices, for `spectral.rs`) and the sphere's loops over a chunk
//! (`sphere_chunk`) at either width share the chunk's layout and its
//! invariants (idle lanes, statuses, the frame of each buffer), which read
//! best in one place. The aspheric step's loops over a chunk, a lock-step
//! driver of `asphere.rs`'s kernel, are `asphere_chunk.rs`.

#[cfg(target_arch = "x86_64")]
use super::asphere_chunk::{asphere_chunk, asphere_chunk_of, NewtonFlags, NewtonScratch};
use super::frame::Frame;
use super::ray::{Outcome, Ray};
#[cfg(target_arch = "x86_64")]
use super::spectral::ChunkIndices;
#[cfg(target_arch = "x86_64")]
use super::step::{
    kind_of, lanes_at, simd_fma, sphere_from_approach, step_lanes, stopped, Step, StepLanes, ASPHERE, CURVED, FLAT,
    PARAXIAL, PLANE,
};
use super::step::{Lane, KIND_BITS, KIND_MASK, PASSED};
use super::tracer::Tracer;
use crate::error::OpticsError;
#[cfg(target_arch = "x86_64")]
use crate::simd::avx2::{columns_to_rows, rows_to_columns, F64x4, M64x4};
#[cfg(target_arch = "x86_64")]
use crate::simd::avx2_f32::F32x8;
#[cfg(target_arch = "x86_64")]
use crate::simd::avx512::{F64x8, M64x8};
#[cfg(target_arch = "x86_64")]
use crate::simd::avx512_f32::F32x16;
#[cfg(target_arch = "x86_64")]
use crate::simd::lanes::Real;
#[cfg(target_arch = "x86_64")]
use crate::trace::asphere::AsphereLanes;
#[cfg(target_arch = "x86_64")]
use crate::trace::step::StepOut;
use crate::trace::step::NOT_CONVERGED;
#[cfg(target_arch = "x86_64")]
use crate::trace::step::{self, Approach};
use glam::DVec3;

/// Rays as a structure of arrays (global frame, mm). After
/// [`Tracer::trace_soa`] each ray holds where it ended, and `status` how.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RayBatch {
    /// x of each ray's point, mm.
    pub x: Vec<f64>,
    /// y of each ray's point, mm.
    pub y: Vec<f64>,
    /// z of each ray's point, mm.
    pub z: Vec<f64>,
    /// x of each unit direction.
    pub dx: Vec<f64>,
    /// y of each unit direction.
    pub dy: Vec<f64>,
    /// z of each unit direction.
    pub dz: Vec<f64>,
    /// Optical path length from the start, mm.
    pub opl: Vec<f64>,
    /// 0 while travelling or when reached; otherwise `(step + 1) << 3 | kind`
    /// (kind 1 missed, 2 blocked, 3 total internal reflection, 4 an
    /// asphere's iteration did not converge). Decode with
    /// [`Tracer::outcome_of`].
    pub status: Vec<u64>,
}

impl RayBatch {
    /// An empty batch with room for `n` rays.
    pub fn with_capacity(n: usize) -> Self {
        let v = || Vec::with_capacity(n);
        RayBatch { x: v(), y: v(), z: v(), dx: v(), dy: v(), dz: v(), opl: v(), status: Vec::with_capacity(n) }
    }

    /// Appends a ray (status 0, path length 0).
    pub fn push(&mut self, r: Ray) {
        self.x.push(r.origin.x);
        self.y.push(r.origin.y);
        self.z.push(r.origin.z);
        self.dx.push(r.direction.x);
        self.dy.push(r.direction.y);
        self.dz.push(r.direction.z);
        self.opl.push(0.0);
        self.status.push(0);
    }

    /// Appends a placeholder the tracer leaves alone: a ray that could not
    /// be formed (status `u64::MAX`, which no trace gives).
    pub fn push_skipped(&mut self) {
        self.push(Ray::default());
        if let Some(s) = self.status.last_mut() {
            *s = u64::MAX;
        }
    }

    /// Number of rays.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the batch is empty.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Ray `i` as a kernel lane.
    fn lane(&self, i: usize) -> Lane<f64> {
        Lane {
            px: self.x[i],
            py: self.y[i],
            pz: self.z[i],
            dx: self.dx[i],
            dy: self.dy[i],
            dz: self.dz[i],
            opl: self.opl[i],
        }
    }

    /// Sets ray `i` from a kernel lane (global frame).
    fn set_lane(&mut self, i: usize, l: Lane<f64>) {
        self.x[i] = l.px;
        self.y[i] = l.py;
        self.z[i] = l.pz;
        self.dx[i] = l.dx;
        self.dy[i] = l.dy;
        self.dz[i] = l.dz;
        self.opl[i] = l.opl;
    }

    /// Removes every ray, keeping the allocations.
    pub fn clear(&mut self) {
        for v in [&mut self.x, &mut self.y, &mut self.z, &mut self.dx, &mut self.dy, &mut self.dz, &mut self.opl] {
            v.clear();
        }
        self.status.clear();
    }
}

/// Rays traced per chunk: all surfaces are applied to a chunk before the
/// next, so that its buffers (about 13 KiB) stay in the L1 cache. 64
/// measured 5% faster than 32 and 15% faster than 128
/// (docs/performance.md).
pub(super) const CHUNK: usize = 64;

/// Vectors of four rays per chunk.
#[cfg(target_arch = "x86_64")]
pub(super) const VECTORS: usize = CHUNK / 4;

/// Bit `i` set where `status[i]` is not 0 (at most 64 entries), found
/// without a branch per ray: stopped rays come in no pattern a branch
/// predictor could learn.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn nonzero(status: &[u64]) -> u64 {
    status.iter().enumerate().fold(0, |m, (i, st)| m | u64::from(*st != 0) << i)
}

/// The indices of the bits set in `m`, lowest first.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn ones(mut m: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            i
        })
    })
}

/// The vectors marked in `live` (bit `j` for vector `j` of `W::N` rays,
/// lowest first), each below a chunk's count of them (masked: the kernels'
/// reads then need no bounds checks).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn vectors_in<W: Wide>(live: u64) -> impl Iterator<Item = usize> {
    ones(live).map(vector_below::<W>)
}

/// `j` masked below a chunk's count of `W::N`-ray vectors (a power of two)
/// at four lanes; as it is at eight, whose loops measured 0.05-0.1 ns a
/// step slower with the mask.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn vector_below<W: Wide>(j: usize) -> usize {
    if W::N == 4 {
        j & (CHUNK / W::N - 1)
    } else {
        j
    }
}

/// Asks the caches for rays `r` of `batch` (the next chunk, while this one
/// is traced): a chunk reads 8 arrays a few cache lines each, too little
/// for the hardware prefetcher to run ahead of, and from memory each read
/// would wait.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch_rays(batch: &RayBatch, r: std::ops::Range<usize>) {
    for a in [&batch.x, &batch.y, &batch.z, &batch.dx, &batch.dy, &batch.dz, &batch.opl] {
        prefetch_lines(a[r.clone()].as_ptr(), r.len());
    }
    prefetch_lines(batch.status[r.clone()].as_ptr(), r.len());
}

/// Copies `from` (at most a chunk) into the first values of `to`: for a
/// whole chunk, a vector at a time, inline (a call to `memcpy` for each of
/// a chunk's eight 512-byte arrays cost more than the copy).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn copy_quads(to: &mut [[f64; 4]; VECTORS], from: &[f64]) {
    if from.len() == CHUNK {
        for (t, f) in to.iter_mut().zip(from.chunks_exact(4)) {
            let f: &[f64; 4] = f.try_into().expect("chunks of 4");
            F64x4::load(f).store(t);
        }
    } else {
        to.as_flattened_mut()[..from.len()].copy_from_slice(from);
    }
}

/// Copies the first `to.len()` values (at most a chunk) of `from` into
/// `to`, as [`copy_quads`] does the other way.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn copy_from_quads(to: &mut [f64], from: &[[f64; 4]; VECTORS]) {
    if to.len() == CHUNK {
        for (t, f) in to.chunks_exact_mut(4).zip(from.iter()) {
            let t: &mut [f64; 4] = t.try_into().expect("chunks of 4");
            F64x4::load(f).store(t);
        }
    } else {
        to.copy_from_slice(&from.as_flattened()[..to.len()]);
    }
}

/// Asks the caches for the `n` values of type `T` from `p` (which must lie
/// in one allocation; prefetching never faults).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch_lines<T>(p: *const T, n: usize) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    let bytes = n * std::mem::size_of::<T>();
    for off in (0..bytes).step_by(64) {
        // SAFETY: prefetching never faults; the address stays within the
        // allocation `p` points into (`wrapping_add`, no dereference).
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>().wrapping_add(off)) };
    }
}

/// Rays in groups of four (one AVX2 vector each; two make one AVX-512
/// vector), structure of arrays.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(super) struct Rays4 {
    x: [[f64; 4]; VECTORS],
    y: [[f64; 4]; VECTORS],
    z: [[f64; 4]; VECTORS],
    dx: [[f64; 4]; VECTORS],
    dy: [[f64; 4]; VECTORS],
    dz: [[f64; 4]; VECTORS],
    opl: [[f64; 4]; VECTORS],
}

#[cfg(target_arch = "x86_64")]
impl Rays4 {
    /// Ray `i` (a lane of one vector).
    fn get(&self, i: usize) -> Lane<f64> {
        let (j, k) = (i / 4, i % 4);
        Lane {
            px: self.x[j][k],
            py: self.y[j][k],
            pz: self.z[j][k],
            dx: self.dx[j][k],
            dy: self.dy[j][k],
            dz: self.dz[j][k],
            opl: self.opl[j][k],
        }
    }

    /// The first `n` four-ray vectors carried into a decentred or tilted
    /// surface's own frame ([`Frame::enter`], the one-ray path's
    /// operations four lanes at once).
    #[inline(always)]
    fn enter(&mut self, f: &Frame, n: usize) {
        let f = f.lanes::<F64x4>();
        for j in 0..n {
            let l = f.enter(self.vector(j));
            self.set_vector(j, l);
        }
    }

    /// The first `n` four-ray vectors carried back from a surface's own
    /// frame ([`Frame::leave`]); the lanes not in `alive` (stopped, or
    /// padding) go back on idle.
    #[inline(always)]
    fn leave(&mut self, f: &Frame, n: usize, alive: u64) {
        let f = f.lanes::<F64x4>();
        for j in 0..n {
            let l = f.leave(self.vector(j));
            self.set_vector(j, l);
        }
        for i in ones(!alive & ((1u128 << (4 * n)) - 1) as u64) {
            self.set(i, IDLE);
        }
    }

    /// Vector `j` (rays 4 j to 4 j + 3) as lanes, positions and directions
    /// only (a frame change leaves the path length alone: 0 here).
    #[inline(always)]
    fn vector(&self, j: usize) -> Lane<F64x4> {
        Lane {
            px: F64x4::load(&self.x[j]),
            py: F64x4::load(&self.y[j]),
            pz: F64x4::load(&self.z[j]),
            dx: F64x4::load(&self.dx[j]),
            dy: F64x4::load(&self.dy[j]),
            dz: F64x4::load(&self.dz[j]),
            opl: F64x4::splat(0.0),
        }
    }

    /// Stores the positions and directions of lanes `l` as vector `j`.
    #[inline(always)]
    fn set_vector(&mut self, j: usize, l: Lane<F64x4>) {
        l.px.store(&mut self.x[j]);
        l.py.store(&mut self.y[j]);
        l.pz.store(&mut self.z[j]);
        l.dx.store(&mut self.dx[j]);
        l.dy.store(&mut self.dy[j]);
        l.dz.store(&mut self.dz[j]);
    }

    fn set(&mut self, i: usize, l: Lane<f64>) {
        let (j, k) = (i / 4, i % 4);
        self.x[j][k] = l.px;
        self.y[j][k] = l.py;
        self.z[j][k] = l.pz;
        self.dx[j][k] = l.dx;
        self.dy[j][k] = l.dy;
        self.dz[j][k] = l.dz;
        self.opl[j][k] = l.opl;
    }
}

/// A ray lanes hold once theirs has stopped: on the axis, along it, so the
/// arithmetic the kernel still does on them stays finite and normal.
#[cfg(target_arch = "x86_64")]
const IDLE: Lane<f64> = Lane { px: 0.0, py: 0.0, pz: 0.0, dx: 0.0, dy: 0.0, dz: 1.0, opl: 0.0 };

/// One chunk of rays. The kernel carries every lane through every step
/// without masking, from one of the two `live` buffers into the other; a ray
/// that stops is copied, in the global frame, into `done` (a rare, separate
/// path), and its lane goes on idle.
#[cfg(target_arch = "x86_64")]
#[derive(Clone)]
struct Chunk {
    /// Travelling rays: before step k in `live[k % 2]`, in the frame of the
    /// step before.
    live: [Rays4; 2],
    /// Rays that stopped, in the global frame.
    done: Rays4,
    /// 0 while travelling (or when reached), else as [`RayBatch::status`];
    /// `u64::MAX` for padding.
    status: [[u64; 4]; VECTORS],
    /// Each vector's closest approach to a sphere, between the step's two
    /// loops.
    approach: [f64; CHUNK * 4],
    /// Bit `i` set while ray `i` travels.
    alive: u64,
    /// The CPU has AVX-512F and VL: every step takes eight rays a vector
    /// ([`wide_registers`]).
    wide: bool,
    /// Each step's asphere in four lanes, made once per trace
    /// ([`Chunk::for_tracer`]), `None` for the other steps; empty where the
    /// chunk takes eight lanes.
    aspheres: Vec<Option<AsphereLanes<F64x4>>>,
    /// The same in eight lanes, where the CPU has AVX-512F and VL (empty
    /// elsewhere): an asphere step then takes eight rays a vector.
    aspheres8: Vec<Option<AsphereLanes<F64x8>>>,
    /// An asphere step's numbers between its loops.
    newton: NewtonScratch,
}

/// A step's verdicts for a chunk, one bit per ray.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Default)]
pub(super) struct Bits {
    /// The ray did not pass.
    failed: u64,
    /// It met the surface.
    ok: u64,
    /// ... where an asphere's iteration converged.
    converged: u64,
    /// ... inside the clear aperture.
    inside: u64,
}

#[cfg(target_arch = "x86_64")]
thread_local! {
    /// Each thread's chunk between traces ([`Chunk::for_tracer`]).
    static SPARE_CHUNK: std::cell::Cell<Option<Box<Chunk>>> = const { std::cell::Cell::new(None) };
}

#[cfg(target_arch = "x86_64")]
impl Chunk {
    fn new() -> Box<Self> {
        let v = [[0.0; 4]; VECTORS];
        let rays = Rays4 { x: v, y: v, z: v, dx: v, dy: v, dz: v, opl: v };
        Box::new(Chunk {
            live: [rays; 2],
            done: rays,
            status: [[0; 4]; VECTORS],
            approach: [0.0; CHUNK * 4],
            alive: 0,
            wide: false,
            aspheres: Vec::new(),
            aspheres8: Vec::new(),
            newton: NewtonScratch::ZERO,
        })
    }

    /// A chunk for tracing through `t`'s steps: this thread's spare one
    /// ([`Chunk::keep`]) where there is one, else a new one. Made per
    /// trace, a chunk (13 KiB, built and copied to the heap) cost more than
    /// tracing the few rays of a small batch; every field the kernel reads
    /// is written before it is read, so a used chunk serves as a new one.
    #[inline(always)]
    fn for_tracer(t: &Tracer) -> Box<Self> {
        let mut c = SPARE_CHUNK.take().unwrap_or_else(Chunk::new);
        c.alive = 0;
        // each asphere in the lanes the steps will take, only those (a
        // ring table each, made per trace); no list at all for a tracer
        // without aspheres (a list of empty entries, each the size of an
        // asphere's tables, cost a small batch more than its tracing)
        c.wide = wide_registers();
        c.aspheres.clear();
        c.aspheres8.clear();
        if t.steps.iter().all(|s| s.asphere.is_none()) {
            return c;
        }
        if c.wide {
            // SAFETY: the CPU has AVX-512F and VL (checked by wide_registers).
            c.aspheres8 = unsafe { wide_aspheres(t) };
        } else {
            c.aspheres =
                t.steps.iter().map(|s| s.asphere.map(|a| AsphereLanes::with_zones(s.c, &a, s.sd2, s.zones))).collect();
        }
        c
    }

    /// Keeps `c` as this thread's spare chunk for the next trace.
    fn keep(c: Box<Self>) {
        SPARE_CHUNK.set(Some(c));
    }

    /// Puts ray `i` (global frame) with its status into the chunk.
    fn put(&mut self, i: usize, l: Lane<f64>, status: u64) {
        self.status[i / 4][i % 4] = status;
        if status == 0 {
            self.live[0].set(i, l);
        } else {
            self.done.set(i, l);
            self.live[0].set(i, IDLE);
        }
    }

    /// Ray `i` after tracing `steps` steps, in the global frame, with its
    /// status.
    fn take(&self, i: usize, steps: usize, last_vertex_z: f64) -> (Lane<f64>, u64) {
        let st = self.status[i / 4][i % 4];
        if st == 0 {
            let l = self.live[steps % 2].get(i);
            (Lane { pz: l.pz + last_vertex_z, ..l }, 0)
        } else {
            (self.done.get(i), st)
        }
    }

    /// Rays `0..m` that are not travelling after tracing: those that stopped
    /// and those that came in stopped (their status is not 0).
    fn stopped(&self, m: usize) -> u64 {
        !self.alive & (u64::MAX >> (64 - m))
    }

    /// Pads rays `m..` up to a whole pair of four-ray vectors with idle
    /// lanes and marks the travelling rays alive; returns the number of
    /// four-ray vectors.
    fn pad(&mut self, m: usize) -> usize {
        // whole pairs: an eight-lane step reads two
        let n = m.div_ceil(8) * 2;
        for i in m..n * 4 {
            self.put(i, IDLE, u64::MAX);
        }
        self.alive = !nonzero(&self.status.as_flattened()[..n * 4]);
        n
    }
}

impl Tracer {
    /// Traces every ray of `batch` in place. The batch's rays start in the
    /// global frame and end there, holding the state described by
    /// [`Outcome`]; rays whose `status` is already non-zero are left alone,
    /// and path lengths add to the `opl` a ray starts with. Uses one
    /// chunk buffer (about 13 KiB, kept per thread), nothing per ray.
    pub fn trace_soa(&self, batch: &mut RayBatch) {
        if self.steps.is_empty() {
            // an empty range: nothing to cross
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if simd_fma() {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            unsafe { self.trace_soa_avx2::<false>(batch, &[], &mut ChunkIndices::default()) };
            return;
        }
        self.trace_soa_portable(batch)
    }

    /// [`Self::trace_soa`] that also gives each ray's Fresnel weight in
    /// `weights` (made the batch's length): the fraction of its power that
    /// takes this path, as [`Self::trace_fresnel`] gives it for one ray,
    /// the same bits (1 for a ray that came in stopped). The steps run a
    /// chunk of rays at a time where the CPU has AVX2 and FMA and the
    /// tracer no decentred or tilted step; the weights are taken ray by
    /// ray after each step.
    ///
    /// ```
    /// use glam::DVec3;
    /// use lens::{Prescription, Ray, RayBatch, Tracer};
    /// let p = Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true, "coating": "none"},
    ///   {"thickness": 97.2, "semi_diameter": 12.7, "coating": "none"}]}"#, "<doc>").unwrap();
    /// let ghost = Tracer::ghost(&p, 0, 1, 97.2).unwrap();
    /// let rays: Vec<Ray> = (0..5).map(|k| Ray::new(DVec3::new(0.0, 2.0 * k as f64, -5.0), DVec3::Z).unwrap()).collect();
    /// let mut batch = RayBatch::with_capacity(rays.len());
    /// rays.iter().for_each(|r| batch.push(*r));
    /// let mut weights = Vec::new();
    /// ghost.trace_fresnel_soa(&mut batch, &mut weights);
    /// for (k, r) in rays.iter().enumerate() {
    ///     let (_, w) = ghost.trace_fresnel(*r);
    ///     assert_eq!(weights[k].to_bits(), w.to_bits());
    /// }
    /// // the axial ray: in through one face, reflected by each, out again
    /// let r = (0.5168f64 / 2.5168).powi(2);
    /// assert!((weights[0] - r * r * (1.0 - r) * (1.0 - r)).abs() < 1e-12, "{}", weights[0]);
    /// ```
    pub fn trace_fresnel_soa(&self, batch: &mut RayBatch, weights: &mut Vec<f64>) {
        weights.clear();
        weights.resize(batch.len(), 1.0);
        if self.steps.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if simd_fma() && self.steps.iter().all(|s| s.frame.is_none()) {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            unsafe { self.trace_fresnel_avx2(batch, weights) };
            return;
        }
        self.each_ray(batch, |i, l| {
            let (l, k, kind, w) = self.fresnel_walk(l);
            weights[i] = w;
            (l, k, kind)
        });
    }

    /// [`Self::trace_soa`] ray by ray on the one-ray path: for CPUs without
    /// AVX2 and FMA.
    fn trace_soa_portable(&self, batch: &mut RayBatch) {
        self.each_ray(batch, |_, l| self.walk_lane(l, |_, _, _| {}));
    }

    /// Carries every travelling ray `i` of `batch` one at a time by `walk`
    /// (its state in, its state in the frame of the step `k` where it
    /// stopped and the stop's kind out), and writes back its global state
    /// and status: the one-ray path over a batch.
    pub(super) fn each_ray(
        &self,
        batch: &mut RayBatch,
        mut walk: impl FnMut(usize, Lane<f64>) -> (Lane<f64>, usize, u64),
    ) {
        for i in 0..batch.len() {
            if batch.status[i] != 0 {
                continue;
            }
            let (l, k, kind) = walk(i, batch.lane(i));
            batch.set_lane(i, Lane { pz: l.pz + self.steps[k].vertex_z, ..l });
            batch.status[i] = if kind == PASSED { 0 } else { ((k as u64 + 1) << KIND_BITS) | kind };
        }
    }

    /// Traces `rays` into `out` (pairs up to the shorter length), chunk by
    /// chunk: one chunk buffer (kept per thread), no allocation per ray.
    pub fn trace_batch(&self, rays: &[Ray], out: &mut [Outcome]) {
        #[cfg(target_arch = "x86_64")]
        if simd_fma() {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            unsafe { self.trace_batch_avx2(rays, out) };
            return;
        }
        for (r, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.trace(*r);
        }
    }

    /// Traces rays given as rows `[x y z dx dy dz]` (global frame, mm: the
    /// layout of an (N, 6) array; a direction of any length but zero,
    /// normalised as [`DVec3::normalize`] does) into `out`'s rows (where
    /// and how each ray ended, as [`Self::trace_soa`] leaves it) and
    /// `status` (as [`RayBatch::status`]), chunk by chunk straight from the
    /// rows and back, with no array of the batch's in between. The same
    /// numbers, to the bit, as [`Self::trace_soa`] on the same rays
    /// normalised. Errors with the index of the first row whose numbers are
    /// not all finite or whose direction is zero (the outputs are then
    /// unspecified). Rows beyond the shortest of `rows` / 6, `out` / 6 and
    /// `status` are left alone.
    ///
    /// ```
    /// let p = lens::Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "glass": "SCHOTT:N-BK7", "semi_diameter": 12.7, "stop": true},
    ///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
    /// let rows = [0.0, 5.0, -10.0, 0.0, 0.0, 2.0];
    /// let (mut out, mut status) = ([0.0; 6], [0u64; 1]);
    /// lens::Tracer::forward(&p).trace_rows(&rows, &mut out, &mut status).unwrap();
    /// assert_eq!(status[0], 0);
    /// assert!(out[1].abs() < 0.2 && out[5] > 0.99);
    /// assert_eq!(lens::Tracer::forward(&p).trace_rows(&[0.0; 6], &mut out, &mut status), Err(0));
    /// ```
    pub fn trace_rows(&self, rows: &[f64], out: &mut [f64], status: &mut [u64]) -> Result<(), usize> {
        let n = (rows.len() / 6).min(out.len() / 6).min(status.len());
        let (rows, out, status) = (&rows[..n * 6], &mut out[..n * 6], &mut status[..n]);
        let lane = |r: &[f64]| -> Option<Lane<f64>> {
            let d = DVec3::new(r[3], r[4], r[5]);
            let fine = r[0].is_finite() && r[1].is_finite() && r[2].is_finite() && d.is_finite() && d != DVec3::ZERO;
            let d = d.normalize();
            fine.then_some(Lane { px: r[0], py: r[1], pz: r[2], dx: d.x, dy: d.y, dz: d.z, opl: 0.0 })
        };
        if self.steps.is_empty() {
            for (i, (r, o)) in rows.chunks_exact(6).zip(out.chunks_exact_mut(6)).enumerate() {
                let l = lane(r).ok_or(i)?;
                o.copy_from_slice(&[l.px, l.py, l.pz, l.dx, l.dy, l.dz]);
            }
            status.fill(0);
            return Ok(());
        }
        #[cfg(target_arch = "x86_64")]
        if simd_fma() {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            return unsafe { self.trace_rows_avx2(rows, out, status, lane) };
        }
        for (i, ((r, o), st)) in rows.chunks_exact(6).zip(out.chunks_exact_mut(6)).zip(status.iter_mut()).enumerate() {
            let (l, k, kind) = self.walk_lane(lane(r).ok_or(i)?, |_, _, _| {});
            let l = Lane { pz: l.pz + self.steps[k].vertex_z, ..l };
            o.copy_from_slice(&[l.px, l.py, l.pz, l.dx, l.dy, l.dz]);
            *st = if kind == PASSED { 0 } else { ((k as u64 + 1) << KIND_BITS) | kind };
        }
        Ok(())
    }

    /// [`Self::trace_rows`] on AVX2 + FMA, a chunk at a time: each chunk's
    /// rows gathered into its lanes (`lane` reads and checks a row), traced,
    /// and its rays stored back as rows.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn trace_rows_avx2(
        &self,
        rows: &[f64],
        out: &mut [f64],
        status: &mut [u64],
        lane: impl Fn(&[f64]) -> Option<Lane<f64>>,
    ) -> Result<(), usize> {
        let mut c = Chunk::for_tracer(self);
        let last_z = self.steps[self.steps.len() - 1].vertex_z;
        let n = status.len();
        let mut start = 0;
        while start < n {
            let m = (n - start).min(CHUNK);
            let (from, to) = (&rows[start * 6..(start + m) * 6], &mut out[start * 6..(start + m) * 6]);
            let next = (start + m) * 6..((start + 2 * m).min(n)) * 6;
            prefetch_lines(rows[next.clone()].as_ptr(), next.len() / 8);
            // four rows at a time: loaded as whole vectors, turned into
            // columns in registers, checked and normalised four lanes at
            // once (the same IEEE operations as `lane`'s, so the same bits)
            let groups = m / 4;
            let live = &mut c.live[0];
            let zero = F64x4::splat(0.0);
            for (j, r) in from.chunks_exact(24).enumerate() {
                let r: &[f64; 24] = r.try_into().expect("24 numbers");
                let [x, y, z, dx, dy, dz] = rows_to_columns(r);
                let null = dx.abs().le(zero) & dy.abs().le(zero) & dz.abs().le(zero);
                let finite = x.is_finite() & y.is_finite() & z.is_finite();
                if (finite & dx.is_finite() & dy.is_finite() & dz.is_finite() & !null).bits() != 0b1111 {
                    let k = (0..4).find(|&k| lane(&r[6 * k..6 * k + 6]).is_none()).unwrap_or(0);
                    Chunk::keep(c);
                    return Err(start + 4 * j + k);
                }
                let inv = F64x4::splat(1.0) / (dx * dx + dy * dy + dz * dz).sqrt();
                x.store(&mut live.x[j]);
                y.store(&mut live.y[j]);
                z.store(&mut live.z[j]);
                (dx * inv).store(&mut live.dx[j]);
                (dy * inv).store(&mut live.dy[j]);
                (dz * inv).store(&mut live.dz[j]);
                live.opl[j] = [0.0; 4];
                c.status[j] = [0; 4];
            }
            for (i, r) in from.chunks_exact(6).enumerate().skip(groups * 4) {
                let Some(l) = lane(r) else {
                    Chunk::keep(c);
                    return Err(start + i);
                };
                c.live[0].set(i, l);
                c.status[i / 4][i % 4] = 0;
            }
            self.trace_chunk::<false>(&mut c, m, &ChunkIndices::default());
            let fin = &c.live[self.steps.len() % 2];
            let lz = F64x4::splat(last_z);
            for (j, o) in to.chunks_exact_mut(24).enumerate() {
                let column = |v: &[[f64; 4]; VECTORS]| F64x4::load(&v[j]);
                let columns = [
                    column(&fin.x),
                    column(&fin.y),
                    column(&fin.z) + lz,
                    column(&fin.dx),
                    column(&fin.dy),
                    column(&fin.dz),
                ];
                columns_to_rows(columns, o.try_into().expect("24 numbers"));
            }
            for (i, o) in to.chunks_exact_mut(6).enumerate().skip(groups * 4) {
                let l = fin.get(i);
                o.copy_from_slice(&[l.px, l.py, l.pz + last_z, l.dx, l.dy, l.dz]);
            }
            status[start..start + m].copy_from_slice(&c.status.as_flattened()[..m]);
            for i in ones(c.stopped(m)) {
                let l = c.done.get(i);
                to[i * 6..i * 6 + 6].copy_from_slice(&[l.px, l.py, l.pz, l.dx, l.dy, l.dz]);
            }
            start += m;
        }
        Chunk::keep(c);
        Ok(())
    }

    /// The outcome of ray `i` of a batch traced by [`Self::trace_soa`].
    /// Errors when its `status` is neither 0 nor a code this tracer writes
    /// (a stop at one of its steps), as a status set by hand may be.
    ///
    /// # Panics
    ///
    /// When `i` is not a ray of the batch.
    pub fn outcome_of(&self, batch: &RayBatch, i: usize) -> Result<Outcome, OpticsError> {
        let status = batch.status[i];
        let step = (status >> KIND_BITS) as usize;
        let kind = status & KIND_MASK;
        if status != 0 && (step == 0 || step > self.steps.len() || kind == PASSED || kind > NOT_CONVERGED) {
            return Err(OpticsError::BadInput {
                name: "status",
                value: status as f64,
                expected: "0 (travelling or reached) or a code written by trace_soa: (step + 1) << 3 | kind, kind 1-4",
            });
        }
        let ray = Ray {
            origin: DVec3::new(batch.x[i], batch.y[i], batch.z[i]),
            direction: DVec3::new(batch.dx[i], batch.dy[i], batch.dz[i]),
        };
        Ok(self.decode(ray, batch.opl[i], status))
    }

    fn decode(&self, ray: Ray, opl: f64, status: u64) -> Outcome {
        let (k, kind) = if status == 0 {
            (self.steps.len() - 1, PASSED)
        } else {
            ((status >> KIND_BITS) as usize - 1, status & KIND_MASK)
        };
        self.classify(ray, opl, k, kind)
    }

    /// [`Self::trace_soa`] on AVX2 + FMA, a chunk at a time; with
    /// `PER_RAY`, each ray at its own wavelength (`wavelength_nm`, one per
    /// ray), the glasses' indices evaluated into `ix` for each chunk.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn trace_soa_avx2<const PER_RAY: bool>(
        &self,
        batch: &mut RayBatch,
        wavelength_nm: &[f64],
        ix: &mut ChunkIndices,
    ) {
        self.trace_soa_chunks::<PER_RAY>(batch, wavelength_nm, ix, |_, _, _, _, _, _| {});
    }

    /// [`Self::trace_soa_avx2`], showing `after` each step of each chunk
    /// (the chunk's first ray's index in the batch, then as
    /// [`Self::trace_chunk_with`] shows them). Inlined into callers that
    /// have AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn trace_soa_chunks<const PER_RAY: bool>(
        &self,
        batch: &mut RayBatch,
        wavelength_nm: &[f64],
        ix: &mut ChunkIndices,
        mut after: impl FnMut(usize, usize, &Step, &Rays4, &Rays4, u64),
    ) {
        let mut c = Chunk::for_tracer(self);
        let last_z = self.steps[self.steps.len() - 1].vertex_z;
        let n = batch.len();
        let mut start = 0;
        while start < n {
            let m = (n - start).min(CHUNK);
            let r = start..start + m;
            let live = &mut c.live[0];
            for (to, from) in [
                (&mut live.x, &batch.x),
                (&mut live.y, &batch.y),
                (&mut live.z, &batch.z),
                (&mut live.dx, &batch.dx),
                (&mut live.dy, &batch.dy),
                (&mut live.dz, &batch.dz),
                (&mut live.opl, &batch.opl),
            ] {
                copy_quads(to, &from[r.clone()]);
            }
            c.status.as_flattened_mut()[..m].copy_from_slice(&batch.status[r.clone()]);
            for i in ones(nonzero(&batch.status[r.clone()])) {
                c.put(i, batch.lane(start + i), batch.status[start + i]);
            }
            prefetch_rays(batch, start + m..(start + 2 * m).min(n));
            if PER_RAY {
                if c.wide {
                    // SAFETY: `wide` is set only where the CPU has AVX-512F
                    // and VL (Chunk::for_tracer).
                    unsafe { self.chunk_indices_wide(&wavelength_nm[r.clone()], ix) };
                } else {
                    self.chunk_indices::<F64x4>(&wavelength_nm[r.clone()], ix);
                }
            }
            self.trace_chunk_with::<PER_RAY>(&mut c, m, ix, |k, s, before, now, alive| {
                after(start, k, s, before, now, alive)
            });
            let fin = &c.live[self.steps.len() % 2];
            for (to, from) in [
                (&mut batch.x, &fin.x),
                (&mut batch.y, &fin.y),
                (&mut batch.z, &fin.z),
                (&mut batch.dx, &fin.dx),
                (&mut batch.dy, &fin.dy),
                (&mut batch.dz, &fin.dz),
                (&mut batch.opl, &fin.opl),
            ] {
                copy_from_quads(&mut to[r.clone()], from);
            }
            for z in &mut batch.z[r.clone()] {
                *z += last_z;
            }
            batch.status[r.clone()].copy_from_slice(&c.status.as_flattened()[..m]);
            for i in ones(c.stopped(m)) {
                batch.set_lane(start + i, c.done.get(i));
            }
            start += m;
        }
        Chunk::keep(c);
    }

    /// [`Self::trace_batch`] on AVX2 + FMA, a chunk at a time.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn trace_batch_avx2(&self, rays: &[Ray], out: &mut [Outcome]) {
        let mut c = Chunk::for_tracer(self);
        let last_z = self.steps[self.steps.len() - 1].vertex_z;
        let total = rays.len().min(out.len());
        let (all_rays, out_ptr) = (rays, out.as_ptr());
        for (k, (rays, out)) in rays.chunks(CHUNK).zip(out.chunks_mut(CHUNK)).enumerate() {
            // the next chunk's rays and outcomes into the caches meanwhile
            let next = ((k + 1) * CHUNK).min(total)..((k + 2) * CHUNK).min(total);
            prefetch_lines(all_rays[next.clone()].as_ptr(), next.len());
            prefetch_lines(out_ptr.wrapping_add(next.start), next.len());
            let m = rays.len().min(out.len());
            if m == CHUNK {
                // four rays' fields gathered in registers and stored as one
                // vector each (a store per field and ray cost more)
                let live = &mut c.live[0];
                for (j, r) in rays.chunks_exact(4).enumerate() {
                    let field = |f: fn(&Ray) -> f64| F64x4::new(f(&r[0]), f(&r[1]), f(&r[2]), f(&r[3]));
                    field(|r| r.origin.x).store(&mut live.x[j]);
                    field(|r| r.origin.y).store(&mut live.y[j]);
                    field(|r| r.origin.z).store(&mut live.z[j]);
                    field(|r| r.direction.x).store(&mut live.dx[j]);
                    field(|r| r.direction.y).store(&mut live.dy[j]);
                    field(|r| r.direction.z).store(&mut live.dz[j]);
                    live.opl[j] = [0.0; 4];
                }
                c.status = [[0; 4]; VECTORS];
            } else {
                for (i, r) in rays[..m].iter().enumerate() {
                    c.put(i, Lane::of_ray(r), 0);
                }
            }
            self.trace_chunk::<false>(&mut c, m, &ChunkIndices::default());
            // every ray as reached, without a branch per ray; then the few
            // that stopped
            let fin = &c.live[self.steps.len() % 2];
            for (i, o) in out[..m].iter_mut().enumerate() {
                let l = fin.get(i);
                let ray =
                    Ray { origin: DVec3::new(l.px, l.py, l.pz + last_z), direction: DVec3::new(l.dx, l.dy, l.dz) };
                *o = Outcome::Reached { ray, opl: l.opl };
            }
            for i in ones(c.stopped(m)) {
                let (l, st) = c.take(i, self.steps.len(), last_z);
                let ray = Ray { origin: DVec3::new(l.px, l.py, l.pz), direction: DVec3::new(l.dx, l.dy, l.dz) };
                out[i] = self.decode(ray, l.opl, st);
            }
        }
        Chunk::keep(c);
    }

    /// Runs every step over the first `m` rays of the chunk.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn trace_chunk<const PER_RAY: bool>(&self, c: &mut Chunk, m: usize, ix: &ChunkIndices) {
        self.trace_chunk_with::<PER_RAY>(c, m, ix, |_, _, _, _, _| {});
    }

    /// [`Self::trace_chunk`], showing `after` each step `k` (the step, the
    /// rays before it and after it, each in its step's frame, and the rays
    /// that passed every step so far: bit `i` for ray `i`).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn trace_chunk_with<const PER_RAY: bool>(
        &self,
        c: &mut Chunk,
        m: usize,
        ix: &ChunkIndices,
        mut after: impl FnMut(usize, &Step, &Rays4, &Rays4, u64),
    ) {
        let n = c.pad(m);
        for (k, s) in self.steps.iter().enumerate() {
            // a decentred or tilted surface is met in its own frame
            if let Some(f) = &s.frame {
                c.live[k % 2].enter(f, n.min(VECTORS));
            }
            match (s.refract, s.shape) {
                (_, PARAXIAL) => paraxial_chunk(s, k, c, n),
                (true, ASPHERE) => step_chunk::<true, ASPHERE, PER_RAY>(s, k, c, n, ix),
                (false, ASPHERE) => step_chunk::<false, ASPHERE, PER_RAY>(s, k, c, n, ix),
                (true, PLANE) => step_chunk::<true, PLANE, PER_RAY>(s, k, c, n, ix),
                (true, FLAT) => step_chunk::<true, FLAT, PER_RAY>(s, k, c, n, ix),
                (true, _) => step_chunk::<true, CURVED, PER_RAY>(s, k, c, n, ix),
                (false, PLANE) => step_chunk::<false, PLANE, PER_RAY>(s, k, c, n, ix),
                (false, FLAT) => step_chunk::<false, FLAT, PER_RAY>(s, k, c, n, ix),
                (false, _) => step_chunk::<false, CURVED, PER_RAY>(s, k, c, n, ix),
            }
            if let Some(f) = &s.frame {
                let alive = c.alive;
                c.live[(k + 1) % 2].leave(f, n.min(VECTORS), alive);
            }
            let [a, b] = &c.live;
            let (before, now) = if k.is_multiple_of(2) { (a, b) } else { (b, a) };
            after(k, s, before, now, c.alive & (u64::MAX >> (64 - m.max(1))));
        }
    }

    /// [`Self::trace_fresnel_soa`] on AVX2 + FMA, a chunk at a time, for a
    /// tracer without decentred or tilted steps: each step's weight from
    /// the chunk's rays before and after it, ray by ray by
    /// [`Tracer::passed_weight`] as the one-ray path does.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn trace_fresnel_avx2(&self, batch: &mut RayBatch, weights: &mut [f64]) {
        self.trace_soa_chunks::<false>(batch, &[], &mut ChunkIndices::default(), |start, _, s, before, now, alive| {
            for i in ones(alive) {
                let (b, w) = (before.get(i), &mut weights[start + i]);
                *w = self.passed_weight(*w, s, DVec3::new(b.dx, b.dy, b.dz), b.opl, &now.get(i));
            }
        });
    }
}

/// [`sphere_chunk`] eight rays a vector, over the chunk's first `n`
/// eight-ray vectors.
///
/// # Safety
///
/// The CPU must have AVX2, FMA, AVX-512F and AVX-512VL.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
#[allow(clippy::too_many_arguments)]
unsafe fn sphere_chunk_wide<const REFRACT: bool, const SHAPE: u8, const PER_RAY: bool>(
    s: &Step,
    src: &Rays4,
    dst: &mut Rays4,
    n: usize,
    ix: &ChunkIndices,
    bits: &mut Bits,
    approach: &mut [f64; CHUNK * 4],
) {
    let sl = StepLanes::<F64x8>::of(s);
    sphere_chunk::<F64x8, REFRACT, SHAPE, PER_RAY>(s, &sl, src, dst, n, ix, bits, approach)
}

/// A sphere or plane step over the first `n` vectors of a chunk (`W::N`
/// rays a vector), every lane computed and stored without masking.
///
/// A sphere takes two loops over the chunk, split before the square roots:
/// the closest approach (kept in `approach`), then the rest. Each loop's
/// chain of dependent operations is short enough that the processor runs
/// several vectors at once (docs/performance.md).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sphere_chunk<W: Wide, const REFRACT: bool, const SHAPE: u8, const PER_RAY: bool>(
    s: &Step,
    sl: &StepLanes<W>,
    src: &Rays4,
    dst: &mut Rays4,
    n: usize,
    ix: &ChunkIndices,
    bits: &mut Bits,
    approach: &mut [f64; CHUNK * 4],
) {
    if SHAPE != PLANE {
        for j in 0..n {
            let (p, d, _) = load_rays::<W>(src, j);
            let a = step::approach(sl.c, p[0], p[1], p[2] - sl.shift, d[0], d[1], d[2]);
            put_vectors(approach, j, [a.t0, a.f, a.g, a.disc]);
        }
    }
    for j in 0..n {
        // each ray's own indices (a batch of mixed wavelengths)
        let sl = if PER_RAY { lanes_at(*sl, s, &ix.vector(j)) } else { *sl };
        let (p, d, opl) = load_rays::<W>(src, j);
        let out = if SHAPE == PLANE {
            step_lanes::<W, REFRACT, PLANE>(
                &sl,
                Lane { px: p[0], py: p[1], pz: p[2], dx: d[0], dy: d[1], dz: d[2], opl },
            )
        } else {
            let [t0, f, g, disc] = get4(approach, j);
            let p = [p[0], p[1], p[2] - sl.shift];
            sphere_from_approach::<W, REFRACT, SHAPE>(&sl, &Approach { t0, f, g, disc }, p, d, opl)
        };
        store_out(dst, j, &out, bits);
    }
}

/// Step `k` applied to the first `n` four-ray vectors of a chunk, from
/// `live[k % 2]` into the other buffer: eight rays a vector where the CPU
/// has AVX-512 (`c.wide`), else four; a sphere or plane by
/// [`sphere_chunk`], an asphere by [`asphere_chunk`]. Rays that stopped are
/// recorded after the loops, on a rare path ([`stop_rays`]).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn step_chunk<const REFRACT: bool, const SHAPE: u8, const PER_RAY: bool>(
    s: &Step,
    k: usize,
    c: &mut Chunk,
    n: usize,
    ix: &ChunkIndices,
) {
    let sl = StepLanes::<F64x4>::of(s);
    let n = n.min(VECTORS);
    let Chunk { live: [a, b], done, status, approach, alive, wide, aspheres, aspheres8, newton } = c;
    let (src, dst) = if k.is_multiple_of(2) { (&*a, b) } else { (&*b, a) };
    let mut bits = Bits::default();
    // the step's asphere in the chunk's lanes (only those are made)
    if let Some(a8) = step_asphere::<_, SHAPE>(aspheres8, k) {
        // SAFETY: `aspheres8` is filled only where the CPU has AVX-512F and
        // VL (Chunk::for_tracer); AVX2 and FMA are this function's.
        unsafe { asphere_chunk_of::<F64x8, REFRACT, PER_RAY>(s, a8, src, dst, n.div_ceil(2), ix, &mut bits, newton) }
    } else if let Some(a4) = step_asphere::<_, SHAPE>(aspheres, k) {
        // SAFETY: AVX2 and FMA are this function's
        unsafe { asphere_chunk_of::<F64x4, REFRACT, PER_RAY>(s, a4, src, dst, n, ix, &mut bits, newton) }
    } else if *wide {
        // SAFETY: `wide` is set only where the CPU has AVX-512F and VL
        // (Chunk::for_tracer); AVX2 and FMA are this function's.
        unsafe { sphere_chunk_wide::<REFRACT, SHAPE, PER_RAY>(s, src, dst, n.div_ceil(2), ix, &mut bits, approach) }
    } else {
        sphere_chunk::<F64x4, REFRACT, SHAPE, PER_RAY>(s, &sl, src, dst, n, ix, &mut bits, approach);
    }
    let dying = *alive & bits.failed;
    if dying != 0 {
        *alive &= !dying;
        stop_rays(s, k, src, dst, done, status, bits, dying);
    }
}

/// An ideal-lens step ([`super::step::paraxial_step`]) over the chunk's
/// first `n` four-ray vectors, ray by ray: the same function as the one-ray
/// path, so both agree bit for bit. Its medium's index is the step's own
/// (an ideal lens inside a glass gives a mixed-wavelength batch the
/// primary's optical path; directions do not depend on it).
#[cfg(target_arch = "x86_64")]
fn paraxial_chunk(s: &Step, k: usize, c: &mut Chunk, n: usize) {
    let sl = StepLanes::<f64>::of(s);
    let n = n.min(VECTORS);
    let Chunk { live: [a, b], done, status, alive, .. } = c;
    let (src, dst) = if k.is_multiple_of(2) { (&*a, b) } else { (&*b, a) };
    let mut bits = Bits::default();
    for i in 0..4 * n {
        let l = src.get(i);
        if *alive >> i & 1 == 0 {
            dst.set(i, l);
            continue;
        }
        let out = super::step::paraxial_step(&sl, s.focal, l);
        dst.set(i, out.next);
        let v = out.verdict;
        bits.failed |= u64::from(!v.passed) << i;
        bits.ok |= u64::from(v.ok) << i;
        bits.converged |= u64::from(v.converged) << i;
        bits.inside |= u64::from(v.inside) << i;
    }
    let dying = *alive & bits.failed;
    if dying != 0 {
        *alive &= !dying;
        stop_rays(s, k, src, dst, done, status, bits, dying);
    }
}

/// Step `k`'s asphere from a chunk's list of them (`aspheres` or
/// `aspheres8`, whichever [`Chunk::for_tracer`] made), `None` for a step of
/// another `SHAPE` or a list not made.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn step_asphere<T, const SHAPE: u8>(list: &[Option<T>], k: usize) -> Option<&T> {
    if SHAPE == ASPHERE {
        list.get(k).and_then(Option::as_ref)
    } else {
        None
    }
}

/// A vector of rays: four lanes (AVX2) or eight (AVX-512), read from and
/// written to a chunk's arrays (each `CHUNK` numbers, vector `j` at lanes
/// `j N .. (j + 1) N`).
#[cfg(target_arch = "x86_64")]
pub(super) trait Wide: Real + NewtonFlags {
    /// Lanes per vector.
    const N: usize;
    /// Vector `j` of `s`.
    fn at(s: &[f64], j: usize) -> Self;
    /// Stores into vector `j` of `s`.
    fn put(self, s: &mut [f64], j: usize);
    /// One bit per lane of `m`, lane 0 the lowest.
    fn mask_bits(m: Self::Mask) -> u64;
    /// The lanes of `lo` then `hi` in one vector of f32 lanes (each
    /// rounded to the nearest f32), in which an asphere's start is made.
    fn narrow(lo: Self, hi: Self) -> Self::F32;
    /// [`Self::narrow`]'s two vectors back from its f32 lanes (exactly).
    fn widen(x: Self::F32) -> (Self, Self);
    /// The f32 vector held in the bytes of vector `j` of `s`.
    fn at32(s: &[f64], j: usize) -> Self::F32;
    /// Stores an f32 vector into the bytes of vector `j` of `s`.
    fn put32(x: Self::F32, s: &mut [f64], j: usize);
    /// [`asphere_chunk`] for one kind of asphere at this width, over the
    /// chunk's first `n` vectors, compiled with the width's target
    /// features: a function of its own for each kind (`THIRD`, `ODD`,
    /// `TERMS`) and width, so that one kind's code and its layout do not
    /// move with another's (all kinds in one function, adding a kind moved
    /// the others' steps by 0.1-0.2 ns). Its arguments one by one, not in a
    /// struct: references read from a struct are not known apart, and the
    /// kernel then reloads what it keeps in registers (measured: 0.4 ns a
    /// step slower).
    ///
    /// # Safety
    ///
    /// The CPU must have the width's target features: AVX2 and FMA, and
    /// for eight lanes AVX-512F and AVX-512VL.
    #[allow(clippy::too_many_arguments)]
    unsafe fn asphere_kind<
        const REFRACT: bool,
        const PER_RAY: bool,
        const THIRD: bool,
        const ODD: bool,
        const TERMS: usize,
    >(
        s: &Step,
        a: &AsphereLanes<Self>,
        src: &Rays4,
        dst: &mut Rays4,
        n: usize,
        ix: &ChunkIndices,
        bits: &mut Bits,
        nw: &mut NewtonScratch,
    );
}

/// [`Wide`] for a lane type `$t` of `$n` lanes with `load`, `store` and a
/// mask type `$mask` with `bits`, its kernel for one kind of asphere
/// compiled with `$features`.
macro_rules! wide {
    ($t:ident, $mask:ident, $f32:ident, $n:literal, $features:literal) => {
        #[cfg(target_arch = "x86_64")]
        impl Wide for $t {
            const N: usize = $n;
            #[inline(always)]
            fn at(s: &[f64], j: usize) -> Self {
                $t::load(s[$n * j..].first_chunk().expect("a whole vector"))
            }
            #[inline(always)]
            fn put(self, s: &mut [f64], j: usize) {
                self.store(s[$n * j..].first_chunk_mut().expect("a whole vector"));
            }
            #[inline(always)]
            fn mask_bits(m: $mask) -> u64 {
                u64::from(m.bits())
            }
            #[inline(always)]
            fn narrow(lo: Self, hi: Self) -> $f32 {
                $f32::narrow(lo, hi)
            }
            #[inline(always)]
            fn widen(x: $f32) -> (Self, Self) {
                x.widen()
            }
            #[inline(always)]
            fn at32(s: &[f64], j: usize) -> $f32 {
                $f32::load_bits(s[$n * j..].first_chunk().expect("a whole vector"))
            }
            #[inline(always)]
            fn put32(x: $f32, s: &mut [f64], j: usize) {
                x.store_bits(s[$n * j..].first_chunk_mut().expect("a whole vector"));
            }
            #[target_feature(enable = $features)]
            #[inline(never)]
            unsafe fn asphere_kind<
                const REFRACT: bool,
                const PER_RAY: bool,
                const THIRD: bool,
                const ODD: bool,
                const TERMS: usize,
            >(
                s: &Step,
                a: &AsphereLanes<Self>,
                src: &Rays4,
                dst: &mut Rays4,
                n: usize,
                ix: &ChunkIndices,
                bits: &mut Bits,
                nw: &mut NewtonScratch,
            ) {
                let sl = StepLanes::<$t>::of(s);
                asphere_chunk::<$t, REFRACT, PER_RAY, THIRD, ODD, TERMS>(s, &sl, a, src, dst, n, ix, bits, nw)
            }
        }
    };
}

wide!(F64x4, M64x4, F32x8, 4, "avx2,fma");
wide!(F64x8, M64x8, F32x16, 8, "avx2,fma,avx512f,avx512vl");

/// Vector `j` of `rays`: points, directions, path lengths.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn load_rays<W: Wide>(rays: &Rays4, j: usize) -> ([W; 3], [W; 3], W) {
    let at = vector_of::<W>;
    (
        [at(&rays.x, j), at(&rays.y, j), at(&rays.z, j)],
        [at(&rays.dx, j), at(&rays.dy, j), at(&rays.dz, j)],
        at(&rays.opl, j),
    )
}

/// Vector `j` of one of a chunk's arrays. A function, not a closure: a
/// closure that is not inlined runs outside the caller's target features.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn vector_of<W: Wide>(a: &[[f64; 4]; VECTORS], j: usize) -> W {
    W::at(a.as_flattened(), j)
}

/// Stores a step's result for vector `j` into `dst` and its verdicts into
/// `bits`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn store_out<W: Wide>(dst: &mut Rays4, j: usize, out: &StepOut<W>, bits: &mut Bits) {
    let o = out.next;
    o.px.put(dst.x.as_flattened_mut(), j);
    o.py.put(dst.y.as_flattened_mut(), j);
    o.pz.put(dst.z.as_flattened_mut(), j);
    o.dx.put(dst.dx.as_flattened_mut(), j);
    o.dy.put(dst.dy.as_flattened_mut(), j);
    o.dz.put(dst.dz.as_flattened_mut(), j);
    o.opl.put(dst.opl.as_flattened_mut(), j);
    let v = out.verdict;
    let (all, at) = (u64::MAX >> (64 - W::N), W::N * j);
    bits.failed |= (!W::mask_bits(v.passed) & all) << at;
    bits.ok |= W::mask_bits(v.ok) << at;
    bits.converged |= W::mask_bits(v.converged) << at;
    bits.inside |= W::mask_bits(v.inside) << at;
}

/// Four vectors stored one after another for each vector `j`: vector
/// `j`'s `k`-th is vector `4 j + k` of `from`. Written out (no loop, no
/// closure): `array::from_fn`'s closure stayed a call outside the AVX2
/// function, and a loop into an array was slower at eight lanes.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn get4<W: Wide>(from: &[f64], j: usize) -> [W; 4] {
    let j = 4 * j;
    [W::at(from, j), W::at(from, j + 1), W::at(from, j + 2), W::at(from, j + 3)]
}

/// Six vectors for each vector `j`, as [`get4`] reads four.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn get6<W: Wide>(from: &[f64], j: usize) -> [W; 6] {
    let j = 6 * j;
    let at = W::at;
    [at(from, j), at(from, j + 1), at(from, j + 2), at(from, j + 3), at(from, j + 4), at(from, j + 5)]
}

/// Stores `K` vectors for vector `j` as [`get4`] and [`get6`] read them.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn put_vectors<W: Wide, const K: usize>(to: &mut [f64], j: usize, v: [W; K]) {
    for (k, v) in v.into_iter().enumerate() {
        v.put(to, j * K + k);
    }
}

/// Whether the batch takes eight rays a vector: the CPU has AVX-512F and
/// AVX-512VL (detected once, cached by the standard library) and the
/// environment variable `LENS_SIMD` is not `avx2` (which keeps the four-lane
/// kernels, to compare the two: docs/performance.md). Both give the same
/// bits.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(super) fn wide_registers() -> bool {
    static FOUR_LANES: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    #[cfg(test)]
    if tests::NARROW.with(|n| n.get()) {
        return false;
    }
    std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512vl")
        && !*FOUR_LANES.get_or_init(|| std::env::var("LENS_SIMD").is_ok_and(|v| v == "avx2"))
}

/// Each step's asphere in eight lanes (`None` for the other steps), made
/// where those lanes can be.
///
/// # Safety
///
/// The CPU must have AVX2, FMA, AVX-512F and AVX-512VL.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
unsafe fn wide_aspheres(t: &Tracer) -> Vec<Option<AsphereLanes<F64x8>>> {
    t.steps.iter().map(|s| s.asphere.map(|a| AsphereLanes::with_zones(s.c, &a, s.sd2, s.zones))).collect()
}

/// The rays marked in `dying` (bit `i` for ray `i` of the chunk) stopped at
/// step `k`: their states, as [`stopped`] gives them from `before` and
/// `after` the step (the one-ray path's own function), go to `done` in the
/// global frame, their status says where and how, and their lanes go idle.
#[cfg(target_arch = "x86_64")]
#[cold]
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn stop_rays(
    s: &Step,
    k: usize,
    before: &Rays4,
    after: &mut Rays4,
    done: &mut Rays4,
    status: &mut [[u64; 4]; VECTORS],
    bits: Bits,
    dying: u64,
) {
    for i in ones(dying) {
        let (j, lane) = (i / 4, i % 4);
        let [ok, converged, inside] = [bits.ok, bits.converged, bits.inside].map(|m| m >> i & 1 != 0);
        // a ray that met the surface inside its aperture and stopped was
        // totally reflected
        let kind = kind_of(ok, converged, inside, false);
        let l = stopped(s, before.get(i), after.get(i), kind);
        let l = s.frame.map_or(l, |f| f.leave(l));
        done.set(i, Lane { pz: l.pz + s.vertex_z, ..l });
        status[j][lane] = ((k as u64 + 1) << KIND_BITS) | kind;
        after.set(i, IDLE);
    }
}

#[cfg(test)]
mod tests {
    use crate::trace::bench::Workload;
    use crate::trace::SpectralBatch;
    use crate::Prescription;
    use std::cell::Cell;

    thread_local! {
        /// Set: this thread's batches take four rays a vector even where
        /// the CPU has AVX-512 ([`super::wide_registers`]).
        pub(super) static NARROW: Cell<bool> = const { Cell::new(false) };
    }

    /// The four-lane and eight-lane kernels give the same bits, sphere,
    /// plane and asphere steps (rings, even, odd terms), one wavelength and
    /// mixed, with chunks not a whole number of vectors and rays that
    /// arrive stopped. Where the CPU has no AVX-512 both runs take four
    /// lanes and the test compares that path with itself.
    #[test]
    fn four_and_eight_lanes_agree() {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for name in [
            "double-gauss-50mm.json",
            "library/canon-35mm-f2-is-aspheric-us20150205081.json",
            "library/phone-5.6mm-f3.5-us7535658.json",
            "library/kit-zoom-18.5mm-f3.5-wide-us7277232.json",
            "library/sony-planar-50mm-f1.4-aspheric-us20140071331.json",
        ] {
            let path = format!("{}/../../lens-data/{name}", env!("CARGO_MANIFEST_DIR"));
            let p = Prescription::load(&path).unwrap();
            let w = Workload::new(&p, 1001).unwrap();
            let mut wide = SpectralBatch { rays: w.rays.clone(), wavelength_nm: w.wavelength_nm.clone() };
            wide.rays.status[7] = 9;
            let mut narrow = wide.clone();
            let (mut wide_one, mut narrow_one) = (wide.rays.clone(), wide.rays.clone());
            w.tracer.trace_spectral(&mut wide).unwrap();
            w.tracer.trace_soa(&mut wide_one);
            NARROW.with(|n| n.set(true));
            w.tracer.trace_spectral(&mut narrow).unwrap();
            w.tracer.trace_soa(&mut narrow_one);
            NARROW.with(|n| n.set(false));
            for (a, b) in [(&wide.rays, &narrow.rays), (&wide_one, &narrow_one)] {
                assert_eq!(a.status, b.status, "{name}");
                assert!(a.status.iter().filter(|s| **s == 0).count() > 500, "{name}: most rays pass");
                for (x, y) in [(&a.x, &b.x), (&a.y, &b.y), (&a.z, &b.z), (&a.dx, &b.dx), (&a.dy, &b.dy)] {
                    assert_eq!(bits(x), bits(y), "{name}");
                }
                assert_eq!(bits(&a.dz), bits(&b.dz), "{name}");
                assert_eq!(bits(&a.opl), bits(&b.opl), "{name}");
            }
        }
    }

    /// The portable path (for CPUs without AVX2) gives the vector path's
    /// bits, also for rays already finished.
    #[test]
    fn portable_batch_is_the_vector_batch() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/double-gauss-50mm.json");
        let p = Prescription::load(path).unwrap();
        let w = Workload::new(&p, 1001).unwrap();
        let mut a = w.rays.clone();
        a.status[7] = 9;
        let mut b = a.clone();
        w.tracer.trace_soa(&mut a);
        w.tracer.trace_soa_portable(&mut b);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(a.status, b.status);
        assert!(a.status.iter().any(|s| *s != 0 && *s != 9));
        for (x, y) in [(&a.x, &b.x), (&a.y, &b.y), (&a.z, &b.z), (&a.dx, &b.dx), (&a.dz, &b.dz), (&a.opl, &b.opl)] {
            assert_eq!(bits(x), bits(y));
        }
    }
}
