//! The morph as an animated PNG (APNG): full 8-bit alpha and true colour, so unlike the GIF it
//! needs no background and no palette; delays are exact fractions of a second.

use tiny_skia::Pixmap;

use super::gif::{check_frames, playback_schedule};
use super::Timeline;
use crate::render::straight_rgba;
use crate::{Error, Result};

/// Shortest delay browsers honour for animated images: Chromium and Firefox show frames with a
/// delay of 10 ms or less for 100 ms, so shorter intervals skip frames instead.
const APNG_MIN_DELAY: f64 = 0.011;

/// Encodes rendered frames as an animated PNG.
///
/// `frames[i]` is frame `i` of `timeline` (premultiplied RGBA, all the same size); they are
/// stored as straight RGBA with their alpha intact, in [`Timeline::sequence`] order, played
/// forever (`num_plays = 0`) when [`Timeline::repeats`], else once. Each frame's delay is its
/// number of frame intervals times the interval, as the closest fraction with 16-bit numerator
/// and denominator (exact for intervals such as `2 s / 59`). When the interval is 10 ms or less,
/// frames are skipped evenly rather than slowed down by browsers, keeping the source and target
/// frames (only the target's own last interval, before the end or the restart, is then
/// lengthened to 11 ms); identical consecutive frames merge into one longer delay. Output is deterministic.
///
/// Errors (internal): no frames, a frame count other than the timeline's, or frames of
/// different sizes.
pub fn encode_apng(frames: &[Pixmap], timeline: &Timeline) -> Result<Vec<u8>> {
    let (w, h) = check_frames(frames, timeline)?;
    let tl = timeline.sanitized();
    let interval = tl.frame_interval();

    // (frame, intervals shown), identical neighbours merged.
    let mut pieces: Vec<(usize, usize)> = Vec::new();
    for s in playback_schedule(&tl, APNG_MIN_DELAY) {
        match pieces.last_mut() {
            Some((f, n)) if frames[*f].data() == frames[s.frame].data() => *n += s.intervals,
            _ => pieces.push((s.frame, s.intervals)),
        }
    }

    let err = |e: png::EncodingError| Error::internal(format!("APNG encoding failed: {e}"));
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let plays = if tl.repeats() { 0 } else { 1 };
    enc.set_animated(pieces.len() as u32, plays).map_err(err)?;
    enc.set_blend_op(png::BlendOp::Source).map_err(err)?;
    enc.set_dispose_op(png::DisposeOp::None).map_err(err)?;
    let mut writer = enc.write_header().map_err(err)?;
    for &(frame, intervals) in &pieces {
        // Only the target's last interval (once / loop) can be shorter than the minimum.
        let (num, den) = rational_seconds((intervals as f64 * interval).max(APNG_MIN_DELAY));
        writer.set_frame_delay(num, den).map_err(err)?;
        writer
            .write_image_data(&straight_rgba(&frames[frame]))
            .map_err(err)?;
    }
    writer.finish().map_err(err)?;
    Ok(out)
}

/// The fraction `num / den` closest to `seconds` with both parts in `u16` (APNG's `fcTL` delay):
/// the continued-fraction convergent or semiconvergent of largest admissible denominator.
/// Clamped to `[0, 65535]` seconds.
fn rational_seconds(seconds: f64) -> (u16, u16) {
    const MAX: u64 = u16::MAX as u64;
    if seconds.is_nan() || seconds <= 0.0 {
        return (0, 1);
    }
    if seconds >= MAX as f64 {
        return (u16::MAX, 1);
    }
    let err = |p: u64, q: u64| (p as f64 / q as f64 - seconds).abs();
    // Convergents h(k)/k(k): (p0, q0) the one before (p1, q1).
    let (mut p0, mut q0, mut p1, mut q1) = (0u64, 1u64, 1u64, 0u64);
    let mut v = seconds;
    loop {
        let a = v.floor();
        let a_int = a as u64;
        let (p2, q2) = (a_int * p1 + p0, a_int * q1 + q0);
        if a >= MAX as f64 || p2 > MAX || q2 > MAX {
            // The best semiconvergent t·(p1, q1) + (p0, q0) that still fits, if it beats (p1, q1).
            let fit = |x0: u64, x1: u64| (MAX - x0).checked_div(x1).unwrap_or(u64::MAX);
            let t = fit(p0, p1).min(fit(q0, q1));
            if t >= 1 {
                let (ps, qs) = (t * p1 + p0, t * q1 + q0);
                if q1 == 0 || err(ps, qs) < err(p1, q1) {
                    return (ps as u16, qs as u16);
                }
            }
            break;
        }
        (p0, q0, p1, q1) = (p1, q1, p2, q2);
        let frac = v - a;
        if frac <= 0.0 || err(p1, q1) <= seconds * 1e-12 {
            break;
        }
        v = 1.0 / frac;
    }
    (p1 as u16, q1.max(1) as u16)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::Playback;
    use std::io::Cursor;
    use tiny_skia::{Color, Paint, Rect, Transform};

    /// `n` frames of a half-transparent bar sliding over a transparent background.
    fn sliding(n: usize) -> Vec<Pixmap> {
        (0..n)
            .map(|i| {
                let x = 12.0 * i as f32 / (n - 1) as f32;
                let mut p = Pixmap::new(16, 4).unwrap();
                let mut paint = Paint::default();
                paint.set_color(Color::from_rgba8(20, 200, 90, 128));
                paint.anti_alias = false;
                let r = Rect::from_ltrb(x, 0.0, x + 4.0, 4.0).unwrap();
                p.fill_rect(r, &paint, Transform::identity(), None);
                p
            })
            .collect()
    }

    struct Decoded {
        num_frames: u32,
        num_plays: u32,
        delays: Vec<(u16, u16)>,
        images: Vec<Vec<u8>>,
    }

    fn decode(bytes: &[u8]) -> Decoded {
        let mut r = png::Decoder::new(Cursor::new(bytes)).read_info().unwrap();
        let actl = r.info().animation_control.unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let (mut delays, mut images) = (vec![], vec![]);
        for _ in 0..actl.num_frames {
            let out = r.next_frame(&mut buf).unwrap();
            let fc = r.info().frame_control.unwrap();
            delays.push((fc.delay_num, fc.delay_den));
            images.push(buf[..out.buffer_size()].to_vec());
        }
        Decoded {
            num_frames: actl.num_frames,
            num_plays: actl.num_plays,
            delays,
            images,
        }
    }

    #[test]
    fn frames_delays_and_plays_follow_the_timeline() {
        for (playback, shown, plays) in [
            (Playback::Once, 5, 1),
            (Playback::Loop, 5, 0),
            (Playback::Yoyo, 8, 0),
        ] {
            let tl = Timeline {
                frames: 5,
                duration: 1.0,
                playback,
                ..Timeline::default()
            };
            let frames = sliding(5);
            let bytes = encode_apng(&frames, &tl).unwrap();
            assert_eq!(bytes, encode_apng(&frames, &tl).unwrap(), "deterministic");
            let d = decode(&bytes);
            assert_eq!((d.num_frames, d.num_plays), (shown, plays), "{playback:?}");
            assert!(d.delays.iter().all(|&dl| dl == (1, 4)), "{:?}", d.delays);
            // Alpha survives: frame k of the sequence is the straight-RGBA source frame.
            for (k, &f) in tl.sequence().iter().enumerate() {
                assert_eq!(d.images[k], straight_rgba(&frames[f]), "{playback:?} {k}");
            }
            assert_eq!(d.images[0][3], 128);
            assert_eq!(d.images[0][4 * 15 + 3], 0);
        }
    }

    #[test]
    fn short_intervals_skip_frames_with_exact_delays() {
        // 201 frames over 1 s: 5 ms apart, so every third frame is kept (15 ms).
        let tl = Timeline {
            frames: 201,
            duration: 1.0,
            ..Timeline::default()
        };
        let d = decode(&encode_apng(&sliding(201), &tl).unwrap());
        let total: f64 = d.delays.iter().map(|&(n, q)| n as f64 / q as f64).sum();
        // The target's own interval (5 ms) is lengthened to the minimum, nothing else.
        assert!((total - (1.0 + APNG_MIN_DELAY)).abs() < 1e-9, "{total}");
        assert!(d.delays.iter().all(|&(n, q)| n as f64 / q as f64 > 0.010));
        assert!(d.num_frames < 201);
    }

    #[test]
    fn delays_are_the_closest_16_bit_fractions() {
        assert_eq!(rational_seconds(2.0 / 59.0), (2, 59));
        assert_eq!(rational_seconds(0.1), (1, 10));
        assert_eq!(rational_seconds(1.234 / 59.0), (617, 29500));
        assert_eq!(rational_seconds(3.0), (3, 1));
        assert_eq!(rational_seconds(0.0), (0, 1));
        assert_eq!(rational_seconds(1e9), (u16::MAX, 1));
        // No fraction with a 16-bit denominator is closer (brute force).
        for x in [
            std::f64::consts::PI / 100.0,
            0.0173,
            7.77,
            1.0 / 65536.0 * 3.0,
        ] {
            let (n, q) = rational_seconds(x);
            let ours = (n as f64 / q as f64 - x).abs();
            let best = (1..=65535u32)
                .map(|q| ((x * q as f64).round().min(65535.0) / q as f64 - x).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(ours <= best + 1e-15, "{x}: {n}/{q} err {ours} > {best}");
        }
        let (n, q) = rational_seconds(1e-6);
        assert!(n as f64 / q as f64 <= 2e-5 && q > 0);
    }

    #[test]
    fn bad_input_is_an_error() {
        let tl = Timeline {
            frames: 3,
            ..Timeline::default()
        };
        assert!(encode_apng(&[], &tl).is_err());
        assert!(encode_apng(&sliding(2), &tl).is_err());
    }
}
