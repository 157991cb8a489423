//! Reading a drawing: the artwork and the control geometry of one SVG file (DESIGN.md §1).
//!
//! usvg parses and normalizes the SVG (transforms resolved, shapes turned into paths) for the
//! artwork; quick-xml reads the raw ids and the `controls` guide group that usvg drops, so that
//! control curves are found by id wherever they are. Curves are flattened with lyon at a tolerance
//! relative to the drawing's size ([`crate::tolerance`]).

use crate::geometry::Point;
use crate::mesh::CurveKind;

/// A boundary or feature curve read from a drawing, flattened to a polyline in the root's user
/// space.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlCurve {
    /// The element id as written in the file (`boundary`, `feature-eye`, …).
    pub id: String,
    /// The matching key: `boundary` for the boundary, `NAME` for `feature-NAME`.
    pub name: String,
    /// Boundary or feature.
    pub kind: CurveKind,
    /// Whether the curve is closed (its last point connects back to the first; the first point is
    /// not repeated at the end).
    pub closed: bool,
    /// Flattened points, consecutive duplicates removed.
    pub points: Vec<Point>,
}

/// A pinned correspondence point (`anchor-NAME`).
#[derive(Debug, Clone, PartialEq)]
pub struct Anchor {
    /// The element id as written in the file.
    pub id: String,
    /// The matching key `NAME`.
    pub name: String,
    /// Position in the root's user space.
    pub point: Point,
}

/// A skeleton polyline (`skeleton` or `skeleton-NAME`): its vertices are joints, its segments
/// bones (§4.2).
#[derive(Debug, Clone, PartialEq)]
pub struct SkeletonChain {
    /// The element id as written in the file.
    pub id: String,
    /// Joint positions in the root's user space.
    pub points: Vec<Point>,
}

/// The control geometry of one drawing: what steers the morph.
#[derive(Debug, Clone, PartialEq)]
pub struct Controls {
    /// The outline of the shape: `boundary`, or the viewBox rectangle in image-morph mode.
    pub boundary: ControlCurve,
    /// Whether the boundary is the viewBox rectangle because the file has no `boundary` element.
    pub boundary_from_view_box: bool,
    /// Feature curves, sorted by name.
    pub features: Vec<ControlCurve>,
    /// Anchors, sorted by name.
    pub anchors: Vec<Anchor>,
    /// Skeleton chains in document order.
    pub skeleton: Vec<SkeletonChain>,
    /// Ids that almost follow a convention (`Boundary`, `feature_eye`), in document order: they
    /// are not control geometry, and the errors and notes about this drawing name them.
    pub near_misses: Vec<NearMiss>,
}

impl Controls {
    /// The near miss that most likely meant `id` (a convention id missing from this drawing).
    pub fn near_miss_of(&self, id: &str) -> Option<&NearMiss> {
        self.near_misses.iter().find(|n| n.meant == id)
    }
}

/// Id conventions for control geometry (renamed by `--boundary-id`, `--feature-prefix`,
/// `--skeleton-id`).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct ControlIds {
    /// Id of the boundary element. Default: `boundary`.
    pub boundary: String,
    /// Prefix of feature curve ids. Default: `feature-`.
    pub feature_prefix: String,
    /// Prefix of anchor ids. Default: `anchor-`.
    pub anchor_prefix: String,
    /// Id (and, followed by `-`, prefix) of skeleton elements. Default: `skeleton`.
    pub skeleton: String,
    /// Id of the group whose children are guides (never rendered). Default: `controls`.
    pub guides_group: String,
}

impl Default for ControlIds {
    fn default() -> Self {
        ControlIds {
            boundary: "boundary".into(),
            feature_prefix: "feature-".into(),
            anchor_prefix: "anchor-".into(),
            skeleton: "skeleton".into(),
            guides_group: "controls".into(),
        }
    }
}

mod controls;
mod flatten;
mod near_miss;
mod shapes;
mod xml;

pub(crate) use flatten::flattened_count;
pub use near_miss::{resembles, NearMiss};

use crate::error::{Error, Result};
use crate::tolerance::Tolerances;

/// Options for reading a drawing.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ReadOptions {
    /// Id conventions. Default: [`ControlIds::default`].
    pub ids: ControlIds,
    /// Vertex density multiplier (2.0 = twice as many vertices per unit length). Default: 1.0.
    pub density: f64,
    /// What may be read and how much work a drawing may cause. Default: no local files, the
    /// default [`Limits`](crate::input::Limits).
    pub policy: crate::input::InputPolicy,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            ids: ControlIds::default(),
            density: 1.0,
            policy: crate::input::InputPolicy::default(),
        }
    }
}

/// One SVG drawing: its control geometry, and its source text for the artwork stage.
#[derive(Debug, Clone)]
pub struct Drawing {
    /// The file name used in error messages.
    pub file: String,
    /// The control geometry, in the root's user space.
    pub controls: Controls,
    /// Tolerances relative to this drawing's size.
    pub tolerances: Tolerances,
    /// The root's viewBox as `(min, max)` corners (from `viewBox`, else `width`/`height`).
    pub view_box: Option<(Point, Point)>,
    /// The SVG source text, as prepared for parsing ([`crate::input::prepare`]: decoded,
    /// entities expanded, checked against the limits).
    pub svg: String,
    /// The folder the file is in, against which its image references resolve (`None` for text
    /// that came from no file).
    pub dir: Option<std::path::PathBuf>,
    /// What the drawing may make crmorph read, and its limits (from [`ReadOptions::policy`]).
    pub policy: crate::input::InputPolicy,
    /// The id of the group of guides (never rendered), from [`ControlIds::guides_group`].
    pub guides_group: String,
    /// What the reader noticed and left out, one line each (an image the policy does not let
    /// it read): for the user, not errors.
    pub notes: Vec<String>,
}

impl Drawing {
    /// Reads and validates a drawing from SVG text; `file` names it in error messages. The
    /// text is prepared first ([`crate::input::prepare`]), under `opts.policy`'s limits.
    pub fn from_str(file: &str, text: &str, opts: &ReadOptions) -> Result<Self> {
        let text = crate::input::prepare(file, text, &opts.policy.limits)?;
        Self::from_prepared(file, text.into_owned(), None, opts)
    }

    /// Reads and validates a drawing from a file under `opts.policy`: a regular file within the
    /// byte limit, `.svgz` decompressed, UTF-16 or a declared encoding decoded
    /// ([`crate::input::read_svg`]).
    pub fn open(path: &std::path::Path, opts: &ReadOptions) -> Result<Self> {
        let file = crate::error::printable_path(path);
        let text = crate::input::read_svg(path, &file, &opts.ids.boundary, &opts.policy.limits)?;
        let dir = match path.parent() {
            Some(p) if p.as_os_str().is_empty() => Some(std::path::PathBuf::from(".")),
            p => p.map(std::path::Path::to_path_buf),
        };
        Self::from_prepared(&file, text, dir, opts)
    }

    fn from_prepared(
        file: &str,
        svg: String,
        dir: Option<std::path::PathBuf>,
        opts: &ReadOptions,
    ) -> Result<Self> {
        let root = xml::parse(&svg).map_err(|p| Error::input(file, p.to_string()))?;
        let (controls, tolerances, view_box) =
            controls::read_controls(&root, file, &opts.ids, opts.density, &opts.policy.limits)?;
        let notes = crate::input::refused_images(file, &svg, dir.as_deref(), &opts.policy);
        Ok(Drawing {
            file: file.to_string(),
            controls,
            tolerances,
            view_box,
            svg,
            dir,
            policy: opts.policy.clone(),
            guides_group: opts.ids.guides_group.clone(),
            notes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <path id="boundary" d="M10 10 H90 V90 H10 Z" fill="red"/>
      <g id="controls" style="display:none" transform="translate(5 0)">
        <polyline id="feature-line" points="30,50 60,50"/>
        <circle id="feature-eye" cx="45" cy="30" r="5"/>
        <circle id="anchor-top" cx="50" cy="10" r="1"/>
        <polyline id="skeleton-arm" points="30,70 50,70 70,70"/>
      </g></svg>"#;

    fn read(text: &str) -> Result<Drawing> {
        Drawing::from_str("t.svg", text, &ReadOptions::default())
    }

    #[test]
    fn reads_controls_with_transforms_and_guides() {
        let d = read(SQUARE).unwrap();
        let c = &d.controls;
        assert_eq!(c.boundary.points.len(), 4);
        assert!(c.boundary.closed);
        assert!(!c.boundary_from_view_box);
        assert_eq!(c.features.len(), 2);
        assert_eq!(c.features[0].name, "eye");
        assert!(c.features[0].closed);
        assert_eq!(c.features[1].name, "line");
        assert!(!c.features[1].closed);
        assert_eq!(
            c.features[1].points,
            vec![Point::new(35.0, 50.0), Point::new(65.0, 50.0)]
        );
        assert_eq!(c.anchors[0].point, Point::new(55.0, 10.0));
        assert_eq!(c.skeleton[0].points.len(), 3);
        assert!(
            (d.tolerances.diagonal - 80.0 * 2f64.sqrt()).abs() < 1e-9,
            "the size of a square is its diagonal"
        );
    }

    #[test]
    fn viewbox_is_the_boundary_in_image_mode() {
        let d = read(r#"<svg viewBox="0 0 200 100"><rect width="10" height="10"/></svg>"#).unwrap();
        assert!(d.controls.boundary_from_view_box);
        assert_eq!(
            crate::geometry::polygon_area(&d.controls.boundary.points),
            20000.0
        );
    }

    fn err(text: &str) -> String {
        read(text).unwrap_err().to_string()
    }

    #[test]
    fn bad_inputs_give_located_one_line_errors() {
        let cases = [
            (
                r#"<svg><path id="boundary" d="M0 0 L10 0 L10 10"/></svg>"#,
                "element 'boundary': is not closed",
            ),
            (
                r#"<svg><path id="boundary" d="M0 0 L10 10 L10 0 L0 10 Z"/></svg>"#,
                "crosses itself",
            ),
            (
                r#"<svg><path id="boundary" d="M0 0 L10 0 L20 0 Z"/></svg>"#,
                "encloses no area",
            ),
            (
                r#"<svg><path id="boundary" d="M0 0 L1e300 0 L0 10 Z"/></svg>"#,
                "too large",
            ),
            (
                r#"<svg><rect id="boundary" width="10" height="10"/><line id="feature-a" x1="5" y1="5" x2="50" y2="5"/></svg>"#,
                "element 'feature-a': leaves 'boundary'",
            ),
            (
                r#"<svg><rect id="boundary" width="10" height="10"/><line id="feature-a" x1="2" y1="5" x2="8" y2="5"/><line id="feature-b" x1="5" y1="2" x2="5" y2="8"/></svg>"#,
                "element 'feature-b': crosses 'feature-a'",
            ),
            (
                r#"<svg><rect id="boundary" width="10" height="10"/><line id="feature-a" x1="20" y1="5" x2="30" y2="5"/></svg>"#,
                "lies outside",
            ),
            (
                r#"<svg><rect id="boundary" width="10" height="10"/><rect id="boundary" width="5" height="5"/></svg>"#,
                "more than one element",
            ),
            (
                r#"<svg><path id="boundary" d="M0 0 L10 0 L0 10 Z M20 20 L30 20 L20 30 Z"/></svg>"#,
                "2 subpaths",
            ),
            (
                r#"<svg><rect id="boundary" width="10" height="10"/><line id="feature-a" x1="5" y1="5" x2="5" y2="5"/></svg>"#,
                "no length",
            ),
            (
                r#"<svg><text id="feature-a">hi</text><rect id="boundary" width="10" height="10"/></svg>"#,
                "cannot be control geometry",
            ),
            (
                r#"<svg><g></g></svg>"#,
                "no 'boundary' element and no viewBox",
            ),
            ("", "empty"),
            ("<svg><g>", "truncated"),
            ("just text", "not an SVG"),
        ];
        for (svg, expected) in cases {
            let e = err(svg);
            assert!(
                e.contains(expected),
                "{svg}\n  gave: {e}\n  expected: {expected}"
            );
            assert!(e.starts_with("t.svg"), "{e}");
            assert!(!e.contains('\n'));
        }
    }
}
