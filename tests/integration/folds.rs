//! Issue #9 item 4: no inverted triangle in any frame of the disc interpolation as the CLI builds
//! it (`Compatible::interpolator`), for inputs rounded as SVG optimisers write them, at
//! densities across [0.5, 2], in both directions: every fixture, and generated pairs.

use crmorph::compatible::{build, Compatible, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::mesh::count_inverted;
use crmorph::rigid::Method;
use crmorph::Side;
use proptest::prelude::*;

use crate::common::pairs;
use crate::rounding::rounded;

/// Reads both drawings at `density` and builds their compatible triangulation.
fn build_at(src: &str, tgt: &str, density: f64, from_target: bool) -> crmorph::Result<Compatible> {
    let mut o = ReadOptions::default();
    o.density = density;
    let s = Drawing::from_str("source.svg", src, &o)?;
    let t = Drawing::from_str("target.svg", tgt, &o)?;
    let mut opts = MorphOptions::default();
    opts.density = density;
    opts.triangulated = if from_target {
        Side::Target
    } else {
        Side::Source
    };
    build(&s, &t, &opts)
}

/// The frames at t = k/`n` (k = 0…n) that invert a triangle, as `(t, count)`.
fn folded(c: &Compatible, n: usize) -> Vec<(f64, usize)> {
    let interp = c.interpolator(Method::Disc).unwrap();
    let ts: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    ts.iter()
        .zip(interp.frames(&ts))
        .map(|(&t, f)| (t, count_inverted(&c.meshes.triangles, &f)))
        .filter(|&(_, k)| k > 0)
        .collect()
}

#[test]
fn rounded_fixtures_fold_no_triangle_at_any_density() {
    let mut checked = 0;
    for (name, s, t) in pairs() {
        let (src, tgt) = (
            std::fs::read_to_string(s).unwrap(),
            std::fs::read_to_string(t).unwrap(),
        );
        for decimals in [Some(1), Some(2), Some(3)] {
            let (src, tgt) = (rounded(&src, decimals), rounded(&tgt, decimals));
            for density in [0.5, 1.0, 2.0] {
                for from_target in [false, true] {
                    let c = build_at(&src, &tgt, density, from_target)
                        .unwrap_or_else(|e| panic!("{name} {decimals:?} {density}: {e}"));
                    let bad = folded(&c, 32);
                    assert!(
                        bad.is_empty(),
                        "{name}, {decimals:?} decimals, density {density}, from target \
                         {from_target}: inverted triangles (t, count) {bad:?}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 5 * 18, "{checked} morphs checked");
}

/// A closed outline about (100, 100) as a path: radius `r(θ)` sampled at `n` angles, joined by
/// straight segments (`smooth`: by quadratic curves through the midpoints).
fn radial(n: usize, r: impl Fn(f64) -> f64, smooth: bool, decimals: usize) -> String {
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            (100.0 + r(a) * a.cos(), 100.0 + r(a) * a.sin())
        })
        .collect();
    let f = |v: f64| format!("{v:.decimals$}");
    let mut d = String::new();
    if smooth {
        let mid = |i: usize| {
            let (p, q) = (pts[i % n], pts[(i + 1) % n]);
            ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0)
        };
        let m = mid(n - 1);
        d.push_str(&format!("M{} {}", f(m.0), f(m.1)));
        for (i, p) in pts.iter().enumerate() {
            let m = mid(i);
            d.push_str(&format!(" Q{} {} {} {}", f(p.0), f(p.1), f(m.0), f(m.1)));
        }
    } else {
        for (i, p) in pts.iter().enumerate() {
            d.push_str(&format!(
                "{}{} {} ",
                if i == 0 { "M" } else { "L" },
                f(p.0),
                f(p.1)
            ));
        }
    }
    d.push('Z');
    d
}

/// A worm: a thick band along an arc of `bend` radians, its ends rounded.
fn worm(bend: f64, decimals: usize) -> String {
    let (c, rm, w) = (
        (100.0, 100.0 + 60.0 / bend.max(0.2)),
        60.0 / bend.max(0.2),
        14.0,
    );
    let steps = 24;
    let at = |r: f64, a: f64| (c.0 + r * a.sin(), c.1 - r * a.cos());
    let f = |v: f64| format!("{v:.decimals$}");
    let mut d = String::new();
    for k in 0..=steps {
        let a = -bend / 2.0 + bend * k as f64 / steps as f64;
        let p = at(rm + w, a);
        d.push_str(&format!(
            "{}{} {} ",
            if k == 0 { "M" } else { "L" },
            f(p.0),
            f(p.1)
        ));
    }
    for k in (0..=steps).rev() {
        let a = -bend / 2.0 + bend * k as f64 / steps as f64;
        let p = at(rm - w, a);
        d.push_str(&format!("L{} {} ", f(p.0), f(p.1)));
    }
    d.push('Z');
    d
}

/// An SVG whose boundary is `outline`, with a small closed feature curve `eye` about
/// (`ex`, 100), the two turned by `turn` degrees about the centre.
fn drawing(outline: &str, ex: f64, turn: f64, decimals: usize) -> String {
    let f = |v: f64| format!("{v:.decimals$}");
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 200 200\">\
         <g transform=\"rotate({} 100 100)\">\
         <path id=\"boundary\" d=\"{outline}\" fill=\"#8bc34a\"/>\
         <ellipse id=\"feature-eye\" cx=\"{}\" cy=\"100\" rx=\"{}\" ry=\"{}\" fill=\"#333\"/>\
         </g></svg>",
        f(turn),
        f(ex),
        f(6.3),
        f(4.7)
    )
}

/// One generated pair: a star, blob or worm (`kind` 0, 1, 2) morphing into the next, each with
/// an eye, the target turned by `turn` degrees, written with `decimals` decimals.
#[derive(Debug, Clone, Copy)]
struct Generated {
    kind: usize,
    spikes: usize,
    depth: f64,
    wobble: f64,
    bend: f64,
    decimals: usize,
    density: f64,
    from_target: bool,
    turn: f64,
}

/// Builds the pair `g` and checks its frames; `Err` says why it failed to map or which frames
/// fold.
fn generated_pair(g: Generated) -> Result<(), String> {
    let star = radial(
        2 * g.spikes,
        |a| {
            let k = (a * g.spikes as f64 / std::f64::consts::PI).round() as i64;
            if k % 2 == 0 {
                70.0
            } else {
                70.0 * (1.0 - g.depth)
            }
        },
        false,
        g.decimals,
    );
    let blob = radial(
        12,
        |a| 60.0 * (1.0 + g.wobble * (3.0 * a).sin()),
        true,
        g.decimals,
    );
    let w = worm(g.bend, g.decimals);
    let (a, b) = [(&star, &blob), (&blob, &w), (&w, &star)][g.kind];
    let (src, tgt) = (
        drawing(a, 95.0, 0.0, g.decimals),
        drawing(b, 105.0, g.turn, g.decimals),
    );
    let c = build_at(&src, &tgt, g.density, g.from_target).map_err(|e| e.to_string())?;
    // The disc set-up refuses meshes with coincident vertices.
    c.interpolator(Method::Disc).map_err(|e| e.to_string())?;
    let bad = folded(&c, 32);
    if bad.is_empty() {
        Ok(())
    } else {
        Err(format!("inverted triangles (t, count) {bad:?}"))
    }
}

/// Pairs that random runs of the property below once found failing (each fails without the
/// fixes it names), kept as cases of their own: a star's tip pinned flat against a straight run of the blob (no mapping can unfold a
/// triangle of three curve vertices), and two refinement points of a worm a rounding error
/// apart (a disc edge of zero length).
#[test]
fn generated_pairs_once_found_failing_now_morph() {
    let case = |kind, spikes, depth, wobble, bend, decimals, density, turn| Generated {
        kind,
        spikes,
        depth,
        wobble,
        bend,
        decimals,
        density,
        from_target: false,
        turn,
    };
    let cases = [
        case(
            0,
            8,
            0.49324702774485607,
            0.07592304800422361,
            0.5,
            3,
            1.9053426583866715,
            -90.87675513730998,
        ),
        case(0, 8, 0.474, 0.021, 1.901, 3, 1.924, 109.63),
        case(0, 8, 0.491, 0.027, 1.948, 2, 1.643, -170.73),
        case(2, 5, 0.385, 0.010, 0.517, 1, 1.641, -38.69),
        case(2, 6, 0.259, 0.202, 0.637, 1, 1.975, -87.49),
    ];
    let failed: Vec<String> = cases
        .iter()
        .filter_map(|&g| generated_pair(g).err().map(|e| format!("{g:?}: {e}")))
        .collect();
    assert!(failed.is_empty(), "{failed:#?}");
}

proptest! {
    // 32 cases from the workspace's fixed seed (`.cargo/config.toml`); a long hunt sets
    // PROPTEST_CASES and another PROPTEST_RNG_SEED.
    #![proptest_config(ProptestConfig::with_cases(
        std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(32)
    ))]

    /// Star → blob, blob → worm and worm → star pairs, each with an eye, the target turned by up
    /// to a half turn, written with 1–3 decimals, at densities in [0.5, 2], in both
    /// directions: each maps, and no frame folds.
    #[test]
    fn generated_pairs_fold_no_triangle(
        kind in 0usize..3,
        spikes in 5usize..9,
        depth in 0.25f64..0.5,
        wobble in 0.0f64..0.25,
        bend in 0.5f64..2.5,
        decimals in 1usize..=3,
        density in 0.5f64..2.0,
        from_target in any::<bool>(),
        turn in -179.0f64..179.0,
    ) {
        let r = generated_pair(Generated {
            kind, spikes, depth, wobble, bend, decimals, density, from_target, turn,
        });
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }
}
