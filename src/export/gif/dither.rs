//! Ordered dithering against an arbitrary palette (Thomas Knoll's pattern dithering), for the
//! GIF's frames when the animation has more colours than its palette.
//!
//! For a colour `c` the ditherer chooses [`CANDIDATES`] palette entries one after another,
//! each the nearest to `c` plus the error the entries chosen so far left (`c` minus their
//! colours), so that together they average to `c`; sorted by lightness, the entry a pixel
//! shows is the one its place in an 8 × 8 Bayer matrix picks. Why this and not error diffusion
//! (Floyd–Steinberg):
//!
//! - **A pixel's index depends only on its own colour and position.** A part of the picture
//!   that does not change between frames keeps exactly its indices, so it neither crawls nor
//!   shimmers, and the encoder can still store only the rectangle that changed. Error diffusion
//!   carries each pixel's error to its neighbours, so one changed pixel changes the pattern
//!   downstream of it and the dots crawl over still areas from frame to frame.
//! - **Colours in the palette stay flat.** A colour the palette holds has no error: all
//!   candidates are that entry, so flat fills and the background are not dotted.
//! - Deterministic, and parallel over frames and pixels.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use rustc_hash::FxHashMap;

/// Palette entries mixed per colour (each shows in `64 / CANDIDATES` cells of the 8 × 8
/// matrix): 16 mixes a gradient in steps of 1/16 of the palette's spacing.
pub(super) const CANDIDATES: usize = 16;

/// How much of the error left so far the next candidate corrects (1 would aim the average at
/// the colour exactly; a little less keeps the pattern from spreading over far entries).
const ERROR_GAIN: f32 = 0.85;

/// The 8 × 8 Bayer matrix: each cell's rank among the 64, arranged so that every prefix of the
/// ranks is spread as evenly as possible.
const BAYER: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];

/// Cells per channel of the grid that speeds up the nearest-entry search.
const GRID: usize = 16;
/// Width of a grid cell in channel levels.
const CELL: f32 = 256.0 / GRID as f32;

/// A palette with a fast nearest-entry search (squared distance in RGB): each cell of a
/// 16³ grid over the RGB cube lists the entries that can be nearest to some colour in it.
pub(super) struct Ditherer {
    /// A number no other ditherer of this process has: the key of the candidate cache.
    id: u64,
    /// The palette's colours.
    colours: Vec<[f32; 3]>,
    /// The lightness order of the entries, to sort candidates by.
    rank: Vec<u16>,
    /// For each cell, the range of `lists` (and of `list_colours`) holding its entries.
    cells: Vec<(u32, u32)>,
    /// Entry indices, cell after cell.
    lists: Vec<u8>,
    /// The colours of the entries in `lists`, channel by channel, so that a cell's search
    /// reads three contiguous runs instead of looking each entry up.
    list_colours: [Vec<f32>; 3],
}

impl Ditherer {
    /// Prepares the search for `palette` (packed RGB triples, at most 256).
    pub(super) fn new(palette: &[u8]) -> Ditherer {
        let colours: Vec<[f32; 3]> = palette
            .chunks_exact(3)
            .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
            .collect();
        let mut order: Vec<usize> = (0..colours.len()).collect();
        let luma = |c: &[f32; 3]| 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
        order.sort_by(|&a, &b| {
            luma(&colours[a])
                .total_cmp(&luma(&colours[b]))
                .then(a.cmp(&b))
        });
        let mut rank = vec![0u16; colours.len()];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r as u16;
        }
        let (mut cells, mut lists) = (Vec::with_capacity(GRID.pow(3)), Vec::new());
        for cell in 0..GRID.pow(3) {
            let lo =
                [cell / (GRID * GRID), cell / GRID % GRID, cell % GRID].map(|k| k as f32 * CELL);
            // An entry can be nearest to a point of the box only if its least distance to the
            // box is at most the smallest greatest distance of any entry to the box.
            let (near, far): (Vec<f32>, Vec<f32>) = colours
                .iter()
                .map(|c| {
                    (0..3).fold((0.0, 0.0), |(n, f), k| {
                        let (a, b) = (lo[k], lo[k] + CELL);
                        let d = (a - c[k]).max(c[k] - b).max(0.0);
                        let e = (c[k] - a).abs().max((c[k] - b).abs());
                        (n + d * d, f + e * e)
                    })
                })
                .unzip();
            let bound = far.iter().copied().fold(f32::INFINITY, f32::min);
            let start = lists.len() as u32;
            lists.extend(
                (0..colours.len())
                    .filter(|&i| near[i] <= bound)
                    .map(|i| i as u8),
            );
            cells.push((start, lists.len() as u32));
        }
        let list_colours =
            [0, 1, 2].map(|k| lists.iter().map(|&i| colours[i as usize][k]).collect());
        Ditherer {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            colours,
            rank,
            cells,
            lists,
            list_colours,
        }
    }

    /// The entry nearest to `c` clamped to the RGB cube (the lowest index among equals).
    fn nearest(&self, c: [f32; 3]) -> u8 {
        self.search(c).1
    }

    /// The squared RGB distance from `c` to its nearest entry.
    pub(super) fn nearest_distance(&self, c: [f32; 3]) -> f32 {
        self.search(c).0
    }

    /// The nearest entry to `c` and its squared distance.
    fn search(&self, c: [f32; 3]) -> (f32, u8) {
        let c = c.map(|v| v.clamp(0.0, 255.0));
        let k = c.map(|v| ((v / CELL) as usize).min(GRID - 1));
        let (a, b) = self.cells[(k[0] * GRID + k[1]) * GRID + k[2]];
        let range = a as usize..b as usize;
        let [r, g, bl] = &self.list_colours;
        let (r, g, bl) = (&r[range.clone()], &g[range.clone()], &bl[range.clone()]);
        let (mut best, mut at) = (f32::INFINITY, 0);
        for k in 0..r.len() {
            let (dr, dg, db) = (r[k] - c[0], g[k] - c[1], bl[k] - c[2]);
            let d = dr * dr + dg * dg + db * db;
            if d < best {
                (best, at) = (d, k);
            }
        }
        match self.lists.get(range.start + at) {
            Some(&i) if best.is_finite() => (best, i),
            _ => (f32::INFINITY, 0),
        }
    }

    /// The candidates of colour `c`, sorted by lightness (see the module docs).
    fn candidates(&self, c: [u8; 3]) -> [u8; CANDIDATES] {
        let c = c.map(|v| v as f32);
        let mut err = [0.0f32; 3];
        let mut out = [0u8; CANDIDATES];
        for slot in out.iter_mut() {
            let aim = [0, 1, 2].map(|k| c[k] + ERROR_GAIN * err[k]);
            *slot = self.nearest(aim);
            let p = self.colours[*slot as usize];
            (0..3).for_each(|k| err[k] += c[k] - p[k]);
        }
        out.sort_by_key(|&i| self.rank[i as usize]);
        out
    }

    /// One frame's packed RGB pixels (`width` per row) as dithered palette indices.
    ///
    /// A colour's candidates depend only on the colour and the palette, and neighbouring
    /// frames of a morph (dithered one after another on a thread, often against the same
    /// palette) share most of their colours, so each thread keeps the candidates it found for
    /// the last palette it dithered against ([`CACHE`]); the indices are the same with or
    /// without it.
    pub(super) fn map(&self, rgb: &[u8], width: usize) -> Vec<u8> {
        CACHE.with_borrow_mut(|(id, seen)| {
            if *id != self.id || seen.len() > CACHE_LIMIT {
                seen.clear();
                *id = self.id;
            }
            let mut last: Option<([u8; 3], [u8; CANDIDATES])> = None;
            rgb.chunks_exact(3)
                .enumerate()
                .map(|(i, c)| {
                    let c = [c[0], c[1], c[2]];
                    let cand = match last {
                        Some((l, cand)) if l == c => cand,
                        _ => {
                            let cand = *seen.entry(c).or_insert_with(|| self.candidates(c));
                            last = Some((c, cand));
                            cand
                        }
                    };
                    let (x, y) = (i % width, i / width);
                    cand[BAYER[y % 8][x % 8] as usize * CANDIDATES / 64]
                })
                .collect()
        })
    }
}

/// The source of [`Ditherer::id`].
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// At most this many colours' candidates are cached per thread: the map then holds 2²⁰
/// buckets of 20 bytes, 20 MiB, which a thread keeps until it dithers again (a run of six
/// 512² picture frames has a few hundred thousand colours).
const CACHE_LIMIT: usize = 1 << 19;

/// The candidates found so far for colours dithered against one palette.
type Candidates = FxHashMap<[u8; 3], [u8; CANDIDATES]>;

thread_local! {
    /// Per thread: the id of the palette last dithered against, and the candidates found for
    /// it so far.
    static CACHE: RefCell<(u64, Candidates)> = RefCell::new((u64::MAX, Candidates::default()));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grey ramp palette: 0, 17, 34, …, 255 (16 greys).
    fn greys() -> Vec<u8> {
        (0..16u8).flat_map(|k| [k * 17; 3]).collect()
    }

    #[test]
    fn the_grid_search_finds_the_nearest_entry() {
        let mut palette = greys();
        palette.extend_from_slice(&[255, 0, 0, 0, 200, 40, 30, 60, 220]);
        let d = Ditherer::new(&palette);
        let mut seed = 7u32;
        for _ in 0..2000 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let c = [seed >> 24, (seed >> 16) & 255, (seed >> 8) & 255].map(|v| v as f32);
            let brute = (0..d.colours.len())
                .min_by(|&a, &b| {
                    let dist = |i: usize| (0..3).map(|k| (d.colours[i][k] - c[k]).powi(2)).sum();
                    f32::total_cmp(&dist(a), &dist(b))
                })
                .unwrap();
            let (got, want) = (d.nearest(c) as usize, brute);
            let dist = |i: usize| {
                (0..3)
                    .map(|k| (d.colours[i][k] - c[k]).powi(2))
                    .sum::<f32>()
            };
            assert_eq!(dist(got), dist(want), "{c:?}");
        }
    }

    #[test]
    fn palette_colours_stay_flat_and_others_mix_to_their_average() {
        let d = Ditherer::new(&greys());
        let (w, h) = (16, 16);
        let flat = vec![34u8; 3 * w * h];
        assert!(
            d.map(&flat, w).iter().all(|&i| i == 2),
            "a palette grey stays flat"
        );
        // 40 lies between the entries 34 and 51: dots of both, averaging close to 40.
        let between = vec![40u8; 3 * w * h];
        let idx = d.map(&between, w);
        assert!(idx.iter().all(|&i| i == 2 || i == 3), "{idx:?}");
        let mean = idx.iter().map(|&i| i as f64 * 17.0).sum::<f64>() / idx.len() as f64;
        assert!((mean - 40.0).abs() < 1.5, "mean {mean}");
        // The same colour at the same place gets the same index: still areas stay still.
        assert_eq!(idx, d.map(&between, w));
    }

    #[test]
    fn cached_candidates_belong_to_their_palette() {
        // A gradient dithered against two palettes in turn on one thread (the cache then holds
        // the other palette's candidates) gives what each gives on a fresh thread.
        let (w, h) = (64, 8);
        let rgb: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let x = (i % w) as u8;
                [x * 3, 255 - x * 2, 40 + x]
            })
            .collect();
        let mut tinted = greys();
        tinted
            .iter_mut()
            .step_by(3)
            .for_each(|r| *r = r.saturating_add(9));
        let (greys, tints) = (Ditherer::new(&greys()), Ditherer::new(&tinted));
        let fresh =
            |d: &Ditherer| std::thread::scope(|s| s.spawn(|| d.map(&rgb, w)).join().unwrap());
        let (want_greys, want_tints) = (fresh(&greys), fresh(&tints));
        assert_ne!(want_greys, want_tints, "the palettes dither differently");
        for _ in 0..2 {
            assert_eq!(greys.map(&rgb, w), want_greys);
            assert_eq!(tints.map(&rgb, w), want_tints);
        }
    }
}
