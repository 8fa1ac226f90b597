//! The pupil grid the wave analyses sample: an n x n square grid of cells
//! over the normalised pupil [-1, 1]^2, each cell weighted by the share of
//! its area inside the unit disk, so that sums over the grid are integrals
//! over the disk (a bare grid of the points inside the disk misses up to
//! half a cell's area at every rim cell: RMS and Strehl would then depend
//! on where the grid happens to cut the rim).

/// One cell of a [`PupilGrid`] that overlaps the unit disk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Column (x) and row (y) of the cell, 0-based from the grid's
    /// corner at (-1, -1).
    pub column: usize,
    /// Row, 0-based from y = -1.
    pub row: usize,
    /// Where the cell is sampled, normalised pupil coordinates (px, py):
    /// its centre, or for a cell the disk's rim cuts, the centroid of its
    /// part inside the disk (so every sample lies in the pupil, and sums
    /// over the grid integrate linear terms exactly).
    pub centre: (f64, f64),
    /// The share of the cell's area inside the unit disk, (0, 1].
    pub area: f64,
}

/// An n x n grid over the normalised pupil: the cells that overlap the
/// unit disk, row by row.
#[derive(Debug, Clone, PartialEq)]
pub struct PupilGrid {
    /// Cells across the pupil's diameter.
    pub n: usize,
    /// The cells that overlap the disk, row by row from y = -1.
    pub cells: Vec<Cell>,
}

impl PupilGrid {
    /// The grid of `n` cells across the pupil (n >= 1).
    ///
    /// ```
    /// let g = lens::analysis::wave::pupil::PupilGrid::new(64);
    /// let area: f64 = g.cells.iter().map(|c| c.area).sum::<f64>() * g.cell_area();
    /// assert!((area - std::f64::consts::PI).abs() < 1e-6);
    /// ```
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let h = 2.0 / n as f64;
        let mut cells = Vec::with_capacity(n * n);
        for row in 0..n {
            for column in 0..n {
                let (x0, y0) = (-1.0 + column as f64 * h, -1.0 + row as f64 * h);
                let (area, centre) = inside_disk(x0, x0 + h, y0, y0 + h);
                if area > 0.0 {
                    cells.push(Cell { column, row, centre, area: (area / (h * h)).min(1.0) });
                }
            }
        }
        PupilGrid { n, cells }
    }

    /// The area of one whole cell in the normalised pupil, (2/n)^2.
    pub fn cell_area(&self) -> f64 {
        let h = 2.0 / self.n as f64;
        h * h
    }

    /// The cells' centres, in order.
    pub fn points(&self) -> Vec<(f64, f64)> {
        self.cells.iter().map(|c| c.centre).collect()
    }
}

/// The area of the rectangle [x0, x1] x [y0, y1] inside the unit disk,
/// and the centroid of that part (the rectangle's centre where it is
/// wholly inside).
fn inside_disk(x0: f64, x1: f64, y0: f64, y1: f64) -> (f64, (f64, f64)) {
    let middle = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    // the nearest and farthest points of the rectangle from the centre
    let near = |a: f64, b: f64| {
        if a > 0.0 {
            a
        } else if b < 0.0 {
            -b
        } else {
            0.0
        }
    };
    let (nx, ny) = (near(x0, x1), near(y0, y1));
    if nx * nx + ny * ny >= 1.0 {
        return (0.0, middle);
    }
    let far = |a: f64, b: f64| a.abs().max(b.abs());
    let (fx, fy) = (far(x0, x1), far(y0, y1));
    if fx * fx + fy * fy <= 1.0 {
        return ((x1 - x0) * (y1 - y0), middle);
    }
    // exactly: between the x where the circle crosses y0 or y1 the upper
    // edge is y1 or the circle s(x) = sqrt(1 - x^2), the lower y0 or -s(x)
    let mut cuts = vec![x0, x1];
    for y in [y0, y1] {
        if y.abs() < 1.0 {
            let x = (1.0 - y * y).sqrt();
            cuts.extend([-x, x].into_iter().filter(|c| *c > x0 && *c < x1));
        }
    }
    cuts.sort_by(f64::total_cmp);
    let (mut area, mut mx, mut my) = (0.0, 0.0, 0.0);
    for w in cuts.windows(2) {
        let (a, b) = (w[0].max(-1.0), w[1].min(1.0));
        if b <= a {
            continue;
        }
        let m = 0.5 * (a + b);
        let s = (1.0 - m * m).sqrt();
        // each edge on (a, b): a constant, or +-s(x)
        let upper = if y1 < s { Edge::Flat(y1) } else { Edge::Circle(1.0) };
        let lower = if y0 > -s { Edge::Flat(y0) } else { Edge::Circle(-1.0) };
        if upper.at(m) <= lower.at(m) {
            continue;
        }
        area += upper.integral(a, b) - lower.integral(a, b);
        mx += upper.x_moment(a, b) - lower.x_moment(a, b);
        my += 0.5 * (upper.square_integral(a, b) - lower.square_integral(a, b));
    }
    if area > 0.0 {
        (area, (mx / area, my / area))
    } else {
        (0.0, middle)
    }
}

/// An edge of a cell's part inside the disk over an interval of x: y = c,
/// or y = k sqrt(1 - x^2) (k = 1 the upper half of the circle, -1 the
/// lower).
#[derive(Debug, Clone, Copy)]
enum Edge {
    Flat(f64),
    Circle(f64),
}

impl Edge {
    fn at(self, x: f64) -> f64 {
        match self {
            Edge::Flat(c) => c,
            Edge::Circle(k) => k * (1.0 - x * x).max(0.0).sqrt(),
        }
    }

    /// The integral of y dx over [a, b].
    fn integral(self, a: f64, b: f64) -> f64 {
        // the antiderivative of sqrt(1 - x^2)
        let f = |x: f64| 0.5 * (x * (1.0 - x * x).max(0.0).sqrt() + x.clamp(-1.0, 1.0).asin());
        match self {
            Edge::Flat(c) => c * (b - a),
            Edge::Circle(k) => k * (f(b) - f(a)),
        }
    }

    /// The integral of x y dx over [a, b].
    fn x_moment(self, a: f64, b: f64) -> f64 {
        // the antiderivative of x sqrt(1 - x^2)
        let g = |x: f64| -(1.0 - x * x).max(0.0).powf(1.5) / 3.0;
        match self {
            Edge::Flat(c) => c * 0.5 * (b * b - a * a),
            Edge::Circle(k) => k * (g(b) - g(a)),
        }
    }

    /// The integral of y^2 dx over [a, b].
    fn square_integral(self, a: f64, b: f64) -> f64 {
        match self {
            Edge::Flat(c) => c * c * (b - a),
            Edge::Circle(_) => (b - a) - (b * b * b - a * a * a) / 3.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cells_cover_the_disk_exactly() {
        for n in [1, 2, 7, 32, 65, 128] {
            let g = PupilGrid::new(n);
            let area: f64 = g.cells.iter().map(|c| c.area).sum::<f64>() * g.cell_area();
            println!("n {n}: area {area:.9} (pi {:.9})", std::f64::consts::PI);
            assert!(g.cells.iter().all(|c| c.centre.0.hypot(c.centre.1) <= 1.0), "every sample inside the disk");
            assert!((area - std::f64::consts::PI).abs() < 1e-12, "n {n}: {area}");
            // the second moment of the disk, pi/4 per axis
            let m2: f64 = g.cells.iter().map(|c| c.area * c.centre.0 * c.centre.0).sum::<f64>() * g.cell_area();
            if n >= 32 {
                assert!((m2 - std::f64::consts::FRAC_PI_4).abs() < 2.0 / (n * n) as f64, "n {n}: {m2}");
            }
        }
    }
}
