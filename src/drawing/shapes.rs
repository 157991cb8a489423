//! SVG shapes and paths of control elements as exact curves (kurbo), and their transforms.
//!
//! Paths are parsed with svgtypes' simplifying parser (relative commands, arcs and smooth
//! segments resolved to absolute lines, quadratics and cubics), basic shapes are built with
//! kurbo's shape types, and transforms are composed from the root down.

use std::str::FromStr;

use kurbo::{Affine, BezPath, Shape};

use super::xml::Element;

/// Accuracy used when turning circles and ellipses into Béziers (in the element's own units,
/// relative to its size); far below any flattening tolerance.
const SHAPE_ACCURACY: f64 = 1e-9;

/// A problem with one element's geometry, worded for an error message.
pub(crate) type ShapeResult<T> = Result<T, String>;

/// Parses an SVG length attribute to user units (absolute units converted at 96 dpi).
pub(crate) fn length(el: &Element, name: &str, default: f64) -> ShapeResult<f64> {
    let Some(v) = el.attr(name) else {
        return Ok(default);
    };
    let l = svgtypes::Length::from_str(v.trim())
        .map_err(|_| format!("attribute {name}=\"{v}\" is not a length"))?;
    use svgtypes::LengthUnit as U;
    let k = match l.unit {
        U::None | U::Px => 1.0,
        U::In => 96.0,
        U::Cm => 96.0 / 2.54,
        U::Mm => 96.0 / 25.4,
        U::Pt => 4.0 / 3.0,
        U::Pc => 16.0,
        _ => {
            return Err(format!(
                "attribute {name}=\"{v}\": relative units are not supported here"
            ))
        }
    };
    let x = l.number * k;
    if !x.is_finite() {
        return Err(format!("attribute {name}=\"{v}\" is not finite"));
    }
    Ok(x)
}

/// The element's own `transform` attribute (identity when absent).
pub(crate) fn transform(el: &Element) -> ShapeResult<Affine> {
    let Some(v) = el.attr("transform") else {
        return Ok(Affine::IDENTITY);
    };
    let t = svgtypes::Transform::from_str(v).map_err(|e| format!("bad transform \"{v}\": {e}"))?;
    let a = Affine::new([t.a, t.b, t.c, t.d, t.e, t.f]);
    if !a.is_finite() || a.determinant() == 0.0 {
        return Err(format!("transform \"{v}\" is degenerate"));
    }
    Ok(a)
}

fn path_data(d: &str) -> ShapeResult<BezPath> {
    use svgtypes::SimplePathSegment as S;
    let mut p = BezPath::new();
    for seg in svgtypes::SimplifyingPathParser::from(d) {
        match seg.map_err(|e| format!("bad path data: {e}"))? {
            S::MoveTo { x, y } => p.move_to((x, y)),
            S::LineTo { x, y } => p.line_to((x, y)),
            S::Quadratic { x1, y1, x, y } => p.quad_to((x1, y1), (x, y)),
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => p.curve_to((x1, y1), (x2, y2), (x, y)),
            S::ClosePath => p.close_path(),
        }
    }
    Ok(p)
}

fn points_list(v: &str) -> ShapeResult<Vec<(f64, f64)>> {
    let nums: Vec<f64> = v
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("bad number \"{s}\" in points"))
        })
        .collect::<Result<_, _>>()?;
    if nums.len() % 2 != 0 {
        return Err("odd number of coordinates in points".into());
    }
    Ok(nums.chunks(2).map(|c| (c[0], c[1])).collect())
}

/// Whether an element name is one of the geometry elements control curves can be.
pub(crate) fn is_shape(name: &str) -> bool {
    matches!(
        name,
        "path" | "rect" | "circle" | "ellipse" | "line" | "polyline" | "polygon"
    )
}

/// The element's geometry in its own coordinates (before its `transform`).
pub(crate) fn outline(el: &Element) -> ShapeResult<BezPath> {
    let mut p = BezPath::new();
    match el.name.as_str() {
        "path" => p = path_data(el.attr("d").unwrap_or(""))?,
        "rect" => {
            let (x, y) = (length(el, "x", 0.0)?, length(el, "y", 0.0)?);
            let (w, h) = (length(el, "width", 0.0)?, length(el, "height", 0.0)?);
            if w.is_nan() || h.is_nan() || w < 0.0 || h < 0.0 {
                return Err(format!("has a negative width or height ({w} × {h})"));
            }
            let rx = el.attr("rx").map(|_| length(el, "rx", 0.0)).transpose()?;
            let ry = el.attr("ry").map(|_| length(el, "ry", 0.0)).transpose()?;
            let (rx, ry) = match (rx, ry) {
                (Some(a), Some(b)) => (a, b),
                (Some(a), None) | (None, Some(a)) => (a, a),
                (None, None) => (0.0, 0.0),
            };
            // A negative radius is an error in SVG; read it as none, as browsers do.
            let (rx, ry) = (rx.max(0.0).min(w / 2.0), ry.max(0.0).min(h / 2.0));
            let r = kurbo::Rect::new(x, y, x + w, y + h);
            if rx > 0.0 && ry > 0.0 {
                // A rounded rectangle with elliptical corners: scale a circular one.
                let k = ry / rx;
                let rr = kurbo::RoundedRect::new(x, y / k, x + w, (y + h) / k, rx);
                p = Affine::scale_non_uniform(1.0, k) * rr.to_path(SHAPE_ACCURACY);
            } else {
                p = r.to_path(SHAPE_ACCURACY);
            }
        }
        "circle" => {
            let c = (length(el, "cx", 0.0)?, length(el, "cy", 0.0)?);
            let r = length(el, "r", 0.0)?;
            if r.is_nan() || r < 0.0 {
                return Err(format!("has a negative radius ({r})"));
            }
            p = kurbo::Circle::new(c, r).to_path(SHAPE_ACCURACY * r.max(1.0));
        }
        "ellipse" => {
            let c = (length(el, "cx", 0.0)?, length(el, "cy", 0.0)?);
            let (rx, ry) = (length(el, "rx", 0.0)?, length(el, "ry", 0.0)?);
            if rx.is_nan() || ry.is_nan() || rx < 0.0 || ry < 0.0 {
                return Err(format!("has a negative radius ({rx}, {ry})"));
            }
            p = kurbo::Ellipse::new(c, (rx, ry), 0.0).to_path(SHAPE_ACCURACY * rx.max(ry).max(1.0));
        }
        "line" => {
            p.move_to((length(el, "x1", 0.0)?, length(el, "y1", 0.0)?));
            p.line_to((length(el, "x2", 0.0)?, length(el, "y2", 0.0)?));
        }
        "polyline" | "polygon" => {
            let pts = points_list(el.attr("points").unwrap_or(""))?;
            for (i, q) in pts.iter().enumerate() {
                if i == 0 {
                    p.move_to(*q);
                } else {
                    p.line_to(*q);
                }
            }
            if el.name == "polygon" && !pts.is_empty() {
                p.close_path();
            }
        }
        other => {
            return Err(format!(
                "<{other}> cannot be a control curve (use a path or a basic shape)"
            ))
        }
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::xml::parse;

    fn first(svg: &str) -> Element {
        parse(svg).unwrap().children.remove(0)
    }

    #[test]
    fn path_with_arcs_and_relative_commands() {
        let el = first(r#"<svg><path d="M10 10 h 10 v 10 a 5 5 0 0 1 -10 0 z"/></svg>"#);
        let p = outline(&el).unwrap();
        let bb = p.bounding_box();
        assert!((bb.x0 - 10.0).abs() < 1e-9 && (bb.x1 - 20.0).abs() < 1e-9);
        assert!((bb.y1 - 25.0).abs() < 1e-6, "{bb:?}");
    }

    #[test]
    fn basic_shapes() {
        let c = outline(&first(r#"<svg><circle cx="5" cy="5" r="2"/></svg>"#)).unwrap();
        assert!((c.area().abs() - std::f64::consts::PI * 4.0).abs() < 1e-6);
        let r = outline(&first(
            r#"<svg><rect x="1" y="2" width="3" height="4"/></svg>"#,
        ))
        .unwrap();
        assert!((r.area().abs() - 12.0).abs() < 1e-12);
        let pg = outline(&first(r#"<svg><polygon points="0,0 4,0 0,3"/></svg>"#)).unwrap();
        assert!((pg.area().abs() - 6.0).abs() < 1e-12);
        let mm = length(&first(r#"<svg><rect width="25.4mm"/></svg>"#), "width", 0.0).unwrap();
        assert!((mm - 96.0).abs() < 1e-9);
    }

    #[test]
    fn transforms_and_errors() {
        let el = first(r#"<svg><g transform="translate(10 20) scale(2)"/></svg>"#);
        let a = transform(&el).unwrap();
        assert_eq!(
            a * kurbo::Point::new(1.0, 1.0),
            kurbo::Point::new(12.0, 22.0)
        );
        assert!(transform(&first(r#"<svg><g transform="scale(0)"/></svg>"#)).is_err());
        assert!(outline(&first(r#"<svg><path d="M 0 0 L zz"/></svg>"#)).is_err());
        assert!(outline(&first(r#"<svg><text/></svg>"#)).is_err());
    }
}
