//! Rendering tests: frames against resvg renders of the input files, the SVG blend against the
//! pixel blend, determinism.
//!
//! Pixel comparisons allow antialiasing differences: a channel may differ by at most
//! [`CHANNEL_TOL`] on all but [`OUTLIER_FRACTION`] of the pixels, and by at most
//! [`MAX_CHANNEL_DIFF`] anywhere (flattening moves edges by up to a quarter pixel, which changes
//! an edge pixel's coverage by up to a quarter). On failure an `expected | diff | actual` picture
//! is written to `target/crmorph-render-failures/NAME.png`.

use super::*;
use crate::artwork::{Binding, Item, Scene};
use crate::geometry::Point;
use tiny_skia::{Pixmap, Transform};

/// Per-channel difference allowed on almost every pixel.
const CHANNEL_TOL: u8 = 8;
/// Fraction of pixels allowed beyond [`CHANNEL_TOL`] (when flattening is fine enough not to
/// move edges visibly).
const OUTLIER_FRACTION: f64 = 0.005;
/// Per-channel difference allowed anywhere: a quarter pixel of coverage, plus rounding.
const MAX_CHANNEL_DIFF: u8 = 72;

/// A 4×4 PNG with four coloured quadrants, as a data URL.
fn png_data_url() -> String {
    let mut p = Pixmap::new(4, 4).unwrap();
    let cols = [[230, 57, 70], [42, 157, 143], [233, 196, 106], [38, 70, 83]];
    for (i, px) in p.pixels_mut().iter_mut().enumerate() {
        let (x, y) = (i % 4, i / 4);
        let c = cols[(y / 2) * 2 + x / 2];
        *px = tiny_skia::ColorU8::from_rgba(c[0], c[1], c[2], 255).premultiply();
    }
    format!(
        "data:image/png;base64,{}",
        crate::base64::encode(&p.encode_png().unwrap())
    )
}

/// The source drawing: gradients (linear in bbox units, radial with reflect), a round-joined
/// stroke, a transformed group with opacity, a dashed curved stroke, an image, and guides.
fn source_svg() -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="120" height="90" viewBox="0 0 120 90">
  <defs>
    <linearGradient id="sky" x1="0" y1="0" x2="0" y2="1"><stop offset="0" stop-color="#3b7dd8"/><stop offset="1" stop-color="#bde0fe" stop-opacity="0.8"/></linearGradient>
    <radialGradient id="sun" cx="0.4" cy="0.4" r="0.3" spreadMethod="reflect"><stop offset="0" stop-color="#fff3b0"/><stop offset="1" stop-color="#f4a259"/></radialGradient>
  </defs>
  <rect x="5" y="5" width="110" height="80" rx="8" fill="url(#sky)" stroke="#1d3557" stroke-width="3" stroke-linejoin="round"/>
  <circle cx="40" cy="38" r="18" fill="url(#sun)"/>
  <clipPath id="round"><circle cx="0" cy="0" r="19"/></clipPath>
  <g transform="translate(70 50) rotate(-15)" opacity="0.6" clip-path="url(#round)">
    <rect x="-20" y="-12" width="40" height="24" fill="#e63946"/>
    <rect x="-10" y="-20" width="20" height="30" fill="#2a9d8f" stroke="#000" stroke-width="1.5"/>
  </g>
  <path d="M10 80 Q 60 55 110 80" fill="none" stroke="#264653" stroke-width="4" stroke-linecap="round" stroke-dasharray="6 4"/>
  <g transform="translate(18 62) rotate(30) scale(1.8 0.6)"><circle r="6" fill="none" stroke="#6a040f" stroke-width="2.5" stroke-dasharray="3 2"/></g>
  <image x="88" y="8" width="20" height="20" xlink:href="{}"/>
  <g id="controls" style="display:none"><path id="boundary" d="M5 5 H115 V85 H5 Z" fill="magenta"/></g>
</svg>"##,
        png_data_url()
    )
}

/// The target drawing: different shapes and paint, same size.
const TARGET_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="90" viewBox="0 0 120 90">
  <defs><radialGradient id="g" cx="60" cy="45" r="50" gradientUnits="userSpaceOnUse"><stop offset="0" stop-color="#ffd166"/><stop offset="1" stop-color="#ef476f"/></radialGradient></defs>
  <ellipse cx="60" cy="45" rx="52" ry="38" fill="url(#g)" stroke="#073b4c" stroke-width="2.5"/>
  <g opacity="0.7"><polygon points="30,60 60,15 90,60" fill="#06d6a0" stroke="#118ab2" stroke-width="3" stroke-linejoin="bevel"/></g>
</svg>"##;

/// A grid mesh over a margin around the 120×90 view, and a bent copy of it.
fn meshes() -> (Vec<Point>, Vec<Point>, Vec<[u32; 3]>) {
    let (mut pts, tris) = crate::artwork::bind_tests::grid(14, 11, 140.0, 110.0);
    for p in &mut pts {
        *p -= Point::new(10.0, 10.0);
    }
    let c = Point::new(60.0, 45.0);
    let bent = pts
        .iter()
        .map(|p| {
            let r = glam::DMat2::from_angle(0.35 + 0.25 * (p.x - 60.0) / 70.0);
            c + r * (*p - c) * 0.9 + Point::new(4.0, -3.0)
        })
        .collect();
    (pts, bent, tris)
}

fn opts() -> FrameOptions {
    FrameOptions {
        view_box: (Point::ZERO, Point::new(120.0, 90.0)),
        size: (240, 180),
        background: None,
        max_pixels: crate::input::Limits::default().pixels,
    }
}

/// resvg's own render of an SVG file at `size`.
fn resvg_render(svg: &str, size: (u32, u32)) -> Pixmap {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).unwrap();
    let mut p = Pixmap::new(size.0, size.1).unwrap();
    let ts = Transform::from_scale(
        size.0 as f32 / tree.size().width(),
        size.1 as f32 / tree.size().height(),
    );
    resvg::render(&tree, ts, &mut p.as_mut());
    p
}

/// Compares two pixmaps within the stated tolerance; writes expected | diff | actual on failure.
fn assert_close(name: &str, expected: &Pixmap, actual: &Pixmap, outlier_fraction: f64) {
    assert_close_with(
        name,
        expected,
        actual,
        CHANNEL_TOL,
        outlier_fraction,
        MAX_CHANNEL_DIFF,
    )
}

/// At most `fraction` of the pixels differ by more than `channel_tol` in some channel, and none
/// by more than `max_diff`.
fn assert_close_with(
    name: &str,
    expected: &Pixmap,
    actual: &Pixmap,
    channel_tol: u8,
    fraction: f64,
    max_diff: u8,
) {
    assert_eq!(
        (expected.width(), expected.height()),
        (actual.width(), actual.height())
    );
    let (e, a) = (expected.data(), actual.data());
    let mut outliers = 0usize;
    let mut worst = 0u8;
    let mut diff = Pixmap::new(expected.width(), expected.height()).unwrap();
    for (i, (pe, pa)) in e.chunks(4).zip(a.chunks(4)).enumerate() {
        let d = pe
            .iter()
            .zip(pa)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap();
        worst = worst.max(d);
        if d > channel_tol {
            outliers += 1;
        }
        let v = d.saturating_mul(3);
        diff.pixels_mut()[i] = tiny_skia::ColorU8::from_rgba(v, 0, 0, 255).premultiply();
    }
    let n = e.len() / 4;
    let ok = (outliers as f64) <= fraction * n as f64 && worst <= max_diff;
    if !ok {
        let (w, h) = (expected.width(), expected.height());
        let mut sheet = Pixmap::new(3 * w, h).unwrap();
        for (k, p) in [expected, &diff, actual].into_iter().enumerate() {
            sheet.draw_pixmap(
                (k as u32 * w) as i32,
                0,
                p.as_ref(),
                &tiny_skia::PixmapPaint::default(),
                Transform::identity(),
                None,
            );
        }
        let dir =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/crmorph-render-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = sheet.save_png(dir.join(format!("{name}.png")));
    }
    assert!(
        ok,
        "{name}: {outliers} of {n} pixels differ by more than {channel_tol} (allowed {fraction}), \
         worst {worst} (allowed {max_diff})"
    );
}

struct Fixture {
    src_bind: Binding,
    tgt_bind: Binding,
    src_mesh: Vec<Point>,
    tgt_mesh: Vec<Point>,
}

fn fixture() -> Fixture {
    fixture_at(opts().flatten_tolerance())
}

/// The fixture with curves flattened at `tol` user units.
fn fixture_at(tol: f64) -> Fixture {
    let (src_mesh, tgt_mesh, tris) = meshes();
    let src = Scene::from_svg("src.svg", &source_svg(), "controls").unwrap();
    let tgt = Scene::from_svg("tgt.svg", TARGET_SVG, "controls").unwrap();
    Fixture {
        src_bind: Binding::new(&src, &src_mesh, &tris, tol).unwrap(),
        tgt_bind: Binding::new(&tgt, &tgt_mesh, &tris, tol).unwrap(),
        src_mesh,
        tgt_mesh,
    }
}

impl Fixture {
    /// The mesh at t by linear blending (the interpolator's stand-in for these tests).
    fn at(&self, t: f64) -> Vec<Point> {
        self.src_mesh
            .iter()
            .zip(&self.tgt_mesh)
            .map(|(a, b)| a.lerp(*b, t))
            .collect()
    }

    fn warped(&self, t: f64) -> (Scene, Scene) {
        let v = self.at(t);
        (
            self.src_bind.warp(&v).unwrap(),
            self.tgt_bind.warp(&v).unwrap(),
        )
    }
}

#[test]
fn ends_render_like_the_input_files() {
    let o = opts();
    let f = fixture();
    // Frames 0 and 1 as an interpolator gives them: the rest meshes up to rounding.
    let near = |v: &[Point]| -> Vec<Point> { v.iter().map(|p| *p + Point::splat(1e-13)).collect() };
    let s0 = f.src_bind.place(&near(&f.src_mesh)).unwrap();
    let t0 = f.tgt_bind.place(&near(&f.src_mesh)).unwrap();
    let frame0 = frame_pixmap(&s0, &t0, 0.0, &o).unwrap();
    assert_close(
        "t0",
        &resvg_render(&source_svg(), o.size),
        &frame0,
        OUTLIER_FRACTION,
    );
    let s1 = f.src_bind.place(&near(&f.tgt_mesh)).unwrap();
    let t1 = f.tgt_bind.place(&near(&f.tgt_mesh)).unwrap();
    let frame1 = frame_pixmap(&s1, &t1, 1.0, &o).unwrap();
    assert_close(
        "t1",
        &resvg_render(TARGET_SVG, o.size),
        &frame1,
        OUTLIER_FRACTION,
    );
    // The end frames' SVG has no blend filter: it is the one drawing.
    let svg0 = frame_svg(&s0, &t0, 0.0, &o).unwrap();
    assert!(!svg0.contains("filter"));
    assert_close(
        "t0-svg",
        &resvg_render(&source_svg(), o.size),
        &resvg_render(&svg0, o.size),
        OUTLIER_FRACTION,
    );
    // Warped polylines (flattened at a quarter pixel) at the rest mesh: edges move by less than
    // a quarter pixel, so only pixels along curved edges differ: by more than 8 on at most 3% of
    // the pixels of this small, curve-heavy picture. resvg approximates the input's curves with
    // an error of its own (tiny-skia cuts them into lines), which can add to ours: by more than a
    // quarter coverage (64) on at most 0.5% of the pixels.
    for (name, bind, mesh, svg) in [
        ("t0-flat", &f.src_bind, &f.src_mesh, source_svg()),
        ("t1-flat", &f.tgt_bind, &f.tgt_mesh, TARGET_SVG.to_string()),
    ] {
        let w = bind.warp(mesh).unwrap();
        let frame = frame_pixmap(&w, &w, 0.0, &o).unwrap();
        let reference = resvg_render(&svg, o.size);
        assert_close_with(name, &reference, &frame, CHANNEL_TOL, 0.03, 255);
        assert_close_with(name, &reference, &frame, 64, 0.005, 255);
    }
}

#[test]
fn mid_frame_is_the_dissolve_and_opaque_where_both_are() {
    let f = fixture();
    let o = opts();
    let t = 0.37;
    let (s, g) = f.warped(t);
    let frame = frame_pixmap(&s, &g, t, &o).unwrap();
    // Each side rendered alone, as the frame writes it.
    let rs = super::raster::render_side(&s, &o).unwrap();
    let rt = super::raster::render_side(&g, &o).unwrap();
    let mut opaque_both = 0;
    for ((pf, ps), pt) in frame.pixels().iter().zip(rs.pixels()).zip(rt.pixels()) {
        // The target at opacity b over the source at opacity a, premultiplied.
        let (a, b) = super::dissolve(t);
        let cover = 1.0 - b * pt.alpha() as f64 / 255.0;
        let want = |x: u8, y: u8| (b * y as f64 + cover * a * x as f64).round() as i32;
        assert!((pf.red() as i32 - want(ps.red(), pt.red())).abs() <= 1);
        assert!((pf.alpha() as i32 - want(ps.alpha(), pt.alpha())).abs() <= 1);
        if ps.alpha() == 255 && pt.alpha() == 255 {
            opaque_both += 1;
            assert_eq!(pf.alpha(), 255, "no see-through where both are opaque");
        }
    }
    assert!(opaque_both > 1000, "the fixture overlaps: {opaque_both}");
    // CRMORPH_TEST_DUMP=DIR writes frames to look at.
    if let Ok(dir) = std::env::var("CRMORPH_TEST_DUMP") {
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        for t in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let (s, g) = f.warped(t);
            let o2 = FrameOptions {
                size: (480, 360),
                ..o
            };
            std::fs::write(
                dir.join(format!("frame_{t}.png")),
                frame_png(&s, &g, t, &o2).unwrap(),
            )
            .unwrap();
            std::fs::write(
                dir.join(format!("frame_{t}.svg")),
                frame_svg(&s, &g, t, &o2).unwrap(),
            )
            .unwrap();
        }
    }
}

#[test]
fn svg_frame_renders_like_the_raster_frame() {
    let f = fixture();
    let mut o = opts();
    o.background = Some(crate::artwork::Rgba {
        r: 250,
        g: 250,
        b: 240,
        a: 255,
    });
    for t in [0.0, 0.37, 0.8, 1.0] {
        let (s, g) = f.warped(t);
        let svg = frame_svg(&s, &g, t, &o).unwrap();
        assert_eq!(svg.contains("crmorph-target"), t != 0.0 && t != 1.0);
        let raster = frame_pixmap(&s, &g, t, &o).unwrap();
        assert_close(
            &format!("svg-vs-raster-{t}"),
            &raster,
            &resvg_render(&svg, o.size),
            OUTLIER_FRACTION,
        );
    }
}

#[test]
fn output_is_deterministic() {
    let f = fixture();
    let o = opts();
    let (s, g) = f.warped(0.5);
    let a = frame_svg(&s, &g, 0.5, &o).unwrap();
    let b = {
        let f2 = fixture();
        let (s2, g2) = f2.warped(0.5);
        frame_svg(&s2, &g2, 0.5, &o).unwrap()
    };
    assert_eq!(a, b);
    assert_eq!(
        frame_png(&s, &g, 0.5, &o).unwrap(),
        frame_png(&s, &g, 0.5, &o).unwrap()
    );
}

#[test]
fn warping_carries_strokes_gradients_and_images() {
    let f = fixture();
    // A uniform scale by 2 about the origin: everything doubles.
    let big: Vec<Point> = f.src_mesh.iter().map(|p| *p * 2.0).collect();
    let w = f.src_bind.warp(&big).unwrap();
    let rest = f.src_bind.warp(&f.src_mesh).unwrap();
    let (items_w, items_r) = (w.items(), rest.items());
    assert_eq!(items_w.len(), items_r.len());
    let mut seen = (0, 0, 0, 0);
    for (a, b) in items_w.iter().zip(&items_r) {
        match (a, b) {
            (Item::Path(a), Item::Path(b)) => {
                for (ea, eb) in a.path.elements().iter().zip(b.path.elements()) {
                    if let (Some(pa), Some(pb)) = (ea.end_point(), eb.end_point()) {
                        assert!((pa - (pb.to_vec2() * 2.0).to_point()).hypot() < 1e-9);
                    }
                }
                if let (Some(sa), Some(sb)) = (&a.stroke, &b.stroke) {
                    if let (Some(fa), Some(fb)) = (sa.frame, sb.frame) {
                        // A shaped pen: its frame scales, its width stays in frame units.
                        let want = kurbo::Affine::scale(2.0) * fb;
                        let d = (fa.as_coeffs().iter())
                            .zip(want.as_coeffs())
                            .map(|(x, y)| (x - y).abs())
                            .fold(0.0, f64::max);
                        assert!(d < 1e-9 && sa.width == sb.width);
                        continue;
                    }
                    assert!((sa.width - 2.0 * sb.width).abs() < 1e-9);
                    for (da, db) in sa.dashes.iter().zip(&sb.dashes) {
                        assert!((da - 2.0 * db).abs() < 1e-9);
                    }
                    seen.0 += 1;
                }
                if let (
                    Some(crate::artwork::Fill {
                        paint: crate::artwork::Paint::Gradient(ga),
                        ..
                    }),
                    Some(crate::artwork::Fill {
                        paint: crate::artwork::Paint::Gradient(gb),
                        ..
                    }),
                ) = (&a.fill, &b.fill)
                {
                    let want = kurbo::Affine::scale(2.0) * gb.transform;
                    let d = (ga.transform.as_coeffs().iter())
                        .zip(want.as_coeffs())
                        .map(|(x, y)| (x - y).abs())
                        .fold(0.0, f64::max);
                    assert!(d < 1e-9);
                    seen.1 += 1;
                }
            }
            (Item::Image(a), Item::Image(b)) => {
                // The texture grid is placed twice as large; every piece maps the image as
                // the reference placement scaled by 2.
                let want = kurbo::Affine::scale(2.0) * b.transform;
                let grid = a.grid.as_ref().expect("a warped image has its grid");
                let mut pieces = 0;
                for piece in grid.pieces(a) {
                    let m = piece.transform().unwrap();
                    let d = (m.as_coeffs().iter())
                        .zip(want.as_coeffs())
                        .map(|(x, y)| (x - y).abs())
                        .fold(0.0, f64::max);
                    assert!(d < 1e-9, "{m:?} vs {want:?}");
                    pieces += 1;
                }
                assert!(pieces >= 2);
                seen.2 += 1;
            }
            (Item::Group(a), Item::Group(b)) => {
                assert_eq!(a.opacity, b.opacity);
                assert_eq!(a.clip.is_some(), b.clip.is_some());
                if let (Some(ca), Some(cb)) = (&a.clip, &b.clip) {
                    let pa = ca.shapes[0].path.elements()[0].end_point().unwrap();
                    let pb = cb.shapes[0].path.elements()[0].end_point().unwrap();
                    assert!((pa - (pb.to_vec2() * 2.0).to_point()).hypot() < 1e-9);
                    seen.3 += 1;
                }
            }
            _ => panic!("structure differs"),
        }
    }
    assert_eq!(
        seen,
        (3, 2, 1, 1),
        "round strokes, gradient fills, images, clips"
    );
}

#[test]
fn png_round_trips() {
    let f = fixture();
    let o = opts();
    let (s, g) = f.warped(0.37);
    let p = frame_pixmap(&s, &g, 0.37, &o).unwrap();
    let bytes = frame_png(&s, &g, 0.37, &o).unwrap();
    let back = Pixmap::decode_png(&bytes).unwrap();
    assert_eq!((back.width(), back.height()), (240, 180));
    // Premultiply(demultiply(x)) may move a channel by one.
    for (a, b) in p.data().iter().zip(back.data()) {
        assert!(a.abs_diff(*b) <= 1);
    }
}

#[test]
fn bad_sizes_and_times_do_not_panic() {
    let f = fixture();
    let (s, g) = f.warped(0.5);
    let zero = FrameOptions {
        size: (0, 10),
        ..opts()
    };
    assert!(frame_pixmap(&s, &g, 0.5, &zero).is_err());
    assert!(frame_png(&s, &g, 0.5, &zero).is_err());
    let o = opts();
    // NaN is frame 0; out-of-range t clamps.
    assert_eq!(
        frame_svg(&s, &g, f64::NAN, &o).unwrap(),
        scene_svg(&s, &o).unwrap()
    );
    assert_eq!(
        frame_svg(&s, &g, 7.0, &o).unwrap(),
        scene_svg(&g, &o).unwrap()
    );
}
