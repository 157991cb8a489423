//! Quality measures of interpolated frames: inverted triangles, distortion, area.
//!
//! They quantify what the paper shows in its figures: linear interpolation shrinks rotating
//! shapes (area through time), triangle-based interpolation distorts thin triangles (Fig. 13),
//! and a good morph inverts no triangle.

use crate::geometry::{triangle_area, Point};
use crate::rigid::Interpolator;

/// Number of triangles that are not strictly counter-clockwise in `points` (exact predicate),
/// i.e. inverted or collapsed.
pub fn inverted_triangles(triangles: &[[u32; 3]], points: &[Point]) -> usize {
    crate::mesh::count_inverted(triangles, points)
}

/// Per-triangle distortion of `frame` relative to `source`: the ratio `σ_max / σ_min ≥ 1` of the
/// singular values of the affine map taking the source triangle to the frame triangle. 1 for a
/// similarity; `f64::INFINITY` when either triangle is degenerate.
pub fn distortion(triangles: &[[u32; 3]], source: &[Point], frame: &[Point]) -> Vec<f64> {
    triangles
        .iter()
        .map(|&t| triangle_distortion(t, source, frame))
        .collect()
}

/// [`distortion`] of one triangle `t`, without a list (the relaxation of the mapped mesh asks
/// for one star at a time).
pub(crate) fn triangle_distortion(t: [u32; 3], source: &[Point], frame: &[Point]) -> f64 {
    let [a, b, c] = t.map(|i| source[i as usize]);
    let [x, y, z] = t.map(|i| frame[i as usize]);
    let (p0, p1) = (b - a, c - a);
    let det = p0.perp_dot(p1);
    if det == 0.0 || !det.is_finite() {
        return f64::INFINITY;
    }
    // A = F P⁻¹ with P = [p0 p1], F = [f0 f1].
    let (f0, f1) = (y - x, z - x);
    let r0 = Point::new(p1.y, -p1.x) / det;
    let r1 = Point::new(-p0.y, p0.x) / det;
    let c0 = f0 * r0.x + f1 * r1.x;
    let c1 = f0 * r0.y + f1 * r1.y;
    let ratio = singular_value_ratio(c0.x, c1.x, c0.y, c1.y);
    if ratio.is_nan() {
        f64::INFINITY
    } else {
        ratio
    }
}

/// `σ_max / σ_min` of `[[a, b], [c, d]]`, from its split into a similarity part and an
/// anti-similarity part: `σ = |q| ± |r|` with `q = ((a + d) + i(c − b))/2`, `r = ((a − d) + i(c + b))/2`.
fn singular_value_ratio(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let q = 0.5 * (a + d).hypot(c - b);
    let r = 0.5 * (a - d).hypot(c + b);
    let lo = (q - r).abs();
    if lo == 0.0 {
        f64::INFINITY
    } else {
        (q + r) / lo
    }
}

/// Largest [`distortion`] over the triangles (1 for an empty mesh).
pub fn max_distortion(triangles: &[[u32; 3]], source: &[Point], frame: &[Point]) -> f64 {
    distortion(triangles, source, frame)
        .into_iter()
        .fold(1.0, f64::max)
}

/// Sum of the signed triangle areas (positive for counter-clockwise triangles).
pub fn area(triangles: &[[u32; 3]], points: &[Point]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| points[i as usize]);
            triangle_area(a, b, c)
        })
        .sum()
}

/// [`area`] of `samples` frames at `t = k / (samples − 1)`, `k = 0..samples` (shrinkage through
/// time; `samples < 2` gives the source area only when 1, nothing when 0).
pub fn area_through_time(
    interp: &Interpolator,
    triangles: &[[u32; 3]],
    samples: usize,
) -> Vec<f64> {
    let ts: Vec<f64> = match samples {
        0 => Vec::new(),
        1 => vec![0.0],
        s => (0..s).map(|k| k as f64 / (s - 1) as f64).collect(),
    };
    let mut ws = interp.workspace();
    let mut frame = vec![Point::ZERO; interp.vertex_count()];
    ts.iter()
        .map(|&t| {
            interp.at(t, &mut frame, &mut ws);
            area(triangles, &frame)
        })
        .collect()
}

/// Arc-length samples of a closed outline for [`shape_turn`].
const TURN_SAMPLES: usize = 64;

/// `n` points evenly spaced by arc length along the closed polyline `ring`, from its first
/// vertex.
pub(crate) fn ring_samples(ring: &[Point], n: usize) -> Vec<Point> {
    let m = ring.len();
    if m == 0 {
        return Vec::new();
    }
    let lens: Vec<f64> = (0..m)
        .map(|i| ring[i].distance(ring[(i + 1) % m]))
        .collect();
    let total: f64 = lens.iter().sum();
    let mut out = Vec::with_capacity(n);
    let (mut i, mut acc) = (0usize, 0.0);
    for k in 0..n {
        let s = total * k as f64 / n as f64;
        while i + 1 < m && acc + lens[i] < s {
            acc += lens[i];
            i += 1;
        }
        let u = if lens[i] > 0.0 {
            ((s - acc) / lens[i]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(ring[i] + (ring[(i + 1) % m] - ring[i]) * u);
    }
    out
}

/// The turn (radians, in (−π, π]) that best aligns the closed outline `b` with `a` as shapes,
/// whatever their vertex correspondence: of every start of `b`'s arc-length resampling (both
/// wound the same way), the best-fit similarity of least residual; among starts within 2 % of
/// the best residual — a symmetric shape fits several ways, a star at every tip — the one
/// turning least. For an upright heart and an upright star it is about 0: any turn a morph
/// between them shows mid-way is spin that neither end has (issue #7, item 7).
pub fn shape_turn(a: &[Point], b: &[Point]) -> f64 {
    shape_turn_near(a, b, 0.0)
}

/// [`shape_turn`] where symmetry leaves a choice, the fit turning nearest to `prefer` (radians)
/// instead of the least: a part of an icon whose whole figure turns by `prefer` takes the
/// figure's turn when its own shape cannot tell (a bar turned half round looks unturned).
pub fn shape_turn_near(a: &[Point], b: &[Point], prefer: f64) -> f64 {
    let wind = |r: &[Point]| -> Vec<Point> {
        let mut r = r.to_vec();
        if crate::geometry::polygon_area(&r) < 0.0 {
            r.reverse();
        }
        r
    };
    let (sa, sb) = (
        ring_samples(&wind(a), TURN_SAMPLES),
        ring_samples(&wind(b), TURN_SAMPLES),
    );
    if sa.len() < 3 || sb.len() < 3 {
        return 0.0;
    }
    let n = sb.len();
    let fits: Vec<(f64, f64)> = (0..n)
        .map(|j| {
            let rotated: Vec<Point> = (0..n).map(|i| sb[(i + j) % n]).collect();
            let f = crate::geometry::SimilarityFit::new(&sa, &rotated);
            let explained =
                (f.dot * f.dot + f.cross * f.cross) / f.from_spread.max(f64::MIN_POSITIVE);
            let residual =
                ((f.to_spread - explained) / f.to_spread.max(f64::MIN_POSITIVE)).max(0.0);
            (residual, f.rotation())
        })
        .collect();
    let best = fits.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
    let off = |x: f64| {
        let d = x - prefer;
        d.sin().atan2(d.cos()).abs()
    };
    fits.iter()
        .filter(|f| f.0 <= best + 0.02)
        .map(|f| f.1)
        .min_by(|x, y| off(*x).total_cmp(&off(*y)))
        .unwrap_or(0.0)
}

/// The spin of a morph's middle frame (radians, ≥ 0): how far the best-fit turn of the outline
/// from the source (`a`) to the frame at t = ½ (`mid`, vertex for vertex) is from half the
/// shapes' own turn ([`shape_turn`] of `a` to the target `b`). A morph between two upright
/// shapes that tips its middle frame over by 30° spins 30°.
pub fn spin(a: &[Point], b: &[Point], mid: &[Point]) -> f64 {
    let half = 0.5 * shape_turn(a, b);
    let turned = crate::geometry::SimilarityFit::new(a, mid).rotation();
    let d = turned - half;
    d.sin().atan2(d.cos()).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn distortion_of_similarity_shear_and_flip() {
        let tri = [[0u32, 1, 2]];
        let src = [p(0., 0.), p(1., 0.), p(0., 1.)];
        let sim: Vec<Point> = src
            .iter()
            .map(|q| Point::new(3.0 * q.y, -3.0 * q.x) * -1.0 + p(5., 1.))
            .collect();
        assert!((distortion(&tri, &src, &sim)[0] - 1.0).abs() < 1e-12);
        // Stretch x by 4: ratio 4.
        let st = [p(0., 0.), p(4., 0.), p(0., 1.)];
        assert!((max_distortion(&tri, &src, &st) - 4.0).abs() < 1e-12);
        // Collapsed frame triangle: infinite.
        let flat = [p(0., 0.), p(1., 0.), p(2., 0.)];
        assert_eq!(distortion(&tri, &src, &flat)[0], f64::INFINITY);
        assert_eq!(inverted_triangles(&tri, &flat), 1);
        assert_eq!(inverted_triangles(&tri, &src), 0);
        assert!((area(&tri, &src) - 0.5).abs() < 1e-15);
        assert!((area(&tri, &st) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn singular_values_match_a_direct_computation() {
        let (a, b, c, d): (f64, f64, f64, f64) = (1.3, -0.4, 2.2, 0.9);
        // Eigenvalues of AᵀA.
        let (m00, m01, m11) = (a * a + c * c, a * b + c * d, b * b + d * d);
        let tr = m00 + m11;
        let disc = ((m00 - m11).powi(2) + 4.0 * m01 * m01).sqrt();
        let want = ((tr + disc) / (tr - disc)).sqrt();
        assert!((singular_value_ratio(a, b, c, d) - want).abs() < 1e-12);
    }
}
