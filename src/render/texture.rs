//! Drawing a warped raster image into pixels: every triangle of its texture grid
//! ([`crate::artwork::ImageGrid`]) filled with the image under that triangle's affine map,
//! sampled bilinearly (nearest for `image-rendering: pixelated`) on premultiplied RGBA.
//!
//! The triangles are rasterized here rather than by one tiny-skia `fill_path` each: a grid has
//! up to 4608 of them, and the per-call set-up of a shader pipeline cost more than the pixels.
//! Coverage is decided at pixel centres with a tie rule that gives a pixel on an edge shared by
//! two triangles to exactly one of them (each edge is evaluated from its endpoints in one fixed
//! order, so both triangles compute the same number), so the triangles tile the image with no
//! crack and no pixel drawn twice: a solid texture stays solid. The image's own edge is
//! antialiased instead: the grid is drawn with its outer vertices pushed out by
//! [`BORDER_DILATION`] pixels (the texture's edge texels extended), then composited through an
//! antialiased mask of the undilated outline.

use crate::artwork::{ImageGrid, ImageItem};
use crate::geometry::Point;
use kurbo::Affine;
use tiny_skia::{FillRule, Mask, PathBuilder, Pixmap, Transform};

/// How far, in output pixels, the image's outer edge is pushed out before the antialiased
/// outline mask cuts it back.
const BORDER_DILATION: f64 = 1.5;

/// The image's pixels decoded (premultiplied), once per image: rendered by resvg at its natural
/// size with nearest-neighbour sampling, which reproduces every pixel exactly and decodes every
/// format usvg accepts (PNG, JPEG, GIF, WebP). `None` when it cannot be decoded.
pub(crate) fn decoded(img: &ImageItem) -> Option<std::sync::Arc<Pixmap>> {
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
        Some(pixmap)
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
        texture.width() as f64 / img.width,
        texture.height() as f64 / img.height,
    );
    let sampler = Sampler {
        texels: texture.data(),
        width: texture.width() as i32,
        height: texture.height() as i32,
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
/// pixels the mask does not fully cover.
fn scale_by_mask(pixels: &mut [u8], mask: &[u8]) {
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

/// Premultiplied RGBA8 texels, sampled with clamping to the edge.
struct Sampler<'a> {
    texels: &'a [u8],
    width: i32,
    height: i32,
    nearest: bool,
}

impl Sampler<'_> {
    /// Texel `(x, y)` clamped to the image, packed as in memory (RGBA, little-endian).
    #[inline(always)]
    fn texel(&self, x: i32, y: i32) -> u32 {
        let x = x.clamp(0, self.width - 1);
        let y = y.clamp(0, self.height - 1);
        let i = 4 * (y as usize * self.width as usize + x as usize);
        match self.texels.get(i..i + 4) {
            Some(&[r, g, b, a]) => u32::from_le_bytes([r, g, b, a]),
            _ => 0,
        }
    }

    /// Two horizontally adjacent texels `(x, y)` and `(x + 1, y)`, both inside the image.
    #[inline(always)]
    fn pair(&self, x: i32, y: i32) -> (u32, u32) {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        match self.texels.get(i..i + 8) {
            Some(&[r0, g0, b0, a0, r1, g1, b1, a1]) => (
                u32::from_le_bytes([r0, g0, b0, a0]),
                u32::from_le_bytes([r1, g1, b1, a1]),
            ),
            _ => (0, 0),
        }
    }

    /// The colour at texel coordinates `(u, v)` (texel centres at half integers), packed:
    /// bilinear with 8-bit weights, two channels at a time in 16-bit lanes, or the texel under
    /// it when pixelated.
    #[inline(always)]
    fn sample(&self, u: f32, v: f32) -> u32 {
        // Far outside the image every coordinate clamps alike; this keeps the casts in range
        // and makes truncation a floor (the shifted values are positive).
        const SHIFT: f32 = 16.0;
        let u = u.clamp(-8.0, self.width as f32 + 8.0);
        let v = v.clamp(-8.0, self.height as f32 + 8.0);
        if self.nearest {
            let x = (u + SHIFT) as i32 - SHIFT as i32;
            let y = (v + SHIFT) as i32 - SHIFT as i32;
            return self.texel(x, y);
        }
        let (x, y) = (u - 0.5 + SHIFT, v - 0.5 + SHIFT);
        let (xi, yi) = (x as i32, y as i32);
        let fx = ((x - xi as f32) * 256.0) as u32;
        let fy = ((y - yi as f32) * 256.0) as u32;
        let (x0, y0) = (xi - SHIFT as i32, yi - SHIFT as i32);
        let ((a, b), (c, d)) = if x0 >= 0 && y0 >= 0 && x0 + 1 < self.width && y0 + 1 < self.height
        {
            (self.pair(x0, y0), self.pair(x0, y0 + 1))
        } else {
            (
                (self.texel(x0, y0), self.texel(x0 + 1, y0)),
                (self.texel(x0, y0 + 1), self.texel(x0 + 1, y0 + 1)),
            )
        };
        let lerp = |p: u32, q: u32, f: u32| -> u32 {
            const LANES: u32 = 0x00ff_00ff;
            let (g, h) = (256 - f, f);
            let even = ((p & LANES) * g + (q & LANES) * h + 0x0080_0080) >> 8;
            let odd = (((p >> 8) & LANES) * g + ((q >> 8) & LANES) * h + 0x0080_0080) >> 8;
            (even & LANES) | ((odd & LANES) << 8)
        };
        lerp(lerp(a, b, fx), lerp(c, d, fx), fy)
    }
}

/// The layer the triangles are filled into (premultiplied RGBA8, replaced, not blended:
/// the triangles do not overlap).
struct Target<'a> {
    data: &'a mut [u8],
    width: i64,
    height: i64,
}

/// The edge function of the line through two corners, `E(x, y) = a·x + b·y + c`, its
/// coefficients computed from the endpoints in one fixed (lexicographic) order, so that the
/// two triangles sharing an edge compute bit-identical values at every pixel centre.
#[derive(Clone, Copy)]
struct Edge {
    a: f64,
    b: f64,
    c: f64,
    /// +1 when the triangle lies where `E > 0`, else −1.
    side: f64,
    /// `−1/a` (0 for a horizontal edge): where a row crosses the edge, from its constant.
    crossing: f64,
}

impl Edge {
    fn new(p: Point, q: Point, third: Point) -> Edge {
        let (p, q) = if (p.x, p.y) <= (q.x, q.y) {
            (p, q)
        } else {
            (q, p)
        };
        let (dx, dy) = (q.x - p.x, q.y - p.y);
        let (a, b, c) = (-dy, dx, dy * p.x - dx * p.y);
        let at_third = a * third.x + (b * third.y + c);
        Edge {
            a,
            b,
            c,
            side: if at_third > 0.0 { 1.0 } else { -1.0 },
            crossing: if a == 0.0 { 0.0 } else { -1.0 / a },
        }
    }

    /// The part of `E` that is constant along pixel row `y` (centre `py`).
    #[inline(always)]
    fn row(&self, py: f64) -> f64 {
        self.b * py + self.c
    }

    /// Whether the pixel centre at `px` of a row with constant `row` is on the triangle's
    /// side: strictly, or exactly on the edge when the triangle's side is the positive one
    /// (the tie goes to one of the two triangles sharing the edge, never both, never neither).
    #[inline(always)]
    fn holds(&self, px: f64, row: f64) -> bool {
        let v = (self.a * px + row) * self.side;
        v > 0.0 || (v == 0.0 && self.side > 0.0)
    }
}

/// Fills triangle `tri` (output pixels) with texels at `to_texel` of each pixel centre.
///
/// A pixel is inside when its centre is on the triangle's side of all three edges
/// ([`Edge::holds`]). That decision is made exactly for the pixels at the two ends of each
/// row's run (found from the run's approximate ends); the pixels between are inside because
/// the triangle is convex.
fn fill_triangle(target: &mut Target, tri: [Point; 3], to_texel: Affine, sampler: &Sampler) {
    let [a, b, c] = tri;
    if crate::geometry::orient2d(a, b, c) == 0.0 {
        return;
    }
    let edges = [Edge::new(a, b, c), Edge::new(b, c, a), Edge::new(c, a, b)];
    let lo = a.min(b).min(c);
    let hi = a.max(b).max(c);
    // Pixel ranges a pixel wider than the bounding box (truncation is not a floor below 0);
    // the exact tests trim them.
    let x0 = ((lo.x - 0.5) as i64).max(0);
    let x1 = ((hi.x - 0.5) as i64 + 1).min(target.width - 1);
    let y0 = ((lo.y - 0.5) as i64).max(0);
    let y1 = ((hi.y - 0.5) as i64 + 1).min(target.height - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let [m0, m1, m2, m3, m4, m5] = to_texel.as_coeffs();
    let (du, dv) = (m0 as f32, m1 as f32);
    for y in y0..=y1 {
        let py = y as f64 + 0.5;
        let rows = edges.map(|e| e.row(py));
        let inside = |x: i64| {
            let px = x as f64 + 0.5;
            (0..3).all(|k| edges[k].holds(px, rows[k]))
        };
        // The run's approximate ends: where the row crosses the edges, a pixel wider.
        let (mut l, mut r) = (x0, x1);
        for (e, row) in edges.iter().zip(rows) {
            if e.a == 0.0 {
                continue;
            }
            let cross = (row * e.crossing - 0.5).clamp(-1.0, target.width as f64 + 1.0) as i64;
            if e.a * e.side > 0.0 {
                l = l.max(cross - 1);
            } else {
                r = r.min(cross + 1);
            }
        }
        while l <= r && !inside(l) {
            l += 1;
        }
        while r >= l && !inside(r) {
            r -= 1;
        }
        if l > r {
            continue;
        }
        let px = l as f64 + 0.5;
        let u = (m0 * px + m2 * py + m4) as f32;
        let v = (m1 * px + m3 * py + m5) as f32;
        let row = (y * target.width) as usize;
        let out = &mut target.data[4 * (row + l as usize)..4 * (row + r as usize + 1)];
        for (k, px) in out.chunks_exact_mut(4).enumerate() {
            let k = k as f32;
            px.copy_from_slice(&sampler.sample(u + du * k, v + dv * k).to_le_bytes());
        }
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
