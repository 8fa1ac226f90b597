//! Tracing many rays at once: structure of arrays, surfaces in the outer loop,
//! rays in the inner loop, finished rays masked rather than branched on, so
//! that the compiler vectorises the inner loop. Results are bit-for-bit those
//! of [`Tracer::trace`], which runs the same per-surface kernel.

use crate::intersect::LaneHit;
use crate::ray::{Outcome, Ray};
use crate::trace::{finish_lane, shift_and_hit, Lane, Step, Tracer, PASSED};
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
    /// 0 while travelling or when reached; otherwise `(step + 1) << 2 | kind`
    /// (kind 1 missed, 2 blocked, 3 total internal reflection). Decode with
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

    /// Number of rays.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the batch is empty.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
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
/// next, so the two chunks (2 x 6.5 KiB) stay in the L1 cache. 16 to 64 rays
/// measured 10-15% faster than 256 on Zen 3 (docs/performance.md).
const CHUNK: usize = 64;

/// One chunk of rays as a structure of arrays. Each surface reads one chunk
/// and writes another (ping-pong): writing in place would let the compiler
/// turn the "keep finished rays" selects into masked stores, which are slow.
#[derive(Clone)]
struct Chunk {
    x: [f64; CHUNK],
    y: [f64; CHUNK],
    z: [f64; CHUNK],
    dx: [f64; CHUNK],
    dy: [f64; CHUNK],
    dz: [f64; CHUNK],
    opl: [f64; CHUNK],
    status: [u64; CHUNK],
    /// Scratch between the two passes of a surface: each ray's hit point,
    /// distance and whether it exists. Kept apart from the outputs: parked in
    /// them, the "keep the old value" selects became masked stores.
    hx: [f64; CHUNK],
    hy: [f64; CHUNK],
    hz: [f64; CHUNK],
    ht: [f64; CHUNK],
    hok: [u64; CHUNK],
}

impl Chunk {
    fn new() -> Box<Self> {
        Box::new(Chunk {
            x: [0.0; CHUNK],
            y: [0.0; CHUNK],
            z: [0.0; CHUNK],
            dx: [0.0; CHUNK],
            dy: [0.0; CHUNK],
            dz: [0.0; CHUNK],
            opl: [0.0; CHUNK],
            status: [0; CHUNK],
            hx: [0.0; CHUNK],
            hy: [0.0; CHUNK],
            hz: [0.0; CHUNK],
            ht: [0.0; CHUNK],
            hok: [0; CHUNK],
        })
    }
}

impl Tracer {
    /// Traces every ray of `batch` in place. The batch's rays start in the
    /// global frame and end there, holding the state described by
    /// [`Outcome`]; rays whose `status` is already non-zero are left alone.
    /// Allocates two chunk buffers (13 KiB) per call, nothing per ray.
    pub fn trace_soa(&self, batch: &mut RayBatch) {
        let n = batch.len();
        let (mut a, mut b) = (Chunk::new(), Chunk::new());
        let mut start = 0;
        while start < n {
            let m = (n - start).min(CHUNK);
            let r = start..start + m;
            a.x[..m].copy_from_slice(&batch.x[r.clone()]);
            a.y[..m].copy_from_slice(&batch.y[r.clone()]);
            a.z[..m].copy_from_slice(&batch.z[r.clone()]);
            a.dx[..m].copy_from_slice(&batch.dx[r.clone()]);
            a.dy[..m].copy_from_slice(&batch.dy[r.clone()]);
            a.dz[..m].copy_from_slice(&batch.dz[r.clone()]);
            a.opl[..m].copy_from_slice(&batch.opl[r.clone()]);
            a.status[..m].copy_from_slice(&batch.status[r.clone()]);
            let out = self.trace_chunk(&mut a, &mut b, m);
            batch.x[r.clone()].copy_from_slice(&out.x[..m]);
            batch.y[r.clone()].copy_from_slice(&out.y[..m]);
            batch.z[r.clone()].copy_from_slice(&out.z[..m]);
            batch.dx[r.clone()].copy_from_slice(&out.dx[..m]);
            batch.dy[r.clone()].copy_from_slice(&out.dy[..m]);
            batch.dz[r.clone()].copy_from_slice(&out.dz[..m]);
            batch.opl[r.clone()].copy_from_slice(&out.opl[..m]);
            batch.status[r].copy_from_slice(&out.status[..m]);
            start += m;
        }
    }

    /// Traces `rays` into `out` (pairs up to the shorter length), chunk by
    /// chunk: two chunk buffers per call, no allocation per ray.
    pub fn trace_batch(&self, rays: &[Ray], out: &mut [Outcome]) {
        let (mut a, mut b) = (Chunk::new(), Chunk::new());
        for (rays, out) in rays.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
            let m = rays.len().min(out.len());
            for (i, r) in rays[..m].iter().enumerate() {
                a.x[i] = r.origin.x;
                a.y[i] = r.origin.y;
                a.z[i] = r.origin.z;
                a.dx[i] = r.direction.x;
                a.dy[i] = r.direction.y;
                a.dz[i] = r.direction.z;
                a.opl[i] = 0.0;
                a.status[i] = 0;
            }
            let c = self.trace_chunk(&mut a, &mut b, m);
            for (i, o) in out[..m].iter_mut().enumerate() {
                let ray = Ray {
                    origin: DVec3::new(c.x[i], c.y[i], c.z[i]),
                    direction: DVec3::new(c.dx[i], c.dy[i], c.dz[i]),
                };
                *o = self.decode(ray, c.opl[i], c.status[i]);
            }
        }
    }

    /// The outcome of ray `i` of a batch traced by [`Self::trace_soa`].
    pub fn outcome_of(&self, batch: &RayBatch, i: usize) -> Outcome {
        let ray = Ray {
            origin: DVec3::new(batch.x[i], batch.y[i], batch.z[i]),
            direction: DVec3::new(batch.dx[i], batch.dy[i], batch.dz[i]),
        };
        self.decode(ray, batch.opl[i], batch.status[i])
    }

    fn decode(&self, ray: Ray, opl: f64, status: u64) -> Outcome {
        let (k, kind) =
            if status == 0 { (self.steps.len() - 1, PASSED) } else { ((status >> 2) as usize - 1, status & 3) };
        self.classify(ray, opl, k, kind)
    }

    /// Runs every step over the first `m` rays of `a`, using `b` as scratch;
    /// returns the chunk that holds the result, in the global frame.
    fn trace_chunk<'c>(&self, a: &'c mut Chunk, b: &'c mut Chunk, m: usize) -> &'c mut Chunk {
        #[cfg(target_arch = "x86_64")]
        let avx2 = crate::trace::simd_fma();
        let (mut src, mut dst) = (a, b);
        for (k, s) in self.steps.iter().enumerate() {
            let code = ((k as u64) + 1) << 2;
            #[cfg(target_arch = "x86_64")]
            if avx2 {
                // SAFETY: the CPU supports AVX2 (checked above).
                unsafe {
                    if s.refract {
                        step_chunk_avx2::<true>(s, code, src, dst, m);
                    } else {
                        step_chunk_avx2::<false>(s, code, src, dst, m);
                    }
                }
                std::mem::swap(&mut src, &mut dst);
                continue;
            }
            if s.refract {
                step_chunk::<true>(s, code, src, dst, m);
            } else {
                step_chunk::<false>(s, code, src, dst, m);
            }
            std::mem::swap(&mut src, &mut dst);
        }
        // Back to the global frame: each ray is in the frame of the step where
        // it stopped (the last step when it passed every one).
        let last = self.steps.len() - 1;
        for (z, st) in src.z[..m].iter_mut().zip(src.status[..m].iter()) {
            let k = if *st == 0 { last } else { (*st >> 2) as usize - 1 };
            *z += self.steps[k].vertex_z;
        }
        src
    }
}

/// [`step_chunk`] compiled for AVX2 (4 f64 lanes) and hardware fused
/// multiply-add, chosen at run time.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn step_chunk_avx2<const REFRACT: bool>(s: &Step, code: u64, src: &Chunk, dst: &mut Chunk, m: usize) {
    step_chunk::<REFRACT>(s, code, src, dst, m)
}

/// One surface applied to the first `m` rays of `src`, written to `dst`.
/// Finished rays are copied unchanged; a ray that stops here gets `code`
/// (the step) with its kind. Two passes over the chunk (intersect, then clip
/// and refract) keep each loop body short, so the processor overlaps the
/// long square-root and division latencies of neighbouring rays.
#[inline(always)]
fn step_chunk<const REFRACT: bool>(s: &Step, code: u64, src: &Chunk, dst: &mut Chunk, m: usize) {
    let m = m.min(CHUNK);
    // Pass 1: the hit of every ray, parked in dst's scratch arrays.
    for i in 0..m {
        let lane = Lane {
            px: src.x[i],
            py: src.y[i],
            pz: src.z[i],
            dx: src.dx[i],
            dy: src.dy[i],
            dz: src.dz[i],
            opl: src.opl[i],
        };
        let (_, h) = shift_and_hit(s, lane);
        dst.hx[i] = h.x;
        dst.hy[i] = h.y;
        dst.hz[i] = h.z;
        dst.ht[i] = h.t;
        dst.hok[i] = h.ok as u64;
    }
    // Pass 2: clip, refract, classify; keep finished rays as they were.
    for i in 0..m {
        let st = src.status[i];
        let alive = st == 0;
        let lane = Lane {
            px: src.x[i],
            py: src.y[i],
            pz: src.z[i] - s.shift,
            dx: src.dx[i],
            dy: src.dy[i],
            dz: src.dz[i],
            opl: src.opl[i],
        };
        let h = LaneHit { t: dst.ht[i], x: dst.hx[i], y: dst.hy[i], z: dst.hz[i], ok: dst.hok[i] != 0 };
        let (next, kind) = finish_lane::<REFRACT>(s, lane, h);
        // bitwise blends: plain selects here were turned into masked stores
        let keep = (alive as u64).wrapping_neg();
        dst.x[i] = blend(keep, next.px, src.x[i]);
        dst.y[i] = blend(keep, next.py, src.y[i]);
        dst.z[i] = blend(keep, next.pz, src.z[i]);
        dst.dx[i] = blend(keep, next.dx, src.dx[i]);
        dst.dy[i] = blend(keep, next.dy, src.dy[i]);
        dst.dz[i] = blend(keep, next.dz, src.dz[i]);
        dst.opl[i] = blend(keep, next.opl, src.opl[i]);
        dst.status[i] = if alive && kind != PASSED { code | kind } else { st };
    }
}

/// `a` where `mask` is all ones, `b` where it is zero, bit by bit.
#[inline(always)]
fn blend(mask: u64, a: f64, b: f64) -> f64 {
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}
