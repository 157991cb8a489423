//! Skeleton control (§4.2) on the dancer fixture: without poses nothing changes; with a pose the
//! frame meets it while the ends stay exact; bones of the desired skeleton never shrink; a
//! lower-body skeleton leaves the upper body moving as without it; no frame inverts a triangle.

use crmorph::geometry::Point;
use crmorph::mesh::count_inverted;
use crmorph::rigid::{Interpolator, Method};
use crmorph::skeleton::{Pose, Skeleton, SkeletonControl};

use crate::common::{compatible, fixtures, open};

struct Dancer {
    meshes: crmorph::CompatibleMeshes,
    skeleton: Skeleton,
    diagonal: f64,
}

fn dancer(source: &str) -> Dancer {
    let dir = fixtures().join("dancer");
    let (s, t) = (open(&dir.join(source)), open(&dir.join("target.svg")));
    let c = compatible(&s, &t, false);
    let skeleton = Skeleton::from_chains(&s.file, &s.controls.skeleton, c.tolerances.snap)
        .unwrap_or_else(|e| panic!("{e}"));
    Dancer {
        meshes: c.meshes,
        skeleton,
        diagonal: c.tolerances.diagonal,
    }
}

/// `pose` with the joints of every chain with id `id` after the chain's first joint rotated by
/// `angle` about that first joint (a limb swung at its root: bone lengths kept).
fn swing(skeleton: &Skeleton, pose: &[Point], id: &str, which: usize, angle: f64) -> Vec<Point> {
    let mut out = pose.to_vec();
    let (_, joints) = skeleton
        .chains
        .iter()
        .filter(|(cid, _)| cid == id)
        .nth(which)
        .expect("chain");
    let pivot = pose[joints[0] as usize];
    let r = Point::from_angle(angle);
    for &j in &joints[1..] {
        out[j as usize] = pivot + r.rotate(pose[j as usize] - pivot);
    }
    out
}

/// Skeleton control of `d` without poses (the plain interpolation) and its derived skeleton at
/// `t`, the starting point of a pose.
fn unposed(d: &Dancer, t: f64) -> (SkeletonControl, Vec<Point>) {
    let plain = SkeletonControl::new(&d.meshes, d.skeleton.clone(), &[]).unwrap();
    let derived = plain.derived(&plain.at_vec(t));
    (plain, derived)
}

/// Skeleton control of `d` without poses, its derived skeleton at `t`, and that skeleton
/// with the second leg swung by `degrees` at the hip: the pose the tests set at `t`.
fn leg_swung(d: &Dancer, t: f64, degrees: f64) -> (SkeletonControl, Vec<Point>, Vec<Point>) {
    let (plain, derived) = unposed(d, t);
    let pose = swing(
        &d.skeleton,
        &derived,
        "skeleton-legs",
        1,
        degrees.to_radians(),
    );
    (plain, derived, pose)
}

/// Skeleton control of `d` with one pose, `joints` at `t`.
fn posed(d: &Dancer, t: f64, joints: Vec<Point>) -> SkeletonControl {
    SkeletonControl::new(&d.meshes, d.skeleton.clone(), &[Pose { t, joints }])
        .unwrap_or_else(|e| panic!("{e}"))
}

fn max_distance(a: &[Point], b: &[Point]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

#[test]
fn without_poses_the_motion_is_the_plain_rigid_interpolation() {
    let d = dancer("source.svg");
    let m = &d.meshes;
    let control = SkeletonControl::new(m, d.skeleton.clone(), &[]).unwrap();
    assert!(!control.is_active());
    let plain = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    for t in [0.0, 0.3, 0.77, 1.0] {
        assert_eq!(control.at_vec(t), plain.at_vec(t), "t = {t}");
    }
}

#[test]
fn a_pose_is_met_at_its_frame_and_the_ends_stay_exact() {
    let d = dancer("source.svg");
    let m = &d.meshes;
    let tc = 0.5;
    // Kick the second leg up by 35° and raise the first arm by 30°.
    let (_, derived, pose) = leg_swung(&d, tc, -35.0);
    let pose = swing(&d.skeleton, &pose, "skeleton-arms", 0, 30f64.to_radians());
    let control = posed(&d, tc, pose.clone());
    assert!(control.is_active());
    let at_tc = control.at_vec(tc);
    let miss = max_distance(&control.derived(&at_tc), &pose);
    eprintln!(
        "pose at t = {tc}: joints within {miss:.3} ({:.4} of the diagonal)",
        miss / d.diagonal
    );
    assert!(miss <= 0.01 * d.diagonal, "joints miss the pose by {miss}");
    // The pose changes the frame visibly: the kicked foot moved.
    let moved = max_distance(&derived, &pose);
    assert!(moved > 0.1 * d.diagonal, "{moved}");
    // Ends exact.
    let eps = 1e-9 * d.diagonal;
    assert!(max_distance(&control.at_vec(0.0), &m.source) <= eps);
    assert!(max_distance(&control.at_vec(1.0), &m.target) <= eps);
    // No triangle inverts in any frame.
    let ts: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let frames = control.frames(&ts);
    let inverted: usize = frames.iter().map(|f| count_inverted(&m.triangles, f)).sum();
    for (t, f) in ts.iter().zip(&frames) {
        let n = count_inverted(&m.triangles, f);
        if n > 0 {
            for tri in &m.triangles {
                let [a, b, c] = tri.map(|v| f[v as usize]);
                if (b - a).perp_dot(c - a) <= 0.0 {
                    eprintln!("t={t} inverted at source {:?}", m.source[tri[0] as usize]);
                }
            }
        }
    }
    assert_eq!(inverted, 0, "inverted triangles over 101 frames");
}

#[test]
fn desired_bones_stay_between_their_key_lengths() {
    let d = dancer("source.svg");
    let m = &d.meshes;
    let plain = SkeletonControl::new(m, d.skeleton.clone(), &[]).unwrap();
    let key_times = [0.0, 0.35, 0.7, 1.0];
    let mut keys: Vec<Vec<Point>> = key_times
        .iter()
        .map(|&t| plain.derived(&plain.at_vec(t)))
        .collect();
    keys[1] = swing(
        &d.skeleton,
        &keys[1],
        "skeleton-legs",
        0,
        60f64.to_radians(),
    );
    keys[2] = swing(
        &d.skeleton,
        &keys[2],
        "skeleton-arms",
        1,
        -80f64.to_radians(),
    );
    let poses: Vec<Pose> = (1..3)
        .map(|k| Pose {
            t: key_times[k],
            joints: keys[k].clone(),
        })
        .collect();
    let control = SkeletonControl::new(m, d.skeleton.clone(), &poses).unwrap();
    let len = |p: &[Point], [a, b]: [u32; 2]| p[a as usize].distance(p[b as usize]);
    let mut linear_shrink = 0.0f64;
    for i in 0..=200 {
        let t = i as f64 / 200.0;
        let k = key_times.windows(2).position(|w| t <= w[1]).unwrap();
        let desired = control.desired_at(t);
        let u = (t - key_times[k]) / (key_times[k + 1] - key_times[k]);
        let linear: Vec<Point> = keys[k]
            .iter()
            .zip(&keys[k + 1])
            .map(|(a, b)| *a + (*b - *a) * u)
            .collect();
        for &bone in &d.skeleton.bones {
            let (a, b) = (len(&keys[k], bone), len(&keys[k + 1], bone));
            let l = len(&desired, bone);
            assert!(
                l >= a.min(b) * (1.0 - 1e-9) && l <= a.max(b) * (1.0 + 1e-9),
                "bone {bone:?} at t = {t}: {l} outside [{a}, {b}]"
            );
            linear_shrink = linear_shrink.max(1.0 - len(&linear, bone) / a.min(b));
        }
    }
    eprintln!(
        "linear joint interpolation shrinks a bone by {:.1} %",
        100.0 * linear_shrink
    );
    assert!(
        linear_shrink > 0.05,
        "the keys are ones where linear interpolation shrinks bones"
    );
}

#[test]
fn a_lower_body_skeleton_leaves_the_upper_body_alone() {
    let d = dancer("source-lower.svg");
    let m = &d.meshes;
    let tc = 0.5;
    let (plain, _, pose) = leg_swung(&d, tc, -30.0);
    let control = posed(&d, tc, pose);
    // Vertices above the chest (y < 140 in the source: head and arms) are far from the hip and
    // legs.
    let upper: Vec<usize> = (0..m.source.len())
        .filter(|&v| m.source[v].y < 140.0)
        .collect();
    assert!(upper.len() > 50);
    let mut worst = 0.0f64;
    let mut legs = 0.0f64;
    for t in [0.25, 0.5, 0.75] {
        let (a, b) = (control.at_vec(t), plain.at_vec(t));
        for &v in &upper {
            worst = worst.max(a[v].distance(b[v]));
        }
        legs = legs.max(max_distance(&a, &b));
    }
    eprintln!(
        "upper body moved by at most {worst:.3} ({:.4} of the diagonal); the frame by {legs:.2}",
        worst / d.diagonal
    );
    assert!(
        legs > 0.05 * d.diagonal,
        "the pose changes the legs: {legs}"
    );
    assert!(
        worst <= 0.02 * d.diagonal,
        "the upper body moved by {worst}"
    );
}

#[test]
fn the_bundled_poses_morph_without_inverted_triangles() {
    for (source, pose_file) in [
        ("source.svg", "pose-0.5.svg"),
        ("source-lower.svg", "pose-lower-0.5.svg"),
    ] {
        let d = dancer(source);
        let m = &d.meshes;
        let pose_drawing = open(&fixtures().join("dancer").join(pose_file));
        let joints = d
            .skeleton
            .pose_from_chains(&pose_drawing.file, &pose_drawing.controls.skeleton)
            .unwrap_or_else(|e| panic!("{e}"));
        let control = posed(&d, 0.5, joints.clone());
        let miss = max_distance(&control.derived(&control.at_vec(0.5)), &joints);
        assert!(
            miss <= 0.01 * d.diagonal,
            "{pose_file}: joints miss by {miss}"
        );
        let ts: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        let inverted: usize = control
            .frames(&ts)
            .iter()
            .map(|f| count_inverted(&m.triangles, f))
            .sum();
        assert_eq!(
            inverted, 0,
            "{pose_file}: inverted triangles over 101 frames"
        );
    }
}

/// Frames solved together (up to eight per pass over the factor, on rayon's threads) have the
/// bits of frames solved one at a time, with a pose (per-frame targets and bone adjustments)
/// and without, over batches of several lengths and times outside [0, 1].
#[test]
fn frames_solved_together_have_the_bits_of_lone_frames() {
    let d = dancer("source.svg");
    let tc = 0.5;
    let (plain, _, pose) = leg_swung(&d, tc, -35.0);
    let posed = posed(&d, tc, pose);
    for (name, control) in [("unposed", &plain), ("posed", &posed)] {
        for count in [1usize, 3, 8, 9, 17] {
            let ts: Vec<f64> = (0..count)
                .map(|i| -0.1 + 1.2 * i as f64 / count as f64)
                .collect();
            let frames = control.frames(&ts);
            assert_eq!(frames.len(), count);
            for (&t, frame) in ts.iter().zip(&frames) {
                let lone = control.at_vec(t);
                let same = frame.len() == lone.len()
                    && frame.iter().zip(&lone).all(|(a, b)| {
                        a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits()
                    });
                assert!(
                    same,
                    "{name}, {count} frames: t = {t} differs from its lone frame"
                );
            }
        }
    }
}
