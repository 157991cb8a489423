//! Drawing a warped raster image into pixels: every triangle of its texture grid
//! ([`crate::artwork::ImageGrid`]) filled with the image under that triangle's affine map,
//! sampled bilinearly (nearest for `image-rendering: pixelated`) on premultiplied RGBA.
//!
//! The triangles are rasterized here rather than by one tiny-skia `fill_path` each: a grid has
//! up to 2048 of them, and the per-call set-up of a shader pipeline cost more than the pixels.
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
use tiny_skia::{FillRule, Mask, PathBuilder, Pixmap, PixmapPaint, Transform};

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
            super::svg_frame::base64(&img.data)
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
/// the pixmap's pixels. An image that cannot be decoded is not drawn (a `log::warn!`).
pub(crate) fn draw_image(pixmap: &mut Pixmap, img: &ImageItem, grid: &ImageGrid, to_px: Affine) {
    let Some(texture) = decoded(img) else {
        log::warn!("image '{}': cannot be decoded; not drawn", img.id);
        return;
    };
    let (w, h) = (pixmap.width(), pixmap.height());
    let Some(mut layer) = Pixmap::new(w, h) else {
        return;
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
        width: texture.width() as i64,
        height: texture.height() as i64,
        nearest: img.pixelated,
    };
    let mut target = Target {
        data: layer.data_mut(),
        width: w as i64,
        height: h as i64,
    };
    for piece in grid.pieces(img) {
        // Output pixels → texels, from the undilated placement.
        let px = piece.vertices.map(|k| placed[k]);
        let Some(back) = affine_from(piece.image, px).and_then(|m| invert(m)) else {
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
    pixmap.draw_pixmap(
        0,
        0,
        layer.as_ref(),
        &PixmapPaint::default(),
        Transform::identity(),
        Some(&mask),
    );
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

/// The affine map taking triangle `from` to triangle `to`, `None` when `from` is degenerate.
fn affine_from(from: [Point; 3], to: [Point; 3]) -> Option<Affine> {
    let m =
        |[a, b, c]: [Point; 3]| Affine::new([b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y, a.x, a.y]);
    let f = m(from);
    let det = f.determinant();
    (det != 0.0 && det.is_finite()).then(|| m(to) * f.inverse())
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
    width: i64,
    height: i64,
    nearest: bool,
}

impl Sampler<'_> {
    /// The texel colour at texel coordinates `(u, v)` (texel centres at half integers).
    #[inline]
    fn sample(&self, u: f64, v: f64) -> [u8; 4] {
        let at = |x: i64, y: i64| -> &[u8] {
            let x = x.clamp(0, self.width - 1);
            let y = y.clamp(0, self.height - 1);
            let i = 4 * (y * self.width + x) as usize;
            &self.texels[i..i + 4]
        };
        if self.nearest {
            let t = at(u.floor() as i64, v.floor() as i64);
            return [t[0], t[1], t[2], t[3]];
        }
        let (x, y) = (u - 0.5, v - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let (a, b, c, d) = (
            at(x0, y0),
            at(x0 + 1, y0),
            at(x0, y0 + 1),
            at(x0 + 1, y0 + 1),
        );
        let mut out = [0u8; 4];
        for k in 0..4 {
            let top = a[k] as f64 + (b[k] as f64 - a[k] as f64) * fx;
            let bottom = c[k] as f64 + (d[k] as f64 - c[k] as f64) * fx;
            out[k] = (top + (bottom - top) * fy + 0.5) as u8;
        }
        // Premultiplied: no channel above alpha, whatever the rounding did.
        let a = out[3];
        for v in &mut out[..3] {
            *v = (*v).min(a);
        }
        out
    }
}

/// The layer the triangles are filled into (premultiplied RGBA8, replaced, not blended:
/// the triangles do not overlap).
struct Target<'a> {
    data: &'a mut [u8],
    width: i64,
    height: i64,
}

/// The edge function of the line through `a` and `b` at `p`, computed from the endpoints in
/// one fixed (lexicographic) order so that two triangles sharing the edge get exactly opposite
/// values.
#[inline]
fn edge(a: Point, b: Point, p: Point) -> f64 {
    if (a.x, a.y) <= (b.x, b.y) {
        (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
    } else {
        -((a.x - b.x) * (p.y - b.y) - (a.y - b.y) * (p.x - b.x))
    }
}

/// Fills triangle `tri` (output pixels) with texels at `to_texel` of each pixel centre.
fn fill_triangle(target: &mut Target, tri: [Point; 3], to_texel: Affine, sampler: &Sampler) {
    let [a, b, c] = tri;
    if crate::geometry::orient2d(a, b, c) == 0.0 {
        return;
    }
    // Each edge with the side its triangle lies on: a pixel exactly on an edge goes to the
    // triangle on the positive side (the one neighbour that has it there).
    let edges = [(a, b, c), (b, c, a), (c, a, b)].map(|(p, q, r)| {
        let s = edge(p, q, r);
        (p, q, if s > 0.0 { 1.0 } else { -1.0 })
    });
    let lo = a.min(b).min(c);
    let hi = a.max(b).max(c);
    let x0 = ((lo.x - 0.5).ceil() as i64).max(0);
    let x1 = ((hi.x - 0.5).floor() as i64).min(target.width - 1);
    let y0 = ((lo.y - 0.5).ceil() as i64).max(0);
    let y1 = ((hi.y - 0.5).floor() as i64).min(target.height - 1);
    let [m0, m1, m2, m3, m4, m5] = to_texel.as_coeffs();
    for y in y0..=y1 {
        let py = y as f64 + 0.5;
        let row = (y * target.width) as usize;
        for x in x0..=x1 {
            let p = Point::new(x as f64 + 0.5, py);
            let inside = edges.iter().all(|&(e0, e1, s)| {
                let v = edge(e0, e1, p) * s;
                v > 0.0 || (v == 0.0 && s > 0.0)
            });
            if !inside {
                continue;
            }
            let u = m0 * p.x + m2 * p.y + m4;
            let v = m1 * p.x + m3 * p.y + m5;
            let i = 4 * (row + x as usize);
            target.data[i..i + 4].copy_from_slice(&sampler.sample(u, v));
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
