//! Automatic mode over the icon fixtures (`fixtures/icons/`, real icons with no markup): every
//! pair morphs, the ends are the input drawings, the meshes stay flip-free, and the matched
//! contours move as a designer expects — a rotated copy turns rigidly, a logo flipped upside
//! down turns instead of shrinking through zero, a circle becomes a square without twisting.

use std::path::{Path, PathBuf};

use crmorph::artwork::Scene;
use crmorph::auto::build_auto;
use crmorph::compatible::MorphOptions;
use crmorph::export::Morph;
use crmorph::geometry::{polygon_area, Point, SimilarityFit};
use crmorph::mesh::count_inverted;
use crmorph::render::FrameOptions;
use crmorph::rigid::{Interpolator, Method};

use crate::common::{fixtures, open, pixels_off_input};

fn icon_pairs() -> Vec<(String, PathBuf, PathBuf)> {
    let mut v: Vec<_> = std::fs::read_dir(fixtures().join("icons"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("source.svg").exists())
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                p.join("source.svg"),
                p.join("target.svg"),
            )
        })
        .collect();
    v.sort();
    assert!(
        v.len() >= 12,
        "expected a dozen icon pairs, found {}",
        v.len()
    );
    v
}

struct Auto {
    morph: Morph,
    /// Feature curves (name, mesh vertex chain, closed).
    features: Vec<(String, Vec<u32>, bool)>,
}

fn auto(s: &Path, t: &Path) -> Auto {
    let (ds, dt) = (open(s), open(t));
    let scene = crate::common::scene_of;
    let (ss, ts) = (scene(s), scene(t));
    let (c, _report, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", s.display()));
    let m = &c.meshes;
    let features = m
        .curves
        .iter()
        .filter(|k| k.name != "boundary")
        .map(|k| (k.name.clone(), k.vertices.clone(), k.closed))
        .collect();
    let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    // Icons are tiny (16–48 units): render at 192 px so that one antialiased edge pixel is not
    // a large share of the picture.
    let mut frame = FrameOptions::for_scene(&ss);
    frame.size = (192, 192);
    let morph = Morph::new(c.meshes, interp, &ss, &ts, frame).unwrap();
    Auto { morph, features }
}

fn chain(v: &[Point], idx: &[u32]) -> Vec<Point> {
    idx.iter().map(|&i| v[i as usize]).collect()
}

#[test]
fn every_icon_pair_morphs_flip_free_with_exact_ends() {
    for (name, s, t) in icon_pairs() {
        let a = auto(&s, &t);
        let m = a.morph.meshes();
        let ts: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
        let frames = a.morph.vertex_frames(&crmorph::export::Timeline {
            frames: 41,
            ..Default::default()
        });
        assert_eq!(frames.len(), ts.len());
        let inverted: usize = frames.iter().map(|f| count_inverted(&m.triangles, f)).sum();
        eprintln!("{name}: {} features", a.features.len());
        assert_eq!(inverted, 0, "{name}: inverted triangles over 41 frames");
        assert_eq!(
            count_inverted(&m.triangles, &m.target),
            0,
            "{name}: target mesh"
        );
        // The ends render as the input files (within antialiasing).
        for (at, file) in [(0.0, &s), (1.0, &t)] {
            let (bad, n) = pixels_off_input(file, &a.morph.pixmap_at(at).unwrap());
            assert!(
                bad as f64 <= 0.005 * n as f64,
                "{name} at t = {at}: {bad} pixels differ from the input"
            );
        }
    }
}

/// Best-fit rotation (degrees) and relative residual of `b` against `a` by a similarity.
fn fit(a: &[Point], b: &[Point]) -> (f64, f64) {
    let f = SimilarityFit::new(a, b);
    let residual =
        (f.to_spread - (f.dot * f.dot + f.cross * f.cross) / f.from_spread).max(0.0) / f.to_spread;
    (f.cross.atan2(f.dot).to_degrees(), residual.sqrt())
}

#[test]
fn a_circle_becomes_a_square_without_twisting() {
    let dir = fixtures().join("icons/circle-to-square");
    let a = auto(&dir.join("source.svg"), &dir.join("target.svg"));
    assert_eq!(a.features.len(), 1);
    let m = a.morph.meshes();
    let (angle, _) = fit(
        &chain(&m.source, &a.features[0].1),
        &chain(&m.target, &a.features[0].1),
    );
    eprintln!("circle → square: the correspondence turns by {angle:.2}°");
    assert!(angle.abs() < 5.0, "{angle}");
}

#[test]
fn a_rotated_copy_turns_rigidly_and_a_flipped_logo_turns_instead_of_shrinking() {
    let dir = fixtures().join("icons/nike-rotated");
    let a = auto(&dir.join("source.svg"), &dir.join("target.svg"));
    let m = a.morph.meshes();
    let (_, idx, _) = &a.features[0];
    let src = chain(&m.source, idx);
    let mut worst = 0.0f64;
    for i in 1..10 {
        let t = i as f64 / 10.0;
        let (angle, residual) = fit(&src, &chain(&a.morph.vertices_at(t), idx));
        eprintln!("nike at t = {t}: turned {angle:.2}°, off a similarity by {residual:.4}");
        worst = worst.max(residual);
        assert!((angle.abs() - 90.0 * t).abs() < 10.0, "t = {t}: {angle}°");
    }
    assert!(
        worst < 0.05,
        "the rotated copy is not moved rigidly: {worst}"
    );
    // The apple turned upside down: its area never dips, it turns half round.
    let dir = fixtures().join("icons/apple-flipped");
    let a = auto(&dir.join("source.svg"), &dir.join("target.svg"));
    let m = a.morph.meshes();
    let area = |v: &[Point]| -> f64 {
        a.features
            .iter()
            .filter(|f| f.2)
            .map(|f| polygon_area(&chain(v, &f.1)).abs())
            .sum()
    };
    let (a0, a1) = (area(&m.source), area(&m.target));
    for i in 1..10 {
        let t = i as f64 / 10.0;
        let ratio = area(&a.morph.vertices_at(t)) / ((1.0 - t) * a0 + t * a1);
        assert!(ratio > 0.9, "apple at t = {t}: area {ratio} of the blend");
    }
}

#[test]
fn matched_paths_morph_as_one_crisp_shape() {
    for name in ["circle-to-square", "heart-to-star", "ok-to-rating"] {
        let dir = fixtures().join("icons").join(name);
        let (s, t) = (dir.join("source.svg"), dir.join("target.svg"));
        let (ds, dt) = (open(&s), open(&t));
        let scene = crate::common::scene_of;
        let (ss, ts) = (scene(&s), scene(&t));
        let (c, report, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default()).unwrap();
        assert!(
            !report.morphing.is_empty(),
            "{name}: no path morphs as one shape"
        );
        let m = &c.meshes;
        let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        let mut frame = FrameOptions::for_scene(&ss);
        frame.size = (192, 192);
        let plain = Morph::new(
            c.meshes.clone(),
            Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap(),
            &ss,
            &ts,
            frame,
        )
        .unwrap();
        let morph =
            Morph::with_morphing_paths(c.meshes.clone(), interp, &ss, &ts, frame, report.morphing)
                .unwrap();
        // Translucent pixels: edges only when the shape morphs as one; a cross-fade leaves
        // half-covered regions where the two shapes differ.
        let translucent = |p: &tiny_skia::Pixmap| {
            p.pixels()
                .iter()
                .filter(|q| q.alpha() > 30 && q.alpha() < 225)
                .count() as f64
                / p.pixels().len() as f64
        };
        let (one, blend) = (
            translucent(&morph.pixmap_at(0.5).unwrap()),
            translucent(&plain.pixmap_at(0.5).unwrap()),
        );
        eprintln!(
            "{name}: translucent pixels at t = 0.5: {:.2} % as one shape, {:.2} % blended",
            100.0 * one,
            100.0 * blend
        );
        assert!(one < 0.02, "{name}: {one} translucent (blended: {blend})");
        // The ends stay the exact inputs; the animated SVG animates the one path's outline
        // and colour.
        assert_eq!(
            morph.pixmap_at(0.0).unwrap().data(),
            plain.pixmap_at(0.0).unwrap().data()
        );
        let svg = morph
            .animated_svg(&crmorph::export::Timeline {
                frames: 12,
                ..Default::default()
            })
            .unwrap();
        usvg::Tree::from_str(&svg, &usvg::Options::default()).unwrap();
        // ok-to-rating's badge is the same circle at both ends: it only changes colour.
        if name != "ok-to-rating" {
            assert!(
                svg.contains("attributeName=\"d\""),
                "{name}: outline animates"
            );
        }
        if name == "ok-to-rating" {
            assert!(svg.contains("attributeName=\"fill\""), "colours animate");
            // The disc's colour at t = 0.5 is the Oklab mix of green and red, not the sRGB
            // average a cross-fade gives.
            let fill = |sc: &Scene| match &sc.items()[0] {
                crmorph::artwork::Item::Path(p) => match &p.fill.as_ref().unwrap().paint {
                    crmorph::artwork::Paint::Color(c) => *c,
                    _ => panic!("solid fill"),
                },
                _ => panic!("a path first"),
            };
            let (a, b) = (fill(&ss), fill(&ts));
            let want = crmorph::color::mix(a, b, 0.5);
            let px = morph.pixmap_at(0.5).unwrap();
            let q = px.pixel(30, 96).unwrap().demultiply();
            let got = [q.red(), q.green(), q.blue()];
            let near = |x: u8, y: u8| x.abs_diff(y) <= 3;
            eprintln!("disc colour {got:?}, Oklab mix {want:?}");
            assert!(near(got[0], want.r) && near(got[1], want.g) && near(got[2], want.b));
            let avg = [(a.r as u16 + b.r as u16) / 2, (a.g as u16 + b.g as u16) / 2];
            assert!(
                avg[1].abs_diff(got[1] as u16) > 5,
                "distinguishable from the sRGB average"
            );
        }
    }
}

#[test]
fn matched_contours_keep_their_vertex_correspondence() {
    for (name, s, t) in icon_pairs() {
        let (ds, dt) = (open(&s), open(&t));
        let scene = crate::common::scene_of;
        let (c, _, ds, dt) =
            build_auto(&ds, &dt, &scene(&s), &scene(&t), &MorphOptions::default()).unwrap();
        let m = &c.meshes;
        let eps = 1e-6 * c.tolerances.diagonal;
        for curve in m.curves.iter().filter(|k| k.name != "boundary") {
            for (d, mesh) in [(&ds, &m.source), (&dt, &m.target)] {
                let f = d
                    .controls
                    .features
                    .iter()
                    .find(|f| f.id == curve.name)
                    .unwrap_or_else(|| panic!("{name}: {} has no feature", curve.name));
                let n = f.points.len();
                let edges = if f.closed { n } else { n - 1 };
                for &v in &curve.vertices {
                    let p = mesh[v as usize];
                    let off = (0..edges)
                        .map(|i| {
                            crmorph::geometry::point_segment_distance(
                                p,
                                f.points[i],
                                f.points[(i + 1) % n],
                            )
                            .0
                        })
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        off <= eps,
                        "{name}: {} vertex {v} is {off} off its contour",
                        curve.name
                    );
                }
            }
        }
    }
}

/// A pair's morph with its matched paths morphing as one shape (at 192 px), and the indices of
/// the source items that morph.
fn auto_morphing(name: &str) -> (Morph, Vec<usize>) {
    let dir = fixtures().join("icons").join(name);
    let (s, t) = (dir.join("source.svg"), dir.join("target.svg"));
    let scene = crate::common::scene_of;
    let (ss, ts) = (scene(&s), scene(&t));
    let (c, report, _, _) =
        build_auto(&open(&s), &open(&t), &ss, &ts, &MorphOptions::default()).unwrap();
    let m = &c.meshes;
    let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    let mut frame = FrameOptions::for_scene(&ss);
    frame.size = (192, 192);
    let items = report.morphing.iter().map(|p| p.source_item).collect();
    let morph =
        Morph::with_morphing_paths(c.meshes.clone(), interp, &ss, &ts, frame, report.morphing)
            .unwrap();
    (morph, items)
}

/// The share of pixels whose channels differ by more than 8 of 255.
fn share_off(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap) -> f64 {
    let off = a
        .pixels()
        .iter()
        .zip(b.pixels())
        .filter(|(p, q)| {
            p.red().abs_diff(q.red()) > 8
                || p.green().abs_diff(q.green()) > 8
                || p.blue().abs_diff(q.blue()) > 8
                || p.alpha().abs_diff(q.alpha()) > 8
        })
        .count();
    off as f64 / a.pixels().len() as f64
}

/// The share of pixels of `a` with a channel more than 8 of 255 outside that channel's range
/// over the 3×3 neighbourhood of the pixel in `b`: differences that moving an edge by less
/// than a pixel (a flattening or curve-fitting tolerance) cannot explain, such as a region
/// changing colour.
fn share_beyond_a_pixel(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap) -> f64 {
    let (w, h) = (a.width() as i64, a.height() as i64);
    let channels = |p: tiny_skia::PremultipliedColorU8| [p.red(), p.green(), p.blue(), p.alpha()];
    let mut off = 0;
    for y in 0..h {
        for x in 0..w {
            let p = channels(a.pixels()[(y * w + x) as usize]);
            let (mut lo, mut hi) = ([255u8; 4], [0u8; 4]);
            for (u, v) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (x + dx, y + dy))) {
                if (0..w).contains(&u) && (0..h).contains(&v) {
                    let q = channels(b.pixels()[(v * w + u) as usize]);
                    for c in 0..4 {
                        lo[c] = lo[c].min(q[c]);
                        hi[c] = hi[c].max(q[c]);
                    }
                }
            }
            if (0..4).any(|c| p[c] as i32 + 8 < lo[c] as i32 || p[c] as i32 > hi[c] as i32 + 8) {
                off += 1;
            }
        }
    }
    off as f64 / (w * h) as f64
}

/// Frames at t = 1e-4 and 1 − 1e-4 show the input drawings: strictly their edges differ by the
/// flattening tolerances (as they do without morphing paths), nothing else may — at most 0.5 %
/// of pixels beyond a pixel's edge shift.
fn no_pop_near_the_ends(morph: &Morph, name: &str) {
    for (near, end) in [(1e-4, 0.0), (1.0 - 1e-4, 1.0)] {
        let (a, b) = (
            morph.pixmap_at(near).unwrap(),
            morph.pixmap_at(end).unwrap(),
        );
        let off = share_beyond_a_pixel(&a, &b);
        eprintln!(
            "{name}: t = {near}: {:.3} % pixels off t = {end} by more than a pixel's edge shift \
             ({:.3} % strictly)",
            100.0 * off,
            100.0 * share_off(&a, &b)
        );
        assert!(off <= 0.005, "{name}: t = {near} pops: {off}");
    }
}

/// An SVG document rendered with resvg at `like`'s size.
fn render_svg(svg: &str, like: &tiny_skia::Pixmap) -> tiny_skia::Pixmap {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).unwrap();
    let mut out = tiny_skia::Pixmap::new(like.width(), like.height()).unwrap();
    let sx = like.width() as f32 / tree.size().width();
    let sy = like.height() as f32 / tree.size().height();
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(sx, sy),
        &mut out.as_mut(),
    );
    out
}

#[test]
fn in_between_frames_keep_the_inputs_paint_order() {
    // The badge's white minus lies over its body; the body morphs as one shape, the minus
    // (whose partner has two dots) cross-fades. Near the ends the frame is the input drawing:
    // the body must not cover the minus.
    let (morph, items) = auto_morphing("badge-minus-to-dots");
    assert_eq!(items, [0], "the body morphs, the detail above it does not");
    for name in ["badge-minus-to-dots", "ok-to-rating", "lock-to-unlock"] {
        let (morph, _) = auto_morphing(name);
        no_pop_near_the_ends(&morph, name);
        // The SVG frame (layers as filter groups) shows what the raster frame shows.
        for t in [0.3, 0.5] {
            let px = morph.pixmap_at(t).unwrap();
            let off = share_off(&render_svg(&morph.svg_at(t).unwrap(), &px), &px);
            eprintln!(
                "{name}: t = {t}: SVG vs raster {:.3} % pixels off",
                100.0 * off
            );
            assert!(
                off <= 0.005,
                "{name}: SVG and raster frames differ at {t}: {off}"
            );
        }
    }
    // Mid-morph the minus is still on top: the badge's centre stays light.
    let q = morph
        .pixmap_at(0.1)
        .unwrap()
        .pixel(96, 96)
        .unwrap()
        .demultiply();
    assert!(q.red() > 200 && q.green() > 200 && q.blue() > 200, "{q:?}");
    // The animated SVG stacks the same layers in every keyframe: the body, then the detail's
    // own blend group over it.
    let tl = crmorph::export::Timeline {
        frames: 9,
        ..Default::default()
    };
    let anim = morph.animated_svg(&tl).unwrap();
    usvg::Tree::from_str(&anim, &usvg::Options::default()).unwrap();
    assert_eq!(anim.matches("filter=\"url(#crmorph-blend)\"").count(), 1);
    assert_eq!(anim, morph.animated_svg(&tl).unwrap(), "deterministic");
}

#[test]
fn gradients_interpolate_on_paths_that_morph_as_one_shape() {
    let (morph, items) = auto_morphing("gradient-badge");
    assert_eq!(
        items,
        [0, 1],
        "body and highlight morph, both with gradients"
    );
    let svg = morph.svg_at(0.5).unwrap();
    assert!(svg.contains("<linearGradient") && svg.contains("<radialGradient"));
    // Unblended: the gradients are painted once, not cross-faded (no blend filter group).
    assert!(!svg.contains("crmorph-blend"), "nothing left to blend");
    no_pop_near_the_ends(&morph, "gradient-badge");
    for t in [0.25, 0.5, 0.75] {
        let px = morph.pixmap_at(t).unwrap();
        let off = share_off(&render_svg(&morph.svg_at(t).unwrap(), &px), &px);
        eprintln!(
            "gradient-badge: t = {t}: SVG vs raster {:.3} % pixels off",
            100.0 * off
        );
        assert!(off <= 0.005, "SVG and raster frames differ at {t}: {off}");
    }
    // Mid-morph the body's gradient still runs across it: its top-left and bottom-right
    // differ in colour, and both differ from either end's colours there.
    let mid = morph.pixmap_at(0.5).unwrap();
    let rgb = |p: &tiny_skia::Pixmap, x: u32, y: u32| {
        let q = p.pixel(x, y).unwrap().demultiply();
        [q.red(), q.green(), q.blue()]
    };
    let (tl, br) = (rgb(&mid, 56, 56), rgb(&mid, 136, 136));
    eprintln!("gradient-badge at t = 0.5: top left {tl:?}, bottom right {br:?}");
    let far = |a: [u8; 3], b: [u8; 3]| a.iter().zip(b).any(|(x, y)| x.abs_diff(y) > 30);
    assert!(far(tl, br), "the gradient runs across the body");
    let anim = morph
        .animated_svg(&crmorph::export::Timeline {
            frames: 12,
            ..Default::default()
        })
        .unwrap();
    usvg::Tree::from_str(&anim, &usvg::Options::default()).unwrap();
    assert!(
        anim.contains("attributeName=\"stop-color\""),
        "stops animate"
    );
}

/// The subpaths of a polygonal path (move-to / line-to / close).
fn subpaths(path: &kurbo::BezPath) -> Vec<Vec<Point>> {
    let mut out: Vec<Vec<Point>> = Vec::new();
    for el in path.elements() {
        match *el {
            kurbo::PathEl::MoveTo(p) => out.push(vec![Point::new(p.x, p.y)]),
            kurbo::PathEl::LineTo(p) => {
                if let Some(last) = out.last_mut() {
                    last.push(Point::new(p.x, p.y));
                }
            }
            _ => {}
        }
    }
    out
}

/// "e" → "c": the counter has no partner in the "c" (no contour tween can pair 2 contours with
/// 1). It closes inside the glyph, which morphs as one shape: the counter's area shrinks
/// steadily to nothing, it stays inside the glyph's outline in every frame, and the mid frame is
/// crisp (no half-faded counter).
#[test]
fn a_counter_closes_smoothly_into_a_glyph_without_one() {
    let dir = fixtures().join("icons").join("glyph-e-to-c");
    let (s, t) = (dir.join("source.svg"), dir.join("target.svg"));
    let scene = crate::common::scene_of;
    let (ss, ts) = (scene(&s), scene(&t));
    let (c, report, _, _) =
        build_auto(&open(&s), &open(&t), &ss, &ts, &MorphOptions::default()).unwrap();
    assert_eq!(report.morphing.len(), 1, "{report}");
    let m = &c.meshes;
    let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    let glyph = &report.morphing[0];
    let mut areas = Vec::new();
    for k in 0..=20 {
        let t = k as f64 / 20.0;
        let v = interp.at_vec(t);
        let parts = subpaths(&glyph.at(m, &v, t).path);
        assert_eq!(parts.len(), 2, "outline and counter");
        let (outline, counter) = (&parts[0], &parts[1]);
        let area = polygon_area(counter).abs();
        if area > 0.0 {
            for p in counter {
                assert!(
                    crmorph::geometry::point_in_polygon(*p, outline),
                    "t = {t}: the counter leaves the glyph at {p}"
                );
            }
        }
        areas.push(area / polygon_area(outline).abs());
    }
    eprintln!("counter area / glyph area: {areas:.4?}");
    assert!(areas[0] > 0.05, "the e's counter is there at t = 0");
    assert!(areas[20] < 1e-12, "and gone at t = 1");
    assert!(
        areas.windows(2).all(|w| w[1] < w[0]),
        "it shrinks steadily: {areas:?}"
    );
    let mut frame = FrameOptions::for_scene(&ss);
    frame.size = (192, 192);
    let morph = Morph::with_morphing_paths(
        c.meshes.clone(),
        interp,
        &ss,
        &ts,
        frame,
        report.morphing.clone(),
    )
    .unwrap();
    let mid = morph.pixmap_at(0.5).unwrap();
    let translucent = mid
        .pixels()
        .iter()
        .filter(|q| q.alpha() > 30 && q.alpha() < 225)
        .count() as f64
        / mid.pixels().len() as f64;
    assert!(translucent < 0.02, "{translucent}");
}

/// Marked-up drawings: an artwork path that is its own boundary or feature curve in both files
/// morphs as one shape too. Over the marked fixtures: which paths do, frames near the ends are
/// the input drawings (no pop, paint order kept), SVG and raster frames agree, and the
/// leaf's boundary colour at t = ½ is an Oklab mix rather than a cross-fade.
#[test]
fn marked_up_boundary_and_feature_artwork_morphs_as_one_shape() {
    use crmorph::auto::geometric::named_morphing_paths;
    let mut total = 0;
    for name in [
        "gourd",
        "leaf-to-butterfly",
        "star-to-blob",
        "u-to-s",
        "dancer",
    ] {
        let dir = fixtures().join(name);
        let (s, t) = (dir.join("source.svg"), dir.join("target.svg"));
        let (ds, dt) = (open(&s), open(&t));
        let scene = crate::common::scene_of;
        let (ss, ts) = (scene(&s), scene(&t));
        let c = crmorph::compatible::build(&ds, &dt, &MorphOptions::default()).unwrap();
        let paths = named_morphing_paths(&ss, &ts, &c);
        let ids: Vec<String> = paths
            .iter()
            .map(|p| c.pairs[p.curves[0]].id.clone())
            .collect();
        eprintln!("{name}: {ids:?} morph as one shape");
        total += paths.len();
        let m = &c.meshes;
        let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        let mut frame = FrameOptions::for_scene(&ss);
        frame.size = (192, 192);
        let morph =
            Morph::with_morphing_paths(c.meshes.clone(), interp, &ss, &ts, frame, paths).unwrap();
        no_pop_near_the_ends(&morph, name);
        let px = morph.pixmap_at(0.5).unwrap();
        let off = share_off(&render_svg(&morph.svg_at(0.5).unwrap(), &px), &px);
        assert!(off <= 0.005, "{name}: SVG and raster differ: {off}");
        if name == "star-to-blob" {
            assert_eq!(ids, ["boundary"]);
            // The star's yellow and the blob's red-orange meet in Oklab at t = ½.
            let fill = |sc: &Scene| match &sc.items()[0] {
                crmorph::artwork::Item::Path(p) => match &p.fill.as_ref().unwrap().paint {
                    crmorph::artwork::Paint::Color(c) => *c,
                    other => panic!("{other:?}"),
                },
                other => panic!("{other:?}"),
            };
            let want = crmorph::color::mix(fill(&ss), fill(&ts), 0.5);
            let q = px.pixel(96, 96).unwrap().demultiply();
            let near = |a: u8, b: u8| a.abs_diff(b) <= 2;
            assert!(
                near(q.red(), want.r) && near(q.green(), want.g) && near(q.blue(), want.b),
                "{q:?} vs {want:?}"
            );
        }
    }
    assert!(
        total >= 5,
        "marked fixtures' own boundaries and features morph as one"
    );
}

/// Automatic mode's boundary is a padded frame around the icon, so the area rule keeps the area
/// the matched artwork covers (`Compatible::area_region`: the triangles inside closed outline
/// features), not the frame's: that area follows a similarity's, `((1 − t)·√A₀ + t·√A₁)²`, in
/// every frame.
#[test]
fn automatic_mode_keeps_the_artworks_area_not_the_frames() {
    use crmorph::quality::area;
    let mut checked = 0;
    for (name, s, t) in icon_pairs() {
        let (ds, dt) = (open(&s), open(&t));
        let scene = crate::common::scene_of;
        let (c, _, _, _) =
            build_auto(&ds, &dt, &scene(&s), &scene(&t), &MorphOptions::default()).unwrap();
        let Some(region) = &c.area_region else {
            continue;
        };
        let m = &c.meshes;
        assert!(
            region.len() < m.triangles.len(),
            "{name}: the frame is outside"
        );
        let it =
            Interpolator::with_area_region(&m.source, &m.target, &m.triangles, region).unwrap();
        let (r0, r1) = (
            area(region, &m.source).sqrt(),
            area(region, &m.target).sqrt(),
        );
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let want = ((1.0 - t) * r0 + t * r1).powi(2);
            let got = area(region, &it.at_vec(t));
            assert!(
                (got / want - 1.0).abs() < 1e-9,
                "{name}: t = {t}: {got} vs {want}"
            );
        }
        checked += 1;
    }
    assert!(checked >= 10, "{checked} pairs with a filled region");
}

/// An anchor in the plain files still pins the correspondence in automatic mode: the circle's
/// top is tied to the square's right side, a quarter turn from where crmorph would put it.
#[test]
fn anchors_override_the_automatic_correspondence() {
    let dir = fixtures().join("icons").join("circle-to-square");
    let with_anchor = |file: &str, x: f64, y: f64| {
        let svg = std::fs::read_to_string(dir.join(file)).unwrap();
        svg.replace(
            "</svg>",
            &format!(
                "<g id=\"controls\"><circle id=\"anchor-turn\" cx=\"{x}\" cy=\"{y}\" r=\"0.1\"/></g></svg>"
            ),
        )
    };
    let (src, tgt) = (
        with_anchor("source.svg", 8.0, 0.0),
        with_anchor("target.svg", 16.0, 8.0),
    );
    let o = crmorph::drawing::ReadOptions::default();
    let ds = crmorph::drawing::Drawing::from_str("circle.svg", &src, &o).unwrap();
    let dt = crmorph::drawing::Drawing::from_str("square.svg", &tgt, &o).unwrap();
    assert!(
        crmorph::auto::is_unmarked(&ds),
        "anchors alone keep automatic mode"
    );
    let ss = Scene::from_svg("circle.svg", &src, "controls").unwrap();
    let ts = Scene::from_svg("square.svg", &tgt, "controls").unwrap();
    let (c, report, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default()).unwrap();
    assert_eq!(report.features.len(), 1, "{report}");
    let m = &c.meshes;
    let curve = m.curves.iter().find(|k| k.name != "boundary").unwrap();
    let top = curve
        .vertices
        .iter()
        .min_by(|&&a, &&b| {
            let d = |v: u32| m.source[v as usize].distance(Point::new(8.0, 0.0));
            d(a).total_cmp(&d(b))
        })
        .copied()
        .unwrap();
    let there = m.target[top as usize];
    assert!(
        there.distance(Point::new(16.0, 8.0)) < 0.2,
        "the circle's top goes to {there}"
    );
}

/// When two features touch, the one with the shorter outline is the one dropped: the lock's
/// shackle ends on its body, and the body (item 1) keeps its crisp morph while the shackle's
/// changing leg cross-fades.
#[test]
fn of_two_touching_features_the_smaller_is_dropped() {
    let (_, items) = auto_morphing("lock-to-unlock");
    assert!(
        items.contains(&1),
        "the body morphs as one shape: {items:?}"
    );
    assert!(!items.contains(&0), "the shackle is blended: {items:?}");
}
