//! Raster images (PNG, JPEG, GIF, WebP) as drawings: an image file becomes the SVG text of a
//! drawing that embeds it, with a boundary, before it is parsed like any SVG.
//!
//! The drawing is the image at its pixel size (`viewBox="0 0 W H"`, one user unit per pixel),
//! its `<image id="image">` a data URI of the file's own bytes, and a guide group
//! `<g id="controls" style="display:none">` holding the boundary:
//!
//! - **Opaque images** (every JPEG; a PNG, GIF or WebP with no pixel of alpha below 255): the
//!   image rectangle (the paper's image morph, Fig. 15).
//! - **Images with transparency**: the outline of the pixels at least half opaque (alpha ≥
//!   128), of the largest region they form, holes ignored. The outline of the region's pixel
//!   squares is pushed outward by the simplification tolerance, then simplified
//!   (Douglas–Peucker) to that tolerance: the drawing's flattening tolerance (a thousandth of the
//!   image's diagonal), never below 1 px so that the stair-steps of pixel edges (at most a pixel
//!   deep) vanish. The result is checked to be a simple closed polygon containing every pixel
//!   square of the region; failing that, it is pushed out further and simplified less. Pixels
//!   less than half opaque (the outer half of an anti-aliased edge) may lie outside: the
//!   artwork there follows the nearest triangle, as any artwork outside the boundary does.
//!
//! Pixels are decoded by resvg (the decoders that render the image), drawn at 1:1 with
//! nearest-neighbour sampling, so the alpha values are the file's own.
//!
//! [`merge_controls`] adds the control geometry of an SVG drawn in the image's pixel
//! coordinates (`crmorph --controls`) to such a drawing.

use i_overlay::core::fill_rule::FillRule;
use i_overlay::float::simplify::SimplifyShape;
use i_overlay::mesh::float::outline::offset::OutlineOffset;
use i_overlay::mesh::float::style::{LineJoin, OutlineStyle};

use super::{Limit, Limits};
use crate::error::{Error, Result};
use crate::geometry::{point_in_polygon, polygon_area, polyline_self_intersection, Point};

/// A raster image format crmorph reads as a drawing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// PNG (and APNG: its first frame).
    Png,
    /// JPEG (always opaque).
    Jpeg,
    /// GIF (its first frame).
    Gif,
    /// WebP.
    Webp,
}

impl ImageFormat {
    /// The media type of a data URI of this format.
    pub fn mime(self) -> &'static str {
        match self {
            ImageFormat::Png => "image/png",
            ImageFormat::Jpeg => "image/jpeg",
            ImageFormat::Gif => "image/gif",
            ImageFormat::Webp => "image/webp",
        }
    }
}

/// The image format whose signature `bytes` start with, if any.
pub fn sniff(bytes: &[u8]) -> Option<ImageFormat> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some(ImageFormat::Png)
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        Some(ImageFormat::Jpeg)
    } else if bytes.starts_with(b"GIF87a") || bytes.starts_with(b"GIF89a") {
        Some(ImageFormat::Gif)
    } else if bytes.len() >= 12 && bytes.starts_with(b"RIFF") && &bytes[8..12] == b"WEBP" {
        Some(ImageFormat::Webp)
    } else {
        None
    }
}

/// Alpha of at least this is inside a traced outline (half opaque).
const ALPHA_INSIDE: u8 = 128;
/// Fewest pixels the largest opaque region of an image may have.
const MIN_REGION_PIXELS: f64 = 16.0;
/// Smallest simplification tolerance, in pixels: stair-steps of pixel edges are at most one
/// pixel deep.
const MIN_TOLERANCE_PX: f64 = 1.0;

/// The opening tag of the guide group of an image drawing, where controls are merged.
const CONTROLS_OPEN: &str = "<g id=\"controls\" style=\"display:none\">";
/// How the traced boundary's element, with id `boundary_id`, starts in an image drawing.
fn boundary_open(boundary_id: &str) -> String {
    format!("    <path id=\"{}\"", escape_attr(boundary_id))
}

/// The SVG text of the drawing for the image file `bytes` of `format` (see the module docs);
/// `name` is how errors call the file, `boundary_id` the id its boundary gets (`boundary`
/// unless the user renamed it, `--boundary-id`).
///
/// Errors: an image whose size cannot be read, that cannot be decoded, that is larger than
/// [`Limits::pixels`], or that has no region of at least 16 half-opaque pixels.
pub fn image_svg(
    name: &str,
    bytes: &[u8],
    format: ImageFormat,
    boundary_id: &str,
    limits: &Limits,
) -> Result<String> {
    let size = imagesize::blob_size(bytes)
        .map_err(|e| Error::input(name, format!("image: cannot read its size: {e}")))?;
    let (w, h) = (size.width as u64, size.height as u64);
    if w == 0 || h == 0 {
        return Err(Error::input(
            name,
            format!("image: it is {w} × {h} px, empty"),
        ));
    }
    if w.saturating_mul(h) > limits.pixels {
        return Err(Limit::Pixels.exceeded(name, &format!("an image of {w} × {h} px"), limits));
    }
    let href = format!(
        "data:{};base64,{}",
        format.mime(),
        crate::base64::encode(bytes)
    );
    let rect = || {
        let (w, h) = (w as f64, h as f64);
        vec![
            Point::new(0.0, 0.0),
            Point::new(w, 0.0),
            Point::new(w, h),
            Point::new(0.0, h),
        ]
    };
    let boundary = if format == ImageFormat::Jpeg {
        rect()
    } else {
        let alpha = decode_alpha(name, &href, w as u32, h as u32)?;
        if alpha.iter().all(|&a| a == 255) {
            rect()
        } else {
            traced_boundary(name, &alpha, w as usize, h as usize)?
        }
    };
    Ok(format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" \
         width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n\
         \x20 <!-- Made by crmorph from an image. Draw feature-NAME curves (and anchor-NAME points, \
         a skeleton) inside the controls group, in pixel coordinates; show the group to see the \
         boundary. -->\n\
         \x20 <image id=\"image\" width=\"{w}\" height=\"{h}\" preserveAspectRatio=\"none\" \
         xlink:href=\"{href}\"/>\n\
         \x20 {CONTROLS_OPEN}\n\
         {} fill=\"none\" stroke=\"#ff00ff\" d=\"{}\"/>\n\
         \x20 </g>\n\
         </svg>\n",
        boundary_open(boundary_id),
        path_data(&boundary)
    ))
}

/// `image_svg` (the text [`image_svg`] made, named `image_name`) with the control geometry of
/// the SVG text `controls` (named `controls_name`, drawn in the image's pixel coordinates)
/// added to its guide group: everything inside the controls file's root element, with the
/// root's namespace declarations. When the controls hold an element with id `boundary_id`, it
/// replaces the traced boundary.
///
/// Errors: `controls` is not well-formed SVG, or `image_svg` is not an image drawing.
pub fn merge_controls(
    image_name: &str,
    image_svg: &str,
    controls_name: &str,
    controls: &str,
    boundary_id: &str,
) -> Result<String> {
    let (namespaces, body, has_boundary) = root_content(controls_name, controls, boundary_id)?;
    let Some(open) = image_svg.find(CONTROLS_OPEN) else {
        return Err(Error::input(
            image_name,
            "is not an image drawing made by crmorph: no controls group to add controls to",
        ));
    };
    let insert_at = open + CONTROLS_OPEN.len();
    let mut out = String::with_capacity(image_svg.len() + body.len() + 256);
    out.push_str(&image_svg[..insert_at]);
    let mut rest = &image_svg[insert_at..];
    if has_boundary {
        // Drop the traced boundary: the controls' own replaces it.
        if let Some(start) = rest.find(&boundary_open(boundary_id)) {
            if let Some(len) = rest[start..].find("/>\n") {
                out.push_str(&rest[..start]);
                rest = &rest[start + len + 3..];
            }
        }
    }
    out.push_str("\n    <g id=\"controls-from-file\"");
    for (k, v) in &namespaces {
        out.push_str(&format!(" {k}=\"{}\"", escape_attr(v)));
    }
    out.push('>');
    out.push_str(body);
    out.push_str("</g>");
    out.push_str(rest);
    Ok(out)
}

/// What [`root_content`] finds: the root's namespace declarations, its content, and whether the
/// boundary is in it.
type RootContent<'a> = (Vec<(String, String)>, &'a str, bool);

/// The namespace declarations of the root element of `text`, the text between its start and
/// end tags, and whether an element inside has the id `boundary_id`.
fn root_content<'a>(name: &str, text: &'a str, boundary_id: &str) -> Result<RootContent<'a>> {
    use quick_xml::events::Event;
    let bad = |e: String| Error::input(name, format!("controls: not well-formed XML: {e}"));
    let mut reader = quick_xml::Reader::from_str(text);
    let mut depth = 0usize;
    let mut start = None;
    let mut namespaces = Vec::new();
    let mut has_boundary = false;
    loop {
        let before = reader.buffer_position() as usize;
        match reader.read_event().map_err(|e| bad(e.to_string()))? {
            Event::Start(e) if start.is_some() => {
                has_boundary |= has_id(&e, boundary_id);
                depth += 1;
            }
            Event::Empty(e) if start.is_some() => has_boundary |= has_id(&e, boundary_id),
            Event::Empty(e) => {
                root_namespaces(name, &e, &mut namespaces)?;
                return Ok((namespaces, "", false));
            }
            Event::Start(e) => {
                root_namespaces(name, &e, &mut namespaces)?;
                start = Some(reader.buffer_position() as usize);
            }
            Event::End(_) if depth > 0 => depth -= 1,
            Event::End(_) => {
                let Some(s) = start else {
                    return Err(bad("an end tag without a start".into()));
                };
                return Ok((namespaces, &text[s..before], has_boundary));
            }
            Event::Eof => return Err(bad("it ends before its root element does".into())),
            _ => {}
        }
    }
}

/// The `xmlns:…` declarations of the root element `e` of the controls file `name`, into `out`.
fn root_namespaces(
    name: &str,
    e: &quick_xml::events::BytesStart,
    out: &mut Vec<(String, String)>,
) -> Result<()> {
    if e.local_name().as_ref() != "svg" {
        return Err(Error::input(
            name,
            "controls: the root element is not <svg>",
        ));
    }
    for a in e.attributes().flatten() {
        let key = a.key.as_ref().to_string();
        if key.starts_with("xmlns:") {
            let v = a
                .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .map_err(|e| Error::input(name, format!("controls: not well-formed XML: {e}")))?;
            out.push((key, v.into_owned()));
        }
    }
    Ok(())
}

fn has_id(e: &quick_xml::events::BytesStart, id: &str) -> bool {
    e.attributes()
        .flatten()
        .any(|a| a.key.as_ref() == "id" && a.value.trim() == id)
}

fn escape_attr(v: &str) -> String {
    v.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
}

/// The alpha of every pixel of the image at `href`, row by row: the image drawn by resvg at
/// 1:1 with nearest-neighbour sampling.
fn decode_alpha(name: &str, href: &str, w: u32, h: u32) -> Result<Vec<u8>> {
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\"><image width=\"{w}\" height=\"{h}\" \
         preserveAspectRatio=\"none\" image-rendering=\"optimizeSpeed\" href=\"{href}\"/></svg>"
    );
    let opts = super::usvg_options(name, None, &super::InputPolicy::default());
    let tree = usvg::Tree::from_str(&svg, &opts)
        .map_err(|e| Error::input(name, format!("image: cannot decode it: {e}")))?;
    if !tree.root().has_children() {
        return Err(Error::input(name, "image: cannot decode it"));
    }
    let mut pixmap = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| Error::input(name, format!("image: {w} × {h} px is too large")))?;
    resvg::render(
        &tree,
        tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap.data().chunks_exact(4).map(|p| p[3]).collect())
}

/// The outline of the largest region of pixels with alpha ≥ [`ALPHA_INSIDE`] in the `w` × `h`
/// `alpha` mask, pushed outward and simplified (see the module docs).
fn traced_boundary(name: &str, alpha: &[u8], w: usize, h: usize) -> Result<Vec<Point>> {
    // Each row's runs of half-opaque pixels as rectangles, united by i_overlay.
    let mut runs: Vec<Vec<[f64; 2]>> = Vec::new();
    for y in 0..h {
        let row = &alpha[y * w..(y + 1) * w];
        let mut x = 0;
        while x < w {
            if row[x] < ALPHA_INSIDE {
                x += 1;
                continue;
            }
            let x0 = x;
            while x < w && row[x] >= ALPHA_INSIDE {
                x += 1;
            }
            let (x0, x1, y0, y1) = (x0 as f64, x as f64, y as f64, (y + 1) as f64);
            runs.push(vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]);
        }
    }
    if runs.is_empty() {
        return Err(Error::input(name, "image: no opaque pixels").with_hint(
            "an image with transparency is outlined where its pixels are at least half opaque",
        ));
    }
    let pixels = runs.simplify_shape(FillRule::NonZero);
    let diagonal = ((w * w + h * h) as f64).sqrt();
    let tolerance = (diagonal * 1e-3).max(MIN_TOLERANCE_PX);
    let grow = |push: f64| -> Option<Vec<Point>> {
        pixels
            .outline(&OutlineStyle::new(push).line_join(LineJoin::Bevel))
            .iter()
            .filter_map(|shape| shape.first())
            .map(|ring| {
                ring.iter()
                    .map(|p| Point::new(p[0], p[1]))
                    .collect::<Vec<_>>()
            })
            .max_by(|a, b| polygon_area(a).abs().total_cmp(&polygon_area(b).abs()))
    };
    let Some(outer) = grow(tolerance) else {
        return Err(Error::internal(format!(
            "{name}: the opaque pixels of the image have no outline"
        )));
    };
    // The region's pixels: the pixel shapes inside the grown outline.
    let mut samples = Vec::new();
    let mut area = 0.0;
    for shape in &pixels {
        let Some(ring) = shape.first() else { continue };
        let ring: Vec<Point> = ring.iter().map(|p| Point::new(p[0], p[1])).collect();
        if !ring.first().is_some_and(|&p| point_in_polygon(p, &outer)) {
            continue;
        }
        area += polygon_area(&ring).abs();
        for r in shape.iter() {
            let r: Vec<Point> = r.iter().map(|p| Point::new(p[0], p[1])).collect();
            edge_samples(&r, &mut samples);
        }
        area -= shape[1..]
            .iter()
            .map(|r| {
                polygon_area(&r.iter().map(|p| Point::new(p[0], p[1])).collect::<Vec<_>>()).abs()
            })
            .sum::<f64>();
    }
    if area < MIN_REGION_PIXELS {
        return Err(Error::input(
            name,
            format!(
                "image: its largest opaque region has only {area:.0} pixels, too small to morph"
            ),
        )
        .with_hint(
            "an image with transparency is outlined where its pixels are at least half opaque",
        ));
    }
    // Pushed out by the tolerance, a simplified outline holds the region unless it cuts a
    // concave corner deeply; then it is pushed out further and, only if that fails, simplified
    // less (which brings the stair-steps back).
    for tol in [1.0, 0.5, 0.25] {
        for push in [0.5, 1.0, 1.5, 2.0, 3.0] {
            let Some(grown) = grow(push * tolerance) else {
                continue;
            };
            let candidate = rounded(&douglas_peucker(&grown, tol * tolerance));
            if is_valid(&candidate, &samples) {
                return Ok(candidate);
            }
        }
    }
    let candidate = rounded(&outer);
    if is_valid(&candidate, &samples) {
        return Ok(candidate);
    }
    Err(Error::internal(format!(
        "{name}: the outline traced around the image's opaque pixels is not a simple curve"
    )))
}

/// Points along every edge of the closed `ring`, at most half a pixel apart.
fn edge_samples(ring: &[Point], out: &mut Vec<Point>) {
    for (i, &a) in ring.iter().enumerate() {
        let b = ring[(i + 1) % ring.len()];
        let n = ((a.distance(b) * 2.0).ceil() as usize).max(1);
        out.extend((0..n).map(|k| a.lerp(b, k as f64 / n as f64)));
    }
}

/// Whether `ring` can be the boundary: at least three points, no crossing, and every sample of
/// the region inside.
fn is_valid(ring: &[Point], samples: &[Point]) -> bool {
    ring.len() >= 3
        && polygon_area(ring).abs() > 0.0
        && polyline_self_intersection(ring, true).is_none()
        && samples.iter().all(|&p| point_in_polygon(p, ring))
}

/// `ring` with coordinates rounded to thousandths (as written), repeated points removed.
fn rounded(ring: &[Point]) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::with_capacity(ring.len());
    for p in ring {
        let q = Point::new((p.x * 1e3).round() / 1e3, (p.y * 1e3).round() / 1e3);
        if out.last() != Some(&q) {
            out.push(q);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// The closed polygon `ring` simplified by Douglas–Peucker to within `tol`. (kurbo's
/// simplifier fits smooth curves and keeps the corners of a pixel staircase; this drops them.)
fn douglas_peucker(ring: &[Point], tol: f64) -> Vec<Point> {
    let n = ring.len();
    if n < 4 {
        return ring.to_vec();
    }
    // Split the ring at its first point and the point farthest from it.
    let far = (1..n)
        .max_by(|&a, &b| {
            ring[0]
                .distance_squared(ring[a])
                .total_cmp(&ring[0].distance_squared(ring[b]))
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n + 1];
    keep[0] = true;
    keep[far] = true;
    keep[n] = true;
    let at = |i: usize| ring[i % n];
    let mut stack = vec![(0, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        let (pa, pb) = (at(a), at(b));
        let mut worst = (0.0, a);
        for i in a + 1..b {
            let (d, _) = crate::geometry::point_segment_distance(at(i), pa, pb);
            if d > worst.0 {
                worst = (d, i);
            }
        }
        if worst.0 > tol {
            keep[worst.1] = true;
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        }
    }
    (0..n).filter(|&i| keep[i]).map(|i| ring[i]).collect()
}

/// SVG path data of the closed polygon `ring`.
fn path_data(ring: &[Point]) -> String {
    let mut d = String::with_capacity(ring.len() * 16);
    for (i, p) in ring.iter().enumerate() {
        d.push_str(if i == 0 { "M" } else { " L" });
        d.push_str(&format!("{} {}", num(p.x), num(p.y)));
    }
    d.push_str(" Z");
    d
}

fn num(v: f64) -> String {
    let v = (v * 1e3).round() / 1e3;
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{Drawing, ReadOptions};

    /// A `w` × `h` RGBA PNG whose pixel (x, y) is `f(x, y)`.
    fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
        let mut data = Vec::with_capacity((w * h * 4) as usize);
        for y in 0..h {
            for x in 0..w {
                data.extend_from_slice(&f(x, y));
            }
        }
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().unwrap();
        writer.write_image_data(&data).unwrap();
        writer.finish().unwrap();
        out
    }

    /// A disc of radius `r` about (`cx`, `cy`), anti-aliased (alpha is the coverage of a pixel
    /// by the disc, approximately).
    fn disc(x: u32, y: u32, (cx, cy, r): (f64, f64, f64)) -> [u8; 4] {
        let d = ((x as f64 + 0.5 - cx).powi(2) + (y as f64 + 0.5 - cy).powi(2)).sqrt();
        let a = (r + 0.5 - d).clamp(0.0, 1.0);
        [200, 40, 40, (a * 255.0).round() as u8]
    }

    fn drawing(name: &str, bytes: &[u8]) -> Result<Drawing> {
        let format = sniff(bytes).unwrap();
        let svg = image_svg(name, bytes, format, "boundary", &Limits::default())?;
        Drawing::from_str(name, &svg, &ReadOptions::default())
    }

    #[test]
    fn signatures_pick_the_format() {
        assert_eq!(sniff(b"\x89PNG\r\n\x1a\n...."), Some(ImageFormat::Png));
        assert_eq!(sniff(&[0xff, 0xd8, 0xff, 0xe0]), Some(ImageFormat::Jpeg));
        assert_eq!(sniff(b"GIF89a...."), Some(ImageFormat::Gif));
        assert_eq!(sniff(b"GIF87a...."), Some(ImageFormat::Gif));
        assert_eq!(sniff(b"RIFF\0\0\0\0WEBPVP8 "), Some(ImageFormat::Webp));
        assert_eq!(sniff(b"RIFF\0\0\0\0WAVEfmt "), None);
        assert_eq!(sniff(b"<svg xmlns=\"http://www.w3.org/2000/svg\"/>"), None);
        assert_eq!(sniff(b"\x89PN"), None);
        assert_eq!(sniff(b""), None);
    }

    #[test]
    fn an_opaque_image_is_bounded_by_its_rectangle() {
        let bytes = png(40, 30, |x, y| [x as u8 * 6, y as u8 * 8, 100, 255]);
        let d = drawing("o.png", &bytes).unwrap();
        let b = &d.controls.boundary;
        assert!(!d.controls.boundary_from_view_box);
        assert_eq!(b.points.len(), 4);
        assert_eq!(polygon_area(&b.points).abs(), 1200.0);
        assert_eq!(d.view_box, Some((Point::ZERO, Point::new(40.0, 30.0))));
        assert!(d.svg.contains("data:image/png;base64,"));
        // Same input, same bytes.
        let svg = |b: &[u8]| {
            image_svg("o.png", b, ImageFormat::Png, "boundary", &Limits::default()).unwrap()
        };
        assert_eq!(svg(&bytes), svg(&bytes));
    }

    #[test]
    fn a_transparent_disc_is_traced_close_to_its_outline() {
        let (cx, cy, r) = (128.0, 120.0, 100.0);
        let (w, h) = (256, 256);
        let bytes = png(w, h, |x, y| disc(x, y, (cx, cy, r)));
        let d = drawing("disc.png", &bytes).unwrap();
        let b = &d.controls.boundary.points;
        let area = polygon_area(b).abs();
        let disc_area = std::f64::consts::PI * r * r;
        assert!(
            (area / disc_area - 1.0).abs() < 0.05,
            "area {area} vs {disc_area}"
        );
        assert!(
            b.len() < 120,
            "{} vertices: the stair-steps remain",
            b.len()
        );
        for y in 0..h {
            for x in 0..w {
                if disc(x, y, (cx, cy, r))[3] >= 128 {
                    let p = Point::new(x as f64 + 0.5, y as f64 + 0.5);
                    assert!(point_in_polygon(p, b), "pixel ({x}, {y}) is outside");
                }
            }
        }
        // The alpha resvg decodes is the file's own.
        let href = format!("data:image/png;base64,{}", crate::base64::encode(&bytes));
        let alpha = decode_alpha("disc.png", &href, w, h).unwrap();
        for y in 0..h {
            for x in 0..w {
                assert_eq!(alpha[(y * w + x) as usize], disc(x, y, (cx, cy, r))[3]);
            }
        }
    }

    #[test]
    fn the_largest_region_is_traced_and_holes_are_ignored() {
        // A ring (a disc with a hole) and a small square apart from it.
        let bytes = png(100, 100, |x, y| {
            let d = ((x as f64 - 40.0).powi(2) + (y as f64 - 40.0).powi(2)).sqrt();
            let on = (15.0..30.0).contains(&d) || ((85..92).contains(&x) && (85..92).contains(&y));
            [0, 0, 0, if on { 255 } else { 0 }]
        });
        let d = drawing("ring.png", &bytes).unwrap();
        let b = &d.controls.boundary.points;
        assert!(
            point_in_polygon(Point::new(40.0, 40.0), b),
            "the hole is inside"
        );
        assert!(!point_in_polygon(Point::new(88.0, 88.0), b));
    }

    #[test]
    fn transparent_and_speck_images_are_one_line_errors() {
        let clear = png(20, 20, |_, _| [255, 255, 255, 0]);
        let e = drawing("clear.png", &clear).unwrap_err().to_string();
        assert!(e.starts_with("clear.png: image: no opaque pixels"), "{e}");
        let faint = png(20, 20, |_, _| [0, 0, 0, 100]);
        let e = drawing("faint.png", &faint).unwrap_err().to_string();
        assert!(e.contains("no opaque pixels"), "{e}");
        let speck = png(20, 20, |x, y| {
            [0, 0, 0, if x == 5 && y == 5 { 255 } else { 0 }]
        });
        let e = drawing("speck.png", &speck).unwrap_err().to_string();
        assert!(e.contains("only 1 pixels, too small"), "{e}");
        let e = image_svg(
            "bad.png",
            b"\x89PNG\r\n\x1a\nnonsense",
            ImageFormat::Png,
            "boundary",
            &Limits::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("bad.png: image: cannot"), "{e}");
        let small = Limits {
            pixels: 100,
            ..Limits::default()
        };
        let e = image_svg("big.png", &clear, ImageFormat::Png, "boundary", &small)
            .unwrap_err()
            .to_string();
        assert!(e.contains("over the limit of 100 pixels per frame"), "{e}");
        assert!(e.contains("--max-pixels"), "{e}");
    }

    #[test]
    fn controls_are_merged_into_the_guides_and_may_replace_the_boundary() {
        let bytes = png(100, 80, |_, _| [10, 20, 30, 255]);
        let svg = image_svg(
            "a.png",
            &bytes,
            ImageFormat::Png,
            "boundary",
            &Limits::default(),
        )
        .unwrap();
        let controls = r#"<?xml version="1.0"?>
<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" viewBox="0 0 100 80">
  <g inkscape:groupmode="layer" transform="translate(10 0)">
    <path id="feature-eye" d="M20 30 L40 30"/>
    <circle id="anchor-top" cx="40" cy="5" r="1"/>
  </g>
</svg>"#;
        let merged = merge_controls("a.png", &svg, "c.svg", controls, "boundary").unwrap();
        let d = Drawing::from_str("a.png", &merged, &ReadOptions::default()).unwrap();
        assert_eq!(d.controls.features.len(), 1);
        assert_eq!(d.controls.features[0].points[0], Point::new(30.0, 30.0));
        assert_eq!(d.controls.anchors.len(), 1);
        assert_eq!(polygon_area(&d.controls.boundary.points).abs(), 8000.0);
        // The merged controls are guides: nothing of them is drawn.
        assert!(merged.contains("<g id=\"controls-from-file\" xmlns:inkscape="));

        let own = r#"<svg xmlns="http://www.w3.org/2000/svg"><rect id="boundary" x="10" y="10" width="50" height="50"/><path id="feature-x" d="M20 20 L30 30"/></svg>"#;
        let merged = merge_controls("a.png", &svg, "c.svg", own, "boundary").unwrap();
        let d = Drawing::from_str("a.png", &merged, &ReadOptions::default()).unwrap();
        assert_eq!(polygon_area(&d.controls.boundary.points).abs(), 2500.0);

        let e = merge_controls("a.png", &svg, "c.svg", "<svg><g></svg>", "boundary")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.svg: controls: not well-formed XML"), "{e}");
        let e = merge_controls("a.svg", "<svg/>", "c.svg", own, "boundary")
            .unwrap_err()
            .to_string();
        assert!(e.contains("not an image drawing"), "{e}");
    }
}
