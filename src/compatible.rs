//! Compatible triangulation of a source and a target drawing: stages 2–4 of the pipeline.
//!
//! [`build`] runs the vertex correspondence (§3), the constrained Delaunay triangulation of the
//! source (or of the target with [`MorphOptions::triangulated`], Fig. 12) and the composite harmonic
//! mapping through the barycenter-based shape model (§5), and returns meshes that share
//! connectivity, with every curve vertex on its twin.

use crate::correspondence::{
    correspond_all_reusing, CorrespondenceOptions, Correspondences, CurvePair,
};
use crate::drawing::Drawing;
use crate::error::{Error, Result};
use crate::mapping::{
    check_curves, composite_map_reusing, Attachments, CurveCheck, MappingOptions, MappingStats,
};
use crate::mesh::{CompatibleMeshes, Side};
use crate::rigid::{Chain, DiscSetup, Interpolator, Method};
use crate::tolerance::Tolerances;
use crate::triangulation::triangulate;

/// Options of the compatible triangulation.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct MorphOptions {
    /// The side that is triangulated and mapped onto the other (Fig. 12 triangulates the
    /// target). Default: the source.
    pub triangulated: Side,
    /// Vertex density multiplier for correspondence and refinement. Default: 0, the density
    /// the source drawing was read with ([`crate::drawing::ReadOptions::density`], kept in
    /// [`Tolerances::density`]), so that one setting reads and triangulates; a positive number
    /// overrides it.
    pub density: f64,
    /// Vertex correspondence options. Default: [`CorrespondenceOptions::default`].
    pub correspondence: CorrespondenceOptions,
    /// Composite mapping options. Default: [`MappingOptions::default`].
    pub mapping: MappingOptions,
}

/// The result of [`build`]: compatible meshes and what they were made from.
#[derive(Debug, Clone)]
pub struct Compatible {
    /// The two meshes with shared connectivity.
    pub meshes: CompatibleMeshes,
    /// The curve pairs with their vertex correspondence (boundary first, then features by name);
    /// `meshes.curves[k]` is `pairs[k]`.
    pub pairs: Vec<CurvePair>,
    /// Counts from the composite mapping.
    pub stats: MappingStats,
    /// The tolerances used (relative to the larger of the two drawings).
    pub tolerances: Tolerances,
    /// The triangles whose area the disc method's area rule keeps (`rigid::area`): `None` for
    /// the whole mesh (the boundary is the shape); automatic mode, whose boundary is a padded
    /// frame, sets the regions filled by the matched outlines.
    pub area_region: Option<Vec<[u32; 3]>>,
}

impl Compatible {
    /// The interpolation of `method` between the two meshes. The disc method keeps the area
    /// of [`Compatible::area_region`] and, on meshes made of several shapes
    /// ([`crate::mesh::Parts`]), moves curves without triangles as chains of discs and the
    /// shapes as one figure, the still part apart.
    pub fn interpolator(&self, method: Method) -> Result<Interpolator> {
        let m = &self.meshes;
        if method != Method::Disc {
            return Interpolator::new(method, &m.source, &m.target, &m.triangles);
        }
        self.disc_interpolator(None)
    }

    /// The disc method's [`Compatible::interpolator`], reusing the factored matrix of `like`
    /// when it was set up on the same connectivity ([`DiscSetup::system_of`]).
    fn disc_interpolator(&self, like: Option<&Interpolator>) -> Result<Interpolator> {
        let m = &self.meshes;
        let chains: Vec<Chain> = m
            .parts
            .iter()
            .flat_map(|p| &p.chains)
            .filter_map(|&c| m.curves.get(c))
            .map(|c| Chain {
                vertices: c.vertices.clone(),
                closed: c.closed,
            })
            .collect();
        let together: Option<Vec<bool>> = m.parts.as_ref().map(|p| {
            let mut flags = vec![true; m.source.len()];
            for (t, &k) in m.triangles.iter().zip(&p.of_triangle) {
                if Some(k) == p.still {
                    for &v in t {
                        flags[v as usize] = false;
                    }
                }
            }
            flags
        });
        // Fold repair, curve vertices held: on the whole mesh of a marked-up drawing, on the
        // parts that need it in automatic mode.
        let repaired: Vec<[u32; 3]> = match &m.parts {
            None => m.triangles.clone(),
            Some(p) => m
                .triangles
                .iter()
                .zip(&p.of_triangle)
                .filter(|(_, k)| p.repair.contains(k))
                .map(|(t, _)| *t)
                .collect(),
        };
        let mut on_curve = vec![false; m.source.len()];
        for &v in m.curves.iter().flat_map(|c| &c.vertices) {
            if let Some(f) = on_curve.get_mut(v as usize) {
                *f = true;
            }
        }
        Interpolator::disc(
            &m.source,
            &m.target,
            &DiscSetup {
                triangles: &m.triangles,
                chains: &chains,
                area_region: self.area_region.as_deref(),
                together: together.as_deref(),
                repair: (!repaired.is_empty()).then_some((&repaired[..], &on_curve[..])),
                repair_curves: m.parts.is_none(),
                system_of: like,
            },
        )
    }
}

/// Frames of `interp`, the disc interpolation of `c`, that invert a triangle after fold
/// repair, at t = k/64 (k = 1…63), counted up to `enough` (the count stops there, a few frames
/// at a time, when more would not change the caller's choice): the check that picks the mesh
/// [`build`] returns. The frames at k/32 come first, and a mesh that folds in none of them
/// counts as folding nowhere: most meshes fold in no frame, so the odd k/64 are read only for
/// meshes that fold at all, which halves the check on the others (issue 16). On the 640 pairs
/// of the two random icon corpora every pick, and so every output, stayed the same. Times in
/// `unfolded` are ones the caller saw no plain frame fold at ([`MotionChecked::unfolded_at`]):
/// they are not read again.
fn folded_frames(c: &Compatible, interp: &Interpolator, enough: usize, unfolded: &[f64]) -> usize {
    let at_a_time = rayon::current_num_threads().max(1) * 2;
    count_folded(at_a_time, enough, unfolded, |ts| {
        interp
            .frames(ts)
            .iter()
            .filter(|f| crate::mesh::count_inverted(&c.meshes.triangles, f) > 0)
            .count()
    })
}

/// [`folded_frames`]'s sampling: `folded(ts)` counts the frames at `ts` that fold, asked
/// `at_a_time` times at once, at t = k/32 first (those in `unfolded` left out: they fold
/// nowhere) and at the odd k/64 only if one of those folded; the count stops once it reaches
/// `enough`.
fn count_folded(
    at_a_time: usize,
    enough: usize,
    unfolded: &[f64],
    mut folded: impl FnMut(&[f64]) -> usize,
) -> usize {
    let coarse: Vec<f64> = (1..32)
        .map(|k| k as f64 / 32.0)
        .filter(|t| !unfolded.contains(t))
        .collect();
    let fine: Vec<f64> = (0..32).map(|k| (2 * k + 1) as f64 / 64.0).collect();
    let mut count = 0;
    for (is_fine, ts) in [(false, coarse), (true, fine)] {
        if is_fine && count == 0 {
            break;
        }
        for chunk in ts.chunks(at_a_time.max(1)) {
            count += folded(chunk);
            if count >= enough {
                return count;
            }
        }
    }
    count
}

/// Relaxes the mesh the harmonic map produced (the side not `triangulated`) towards the
/// triangle shapes of the triangulated one, curve vertices held (`mapping::relax_towards`): fewer slivers, so fewer triangles for the interpolation to fold.
fn relax_mapped(m: &mut CompatibleMeshes, triangulated: Side) {
    let mut held = vec![false; m.source.len()];
    for &v in m.curves.iter().flat_map(|c| &c.vertices) {
        if let Some(h) = held.get_mut(v as usize) {
            *h = true;
        }
    }
    let (rest, mapped) = match triangulated {
        Side::Target => (&m.target, &mut m.source),
        Side::Source => (&m.source, &mut m.target),
    };
    crate::mapping::relax_towards(rest, mapped, &m.triangles, &held);
}

/// Tolerances common to both drawings: relative to the larger one, at `density` (not a
/// positive number: the density the source was read with, see [`MorphOptions::density`]).
pub fn common_tolerances(source: &Drawing, target: &Drawing, density: f64) -> Tolerances {
    let d = source.tolerances.diagonal.max(target.tolerances.diagonal);
    let density = if density > 0.0 && density.is_finite() {
        density
    } else {
        source.tolerances.density
    };
    Tolerances::new(d, density)
}

/// Names the drawings of an error from a stage without file names ([`Error::with_files`]).
/// Each side names its own file, whichever is triangulated.
fn name_files(e: Error, source: &Drawing, target: &Drawing) -> Error {
    e.with_files(&source.file, &target.file)
}

/// The common tolerances and the corresponded curve pairs of two drawings (§3): the first stage
/// of [`build`], on its own for tools that look at the curves.
pub fn curve_pairs(
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
) -> Result<(Tolerances, Vec<CurvePair>)> {
    curve_pairs_reusing(source, target, opts, &mut Correspondences::default())
}

/// [`curve_pairs`], with the correspondences `made` holds for the same curves taken from it
/// and the new ones kept there.
fn curve_pairs_reusing(
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
    made: &mut Correspondences,
) -> Result<(Tolerances, Vec<CurvePair>)> {
    let tol = common_tolerances(source, target, opts.density);
    let pairs = correspond_all_reusing(
        &source.file,
        &source.controls,
        &target.file,
        &target.controls,
        &tol,
        &opts.correspondence,
        made,
    )?;
    Ok((tol, pairs))
}

/// Refuses, before anything is built, two drawings whose meshes at `opts.density` would pass
/// the vertex budget ([`crate::budget`]).
fn check_vertex_budget(source: &Drawing, target: &Drawing, opts: &MorphOptions) -> Result<()> {
    let tol = common_tolerances(source, target, opts.density);
    fn side(d: &Drawing) -> Vec<(&[crate::geometry::Point], bool)> {
        let c = &d.controls;
        std::iter::once(&c.boundary)
            .chain(&c.features)
            .map(|k| (&k.points[..], k.closed))
            .collect()
    }
    let v = crate::budget::mesh_vertices(&side(source), &side(target), &tol);
    let files = format!("{} → {}", source.file, target.file);
    // The source drawing's limits (both come from the same options in the CLI).
    crate::budget::check(v, tol.density, &files, &source.policy.limits)
}

/// Builds compatible triangulations of two drawings (§3, §5).
pub fn build(source: &Drawing, target: &Drawing, opts: &MorphOptions) -> Result<Compatible> {
    build_accepted(source, target, opts, |_, _| Ok(())).map(|(c, ())| c)
}

/// What the `accept` check of [`build_accepted`] learnt of a mesh's motion on its way.
pub(crate) trait MotionChecked {
    /// Times t at which the check saw the mesh's disc interpolation, without fold repair,
    /// invert no triangle. The fold count that picks the mesh reads repaired frames, and a
    /// frame with no triangle inverted is one the repair leaves as it is, so it does not read
    /// these again.
    fn unfolded_at(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// A check that looks at no frame.
impl MotionChecked for () {}

/// [`build`], then `accept` on the meshes it returns, given the disc interpolator that the
/// fold check which chose them set up ([`Compatible::interpolator`]; `None` when it cannot be
/// set up): automatic mode checks their motion further and reads its frames again rather than
/// setting it up a second time.
///
/// [`build`] picks the harmonic map's own mesh or the relaxed one by counting the frames each
/// folds (31 frames with fold repair, and 32 more once one of them folds: the dearest check on
/// meshes that fold). When the harmonic map's mesh fails `accept`, the relaxed one is tried
/// with `accept` first: if it fails too, neither pick can be accepted and nothing is counted
/// (the error is then the first mesh's). Otherwise the result is what `accept` makes of
/// [`build`]'s mesh.
pub(crate) fn build_accepted<T: MotionChecked>(
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
    accept: impl Fn(&Compatible, Option<&Interpolator>) -> Result<T>,
) -> Result<(Compatible, T)> {
    let (tol, pairs) = checked_curve_pairs(source, target, opts, &mut Correspondences::default())?;
    let made = &mut Attachments::default();
    build_accepted_from(source, target, opts, (tol, pairs), made, accept)
}

/// The first stage of [`build`] and [`build_accepted`]: the vertex budget checked, then the
/// curve pairs ([`curve_pairs`]), taking from `made` the correspondences it holds for the same
/// curves and keeping the new ones there. Neither depends on [`MorphOptions::triangulated`], so
/// automatic mode corresponds a hole set once for both sides it tries.
pub(crate) fn checked_curve_pairs(
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
    made: &mut Correspondences,
) -> Result<(Tolerances, Vec<CurvePair>)> {
    check_vertex_budget(source, target, opts)?;
    curve_pairs_reusing(source, target, opts, made)
}

/// [`build_accepted`] from the curve pairs that [`checked_curve_pairs`] gave for the same
/// drawings and options (any [`MorphOptions::triangulated`]); the mapping's carried features
/// take their attachments from `made` and keep them there for the next build of the same
/// curves.
pub(crate) fn build_accepted_from<T: MotionChecked>(
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
    (tol, pairs): (Tolerances, Vec<CurvePair>),
    made: &mut Attachments,
    accept: impl Fn(&Compatible, Option<&Interpolator>) -> Result<T>,
) -> Result<(Compatible, T)> {
    let fix = |e| name_files(e, source, target);
    let model = match check_curves(&pairs, &tol, &opts.mapping, opts.triangulated, made) {
        CurveCheck::Fails(e) => return Err(fix(e)),
        CurveCheck::Try(model) => model,
    };
    let tri = triangulate(&pairs, &tol, opts.triangulated).map_err(fix)?;
    let (meshes, stats) =
        composite_map_reusing(&tri, &pairs, &tol, &opts.mapping, made, model).map_err(fix)?;
    let plain = Compatible {
        meshes,
        pairs,
        stats,
        tolerances: tol,
        area_region: None,
    };
    // The relaxed mesh has the mapped mesh's triangles, so it reuses its factored matrix.
    let relaxed = |like: Option<&Interpolator>| {
        let mut r = plain.clone();
        relax_mapped(&mut r.meshes, opts.triangulated);
        let motion = r.disc_interpolator(like);
        (r, motion)
    };
    // The harmonic map's own mesh unless its interpolation folds (`folds` frames) where the
    // relaxed one folds less (both after fold repair).
    let relaxed_is_picked = |r: &Compatible, motion: &Interpolator, folds: usize| {
        folds > 0 && folded_frames(r, motion, folds, &[]) < folds
    };
    let Ok(plain_motion) = plain.interpolator(Method::Disc) else {
        // No interpolation to check counts as folding everywhere: the relaxed mesh is better
        // if it can be set up at all.
        return match relaxed(None) {
            (r, Ok(i)) => accept(&r, Some(&i)).map(|x| (r, x)),
            (_, Err(_)) => accept(&plain, None).map(|x| (plain, x)),
        };
    };
    let plain_accepted = match accept(&plain, Some(&plain_motion)) {
        Ok(x) => x,
        Err(e) => {
            // Only the relaxed mesh can pass, and only if the count picks it.
            let (r, Ok(i)) = relaxed(Some(&plain_motion)) else {
                return Err(e);
            };
            let x = accept(&r, Some(&i)).map_err(|_| e.clone())?;
            let folds = folded_frames(&plain, &plain_motion, usize::MAX, &[]);
            return if relaxed_is_picked(&r, &i, folds) {
                Ok((r, x))
            } else {
                Err(e)
            };
        }
    };
    let unfolded = plain_accepted.unfolded_at();
    let folds = folded_frames(&plain, &plain_motion, usize::MAX, &unfolded);
    if folds == 0 {
        return Ok((plain, plain_accepted));
    }
    match relaxed(Some(&plain_motion)) {
        (r, Ok(i)) if relaxed_is_picked(&r, &i, folds) => accept(&r, Some(&i)).map(|x| (r, x)),
        _ => Ok((plain, plain_accepted)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::ReadOptions;
    use crate::mapping::composite_map;

    /// The acceptance checks of these tests read no frames.
    impl MotionChecked for usize {}

    /// The fold check's samples: what `count_folded` asked for, chunk by chunk, and its count,
    /// for frames that fold where `folds(t)` says.
    fn fold_check(
        at_a_time: usize,
        enough: usize,
        folds: impl Fn(f64) -> bool,
    ) -> (Vec<Vec<f64>>, usize) {
        fold_check_knowing(at_a_time, enough, &[], folds)
    }

    /// [`fold_check`] told that the frames at `unfolded` fold nowhere.
    fn fold_check_knowing(
        at_a_time: usize,
        enough: usize,
        unfolded: &[f64],
        folds: impl Fn(f64) -> bool,
    ) -> (Vec<Vec<f64>>, usize) {
        let mut asked = Vec::new();
        let n = count_folded(at_a_time, enough, unfolded, |ts| {
            asked.push(ts.to_vec());
            ts.iter().filter(|&&t| folds(t)).count()
        });
        (asked, n)
    }

    #[test]
    fn a_mesh_that_folds_nowhere_costs_the_coarse_frames_only() {
        let (asked, n) = fold_check(4, usize::MAX, |_| false);
        assert_eq!(n, 0);
        let read: Vec<f64> = asked.concat();
        let coarse: Vec<f64> = (1..32).map(|k| k as f64 / 32.0).collect();
        assert_eq!(read, coarse);
        assert!(asked.iter().all(|c| c.len() <= 4), "{asked:?}");
    }

    #[test]
    fn a_mesh_that_folds_is_counted_at_every_sixty_fourth() {
        // Folds over a stretch of t: every frame of k/64 in it counts, odd k included.
        let stretch = |t: f64| (0.3..0.45).contains(&t);
        let (asked, n) = fold_check(4, usize::MAX, stretch);
        let all: Vec<f64> = (1..64).map(|k| k as f64 / 64.0).collect();
        assert_eq!(n, all.iter().filter(|&&t| stretch(t)).count());
        let mut read: Vec<f64> = asked.concat();
        read.sort_by(f64::total_cmp);
        assert_eq!(read, all, "each frame read once");
        // Folds between the coarse samples only are not seen: the check's stated rule.
        let (_, n) = fold_check(4, usize::MAX, |t| t == 7.0 / 64.0);
        assert_eq!(n, 0);
    }

    #[test]
    fn frames_the_accept_check_saw_unfolded_are_not_read_again() {
        let sixteenths: Vec<f64> = (1..16).map(|k| k as f64 / 16.0).collect();
        let (asked, n) = fold_check_knowing(4, usize::MAX, &sixteenths, |_| false);
        assert_eq!(n, 0);
        let read: Vec<f64> = asked.concat();
        let odd: Vec<f64> = (0..16).map(|k| (2 * k + 1) as f64 / 32.0).collect();
        assert_eq!(read, odd);
        // A fold at an odd k/32 still reads the odd k/64, and the count is the whole one.
        let stretch = |t: f64| (0.53..0.56).contains(&t);
        let (asked, n) = fold_check_knowing(4, usize::MAX, &sixteenths, stretch);
        let all: Vec<f64> = (1..64).map(|k| k as f64 / 64.0).collect();
        assert_eq!(n, all.iter().filter(|&&t| stretch(t)).count());
        assert_eq!(asked.concat().len(), 16 + 32);
    }

    #[test]
    fn the_fold_count_stops_where_the_caller_has_enough() {
        let (asked, n) = fold_check(4, 3, |t| t > 0.5);
        // Frames from 17/32 on fold: the chunk of 17/32–20/32 reaches three (with all four
        // of its own), and nothing after it is read.
        assert_eq!(n, 4);
        assert_eq!(asked.last().map(|c| c[0]), Some(17.0 / 32.0));
        assert_eq!(asked.len(), 5);
    }

    #[test]
    fn each_placeholder_names_its_own_file_whichever_side_is_triangulated() {
        // Stages name the side they checked (`Side::drawing`): "<target>" is the target
        // even when the target is the side triangulated (before, it was swapped then).
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><rect width="10" height="10"/></svg>"#;
        let read = |name: &str| Drawing::from_str(name, svg, &ReadOptions::default()).unwrap();
        let (s, t) = (read("a.svg"), read("b.svg"));
        for (placeholder, file) in [(Side::Source, "a.svg"), (Side::Target, "b.svg")] {
            let e = name_files(Error::input(placeholder.drawing(), "x"), &s, &t);
            assert_eq!(e.to_string(), format!("{file}: x"));
        }
        let e = name_files(Error::input(crate::Drawings::Pair, "x"), &s, &t);
        assert_eq!(e.to_string(), "a.svg → b.svg: x");
    }

    #[test]
    fn accepting_while_building_gives_what_accepting_the_built_meshes_gives() {
        // `build_accepted` tries `accept` on both candidate meshes before it counts their
        // folds; whatever `accept` says, the outcome must be `accept` of `build`'s meshes.
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/");
        for pair in ["u-to-s", "star-to-blob", "leaf-to-butterfly"] {
            let read = |side: &str| {
                let path = std::path::PathBuf::from(format!("{dir}{pair}/{side}.svg"));
                Drawing::open(&path, &ReadOptions::default()).unwrap()
            };
            let (s, t) = (read("source"), read("target"));
            let opts = MorphOptions::default();
            let built = build(&s, &t, &opts).unwrap();
            let (tol, pairs) = curve_pairs(&s, &t, &opts).unwrap();
            let tri = triangulate(&pairs, &tol, opts.triangulated).unwrap();
            let (harmonic, _) = composite_map(&tri, &pairs, &tol, &opts.mapping).unwrap();
            let same = |a: &CompatibleMeshes, b: &CompatibleMeshes| {
                a.source == b.source && a.target == b.target && a.triangles == b.triangles
            };
            let is_harmonic = |c: &Compatible| same(&c.meshes, &harmonic);
            type Rule<'a> = (&'a str, &'a dyn Fn(&Compatible) -> bool);
            let rules: [Rule<'_>; 4] = [
                ("every mesh", &|_| true),
                ("no mesh", &|_| false),
                ("the harmonic map's mesh", &|c| is_harmonic(c)),
                ("the relaxed mesh", &|c| !is_harmonic(c)),
            ];
            for (name, passes) in rules {
                let accept = |c: &Compatible, motion: Option<&Interpolator>| {
                    assert!(motion.is_some(), "{pair}: the fixture's meshes interpolate");
                    if passes(c) {
                        Ok(c.meshes.source.len())
                    } else {
                        Err(Error::input("<test>", "rejected"))
                    }
                };
                let got = build_accepted(&s, &t, &opts, accept);
                match (passes(&built), got) {
                    (true, Ok((c, n))) => {
                        assert!(
                            same(&c.meshes, &built.meshes),
                            "{pair}, {name}: another mesh"
                        );
                        assert_eq!(n, built.meshes.source.len());
                    }
                    (false, Err(e)) => assert!(e.to_string().contains("rejected")),
                    (want, got) => panic!(
                        "{pair}, accepting {name}: wanted {}, got {:?}",
                        if want { "the built mesh" } else { "an error" },
                        got.map(|(_, n)| n)
                    ),
                }
            }
        }
    }

    #[test]
    fn the_reading_density_is_the_triangulations_unless_set() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><rect width="10" height="10"/></svg>"#;
        let read = |density: f64| {
            let opts = ReadOptions {
                density,
                ..ReadOptions::default()
            };
            Drawing::from_str("a.svg", svg, &opts).unwrap()
        };
        let (s, t) = (read(2.0), read(2.0));
        let built = |density: f64| {
            let opts = MorphOptions {
                density,
                ..MorphOptions::default()
            };
            build(&s, &t, &opts).unwrap()
        };
        let default = built(0.0);
        assert_eq!(default.tolerances.density, 2.0);
        assert_eq!(default.meshes.source.len(), built(2.0).meshes.source.len());
        assert!(built(1.0).meshes.source.len() < default.meshes.source.len());
    }
}
