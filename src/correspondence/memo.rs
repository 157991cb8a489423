//! Correspondences already made, kept for the next build of the same curves (issue 16).
//!
//! Automatic mode corresponds a part's outline and holes again on every rung of its ladder,
//! each time it gives up a hole: the outline and the holes kept are the same curves with the
//! same anchors, so their correspondences are the same. A curve pair's correspondence depends
//! only on its two curves, its anchors, the tolerances and the options, so it is looked up by
//! their bits and made once.

use super::{CorrespondenceOptions, CurvePair};
use crate::drawing::ControlCurve;
use crate::geometry::{same_bits, Point};
use crate::tolerance::Tolerances;
use crate::Result;

/// The correspondences made so far, by what they were made from, and the misfits measured.
#[derive(Debug, Default)]
pub(crate) struct Correspondences {
    made: Vec<Made>,
    /// Per boundary pair (source, target vertices): per feature pair, its misfit.
    misfits: Vec<(Vec<Point>, Vec<Point>, Vec<Misfit>)>,
}

/// A feature pair's vertices and its misfit against a boundary pair.
#[derive(Debug)]
struct Misfit {
    source: Vec<Point>,
    target: Vec<Point>,
    misfit: f64,
}

/// One correspondence and what it was made from (the curves' ids are not part of it: the
/// result takes the id and kind of the curve it is asked for).
#[derive(Debug)]
struct Made {
    source: (Vec<Point>, bool),
    target: (Vec<Point>, bool),
    anchors: Vec<Point>,
    reverse: Option<bool>,
    tol: Tolerances,
    opts: CorrespondenceOptions,
    pairs: Vec<CurvePair>,
}

/// An optional number as bits, so that −0 and 0 are told apart.
fn bits(x: Option<f64>) -> Option<u64> {
    x.map(f64::to_bits)
}

impl Made {
    fn is_for(&self, ask: &Ask<'_>) -> bool {
        let anchors_match = self.anchors.len() == 2 * ask.anchors.len()
            && self
                .anchors
                .chunks_exact(2)
                .zip(ask.anchors)
                .all(|(m, &(p, q))| same_bits(m, &[p, q]));
        self.reverse == ask.reverse
            && self.source.1 == ask.src.closed
            && self.target.1 == ask.tgt.closed
            && same_bits(&self.source.0, &ask.src.points)
            && same_bits(&self.target.0, &ask.tgt.points)
            && anchors_match
            && self.tol == *ask.tol
            && self.opts == *ask.opts
            && bits(self.opts.preferred_rotation) == bits(ask.opts.preferred_rotation)
            && bits(self.opts.outline_turn) == bits(ask.opts.outline_turn)
    }
}

/// What a correspondence is asked for with.
pub(super) struct Ask<'a> {
    pub(super) src: &'a ControlCurve,
    pub(super) tgt: &'a ControlCurve,
    pub(super) anchors: &'a [(Point, Point)],
    pub(super) tol: &'a Tolerances,
    pub(super) opts: &'a CorrespondenceOptions,
    pub(super) reverse: Option<bool>,
}

impl Correspondences {
    /// How many correspondences and misfits it holds.
    #[cfg(test)]
    pub(super) fn counts(&self) -> (usize, usize) {
        let misfits = self.misfits.iter().map(|m| m.2.len()).sum();
        (self.made.len(), misfits)
    }

    /// [`super::misfit_of`]`(boundary, f)`, measured once for the same vertices.
    pub(super) fn misfit(&mut self, boundary: &CurvePair, f: &CurvePair) -> f64 {
        let k =
            match self.misfits.iter().position(|(s, t, _)| {
                same_bits(s, &boundary.source) && same_bits(t, &boundary.target)
            }) {
                Some(k) => k,
                None => {
                    let entry = (boundary.source.clone(), boundary.target.clone(), Vec::new());
                    self.misfits.push(entry);
                    self.misfits.len() - 1
                }
            };
        let known = &mut self.misfits[k].2;
        if let Some(m) = known
            .iter()
            .find(|m| same_bits(&m.source, &f.source) && same_bits(&m.target, &f.target))
        {
            return m.misfit;
        }
        let misfit = super::misfit_of(boundary, f);
        known.push(Misfit {
            source: f.source.clone(),
            target: f.target.clone(),
            misfit,
        });
        misfit
    }

    /// The correspondence `ask` describes: the one made before for the same curves, anchors,
    /// tolerances and options, else `make()` (kept when it succeeds). Either way the pairs
    /// carry the id and kind of `ask.src`.
    pub(super) fn get_or_make(
        &mut self,
        ask: Ask<'_>,
        make: impl FnOnce() -> Result<Vec<CurvePair>>,
    ) -> Result<Vec<CurvePair>> {
        let mut pairs = match self.made.iter().find(|m| m.is_for(&ask)) {
            Some(m) => m.pairs.clone(),
            None => {
                let pairs = make()?;
                self.made.push(Made {
                    source: (ask.src.points.clone(), ask.src.closed),
                    target: (ask.tgt.points.clone(), ask.tgt.closed),
                    anchors: ask.anchors.iter().flat_map(|&(p, q)| [p, q]).collect(),
                    reverse: ask.reverse,
                    tol: *ask.tol,
                    opts: ask.opts.clone(),
                    pairs: pairs.clone(),
                });
                pairs
            }
        };
        for p in &mut pairs {
            p.id.clone_from(&ask.src.id);
            p.kind = ask.src.kind;
        }
        Ok(pairs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::CurveKind;

    #[test]
    fn options_that_differ_only_in_the_sign_of_a_zero_are_different_asks() {
        let c = ControlCurve {
            id: "feature-a".into(),
            name: "a".into(),
            kind: CurveKind::Feature,
            closed: false,
            points: vec![Point::new(0.0, 0.0), Point::new(1.0, 0.5)],
        };
        let tol = Tolerances::new(10.0, 1.0);
        let made = &mut Correspondences::default();
        let mut calls = 0;
        let mut ask = |turn: f64, made: &mut Correspondences| {
            let opts = CorrespondenceOptions {
                preferred_rotation: Some(turn),
                ..Default::default()
            };
            let ask = Ask {
                src: &c,
                tgt: &c,
                anchors: &[],
                tol: &tol,
                opts: &opts,
                reverse: None,
            };
            made.get_or_make(ask, || {
                calls += 1;
                Ok(Vec::new())
            })
            .unwrap();
        };
        ask(0.0, made);
        ask(0.0, made);
        ask(-0.0, made);
        assert_eq!(made.counts().0, 2);
        assert_eq!(calls, 2);
    }
}
