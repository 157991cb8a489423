//! How faithfully an encoded GIF shows the frames it was made from, measured in Oklab.
//!
//! A GIF has 256 colours; the frames it is made from have millions. The measure decodes the
//! GIF as a player would (each frame drawn over the last), takes the canvas on screen when each
//! frame of one period is due, and compares it with that frame composited over the same
//! background, pixel by pixel, as ΔEOK ([`crate::color::delta_e_ok`]). Only the pixels the
//! drawing covers count: the background is reproduced exactly and would dilute the figure.
//!
//! Two figures, because dithering trades one kind of error for another: the plain per-pixel
//! mean, and the mean after both images are averaged over 5 × 5 pixels in linear light (what
//! the eye sees of a pattern of small dots). Bands of one palette colour across a gradient show
//! in both; a dither pattern that reproduces the gradient on average scores well in the second.

use tiny_skia::Pixmap;

use super::{check_frames, composite_rgb, delays_cs, opaque_background, playback_schedule};
use super::{Timeline, GIF_MIN_DELAY};
use crate::artwork::Rgba;
use crate::color::{delta_e_ok, linear_to_oklab, to_linear};
use crate::{Error, Result};

/// Half the side of the square over which [`Fidelity::mean_smoothed_delta_e`] averages.
const SMOOTHING_RADIUS: usize = 2;

/// How closely a GIF reproduces its frames (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fidelity {
    /// Mean ΔEOK per covered pixel over every frame of one period (about 0.02 is just
    /// noticeable side by side).
    pub mean_delta_e: f64,
    /// The same after both images are averaged over 5 × 5 pixels in linear light: low when
    /// dithering reproduces the colours on average, high where flat bands replace a gradient.
    pub mean_smoothed_delta_e: f64,
    /// How many frames were compared (one period of playback; a yoyo shows most frames twice).
    pub frames: usize,
}

/// Measures how closely `gif` (as [`super::encode_gif`] made it from `frames`, `timeline` and
/// `background`) shows each frame: decodes it, and compares the canvas on screen when each
/// frame of one period is due with that frame over the background (see the module docs).
///
/// Errors (internal): the GIF does not decode, its size differs from the frames', or the frames
/// do not fit the timeline.
pub fn gif_fidelity(
    gif: &[u8],
    frames: &[Pixmap],
    timeline: &Timeline,
    background: Option<Rgba>,
) -> Result<Fidelity> {
    let (w, h) = check_frames(frames, timeline)?;
    let (w, h) = (w as usize, h as usize);
    let tl = timeline.sanitized();
    let bg = opaque_background(background);
    let canvases = decode_canvases(gif, w, h)?;
    let schedule = playback_schedule(&tl, GIF_MIN_DELAY);
    let lin: Vec<f64> = (0..=255u8).map(to_linear).collect();

    let (mut plain, mut smooth, mut count) = (0.0, 0.0, 0usize);
    let mut start = 0.0;
    for (s, delay) in schedule
        .iter()
        .zip(delays_cs(&schedule, tl.frame_interval()))
    {
        // The last GIF frame that started by then is on screen.
        let shown = canvases
            .iter()
            .rposition(|(t, _)| *t <= start + 1e-9)
            .ok_or_else(|| Error::internal("the GIF has no frame at its start"))?;
        start += delay;
        let got = linear_rgb(&canvases[shown].1, &lin);
        let want = linear_rgb(&composite_rgb(&frames[s.frame], bg), &lin);
        let covered: Vec<bool> = frames[s.frame]
            .pixels()
            .iter()
            .map(|p| p.alpha() > 0)
            .collect();
        let (got_s, want_s) = (box_blur(&got, w, h), box_blur(&want, w, h));
        for (i, _) in covered.iter().enumerate().filter(|(_, c)| **c) {
            plain += delta_e_ok(linear_to_oklab(got[i]), linear_to_oklab(want[i]));
            smooth += delta_e_ok(linear_to_oklab(got_s[i]), linear_to_oklab(want_s[i]));
            count += 1;
        }
    }
    let n = count.max(1) as f64;
    Ok(Fidelity {
        mean_delta_e: plain / n,
        mean_smoothed_delta_e: smooth / n,
        frames: schedule.len(),
    })
}

/// Each frame of a GIF as the canvas shows it after drawing that frame (packed RGB), with the
/// time in centiseconds at which it appears.
fn decode_canvases(gif: &[u8], w: usize, h: usize) -> Result<Vec<(f64, Vec<u8>)>> {
    let err = |e: gif::DecodingError| Error::internal(format!("the GIF does not decode: {e}"));
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(gif).map_err(err)?;
    if (d.width() as usize, d.height() as usize) != (w, h) {
        return Err(Error::internal(format!(
            "the GIF is {}×{} but the frames are {w}×{h}",
            d.width(),
            d.height()
        )));
    }
    let mut canvas = vec![0u8; 3 * w * h];
    let (mut out, mut clock) = (Vec::new(), 0.0);
    while let Some(f) = d.read_next_frame().map_err(err)? {
        let (fw, fh) = (f.width as usize, f.height as usize);
        let (left, top) = (f.left as usize, f.top as usize);
        for y in 0..fh.min(h.saturating_sub(top)) {
            for x in 0..fw.min(w.saturating_sub(left)) {
                let src = &f.buffer[4 * (y * fw + x)..4 * (y * fw + x) + 3];
                let dst = 3 * ((y + top) * w + x + left);
                canvas[dst..dst + 3].copy_from_slice(src);
            }
        }
        out.push((clock, canvas.clone()));
        clock += f.delay as f64;
    }
    Ok(out)
}

/// Packed RGB bytes as linear-light triples, through the table `lin` of the 256 levels.
fn linear_rgb(rgb: &[u8], lin: &[f64]) -> Vec<[f64; 3]> {
    rgb.chunks_exact(3)
        .map(|c| [lin[c[0] as usize], lin[c[1] as usize], lin[c[2] as usize]])
        .collect()
}

/// The mean of each pixel's (2r + 1)² neighbourhood (r = [`SMOOTHING_RADIUS`]), cut at the
/// image's edges: a box filter, horizontal then vertical.
fn box_blur(img: &[[f64; 3]], w: usize, h: usize) -> Vec<[f64; 3]> {
    let r = SMOOTHING_RADIUS;
    let pass = |src: &[[f64; 3]], len: usize, lines: usize, at: &dyn Fn(usize, usize) -> usize| {
        let mut out = vec![[0.0; 3]; src.len()];
        for line in 0..lines {
            for i in 0..len {
                let (lo, hi) = (i.saturating_sub(r), (i + r).min(len - 1));
                let mut sum = [0.0; 3];
                for j in lo..=hi {
                    let p = src[at(line, j)];
                    (0..3).for_each(|c| sum[c] += p[c]);
                }
                let n = (hi - lo + 1) as f64;
                out[at(line, i)] = sum.map(|v| v / n);
            }
        }
        out
    };
    let rows = pass(img, w, h, &|y, x| y * w + x);
    pass(&rows, h, w, &|x, y| y * w + x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_blur_keeps_flat_images_and_averages_a_checkerboard() {
        let (w, h) = (7, 5);
        let flat = vec![[0.25, 0.5, 0.75]; w * h];
        for (a, b) in box_blur(&flat, w, h).iter().zip(&flat) {
            (0..3).for_each(|c| assert!((a[c] - b[c]).abs() < 1e-12));
        }
        let checker: Vec<[f64; 3]> = (0..w * h)
            .map(|i| [((i % w + i / w) % 2) as f64; 3])
            .collect();
        let centre = box_blur(&checker, w, h)[2 * w + 3];
        // 25 pixels around the 1 at (3, 2), 13 of them 1.
        assert!((centre[0] - 13.0 / 25.0).abs() < 1e-12, "{centre:?}");
    }
}
