//! Skeleton control of the motion (§4.2): the two-phase propagation, set up once and evaluated
//! per frame.
//!
//! Set-up: the joints' barycentric coordinates `C_k` in the source mesh (the derived skeleton of
//! any frame is `C_k V(t)`); the desired-skeleton track through the keys (phase 1,
//! [`PoseTrack`]); the vertices bound to bones ([`super::binding`]); and two factored systems —
//! eq. (1) alone, and eq. (2): eq. (1) plus one constant row per joint, `‖C_k V − J'_k‖²`. Both
//! matrices are constant in t, so each is factored once.
//!
//! A frame: take the derived joints `J_k = C_k V(t)` of the plain interpolation (from an
//! interpolant of 65 samples made at set-up, in intrinsic parameters, rather than a second solve)
//! and the desired joints `J'_k` from the track, give every bone the rotation and scale from
//! `J_k1 J_k2` to `J'_k1 J'_k2`, add them to the local transformations of the discs of the
//! vertices bound to the bone (phase 2), and solve eq. (2) with targets `J'_k`: one solve, as a
//! plain frame.
//!
//! Without control poses the keys are the derived skeletons themselves, so the control is
//! skipped and every frame is exactly the plain rigid interpolation.

use super::binding::bind;
use super::kinematics::PoseTrack;
use super::Skeleton;
use crate::artwork::{Location, PointLocator};
use crate::error::{Error, Result};
use crate::geometry::Point;
use crate::mesh::{CompatibleMeshes, CurveKind};
use crate::rigid::{DiscRigid, ExtraRow, FrameScratch, Repair};

/// Weight of a joint's row in eq. (2), relative to eq. (1)'s unit edge weights (a mesh vertex's
/// own diagonal is about 12): strong enough that frames meet a pose to within a small fraction of
/// the drawing, soft enough that an inconsistent pose spreads instead of tearing.
const JOINT_WEIGHT: f64 = 400.0;

/// Samples of the derived skeleton over [0, 1]: they unwrap angles for phase 1, and their
/// interpolant (in intrinsic parameters) stands in for the derived skeleton of a frame, so a
/// frame needs one solve (eq. (2)) rather than two.
const GUIDE_SAMPLES: usize = 65;

/// A control pose: the skeleton's joint positions wanted at time `t` (strictly between 0 and 1),
/// in the order of [`Skeleton::joints`].
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Time of the frame the pose was edited on.
    pub t: f64,
    /// Joint positions in the source's user space.
    pub joints: Vec<Point>,
}

/// The morph with skeleton control: plain rigid interpolation, adjusted to meet the poses.
#[derive(Debug)]
pub struct SkeletonControl {
    skeleton: Skeleton,
    triangles: Vec<[u32; 3]>,
    /// Joint locations in the source mesh (`C_k`).
    joints: Vec<Location>,
    plain: DiscRigid,
    /// Eq. (2) and its data; `None` without poses.
    control: Option<Control>,
    n: usize,
}

#[derive(Debug)]
struct Control {
    constrained: DiscRigid,
    track: PoseTrack,
    /// The derived skeleton of the plain interpolation through time.
    derived: PoseTrack,
    /// Bones bound to each vertex, with weights (see [`super::binding`]).
    bound: Vec<Vec<(u32, f64)>>,
}

/// Per-thread buffers for [`SkeletonControl::at`].
#[derive(Debug)]
pub struct ControlWorkspace {
    plain: FrameScratch,
    constrained: Option<FrameScratch>,
    adjust: Vec<Point>,
    /// Per bone: the rotation (unit complex number) and scale, derived → desired.
    bone: Vec<(Point, f64)>,
}

impl SkeletonControl {
    /// Sets up skeleton control over compatible meshes with the disc method. `skeleton` is the
    /// reference skeleton on the source; `poses` the control poses (any number; errors name the
    /// pose by its time: wrong joint count, t outside (0, 1), two poses at one time).
    pub fn new(meshes: &CompatibleMeshes, skeleton: Skeleton, poses: &[Pose]) -> Result<Self> {
        let n = meshes.source.len();
        let rings = crate::mesh::one_rings(&meshes.triangles, n);
        let plain = DiscRigid::with_area_rule(
            &meshes.source,
            &meshes.target,
            &rings,
            &meshes.triangles,
            &[],
            None,
        )?;
        let locator = PointLocator::new(&meshes.source, &meshes.triangles)?;
        let joints: Vec<Location> = skeleton.joints.iter().map(|&j| locator.locate(j)).collect();
        let mut this = SkeletonControl {
            skeleton,
            triangles: meshes.triangles.clone(),
            joints,
            plain,
            control: None,
            n,
        };
        if poses.is_empty() {
            return Ok(this);
        }
        for p in poses {
            if p.joints.len() != this.skeleton.joint_count() {
                return Err(Error::input(
                    format!("<pose t={}>", p.t),
                    format!(
                        "has {} joints, the reference skeleton {}",
                        p.joints.len(),
                        this.skeleton.joint_count()
                    ),
                ));
            }
            if !(p.t > 0.0 && p.t < 1.0) {
                return Err(Error::input(
                    format!("<pose t={}>", p.t),
                    "a control pose must be strictly between t = 0 (the source) and t = 1 (the target)",
                ));
            }
        }
        // Phase 1: keys and the guide for consistent angles.
        let guide_times: Vec<f64> = (0..GUIDE_SAMPLES)
            .map(|i| i as f64 / (GUIDE_SAMPLES - 1) as f64)
            .collect();
        let mut ws = this.plain.scratch();
        let mut mesh = vec![Point::ZERO; n];
        let guide: Vec<Vec<Point>> = guide_times
            .iter()
            .map(|&t| {
                this.plain.at(t, &mut mesh, &mut ws);
                this.derived(&mesh)
            })
            .collect();
        let mut keys = vec![
            (0.0, this.derived(&meshes.source)),
            (1.0, this.derived(&meshes.target)),
        ];
        keys.extend(poses.iter().map(|p| (p.t, p.joints.clone())));
        let track = PoseTrack::new(&this.skeleton, &keys, &guide_times, &guide)?;
        let samples: Vec<(f64, Vec<Point>)> = guide_times
            .iter()
            .copied()
            .zip(guide.iter().cloned())
            .collect();
        let derived = PoseTrack::new(&this.skeleton, &samples, &guide_times, &guide)?;
        // Phase 2 set-up: binding and eq. (2).
        let boundary: Vec<Point> = meshes
            .curves
            .iter()
            .filter(|c| c.kind == CurveKind::Boundary)
            .flat_map(|c| c.vertices.iter().map(|&v| meshes.source[v as usize]))
            .collect();
        let bound = bind(&this.skeleton, &meshes.source, &meshes.triangles, &boundary)?;
        let rows = this
            .joints
            .iter()
            .map(|l| ExtraRow {
                coeffs: this.triangles[l.triangle as usize]
                    .iter()
                    .zip(l.bary)
                    .map(|(&v, c)| (v, c))
                    .collect(),
                weight: JOINT_WEIGHT,
            })
            .collect();
        let constrained = DiscRigid::with_extra_rows(&meshes.source, &meshes.target, &rings, rows)?;
        this.control = Some(Control {
            constrained,
            track,
            derived,
            bound,
        });
        Ok(this)
    }

    /// The reference skeleton.
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// Number of mesh vertices of every frame.
    pub fn vertex_count(&self) -> usize {
        self.n
    }

    /// Whether control poses adjust the motion (false: every frame is the plain interpolation).
    pub fn is_active(&self) -> bool {
        self.control.is_some()
    }

    /// The skeleton carried by a mesh with vertex positions `vertices`: each joint at its
    /// barycentric coordinates in the source mesh, placed in `vertices` (what a frame shows).
    pub fn derived(&self, vertices: &[Point]) -> Vec<Point> {
        self.joints
            .iter()
            .map(|l| l.place(&self.triangles, vertices))
            .collect()
    }

    /// The desired skeleton at `t` (phase 1), or the plain frame's derived skeleton without
    /// poses.
    pub fn desired_at(&self, t: f64) -> Vec<Point> {
        match &self.control {
            Some(c) => c.track.at(t),
            None => {
                let mut ws = self.workspace();
                let mut out = vec![Point::ZERO; self.n];
                self.plain.at(t, &mut out, &mut ws.plain);
                self.derived(&out)
            }
        }
    }

    /// Fresh per-thread buffers.
    pub fn workspace(&self) -> ControlWorkspace {
        ControlWorkspace {
            plain: self.plain.scratch(),
            constrained: self.control.as_ref().map(|c| c.constrained.scratch()),
            adjust: vec![Point::new(1.0, 0.0); self.n],
            bone: vec![(Point::new(1.0, 0.0), 1.0); self.skeleton.bones.len()],
        }
    }

    /// The mesh at `t` into `out` (`out.len() == vertex_count()`): eq. (1), then with poses the
    /// bone transformations and eq. (2).
    ///
    /// # Panics
    /// If `out` has the wrong length (a programming error).
    pub fn at(&self, t: f64, out: &mut [Point], ws: &mut ControlWorkspace) {
        assert_eq!(
            out.len(),
            self.n,
            "output buffer length must equal vertex_count()"
        );
        let t = crate::rigid::clamp_time(t);
        let (Some(c), Some(cws)) = (&self.control, ws.constrained.as_mut()) else {
            self.plain.at(t, out, &mut ws.plain);
            return;
        };
        let desired = self.bone_adjustments(c, t, &mut ws.bone, &mut ws.adjust);
        c.constrained
            .at_adjusted(t, &desired, Some(&ws.adjust), out, cws, Repair::AsSetUp);
    }

    /// The desired skeleton at `t` (phase 1), with each vertex's bone transformation from the
    /// derived to the desired skeleton into `adjust` (§4.2.2); `bone` is scratch, one entry
    /// per bone.
    fn bone_adjustments(
        &self,
        c: &Control,
        t: f64,
        bones: &mut [(Point, f64)],
        adjust: &mut [Point],
    ) -> Vec<Point> {
        let derived = c.derived.at(t);
        let desired = c.track.at(t);
        // Each bone's rotation and scale from the derived to the desired skeleton, as a unit
        // complex number and a scale.
        for (m, &[a, b]) in bones.iter_mut().zip(&self.skeleton.bones) {
            let from = derived[b as usize] - derived[a as usize];
            let to = desired[b as usize] - desired[a as usize];
            let (lf, lt) = (from.length(), to.length());
            *m = if lf > 0.0 && lt > 0.0 && lt.is_finite() {
                (
                    Point::new(from.dot(to), from.perp_dot(to)) / (lf * lt),
                    lt / lf,
                )
            } else {
                (Point::new(1.0, 0.0), 1.0)
            };
        }
        // Each vertex: its bones' transformations blended by the binding weights (rotations by
        // normalized linear blend, scales linearly), the rest of the weight the identity.
        for (a, b) in adjust.iter_mut().zip(&c.bound) {
            *a = match b.as_slice() {
                [] => Point::new(1.0, 0.0),
                [(bone, w)] if *w >= 1.0 - 1e-9 => {
                    let (u, s) = bones[*bone as usize];
                    u * s
                }
                _ => {
                    let (mut u, mut s, mut rest) = (Point::ZERO, 0.0, 1.0);
                    for &(bone, w) in b {
                        let (ub, sb) = bones[bone as usize];
                        u += ub * w;
                        s += sb * w;
                        rest -= w;
                    }
                    u += Point::new(rest, 0.0);
                    s += rest;
                    let l = u.length();
                    if l > 1e-12 {
                        u * (s / l)
                    } else {
                        Point::new(s, 0.0)
                    }
                }
            };
        }
        desired
    }

    /// The mesh at `t` in a new vector.
    pub fn at_vec(&self, t: f64) -> Vec<Point> {
        let mut out = vec![Point::ZERO; self.n];
        self.at(t, &mut out, &mut self.workspace());
        out
    }

    /// Many frames in parallel: `frames[k]` is the mesh at `ts[k]`, with the bits
    /// [`SkeletonControl::at`] gives it; up to eight frames share each pass over the factor.
    pub fn frames(&self, ts: &[f64]) -> Vec<Vec<Point>> {
        crate::rigid::parallel_frames(
            ts,
            self.n,
            || self.workspace(),
            |ts, frames, ws| self.frames_into(ts, frames, ws),
        )
    }

    /// The meshes at every `t` of `ts` into `frames` (one vector of the mesh's length per
    /// time): each frame's desired skeleton and bone transformations, then eq. (2) solved for
    /// the frames together (`DiscRigid::frames_into`).
    fn frames_into(&self, ts: &[f64], frames: &mut [Vec<Point>], ws: &mut ControlWorkspace) {
        let ts: Vec<f64> = ts.iter().map(|&t| crate::rigid::clamp_time(t)).collect();
        let outs = frames.iter_mut().map(Vec::as_mut_slice);
        let (Some(c), Some(cws)) = (&self.control, ws.constrained.as_mut()) else {
            self.plain
                .frames_into(&ts, &[], &[], outs, &mut ws.plain, Repair::AsSetUp);
            return;
        };
        let mut targets = Vec::new();
        let mut adjust = vec![Point::ZERO; ts.len() * self.n];
        for (&t, adjust) in ts.iter().zip(adjust.chunks_mut(self.n.max(1))) {
            targets.extend(self.bone_adjustments(c, t, &mut ws.bone, adjust));
        }
        c.constrained
            .frames_into(&ts, &targets, &adjust, outs, cws, Repair::AsSetUp);
    }
}
