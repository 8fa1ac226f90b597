//! A bounding volume hierarchy over bounded primitives, built only when a
//! scene has enough of them to need one.

use crate::geometry::{Hit, Ray, Shape};
use glam::DVec3;

/// Below this many bounded primitives a linear scan is used instead.
pub const BVH_THRESHOLD: usize = 8;

#[derive(Debug, Clone)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first primitive and count; inner: index of the left child (the
    /// right is at `left + 1`) and count 0.
    start: usize,
    count: usize,
}

/// The hierarchy: nodes and primitive indices in leaf order.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<usize>,
}

impl Bvh {
    /// Builds over `shapes[i]` for i in `items` (median split on the longest
    /// axis of the centroids).
    pub fn build(shapes: &[Shape], items: Vec<usize>) -> Self {
        let mut b = Bvh { nodes: Vec::new(), order: items };
        if b.order.is_empty() {
            return b;
        }
        let bounds: Vec<(DVec3, DVec3)> = shapes.iter().map(|s| s.bounds()).collect();
        b.nodes.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, start: 0, count: 0 });
        let n = b.order.len();
        b.split(0, 0, n, &bounds);
        b
    }

    fn split(&mut self, node: usize, start: usize, end: usize, bounds: &[(DVec3, DVec3)]) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &i in &self.order[start..end] {
            lo = lo.min(bounds[i].0);
            hi = hi.max(bounds[i].1);
            let c = 0.5 * (bounds[i].0 + bounds[i].1);
            clo = clo.min(c);
            chi = chi.max(c);
        }
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        let count = end - start;
        let extent = chi - clo;
        if count <= 4 || extent.max_element() <= 0.0 {
            self.nodes[node].start = start;
            self.nodes[node].count = count;
            return;
        }
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        let key = |i: &usize| 0.5 * (bounds[*i].0[axis] + bounds[*i].1[axis]);
        self.order[start..end].select_nth_unstable_by(mid - start, |a, b| key(a).total_cmp(&key(b)));
        let left = self.nodes.len();
        self.nodes.push(Node { lo, hi, start: 0, count: 0 });
        self.nodes.push(Node { lo, hi, start: 0, count: 0 });
        self.nodes[node].start = left;
        self.nodes[node].count = 0;
        self.split(left, start, mid, bounds);
        self.split(left + 1, mid, end, bounds);
    }

    /// Nearest hit among the primitives: (primitive index, hit).
    pub fn intersect(&self, shapes: &[Shape], r: &Ray, t_min: f64, mut t_max: f64) -> Option<(usize, Hit)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = DVec3::ONE / r.dir;
        let mut best = None;
        let mut stack = [0usize; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp]];
            if !slab(node.lo, node.hi, r.origin, inv, t_min, t_max) {
                continue;
            }
            if node.count > 0 {
                for &i in &self.order[node.start..node.start + node.count] {
                    if let Some(h) = shapes[i].intersect(r, t_min, t_max) {
                        t_max = h.t;
                        best = Some((i, h));
                    }
                }
            } else if sp + 2 <= stack.len() {
                stack[sp] = node.start;
                stack[sp + 1] = node.start + 1;
                sp += 2;
            }
        }
        best
    }
}

/// Ray-box slab test.
fn slab(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, t_min: f64, t_max: f64) -> bool {
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    let tn = t0.min(t1).max_element().max(t_min);
    let tf = t0.max(t1).min_element().min(t_max);
    tn <= tf
}
