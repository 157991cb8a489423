//! The reference skeleton (§4.2): joints and bones from the source drawing's `skeleton` /
//! `skeleton-NAME` polylines, joined into trees.
//!
//! Every polyline vertex is a joint and every segment a bone. Chains that share a joint (within
//! the drawing's snapping tolerance) join there, so `M200,232 L200,150 M200,150 L172,124` is one
//! tree of three joints. Several separate trees are allowed (each has its own root); a cycle is
//! an error, because a bone loop has no forward kinematics. The skeleton may cover only part of
//! the shape (regional control, Fig.14(a)).

use crate::drawing::SkeletonChain;
use crate::error::{Error, Result};
use crate::geometry::Point;

/// Joints, bones and the tree structure of a skeleton.
#[derive(Debug, Clone, PartialEq)]
pub struct Skeleton {
    /// Joint positions, in order of first appearance in the chains.
    pub joints: Vec<Point>,
    /// Bones as `(parent, child)` joint indices, in chain order.
    pub bones: Vec<[u32; 2]>,
    /// The parent of each joint (`None` for a root).
    pub parent: Vec<Option<u32>>,
    /// Joints in an order where every parent comes before its children (roots first).
    pub order: Vec<u32>,
    /// The chains as read: `(element id, joint indices)`, so that a pose can be written with the
    /// same elements and read back joint by joint.
    pub chains: Vec<(String, Vec<u32>)>,
}

impl Skeleton {
    /// Builds the skeleton from the chains of `file`, joining joints closer than `snap`.
    /// Errors name the file and the chain: no chains, a bone of zero length, a cycle.
    pub fn from_chains(file: &str, chains: &[SkeletonChain], snap: f64) -> Result<Self> {
        if chains.is_empty() {
            return Err(Error::input(file, "has no skeleton polylines"));
        }
        let mut joints: Vec<Point> = Vec::new();
        let mut bones_raw: Vec<(u32, u32, String)> = Vec::new();
        let mut layout = Vec::new();
        for c in chains {
            let mut idx = Vec::with_capacity(c.points.len());
            for &p in &c.points {
                let j = match joints.iter().position(|q| q.distance(p) <= snap) {
                    Some(j) => j as u32,
                    None => {
                        joints.push(p);
                        (joints.len() - 1) as u32
                    }
                };
                if idx.last() == Some(&j) {
                    return Err(Error::at(file, &c.id, "has a bone of zero length"));
                }
                idx.push(j);
            }
            for w in idx.windows(2) {
                let dup = bones_raw
                    .iter()
                    .any(|(a, b, _)| (*a == w[0] && *b == w[1]) || (*a == w[1] && *b == w[0]));
                if !dup {
                    bones_raw.push((w[0], w[1], c.id.clone()));
                }
            }
            layout.push((c.id.clone(), idx));
        }
        // Orient every bone away from a root by breadth-first search; the root of a tree is its
        // first joint in document order.
        let n = joints.len();
        let mut adj: Vec<Vec<(u32, usize)>> = vec![Vec::new(); n];
        for (b, (a, c, _)) in bones_raw.iter().enumerate() {
            adj[*a as usize].push((*c, b));
            adj[*c as usize].push((*a, b));
        }
        let mut parent = vec![None; n];
        let mut seen = vec![false; n];
        let mut used = vec![false; bones_raw.len()];
        let mut order = Vec::with_capacity(n);
        let mut bones = Vec::with_capacity(bones_raw.len());
        for root in 0..n {
            if seen[root] {
                continue;
            }
            seen[root] = true;
            let mut queue = std::collections::VecDeque::from([root as u32]);
            while let Some(j) = queue.pop_front() {
                order.push(j);
                for &(k, b) in &adj[j as usize] {
                    if used[b] {
                        continue;
                    }
                    used[b] = true;
                    if seen[k as usize] {
                        return Err(Error::at(
                            file,
                            &bones_raw[b].2,
                            "closes a loop of bones; a skeleton must be a tree",
                        ));
                    }
                    seen[k as usize] = true;
                    parent[k as usize] = Some(j);
                    bones.push([j, k]);
                    queue.push_back(k);
                }
            }
        }
        Ok(Skeleton {
            joints,
            bones,
            parent,
            order,
            chains: layout,
        })
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Reads a pose (new joint positions) from chains laid out like this skeleton's: the same
    /// element ids with the same number of joints each, in the same order. Joints shared by
    /// several chains take the mean of their copies. Errors name `file` and the first chain that
    /// does not match.
    pub fn pose_from_chains(&self, file: &str, chains: &[SkeletonChain]) -> Result<Vec<Point>> {
        if chains.len() != self.chains.len() {
            return Err(Error::input(
                file,
                format!(
                    "has {} skeleton chains, the reference skeleton {} ({}); a pose must keep the \
                     same joints in the same order",
                    chains.len(),
                    self.chains.len(),
                    self.chain_summary()
                ),
            ));
        }
        let mut sum = vec![Point::ZERO; self.joints.len()];
        let mut count = vec![0u32; self.joints.len()];
        for (c, (id, idx)) in chains.iter().zip(&self.chains) {
            if c.id != *id || c.points.len() != idx.len() {
                return Err(Error::at(
                    file,
                    &c.id,
                    format!(
                        "has {} joints where the reference skeleton's chain '{id}' has {}; a pose \
                         must keep the same joints in the same order",
                        c.points.len(),
                        idx.len()
                    ),
                ));
            }
            for (&p, &j) in c.points.iter().zip(idx) {
                sum[j as usize] += p;
                count[j as usize] += 1;
            }
        }
        Ok(sum
            .iter()
            .zip(&count)
            .map(|(s, &c)| *s / c.max(1) as f64)
            .collect())
    }

    fn chain_summary(&self) -> String {
        self.chains
            .iter()
            .map(|(id, idx)| format!("{id}: {} joints", idx.len()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A skeleton of one chain through `points`, for tests.
#[cfg(test)]
pub(crate) fn one_chain(points: &[Point]) -> Skeleton {
    let chain = SkeletonChain {
        id: "skeleton".into(),
        points: points.to_vec(),
    };
    Skeleton::from_chains("a.svg", &[chain], 1e-6).expect("a test chain")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(id: &str, pts: &[(f64, f64)]) -> SkeletonChain {
        SkeletonChain {
            id: id.into(),
            points: pts.iter().map(|&(x, y)| Point::new(x, y)).collect(),
        }
    }

    #[test]
    fn chains_sharing_joints_make_one_tree() {
        let s = Skeleton::from_chains(
            "a.svg",
            &[
                chain("skeleton-body", &[(0.0, 0.0), (0.0, -10.0), (0.0, -20.0)]),
                chain("skeleton-arm", &[(0.0, -10.0), (5.0, -12.0), (9.0, -9.0)]),
                chain("skeleton-arm", &[(0.0, -10.0001), (-5.0, -12.0)]),
            ],
            0.01,
        )
        .unwrap();
        assert_eq!(s.joint_count(), 6);
        assert_eq!(s.bones.len(), 5);
        assert_eq!(s.parent[0], None);
        assert!(s.parent[1..].iter().all(|p| p.is_some()));
        // Parents come first.
        let pos = |j: u32| s.order.iter().position(|&k| k == j).unwrap();
        for (j, p) in s.parent.iter().enumerate() {
            if let Some(p) = p {
                assert!(pos(*p) < pos(j as u32));
            }
        }
        // A pose with the same layout reads back; shared joints average their copies.
        let mut moved: Vec<SkeletonChain> = vec![
            chain("skeleton-body", &[(1.0, 0.0), (1.0, -10.0), (1.0, -20.0)]),
            chain("skeleton-arm", &[(1.0, -10.0), (6.0, -12.0), (10.0, -9.0)]),
            chain("skeleton-arm", &[(1.0, -10.0), (-4.0, -12.0)]),
        ];
        let pose = s.pose_from_chains("p.svg", &moved).unwrap();
        for (a, b) in pose.iter().zip(&s.joints) {
            assert!((*a - *b - Point::new(1.0, 0.0)).length() < 1e-3);
        }
        moved[1].points.pop();
        let e = s.pose_from_chains("p.svg", &moved).unwrap_err().to_string();
        assert!(
            e.contains("p.svg") && e.contains("skeleton-arm") && e.contains("joints"),
            "{e}"
        );
        let e = s
            .pose_from_chains("p.svg", &moved[..1])
            .unwrap_err()
            .to_string();
        assert!(e.contains("1 skeleton chains"), "{e}");
    }

    #[test]
    fn loops_and_empty_skeletons_are_errors() {
        let e = Skeleton::from_chains(
            "a.svg",
            &[chain(
                "skeleton-loop",
                &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 0.0)],
            )],
            0.01,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("skeleton-loop") && e.contains("loop"), "{e}");
        assert!(Skeleton::from_chains("a.svg", &[], 0.01).is_err());
        // Separate trees are fine.
        let s = Skeleton::from_chains(
            "a.svg",
            &[
                chain("skeleton-a", &[(0.0, 0.0), (1.0, 0.0)]),
                chain("skeleton-b", &[(5.0, 0.0), (6.0, 0.0)]),
            ],
            0.01,
        )
        .unwrap();
        assert_eq!(s.parent.iter().filter(|p| p.is_none()).count(), 2);
    }
}
