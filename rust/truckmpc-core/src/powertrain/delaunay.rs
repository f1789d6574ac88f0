//! A Delaunay triangulation built the way VECTO builds its maps: Bowyer–Watson, inserting the points
//! in the order given into a super triangle, with the plain floating-point in-circle test. Where
//! four points lie on one circle (every rectangular cell of a map measured on a grid) either diagonal
//! is a Delaunay triangulation; which one a map gets then depends on the insertion order and that
//! test, so building it the same way is what makes the interpolation VECTO's.
//!
//! Points are expected in [0, 1]² (the caller scales them); the super triangle encloses that square
//! with room to spare. O(n²) to build, O(n) to look up: fuel maps have a few hundred points.

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
}

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
        Some(Triangulation { points: all, triangles, hull })
    }

    /// z at (x, y), linear on the triangle holding the point; `None` outside every triangle.
    pub fn interpolate(&self, x: f64, y: f64) -> Option<f64> {
        [0.0, TOLERANCE].iter().find_map(|&slack| {
            self.triangles.iter().find_map(|t| {
                let [a, b, c] = t.map(|v| self.points[v]);
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
