//! The morph as an animated PNG (APNG): full 8-bit alpha and true colour, so unlike the GIF it
//! needs no background and no palette; delays are exact fractions of a second.
//!
//! The container is assembled here (signature, `IHDR`, `acTL`, then per frame `fcTL` and
//! `IDAT`/`fdAT`, `IEND`) so that frames compress in parallel: each frame's pixels are
//! compressed on their own by the png crate (as a standalone PNG whose `IDAT` stream is exactly
//! the frame's image data), and after the first frame only the rectangle that changed is stored
//! (blend `SOURCE` replaces it, alpha included; dispose `NONE` keeps the rest).

use std::borrow::Cow;
use std::io::{Cursor, Seek, SeekFrom, Write};

use rayon::prelude::*;
use tiny_skia::Pixmap;

use super::gif::{changed_rect, check_frames, playback_schedule};
use super::Timeline;
use crate::render::straight_rgba;
use crate::render::stream::{chunk_len, in_order};
use crate::{Error, Result};

/// Shortest delay browsers honour for animated images: Chromium and Firefox show frames with a
/// delay of 10 ms or less for 100 ms, so shorter intervals skip frames instead.
pub(crate) const APNG_MIN_DELAY: f64 = 0.011;

/// Encodes rendered frames as an animated PNG.
///
/// `frames[i]` is frame `i` of `timeline` (premultiplied RGBA, all the same size); they are
/// stored as straight RGBA with their alpha intact, in [`Timeline::sequence`] order, played
/// forever (`num_plays = 0`) when [`Timeline::repeats`], else once. Each frame's delay is its
/// number of frame intervals times the interval, as the closest fraction with 16-bit numerator
/// and denominator (exact for intervals such as `2 s / 59`). When the interval is 10 ms or less,
/// frames are skipped evenly rather than slowed down by browsers, keeping the source and target
/// frames (only the target's own last interval, before the end or the restart, is then
/// lengthened to 11 ms); identical consecutive frames merge into one longer delay. Output is
/// deterministic.
///
/// Errors (internal): no frames, a frame count other than the timeline's, or frames of
/// different sizes.
pub fn encode_apng(frames: &[Pixmap], timeline: &Timeline) -> Result<Vec<u8>> {
    let size = check_frames(frames, timeline)?;
    let mut out = Cursor::new(Vec::new());
    write_apng(size, |i| Ok(Cow::Borrowed(&frames[i])), timeline, &mut out)?;
    Ok(out.into_inner())
}

/// [`encode_apng`] of frames rendered on demand, written to `out` as they are compressed:
/// memory holds two chunks of frames at a time, however many the timeline has.
///
/// `render(i)` is frame `i` of `timeline`, `size` pixels, called from rayon's threads once per
/// frame shown (twice for the frames a yoyo shows twice). `out` must seek: the frame count in
/// `acTL`, known only once identical neighbours are merged, is written last, at its place after
/// `IHDR`. The bytes are those of [`encode_apng`] on the same frames.
///
/// Errors: those of `render` and of `out`, and (internal) a frame of another size.
pub fn write_apng<'f, W: Write + Seek>(
    size: (u32, u32),
    render: impl Fn(usize) -> Result<Cow<'f, Pixmap>> + Sync,
    timeline: &Timeline,
    mut out: W,
) -> Result<()> {
    let (w, h) = size;
    let tl = timeline.sanitized();
    let interval = tl.frame_interval();
    let io = |e: std::io::Error| Error::internal(format!("APNG writing failed: {e}"));
    let start = out.stream_position().map_err(io)?;

    let mut head = Vec::new();
    head.extend_from_slice(b"\x89PNG\r\n\x1a\n");
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]); // 8-bit RGBA, deflate, adaptive filters, no interlace
    chunk(&mut head, b"IHDR", &ihdr);
    let actl_at = head.len() as u64;
    let plays: u32 = if tl.repeats() { 0 } else { 1 };
    let actl = |frames: u32| {
        let mut a = frames.to_be_bytes().to_vec();
        a.extend_from_slice(&plays.to_be_bytes());
        let mut c = Vec::new();
        chunk(&mut c, b"acTL", &a);
        c
    };
    head.extend_from_slice(&actl(0));
    out.write_all(&head).map_err(io)?;

    let frame = |i: usize| -> Result<Cow<'f, Pixmap>> {
        let f = render(i)?;
        if (f.width(), f.height()) != size {
            return Err(Error::internal(format!(
                "frame {i} is {}×{} but the animation is {w}×{h}",
                f.width(),
                f.height()
            )));
        }
        Ok(f)
    };
    // Identical consecutive frames merge into one longer delay, so a piece is final only when
    // a different frame follows it; final pieces are compressed a chunk at a time.
    let shown: Vec<(usize, usize)> = playback_schedule(&tl, APNG_MIN_DELAY)
        .iter()
        .map(|s| (s.frame, s.intervals))
        .collect();
    let mut writer = PieceWriter {
        last: None,
        ready: Vec::new(),
        sequence: 0,
        pieces: 0,
        interval,
        size: (w as usize, h as usize),
    };
    let mut open: Option<(Cow<'f, Pixmap>, usize)> = None;
    let per_chunk = chunk_len(4 * w as usize * h as usize);
    in_order(
        &shown,
        per_chunk,
        |&(i, intervals)| Ok((frame(i)?, intervals)),
        |(px, intervals)| {
            match &mut open {
                Some((p, n)) if p.data() == px.data() => *n += intervals,
                _ => {
                    if let Some(done) = open.replace((px, intervals)) {
                        writer.ready.push(done);
                        if writer.ready.len() >= per_chunk {
                            writer.flush(&mut out)?;
                        }
                    }
                }
            }
            Ok(())
        },
    )?;
    writer.ready.extend(open);
    writer.flush(&mut out)?;
    let mut end = Vec::new();
    chunk(&mut end, b"IEND", &[]);
    out.write_all(&end).map_err(io)?;
    // The frame count, now known, in place of the placeholder.
    let after = out.stream_position().map_err(io)?;
    out.seek(SeekFrom::Start(start + actl_at)).map_err(io)?;
    out.write_all(&actl(writer.pieces)).map_err(io)?;
    out.seek(SeekFrom::Start(after)).map_err(io)?;
    out.flush().map_err(io)
}

/// Compresses final pieces a chunk at a time, each after the first storing only the rectangle
/// that changed since the piece before, and writes their `fcTL` and `IDAT`/`fdAT` chunks.
struct PieceWriter<'f> {
    /// The last piece written (what the next one is compared with).
    last: Option<Cow<'f, Pixmap>>,
    /// Final pieces not written yet, with the frame intervals each is shown.
    ready: Vec<(Cow<'f, Pixmap>, usize)>,
    /// The next chunk sequence number.
    sequence: u32,
    /// Pieces written so far.
    pieces: u32,
    interval: f64,
    size: (usize, usize),
}

impl PieceWriter<'_> {
    fn flush<W: Write>(&mut self, out: &mut W) -> Result<()> {
        let (wu, hu) = self.size;
        let ready = &self.ready;
        let last = self.last.as_deref();
        let first = self.pieces == 0;
        let encoded: Vec<Result<(Rect, Vec<u8>)>> = ready
            .par_iter()
            .enumerate()
            .map(|(k, (px, _))| {
                let prev = if k == 0 { last } else { Some(&*ready[k - 1].0) };
                let (x0, y0, x1, y1) = changed_rect(prev.map(|p| p.pixels()), px.pixels(), wu, hu);
                let rgba = straight_rgba(px);
                let mut crop = Vec::with_capacity(4 * (x1 - x0) * (y1 - y0));
                for y in y0..y1 {
                    crop.extend_from_slice(&rgba[4 * (y * wu + x0)..4 * (y * wu + x1)]);
                }
                let rect = Rect {
                    x: x0 as u32,
                    y: y0 as u32,
                    w: (x1 - x0) as u32,
                    h: (y1 - y0) as u32,
                };
                Ok((rect, compressed_image_data(&crop, rect.w, rect.h)?))
            })
            .collect();
        let mut bytes = Vec::with_capacity(encoded.iter().flatten().map(|e| e.1.len() + 64).sum());
        for (k, (e, &(_, intervals))) in encoded.into_iter().zip(ready).enumerate() {
            let (rect, data) = e?;
            // Only the target's last interval (once / loop) can be shorter than the minimum.
            let (num, den) =
                rational_seconds((intervals as f64 * self.interval).max(APNG_MIN_DELAY));
            let mut fctl = Vec::with_capacity(26);
            for v in [self.sequence, rect.w, rect.h, rect.x, rect.y] {
                fctl.extend_from_slice(&v.to_be_bytes());
            }
            fctl.extend_from_slice(&num.to_be_bytes());
            fctl.extend_from_slice(&den.to_be_bytes());
            fctl.extend_from_slice(&[0, 0]); // dispose NONE, blend SOURCE
            chunk(&mut bytes, b"fcTL", &fctl);
            self.sequence += 1;
            if first && k == 0 {
                chunk(&mut bytes, b"IDAT", &data);
            } else {
                let mut fdat = Vec::with_capacity(data.len() + 4);
                fdat.extend_from_slice(&self.sequence.to_be_bytes());
                fdat.extend_from_slice(&data);
                chunk(&mut bytes, b"fdAT", &fdat);
                self.sequence += 1;
            }
        }
        out.write_all(&bytes)
            .map_err(|e| Error::internal(format!("APNG writing failed: {e}")))?;
        self.pieces += self.ready.len() as u32;
        if let Some((p, _)) = self.ready.pop() {
            self.last = Some(p);
        }
        self.ready.clear();
        Ok(())
    }
}

/// A frame's region on the canvas, in pixels.
#[derive(Debug, Clone, Copy)]
struct Rect {
    x: u32,
    y: u32,
    w: u32,
    h: u32,
}

/// The zlib stream of filtered scanlines of a `w × h` straight-RGBA image: the concatenated
/// `IDAT` data of that image encoded as a standalone PNG.
fn compressed_image_data(rgba: &[u8], w: u32, h: u32) -> Result<Vec<u8>> {
    let err = |e: png::EncodingError| Error::internal(format!("APNG encoding failed: {e}"));
    let mut png_bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut png_bytes, w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(err)?;
    writer.write_image_data(rgba).map_err(err)?;
    writer.finish().map_err(err)?;
    let mut data = Vec::new();
    let mut pos = 8;
    while pos + 12 <= png_bytes.len() {
        let len = u32::from_be_bytes([
            png_bytes[pos],
            png_bytes[pos + 1],
            png_bytes[pos + 2],
            png_bytes[pos + 3],
        ]) as usize;
        let body = pos + 8..(pos + 8 + len).min(png_bytes.len());
        if &png_bytes[pos + 4..pos + 8] == b"IDAT" {
            data.extend_from_slice(&png_bytes[body]);
        }
        pos += 12 + len;
    }
    Ok(data)
}

/// Appends one PNG chunk: length, type, data, CRC-32 of type and data.
fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(crc32(!0, kind), data);
    out.extend_from_slice(&(!crc).to_be_bytes());
}

/// The CRC-32 (ISO-HDLC, as PNG uses) register after feeding `bytes` into `crc`.
fn crc32(mut crc: u32, bytes: &[u8]) -> u32 {
    const TABLE: [u32; 256] = {
        let mut t = [0u32; 256];
        let mut n = 0;
        while n < 256 {
            let mut c = n as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
                k += 1;
            }
            t[n] = c;
            n += 1;
        }
        t
    };
    for &b in bytes {
        crc = TABLE[((crc ^ b as u32) & 0xFF) as usize] ^ (crc >> 8);
    }
    crc
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
        let w = r.info().width as usize;
        let mut canvas = vec![0; r.output_buffer_size().unwrap()];
        let mut buf = canvas.clone();
        let (mut delays, mut images) = (vec![], vec![]);
        for _ in 0..actl.num_frames {
            let out = r.next_frame(&mut buf).unwrap();
            let fc = r.info().frame_control.unwrap();
            delays.push((fc.delay_num, fc.delay_den));
            // Blend SOURCE, dispose NONE: the sub-frame replaces its rectangle.
            assert_eq!(
                (fc.blend_op, fc.dispose_op),
                (png::BlendOp::Source, png::DisposeOp::None)
            );
            let (fx, fy, fw) = (
                fc.x_offset as usize,
                fc.y_offset as usize,
                out.width as usize,
            );
            for y in 0..out.height as usize {
                let dst = 4 * ((fy + y) * w + fx);
                canvas[dst..dst + 4 * fw].copy_from_slice(&buf[4 * y * fw..4 * (y + 1) * fw]);
            }
            images.push(canvas.clone());
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
    fn chunks_carry_png_crcs() {
        // The CRC of the IEND chunk every PNG ends with.
        let mut out = Vec::new();
        chunk(&mut out, b"IEND", &[]);
        assert_eq!(
            out,
            [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82]
        );
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
