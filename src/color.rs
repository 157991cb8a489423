//! Colour interpolation in Oklab (Björn Ottosson's perceptual colour space), so that a colour
//! morphing between two others passes through what the eye sees as the in-between (red → green
//! through a warm yellow-brown, not a muddy dark olive as in sRGB).

use crate::artwork::Rgba;

/// An sRGB channel (0–255) in linear light (0–1): the inverse of the sRGB transfer curve.
pub fn to_linear(c: u8) -> f64 {
    let x = c as f64 / 255.0;
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

fn to_srgb(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round().clamp(0.0, 255.0) as u8
}

/// sRGB (alpha ignored) to Oklab `[L, a, b]`.
pub fn oklab(c: Rgba) -> [f64; 3] {
    linear_to_oklab([to_linear(c.r), to_linear(c.g), to_linear(c.b)])
}

/// Linear-light RGB (each 0–1) to Oklab `[L, a, b]`: for colours averaged in linear light,
/// which is how the eye mixes neighbouring pixels (what [`oklab`] computes after
/// [`to_linear`]).
pub fn linear_to_oklab([r, g, b]: [f64; 3]) -> [f64; 3] {
    let l = (0.412_221_470_8 * r + 0.536_332_536_3 * g + 0.051_445_992_9 * b).cbrt();
    let m = (0.211_903_498_2 * r + 0.680_699_545_1 * g + 0.107_396_956_6 * b).cbrt();
    let s = (0.088_302_461_9 * r + 0.281_718_837_6 * g + 0.629_978_700_5 * b).cbrt();
    [
        0.210_454_255_3 * l + 0.793_617_785 * m - 0.004_072_046_8 * s,
        1.977_998_495_1 * l - 2.428_592_205 * m + 0.450_593_709_9 * s,
        0.025_904_037_1 * l + 0.782_771_766_2 * m - 0.808_675_766 * s,
    ]
}

/// Oklab back to sRGB, opaque, channels clamped to the gamut.
pub fn from_oklab([l, a, b]: [f64; 3]) -> Rgba {
    let l_ = l + 0.396_337_777_4 * a + 0.215_803_757_3 * b;
    let m_ = l - 0.105_561_345_8 * a - 0.063_854_172_8 * b;
    let s_ = l - 0.089_484_177_5 * a - 1.291_485_548 * b;
    let (l3, m3, s3) = (l_ * l_ * l_, m_ * m_ * m_, s_ * s_ * s_);
    Rgba {
        r: to_srgb(4.076_741_662_1 * l3 - 3.307_711_591_3 * m3 + 0.230_969_929_2 * s3),
        g: to_srgb(-1.268_438_004_6 * l3 + 2.609_757_401_1 * m3 - 0.341_319_396_5 * s3),
        b: to_srgb(-0.004_196_086_3 * l3 - 0.703_418_614_7 * m3 + 1.707_614_701 * s3),
        a: 255,
    }
}

/// ΔEOK, the perceptual difference of two Oklab colours: their Euclidean distance (as CSS
/// Color 4 defines it; about 0.02 is a just noticeable difference, white to black is 1).
pub fn delta_e_ok(p: [f64; 3], q: [f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// The colour a fraction `t` of the way from `a` to `b`, interpolated in Oklab; exactly `a` at
/// 0 and `b` at 1.
pub fn mix(a: Rgba, b: Rgba, t: f64) -> Rgba {
    if t <= 0.0 {
        return a;
    }
    if t >= 1.0 {
        return b;
    }
    let (p, q) = (oklab(a), oklab(b));
    let mut c = from_oklab([
        p[0] + (q[0] - p[0]) * t,
        p[1] + (q[1] - p[1]) * t,
        p[2] + (q[2] - p[2]) * t,
    ]);
    c.a = (a.a as f64 + (b.a as f64 - a.a as f64) * t).round() as u8;
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(r: u8, g: u8, b: u8) -> Rgba {
        Rgba { r, g, b, a: 255 }
    }

    #[test]
    fn round_trips_and_ends_are_exact() {
        for c in [
            rgb(0, 0, 0),
            rgb(255, 255, 255),
            rgb(233, 30, 99),
            rgb(63, 81, 181),
        ] {
            assert_eq!(from_oklab(oklab(c)), c);
        }
        let (a, b) = (rgb(255, 0, 0), rgb(0, 128, 0));
        assert_eq!(mix(a, b, 0.0), a);
        assert_eq!(mix(a, b, 1.0), b);
        // White is L = 1, a = b = 0.
        let w = oklab(rgb(255, 255, 255));
        assert!((w[0] - 1.0).abs() < 1e-6 && w[1].abs() < 1e-6 && w[2].abs() < 1e-6);
    }

    #[test]
    fn the_middle_is_perceptually_between() {
        // Black → white passes mid-grey in lightness (sRGB ≈ 99), not the sRGB average 128.
        let m = mix(rgb(0, 0, 0), rgb(255, 255, 255), 0.5);
        assert!(
            m.r == m.g && m.g == m.b && (95..=103).contains(&m.r),
            "{m:?}"
        );
        // Red → green stays bright instead of dipping to dark olive.
        let y = mix(rgb(255, 0, 0), rgb(0, 255, 0), 0.5);
        assert!(oklab(y)[0] > 0.7, "{y:?}");
    }

    #[test]
    fn delta_e_spans_black_to_white_and_is_symmetric() {
        let (k, w) = (oklab(rgb(0, 0, 0)), oklab(rgb(255, 255, 255)));
        assert!((delta_e_ok(k, w) - 1.0).abs() < 1e-6);
        let (a, b) = (oklab(rgb(29, 78, 216)), oklab(rgb(22, 163, 74)));
        assert_eq!(delta_e_ok(a, b), delta_e_ok(b, a));
        assert_eq!(delta_e_ok(a, a), 0.0);
        // One sRGB step in a mid grey is well under a just noticeable difference.
        let step = delta_e_ok(oklab(rgb(128, 128, 128)), oklab(rgb(129, 129, 129)));
        assert!(step > 0.0 && step < 0.005, "{step}");
        let lin = [to_linear(29), to_linear(78), to_linear(216)];
        assert_eq!(linear_to_oklab(lin), a);
    }
}
