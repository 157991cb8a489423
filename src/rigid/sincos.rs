//! Sines and cosines of many angles at once, for the per-frame rotations `R(tα)`.
//!
//! One rotation per disc edge (or per triangle) dominates the per-frame cost of eq. (1) besides
//! the triangular solves. `f64::sin_cos` is a scalar library call; [`sin_cos_many`] is branch-free
//! straight-line arithmetic the compiler vectorizes, accurate to a few units in the last place:
//! Cody–Waite reduction by π/2 and the classic minimax polynomials of sin and cos on [−π/4, π/4].
//! Angles of magnitude 10⁵ or more (or non-finite) fall back to the standard library.
//!
//! The constants are the well-known splitting of π/2 and the minimax coefficients published with
//! fdlibm, written with all their published digits (the compiler rounds them to f64).
#![allow(clippy::excessive_precision)]

/// Largest |x| reduced here; beyond it `n·PIO2_1` would no longer be exact.
const MAX_REDUCED: f64 = 1e5;
/// 1.5·2⁵²: adding and subtracting it rounds to the nearest integer, and the low bits of the
/// sum's representation hold that integer modulo 4 (2⁵¹ is a multiple of 4).
const SHIFTER: f64 = 6_755_399_441_055_744.0;
/// π/2 split into a 33-bit head and two tails.
const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
const S: [f64; 6] = [
    -1.666_666_666_666_663_243_48e-1,
    8.333_333_333_322_489_461_24e-3,
    -1.984_126_982_985_794_931_34e-4,
    2.755_731_370_707_006_767_89e-6,
    -2.505_076_025_340_686_341_95e-8,
    1.589_690_995_211_550_102_21e-10,
];
const C: [f64; 6] = [
    4.166_666_666_666_660_190_37e-2,
    -1.388_888_888_887_410_957_49e-3,
    2.480_158_728_947_672_941_78e-5,
    -2.755_731_435_139_066_330_35e-7,
    2.087_572_321_298_174_827_9e-9,
    -1.135_964_755_778_819_482_65e-11,
];

/// `sin[k], cos[k] = sin(angles[k]), cos(angles[k])`; the three slices have equal length.
/// Inlined, so that a caller running in `simd::vectorized` gets it in wide instructions.
#[inline(always)]
pub(crate) fn sin_cos_many(angles: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    debug_assert!(angles.len() == sin.len() && angles.len() == cos.len());
    let mut all_small = true;
    for ((&x, s_out), c_out) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
        all_small &= x.abs() < MAX_REDUCED;
        let shifted = x * std::f64::consts::FRAC_2_PI + SHIFTER;
        let q = shifted.to_bits();
        let n = shifted - SHIFTER;
        let y = ((x - n * PIO2_1) - n * PIO2_2) - n * PIO2_2T;
        let z = y * y;
        let ps = S[0] + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5]))));
        let s = y + y * z * ps;
        let pc = C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5]))));
        let hz = 0.5 * z;
        let w = 1.0 - hz;
        let c = w + (((1.0 - w) - hz) + z * z * pc);
        // Quadrant q mod 4: sin = (s, c, −s, −c)[q], cos = (c, −s, −c, s)[q], without branches.
        let (sb, cb) = (s.to_bits(), c.to_bits());
        let odd = 0u64.wrapping_sub(q & 1);
        let sin_bits = (sb & !odd) | (cb & odd);
        let cos_bits = (cb & !odd) | (sb & odd);
        let sin_sign = (q & 2) << 62;
        let cos_sign = (q.wrapping_add(1) & 2) << 62;
        *s_out = f64::from_bits(sin_bits ^ sin_sign);
        *c_out = f64::from_bits(cos_bits ^ cos_sign);
    }
    if !all_small {
        for ((&x, s_out), c_out) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
            if x.is_nan() || x.abs() >= MAX_REDUCED {
                (*s_out, *c_out) = x.sin_cos();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_standard_library() {
        let mut xs: Vec<f64> = (0..200_000).map(|k| -60.0 + k as f64 * 0.000_6).collect();
        xs.extend([
            0.0,
            -0.0,
            1e-300,
            99_999.9,
            -1e5,
            1e6,
            3e300,
            std::f64::consts::PI,
        ]);
        xs.extend([f64::NAN, f64::INFINITY]);
        let mut s = vec![0.0; xs.len()];
        let mut c = vec![0.0; xs.len()];
        sin_cos_many(&xs, &mut s, &mut c);
        let mut worst: f64 = 0.0;
        for ((x, s), c) in xs.iter().zip(&s).zip(&c) {
            let (s0, c0) = x.sin_cos();
            if x.is_finite() {
                worst = worst.max((s - s0).abs()).max((c - c0).abs());
            } else {
                assert!(s.is_nan() && c.is_nan());
            }
        }
        assert!(worst < 5e-16, "worst error {worst}");
    }

    /// Compiled for wide instructions (`simd.rs`), the polynomials give the bits of plain code,
    /// through every quadrant, the fallback and non-finite angles.
    #[test]
    fn wide_instructions_keep_the_bits() {
        let mut xs: Vec<f64> = (0..50_000).map(|k| -300.0 + k as f64 * 0.012_3).collect();
        xs.extend([
            0.0,
            -0.0,
            1e-300,
            99_999.9,
            1e6,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
        ]);
        let run = || {
            let (mut s, mut c) = (vec![0.0; xs.len()], vec![0.0; xs.len()]);
            crate::rigid::simd::vectorized(
                #[inline(always)]
                || sin_cos_many(&xs, &mut s, &mut c),
            );
            (s, c)
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let (ws, wc) = run();
        let (ps, pc) = crate::rigid::simd::scalar(run);
        assert!(bits(&ws) == bits(&ps) && bits(&wc) == bits(&pc));
    }
}
