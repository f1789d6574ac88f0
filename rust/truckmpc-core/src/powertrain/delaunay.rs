//! A Delaunay triangulation built the way VECTO builds its maps: Bowyer–Watson, inserting the points
//! in the order given into a super triangle, with the plain floating-point in-circle test. Where
//! four points lie on one circle (every rectangular cell of a map measured on a grid) either diagonal
//! is a Delaunay triangulation; which one a map gets then depends on the insertion order and that
//! test, so building it the same way is what makes the interpolation VECTO's.
//!
//! Points are expected in [0, 1]² (the caller scales them); the super triangle encloses that square
//! with room to spare. O(n²) to build. A lookup takes the first triangle, in the order built, that
//! holds the point, as a scan of them all would; a grid of cells over the square, each listing the
//! triangles that can hold a point in it, makes that a scan of a few (an electric machine's map of
//! 22 × 42 points has some 1 800 triangles, and a model resamples it at 160 000 points).

/// Corners of the super triangle, counterclockwise, around [0, 1]².
const SUPER: [[f64; 2]; 3] = [[-1.0, -1.0], [4.0, -1.0], [-1.0, 4.0]];
/// Slack of the second, tolerant lookup, for points a rounding error outside every triangle.
const TOLERANCE: f64 = 1e-3;

/// Triangles over points (x, y) carrying a value z, linear on each triangle.
#[derive(Debug, Clone)]
pub struct Triangulation {
    points: Vec<[f64; 3]>,
    /// Vertex indices, counterclockwise.
    triangles: Vec<[usize; 3]>,
    /// Edges of the convex hull (those of exactly one triangle).
    hull: Vec<[usize; 2]>,
    /// The triangles that can hold a point of each cell (tolerance included), in build order.
    cells: Cells,
}

/// A CELLS × CELLS grid over [0, 1]², row after row: each cell's triangles are
/// `triangles[start[k]..start[k + 1]]`.
#[derive(Debug, Clone)]
struct Cells {
    start: Vec<usize>,
    triangles: Vec<usize>,
}

/// Cells along each axis of the lookup grid.
const CELLS: usize = 48;

impl Triangulation {
    /// The triangulation of `points` (x, y, z), inserted in their order; `None` when they span no
    /// triangle (fewer than three, or all on one line).
    pub fn new(points: &[[f64; 3]]) -> Option<Self> {
        let n = points.len();
        let mut all = points.to_vec();
        all.extend(SUPER.iter().map(|&[x, y]| [x, y, 0.0]));
        let mut triangles = vec![[n, n + 1, n + 2]];
        for i in 0..n {
            insert(&all, &mut triangles, i);
        }
        triangles.retain(|t| t.iter().all(|&v| v < n));
        all.truncate(n);
        if triangles.is_empty() {
            return None;
        }
        let hull = single_edges(&triangles);
        let cells = Cells::new(&all, &triangles);
        Some(Triangulation { points: all, triangles, hull, cells })
    }

    /// z at (x, y), linear on the triangle holding the point; `None` outside every triangle.
    pub fn interpolate(&self, x: f64, y: f64) -> Option<f64> {
        let listed = self.cells.of(x, y);
        [0.0, TOLERANCE].iter().find_map(|&slack| {
            listed.iter().find_map(|&k| {
                let [a, b, c] = self.triangles[k].map(|v| self.points[v]);
                let (u, v) = barycentric(a, b, c, x, y)?;
                (u >= -slack && v >= -slack && u + v <= 1.0 + slack)
                    .then(|| a[2] + u * (c[2] - a[2]) + v * (b[2] - a[2]))
            })
        })
    }

    /// The convex hull's edges as pairs of (x, y, z).
    pub fn hull(&self) -> impl Iterator<Item = [[f64; 3]; 2]> + '_ {
        self.hull.iter().map(|&[a, b]| [self.points[a], self.points[b]])
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no points (never: a triangulation has at least three).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

impl Cells {
    /// Each cell's triangles: those whose bounding box, widened by what the tolerant lookup
    /// accepts, meets the cell. A point p a triangle accepts has barycentric weights of at least
    /// −TOLERANCE summing to 1, so it lies within 2·TOLERANCE of the box's width (height) outside
    /// it; the margin is wider still for rounding. Points outside [0, 1]² look in the border cell.
    fn new(points: &[[f64; 3]], triangles: &[[usize; 3]]) -> Self {
        let mut lists = vec![Vec::new(); CELLS * CELLS];
        for (k, t) in triangles.iter().enumerate() {
            let span = |axis: usize| {
                let values = t.map(|v| points[v][axis]);
                let (lo, hi) = (
                    values.iter().copied().fold(f64::INFINITY, f64::min),
                    values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                );
                let margin = 3.0 * TOLERANCE * (hi - lo) + 1e-9;
                (cell_index(lo - margin), cell_index(hi + margin))
            };
            let ((x0, x1), (y0, y1)) = (span(0), span(1));
            for row in y0..=y1 {
                for column in x0..=x1 {
                    lists[row * CELLS + column].push(k);
                }
            }
        }
        let mut start = vec![0];
        start.extend(lists.iter().scan(0, |end, list| {
            *end += list.len();
            Some(*end)
        }));
        Cells { start, triangles: lists.concat() }
    }

    /// The triangles of the cell holding (x, y), in build order.
    fn of(&self, x: f64, y: f64) -> &[usize] {
        let k = cell_index(y) * CELLS + cell_index(x);
        &self.triangles[self.start[k]..self.start[k + 1]]
    }
}

/// The cell along one axis holding `value`, clamped into the grid (NaN: the first).
fn cell_index(value: f64) -> usize {
    ((value * CELLS as f64).floor().max(0.0) as usize).min(CELLS - 1)
}

/// Insert point `i`: remove every triangle whose circumcircle holds it and join it to the edges
/// of the hole they leave, in the order they were found.
fn insert(points: &[[f64; 3]], triangles: &mut Vec<[usize; 3]>, i: usize) {
    let p = points[i];
    let bad: Vec<usize> = (0..triangles.len()).filter(|&k| in_circle(points, triangles[k], p)).collect();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for &k in bad.iter().rev() {
        let [a, b, c] = triangles.remove(k);
        edges.extend([[a, b], [b, c], [c, a]]);
    }
    let count = |e: [usize; 2]| edges.iter().filter(|f| same_edge(**f, e)).count();
    let boundary: Vec<[usize; 2]> = edges.iter().copied().filter(|&e| count(e) == 1).collect();
    triangles.extend(boundary.into_iter().map(|[a, b]| [a, b, i]));
}

fn same_edge(e: [usize; 2], f: [usize; 2]) -> bool {
    e == f || e == [f[1], f[0]]
}

/// Whether `p` lies strictly inside the circumcircle of the counterclockwise triangle `t`.
fn in_circle(points: &[[f64; 3]], t: [usize; 3], p: [f64; 3]) -> bool {
    let [a, b, c] = t.map(|v| [points[v][0] - p[0], points[v][1] - p[1]]);
    let (sa, sb, sc) = (a[0] * a[0] + a[1] * a[1], b[0] * b[0] + b[1] * b[1], c[0] * c[0] + c[1] * c[1]);
    let (dab, dbc, dca) = (a[0] * b[1] - b[0] * a[1], b[0] * c[1] - c[0] * b[1], c[0] * a[1] - a[0] * c[1]);
    sa * dbc + sb * dca + sc * dab > 0.0
}

/// Coordinates (u, v) of (x, y) along c − a and b − a; `None` for a degenerate triangle.
fn barycentric(a: [f64; 3], b: [f64; 3], c: [f64; 3], x: f64, y: f64) -> Option<(f64, f64)> {
    let (v0, v1, v2) = ([c[0] - a[0], c[1] - a[1]], [b[0] - a[0], b[1] - a[1]], [x - a[0], y - a[1]]);
    let dot = |p: [f64; 2], q: [f64; 2]| p[0] * q[0] + p[1] * q[1];
    let (d00, d01, d02, d11, d12) = (dot(v0, v0), dot(v0, v1), dot(v0, v2), dot(v1, v1), dot(v1, v2));
    let det = d00 * d11 - d01 * d01;
    (det.abs() > 0.0).then(|| ((d11 * d02 - d01 * d12) / det, (d00 * d12 - d01 * d02) / det))
}

/// Edges that belong to exactly one triangle.
fn single_edges(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    let edges: Vec<[usize; 2]> = triangles.iter().flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]]).collect();
    edges.iter().copied().filter(|&e| edges.iter().filter(|f| same_edge(**f, e)).count() == 1).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A map measured on a grid (every cell's corners on one circle), with a curved value: the
    /// size of an electric machine's, built once for every test.
    fn grid_map() -> &'static Triangulation {
        static MAP: std::sync::OnceLock<Triangulation> = std::sync::OnceLock::new();
        MAP.get_or_init(|| {
            let points: Vec<[f64; 3]> = (0..22)
                .flat_map(|i| (0..42).map(move |j| (i as f64 / 21.0, j as f64 / 41.0)))
                .map(|(x, y)| [x, y, (3.0 * x).sin() * y * y + x])
                .collect();
            Triangulation::new(&points).expect("a grid spans triangles")
        })
    }

    /// The lookup as a scan of every triangle in build order, the reference the cells must match.
    fn scanned(map: &Triangulation, x: f64, y: f64) -> Option<f64> {
        [0.0, TOLERANCE].iter().find_map(|&slack| {
            map.triangles.iter().find_map(|t| {
                let [a, b, c] = t.map(|v| map.points[v]);
                let (u, v) = barycentric(a, b, c, x, y)?;
                (u >= -slack && v >= -slack && u + v <= 1.0 + slack)
                    .then(|| a[2] + u * (c[2] - a[2]) + v * (b[2] - a[2]))
            })
        })
    }

    #[test]
    fn on_every_node_and_edge_the_cells_find_the_scans_triangle() {
        let map = grid_map();
        for i in 0..=84 {
            for j in 0..=164 {
                let (x, y) = (i as f64 / 84.0, j as f64 / 164.0);
                assert_eq!(map.interpolate(x, y).map(f64::to_bits), scanned(map, x, y).map(f64::to_bits));
            }
        }
    }

    proptest! {
        #[test]
        fn anywhere_the_cells_give_the_scans_value_bit_for_bit(x in -0.01f64..1.01, y in -0.01f64..1.01) {
            let map = grid_map();
            prop_assert_eq!(map.interpolate(x, y).map(f64::to_bits), scanned(map, x, y).map(f64::to_bits));
        }
    }
}
