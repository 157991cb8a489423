//! Far-away artwork and the vertex budget at the library level (issue #12): marked-up drawings
//! whose artwork reaches far outside the view bind and warp in bounded time, a transform past
//! f32 leaves its shape out instead of aborting, and the budget is a
//! [`crmorph::input::Limit::Vertices`] error with the file's name.

use std::time::Instant;

use crmorph::artwork::{within_reach, Binding, Scene};
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::error::Error;
use crmorph::input::Limits;

const MARKED: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
<rect id="boundary" x="10" y="10" width="180" height="180" fill="#c33"/>
EXTRA
</svg>"##;

fn read(file: &str, extra: &str, opts: &ReadOptions) -> crmorph::error::Result<Drawing> {
    Drawing::from_str(file, &MARKED.replace("EXTRA", extra), opts)
}

/// A stroke to x = 1e9 and a scaled shape on a marked-up drawing: the binding (flattening and
/// locating every artwork point) takes milliseconds and its points stay near the view.
#[test]
fn far_artwork_binds_in_bounded_time() {
    let extra = r##"<path d="M20 150 L1e9 160" stroke="#000" stroke-width="4" fill="none"/>
        <path d="M10 180 L40 150 L60 195 Z" transform="scale(1000)"/>
        <path d="M10 180 L4e10 150 L60 195 Z" transform="scale(1e30)"/>"##;
    let d = read("far.svg", extra, &ReadOptions::default()).unwrap();
    let scene = Scene::from_svg("far.svg", &d.svg, "controls").unwrap();
    let (_, far) = within_reach(&scene);
    // The shape scaled past f32 (usvg's precision) is dropped by usvg itself.
    assert_eq!(far.len(), 2, "{far:?}");
    assert!(!far[0].left_out && far[1].left_out, "{far:?}");
    let c = build(&d, &d, &MorphOptions::default()).unwrap();
    let start = Instant::now();
    let b = Binding::new(&scene, &c.meshes.source, &c.meshes.triangles, 0.1).unwrap();
    assert!(start.elapsed().as_secs_f64() < 2.0, "{:?}", start.elapsed());
    assert!(b.point_count() < 100_000, "{} points", b.point_count());
    let warped = b.warp(&c.meshes.source).unwrap();
    let (lo, hi) = warped.bounds().unwrap();
    assert!(
        lo.x > -1000.0 && hi.x < 1000.0 && hi.y < 1000.0,
        "{lo:?} {hi:?}"
    );
}

/// A feature curve that flattens past the budget, and a density whose mesh would, are
/// `Limit::Vertices` errors naming the file and `--max-vertices`.
#[test]
fn the_vertex_budget_is_an_input_error_naming_the_flag() {
    let mut opts = ReadOptions::default();
    let mut limits = Limits::default();
    limits.vertices = 1000;
    opts.policy.limits = limits;
    let wiggle = r##"<path id="feature-w" d="M50 50 C 1e11 50 -1e11 150 150 150"/>"##;
    let e = read("w.svg", wiggle, &opts).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::Input(_)), "{text}");
    assert!(
        text.starts_with("w.svg: control curves flattening to about"),
        "{text}"
    );
    assert!(
        text.contains("--max-vertices") && !text.contains('\n'),
        "{text}"
    );

    let d = read("d.svg", "", &ReadOptions::default()).unwrap();
    let mut mo = MorphOptions::default();
    mo.density = 100.0;
    let start = Instant::now();
    let text = build(&d, &d, &mo).unwrap_err().to_string();
    assert!(start.elapsed().as_secs_f64() < 1.0);
    assert!(
        text.starts_with("d.svg → d.svg: a mesh of about") && text.contains("--max-vertices"),
        "{text}"
    );
}
