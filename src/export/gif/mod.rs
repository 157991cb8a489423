//! The morph as an animated GIF: rendered frames composited onto an opaque background, a
//! global palette (with local ones where it is poor), ordered dithering, and delays in
//! centiseconds that keep the period right.
//!
//! GIF is the most widely playable animation format but a poor fit for antialiased vector art
//! and gradients: 256 colours and 1-bit transparency. The choices below trade file size for an
//! animation that neither bands, flickers nor drifts in time:
//!
//! - **Opaque frames.** Every frame is composited over the background colour (white by
//!   default), because a 1-bit alpha mask would turn the partially covered pixels along
//!   antialiased edges into a dark or ragged fringe.
//! - **One global palette.** Built once from pixels of all frames (exactly, when the animation
//!   has at most 256 colours; with `NeuQuant` otherwise), so a colour maps to the same index in
//!   every frame and flat areas do not shimmer as per-frame palettes would.
//! - **Ordered dithering** (`dither.rs`) when the animation has more colours than that. Mapped
//!   to their nearest entries, the colours of a gradient fall into flat bands, and where the
//!   palette is sparse a band takes a neighbouring hue (a blue → green gradient got a flat
//!   stripe of one green). Dithered, each pixel shows one of a few entries that average to its
//!   colour. Ordered (a Bayer pattern fixed to the pixel grid), not error diffusion: a pixel's
//!   index depends only on its own colour and place, so still parts of the picture keep their
//!   indices from frame to frame (no crawling dots, and the changed rectangle stays small), and
//!   colours the palette holds stay flat.
//! - **Local palettes where the global one is poor.** 256 colours for every frame of a morph
//!   between two different gradients are spread thin. The frames are split into at most ten
//!   runs of consecutive frames; a run whose colours the global table misses by more than 1.5
//!   levels RMS gets a table of its own, shared by its frames, when that one cuts the error
//!   by 40 % (`LocalTables`). Sharing keeps the training, the costliest step, to ten tables
//!   however many frames there are, and a probe trained on a sixth of the sample skips the
//!   runs no table of their own would help. Frames of a morph move almost everywhere, so the
//!   switch does not make still areas shimmer; drawings the global table serves well (the
//!   gourd) never switch.
//! - **Timing.** See `playback_schedule`: delays of at least 2 cs (browsers replace shorter
//!   ones by 100 ms), cumulative rounding so that the period stays right, and skipped frames
//!   rather than a slower morph when the frame interval is under 20 ms.
//! - **Small files.** After the first frame only the rectangle whose colours changed is stored
//!   (frames are opaque, so each one simply draws over the last); identical consecutive frames
//!   merge into one longer delay. Dithering costs size (LZW compresses patterns worse than
//!   bands): the 60-frame gradient fixtures grow from 295 KB and 436 KB to 720 KB and 877 KB,
//!   the gourd from 1.08 MB to 1.29 MB.
//!
//! [`gif_fidelity`] measures the result in Oklab (`cargo run --release --example
//! gif_fidelity`).

mod dither;
mod fidelity;
mod palette;

use std::borrow::Cow;
use std::collections::{BTreeSet, HashMap};
use std::io::Write;

use rayon::prelude::*;
use tiny_skia::Pixmap;

use super::Timeline;
use crate::artwork::Rgba;
use crate::render::stream::{chunk_len, in_order};
use crate::{Error, Result};
pub use fidelity::{gif_fidelity, Fidelity};
use palette::{frame_colours, sample_rgba, FrameColours, Palette, NEUQUANT_SAMPLEFAC};

/// Shortest delay browsers honour: GIF delays of 0 or 1 cs are replaced by 100 ms.
pub(crate) const GIF_MIN_DELAY: f64 = 0.02;

pub(crate) use super::apng::APNG_MIN_DELAY;

/// At most this many pixels train the global `NeuQuant` palette (spread over all frames).
const PALETTE_SAMPLE: usize = 1 << 18;

/// At most this many pixels of a group of frames (spread evenly over them) train the group's
/// local palette and judge both tables (see [`LocalTables`]). `NeuQuant` needs about this
/// many steps for a smooth gradient: with a third of them the blue-green fixture's dither
/// error doubled.
const LOCAL_SAMPLE: usize = 3 << 15;

/// `NeuQuant`'s sampling factor for the probe that decides whether a group's own table is
/// worth training in full: a sixth of the training (see [`LocalTables`]).
const PROBE_SAMPLEFAC: i32 = 6;

/// How many times lower the full table's error is taken to be than the probe's. Measured on
/// the fixtures' groups: 1.7–2× on pictures and 1.8–3.2× on smooth gradients, which need the
/// whole training. A probe whose error is over `PROBE_REACH · LOCAL_GAIN` times the global
/// table's is unlikely to lead to a table that passes [`LOCAL_GAIN`], so the full training is
/// skipped. A wrong guess costs either a wasted training or a group left on the global table
/// (a little more dither noise), never a wrong frame.
const PROBE_REACH: f64 = 2.5;

/// The frames shown are split into at most this many groups of consecutive frames, each of
/// which may get a local table of its own: a group spans a tenth of the morph whatever the
/// frame count, so its frames' colours stay close, and the training time does not grow with
/// the frame count (60 frames: groups of 6).
const LOCAL_GROUPS: usize = 10;

/// The global table is poor for a group of frames when the mean squared distance (RGB levels,
/// 0–255) from their pixels to its nearest entries is over this: an RMS error of 1.5 levels.
/// Below it, no local table is even tried (the gourd's frames sit at about 1; a table of their
/// own, trained on fewer pixels, does worse there).
const POOR_GLOBAL: f64 = 2.25;

/// A group of frames gets its own colour table when that table's mean squared error on the
/// group's sample is under this fraction of the global table's (see [`LocalTables`]).
const LOCAL_GAIN: f64 = 0.6;

/// One frame as shown in one period of playback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Shown {
    /// Index of the frame (into `timeline.times()`).
    pub(crate) frame: usize,
    /// Position in [`Timeline::sequence`] where it starts: its start time is
    /// `start · frame_interval`.
    pub(crate) start: usize,
    /// How many frame intervals it stays on screen.
    pub(crate) intervals: usize,
}

/// Which frames of one period of playback are shown, and for how long, when no frame may be
/// shown for less than `min_delay` seconds (animated image formats: browsers show frames with a
/// delay of 10 ms or less for 100 ms, which would slow the morph down instead).
///
/// When the frame interval is long enough this is [`Timeline::sequence`], one interval each.
/// Otherwise frames are skipped — evenly within each run between the source and the target, and
/// never the source or target frame themselves (the ends of every forward or backward run) — so
/// that the kept frames are at least `min_delay` apart and the period is unchanged. Each frame
/// is shown for one interval, so one period lasts `sequence().len() · frame_interval()`: exactly
/// [`Timeline::period`] for yoyo, and one interval more for once or loop (the target stays on
/// screen for one interval like every other frame before the animation ends or restarts).
pub(crate) fn playback_schedule(timeline: &Timeline, min_delay: f64) -> Vec<Shown> {
    let tl = timeline.sanitized();
    let seq = tl.sequence();
    let n = tl.frames;
    let interval = tl.frame_interval();
    // The smallest whole number of intervals that lasts `min_delay`.
    let stride = if interval >= min_delay {
        1
    } else {
        ((min_delay / interval) * (1.0 - 1e-12)).ceil().max(1.0) as usize
    };
    // Run ends: the source and target frames, and the end of the period.
    let mut ends: Vec<usize> = (0..seq.len())
        .filter(|&p| seq[p] == 0 || seq[p] == n - 1)
        .collect();
    ends.push(seq.len());
    let mut starts = Vec::with_capacity(seq.len());
    for w in ends.windows(2) {
        let (a, r) = (w[0], w[1] - w[0]);
        let m = (r / stride).max(1);
        // Positions a + round(j·r/m), j = 0..m: gaps of ⌊r/m⌋ or ⌈r/m⌉ ≥ stride intervals.
        starts.extend((0..m).map(|j| a + (2 * j * r + m) / (2 * m)));
    }
    starts
        .iter()
        .enumerate()
        .map(|(k, &start)| Shown {
            frame: seq[start],
            start,
            intervals: starts.get(k + 1).copied().unwrap_or(seq.len()) - start,
        })
        .collect()
}

/// The delay of each shown frame in centiseconds, by cumulative rounding: frame `k` starts at
/// `round(start · interval · 100)` cs, and no delay is under 2 cs (browsers replace shorter
/// ones by 100 ms), so the delays add up to the period.
fn delays_cs(schedule: &[Shown], interval: f64) -> Vec<f64> {
    let cs = |pos: usize| (pos as f64 * interval * 100.0).round();
    let mut clock = 0.0;
    schedule
        .iter()
        .map(|s| {
            let delay = (cs(s.start + s.intervals) - clock).max(2.0);
            clock += delay;
            delay
        })
        .collect()
}

/// Checks that there is one rendered frame per timeline frame, all of one non-empty size, and
/// returns that size.
pub(crate) fn check_frames(frames: &[Pixmap], timeline: &Timeline) -> Result<(u32, u32)> {
    let expected = timeline.sanitized().frames;
    let first = frames
        .first()
        .ok_or_else(|| Error::internal("no frames to encode"))?;
    if frames.len() != expected {
        return Err(Error::internal(format!(
            "{} rendered frames for a timeline of {expected} frames",
            frames.len()
        )));
    }
    let size = (first.width(), first.height());
    if let Some(i) = frames.iter().position(|f| (f.width(), f.height()) != size) {
        return Err(Error::internal(format!(
            "frame {i} is {}×{} but frame 0 is {}×{}",
            frames[i].width(),
            frames[i].height(),
            size.0,
            size.1
        )));
    }
    Ok(size)
}

/// Encodes rendered frames as an animated GIF.
///
/// `frames[i]` is frame `i` of `timeline` (premultiplied RGBA, all the same size); they play in
/// [`Timeline::sequence`] order, forever when [`Timeline::repeats`], else once (no loop
/// extension at all: that is what browsers play exactly once). Every frame is composited over
/// `background`, or over **white** when it is `None`: GIF transparency is all-or-nothing, and
/// the partially transparent pixels of antialiased edges would otherwise fringe. A
/// semi-transparent background is itself flattened onto white.
///
/// Frame `k` of the sequence starts at `round(k · interval · 100)` cs, so the delays (at least
/// 2 cs each) add up to the period; when the interval is under 20 ms, frames are skipped rather
/// than the animation slowed down (see `playback_schedule`). Output is deterministic.
///
/// Errors (internal): no frames, a frame count other than the timeline's, frames of different
/// sizes, or frames larger than GIF's 65 535 px.
pub fn encode_gif(
    frames: &[Pixmap],
    timeline: &Timeline,
    background: Option<Rgba>,
) -> Result<Vec<u8>> {
    let size = check_frames(frames, timeline)?;
    let mut out = Vec::new();
    write_gif(
        size,
        |i| Ok(Cow::Borrowed(&frames[i])),
        timeline,
        background,
        &mut out,
    )?;
    Ok(out)
}

/// [`encode_gif`] of frames rendered on demand, written to `out` as they are encoded: memory
/// holds two chunks of frames at a time, however many the timeline has.
///
/// `render(i)` is frame `i` of `timeline`, `size` pixels. It is called from rayon's threads,
/// in two passes over the frames that are shown: the colours of every frame (for the global
/// palette) and then, in playback order, their indices. The first 64 frames (at most 64 MiB)
/// are kept between the passes; the others are rendered twice (three times for the frames a
/// yoyo shows twice) — the price of a palette shared by all frames without keeping them all.
/// The bytes are those of [`encode_gif`] on the same frames.
///
/// Errors: those of `render` and of `out`, and (internal) a frame of another size or larger
/// than GIF's 65 535 px.
pub fn write_gif<'f, W: Write>(
    size: (u32, u32),
    render: impl Fn(usize) -> Result<Cow<'f, Pixmap>> + Sync,
    timeline: &Timeline,
    background: Option<Rgba>,
    out: W,
) -> Result<()> {
    let (w, h) = size;
    let (gw, gh) = match (u16::try_from(w), u16::try_from(h)) {
        (Ok(gw), Ok(gh)) if w > 0 && h > 0 => (gw, gh),
        _ => {
            return Err(Error::internal(format!(
                "{w}×{h} frames exceed GIF's 65535 px limit"
            )))
        }
    };
    let tl = timeline.sanitized();
    let schedule = playback_schedule(&tl, GIF_MIN_DELAY);
    let bg = opaque_background(background);
    let (wu, hu) = (w as usize, h as usize);
    let rgb = |i: usize| -> Result<Vec<u8>> {
        let frame = render(i)?;
        if (frame.width(), frame.height()) != size {
            return Err(Error::internal(format!(
                "frame {i} is {}×{} but the animation is {w}×{h}",
                frame.width(),
                frame.height()
            )));
        }
        Ok(composite_rgb(&frame, bg))
    };

    // Two passes over the frames that are shown (yoyo shows most of them twice): colour
    // statistics, then indices. The first few frames are kept between the passes (all of a
    // short animation); the others are rendered again rather than kept.
    let used = shown_frames(&schedule);
    let kept = &used[..kept_frames(used.len(), size)];
    let per_frame = (PALETTE_SAMPLE / used.len()).max(1);
    let group = used.len().div_ceil(LOCAL_GROUPS).max(1);
    let per_frame_local = (LOCAL_SAMPLE / group).max(1);
    let mut stats: Vec<FrameColours> = Vec::with_capacity(used.len());
    let mut cache: HashMap<usize, Vec<u8>> = HashMap::with_capacity(kept.len());
    let chunk = chunk_len(4 * wu * hu);
    in_order(
        &used,
        chunk,
        |&i| {
            let rgb = rgb(i)?;
            let colours = FrameColours {
                distinct: frame_colours(&rgb, 256),
                sample: sample_rgba(&rgb, per_frame, i as u64),
                run_sample: sample_rgba(&rgb, per_frame_local, !(i as u64)),
            };
            Ok((i, colours, kept.contains(&i).then_some(rgb)))
        },
        |(i, c, rgb)| {
            stats.push(c);
            cache.extend(rgb.map(|rgb| (i, rgb)));
            Ok(())
        },
    )?;
    // The global table trains on one thread while the local tables' first tries train on the
    // others (they do not depend on it); an exact global table needs neither.
    let (global, first) = match Palette::exact(&stats) {
        Some(exact) => (exact, Vec::new()),
        None => rayon::join(
            || {
                let sample: Vec<u8> = stats.iter().flat_map(|s| &s.sample).copied().collect();
                Palette::trained(&sample, NEUQUANT_SAMPLEFAC)
            },
            || LocalTables::first_tries(&stats, group),
        ),
    };
    let locals = LocalTables::build(&global, &used, &stats, group, first);
    drop(stats);

    let err = |e: gif::EncodingError| Error::internal(format!("GIF encoding failed: {e}"));
    let mut enc = gif::Encoder::new(out, gw, gh, &global.colours).map_err(err)?;
    if tl.repeats() {
        enc.set_repeat(gif::Repeat::Infinite).map_err(err)?;
    }
    let shown: Vec<(usize, f64)> = schedule
        .iter()
        .map(|s| s.frame)
        .zip(delays_cs(&schedule, tl.frame_interval()))
        .collect();
    // Identical consecutive frames merge into one longer delay, so a piece is final only when
    // a different frame follows it; final pieces are encoded a chunk at a time.
    let mut writer = PieceWriter {
        last: None,
        ready: Vec::new(),
        global: &global,
        locals: &locals,
        size: (wu, hu),
    };
    let mut open: Option<Piece> = None;
    in_order(
        &shown,
        chunk,
        |&(i, delay)| {
            let local = locals.of(i);
            let mapped = match cache.get(&i) {
                Some(rgb) => Mapped::new(rgb, wu, &global, local),
                None => Mapped::new(&rgb(i)?, wu, &global, local),
            };
            Ok((mapped, delay))
        },
        |(mapped, delay)| {
            match &mut open {
                Some(p) if !(0..wu * hu).any(p.mapped.differs(&mapped, &global, &locals)) => {
                    p.delay += delay;
                }
                _ => {
                    if let Some(done) = open.replace(Piece { mapped, delay }) {
                        writer.ready.push(done);
                        if writer.ready.len() >= chunk {
                            writer.flush(&mut enc)?;
                        }
                    }
                }
            }
            Ok(())
        },
    )?;
    writer.ready.extend(open);
    writer.flush(&mut enc)?;
    enc.into_inner()
        .map_err(err)?
        .flush()
        .map_err(|e| Error::internal(format!("GIF encoding failed: {e}")))
}

/// At most this many frames are kept between the GIF encoder's two passes…
const KEPT_FRAMES: usize = 64;

/// …and at most this many bytes of them (composited RGB).
const KEPT_BYTES: usize = 64 << 20;

/// The frames a schedule shows, each once, in frame order.
fn shown_frames(schedule: &[Shown]) -> Vec<usize> {
    let used: BTreeSet<usize> = schedule.iter().map(|s| s.frame).collect();
    used.into_iter().collect()
}

/// How many of the `used` frames shown (the first ones) stay in memory between the two passes
/// at `size`: all of a default 60-frame animation at sizes up to about 600², so that it is
/// rendered once, and never more than [`KEPT_BYTES`], so that memory does not grow with the
/// frame count.
fn kept_frames(used: usize, size: (u32, u32)) -> usize {
    let bytes = (size.0 as usize * size.1 as usize * 3).max(1);
    used.min(KEPT_FRAMES).min(KEPT_BYTES / bytes)
}

/// How many frames [`write_gif`] renders for `timeline` at `size`: each frame shown in the
/// first pass, and in the second every frame shown (yoyo: most twice) but those kept.
pub(crate) fn gif_renders(timeline: &Timeline, size: (u32, u32)) -> usize {
    let schedule = playback_schedule(timeline, GIF_MIN_DELAY);
    let used = shown_frames(&schedule);
    let kept = &used[..kept_frames(used.len(), size)];
    let again = schedule.iter().filter(|s| !kept.contains(&s.frame)).count();
    used.len() + again
}

/// A frame shown for `delay` centiseconds.
struct Piece {
    mapped: Mapped,
    delay: f64,
}

/// Encodes final pieces a chunk at a time, each after the first storing only the rectangle
/// whose colours changed since the piece before.
struct PieceWriter<'a> {
    /// The last piece written (what the next one is compared with).
    last: Option<Mapped>,
    /// Final pieces not written yet, in order.
    ready: Vec<Piece>,
    global: &'a Palette,
    locals: &'a LocalTables,
    size: (usize, usize),
}

impl PieceWriter<'_> {
    /// LZW-encodes the ready pieces in parallel and writes them in order.
    fn flush<W: Write>(&mut self, enc: &mut gif::Encoder<W>) -> Result<()> {
        let (wu, hu) = self.size;
        let (global, locals) = (self.global, self.locals);
        let ready = &self.ready;
        let last = self.last.as_ref();
        let mut frames: Vec<gif::Frame<'static>> = ready
            .par_iter()
            .enumerate()
            .map(|(k, piece)| {
                let cur = &piece.mapped;
                let prev = if k == 0 {
                    last
                } else {
                    Some(&ready[k - 1].mapped)
                };
                let (x0, y0, x1, y1) = match prev {
                    None => (0, 0, wu, hu),
                    Some(prev) => changed_rect_by(wu, hu, prev.differs(cur, global, locals)),
                };
                let mut pixels = Vec::with_capacity((x1 - x0) * (y1 - y0));
                for y in y0..y1 {
                    pixels.extend_from_slice(&cur.indices[y * wu + x0..y * wu + x1]);
                }
                let mut f = gif::Frame {
                    delay: piece.delay.min(u16::MAX as f64) as u16,
                    dispose: gif::DisposalMethod::Keep,
                    left: x0 as u16,
                    top: y0 as u16,
                    width: (x1 - x0) as u16,
                    height: (y1 - y0) as u16,
                    buffer: pixels.into(),
                    palette: cur.local.map(|k| locals.tables[k].colours.clone()),
                    ..gif::Frame::default()
                };
                f.make_lzw_pre_encoded();
                f
            })
            .collect();
        let err = |e: gif::EncodingError| Error::internal(format!("GIF encoding failed: {e}"));
        for f in frames.iter_mut() {
            enc.write_lzw_pre_encoded_frame(f).map_err(err)?;
        }
        if let Some(p) = self.ready.pop() {
            self.last = Some(p.mapped);
        }
        self.ready.clear();
        Ok(())
    }
}

/// One frame as palette indices, with its local colour table when it has one.
struct Mapped {
    /// A palette index per pixel, row after row.
    indices: Vec<u8>,
    /// The frame's own table (an index into [`LocalTables::tables`]), when the global one is
    /// poor for it.
    local: Option<usize>,
}

impl Mapped {
    /// A frame's packed RGB pixels (`width` per row) dithered against its local table
    /// `local` (its index and the table), or else against the global one.
    fn new(rgb: &[u8], width: usize, global: &Palette, local: Option<(usize, &Palette)>) -> Mapped {
        Mapped {
            indices: local.map_or(global, |(_, t)| t).map(rgb, width),
            local: local.map(|(k, _)| k),
        }
    }

    /// Whether pixel `p` shows another colour in `other` than in `self`: their indices
    /// compared directly when both use one table, else the colours they stand for.
    fn differs<'a>(
        &'a self,
        other: &'a Mapped,
        global: &'a Palette,
        locals: &'a LocalTables,
    ) -> impl Fn(usize) -> bool + 'a {
        let one_table = self.local == other.local;
        move |p| {
            if one_table {
                self.indices[p] != other.indices[p]
            } else {
                self.colour(global, locals, p) != other.colour(global, locals, p)
            }
        }
    }

    /// The colour pixel `p` shows, as an index into the packed triples of its table.
    fn colour<'a>(&'a self, global: &'a Palette, locals: &'a LocalTables, p: usize) -> &'a [u8] {
        let table = self.local.map_or(global, |k| &locals.tables[k]);
        let i = 3 * self.indices[p] as usize;
        &table.colours[i..i + 3]
    }
}

/// The local colour tables of an animation, each shared by a group of consecutive frames.
///
/// Training a `NeuQuant` table is the costliest step of the encoder, and neighbouring frames
/// of a morph hold nearly the same colours, so the frames shown are split into at most
/// [`LOCAL_GROUPS`] runs of consecutive frames, each sharing one table, trained on samples of all of them. A group gets a table where the
/// global one is poor for its frames (a sampled mean squared error over [`POOR_GLOBAL`]) and
/// its own is much closer to their colours (under [`LOCAL_GAIN`] times the global table's
/// error): exactly their colours when they have at most 256, else a `NeuQuant` table. Before
/// that table is trained, a probe trained on a sixth of the sample ([`PROBE_SAMPLEFAC`]) must
/// come close enough ([`PROBE_REACH`]): where it does not (frames the global table serves
/// about as well as any table can), the full training is skipped. An exact global table (at most 256
/// colours in all) is never replaced.
struct LocalTables {
    /// The tables that were kept.
    tables: Vec<Palette>,
    /// For each frame that has a local table, its index in `tables`.
    of_frame: HashMap<usize, usize>,
}

impl LocalTables {
    /// Each group's first try: its frames' exact colours when they have at most 256 in all,
    /// else a probe, a table trained on a sixth of its sample ([`PROBE_SAMPLEFAC`]).
    /// `stats[k]` are the colours of the `k`-th frame shown and samples of its pixels.
    fn first_tries(stats: &[FrameColours], group: usize) -> Vec<Palette> {
        stats
            .par_chunks(group)
            .with_max_len(1)
            .map(|members| {
                Palette::exact(members)
                    .unwrap_or_else(|| Palette::trained(&group_sample(members), PROBE_SAMPLEFAC))
            })
            .collect()
    }

    /// The tables of the frames `used` (in frame order), `stats[k]` being the colours of frame
    /// `used[k]` and samples of its pixels, and `first` the groups' first tries
    /// ([`LocalTables::first_tries`]).
    fn build(
        global: &Palette,
        used: &[usize],
        stats: &[FrameColours],
        group: usize,
        first: Vec<Palette>,
    ) -> LocalTables {
        let mut out = LocalTables {
            tables: Vec::new(),
            of_frame: HashMap::new(),
        };
        if global.is_exact() {
            return out;
        }
        let built: Vec<Option<Palette>> = stats
            .par_chunks(group)
            .zip(first)
            .with_max_len(1)
            .map(|(members, first)| {
                let sample = group_sample(members);
                // Every fourth pixel of the sample judges the tables: plenty for a mean.
                let judge: Vec<u8> = sample
                    .chunks_exact(4)
                    .step_by(4)
                    .flatten()
                    .copied()
                    .collect();
                let poor = global.mean_error(&judge);
                if poor <= POOR_GLOBAL {
                    return None;
                }
                if first.is_exact() {
                    return Some(first);
                }
                if first.mean_error(&judge) >= PROBE_REACH * LOCAL_GAIN * poor {
                    return None;
                }
                let table = Palette::trained(&sample, NEUQUANT_SAMPLEFAC);
                (table.mean_error(&judge) < LOCAL_GAIN * poor).then_some(table)
            })
            .collect();
        for (frames, table) in used.chunks(group).zip(built) {
            if let Some(table) = table {
                let k = out.tables.len();
                out.tables.push(table);
                out.of_frame.extend(frames.iter().map(|&f| (f, k)));
            }
        }
        out
    }

    /// Frame `frame`'s local table and its index, if it has one.
    fn of(&self, frame: usize) -> Option<(usize, &Palette)> {
        self.of_frame.get(&frame).map(|&k| (k, &self.tables[k]))
    }
}

/// The run samples of a group of frames, one after another.
fn group_sample(members: &[FrameColours]) -> Vec<u8> {
    members
        .iter()
        .flat_map(|m| &m.run_sample)
        .copied()
        .collect()
}

/// The background as an opaque colour: white for `None`, a translucent one flattened onto white.
fn opaque_background(background: Option<Rgba>) -> [u8; 3] {
    let c = background.unwrap_or(Rgba {
        r: 255,
        g: 255,
        b: 255,
        a: 255,
    });
    let over_white = |v: u8| ((v as u32 * c.a as u32 + 255 * (255 - c.a as u32) + 127) / 255) as u8;
    [over_white(c.r), over_white(c.g), over_white(c.b)]
}

/// A premultiplied pixmap composited over an opaque colour, as packed RGB bytes.
fn composite_rgb(frame: &Pixmap, bg: [u8; 3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(frame.width() as usize * frame.height() as usize * 3);
    for p in frame.pixels() {
        let rest = 255 - p.alpha() as u32;
        let over = |c: u8, b: u8| (c as u32 + (b as u32 * rest + 127) / 255).min(255) as u8;
        out.extend_from_slice(&[
            over(p.red(), bg[0]),
            over(p.green(), bg[1]),
            over(p.blue(), bg[2]),
        ]);
    }
    out
}

/// The bounding rectangle `(x0, y0, x1, y1)` (exclusive ends) of the pixels of a `w × h` frame
/// that differ from the previous frame; the whole frame for the first one, one pixel for an
/// unchanged one.
pub(crate) fn changed_rect<T: PartialEq>(
    prev: Option<&[T]>,
    cur: &[T],
    w: usize,
    h: usize,
) -> (usize, usize, usize, usize) {
    match prev {
        None => (0, 0, w, h),
        Some(prev) => changed_rect_by(w, h, |p| prev[p] != cur[p]),
    }
}

/// The bounding rectangle `(x0, y0, x1, y1)` (exclusive ends) of the pixels `p = y · w + x` of
/// a `w × h` frame for which `differs(p)`; one pixel when there are none.
fn changed_rect_by(
    w: usize,
    h: usize,
    differs: impl Fn(usize) -> bool,
) -> (usize, usize, usize, usize) {
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    for y in 0..h {
        let d = |x: usize| differs(y * w + x);
        let Some(first) = (0..w).find(|&x| d(x)) else {
            continue;
        };
        let last = (first..w).rev().find(|&x| d(x)).unwrap_or(first);
        x0 = x0.min(first);
        x1 = x1.max(last + 1);
        y0 = y0.min(y);
        y1 = y + 1;
    }
    if x1 == 0 {
        (0, 0, 1, 1)
    } else {
        (x0, y0, x1, y1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::Playback;
    use tiny_skia::{Color, Paint, Rect, Transform};

    /// A `w×h` transparent pixmap with a `(r, g, b, a)` rectangle from x = `x0` to `x1`.
    fn frame(w: u32, h: u32, x0: f32, x1: f32, rgba: [u8; 4]) -> Pixmap {
        let mut p = Pixmap::new(w, h).unwrap();
        let mut paint = Paint::default();
        paint.set_color(Color::from_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]));
        paint.anti_alias = false;
        let r = Rect::from_ltrb(x0, 0.0, x1, h as f32).unwrap();
        p.fill_rect(r, &paint, Transform::identity(), None);
        p
    }

    /// `n` frames of a red bar sliding from the left edge to the right edge over a transparent
    /// background (antialiased, so that sub-pixel steps still change the frame).
    fn sliding(n: usize) -> Vec<Pixmap> {
        (0..n)
            .map(|i| {
                let x = 28.0 * i as f32 / (n - 1) as f32;
                let mut p = Pixmap::new(32, 8).unwrap();
                let mut paint = Paint::default();
                paint.set_color(Color::from_rgba8(200, 30, 40, 255));
                let r = Rect::from_ltrb(x, 0.0, x + 4.0, 8.0).unwrap();
                p.fill_rect(r, &paint, Transform::identity(), None);
                p
            })
            .collect()
    }

    struct Decoded {
        delays: Vec<u16>,
        /// The composed canvas after each frame, packed RGBA.
        canvases: Vec<Vec<u8>>,
        repeat: gif::Repeat,
        has_loop_extension: bool,
    }

    fn decode(bytes: &[u8]) -> Decoded {
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut d = opts.read_info(bytes).unwrap();
        let (w, h) = (d.width() as usize, d.height() as usize);
        let mut canvas = vec![0u8; w * h * 4];
        let (mut delays, mut canvases) = (vec![], vec![]);
        while let Some(f) = d.read_next_frame().unwrap() {
            delays.push(f.delay);
            for y in 0..f.height as usize {
                for x in 0..f.width as usize {
                    let src = 4 * (y * f.width as usize + x);
                    let dst = 4 * ((y + f.top as usize) * w + x + f.left as usize);
                    canvas[dst..dst + 4].copy_from_slice(&f.buffer[src..src + 4]);
                }
            }
            canvases.push(canvas.clone());
        }
        Decoded {
            delays,
            canvases,
            repeat: d.repeat(),
            has_loop_extension: bytes.windows(11).any(|w| w == b"NETSCAPE2.0"),
        }
    }

    fn timeline(frames: usize, duration: f64, playback: Playback) -> Timeline {
        Timeline {
            frames,
            duration,
            playback,
            ..Timeline::default()
        }
    }

    #[test]
    fn frame_counts_delays_and_looping_follow_the_playback() {
        for (playback, shown) in [
            (Playback::Once, 6),
            (Playback::Loop, 6),
            (Playback::Yoyo, 10),
        ] {
            let tl = timeline(6, 1.0, playback);
            let d = decode(&encode_gif(&sliding(6), &tl, None).unwrap());
            assert_eq!(d.delays.len(), shown, "{playback:?}");
            assert!(d.delays.iter().all(|&c| c >= 2), "{:?}", d.delays);
            // One interval (20 cs) per shown frame; the sum is the period (+1 interval unless yoyo).
            let total: u32 = d.delays.iter().map(|&c| c as u32).sum();
            let expected = (tl.sequence().len() as f64 * tl.frame_interval() * 100.0).round();
            assert!(
                (total as f64 - expected).abs() <= 1.0,
                "{total} vs {expected}"
            );
            assert_eq!(d.has_loop_extension, tl.repeats(), "{playback:?}");
            if tl.repeats() {
                assert_eq!(d.repeat, gif::Repeat::Infinite);
            }
        }
    }

    #[test]
    fn short_intervals_skip_frames_but_keep_the_period_and_the_ends() {
        // 101 frames over 1 s: 10 ms apart, so every other frame is dropped.
        let n = 101;
        let tl = timeline(n, 1.0, Playback::Yoyo);
        let sched = playback_schedule(&tl, GIF_MIN_DELAY);
        assert_eq!(sched.first().unwrap().frame, 0);
        assert!(sched.iter().any(|s| s.frame == n - 1));
        assert!(sched.iter().all(|s| s.intervals >= 2));
        let span: usize = sched.iter().map(|s| s.intervals).sum();
        assert_eq!(span, tl.sequence().len());

        let d = decode(&encode_gif(&sliding(n), &tl, None).unwrap());
        assert!(d.delays.iter().all(|&c| c >= 2), "{:?}", d.delays);
        let total: u32 = d.delays.iter().map(|&c| c as u32).sum();
        assert_eq!(total, 200);
        assert!(d.delays.len() <= sched.len());
        // Interval 7 ms: stride of 3 intervals (21 ms), the period stays 0.7 s forwards.
        let tl = timeline(101, 0.7, Playback::Once);
        let d = decode(&encode_gif(&sliding(101), &tl, None).unwrap());
        let total: u32 = d.delays.iter().map(|&c| c as u32).sum();
        assert!((total as i32 - 71).abs() <= 1, "{total}");
        assert!(d.delays.iter().all(|&c| c >= 2), "{:?}", d.delays);
        // The last frame shown is the target (the bar at the right edge).
        let last = d.canvases.last().unwrap();
        let target = composite_rgb(&sliding(n)[n - 1], [255; 3]);
        let rgb: Vec<u8> = last
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        assert_eq!(rgb, target);
    }

    #[test]
    fn flat_colours_and_transparency_over_the_background() {
        let tl = timeline(2, 0.5, Playback::Once);
        let frames = vec![
            frame(16, 4, 0.0, 8.0, [10, 120, 230, 255]),
            frame(16, 4, 0.0, 8.0, [10, 120, 230, 128]),
        ];
        let bg = Rgba {
            r: 0,
            g: 0,
            b: 0,
            a: 255,
        };
        for (background, b) in [(None, [255u8; 3]), (Some(bg), [0u8; 3])] {
            let d = decode(&encode_gif(&frames, &tl, background).unwrap());
            let px = |c: &Vec<u8>, x: usize| [c[4 * x], c[4 * x + 1], c[4 * x + 2], c[4 * x + 3]];
            assert_eq!(px(&d.canvases[0], 2), [10, 120, 230, 255]);
            // Transparent pixels show the background, fully opaque.
            assert_eq!(px(&d.canvases[0], 12), [b[0], b[1], b[2], 255]);
            // Half-transparent blue over the background.
            let got = px(&d.canvases[1], 2);
            for (ch, c) in [10.0, 120.0, 230.0].into_iter().enumerate() {
                let want = c * 128.0 / 255.0 + b[ch] as f64 * 127.0 / 255.0;
                assert!((got[ch] as f64 - want).abs() <= 2.0, "{got:?} ch {ch}");
            }
        }
    }

    #[test]
    fn many_colours_are_dithered_close_to_the_frames() {
        // A horizontal gradient with more than 256 colours, moving by one pixel per frame.
        let n = 4;
        let frames: Vec<Pixmap> = (0..n)
            .map(|k| {
                let mut p = Pixmap::new(300, 4).unwrap();
                for (i, px) in p.pixels_mut().iter_mut().enumerate() {
                    let x = ((i % 300) + k) as u32;
                    let c = tiny_skia::ColorU8::from_rgba(
                        (x * 255 / 303) as u8,
                        (255 - x * 255 / 303) as u8,
                        ((x * 7) % 256) as u8,
                        255,
                    );
                    *px = c.premultiply();
                }
                p
            })
            .collect();
        let tl = timeline(n, 1.0, Playback::Loop);
        let bytes = encode_gif(&frames, &tl, None).unwrap();
        assert_eq!(
            bytes,
            encode_gif(&frames, &tl, None).unwrap(),
            "deterministic"
        );
        let d = decode(&bytes);
        assert_eq!(d.canvases.len(), n);
        for (k, canvas) in d.canvases.iter().enumerate() {
            let src = straight(&frames[k]);
            let errors: Vec<i32> = canvas
                .chunks_exact(4)
                .zip(src.chunks_exact(4))
                .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as i32 - b[c] as i32).abs()))
                .collect();
            let worst = errors.iter().copied().max().unwrap();
            let mean = errors.iter().sum::<i32>() as f64 / errors.len() as f64;
            println!("frame {k}: mean channel error {mean:.2}, worst {worst}");
            assert!(
                mean <= 6.0 && worst <= 64,
                "frame {k}: mean {mean}, worst {worst}"
            );
        }
    }

    /// `n` opaque frames of `size` whose pixel at `(x, y)` (each 0–1 across the frame) has the
    /// colour `colour(x, y, s)` (RGB, 0–255) in frame `k`, `s = k / (n − 1)`.
    fn gradient_frames(
        (w, h): (u32, u32),
        n: usize,
        colour: impl Fn(f64, f64, f64) -> [f64; 3],
    ) -> Vec<Pixmap> {
        (0..n)
            .map(|k| {
                let mut p = Pixmap::new(w, h).unwrap();
                let s = k as f64 / (n - 1) as f64;
                for (i, px) in p.pixels_mut().iter_mut().enumerate() {
                    let x = (i as u32 % w) as f64 / (w - 1) as f64;
                    let y = (i as u32 / w) as f64 / (h - 1) as f64;
                    let c = colour(x, y, s).map(|v| v.round().clamp(0.0, 255.0) as u8);
                    *px = tiny_skia::ColorU8::from_rgba(c[0], c[1], c[2], 255).premultiply();
                }
                p
            })
            .collect()
    }

    /// The case: a blue → green gradient whose colours drift from frame to frame, with
    /// more than 256 colours in every frame. Dithered, the GIF reproduces it on average (no
    /// bands) and within a small per-pixel error.
    #[test]
    fn a_drifting_blue_green_gradient_does_not_band() {
        let n = 12;
        let frames = gradient_frames((480, 32), n, |x, y, shift| {
            let from = [29.0, 78.0 - 40.0 * shift, 216.0 - 30.0 * y];
            let to = [22.0 + 50.0 * shift, 163.0 + 60.0 * shift, 74.0];
            [0, 1, 2].map(|j| from[j] + (to[j] - from[j]) * x)
        });
        let tl = timeline(n, 1.0, Playback::Once);
        let bytes = encode_gif(&frames, &tl, None).unwrap();
        let f = gif_fidelity(&bytes, &frames, &tl, None).unwrap();
        println!("{f:?}, {} bytes", bytes.len());
        assert_eq!(f.frames, n);
        assert!(f.mean_smoothed_delta_e < 0.002, "{f:?}");
        assert!(f.mean_delta_e < 0.006, "{f:?}");
    }

    /// Local colour tables, one per run of consecutive frames: a gradient that drifts over 60
    /// frames gets local tables (the global one is spread over every frame's colours), at most
    /// `LOCAL_GROUPS` of them, each shared by consecutive frames.
    #[test]
    fn runs_of_frames_share_local_tables() {
        let n = 60;
        let frames = gradient_frames((240, 16), n, |x, _, s| {
            [200.0 * s + 30.0 * x, 40.0 + 180.0 * x, 220.0 - 190.0 * s]
        });
        let tl = timeline(n, 2.0, Playback::Once);
        let bytes = encode_gif(&frames, &tl, None).unwrap();
        let mut d = gif::DecodeOptions::new().read_info(&bytes[..]).unwrap();
        let mut tables: Vec<Option<Vec<u8>>> = Vec::new();
        while let Some(f) = d.read_next_frame().unwrap() {
            tables.push(f.palette.clone());
        }
        assert_eq!(tables.len(), n);
        let locals = tables.iter().filter(|t| t.is_some()).count();
        assert!(locals > n / 2, "{locals} of {n} frames have a local table");
        // Count the runs of equal tables: consecutive frames of a group share theirs.
        let runs = 1 + tables.windows(2).filter(|p| p[0] != p[1]).count();
        assert!(runs <= LOCAL_GROUPS + 1, "{runs} runs of tables");
        let f = gif_fidelity(&bytes, &frames, &tl, None).unwrap();
        assert!(f.mean_smoothed_delta_e < 0.002, "{f:?}");
    }

    fn straight(p: &Pixmap) -> Vec<u8> {
        crate::render::straight_rgba(p)
    }

    #[test]
    fn frames_beyond_those_kept_between_the_passes_are_rendered_again_alike() {
        // More frames shown than are kept between the passes: the later ones are rendered a
        // second time, and every frame still decodes to itself (two colours: exact palette).
        let n = KEPT_FRAMES + 40;
        let frames: Vec<Pixmap> = (0..n)
            .map(|k| {
                frame(
                    40,
                    4,
                    (k % 30) as f32,
                    (k % 30 + 6) as f32,
                    [0, 90, 200, 255],
                )
            })
            .collect();
        let tl = timeline(n, 10.0, Playback::Once);
        assert_eq!(gif_renders(&tl, (40, 4)), n + n - KEPT_FRAMES);
        let renders = std::sync::atomic::AtomicUsize::new(0);
        let mut bytes = Vec::new();
        let render = |i: usize| {
            renders.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            Ok(Cow::Borrowed(&frames[i]))
        };
        write_gif((40, 4), render, &tl, None, &mut bytes).unwrap();
        assert_eq!(renders.into_inner(), gif_renders(&tl, (40, 4)));
        assert_eq!(bytes, encode_gif(&frames, &tl, None).unwrap());
        let d = decode(&bytes);
        assert_eq!(d.canvases.len(), n);
        for (k, canvas) in d.canvases.iter().enumerate() {
            let want = composite_rgb(&frames[k], [255; 3]);
            let rgb: Vec<u8> = canvas
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            assert_eq!(rgb, want, "frame {k}");
        }
    }

    #[test]
    fn identical_frames_merge_and_bad_input_is_an_error() {
        let tl = timeline(3, 0.6, Playback::Loop);
        let same = vec![frame(8, 8, 0.0, 4.0, [0, 0, 0, 255]); 3];
        let d = decode(&encode_gif(&same, &tl, None).unwrap());
        assert_eq!(d.delays, vec![90], "three intervals of 30 cs in one");

        assert!(encode_gif(&[], &tl, None).is_err());
        assert!(encode_gif(&same[..2], &tl, None).is_err());
        let mixed = vec![same[0].clone(), same[1].clone(), Pixmap::new(9, 8).unwrap()];
        assert!(encode_gif(&mixed, &tl, None).is_err());
    }
}
