//! Linear vertex interpolation, `v_i(t) = (1 − t)·p_i + t·q_i`: the naive baseline of §4.1
//! (Fig. 3(a)), which shrinks shapes that rotate.

use crate::geometry::Point;

/// Writes `(1 − t)·source + t·target` into `out`.
pub(crate) fn blend(source: &[Point], target: &[Point], t: f64, out: &mut [Point]) {
    for ((o, &p), &q) in out.iter_mut().zip(source).zip(target) {
        *o = p * (1.0 - t) + q * t;
    }
}

/// Least-squares rotation angle taking the vectors `p_j − p_i` of point `i`'s neighbourhood onto
/// `q_j − q_i` (the best-fit angle reported by `rotation_at` for the non-disc methods).
pub(crate) fn best_fit_angles(source: &[Point], target: &[Point], rings: &[Vec<u32>]) -> Vec<f64> {
    rings
        .iter()
        .enumerate()
        .map(|(i, ring)| {
            let (mut cross, mut dot) = (0.0, 0.0);
            for &j in ring {
                let d = source[j as usize] - source[i];
                let e = target[j as usize] - target[i];
                cross += d.perp_dot(e);
                dot += d.dot(e);
            }
            cross.atan2(dot)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blend_is_affine_in_t() {
        let p = [Point::new(0.0, 0.0), Point::new(2.0, 0.0)];
        let q = [Point::new(4.0, 2.0), Point::new(0.0, 2.0)];
        let mut out = [Point::ZERO; 2];
        blend(&p, &q, 0.25, &mut out);
        assert_eq!(out, [Point::new(1.0, 0.5), Point::new(1.5, 0.5)]);
        let a = best_fit_angles(&p, &q, &[vec![1], vec![0]]);
        assert!((a[0].abs() - std::f64::consts::PI).abs() < 1e-12);
    }
}
