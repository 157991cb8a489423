//! Drawing a warped raster image into pixels: every triangle of its texture grid
//! ([`crate::artwork::ImageGrid`]) filled with the image under that triangle's affine map,
//! sampled bilinearly (nearest for `image-rendering: pixelated`) on premultiplied RGBA.
//!
//! The triangles are rasterized here rather than by one tiny-skia `fill_path` each: a grid has
//! up to 4608 of them, and the per-call set-up of a shader pipeline cost more than the pixels.
//! Coverage is decided at pixel centres in exact integer arithmetic (corners snapped to 1/256
//! pixel) with a top-left rule that gives a pixel on an edge shared by two triangles to
//! exactly one of them ([`covered_runs`]), so the triangles tile the image with no crack and
//! no pixel drawn twice: a solid texture stays solid. Each row's run of pixels then steps
//! through the texture in fixed point ([`Sampler::run`]). The image's own edge is
//! antialiased instead: the grid is drawn with its outer vertices pushed out by
//! [`BORDER_DILATION`] pixels (the texture's edge texels extended), then composited through an
//! antialiased mask of the undilated outline.

use crate::artwork::{ImageGrid, ImageItem, Texels};
use crate::geometry::Point;
use kurbo::Affine;
use tiny_skia::{FillRule, Mask, PathBuilder, Pixmap, Transform};

/// How far, in output pixels, the image's outer edge is pushed out before the antialiased
/// outline mask cuts it back.
const BORDER_DILATION: f64 = 1.5;

/// The image's texels decoded (premultiplied), once per image: rendered by resvg at its natural
/// size with nearest-neighbour sampling, which reproduces every pixel exactly and decodes every
/// format usvg accepts (PNG, JPEG, GIF, WebP). `None` when it cannot be decoded.
pub(crate) fn decoded(img: &ImageItem) -> Option<std::sync::Arc<Texels>> {
    img.pixels.get_or_decode(|| {
        let (w, h) = image_size(&img.data)?;
        let svg = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" \
             width=\"{w}\" height=\"{h}\"><image width=\"{w}\" height=\"{h}\" \
             preserveAspectRatio=\"none\" image-rendering=\"optimizeSpeed\" \
             xlink:href=\"data:{};base64,{}\"/></svg>",
            img.mime,
            crate::base64::encode(&img.data)
        );
        let opts = crate::input::usvg_options(
            "<image>",
            None,
            &crate::input::InputPolicy::default(),
        );
        let tree = usvg::Tree::from_str(&svg, &opts).ok()?;
        let mut pixmap = Pixmap::new(w, h)?;
        resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
        Some(Texels::from_pixmap(&pixmap))
    })
}

/// The natural pixel size of an encoded image, from its header.
fn image_size(data: &[u8]) -> Option<(u32, u32)> {
    let s = imagesize::blob_size(data).ok()?;
    let (w, h) = (u32::try_from(s.width).ok()?, u32::try_from(s.height).ok()?);
    (w > 0 && h > 0).then_some((w, h))
}

/// Draws `img`, warped by `grid`, source-over onto `pixmap`; `to_px` maps root user space to
/// the pixmap's pixels. `onto_blank` says that `pixmap` is still fully transparent (the image
/// is the first thing drawn on it, as when a picture is the whole drawing): the triangles
/// then go straight into it and only the pixels along the outline are scaled by their
/// coverage, instead of a layer composited through the mask. An image that cannot be decoded
/// is not drawn (a `log::warn!`).
pub(crate) fn draw_image(
    pixmap: &mut Pixmap,
    img: &ImageItem,
    grid: &ImageGrid,
    to_px: Affine,
    onto_blank: bool,
) {
    let Some(texture) = decoded(img) else {
        log::warn!("image '{}': cannot be decoded; not drawn", img.id);
        return;
    };
    let (w, h) = (pixmap.width(), pixmap.height());
    let mut layer = if onto_blank {
        None
    } else {
        match Pixmap::new(w, h) {
            Some(l) => Some(l),
            None => return,
        }
    };
    let placed: Vec<Point> = grid
        .points
        .iter()
        .map(|p| {
            let q = to_px * kurbo::Point::new(p.x, p.y);
            Point::new(q.x, q.y)
        })
        .collect();
    if placed.iter().any(|p| !p.is_finite()) {
        return;
    }
    let border = grid.border();
    let filled = dilated(&placed, &border);
    // Image pixels → texels of the decoded image (its natural size may differ from the size
    // the SVG gives it).
    let to_texel = Affine::scale_non_uniform(
        texture.width as f64 / img.width,
        texture.height as f64 / img.height,
    );
    let sampler = Sampler {
        texels: &texture.lanes,
        width: texture.width as i32,
        height: texture.height as i32,
        nearest: img.pixelated,
    };
    let mut target = Target {
        data: match &mut layer {
            Some(l) => l.data_mut(),
            None => pixmap.data_mut(),
        },
        width: w as i64,
        height: h as i64,
    };
    for piece in grid.pieces(img) {
        // Output pixels → texels, from the piece's own (undilated) map.
        let Some(back) = piece.transform().map(|m| to_px * m).and_then(invert) else {
            continue;
        };
        let tri = piece.vertices.map(|k| filled[k]);
        fill_triangle(&mut target, tri, to_texel * back, &sampler);
    }
    // The antialiased outline of the undilated grid.
    let mut outline = PathBuilder::new();
    for (n, &k) in border.iter().enumerate() {
        let p = placed[k];
        if n == 0 {
            outline.move_to(p.x as f32, p.y as f32);
        } else {
            outline.line_to(p.x as f32, p.y as f32);
        }
    }
    outline.close();
    let (Some(outline), Some(mut mask)) = (outline.finish(), Mask::new(w, h)) else {
        return;
    };
    mask.fill_path(&outline, FillRule::Winding, true, Transform::identity());
    match &layer {
        Some(layer) => composite_masked(pixmap.data_mut(), layer.data(), mask.data()),
        None => scale_by_mask(pixmap.data_mut(), mask.data()),
    }
}

/// `pixels ← pixels · mask` (premultiplied RGBA8, 8-bit coverage, rounded), touching only the
/// pixels the mask does not fully cover. The mask is read eight pixels at a time: inside the
/// outline it is all 255 and outside all 0, so most groups are skipped or cleared whole.
fn scale_by_mask(pixels: &mut [u8], mask: &[u8]) {
    const GROUP: usize = 8;
    let mut px = pixels.chunks_exact_mut(4 * GROUP);
    let mut ms = mask.chunks_exact(GROUP);
    for (p, m) in (&mut px).zip(&mut ms) {
        match <[u8; GROUP]>::try_from(m).map(u64::from_ne_bytes) {
            Ok(u64::MAX) => {}
            Ok(0) => p.fill(0),
            _ => scale_pixels(p, m),
        }
    }
    scale_pixels(px.into_remainder(), ms.remainder());
}

/// [`scale_by_mask`] pixel by pixel.
fn scale_pixels(pixels: &mut [u8], mask: &[u8]) {
    for (p, &m) in pixels.chunks_exact_mut(4).zip(mask) {
        match m {
            255 => {}
            0 => p.fill(0),
            m => {
                for c in p {
                    *c = ((*c as u32 * m as u32 + 127) / 255) as u8;
                }
            }
        }
    }
}

/// The grid's placed vertices with those on the image's edge pushed out by
/// [`BORDER_DILATION`] pixels along the outline's outward normal.
fn dilated(placed: &[Point], border: &[usize]) -> Vec<Point> {
    let mut out = placed.to_vec();
    let n = border.len();
    if n < 3 {
        return out;
    }
    let ring: Vec<Point> = border.iter().map(|&k| placed[k]).collect();
    // Outward is to the right of travel for a counter-clockwise ring in y-down pixels.
    let sign = if crate::geometry::polygon_area(&ring) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    for i in 0..n {
        let (a, p, b) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
        let normal = |d: Point| {
            let len = d.length();
            if len > 0.0 {
                Point::new(d.y, -d.x) / len
            } else {
                Point::ZERO
            }
        };
        let nrm = normal(p - a) + normal(b - p);
        let len = nrm.length();
        if len > 1e-9 {
            out[border[i]] = p + nrm * (sign * BORDER_DILATION / len);
        }
    }
    out
}

/// The inverse of `m`, `None` when it is singular or not finite.
fn invert(m: Affine) -> Option<Affine> {
    let det = m.determinant();
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = m.inverse();
    inv.as_coeffs().iter().all(|c| c.is_finite()).then_some(inv)
}

/// Fractional bits of the fixed-point texel coordinates a run of pixels steps through.
const FRAC: u32 = 16;
/// One texel in fixed point.
const ONE: i64 = 1 << FRAC;

/// Premultiplied RGBA8 texels ([`Texels`] lanes), sampled with clamping to the edge.
struct Sampler<'a> {
    texels: &'a [u64],
    width: i32,
    height: i32,
    nearest: bool,
}

impl Sampler<'_> {
    /// Texel `(x, y)` clamped to the image, in [`Texels`] lanes.
    #[inline(always)]
    fn texel(&self, x: i64, y: i64) -> u64 {
        let x = x.clamp(0, self.width as i64 - 1);
        let y = y.clamp(0, self.height as i64 - 1);
        let i = y as usize * self.width as usize + x as usize;
        self.texels.get(i).copied().unwrap_or(0)
    }

    /// Whether the bilinear footprint of every pixel centre in triangle `tri` (output pixels)
    /// lies inside the image, at texel coordinates `to_texel` of it less `centre`: the
    /// triangle's corners in texel space lie inside by a margin that covers the corners'
    /// snapping to 1/256 pixel ([`snap`]) and the fixed-point stepping along a run (under one
    /// unit of 2⁻¹⁶ texel a pixel). The texel coordinates are affine in the pixel, so the
    /// pixels inside the triangle map inside the corners' hull.
    fn holds_footprint(&self, tri: [Point; 3], to_texel: Affine, centre: f64) -> bool {
        let [m0, m1, m2, m3, _, _] = to_texel.as_coeffs();
        let (lo, hi) = tri
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.x), hi.max(p.x))
            });
        let run = (hi - lo).max(0.0) + 2.0;
        let margin = 1e-3 + (m0.abs() + m1.abs() + m2.abs() + m3.abs()) / 128.0 + run / ONE as f64;
        let (w, h) = ((self.width - 1) as f64, (self.height - 1) as f64);
        tri.iter().all(|p| {
            let q = to_texel * kurbo::Point::new(p.x, p.y);
            let (u, v) = (q.x - centre, q.y - centre);
            u >= margin && u <= w - margin && v >= margin && v <= h - margin
        })
    }

    /// Fills `out` (packed RGBA8 pixels of one row) with the colours at fixed-point texel
    /// coordinates `(fu, fv) + k·(su, sv)` ([`FRAC`] bits) for its pixels `k`, the texel
    /// centres at half integers already subtracted for bilinear sampling: bilinear with 8-bit
    /// weights, or the texel under each when pixelated. A run whose every bilinear footprint
    /// lies inside the image (checked at its two ends: the coordinates are linear along it)
    /// skips the clamping.
    #[inline(always)]
    fn run(&self, mut fu: i64, mut fv: i64, su: i64, sv: i64, out: &mut [u8]) {
        let n = (out.len() / 4) as i64;
        if n == 0 {
            return;
        }
        if self.nearest {
            for px in out.chunks_exact_mut(4) {
                let texel = Texels::gather(self.texel(fu >> FRAC, fv >> FRAC));
                px.copy_from_slice(&texel.to_le_bytes());
                fu += su;
                fv += sv;
            }
            return;
        }
        let (eu, ev) = (fu + su * (n - 1), fv + sv * (n - 1));
        let inside = |lo: i64, hi: i64, size: i32| lo >= 0 && hi < (size as i64 - 1) << FRAC;
        if inside(fu.min(eu), fu.max(eu), self.width) && inside(fv.min(ev), fv.max(ev), self.height)
        {
            inner_run(self.texels, self.width as usize, (fu, fv), (su, sv), out);
            return;
        }
        for px in out.chunks_exact_mut(4) {
            let (x, y) = (fu >> FRAC, fv >> FRAC);
            let (fx, fy) = weights(fu, fv);
            let (a, b) = (self.texel(x, y), self.texel(x + 1, y));
            let (c, d) = (self.texel(x, y + 1), self.texel(x + 1, y + 1));
            px.copy_from_slice(&bilinear(a, b, c, d, fx, fy).to_le_bytes());
            fu += su;
            fv += sv;
        }
    }
}

/// [`Sampler::run`] for a run whose every bilinear footprint lies inside the image (`width`
/// texels a row), with no clamping. Kept out of line, so the loop has the registers to itself.
#[inline(never)]
fn inner_run(texels: &[u64], width: usize, start: (i64, i64), step: (i64, i64), out: &mut [u8]) {
    let ((mut fu, mut fv), (su, sv)) = (start, step);
    for px in out.chunks_exact_mut(4) {
        let (x, y) = ((fu >> FRAC) as usize, (fv >> FRAC) as usize);
        let (fx, fy) = weights(fu, fv);
        let i = x + width * y;
        let (Some(&[a, b]), Some(&[c, d])) =
            (texels.get(i..i + 2), texels.get(i + width..i + width + 2))
        else {
            return;
        };
        px.copy_from_slice(&bilinear(a, b, c, d, fx, fy).to_le_bytes());
        fu += su;
        fv += sv;
    }
}

/// The 8-bit bilinear weights of fixed-point coordinates (their fractions' top bits).
#[inline(always)]
fn weights(fu: i64, fv: i64) -> (u32, u32) {
    const SHIFT: u32 = FRAC - 8;
    (((fu >> SHIFT) & 0xff) as u32, ((fv >> SHIFT) & 0xff) as u32)
}

/// The bilinear mix, as a packed RGBA8 pixel, of texels `a b` (top row) and `c d` in
/// [`Texels`] lanes with 8-bit weights `fx`, `fy` (toward `b`/`d` and `c`/`d`): all four
/// channels at once, each lane `(p·(256 − f) + q·f + 128) >> 8`, which stays below 2¹⁶.
#[inline(always)]
fn bilinear(a: u64, b: u64, c: u64, d: u64, fx: u32, fy: u32) -> u32 {
    let lerp = |p: u64, q: u64, f: u32| -> u64 {
        let (g, h) = (256 - f as u64, f as u64);
        ((p * g + q * h + 0x0080_0080_0080_0080) >> 8) & Texels::LANES
    };
    Texels::gather(lerp(lerp(a, b, fx), lerp(c, d, fx), fy))
}

/// The layer the triangles are filled into (premultiplied RGBA8, replaced, not blended:
/// the triangles do not overlap).
struct Target<'a> {
    data: &'a mut [u8],
    width: i64,
    height: i64,
}

/// Sub-pixel bits of the snapped triangle corners: a corner is rounded to 1/256 pixel, so
/// coverage is decided in exact integer arithmetic.
const SUB: u32 = 8;
/// How far outside the pixmap, in pixels, a corner may lie before it is clamped (keeps every
/// edge-function product inside `i64`: corners below 2³⁰ sub-pixels, products below 2⁶²).
const REACH: f64 = (1 << 21) as f64;

/// A triangle corner snapped to the sub-pixel grid.
fn snap(p: Point) -> (i64, i64) {
    let s = |x: f64| (x.clamp(-REACH, REACH) * (1 << SUB) as f64).round() as i64;
    (s(p.x), s(p.y))
}

/// A real number as fixed point with [`FRAC`] bits (truncated; the error is far below a
/// bilinear weight's 1/256).
#[inline(always)]
fn fixed(x: f64) -> i64 {
    (x.clamp(-1e9, 1e9) * ONE as f64) as i64
}

/// Fills triangle `tri` (output pixels) with texels at `to_texel` of each pixel centre: each
/// row's run of covered pixels ([`covered_runs`]) sampled by [`Sampler::run`].
fn fill_triangle(target: &mut Target, tri: [Point; 3], to_texel: Affine, sampler: &Sampler) {
    let [m0, m1, m2, m3, m4, m5] = to_texel.as_coeffs();
    let centre = if sampler.nearest { 0.0 } else { 0.5 };
    let (su, sv) = (fixed(m0), fixed(m1));
    // When every covered pixel's footprint is inside the image, its coordinates are small too
    // (no clamp before the fixed-point cast), and each run goes straight to the loop.
    let inside = !sampler.nearest && sampler.holds_footprint(tri, to_texel, centre);
    covered_runs(tri, target.width, target.height, |y, l, r| {
        let (px, py) = (l as f64 + 0.5, y as f64 + 0.5);
        let u = m0 * px + m2 * py + m4 - centre;
        let v = m1 * px + m3 * py + m5 - centre;
        let row = (y * target.width) as usize;
        let out = &mut target.data[4 * (row + l as usize)..4 * (row + r as usize)];
        if inside {
            let start = ((u * ONE as f64) as i64, (v * ONE as f64) as i64);
            inner_run(sampler.texels, sampler.width as usize, start, (su, sv), out);
        } else {
            sampler.run(fixed(u), fixed(v), su, sv, out);
        }
    });
}

/// Hands every row `y` of a `width × height` pixmap that triangle `tri` covers to
/// `run(y, l, r)`, with its covered pixels `l..r` (contiguous: the triangle is convex).
///
/// Coverage is decided at pixel centres with integer edge functions of the corners snapped to
/// 1/256 pixel, and a top-left rule for centres exactly on an edge: an edge shared by two
/// triangles is the same integer line in both, and it is "top-left" in exactly one of them,
/// so a centre on it goes to one triangle, never both, never neither. Triangles that tile a
/// region therefore cover each of its pixels exactly once: no crack, no pixel drawn twice.
fn covered_runs(tri: [Point; 3], width: i64, height: i64, mut run: impl FnMut(i64, i64, i64)) {
    let [mut a, b, mut c] = tri.map(snap);
    let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
    if cross == 0 {
        return;
    }
    // Counter-clockwise in y-down pixels (negative area), so inside is E ≥ 0 below.
    if cross > 0 {
        std::mem::swap(&mut a, &mut c);
    }
    let half = 1i64 << (SUB - 1);
    let unit = 1i64 << SUB;
    // Pixel range of the bounding box (centres at k + ½).
    let first = |lo: i64| (lo - half + unit - 1).div_euclid(unit);
    let last = |hi: i64| (hi - half).div_euclid(unit);
    let x0 = first(a.0.min(b.0).min(c.0)).max(0);
    let x1 = last(a.0.max(b.0).max(c.0)).min(width - 1);
    let y0 = first(a.1.min(b.1).min(c.1)).max(0);
    let y1 = last(a.1.max(b.1).max(c.1)).min(height - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    // Edge p → q: E(x, y) = (q.y − p.y)·(x − p.x) − (q.x − p.x)·(y − p.y), ≥ 0 inside; a
    // top or left edge keeps its zeros, the others drop them (bias −1). Per pixel to the
    // right E grows by (q.y − p.y)·256, per row down by −(q.x − p.x)·256.
    // Each edge as (E at the first pixel centre of row y0, step right, step down).
    let (cx, cy) = (x0 * unit + half, y0 * unit + half);
    let edge = |p: (i64, i64), q: (i64, i64)| {
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let top_left = (dy == 0 && dx > 0) || dy < 0;
        let start = dy * (cx - p.0) - dx * (cy - p.1) - i64::from(!top_left);
        (start, dy * unit, -dx * unit)
    };
    let [(mut e0, s0, d0), (mut e1, s1, d1), (mut e2, s2, d2)] =
        [edge(a, b), edge(b, c), edge(c, a)];
    // A centre is inside when no edge function is negative: when the three's bitwise OR has
    // no sign bit.
    for y in y0..=y1 {
        let (mut f0, mut f1, mut f2) = (e0, e1, e2);
        let mut l = x0;
        while l <= x1 && (f0 | f1 | f2) < 0 {
            (f0, f1, f2) = (f0 + s0, f1 + s1, f2 + s2);
            l += 1;
        }
        let mut r = l;
        while r <= x1 && (f0 | f1 | f2) >= 0 {
            (f0, f1, f2) = (f0 + s0, f1 + s1, f2 + s2);
            r += 1;
        }
        if l < r {
            run(y, l, r);
        }
        (e0, e1, e2) = (e0 + d0, e1 + d1, e2 + d2);
    }
}

/// `below ← layer over below` through coverage `mask` (premultiplied RGBA8, 8-bit coverage,
/// rounded): the image's layer cut by its antialiased outline.
fn composite_masked(below: &mut [u8], layer: &[u8], mask: &[u8]) {
    for ((d, s), &m) in below
        .chunks_exact_mut(4)
        .zip(layer.chunks_exact(4))
        .zip(mask)
    {
        if m == 0 || s[3] == 0 {
            continue;
        }
        let m = m as u32;
        // The layer's pixel scaled by the coverage, then source-over.
        let src = [0, 1, 2, 3].map(|k| (s[k] as u32 * m + 127) / 255);
        let keep = 255 - src[3];
        for k in 0..4 {
            d[k] = (src[k] + (d[k] as u32 * keep + 127) / 255).min(255) as u8;
        }
    }
}

/// Whether a group holds a warped image anywhere below it.
pub(crate) fn has_warped_image(g: &crate::artwork::Group) -> bool {
    g.children.iter().any(|c| match c {
        crate::artwork::Item::Image(i) => i.grid.is_some(),
        crate::artwork::Item::Group(sub) => has_warped_image(sub),
        crate::artwork::Item::Path(_) => false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift), so the jitter is the same on every run.
    fn jitter(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// How many times [`covered_runs`] covers each pixel of a `w × h` pixmap when it is
    /// handed the triangles of an `nx × ny` grid of `points` (row-major), each cell cut along
    /// one diagonal or the other.
    fn coverage(points: &[Point], nx: usize, ny: usize, w: i64, h: i64) -> Vec<u32> {
        let at = |i: usize, j: usize| points[j * (nx + 1) + i];
        let mut count = vec![0u32; (w * h) as usize];
        for j in 0..ny {
            for i in 0..nx {
                let (p, q, r, s) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                let halves = if (i + j) % 2 == 0 {
                    [[p, q, r], [p, r, s]]
                } else {
                    [[p, q, s], [q, r, s]]
                };
                for tri in halves {
                    covered_runs(tri, w, h, |y, l, r| {
                        for x in l..r {
                            count[(y * w + x) as usize] += 1;
                        }
                    });
                }
            }
        }
        count
    }

    #[test]
    fn triangles_that_tile_the_pixmap_cover_each_pixel_once() {
        // A 9 × 7 grid of cells reaching past a 40 × 30 pixmap on every side, its inner
        // vertices moved by at most a pixel each way (so no cell folds): once all onto pixel
        // centres (every edge, horizontal, vertical or slanted, runs through centres: the tie
        // rule decides them), once jittered at random.
        let (w, h) = (40i64, 30i64);
        let (nx, ny) = (9usize, 7usize);
        let mut state = 0x2026_1203u64;
        for snapped in [true, false] {
            let mut points = Vec::new();
            for j in 0..=ny {
                for i in 0..=nx {
                    let x = -3.0 + 46.0 * i as f64 / nx as f64;
                    let y = -3.0 + 36.0 * j as f64 / ny as f64;
                    let inner = i > 0 && i < nx && j > 0 && j < ny;
                    points.push(match (inner, snapped) {
                        (false, _) => Point::new(x, y),
                        (true, true) => Point::new(x.round() + 0.5, y.round() + 0.5),
                        (true, false) => Point::new(
                            x + 2.0 * jitter(&mut state) - 1.0,
                            y + 2.0 * jitter(&mut state) - 1.0,
                        ),
                    });
                }
            }
            let count = coverage(&points, nx, ny, w, h);
            let wrong: Vec<_> = (0..count.len()).filter(|&k| count[k] != 1).collect();
            assert!(
                wrong.is_empty(),
                "snapped {snapped}: pixels covered other than once: {:?}",
                &wrong[..wrong.len().min(10)]
            );
        }
    }

    #[test]
    fn a_triangle_covers_the_pixel_centres_inside_it() {
        // Right triangle (0,0) (10,0) (0,10): centre (x+½, y+½) inside when x + y + 1 < 10,
        // and on the hypotenuse when x + y + 1 = 10 (given to one side by the tie rule).
        let mut rows = Vec::new();
        covered_runs(
            [
                Point::new(0.0, 0.0),
                Point::new(10.0, 0.0),
                Point::new(0.0, 10.0),
            ],
            20,
            20,
            |y, l, r| rows.push((y, l, r)),
        );
        assert_eq!(rows.len(), 10);
        for (y, l, r) in rows {
            assert_eq!(l, 0);
            assert!(r == 9 - y || r == 10 - y, "row {y}: {l}..{r}");
        }
    }

    #[test]
    fn bilinear_in_lanes_is_the_mix_of_each_channel() {
        // Every channel of the lane arithmetic against the plain two-step mix, for random
        // texels and weights, and for the extremes (all 0 and all 255 at full weight).
        let mut state = 0x5eed_u64;
        let mut byte = || (jitter(&mut state) * 256.0) as u32;
        let mut cases: Vec<([u32; 4], u32, u32)> = vec![
            ([u32::MAX; 4], 255, 255),
            ([u32::MAX; 4], 0, 0),
            ([0, u32::MAX, 0, u32::MAX], 255, 128),
        ];
        for _ in 0..2000 {
            let texel = |b: &mut dyn FnMut() -> u32| b() | b() << 8 | b() << 16 | b() << 24;
            let quad = [
                texel(&mut byte),
                texel(&mut byte),
                texel(&mut byte),
                texel(&mut byte),
            ];
            cases.push((quad, byte(), byte()));
        }
        for ([a, b, c, d], fx, fy) in cases {
            let got = bilinear(
                Texels::spread(a),
                Texels::spread(b),
                Texels::spread(c),
                Texels::spread(d),
                fx,
                fy,
            );
            for k in 0..4 {
                let ch = |p: u32| (p >> (8 * k)) & 0xff;
                let mix = |p: u32, q: u32, f: u32| (p * (256 - f) + q * f + 128) >> 8;
                let want = mix(mix(ch(a), ch(b), fx), mix(ch(c), ch(d), fx), fy);
                assert_eq!(
                    ch(got),
                    want,
                    "channel {k} of {a:08x} {b:08x} {c:08x} {d:08x}"
                );
            }
            assert_eq!(Texels::gather(Texels::spread(a)), a);
        }
    }

    #[test]
    fn scaling_by_the_mask_in_groups_is_scaling_each_pixel() {
        // A mask of whole groups of 255 and of 0, and partial groups, over a row whose
        // length is not a multiple of the group.
        let n = 8 * 7 + 5;
        let mask: Vec<u8> = (0..n)
            .map(|i| match i / 8 {
                0 | 3 => 255,
                1 | 5 => 0,
                _ => (i * 37 % 256) as u8,
            })
            .collect();
        let pixels: Vec<u8> = (0..4 * n).map(|i| (i * 11 % 256) as u8).collect();
        let (mut grouped, mut single) = (pixels.clone(), pixels);
        scale_by_mask(&mut grouped, &mask);
        scale_pixels(&mut single, &mask);
        assert_eq!(grouped, single);
        assert!(grouped[4 * 8..4 * 16].iter().all(|&c| c == 0));
    }

    #[test]
    fn a_run_samples_like_the_texels_it_lands_on() {
        // A 4 × 1 texture of grey levels; the run steps half a texel per pixel from the first
        // texel's centre, so it meets each centre (exact texel) and each midpoint (the mean).
        let texels: Vec<u64> = [0u8, 100, 200, 250]
            .iter()
            .map(|&g| Texels::spread(u32::from_le_bytes([g, g, g, 255])))
            .collect();
        let sampler = Sampler {
            texels: &texels,
            width: 4,
            height: 1,
            nearest: false,
        };
        let mut out = vec![0u8; 4 * 7];
        sampler.run(0, 0, ONE / 2, 0, &mut out);
        let grey: Vec<u8> = out.chunks_exact(4).map(|p| p[0]).collect();
        assert_eq!(grey, [0, 50, 100, 150, 200, 225, 250]);
    }
}
