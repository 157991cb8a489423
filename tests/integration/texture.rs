//! Raster images ride the mesh as textures (issue 14): the ends are the input images, a rigid
//! turn of an image morphs as the image turned rigidly, a solid texture shows no seam, and the
//! same input gives the same bytes.

use crmorph::export::{Morph, Timeline};
use crmorph::morpher::View;
use crmorph::render::encode_png;
use crmorph::Morpher;
use tiny_skia::{Color, Pixmap, Transform};

/// Image size in pixels (of the picture and the solid textures).
const W: u32 = 144;
const H: u32 = 112;

/// A test picture with smooth and sharp detail (`fixtures/textures/turn/picture.png`: a
/// diagonal gradient, a disc, a bar, crossing lines and text).
fn picture() -> Vec<u8> {
    include_bytes!("../../fixtures/textures/turn/picture.png").to_vec()
}

/// A solid opaque picture.
fn solid(c: Color) -> Vec<u8> {
    let mut p = Pixmap::new(W, H).unwrap();
    p.fill(c);
    encode_png(&p).unwrap()
}

/// A 240 × 240 drawing of the picture under `transform` (a transform list), with its rectangle
/// as the boundary and its top-left corner as an anchor (a rectangle alone does not say which
/// of its half-turn-symmetric correspondences is meant).
fn drawing(png: &[u8], transform: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
             width="240" height="240" viewBox="0 0 240 240">
          <g transform="{transform}">
            <image id="picture" width="{W}" height="{H}" xlink:href="data:image/png;base64,{}"/>
            <g id="controls" style="display:none">
              <rect id="boundary" width="{W}" height="{H}"/>
              <circle id="anchor-corner" cx="0" cy="0" r="1"/>
            </g>
          </g>
        </svg>"##,
        crmorph::base64::encode(png)
    )
}

/// The source placement: the picture centred.
const SOURCE: &str = "translate(48 64)";
/// The target: turned by 150° and scaled by 1.3 about the view's centre.
const TARGET: &str = "translate(120 120) rotate(150) scale(1.3) translate(-72 -56)";

/// The morph as the CLI makes it, through the front door, showing the source's view (the
/// comparisons below are made in it).
fn morph(source: &str, target: &str) -> Morph {
    Morpher::from_svg(("source.svg", source), ("target.svg", target))
        .unwrap()
        .view(View::Source)
        .build()
        .unwrap()
}

/// The drawing `svg` rendered by resvg at 240 × 240.
fn render(svg: &str) -> Pixmap {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).unwrap();
    let mut p = Pixmap::new(240, 240).unwrap();
    resvg::render(&tree, Transform::identity(), &mut p.as_mut());
    p
}

/// Mean absolute difference per channel (0–255) of two pixmaps.
fn mean_abs(a: &Pixmap, b: &Pixmap) -> f64 {
    let sum: u64 = a
        .data()
        .iter()
        .zip(b.data())
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    sum as f64 / a.data().len() as f64
}

#[test]
fn the_ends_are_the_input_images() {
    let png = picture();
    let (s, t) = (drawing(&png, SOURCE), drawing(&png, TARGET));
    let m = morph(&s, &t);
    for (at, svg) in [(0.0, &s), (1.0, &t)] {
        let got = m.pixmap_at(at).unwrap();
        let d = mean_abs(&got, &render(svg));
        eprintln!("t = {at}: mean absolute difference {d:.4} of 255 from the input");
        assert!(d < 1.0, "t = {at}: mean absolute difference {d} of 255");
    }
}

/// The picture turned by 150° and scaled by 1.3 (with its boundary and anchor turned too)
/// morphs as the picture turned rigidly: at t = ½ the frame is the source under the similarity
/// half way (75°, and the scale the area rule gives), compared inside the shape.
#[test]
fn a_turned_copy_morphs_as_the_image_turned_rigidly() {
    let png = picture();
    let (s, t) = (drawing(&png, SOURCE), drawing(&png, TARGET));
    let m = morph(&s, &t);
    // Where the image's corners are at t = ½: the similarity half way is read off the mesh
    // (the rigid interpolation of a similarity is a similarity).
    let v0 = &m.meshes().source;
    let v = m.vertices_at(0.5);
    let fit = crmorph::geometry::SimilarityFit::new(v0, &v);
    let angle = fit.rotation();
    let scale = fit.dot.hypot(fit.cross) / fit.from_spread;
    let (c, s) = (fit.from_centroid, angle.sin_cos());
    let turned = crmorph::geometry::Point::new(c.x * s.1 - c.y * s.0, c.x * s.0 + c.y * s.1);
    let shift = fit.to_centroid - turned * scale;
    assert!(
        (angle.to_degrees() - 75.0).abs() < 1.0,
        "half way turns by {}°",
        angle.to_degrees()
    );
    // The source picture under that similarity, drawn by resvg.
    let want = drawing(
        &png,
        &format!(
            "translate({} {}) rotate({}) scale({scale}) {SOURCE}",
            shift.x,
            shift.y,
            angle.to_degrees()
        ),
    );
    let want = render(&want);
    // The frame's target half only (at t = ½ it covers the source half completely).
    let got = m.pixmap_at(0.5).unwrap();
    // Inside the shape: pixels opaque in both, away from the edge.
    let (mut se, mut n) = (0.0, 0usize);
    for (a, b) in got.pixels().iter().zip(want.pixels()) {
        if a.alpha() == 255 && b.alpha() == 255 {
            for (x, y) in [
                (a.red(), b.red()),
                (a.green(), b.green()),
                (a.blue(), b.blue()),
            ] {
                se += (x as f64 - y as f64).powi(2);
            }
            n += 3;
        }
    }
    assert!(n > 3 * 4000, "only {} opaque pixels", n / 3);
    let psnr = 10.0 * (255.0f64.powi(2) / (se / n as f64)).log10();
    eprintln!(
        "turned copy at t = 1/2: {angle:.4} rad, scale {scale:.4}, PSNR {psnr:.1} dB over {} pixels",
        n / 3
    );
    assert!(psnr >= 35.0, "PSNR {psnr:.1} dB inside the shape");
}

#[test]
fn a_solid_texture_shows_no_seam() {
    // The bar turned, stretched and squashed: the mesh bends. Every pixel well inside the
    // warped image is exactly the colour, drawn straight onto the frame and drawn over other
    // artwork (a backdrop under the image: the texture goes through a layer and its outline
    // mask).
    let red = solid(Color::from_rgba8(200, 30, 40, 255));
    let turned = "translate(120 120) rotate(40) scale(1.5 0.8) translate(-72 -56)";
    for backdrop in [false, true] {
        let with = |svg: String| {
            if backdrop {
                svg.replacen(
                    "<g transform",
                    r##"<rect width="240" height="240" fill="#123456"/><g transform"##,
                    1,
                )
            } else {
                svg
            }
        };
        let m = morph(&with(drawing(&red, SOURCE)), &with(drawing(&red, turned)));
        for at in [0.2, 0.5, 0.8] {
            let p = m.pixmap_at(at).unwrap();
            let w = p.width() as usize;
            let px = p.pixels();
            let red_at = |i: usize| {
                let c = px[i].demultiply();
                (c.red(), c.green(), c.blue(), c.alpha()) == (200, 30, 40, 255)
            };
            let (mut inner, mut seams) = (0, Vec::new());
            for y in 2..p.height() as usize - 2 {
                for x in 2..w - 2 {
                    // Inside: the pixel and its 5 × 5 neighbourhood are the texture's colour or
                    // a seam; outside pixels are the backdrop or transparent. A pixel is well
                    // inside when its whole 5 × 5 neighbourhood has red pixels on every side.
                    let around =
                        [(-2i64, 0i64), (2, 0), (0, -2), (0, 2)]
                            .iter()
                            .all(|&(dx, dy)| {
                                let j = ((y as i64 + dy) as usize) * w + (x as i64 + dx) as usize;
                                red_at(j)
                            });
                    if around {
                        inner += 1;
                        if !red_at(y * w + x) {
                            seams.push((x, y));
                        }
                    }
                }
            }
            assert!(inner > 3000, "only {inner} inner pixels");
            assert!(
                seams.is_empty(),
                "backdrop {backdrop}, t = {at}: {} seam pixels, e.g. {:?}",
                seams.len(),
                &seams[..seams.len().min(5)]
            );
        }
    }
}

#[test]
fn same_input_same_bytes() {
    let png = picture();
    let (s, t) = (drawing(&png, SOURCE), drawing(&png, TARGET));
    let tl = Timeline {
        frames: 8,
        ..Timeline::default()
    };
    let a = morph(&s, &t);
    let b = morph(&s, &t);
    assert_eq!(a.animated_svg(&tl).unwrap(), b.animated_svg(&tl).unwrap());
    assert_eq!(a.apng(&tl).unwrap(), b.apng(&tl).unwrap());
}
