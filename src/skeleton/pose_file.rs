//! Pose files: a frame of the morph with its derived skeleton drawn on top, for a user to edit
//! in any SVG editor and feed back as a control pose (§4.2: "the user selects any intermediate
//! skeleton and edits it").
//!
//! The skeleton is written with the reference skeleton's own element ids (one `<path>` per id,
//! one subpath per chain, in the source's order), so reading the edited file back with the same
//! conventions gives the same chains: [`Skeleton::pose_from_chains`] then checks that the joints
//! are the same. Joints are marked by a marker at every vertex, which editors move with the
//! vertex.

use super::Skeleton;
use crate::geometry::Point;

/// `frame_svg` (a standalone frame, as [`crate::render::frame_svg`] writes it) with the skeleton
/// `joints` drawn over it. `t` is recorded in a comment with the command that uses the file;
/// `line_width` is the skeleton's stroke width in user units.
pub fn pose_svg(
    frame_svg: &str,
    skeleton: &Skeleton,
    joints: &[Point],
    t: f64,
    line_width: f64,
) -> String {
    let mut group = String::new();
    let r = 1.6 * line_width;
    group.push_str(&format!(
        "<g id=\"crmorph-pose\" fill=\"none\" stroke=\"#00acc1\" stroke-width=\"{}\" \
         stroke-linecap=\"round\" stroke-linejoin=\"round\" opacity=\"0.9\">\
         <defs><marker id=\"crmorph-joint\" viewBox=\"-1 -1 2 2\" markerUnits=\"userSpaceOnUse\" \
         markerWidth=\"{}\" markerHeight=\"{}\"><circle r=\"1\" fill=\"#ffffff\" \
         stroke=\"#00838f\" stroke-width=\"0.4\"/></marker></defs>\
         <desc>crmorph control pose at t = {t}: move the joints (keep them all, in order), then \
         run: crmorph morph SOURCE TARGET -o OUT --pose {t}=THIS_FILE</desc>",
        num(line_width),
        num(2.0 * r),
        num(2.0 * r)
    ));
    let mut ids: Vec<&str> = Vec::new();
    for (id, _) in &skeleton.chains {
        if !ids.contains(&id.as_str()) {
            ids.push(id);
        }
    }
    for id in ids {
        let mut d = String::new();
        for (_, chain) in skeleton.chains.iter().filter(|(cid, _)| cid == id) {
            for (k, &j) in chain.iter().enumerate() {
                let p = joints[j as usize];
                d.push_str(if k == 0 { "M" } else { " L" });
                d.push_str(&format!("{},{}", num(p.x), num(p.y)));
            }
            d.push(' ');
        }
        group.push_str(&format!(
            "<path id=\"{}\" d=\"{}\" marker-start=\"url(#crmorph-joint)\" \
             marker-mid=\"url(#crmorph-joint)\" marker-end=\"url(#crmorph-joint)\"/>",
            escape(id),
            d.trim_end()
        ));
    }
    group.push_str("</g>");
    match frame_svg.rfind("</svg>") {
        Some(i) => format!("{}{}{}", &frame_svg[..i], group, &frame_svg[i..]),
        None => format!("{frame_svg}{group}"),
    }
}

/// A coordinate to 1/1000 of a unit.
fn num(x: f64) -> String {
    crate::number::fixed(x, 3)
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{Drawing, ReadOptions, SkeletonChain};

    #[test]
    fn a_pose_file_reads_back_as_the_same_joints() {
        let chains = vec![
            SkeletonChain {
                id: "skeleton-body".into(),
                points: vec![Point::new(50.0, 90.0), Point::new(50.0, 40.0)],
            },
            SkeletonChain {
                id: "skeleton-arms".into(),
                points: vec![Point::new(50.0, 60.0), Point::new(30.0, 50.0)],
            },
            SkeletonChain {
                id: "skeleton-arms".into(),
                points: vec![Point::new(50.0, 60.0), Point::new(70.0, 50.5)],
            },
        ];
        let s = Skeleton::from_chains("a.svg", &chains, 1e-6).unwrap();
        let frame = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100"><rect width="100" height="100" fill="#eee"/></svg>"##;
        let moved: Vec<Point> = s
            .joints
            .iter()
            .map(|p| *p + Point::new(1.5, -2.25))
            .collect();
        let text = pose_svg(frame, &s, &moved, 0.4, 1.0);
        assert!(text.ends_with("</svg>"));
        let d = Drawing::from_str("pose.svg", &text, &ReadOptions::default()).unwrap();
        let back = s
            .pose_from_chains("pose.svg", &d.controls.skeleton)
            .unwrap();
        for (a, b) in back.iter().zip(&moved) {
            assert!(a.distance(*b) < 1e-3, "{a} vs {b}");
        }
        usvg::Tree::from_str(&text, &usvg::Options::default()).expect("valid SVG");
    }
}
