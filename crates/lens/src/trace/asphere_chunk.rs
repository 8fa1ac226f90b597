//! The aspheric step over a chunk of the batch (`batch.rs`): the stages of
//! `asphere.rs`'s kernel run in lock step over the chunk's vectors, each a
//! loop that leaves what the next needs in the chunk's scratch
//! ([`NewtonScratch`]): the start in f32 lanes over pairs of vectors (the
//! rays narrowed, each ray's ring and its conic, the roots, the starts),
//! Newton's passes over the vectors still iterating, the hits' normals, the
//! refractions. One function per kind of asphere and width
//! ([`super::batch::Wide::asphere_kind`] calls [`asphere_chunk`]), so each
//! lane takes the one-ray path's steps and the bits agree.

use super::asphere::{
    along, asphere_carry, by_asphere_kind, conic_only_root, conic_only_start, conic_root_of, hit_with_normal, is_far,
    newton_eval, newton_finish, newton_hit, newton_running, newton_start_at, ring_conic, ring_or_start, start_root,
    start_u, to_vertex_plane, zones_of, AsphereLanes, ConicRoot, Newton, NewtonEval, StartConic, MAX_NEWTON_STEPS,
};
use super::batch::{get4, get6, load_rays, put_vectors, store_out, vectors_in, Bits, Rays4, Wide, CHUNK};
use super::spectral::ChunkIndices;
use super::step::{lanes_at, Step, StepLanes};
use crate::simd::avx2::{F64x4, M64x4};
use crate::simd::avx512::{F64x8, M64x8};
use crate::simd::lanes::{Mask, Real};

/// [`asphere_chunk`] for the surface `a`'s kind of step, `W::N` rays a
/// vector over the chunk's first `n` vectors ([`Wide::asphere_kind`]).
///
/// # Safety
///
/// The CPU must have `W`'s target features ([`Wide::asphere_kind`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn asphere_chunk_of<W: Wide, const REFRACT: bool, const PER_RAY: bool>(
    s: &Step,
    a: &AsphereLanes<W>,
    src: &Rays4,
    dst: &mut Rays4,
    n: usize,
    ix: &ChunkIndices,
    b: &mut Bits,
    nw: &mut NewtonScratch,
) {
    macro_rules! go {
        ($third:literal, $odd:literal, $terms:literal) => {
            // SAFETY: the caller's
            unsafe { W::asphere_kind::<REFRACT, PER_RAY, $third, $odd, $terms>(s, a, src, dst, n, ix, b, nw) }
        };
    }
    by_asphere_kind!(a, go)
}

/// The start conic of pair `q` (f32 lanes) into the first four of its six
/// root numbers in `nw` (its conic root's loop reads them).
#[inline(always)]
fn put_start_conic<W: Wide>(nw: &mut NewtonScratch, q: usize, sc: StartConic<W::F32>) {
    for (k, v) in [sc.c, sc.kc, sc.k1c, sc.pz].into_iter().enumerate() {
        W::put32(v, &mut nw.root, 6 * q + k);
    }
}

/// The rays of vectors `2 q` and `2 q + 1` in the surface's frame (`shift`
/// the step's), narrowed to f32 lanes (points and directions), and whether
/// some lane is far ([`is_far`]): then the far lanes' points are first moved
/// along their rays to near the vertex plane, by `t0` ([`to_vertex_plane`],
/// stored in each vector's state as `u`, 0 for the other lanes), which the
/// start adds back.
#[inline(always)]
fn pair_rays<W: Wide>(src: &Rays4, shift: W, q: usize, nw: &mut NewtonScratch) -> ([W::F32; 3], [W::F32; 3], bool) {
    let (p0, d0, _) = load_rays::<W>(src, 2 * q);
    let (p1, d1, _) = load_rays::<W>(src, 2 * q + 1);
    let (mut p0, mut p1) = ([p0[0], p0[1], p0[2] - shift], [p1[0], p1[1], p1[2] - shift]);
    let (far0, far1) = (is_far(p0), is_far(p1));
    let far = (far0 | far1).any();
    if far {
        let zero = W::splat(0.0);
        let (t0, t1) = (W::select(far0, to_vertex_plane(p0, d0), zero), W::select(far1, to_vertex_plane(p1, d1), zero));
        t0.put(&mut nw.state, 5 * (2 * q));
        t1.put(&mut nw.state, 5 * (2 * q + 1));
        (p0, p1) = (along(p0, d0, t0), along(p1, d1, t1));
    }
    (
        [W::narrow(p0[0], p1[0]), W::narrow(p0[1], p1[1]), W::narrow(p0[2], p1[2])],
        [W::narrow(d0[0], d1[0]), W::narrow(d0[1], d1[1]), W::narrow(d0[2], d1[2])],
        far,
    )
}

/// The start `u` of vector `j` (starting at `p`) from its f32 start `u32`
/// widened: `t0 + u32` in its far lanes, where [`pair_rays`] moved the
/// point by `t0`, if its pair has any (`far`).
#[inline(always)]
fn start_of_vector<W: Wide>(nw: &NewtonScratch, j: usize, p: [W; 3], u32: W, far: bool) -> W {
    if far {
        W::select(is_far(p), W::at(&nw.state, 5 * j) + u32, u32)
    } else {
        u32
    }
}

/// What [`asphere_chunk`] keeps for each vector between its loops, the
/// kernel's structs as plain numbers: the ray's ring and its conic, then the
/// conic's root (until the start), Newton's iteration (what changes between
/// passes), a pass's evaluation (until its division) and the hit's normal
/// (until the refraction). Only what the surface's kind of step reads is
/// stored: a third-order step's hit evaluates its own normal, so neither
/// its state nor its evaluation keeps `Q` and `m`; the iteration's flags
/// as each width reads them fastest ([`NewtonFlags`]). Each array of
/// numbers holds, for each vector in turn, its numbers one vector after
/// another ([`get4`]), whatever the vector's width.
#[derive(Clone, Copy)]
pub(super) struct NewtonScratch {
    root: [f64; CHUNK * 6],
    /// A vector's `u`, then (four lanes) its flags converged and missed as
    /// numbers or (eight lanes) two unused slots (packing `q` and `m` after
    /// `u` measured 0.04-0.2 ns a step slower, docs/performance.md), then
    /// `q` and `m`.
    state: [f64; CHUNK * 5],
    /// Eight lanes: the iteration's flags, converged and missed, a bit a
    /// lane (mask bits, not numbers: fewer instructions a pass;
    /// [`NewtonFlags`]).
    flags: [[u8; 2]; CHUNK],
    eval: [f64; CHUNK * 5],
    normal: [f64; CHUNK * 4],
    /// Each pair of vectors' rays narrowed to f32 lanes for the start
    /// (points, then directions: six f32 vectors, each in one vector's
    /// bytes), narrowed once instead of in each of the start's loops.
    rays32: [f64; CHUNK * 3],
}

impl NewtonScratch {
    pub(super) const ZERO: NewtonScratch = NewtonScratch {
        root: [0.0; CHUNK * 6],
        state: [0.0; CHUNK * 5],
        flags: [[0; 2]; CHUNK],
        eval: [0.0; CHUNK * 5],
        normal: [0.0; CHUNK * 4],
        rays32: [0.0; CHUNK * 3],
    };

    #[inline(always)]
    fn put_root<W: Wide>(&mut self, j: usize, r: &ConicRoot<W>) {
        put_vectors(&mut self.root, j, [r.k1c, r.pz, r.qa, r.qc, r.far, r.disc]);
    }

    #[inline(always)]
    fn root<W: Wide>(&self, j: usize) -> ConicRoot<W> {
        let [k1c, pz, qa, qc, far, disc] = get6(&self.root, j);
        ConicRoot { k1c, pz, qa, qc, far, disc }
    }

    /// Stores pair `q`'s rays in f32 lanes ([`pair_rays`]).
    #[inline(always)]
    fn put_rays32<W: Wide>(&mut self, q: usize, (p, d): ([W::F32; 3], [W::F32; 3])) {
        for (k, v) in [p[0], p[1], p[2], d[0], d[1], d[2]].into_iter().enumerate() {
            W::put32(v, &mut self.rays32, 6 * q + k);
        }
    }

    /// Pair `q`'s rays in f32 lanes, as [`Self::put_rays32`] stored them.
    #[inline(always)]
    fn rays32<W: Wide>(&self, q: usize) -> ([W::F32; 3], [W::F32; 3]) {
        let (r, q) = (&self.rays32, 6 * q);
        (
            [W::at32(r, q), W::at32(r, q + 1), W::at32(r, q + 2)],
            [W::at32(r, q + 3), W::at32(r, q + 4), W::at32(r, q + 5)],
        )
    }

    /// [`Self::put_root`] for pair `q`'s root in f32 lanes.
    #[inline(always)]
    fn put_root32<W: Wide>(&mut self, q: usize, r: &ConicRoot<W::F32>) {
        for (k, v) in [r.k1c, r.pz, r.qa, r.qc, r.far, r.disc].into_iter().enumerate() {
            W::put32(v, &mut self.root, 6 * q + k);
        }
    }

    /// Pair `q`'s root in f32 lanes.
    #[inline(always)]
    fn root32<W: Wide>(&self, q: usize) -> ConicRoot<W::F32> {
        // written out, no closure (one not inlined runs without the
        // caller's target features)
        let (r, q) = (&self.root, 6 * q);
        let [k1c, pz, qa] = [W::at32(r, q), W::at32(r, q + 1), W::at32(r, q + 2)];
        let [qc, far, disc] = [W::at32(r, q + 3), W::at32(r, q + 4), W::at32(r, q + 5)];
        ConicRoot { k1c, pz, qa, qc, far, disc }
    }

    #[inline(always)]
    fn put_state<W: Wide, const THIRD: bool>(&mut self, j: usize, n: &Newton<W>) {
        n.u.put(&mut self.state, 5 * j);
        W::put_flags(self, j, n.converged, n.missed);
        if !THIRD {
            n.q.put(&mut self.state, 5 * j + 3);
            n.m.put(&mut self.state, 5 * j + 4);
        }
    }

    /// Vector `j`'s iteration, its rays starting at `p`.
    #[inline(always)]
    fn state<W: Wide, const THIRD: bool>(&self, j: usize, p: [W; 3]) -> Newton<W> {
        let get = |k: usize| W::at(&self.state, 5 * j + k);
        let (q, m) = if THIRD { (W::splat(0.0), W::splat(1.0)) } else { (get(3), get(4)) };
        let (converged, missed) = W::flags(self, j);
        Newton { p, u: get(0), q, m, converged, missed }
    }

    #[inline(always)]
    fn put_eval<W: Wide, const THIRD: bool>(&mut self, j: usize, e: &NewtonEval<W>) {
        let to = &mut self.eval;
        e.g.put(to, 5 * j);
        e.gp.put(to, 5 * j + 1);
        e.domain.put(to, 5 * j + 2);
        if THIRD {
            e.gpp.put(to, 5 * j + 3);
        } else {
            e.q.put(to, 5 * j + 3);
            e.m.put(to, 5 * j + 4);
        }
    }

    #[inline(always)]
    fn eval<W: Wide, const THIRD: bool>(&self, j: usize) -> NewtonEval<W> {
        let get = |k: usize| W::at(&self.eval, 5 * j + k);
        let zero = W::splat(0.0);
        let (gpp, q, m) = if THIRD { (get(3), zero, zero) } else { (zero, get(3), get(4)) };
        NewtonEval { g: get(0), gp: get(1), gpp, q, m, domain: get(2) }
    }
}

/// Where a vector's flags of [`Newton`] (converged, missed) wait between
/// the batch's loops, as each width reads them fastest: eight lanes as
/// mask bits, a byte each ([`NewtonScratch::flags`]); four, which have no
/// mask registers (a byte would cost them a broadcast, an `and` and a
/// compare to read), as numbers in the state's slots 1 and 2.
pub(super) trait NewtonFlags: Real {
    /// Stores vector `j`'s flags.
    fn put_flags(nw: &mut NewtonScratch, j: usize, converged: Self::Mask, missed: Self::Mask);
    /// Vector `j`'s flags, converged and missed.
    fn flags(nw: &NewtonScratch, j: usize) -> (Self::Mask, Self::Mask);
}

impl NewtonFlags for F64x8 {
    #[inline(always)]
    fn put_flags(nw: &mut NewtonScratch, j: usize, converged: M64x8, missed: M64x8) {
        nw.flags[j] = [converged.bits() as u8, missed.bits() as u8];
    }
    #[inline(always)]
    fn flags(nw: &NewtonScratch, j: usize) -> (M64x8, M64x8) {
        let [converged, missed] = nw.flags[j];
        (M64x8::of_bits(u32::from(converged)), M64x8::of_bits(u32::from(missed)))
    }
}

impl NewtonFlags for F64x4 {
    #[inline(always)]
    fn put_flags(nw: &mut NewtonScratch, j: usize, converged: M64x4, missed: M64x4) {
        F64x4::from_mask(converged).put(&mut nw.state, 5 * j + 1);
        F64x4::from_mask(missed).put(&mut nw.state, 5 * j + 2);
    }
    #[inline(always)]
    fn flags(nw: &NewtonScratch, j: usize) -> (M64x4, M64x4) {
        (F64x4::at(&nw.state, 5 * j + 1).is_neg(), F64x4::at(&nw.state, 5 * j + 2).is_neg())
    }
}

/// An asphere step over the first `n` vectors of a chunk (`W::N` rays a
/// vector): Newton's iteration in lock step, one step for every vector
/// still iterating per pass over the chunk, so that the vectors' chains of
/// dependent operations overlap (one vector at a time waits on each
/// division in turn). Each lane takes the steps the one-ray path takes, so
/// the bits agree. `THIRD` is the surface's [`AsphereLanes::third_order`],
/// `ODD` its [`AsphereLanes::odd`], `TERMS` its
/// [`AsphereLanes::chain_terms`].
///
/// Every stage is a loop over the vectors that stores what the next needs
/// in `nw` (for a surface with rings, each ray's ring, then its conic;
/// the conic's roots, then the starts; per pass, the evaluations, then the
/// divisions; the hits' normals, then the refractions): each loop's chain
/// of dependent operations is short enough to overlap across vectors, as
/// the sphere's two loops. The vectors still iterating are the bits of one
/// integer, so that a pass visits only those.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn asphere_chunk<
    W: Wide,
    const REFRACT: bool,
    const PER_RAY: bool,
    const THIRD: bool,
    const ODD: bool,
    const TERMS: usize,
>(
    s: &Step,
    sl: &StepLanes<W>,
    a: &AsphereLanes<W>,
    src: &Rays4,
    dst: &mut Rays4,
    n: usize,
    ix: &ChunkIndices,
    bits: &mut Bits,
    nw: &mut NewtonScratch,
) {
    // at most a chunk's vectors: said so, the four-lane loops' reads and
    // writes need no bounds checks of their own
    let n = if W::N == 4 { n.min(CHUNK / W::N) } else { n };
    // vector j's rays in the surface's frame
    let ray = |j: usize| {
        let (p, d, _) = load_rays::<W>(src, j);
        ([p[0], p[1], p[2] - sl.shift], d)
    };
    let mut live = 0u64;
    if a.iterates() {
        // the start in f32, two vectors' rays at a time (`pairs`; where `n`
        // is odd the last pair's second vector is the chunk's next, its
        // lanes computed and not used): each ray's ring and its conic (a
        // table row per lane, read with permutes), then the roots, then
        // the starts: short chains a pair instead of one long one
        let st = a.start();
        let pairs = n.div_ceil(2);
        // the pairs with a lane far from the vertex plane ([`pair_rays`])
        let mut far = 0u64;
        if let Some(z) = zones_of(a) {
            // the rings in one loop, their conics (permutes) in another:
            // measured faster at both widths than one loop
            // (docs/performance.md)
            for q in 0..pairs {
                let (p, d, f) = pair_rays::<W>(src, sl.shift, q, nw);
                far |= u64::from(f) << q;
                nw.put_rays32::<W>(q, (p, d));
                W::put32(z.ring(p, d), &mut nw.root, 6 * q);
            }
            for q in 0..pairs {
                let (p, _) = nw.rays32::<W>(q);
                put_start_conic::<W>(nw, q, ring_conic(z.of_ring(W::at32(&nw.root, 6 * q)), p[2]));
            }
            for q in 0..pairs {
                let (p, d) = nw.rays32::<W>(q);
                let r = &nw.root;
                let [c, kc, k1c, pz] =
                    [W::at32(r, 6 * q), W::at32(r, 6 * q + 1), W::at32(r, 6 * q + 2), W::at32(r, 6 * q + 3)];
                let ring = conic_root_of(&StartConic { c, kc, k1c, pz }, p, d, true);
                nw.put_root32::<W>(q, &ring_or_start(st, ring, p, d));
            }
        } else {
            for q in 0..pairs {
                let (p, d, f) = pair_rays::<W>(src, sl.shift, q, nw);
                far |= u64::from(f) << q;
                nw.put_rays32::<W>(q, (p, d));
                nw.put_root32::<W>(q, &start_root(st, p, d));
            }
        }
        for q in 0..pairs {
            let (p32, d32) = nw.rays32::<W>(q);
            let (u0, u1) = W::widen(start_u(st, p32, d32, &nw.root32::<W>(q)));
            let f = far >> q & 1 != 0;
            let (p, _) = ray(2 * q);
            let first = newton_start_at(p, start_of_vector(nw, 2 * q, p, u0, f));
            nw.put_state::<W, THIRD>(2 * q, &first);
            live |= u64::from(newton_running(&first)) << (2 * q);
            if 2 * q + 1 < n {
                let (p, _) = ray(2 * q + 1);
                let second = newton_start_at(p, start_of_vector(nw, 2 * q + 1, p, u1, f));
                nw.put_state::<W, THIRD>(2 * q + 1, &second);
                live |= u64::from(newton_running(&second)) << (2 * q + 1);
            }
        }
    } else {
        // a pure conic: its root, in f64, is the intersection
        for j in 0..n {
            let (p, d) = ray(j);
            nw.put_root(j, &conic_only_root(a, p, d));
        }
        for j in 0..n {
            let (p, d) = ray(j);
            nw.put_state::<W, THIRD>(j, &conic_only_start(p, d, &nw.root(j)));
        }
    }
    for _ in 0..MAX_NEWTON_STEPS {
        if live == 0 {
            break;
        }
        for j in vectors_in::<W>(live) {
            let (p, d) = ray(j);
            let ev = newton_eval::<W, THIRD, ODD, TERMS>(a, d, &nw.state::<W, THIRD>(j, p));
            nw.put_eval::<W, THIRD>(j, &ev);
        }
        let mut next = 0u64;
        for j in vectors_in::<W>(live) {
            let (p, _) = ray(j);
            let mut st = nw.state::<W, THIRD>(j, p);
            newton_finish::<W, THIRD>(&mut st, &nw.eval::<W, THIRD>(j));
            nw.put_state::<W, THIRD>(j, &st);
            next |= u64::from(newton_running(&st)) << j;
        }
        live = next;
    }
    for j in 0..n {
        let (p, d) = ray(j);
        let h = newton_hit::<W, THIRD, ODD, TERMS>(a, d, &nw.state::<W, THIRD>(j, p));
        put_vectors(&mut nw.normal, j, [h.n[0], h.n[1], h.n[2], h.r2]);
    }
    for j in 0..n {
        let sl = if PER_RAY { lanes_at(*sl, s, &ix.vector(j)) } else { *sl };
        let (p, d) = ray(j);
        let [nx, ny, nz, r2] = get4(&nw.normal, j);
        let h = hit_with_normal(d, &nw.state::<W, THIRD>(j, p), [nx, ny, nz], r2);
        store_out(dst, j, &asphere_carry::<W, REFRACT>(&sl, &h, d, load_rays::<W>(src, j).2), bits);
    }
}
