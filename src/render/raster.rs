//! Raster frames with resvg/tiny-skia: each warped side rendered alone, then blended pixel-wise
//! on premultiplied RGBA (end of §3: the target at opacity `b` over the source at opacity `a`,
//! [`super::dissolve`]), then composited over the background.
//!
//! A side is rendered by writing it with [`scene_svg`] and parsing that with usvg, so raster and
//! SVG frames come from one writer. The blend is the composite the SVG frame's two groups with
//! plain opacity make, on premultiplied values (so the result stays premultiplied), rounded in
//! 16-bit fixed point: within one level of the exact formula.

use super::svg_frame::{scene_svg, side_svg, Layer};
use super::FrameOptions;
use crate::artwork::{Clip, Group, Item, Scene};
use crate::error::{Error, Result};
use tiny_skia::{Pixmap, PixmapPaint, Transform};

/// Renders one scene alone on a transparent pixmap of `opts.size` showing `opts.view_box`
/// (`opts.background` is ignored here; frames apply it after blending).
pub fn render_scene(scene: &Scene, opts: &FrameOptions) -> Result<Pixmap> {
    let svg = scene_svg(
        scene,
        &FrameOptions {
            background: None,
            ..*opts
        },
    )?;
    render_svg(&svg, &scene.file, opts)
}

/// Renders one warped side of an in-between frame exactly as the SVG frame writes it (outlines
/// fitted with curves), so raster and SVG frames show the same geometry. Warped images are
/// drawn triangle by triangle of their texture grid ([`super::texture`]), in paint order
/// between runs of the other artwork, which resvg renders.
pub(crate) fn render_side(scene: &Scene, opts: &FrameOptions) -> Result<Pixmap> {
    if !super::texture::has_warped_image(&scene.root) {
        return render_svg(&side_svg(scene, opts)?, &scene.file, opts);
    }
    let mut pixmap = blank(opts, &scene.file)?;
    let to_px = view_transform(opts) * scene.root_transform;
    draw_items(&mut pixmap, true, scene, &scene.root.children, to_px, opts)?;
    Ok(pixmap)
}

/// The map from user space to output pixels that the frame's root element sets up (`width`,
/// `height` and `viewBox`, `preserveAspectRatio` at its default `xMidYMid meet`).
pub(crate) fn view_transform(opts: &FrameOptions) -> kurbo::Affine {
    let (lo, hi) = opts.view_box;
    let (vw, vh) = (hi.x - lo.x, hi.y - lo.y);
    let (w, h) = (opts.size.0 as f64, opts.size.1 as f64);
    let k = (w / vw).min(h / vh);
    if !k.is_finite() || k <= 0.0 {
        return kurbo::Affine::IDENTITY;
    }
    kurbo::Affine::new([
        k,
        0.0,
        0.0,
        k,
        (w - vw * k) / 2.0 - lo.x * k,
        (h - vh * k) / 2.0 - lo.y * k,
    ])
}

/// Draws `items` of `scene` onto `pixmap` in paint order: warped images by the texture
/// rasterizer, groups holding one through a layer of their own (for their opacity and clip),
/// and every run of other artwork by resvg. `fresh`: nothing has been drawn on `pixmap` yet.
/// Returns whether anything may have been drawn.
fn draw_items(
    pixmap: &mut Pixmap,
    fresh: bool,
    scene: &Scene,
    items: &[Item],
    to_px: kurbo::Affine,
    opts: &FrameOptions,
) -> Result<bool> {
    let mut blank_so_far = fresh;
    let mut run: Vec<Item> = Vec::new();
    let flush = |pixmap: &mut Pixmap, run: &mut Vec<Item>| -> Result<()> {
        if run.is_empty() {
            return Ok(());
        }
        let part = Scene {
            file: scene.file.clone(),
            view_box: scene.view_box,
            size: scene.size,
            root_transform: scene.root_transform,
            root: Group {
                id: String::new(),
                opacity: 1.0,
                clip: None,
                children: std::mem::take(run),
            },
        };
        draw_svg(pixmap, &side_svg(&part, opts)?)
    };
    for item in items {
        match item {
            Item::Image(img) if img.grid.is_some() => {
                blank_so_far &= run.is_empty();
                flush(pixmap, &mut run)?;
                if let Some(grid) = &img.grid {
                    super::texture::draw_image(pixmap, img, grid, to_px, blank_so_far);
                }
                blank_so_far = false;
            }
            Item::Group(g) if super::texture::has_warped_image(g) => {
                blank_so_far &= run.is_empty();
                flush(pixmap, &mut run)?;
                if g.opacity == 1.0 && g.clip.is_none() {
                    let drawn = draw_items(pixmap, blank_so_far, scene, &g.children, to_px, opts)?;
                    blank_so_far &= !drawn;
                    continue;
                }
                blank_so_far = false;
                let mut layer = blank(opts, &scene.file)?;
                draw_items(&mut layer, true, scene, &g.children, to_px, opts)?;
                let mask = g.clip.as_ref().and_then(|c| clip_mask(c, to_px, opts));
                pixmap.draw_pixmap(
                    0,
                    0,
                    layer.as_ref(),
                    &PixmapPaint {
                        opacity: g.opacity as f32,
                        ..PixmapPaint::default()
                    },
                    Transform::identity(),
                    mask.as_ref(),
                );
            }
            other => run.push(other.clone()),
        }
    }
    blank_so_far &= run.is_empty();
    flush(pixmap, &mut run)?;
    Ok(!blank_so_far)
}

/// The coverage of a clip path (the union of its shapes) in output pixels, antialiased.
fn clip_mask(clip: &Clip, to_px: kurbo::Affine, opts: &FrameOptions) -> Option<tiny_skia::Mask> {
    let (w, h) = opts.size;
    let mut mask = tiny_skia::Mask::new(w, h)?;
    for shape in &clip.shapes {
        let mut pb = tiny_skia::PathBuilder::new();
        for el in (to_px * shape.path.clone()).elements() {
            match *el {
                kurbo::PathEl::MoveTo(p) => pb.move_to(p.x as f32, p.y as f32),
                kurbo::PathEl::LineTo(p) => pb.line_to(p.x as f32, p.y as f32),
                kurbo::PathEl::QuadTo(a, p) => {
                    pb.quad_to(a.x as f32, a.y as f32, p.x as f32, p.y as f32)
                }
                kurbo::PathEl::CurveTo(a, b, p) => pb.cubic_to(
                    a.x as f32, a.y as f32, b.x as f32, b.y as f32, p.x as f32, p.y as f32,
                ),
                kurbo::PathEl::ClosePath => pb.close(),
            }
        }
        if let Some(path) = pb.finish() {
            let rule = if shape.even_odd {
                tiny_skia::FillRule::EvenOdd
            } else {
                tiny_skia::FillRule::Winding
            };
            mask.fill_path(&path, rule, true, Transform::identity());
        }
    }
    Some(mask)
}

/// Renders crmorph's own SVG onto `pixmap`, over what it holds.
fn draw_svg(pixmap: &mut Pixmap, svg: &str) -> Result<()> {
    let read = crate::input::usvg_options("<frame>", None, &crate::input::InputPolicy::default());
    let tree = usvg::Tree::from_str(svg, &read)
        .map_err(|e| Error::internal(format!("crmorph wrote an SVG usvg cannot read: {e}")))?;
    resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    Ok(())
}

/// Renders crmorph's own SVG of one side onto a transparent pixmap; `file` is the drawing an
/// over-sized frame is blamed on.
fn render_svg(svg: &str, file: &str, opts: &FrameOptions) -> Result<Pixmap> {
    let mut pixmap = blank(opts, file)?;
    // crmorph's own SVG embeds images as data URIs; it is read as strictly as an input, so a
    // reference that slipped through could never make it read a file.
    let read = crate::input::usvg_options(file, None, &crate::input::InputPolicy::default());
    let tree = usvg::Tree::from_str(svg, &read)
        .map_err(|e| Error::internal(format!("crmorph wrote an SVG usvg cannot read: {e}")))?;
    resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    Ok(pixmap)
}

/// The frame at `t` (clamped to [0, 1]) as pixels: the warped `source` and `target` rendered
/// and cross-dissolved as the SVG frame draws them ([`super::dissolve`]), over
/// `opts.background` if any. At t = 0 and t = 1 only that side is rendered.
pub fn frame_pixmap(source: &Scene, target: &Scene, t: f64, opts: &FrameOptions) -> Result<Pixmap> {
    frame_pixmap_layers(&[Layer::Blend(source, target)], t, opts)
}

/// The frame at `t` made of `layers`, bottom first (see [`super::svg_frame::frame_svg_layers`]):
/// each [`Layer::Blend`] rendered and dissolved on its own, each [`Layer::Over`] rendered, and
/// each composited source-over onto the layers below, then over the background. At t = 0
/// (t = 1) a blend layer is its source (target) side alone.
///
/// Errors: a frame size over `opts.max_pixels` (checked before anything is rendered).
pub fn frame_pixmap_layers(layers: &[Layer], t: f64, opts: &FrameOptions) -> Result<Pixmap> {
    let file = layers.first().map_or("<output>", |l| match l {
        Layer::Blend(s, _) => s.file.as_str(),
        Layer::Over(o) => o.file.as_str(),
    });
    opts.check_pixels(file)?;
    let t = crate::rigid::clamp_time(t);
    let render = |layer: &Layer| -> Result<Pixmap> {
        match *layer {
            Layer::Blend(s, _) if t == 0.0 => render_scene(s, opts),
            Layer::Blend(_, g) if t == 1.0 => render_scene(g, opts),
            Layer::Blend(s, g) => {
                // The two sides are independent: rendered at once.
                let (a, b) = rayon::join(|| render_side(s, opts), || render_side(g, opts));
                let mut a = a?;
                blend_into(&mut a, &b?, t);
                Ok(a)
            }
            Layer::Over(o) => render_side(o, opts),
        }
    };
    let mut stack: Option<Pixmap> = None;
    for layer in layers {
        let top = render(layer)?;
        match &mut stack {
            None => stack = Some(top),
            Some(below) => over(below, &top),
        }
    }
    let blended = match stack {
        Some(p) => p,
        None => blank(opts, file)?,
    };
    match opts.background {
        None => Ok(blended),
        Some(bg) => {
            let mut out = blank(opts, file)?;
            out.fill(tiny_skia::Color::from_rgba8(bg.r, bg.g, bg.b, bg.a));
            over(&mut out, &blended);
            Ok(out)
        }
    }
}

/// A transparent pixmap of the frame's size, checked against `opts.max_pixels` first (the
/// error blames `file`).
fn blank(opts: &FrameOptions, file: &str) -> Result<Pixmap> {
    opts.check_pixels(file)?;
    let (w, h) = opts.size;
    Pixmap::new(w, h).ok_or_else(|| {
        Error::input(
            file,
            format!("cannot render a {w}×{h} image: the size must be positive and not huge"),
        )
    })
}

/// `below ← top over below` (source-over on premultiplied RGBA).
fn over(below: &mut Pixmap, top: &Pixmap) {
    below.draw_pixmap(
        0,
        0,
        top.as_ref(),
        &PixmapPaint::default(),
        Transform::identity(),
        None,
    );
}

/// The frame at `t` encoded as PNG (straight alpha, 8-bit RGBA).
pub fn frame_png(source: &Scene, target: &Scene, t: f64, opts: &FrameOptions) -> Result<Vec<u8>> {
    encode_png(&frame_pixmap(source, target, t, opts)?)
}

/// A pixmap's pixels as straight (not premultiplied) RGBA bytes, row by row: what PNG, APNG
/// and GIF encoders take.
pub fn straight_rgba(pixmap: &Pixmap) -> Vec<u8> {
    let mut out = Vec::with_capacity(pixmap.data().len());
    for p in pixmap.pixels() {
        let c = p.demultiply();
        out.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
    }
    out
}

/// Encodes a pixmap as an 8-bit RGBA PNG with the png crate's fast compression (several times
/// faster than the default level at frame sizes, for files a little larger).
pub fn encode_png(pixmap: &Pixmap) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let err = |e: png::EncodingError| Error::internal(format!("PNG encoding failed: {e}"));
    let mut enc = png::Encoder::new(&mut out, pixmap.width(), pixmap.height());
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut w = enc.write_header().map_err(err)?;
    w.write_image_data(&straight_rgba(pixmap)).map_err(err)?;
    w.finish().map_err(err)?;
    Ok(out)
}

/// `s ← b·d over a·s` (premultiplied RGBA, rounded to nearest) with the dissolve's opacities
/// at `t`: the pixel form of the SVG frame's two groups.
pub(crate) fn blend_into(s: &mut Pixmap, d: &Pixmap, t: f64) {
    let (a, b) = super::dissolve(t);
    // In 16-bit fixed point: `b` and the below's weight `(1 − b·yₐ/255)·a` by the above's
    // alpha, each rounded to 1/65536. Per channel `b·y + keep·x ≤ 255` in exact arithmetic
    // (premultiplied `y ≤ yₐ`), and the weights' rounding adds at most `(x + y)/2¹⁷`, so the
    // rounded result stays a byte: no clamp, and at most one level from the real formula.
    const ONE: f64 = 65536.0;
    let bq = (b * ONE).round() as u32;
    let keep: [u32; 256] =
        std::array::from_fn(|v| ((1.0 - b * v as f64 / 255.0) * a * ONE).round() as u32);
    // In parallel by bands of rows: the pixels are independent.
    const BAND: usize = 1 << 16;
    use rayon::prelude::*;
    s.data_mut()
        .par_chunks_mut(BAND)
        .zip(d.data().par_chunks(BAND))
        .for_each(|(s, d)| {
            for (x, y) in s.chunks_exact_mut(4).zip(d.chunks_exact(4)) {
                if y == [0; 4] && (a == 1.0 || x == [0; 4]) {
                    // Nothing above, and the below kept whole (or nothing there either).
                    continue;
                }
                let cover = keep[y[3] as usize];
                for k in 0..4 {
                    x[k] = ((bq * y[k] as u32 + cover * x[k] as u32 + (1 << 15)) >> 16) as u8;
                }
            }
        });
}

/// Any SVG document (for example [`crate::inspect::inspect_svg`]'s picture) rendered to PNG at
/// `width` pixels wide (default: its own width), height in proportion.
///
/// Errors: an image of more than `max_pixels` pixels ([`crate::input::Limits::pixels`]; the
/// error blames `file`, the drawing whose size it has), checked before allocating.
///
/// Text is set in the bundled DejaVu Sans subset, whatever family it names, and no system font
/// is read: crmorph's own pictures (the inspect captions) look the same on every machine. Only
/// data-URI images are read, under the input policy's rules ([`crate::input`]).
pub fn svg_png(svg: &str, width: Option<u32>, file: &str, max_pixels: u64) -> Result<Vec<u8>> {
    let opts = usvg::Options {
        fontdb: super::font::bundled_fontdb(),
        ..crate::input::usvg_options(file, None, &crate::input::InputPolicy::default())
    };
    let tree = usvg::Tree::from_str(svg, &opts)
        .map_err(|e| Error::internal(format!("cannot read the SVG to render: {e}")))?;
    let size = tree.size();
    let w = width.map(|w| w as f32).unwrap_or(size.width()).max(1.0);
    let scale = w / size.width().max(1e-6);
    let h = (size.height() * scale).round().max(1.0);
    // Float to integer casts saturate: a huge or infinite side becomes u32::MAX, over any limit.
    let (pw, ph) = (w.round() as u32, h as u32);
    super::check_raster_size(file, (pw, ph), max_pixels)?;
    let mut pixmap = Pixmap::new(pw, ph)
        .ok_or_else(|| Error::internal(format!("cannot render a {w}×{h} image")))?;
    resvg::render(
        &tree,
        Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    encode_png(&pixmap)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::svg_frame::frame_svg_layers;

    fn scene(body: &str) -> Scene {
        let svg = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="30" height="30">{body}</svg>"#
        );
        Scene::from_svg("l.svg", &svg, "controls").unwrap()
    }

    #[test]
    fn layers_stack_in_order_in_pixels_and_in_svg() {
        let red = scene(r##"<rect width="30" height="30" fill="#ff0000"/>"##);
        let blue = scene(r##"<rect x="5" y="5" width="20" height="20" fill="#0000ff"/>"##);
        let white = scene(r##"<rect x="12" y="12" width="6" height="6" fill="#ffffff"/>"##);
        let none = scene("");
        // A detail blended in from nothing over a shape drawn as it is, over a blended ground.
        let layers = [
            Layer::Blend(&red, &red),
            Layer::Over(&blue),
            Layer::Blend(&none, &white),
        ];
        let opts = FrameOptions::for_scene(&red);
        for t in [0.0, 0.5, 1.0] {
            let px = frame_pixmap_layers(&layers, t, &opts).unwrap();
            let rgba = |x, y| {
                let p = px.pixel(x, y).unwrap();
                [p.red(), p.green(), p.blue(), p.alpha()]
            };
            assert_eq!(rgba(1, 1), [255, 0, 0, 255], "t = {t}");
            assert_eq!(rgba(7, 7), [0, 0, 255, 255], "t = {t}");
            // The centre: blue under the detail at the dissolve's target opacity.
            let w = (255.0 * crate::render::dissolve(t).1).round() as u8;
            let c = rgba(15, 15);
            assert!(
                c[0].abs_diff(w) <= 1 && c[2] == 255 && c[3] == 255,
                "t = {t}: {c:?}"
            );
            // The SVG frame stacks the same way (a source and a target group per blend layer).
            let svg = frame_svg_layers(&layers, t, &opts).unwrap();
            let groups = svg.matches("class=\"crmorph-target\"").count();
            assert_eq!(groups, if t == 0.5 { 2 } else { 0 });
            let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).unwrap();
            let mut from_svg = Pixmap::new(30, 30).unwrap();
            resvg::render(&tree, Transform::identity(), &mut from_svg.as_mut());
            let worst = from_svg
                .data()
                .iter()
                .zip(px.data())
                .map(|(a, b)| a.abs_diff(*b))
                .max();
            assert!(
                worst <= Some(2),
                "t = {t}: SVG and pixels differ by {worst:?}"
            );
        }
    }
}
