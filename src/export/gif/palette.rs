//! Colour tables: every colour exactly when there are at most 256, else a `NeuQuant` palette
//! trained on a sample of the pixels (of all frames for the global table, of a run of frames
//! for a local one), dithered against (see [`super::dither`]).

use std::collections::BTreeSet;

use rustc_hash::{FxHashMap, FxHashSet};

use super::dither::Ditherer;

/// `NeuQuant`'s sampling factor: 1 is best and slowest, 10 the usual compromise.
pub(super) const NEUQUANT_SAMPLEFAC: i32 = 1;

/// What the palette needs to know of one frame.
pub(super) struct FrameColours {
    /// Its distinct colours, `None` when there are more than 256.
    pub(super) distinct: Option<FxHashSet<[u8; 3]>>,
    /// A sample of its pixels as opaque RGBA, for the global table.
    pub(super) sample: Vec<u8>,
    /// Another, for the local table of its run of frames (see `LocalTables`).
    pub(super) run_sample: Vec<u8>,
}

/// A colour table (the animation's global one, or a frame's local one) and how to find a
/// colour's index in it.
pub(super) struct Palette {
    /// Packed RGB triples, at most 256.
    pub(super) colours: Vec<u8>,
    /// How pixels map to indices.
    lookup: Lookup,
}

/// How a colour finds its index.
enum Lookup {
    /// Every colour of the animation is in the table (at most 256 in all).
    Exact(FxHashMap<[u8; 3], u8>),
    /// A `NeuQuant` palette trained on a sample; pixels are dithered against it.
    Dithered(Ditherer),
}

impl Palette {
    /// The colours of `stats` as an exact table, when there are at most 256 in all.
    pub(super) fn exact(stats: &[FrameColours]) -> Option<Palette> {
        let mut all = BTreeSet::new();
        for s in stats {
            all.extend(s.distinct.as_ref()?.iter().copied());
            if all.len() > 256 {
                return None;
            }
        }
        let lookup = all.iter().enumerate().map(|(i, &c)| (c, i as u8)).collect();
        Some(Palette {
            colours: all.into_iter().flatten().collect(),
            lookup: Lookup::Exact(lookup),
        })
    }

    /// A `NeuQuant` palette trained on `sample` (opaque RGBA) with sampling factor
    /// `samplefac` (1 learns from every pixel of the sample; `k` from one in `k`, faster and
    /// coarser).
    pub(super) fn trained(sample: &[u8], samplefac: i32) -> Palette {
        let nq = color_quant::NeuQuant::new(samplefac, 256, sample);
        let colours = nq.color_map_rgb();
        Palette {
            lookup: Lookup::Dithered(Ditherer::new(&colours)),
            colours,
        }
    }

    /// Whether the table holds every colour it was built from (no quantization, no dithering).
    pub(super) fn is_exact(&self) -> bool {
        matches!(self.lookup, Lookup::Exact(_))
    }

    /// The mean squared RGB distance (channels 0–255) from the pixels of `sample` (opaque
    /// RGBA) to their nearest entries; 0 for an exact table, which holds the colours of the
    /// frames it was built from.
    pub(super) fn mean_error(&self, sample: &[u8]) -> f64 {
        let Lookup::Dithered(d) = &self.lookup else {
            return 0.0;
        };
        let n = (sample.len() / 4).max(1) as f64;
        sample
            .chunks_exact(4)
            .map(|c| d.nearest_distance([c[0], c[1], c[2]].map(f32::from)) as f64)
            .sum::<f64>()
            / n
    }

    /// One frame's packed RGB pixels (`width` per row) as palette indices.
    pub(super) fn map(&self, rgb: &[u8], width: usize) -> Vec<u8> {
        match &self.lookup {
            Lookup::Exact(table) => rgb
                .chunks_exact(3)
                .map(|c| table.get(&[c[0], c[1], c[2]]).copied().unwrap_or(0))
                .collect(),
            Lookup::Dithered(d) => d.map(rgb, width),
        }
    }
}

/// The distinct colours of one frame's packed RGB pixels, or `None` when there are more than
/// `limit`.
pub(super) fn frame_colours(rgb: &[u8], limit: usize) -> Option<FxHashSet<[u8; 3]>> {
    let mut set = FxHashSet::default();
    for c in rgb.chunks_exact(3) {
        if set.insert([c[0], c[1], c[2]]) && set.len() > limit {
            return None;
        }
    }
    Some(set)
}

/// About `max` of one frame's pixels as opaque RGBA, spread evenly over it with a jitter
/// (deterministic, from `seed`) so that the sample does not line up with the image columns.
pub(super) fn sample_rgba(rgb: &[u8], max: usize, seed: u64) -> Vec<u8> {
    let len = rgb.len() / 3;
    let stride = len.div_ceil(max.max(1)).max(1);
    let mut out = Vec::with_capacity(4 * len.div_ceil(stride));
    let mut hash: u64 = 0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xD1B5_4A32_D192_ED03);
    let mut i = 0;
    while i < len {
        out.extend_from_slice(&[rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], 255]);
        // xorshift64 for the jitter within the next stride.
        hash ^= hash << 13;
        hash ^= hash >> 7;
        hash ^= hash << 17;
        i = (i / stride + 1) * stride + (hash % stride as u64) as usize;
    }
    out
}
