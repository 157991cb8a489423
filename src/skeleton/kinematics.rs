//! Phase 1 of skeleton control, frame-to-frame propagation (§4.2.1).
//!
//! The keys — the reference skeleton at t = 0, the control poses, the target's derived skeleton
//! at t = 1 — are turned into *intrinsic parameters*: each root's position, each bone's length,
//! and each bone's angle relative to its parent bone (absolute for bones leaving a root). Every
//! parameter is interpolated through the keys with a monotone cubic (Fritsch–Carlson PCHIP: smooth,
//! and never beyond its neighbouring keys, so a bone never gets shorter than both its key
//! lengths), and the skeleton at t is rebuilt by forward kinematics. Interpolating joint
//! positions instead shortens bones that turn (Fig.6(b)); this does not (Fig.6(a)).
//!
//! Angles are unwrapped with consistent rotation: each key's angles take the branch (± 2kπ)
//! nearest to the derived skeleton sequence at the key's time, whose angles are themselves
//! followed continuously from t = 0, so a bone that the morph turns by more than half a turn
//! keeps turning the same way.

use super::Skeleton;
use crate::error::{Error, Result};
use crate::geometry::Point;
use std::f64::consts::{PI, TAU};

/// The desired skeleton through time: keys' intrinsic parameters and their interpolant.
#[derive(Debug, Clone)]
pub struct PoseTrack {
    /// Parent of each joint (`None` for roots).
    parent: Vec<Option<u32>>,
    /// Joints with parents before children.
    order: Vec<u32>,
    /// Key times, increasing, from 0 to 1.
    times: Vec<f64>,
    /// Per key, the parameter vector (see [`PoseTrack::params`]).
    keys: Vec<Vec<f64>>,
    /// Per key, per parameter: the PCHIP slope.
    slopes: Vec<Vec<f64>>,
}

impl PoseTrack {
    /// Builds the track. `keys` are `(t, joint positions)` in any order, including t = 0 and
    /// t = 1; `guide` is the derived skeleton sampled at increasing times `guide_times` from 0
    /// to 1, used to unwrap angles. Errors on keys outside [0, 1], two keys at one time, or a
    /// pose with the wrong joint count or a zero-length bone.
    pub fn new(
        skeleton: &Skeleton,
        keys: &[(f64, Vec<Point>)],
        guide_times: &[f64],
        guide: &[Vec<Point>],
    ) -> Result<Self> {
        let n = skeleton.joint_count();
        let mut keys: Vec<&(f64, Vec<Point>)> = keys.iter().collect();
        keys.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in keys.windows(2) {
            if (w[1].0 - w[0].0).abs() < 1e-9 {
                return Err(Error::input(
                    "<pose>",
                    format!("two skeleton keys at t = {}", w[0].0),
                ));
            }
        }
        if keys.first().map(|k| k.0) != Some(0.0) || keys.last().map(|k| k.0) != Some(1.0) {
            return Err(Error::internal("pose track keys must span t = 0 to 1"));
        }
        // The guide's absolute bone angles, unwrapped along its samples.
        let mut guide_angles: Vec<Vec<f64>> = Vec::with_capacity(guide.len());
        for (s, g) in guide.iter().enumerate() {
            let mut a = absolute_angles(skeleton, g);
            if s > 0 {
                for (x, prev) in a.iter_mut().zip(&guide_angles[s - 1]) {
                    *x = nearest_branch(*x, *prev);
                }
            }
            guide_angles.push(a);
        }
        let guide_at = |t: f64| -> Vec<f64> {
            let k = guide_times
                .windows(2)
                .position(|w| t <= w[1])
                .unwrap_or(guide_times.len().saturating_sub(2));
            let (t0, t1) = (
                guide_times[k],
                guide_times[(k + 1).min(guide_times.len() - 1)],
            );
            let u = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
            let (a, b) = (
                &guide_angles[k],
                &guide_angles[(k + 1).min(guide.len() - 1)],
            );
            a.iter().zip(b).map(|(x, y)| x + (y - x) * u).collect()
        };
        let mut params = Vec::with_capacity(keys.len());
        for (t, pose) in &keys {
            if pose.len() != n {
                return Err(Error::input(
                    "<pose>",
                    format!("has {} joints, the reference skeleton {n}", pose.len()),
                ));
            }
            if !(0.0..=1.0).contains(t) {
                return Err(Error::input("<pose>", format!("t = {t} is outside [0, 1]")));
            }
            let along = guide_at(*t);
            let mut abs = absolute_angles(skeleton, pose);
            for (x, g) in abs.iter_mut().zip(&along) {
                *x = nearest_branch(*x, *g);
            }
            params.push(Self::params(skeleton, pose, &abs)?);
        }
        let times: Vec<f64> = keys.iter().map(|k| k.0).collect();
        let slopes = pchip_slopes(&times, &params);
        Ok(PoseTrack {
            parent: skeleton.parent.clone(),
            order: skeleton.order.clone(),
            times,
            keys: params,
            slopes,
        })
    }

    /// Parameter vector of a pose with unwrapped absolute bone angles `abs` (per joint, the
    /// angle of the bone from its parent): per joint `[x, y]` for a root, `[length, angle]`
    /// otherwise, the angle relative to the parent's bone (absolute when the parent is a root).
    fn params(skeleton: &Skeleton, pose: &[Point], abs: &[f64]) -> Result<Vec<f64>> {
        let mut out = vec![0.0; 2 * pose.len()];
        for (j, p) in skeleton.parent.iter().enumerate() {
            match p {
                None => {
                    out[2 * j] = pose[j].x;
                    out[2 * j + 1] = pose[j].y;
                }
                Some(p) => {
                    let len = pose[j].distance(pose[*p as usize]);
                    if len.is_nan() || len <= 0.0 {
                        return Err(Error::input(
                            "<pose>",
                            format!(
                                "joint {j} sits on its parent joint {p}: a bone of zero length"
                            ),
                        ));
                    }
                    out[2 * j] = len;
                    out[2 * j + 1] = match skeleton.parent[*p as usize] {
                        None => abs[j],
                        Some(_) => abs[j] - abs[*p as usize],
                    };
                }
            }
        }
        Ok(out)
    }

    /// The desired skeleton's joint positions at `t` (clamped to [0, 1]), by forward kinematics
    /// from the interpolated parameters.
    pub fn at(&self, t: f64) -> Vec<Point> {
        let q = self.params_at(t);
        let n = self.parent.len();
        let mut pos = vec![Point::ZERO; n];
        let mut abs = vec![0.0; n];
        for &j in &self.order {
            let j = j as usize;
            match self.parent[j] {
                None => pos[j] = Point::new(q[2 * j], q[2 * j + 1]),
                Some(p) => {
                    let p = p as usize;
                    abs[j] = match self.parent[p] {
                        None => q[2 * j + 1],
                        Some(_) => abs[p] + q[2 * j + 1],
                    };
                    pos[j] = pos[p] + Point::from_angle(abs[j]) * q[2 * j];
                }
            }
        }
        pos
    }

    /// Bone lengths at `t`, per joint (0 for roots): for tests and diagnostics.
    pub fn lengths_at(&self, t: f64) -> Vec<f64> {
        let q = self.params_at(t);
        (0..self.parent.len())
            .map(|j| {
                if self.parent[j].is_some() {
                    q[2 * j]
                } else {
                    0.0
                }
            })
            .collect()
    }

    fn params_at(&self, t: f64) -> Vec<f64> {
        let t = crate::rigid::clamp_time(t);
        let k = self
            .times
            .windows(2)
            .position(|w| t <= w[1])
            .unwrap_or(self.times.len() - 2);
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let h = t1 - t0;
        let s = (t - t0) / h;
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
            s * (1.0 - s) * (1.0 - s),
            s * s * (3.0 - 2.0 * s),
            s * s * (s - 1.0),
        );
        (0..self.keys[k].len())
            .map(|i| {
                h00 * self.keys[k][i]
                    + h10 * h * self.slopes[k][i]
                    + h01 * self.keys[k + 1][i]
                    + h11 * h * self.slopes[k + 1][i]
            })
            .collect()
    }
}

/// Absolute angle of the bone into each joint from its parent (0 for roots).
pub(crate) fn absolute_angles(skeleton: &Skeleton, pose: &[Point]) -> Vec<f64> {
    skeleton
        .parent
        .iter()
        .enumerate()
        .map(|(j, p)| match p {
            Some(p) => {
                let d = pose[j] - pose[*p as usize];
                d.y.atan2(d.x)
            }
            None => 0.0,
        })
        .collect()
}

/// `a` moved by a multiple of 2π to within π of `reference`.
pub(crate) fn nearest_branch(a: f64, reference: f64) -> f64 {
    a - TAU * ((a - reference + PI) / TAU).floor()
}

/// Fritsch–Carlson slopes per key and parameter: zero at local extrema, a weighted harmonic
/// mean of the neighbouring secants elsewhere, the secant at the ends. The Hermite cubic with
/// these slopes is monotone on every interval.
fn pchip_slopes(times: &[f64], keys: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let m = keys.len();
    let dim = keys.first().map_or(0, Vec::len);
    let mut slopes = vec![vec![0.0; dim]; m];
    for i in 0..dim {
        let h: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let d: Vec<f64> = (0..m - 1)
            .map(|k| (keys[k + 1][i] - keys[k][i]) / h[k])
            .collect();
        slopes[0][i] = d[0];
        slopes[m - 1][i] = d[m - 2];
        for k in 1..m - 1 {
            slopes[k][i] = if d[k - 1] * d[k] <= 0.0 {
                0.0
            } else {
                let (w1, w2) = (2.0 * h[k] + h[k - 1], h[k] + 2.0 * h[k - 1]);
                (w1 + w2) / (w1 / d[k - 1] + w2 / d[k])
            };
        }
    }
    slopes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arm() -> Skeleton {
        crate::skeleton::reference::one_chain(&[
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(20.0, 0.0),
        ])
    }

    fn rotate(p: &[Point], a: f64) -> Vec<Point> {
        p.iter().map(|q| Point::from_angle(a).rotate(*q)).collect()
    }

    #[test]
    fn keys_are_reproduced_and_bones_do_not_shrink() {
        let s = arm();
        let r = s.joints.clone();
        // The arm swings by 160° to the control pose and back to 20°, its elbow bent.
        let mut bent = rotate(&r, 160f64.to_radians());
        bent[2] = bent[1] + Point::from_angle(100f64.to_radians()) * 10.0;
        let target = rotate(&r, 20f64.to_radians());
        let guide_times: Vec<f64> = (0..=20).map(|i| i as f64 / 20.0).collect();
        let guide: Vec<Vec<Point>> = guide_times
            .iter()
            .map(|t| rotate(&r, t * 20f64.to_radians()))
            .collect();
        let keys = vec![(0.0, r.clone()), (0.4, bent.clone()), (1.0, target.clone())];
        let track = PoseTrack::new(&s, &keys, &guide_times, &guide).unwrap();
        for (t, pose) in &keys {
            for (a, b) in track.at(*t).iter().zip(pose) {
                assert!(a.distance(*b) < 1e-9, "key at {t}: {a} vs {b}");
            }
        }
        let mut linear_shrinks = false;
        for i in 0..=100 {
            let t = i as f64 / 100.0;
            for len in track.lengths_at(t).iter().skip(1) {
                assert!((len - 10.0).abs() < 1e-9, "bone length {len} at {t}");
            }
            let p = track.at(t);
            assert!((p[1].distance(p[0]) - 10.0).abs() < 1e-9);
            // Joint positions interpolated linearly between the keys shrink the bone.
            let (k0, k1, u) = if t <= 0.4 {
                (&r, &bent, t / 0.4)
            } else {
                (&bent, &target, (t - 0.4) / 0.6)
            };
            let lin: Vec<Point> = k0.iter().zip(k1).map(|(a, b)| *a + (*b - *a) * u).collect();
            linear_shrinks |= lin[1].distance(lin[0]) < 9.0;
        }
        assert!(
            linear_shrinks,
            "the test pose is one where linear interpolation shrinks"
        );
    }

    #[test]
    fn angles_follow_the_guide_past_half_a_turn() {
        let s = arm();
        let r = s.joints.clone();
        // The morph turns the arm by 270°; with only the end keys the track must turn the same
        // way, not by −90°.
        let guide_times: Vec<f64> = (0..=30).map(|i| i as f64 / 30.0).collect();
        let guide: Vec<Vec<Point>> = guide_times
            .iter()
            .map(|t| rotate(&r, t * 270f64.to_radians()))
            .collect();
        let end = guide.last().unwrap().clone();
        let track =
            PoseTrack::new(&s, &[(0.0, r.clone()), (1.0, end)], &guide_times, &guide).unwrap();
        let mid = track.at(0.5);
        let want = rotate(&r, 135f64.to_radians());
        assert!(mid[2].distance(want[2]) < 1e-9, "{} vs {}", mid[2], want[2]);
        assert!(PoseTrack::new(
            &s,
            &[(0.0, r.clone()), (0.0, r.clone())],
            &[0.0, 1.0],
            &[r.clone(), r.clone()]
        )
        .is_err());
    }

    #[test]
    fn pchip_stays_within_neighbouring_keys() {
        let times = [0.0, 0.3, 0.5, 1.0];
        let keys: Vec<Vec<f64>> = [1.0, 3.0, 3.2, 0.5].iter().map(|v| vec![*v]).collect();
        let slopes = pchip_slopes(&times, &keys);
        assert_eq!(slopes[0].len(), 1);
        let track = PoseTrack {
            parent: vec![None],
            order: vec![0],
            times: times.to_vec(),
            keys: keys.iter().map(|k| vec![k[0], 0.0]).collect(),
            slopes: pchip_slopes(
                &times,
                &keys.iter().map(|k| vec![k[0], 0.0]).collect::<Vec<_>>(),
            ),
        };
        for i in 0..=200 {
            let t = i as f64 / 200.0;
            let v = track.params_at(t)[0];
            let k = times.windows(2).position(|w| t <= w[1]).unwrap();
            let (a, b) = (keys[k][0], keys[k + 1][0]);
            assert!(v >= a.min(b) - 1e-12 && v <= a.max(b) + 1e-12, "{v} at {t}");
        }
    }
}
