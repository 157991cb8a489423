//! A pass over the text before it is parsed into trees: nesting depth, element count and path
//! segments, against the [`Limits`].
//!
//! usvg and crmorph's own reader build trees and walk them recursively; 14,000 nested `<g>`
//! overflow the stack, and a million elements take gigabytes. This pass streams the text with
//! quick-xml, keeps only counters, and stops at the first limit crossed. Text that is not
//! well-formed XML passes: the parsers downstream say what is wrong with it.

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

use super::{Limit, Limits};
use crate::error::Result;

/// Checks `text` against the depth, element and segment limits; `name` is how errors call the
/// file.
pub(crate) fn scan(name: &str, text: &str, limits: &Limits) -> Result<()> {
    let mut reader = Reader::from_str(text);
    let (mut depth, mut elements, mut segments) = (0usize, 0usize, 0usize);
    loop {
        let (start, empty) = match reader.read_event() {
            Ok(Event::Start(e)) => (e, false),
            Ok(Event::Empty(e)) => (e, true),
            Ok(Event::End(_)) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Ok(Event::Eof) | Err(_) => return Ok(()),
            Ok(_) => continue,
        };
        elements += 1;
        if elements > limits.elements {
            return Err(Limit::Elements.exceeded(
                name,
                &format!("more than {} elements", limits.elements),
                limits,
            ));
        }
        if !empty {
            depth += 1;
            if depth > limits.depth {
                let at = reader.buffer_position();
                return Err(Limit::Depth.exceeded(
                    name,
                    &format!("elements nested {depth} deep (at byte {at})"),
                    limits,
                ));
            }
        }
        segments += path_segments(name, &start)?;
        if segments > limits.segments {
            return Err(Limit::Segments.exceeded(
                name,
                &format!("more than {} path segments", limits.segments),
                limits,
            ));
        }
    }
}

/// The largest arc radius accepted in path data. Arcs become cubic curves before anything
/// else sees them, in a number that grows with the radius: 3.4e38 gives millions per arc.
const MAX_ARC_RADIUS: f64 = crate::tolerance::MAX_COORDINATE;

/// The segments of path data `d`, with each arc's radius checked as it will be drawn: the larger
/// of its radii and half its chord (SVG scales radii that cannot reach the end point up), so
/// the current point is followed through relative commands.
fn path_data_segments(name: &str, d: &str) -> Result<usize> {
    use svgtypes::PathSegment as P;
    let (mut n, mut cur, mut start) = (0usize, (0.0f64, 0.0f64), (0.0f64, 0.0f64));
    for seg in svgtypes::PathParser::from(d) {
        let Ok(seg) = seg else { break };
        n += 1;
        let to = |abs: bool, x: f64, y: f64| if abs { (x, y) } else { (cur.0 + x, cur.1 + y) };
        let next = match seg {
            P::MoveTo { abs, x, y } => {
                start = to(abs, x, y);
                start
            }
            P::LineTo { abs, x, y }
            | P::CurveTo { abs, x, y, .. }
            | P::SmoothCurveTo { abs, x, y, .. }
            | P::Quadratic { abs, x, y, .. }
            | P::SmoothQuadratic { abs, x, y } => to(abs, x, y),
            P::HorizontalLineTo { abs, x } => (if abs { x } else { cur.0 + x }, cur.1),
            P::VerticalLineTo { abs, y } => (cur.0, if abs { y } else { cur.1 + y }),
            P::EllipticalArc {
                abs, rx, ry, x, y, ..
            } => {
                let end = to(abs, x, y);
                let half_chord = 0.5 * (end.0 - cur.0).hypot(end.1 - cur.1);
                let r = rx.abs().max(ry.abs()).max(half_chord);
                if r.is_nan() || r > MAX_ARC_RADIUS {
                    return Err(crate::error::Error::input(
                        name,
                        format!(
                            "path data has an arc of radius {r:e}, too large to draw (at most \
                             {MAX_ARC_RADIUS:e})"
                        ),
                    ));
                }
                end
            }
            P::ClosePath { .. } => start,
        };
        cur = next;
    }
    Ok(n)
}

/// The segments an element's geometry attributes describe: the commands of `d`, the points of
/// `points`. An arc whose radius is beyond [`MAX_ARC_RADIUS`] is an error.
fn path_segments(name: &str, e: &BytesStart<'_>) -> Result<usize> {
    let mut n = 0;
    for a in e.attributes().flatten() {
        let key = a.key.local_name();
        match key.as_ref() {
            "d" => n += path_data_segments(name, a.value.as_ref())?,
            "points" => {
                n += svgtypes::PointsParser::from(a.value.as_ref()).count();
            }
            _ => {}
        }
    }
    Ok(n)
}

/// The non-data references of `<image>` and `<feImage>` elements, with their ids.
pub(crate) fn image_refs(text: &str) -> Vec<(Option<String>, String)> {
    let mut out = Vec::new();
    if !text.contains("mage") {
        return out;
    }
    let mut reader = Reader::from_str(text);
    loop {
        let e = match reader.read_event() {
            Ok(Event::Start(e)) | Ok(Event::Empty(e)) => e,
            Ok(Event::Eof) | Err(_) => return out,
            Ok(_) => continue,
        };
        if !matches!(e.local_name().as_ref(), "image" | "feImage") {
            continue;
        }
        let (mut id, mut href) = (None, None);
        for a in e.attributes().flatten() {
            let value = || a.value.trim().to_string();
            match a.key.local_name().as_ref() {
                "id" => id = Some(value()),
                "href" => href = Some(value()),
                _ => {}
            }
        }
        if let Some(h) = href.filter(|h| !h.starts_with("data:") && !h.starts_with('#')) {
            out.push((id, h));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str, limits: &Limits) -> String {
        scan("a.svg", text, limits)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    }

    #[test]
    fn each_limit_is_named_when_crossed() {
        let l = Limits::default();
        let deep = format!(
            "<svg>{}{}</svg>",
            "<g>".repeat(14_000),
            "</g>".repeat(14_000)
        );
        let e = check(&deep, &l);
        assert!(
            e.contains("nested 257 deep") && e.contains("--max-depth"),
            "{e}"
        );
        let mut few = l;
        few.elements = 10;
        let e = check(&format!("<svg>{}</svg>", "<rect/>".repeat(10)), &few);
        assert!(e.contains("--max-elements"), "{e}");
        assert_eq!(
            check(&format!("<svg>{}</svg>", "<rect/>".repeat(9)), &few),
            ""
        );
        let mut short = l;
        short.segments = 4;
        let path = "<svg><path d=\"M0 0 L1 1 2 2 3 3\"/><polyline points=\"0,0 1,1\"/></svg>";
        let e = check(path, &short);
        assert!(e.contains("more than 4 path segments"), "{e}");
        assert_eq!(
            check("<svg><g>", &l),
            "",
            "broken XML is for the parser to report"
        );
    }
}
