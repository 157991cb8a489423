//! Automatic mode over the icon fixtures (`fixtures/icons/`, real icons with no markup) and a
//! fixed sample of the random icon corpus (`fixtures/corpus/`, drawn with a seed by
//! `tools/corpus`): every pair morphs with one compatible triangulation per shape, the ends are
//! the input drawings, no frame inverts a triangle, the in-between frames are crisp shapes
//! rather than cross-fades, and shapes move as a designer expects — a rotated copy turns
//! rigidly, a circle becomes a square without twisting, parts turn together, shapes without a
//! partner shrink away, strokes stay strokes. Assertions are properties, not coordinates.

use std::path::{Path, PathBuf};

use crmorph::artwork::Scene;
use crmorph::auto::{build_auto, AutoReport};
use crmorph::compatible::{Compatible, MorphOptions};
use crmorph::export::Morph;
use crmorph::geometry::{polygon_area, Point, SimilarityFit};
use crmorph::mesh::{count_inverted, CurveKind};
use crmorph::render::FrameOptions;
use crmorph::rigid::Method;

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

/// The 40 pairs of the random corpus sample (`fixtures/corpus/pairs.json`).
fn corpus_pairs() -> Vec<(String, PathBuf, PathBuf)> {
    let dir = fixtures().join("corpus");
    let text = std::fs::read_to_string(dir.join("pairs.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let pairs: Vec<_> = v["pairs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["id"].as_str().unwrap().to_string(),
                dir.join(p["source"].as_str().unwrap()),
                dir.join(p["target"].as_str().unwrap()),
            )
        })
        .collect();
    assert_eq!(pairs.len(), 40, "the sample has 40 pairs");
    pairs
}

/// A pair built as the CLI builds it: automatic meshes, the disc interpolation with parts, the
/// artwork bound, the matched paths morphing as one shape; frames at 192 px.
struct Auto {
    c: Compatible,
    report: AutoReport,
    morph: Morph,
    source: Scene,
}

fn auto_of(s: &Path, t: &Path) -> Auto {
    let scene = crate::common::scene_of;
    let (ss, ts) = (scene(s), scene(t));
    let (c, report, _, _) = build_auto(&open(s), &open(t), &ss, &ts, &MorphOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", s.display()));
    let interp = c.interpolator(Method::Disc).unwrap();
    // Icons are tiny (16–256 units): render at 192 px so that one antialiased edge pixel is
    // not a large share of the picture.
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
    Auto {
        c,
        report,
        morph,
        source: ss,
    }
}

fn auto(name: &str) -> Auto {
    let dir = fixtures().join("icons").join(name);
    auto_of(&dir.join("source.svg"), &dir.join("target.svg"))
}

fn chain(v: &[Point], idx: &[u32]) -> Vec<Point> {
    idx.iter().map(|&i| v[i as usize]).collect()
}

/// The mesh curves that are shapes' outlines (not the still frame).
fn outlines(c: &Compatible) -> Vec<&crmorph::MeshCurve> {
    c.meshes
        .curves
        .iter()
        .filter(|k| k.kind == CurveKind::Boundary && k.name != "still-frame")
        .collect()
}

/// Best-fit rotation (degrees) and relative residual of `b` against `a` by a similarity.
fn fit(a: &[Point], b: &[Point]) -> (f64, f64) {
    let f = SimilarityFit::new(a, b);
    let residual =
        (f.to_spread - (f.dot * f.dot + f.cross * f.cross) / f.from_spread).max(0.0) / f.to_spread;
    (f.cross.atan2(f.dot).to_degrees(), residual.sqrt())
}

/// Ghost of a frame, as the corpus benchmark measures it (`tools/corpus/README.md`): of the inked
/// pixels over white (luma < 250), the share with luma in [40, 215], leaving out pixels whose
/// 3×3 neighbourhood holds both luma < 40 and > 215 (antialiased edges).
fn ghost(p: &tiny_skia::Pixmap) -> f64 {
    let (w, h) = (p.width() as i64, p.height() as i64);
    let luma: Vec<f64> = p
        .pixels()
        .iter()
        .map(|q| {
            let q = q.demultiply();
            let a = q.alpha() as f64 / 255.0;
            let over = |c: u8| c as f64 * a + 255.0 * (1.0 - a);
            0.2126 * over(q.red()) + 0.7152 * over(q.green()) + 0.0722 * over(q.blue())
        })
        .collect();
    let (mut inked, mut grey) = (0usize, 0usize);
    for y in 0..h {
        for x in 0..w {
            let l = luma[(y * w + x) as usize];
            let (mut dark, mut light) = (false, false);
            for (u, v) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (x + dx, y + dy))) {
                if (0..w).contains(&u) && (0..h).contains(&v) {
                    let m = luma[(v * w + u) as usize];
                    dark |= m < 40.0;
                    light |= m > 215.0;
                }
            }
            if dark && light {
                continue;
            }
            if l < 250.0 {
                inked += 1;
                if (40.0..=215.0).contains(&l) {
                    grey += 1;
                }
            }
        }
    }
    if inked == 0 {
        0.0
    } else {
        grey as f64 / inked as f64
    }
}

/// Every frame at t = k/n inverts no triangle; the ends render as the input files.
fn flip_free_with_exact_ends(name: &str, a: &Auto, s: &Path, t: &Path, n: usize) {
    let m = a.morph.meshes();
    let frames = a.morph.vertex_frames(&crmorph::export::Timeline {
        frames: n + 1,
        ..Default::default()
    });
    let inverted: usize = frames.iter().map(|f| count_inverted(&m.triangles, f)).sum();
    assert_eq!(
        inverted,
        0,
        "{name}: inverted triangles over {} frames",
        n + 1
    );
    assert_eq!(
        count_inverted(&m.triangles, &m.target),
        0,
        "{name}: target mesh"
    );
    for (at, file) in [(0.0, s), (1.0, t)] {
        let (bad, total) = pixels_off_input(file, &a.morph.pixmap_at(at).unwrap());
        assert!(
            bad as f64 <= 0.005 * total as f64,
            "{name} at t = {at}: {bad} pixels differ from the input"
        );
    }
}

#[test]
fn every_icon_pair_morphs_flip_free_with_exact_ends() {
    for (name, s, t) in icon_pairs() {
        let a = auto_of(&s, &t);
        eprintln!("{name}: {}", a.report);
        flip_free_with_exact_ends(&name, &a, &s, &t, 40);
    }
}

/// The random corpus sample: every pair morphs, flip-free, with exact ends, and its middle
/// frames are crisp shapes (ghost under 0.10 at t = ¼, ½, ¾; the issue's target is 97 % of pairs
/// and the benchmark's last run made every one of these crisp, so every one must be).
#[test]
fn the_random_corpus_sample_morphs_crisply() {
    let mut worst = (0.0f64, String::new());
    for (name, s, t) in corpus_pairs() {
        let a = auto_of(&s, &t);
        flip_free_with_exact_ends(&name, &a, &s, &t, 20);
        for at in [0.25, 0.5, 0.75] {
            let g = ghost(&a.morph.pixmap_at(at).unwrap());
            if g > worst.0 {
                worst = (g, format!("{name} at t = {at}"));
            }
            assert!(g < 0.10, "{name} at t = {at}: ghost {g:.3}: {}", a.report);
        }
    }
    eprintln!("corpus sample: worst ghost {:.3} ({})", worst.0, worst.1);
}

#[test]
fn a_circle_becomes_a_square_without_twisting() {
    let a = auto("circle-to-square");
    let o = outlines(&a.c);
    assert_eq!(o.len(), 1);
    let m = &a.c.meshes;
    let (angle, _) = fit(
        &chain(&m.source, &o[0].vertices),
        &chain(&m.target, &o[0].vertices),
    );
    eprintln!("circle → square: the correspondence turns by {angle:.2}°");
    assert!(angle.abs() < 5.0, "{angle}");
}

#[test]
fn a_rotated_copy_turns_rigidly_and_a_flipped_logo_turns_instead_of_shrinking() {
    let a = auto("nike-rotated");
    let idx = &outlines(&a.c)[0].vertices;
    let src = chain(&a.c.meshes.source, idx);
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
    let a = auto("apple-flipped");
    let curves = outlines(&a.c);
    let area = |v: &[Point]| -> f64 {
        curves
            .iter()
            .map(|k| polygon_area(&chain(v, &k.vertices)).abs())
            .sum()
    };
    let m = &a.c.meshes;
    let (a0, a1) = (area(&m.source), area(&m.target));
    for i in 1..10 {
        let t = i as f64 / 10.0;
        let ratio = area(&a.morph.vertices_at(t)) / ((1.0 - t) * a0 + t * a1);
        assert!(ratio > 0.9, "apple at t = {t}: area {ratio} of the blend");
    }
}

/// Translucent pixels of a frame: edges only when its shapes morph; a cross-fade leaves
/// half-covered regions where the two drawings differ.
fn translucent(p: &tiny_skia::Pixmap) -> f64 {
    p.pixels()
        .iter()
        .filter(|q| q.alpha() > 30 && q.alpha() < 225)
        .count() as f64
        / p.pixels().len() as f64
}

#[test]
fn matched_paths_morph_as_one_crisp_shape() {
    for name in [
        "circle-to-square",
        "heart-to-star",
        "ok-to-rating",
        "github-to-gitlab",
        "sun-to-moon",
        "grid-to-square",
        "menu-to-x",
    ] {
        let a = auto(name);
        assert!(
            !a.report.morphing.is_empty(),
            "{name}: no path morphs as one shape"
        );
        let mid = a.morph.pixmap_at(0.5).unwrap();
        let share = translucent(&mid);
        eprintln!("{name}: {:.2} % translucent pixels at t = ½", 100.0 * share);
        assert!(share < 0.02, "{name}: {share} translucent: {}", a.report);
        let svg = a
            .morph
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
        } else {
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
            let target = crate::common::scene_of(&fixtures().join("icons/ok-to-rating/target.svg"));
            let (x, y) = (fill(&a.source), fill(&target));
            let want = crmorph::color::mix(x, y, 0.5);
            let q = mid.pixel(30, 96).unwrap().demultiply();
            let got = [q.red(), q.green(), q.blue()];
            let near = |p: u8, r: u8| p.abs_diff(r) <= 3;
            eprintln!("disc colour {got:?}, Oklab mix {want:?}");
            assert!(near(got[0], want.r) && near(got[1], want.g) && near(got[2], want.b));
        }
    }
}

/// Every vertex of every shape's mesh curve lies on a contour of its drawing: the outlines the
/// meshes morph are the artwork's own.
#[test]
fn shape_curves_lie_on_the_artworks_contours() {
    for (name, s, t) in icon_pairs() {
        let a = auto_of(&s, &t);
        let target = crate::common::scene_of(&t);
        let eps = 1e-6 * a.c.tolerances.diagonal;
        for (scene, mesh) in [
            (&a.source, &a.c.meshes.source),
            (&target, &a.c.meshes.target),
        ] {
            let contours = crmorph::auto::contours::contours(
                scene,
                1e-3 * a.c.tolerances.diagonal,
                &crmorph::input::Limits::default(),
            )
            .unwrap();
            for curve in a.c.meshes.curves.iter().filter(|k| k.name != "still-frame") {
                for &v in &curve.vertices {
                    let p = mesh[v as usize];
                    let off = contours
                        .iter()
                        .flat_map(|c| {
                            let n = c.points.len();
                            let edges = if c.closed { n } else { n - 1 };
                            (0..edges).map(move |i| (c.points[i], c.points[(i + 1) % n]))
                        })
                        .map(|(x, y)| crmorph::geometry::point_segment_distance(p, x, y).0)
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

/// Frames at t = 1e-4 and 1 − 1e-4 show the input drawings: strictly their edges differ by the
/// flattening tolerances, nothing else may — at most 0.5 % of pixels beyond a pixel's edge
/// shift.
fn no_pop_near_the_ends(morph: &Morph, name: &str) {
    for (near, end) in [(1e-4, 0.0), (1.0 - 1e-4, 1.0)] {
        let (a, b) = (
            morph.pixmap_at(near).unwrap(),
            morph.pixmap_at(end).unwrap(),
        );
        let off = share_beyond_a_pixel(&a, &b);
        eprintln!(
            "{name}: t = {near}: {:.3} % pixels off t = {end} by more than an edge shift",
            100.0 * off
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

fn morphing_items(a: &Auto) -> Vec<usize> {
    a.report
        .morphing
        .iter()
        .filter_map(|p| p.source_item)
        .collect()
}

#[test]
fn in_between_frames_keep_the_inputs_paint_order() {
    // The badge's white minus lies over its body; both morph, the minus into one of the dots.
    // Near the ends the frame is the input drawing: the body must not cover the minus.
    let a = auto("badge-minus-to-dots");
    assert_eq!(
        morphing_items(&a),
        [0, 1],
        "body and detail morph: {}",
        a.report
    );
    for name in ["badge-minus-to-dots", "ok-to-rating", "lock-to-unlock"] {
        let b = auto(name);
        no_pop_near_the_ends(&b.morph, name);
        // The SVG frame shows what the raster frame shows.
        for t in [0.3, 0.5] {
            let px = b.morph.pixmap_at(t).unwrap();
            let off = share_off(&render_svg(&b.morph.svg_at(t).unwrap(), &px), &px);
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
    let q = a
        .morph
        .pixmap_at(0.1)
        .unwrap()
        .pixel(96, 96)
        .unwrap()
        .demultiply();
    assert!(q.red() > 200 && q.green() > 200 && q.blue() > 200, "{q:?}");
    let tl = crmorph::export::Timeline {
        frames: 9,
        ..Default::default()
    };
    let anim = a.morph.animated_svg(&tl).unwrap();
    usvg::Tree::from_str(&anim, &usvg::Options::default()).unwrap();
    assert!(
        !anim.contains("crmorph-target"),
        "nothing left to cross-fade"
    );
    assert_eq!(anim, a.morph.animated_svg(&tl).unwrap(), "deterministic");
}

#[test]
fn gradients_interpolate_on_paths_that_morph_as_one_shape() {
    let a = auto("gradient-badge");
    assert_eq!(
        morphing_items(&a),
        [0, 1],
        "body and highlight morph, both with gradients"
    );
    let svg = a.morph.svg_at(0.5).unwrap();
    assert!(svg.contains("<linearGradient") && svg.contains("<radialGradient"));
    assert!(!svg.contains("crmorph-target"), "nothing left to blend");
    no_pop_near_the_ends(&a.morph, "gradient-badge");
    for t in [0.25, 0.5, 0.75] {
        let px = a.morph.pixmap_at(t).unwrap();
        let off = share_off(&render_svg(&a.morph.svg_at(t).unwrap(), &px), &px);
        assert!(off <= 0.005, "SVG and raster frames differ at {t}: {off}");
    }
    // Mid-morph the body's gradient still runs across it.
    let mid = a.morph.pixmap_at(0.5).unwrap();
    let rgb = |x: u32, y: u32| {
        let q = mid.pixel(x, y).unwrap().demultiply();
        [q.red(), q.green(), q.blue()]
    };
    let (tl, br) = (rgb(56, 56), rgb(136, 136));
    let far = |p: [u8; 3], q: [u8; 3]| p.iter().zip(q).any(|(x, y)| x.abs_diff(y) > 30);
    assert!(
        far(tl, br),
        "the gradient runs across the body: {tl:?} {br:?}"
    );
    let anim = a
        .morph
        .animated_svg(&crmorph::export::Timeline {
            frames: 12,
            ..Default::default()
        })
        .unwrap();
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
/// steadily, linearly, to nothing, and it stays inside the glyph's outline in every frame.
#[test]
fn a_counter_closes_smoothly_into_a_glyph_without_one() {
    let a = auto("glyph-e-to-c");
    assert_eq!(a.report.morphing.len(), 1, "{}", a.report);
    let interp = a.c.interpolator(Method::Disc).unwrap();
    let glyph = &a.report.morphing[0];
    let m = &a.c.meshes;
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
        areas.push(area);
    }
    eprintln!("counter area: {areas:.4?}");
    assert!(areas[0] > 0.0 && areas[20] < 1e-12 * areas[0]);
    assert!(
        areas.windows(2).all(|w| w[1] < w[0]),
        "it shrinks steadily: {areas:?}"
    );
    // Its area moves linearly (the shrink is √(1 − t)), as the rest of the morph's does.
    let half = areas[10] / areas[0];
    assert!(
        (half - 0.5).abs() < 0.15,
        "half way the counter has {half} of its area"
    );
}

/// Marked-up drawings: an artwork path that is its own boundary or feature curve in both files
/// morphs as one shape too.
#[test]
fn marked_up_boundary_and_feature_artwork_morphs_as_one_shape() {
    use crmorph::morphing::named_morphing_paths;
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
        let interp = c.interpolator(Method::Disc).unwrap();
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

/// Every shape keeps the area a similarity would give it, `((1 − t)·√A₀ + t·√A₁)²` (the area
/// rule, per part), and the still frame does not move.
#[test]
fn every_shape_keeps_a_similaritys_area_and_the_still_frame_stays() {
    use crmorph::quality::area;
    let mut checked = 0;
    for (name, s, t) in icon_pairs() {
        let a = auto_of(&s, &t);
        let m = &a.c.meshes;
        let parts = m.parts.as_ref().expect("automatic meshes have parts");
        let interp = a.c.interpolator(Method::Disc).unwrap();
        for k in 0..parts.count {
            let tris: Vec<[u32; 3]> = m
                .triangles
                .iter()
                .zip(&parts.of_triangle)
                .filter(|(_, &p)| p == k)
                .map(|(t, _)| *t)
                .collect();
            if tris.is_empty() {
                continue;
            }
            let (r0, r1) = (area(&tris, &m.source).sqrt(), area(&tris, &m.target).sqrt());
            for i in 0..=10 {
                let t = i as f64 / 10.0;
                let v = interp.at_vec(t);
                let got = area(&tris, &v);
                if Some(k) == parts.still {
                    let moved = tris
                        .iter()
                        .flatten()
                        .map(|&x| v[x as usize].distance(m.source[x as usize]))
                        .fold(0.0, f64::max);
                    assert!(
                        moved < 1e-9 * a.c.tolerances.diagonal,
                        "{name}: the still frame moves"
                    );
                } else {
                    let want = ((1.0 - t) * r0 + t * r1).powi(2);
                    assert!(
                        (got / want - 1.0).abs() < 1e-9,
                        "{name} part {k}: t = {t}: {got} vs {want}"
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 20, "{checked} parts checked");
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
            &format!("<g id=\"controls\"><circle id=\"anchor-turn\" cx=\"{x}\" cy=\"{y}\" r=\"0.1\"/></g></svg>"),
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
    assert_eq!(report.shapes.len(), 1, "{report}");
    let m = &c.meshes;
    let curve = outlines(&c)[0];
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

/// The lock's shackle ends on its body's top edge: two touching contours, which one mesh could
/// not keep both of. Each is its own shape now, and both morph.
#[test]
fn touching_shapes_both_morph() {
    let a = auto("lock-to-unlock");
    let items = morphing_items(&a);
    assert!(
        items.contains(&0) && items.contains(&1),
        "shackle and body morph: {items:?}"
    );
}

/// A synthetic drawing: an SVG of `body` on a 100 × 100 view.
fn drawing(name: &str, body: &str) -> (crmorph::drawing::Drawing, Scene) {
    let svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100">{body}</svg>"#
    );
    let o = crmorph::drawing::ReadOptions::default();
    (
        crmorph::drawing::Drawing::from_str(name, &svg, &o).unwrap(),
        Scene::from_svg(name, &svg, "controls").unwrap(),
    )
}

fn build(a: &str, b: &str) -> (Compatible, AutoReport) {
    let (ds, ss) = drawing("a.svg", a);
    let (dt, ts) = drawing("b.svg", b);
    let (c, r, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default()).unwrap();
    (c, r)
}

/// Parts of one icon move as one figure: a square and a bar side by side, turned by 170° as a
/// pair (each part's own shape is symmetric enough that only the layout says which way it
/// turns), keep their distance apart all the way — their centroids follow the barycenter
/// mesh's rigid path, not straight lines through the middle — and both turn with the figure.
#[test]
fn parts_of_one_icon_turn_together() {
    let parts = r##"<rect x="16" y="43" width="14" height="14" fill="#000"/><rect x="70" y="30" width="10" height="40" fill="#000"/>"##;
    let turned = format!(r##"<g transform="rotate(170 50 50)">{parts}</g>"##);
    let (c, report) = build(parts, &turned);
    assert_eq!(report.shapes.len(), 2, "{report}");
    let interp = c.interpolator(Method::Disc).unwrap();
    let m = &c.meshes;
    let o = outlines(&c);
    let centre = |v: &[Point], k: usize| crmorph::geometry::centroid(&chain(v, &o[k].vertices));
    let gap0 = centre(&m.source, 0).distance(centre(&m.source, 1));
    let mut turns = Vec::new();
    for i in 1..10 {
        let t = i as f64 / 10.0;
        let v = interp.at_vec(t);
        let gap = centre(&v, 0).distance(centre(&v, 1));
        assert!(
            (gap / gap0 - 1.0).abs() < 0.1,
            "t = {t}: the parts close in ({gap} of {gap0})"
        );
        let turn = |k: usize| {
            fit(
                &chain(&m.source, &o[k].vertices),
                &chain(&v, &o[k].vertices),
            )
            .0
        };
        let (a, b) = (turn(0), turn(1));
        assert!(
            a * b > 0.0,
            "t = {t}: the parts turn opposite ways ({a}°, {b}°)"
        );
        turns.push(a);
    }
    eprintln!("turns: {turns:.1?}");
    assert!(
        (turns[4] - 85.0).abs() < 10.0,
        "half way the figure has turned: {}",
        turns[4]
    );
}

/// Shapes without a partner shrink into the nearest paired shape: of the grid's four squares
/// three have no partner in the one square; their area moves linearly to nothing and they end
/// at the paired square's edge.
#[test]
fn shapes_without_a_partner_shrink_into_a_paired_shape() {
    let a = auto("grid-to-square");
    assert_eq!(a.report.shapes.len(), 1, "{}", a.report);
    assert_eq!(a.report.lone.len(), 3, "{}", a.report);
    assert!(
        a.report.lone.iter().all(|l| l.shrinks && l.host.is_some()),
        "{}",
        a.report
    );
    let interp = a.c.interpolator(Method::Disc).unwrap();
    let m = &a.c.meshes;
    let host = outlines(&a.c)[0];
    let mut lone_area = Vec::new();
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        let v = interp.at_vec(t);
        let rings: Vec<Vec<Point>> = a
            .report
            .morphing
            .iter()
            .flat_map(|p| subpaths(&p.at(m, &v, t).path))
            .collect();
        let outline = chain(&v, &host.vertices);
        let total: f64 = rings.iter().map(|r| polygon_area(r).abs()).sum();
        lone_area.push(total - polygon_area(&outline).abs());
    }
    eprintln!("area of the shrinking squares: {lone_area:.3?}");
    assert!(lone_area[10].abs() < 1e-9 * lone_area[0]);
    let half = lone_area[5] / lone_area[0];
    assert!(
        (half - 0.5).abs() < 0.1,
        "half way they have {half} of their area"
    );
}

/// Stroke-only icons morph as strokes: menu → x keeps round-capped strokes of the same width,
/// the two paired bars turn into the cross's strokes and the third shrinks away, and no frame
/// has a fill.
#[test]
fn stroke_icons_morph_as_strokes() {
    let a = auto("menu-to-x");
    let interp = a.c.interpolator(Method::Disc).unwrap();
    let m = &a.c.meshes;
    let v = interp.at_vec(0.5);
    for p in &a.report.morphing {
        let item = p.at(m, &v, 0.5);
        assert!(item.fill.is_none(), "a stroke icon stays unfilled");
        let s = item.stroke.as_ref().expect("stroked");
        assert!(s.width > 0.0);
    }
    assert!(a
        .report
        .shapes
        .iter()
        .all(|s| s.rung == crmorph::auto::part::Rung::Stroke));
    assert_eq!(a.report.lone.len(), 1, "{}", a.report);
}

/// Unmatched artwork that cannot morph (here a caption in a half-transparent group, far from
/// the logo, in the source only) stays where it is and fades; it does not swing with the logo,
/// which turns.
#[test]
fn unmatched_artwork_stays_where_it_is() {
    let logo = |angle: f64, caption: &str| {
        format!(
            r##"<path transform="rotate({angle} 50 35)" d="M30 20 L70 20 L60 50 L40 50 Z" fill="#246"/>{caption}"##
        )
    };
    let caption =
        r##"<g opacity="0.5"><rect x="20" y="80" width="60" height="8" fill="#000"/></g>"##;
    let (ds, ss) = drawing("a.svg", &logo(0.0, caption));
    let (dt, ts) = drawing("b.svg", &logo(160.0, ""));
    let (c, report, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default()).unwrap();
    let interp = c.interpolator(Method::Disc).unwrap();
    let mut frame = FrameOptions::for_scene(&ss);
    frame.size = (100, 100);
    let morph =
        Morph::with_morphing_paths(c.meshes.clone(), interp, &ss, &ts, frame, report.morphing)
            .unwrap();
    let (s, _) = morph.scenes_at(0.5).unwrap();
    let bb = match &s.items()[2] {
        crmorph::artwork::Item::Path(p) => kurbo::Shape::bounding_box(&p.path),
        other => panic!("{other:?}"),
    };
    assert!(
        (bb.x0 - 20.0).abs() < 1e-6 && (bb.y0 - 80.0).abs() < 1e-6 && (bb.x1 - 80.0).abs() < 1e-6,
        "the caption moved: {bb:?}"
    );
}

/// The same turn with or without markup, the short way: a key-like shape turned by 170° turns
/// +170°, not −190°, in automatic mode as in the marked-up one; and a heart becoming a star
/// (both upright) does not spin half way.
#[test]
fn rotations_go_the_short_way_and_upright_shapes_do_not_spin() {
    let key = |angle: f64, id: &str| {
        format!(
            r##"<path id="{id}" transform="rotate({angle} 50 50)" d="M20 45 L60 45 L60 40 L80 40 L80 60 L60 60 L60 55 L30 55 L30 62 L20 62 Z" fill="#000"/>"##
        )
    };
    let (c, _) = build(&key(0.0, "k"), &key(170.0, "k"));
    let interp = c.interpolator(Method::Disc).unwrap();
    let idx = &outlines(&c)[0].vertices;
    let (turn, _) = fit(
        &chain(&c.meshes.source, idx),
        &chain(&interp.at_vec(0.5), idx),
    );
    eprintln!("automatic key at t = ½: {turn:.1}°");
    assert!((turn - 85.0).abs() < 10.0, "{turn}");
    // Marked up: the key is its own boundary.
    let (ds, _) = drawing("a.svg", &key(0.0, "boundary"));
    let (dt, _) = drawing("b.svg", &key(170.0, "boundary"));
    let c = crmorph::compatible::build(&ds, &dt, &MorphOptions::default()).unwrap();
    let interp = c.interpolator(Method::Disc).unwrap();
    let idx = &c.meshes.curves[0].vertices;
    let (marked, _) = fit(
        &chain(&c.meshes.source, idx),
        &chain(&interp.at_vec(0.5), idx),
    );
    eprintln!("marked-up key at t = ½: {marked:.1}°");
    assert!((marked - turn).abs() < 10.0, "{marked} vs {turn}");
    // heart → star: the middle frame's spin against the shapes' own turn.
    let a = auto("heart-to-star");
    let interp = a.c.interpolator(Method::Disc).unwrap();
    let idx = &outlines(&a.c)[0].vertices;
    let m = &a.c.meshes;
    let spin = crmorph::quality::spin(
        &chain(&m.source, idx),
        &chain(&m.target, idx),
        &chain(&interp.at_vec(0.5), idx),
    )
    .to_degrees();
    eprintln!("heart → star spins {spin:.1}° half way");
    assert!(spin < 20.0, "{spin}");
}
