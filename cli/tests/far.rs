//! Work that does not grow with coordinates, and the vertex budget (issue #12, rows 4, 6 and 7):
//! a small icon with one hostile part — a curve near `f32::MAX`, a vertex a million units away,
//! a `scale(1000)` or `skewX(89.999)` on one shape, a `--density` of 50 — either morphs in
//! bounded time and memory (the far part cut or left out, and said so) or is a one-line error
//! naming `--max-vertices`, with no output left behind.

use std::path::Path;
use std::time::Duration;

#[path = "common/measure.rs"]
mod measure;

use measure::Outcome as Run;

/// Runs `crmorph args…`; running past `limit` fails the test.
fn run(args: &[&str], limit: Duration) -> Run {
    let r = measure::run(args, limit.as_secs_f64());
    assert!(!r.timed_out, "crmorph {args:?} ran past {limit:?}");
    r
}

const TIME: Duration = Duration::from_secs(5);
const GIB_KIB: u64 = 1 << 20;

/// A 200-unit icon of two shapes with `extra` added.
fn icon(extra: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200" width="200" height="200">
<rect x="20" y="20" width="80" height="60" fill="#c33"/>
<circle cx="140" cy="140" r="40" fill="#36c"/>
{extra}
</svg>"##
    )
}

const TARGET: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200" width="200" height="200">
<rect x="100" y="30" width="70" height="70" fill="#3c3"/>
<ellipse cx="60" cy="140" rx="50" ry="30" fill="#c3c"/>
<path d="M10 190 L60 150 L110 190 Z" fill="#333"/>
</svg>"##;

/// Writes the source and target into `dir` and runs `crmorph <command> src tgt … -o out`
/// with `extra` arguments; returns the run and the output path.
fn morph(dir: &Path, source: &str, command: &str, out: &str, extra: &[&str]) -> (Run, bool) {
    let (s, t, o) = (dir.join("s.svg"), dir.join("t.svg"), dir.join(out));
    std::fs::write(&s, source).unwrap();
    std::fs::write(&t, TARGET).unwrap();
    let mut args = vec![command, s.to_str().unwrap(), t.to_str().unwrap()];
    if command == "frame" {
        args.extend(["--at", "0.5"]);
    }
    args.extend(["-o", o.to_str().unwrap()]);
    args.extend(extra);
    let r = run(&args, TIME);
    (r, o.exists())
}

fn assert_bounded(r: &Run, what: &str) {
    assert!(r.secs < TIME.as_secs_f64(), "{what}: {:.2} s", r.secs);
    assert!(r.peak_kib < GIB_KIB, "{what}: peak {} KiB", r.peak_kib);
}

/// Every hostile part of rows 4 and 6: each morphs (frame and animation) in bounded time and
/// memory, the far shape named in automatic mode's report.
#[test]
fn far_and_huge_coordinates_morph_in_bounded_time() {
    let cases = [
        (
            "a curve near f32::MAX",
            r##"<path d="M10 10 C 3.4e38 10 10 3.4e38 50 50 Z" fill="#000"/>"##,
            "reaches far outside the view",
        ),
        (
            "a vertex at x = 1e6",
            r##"<path d="M10 180 L1000000 185 L20 195 Z" fill="#000"/>"##,
            "reaches far outside the view",
        ),
        (
            "a stroke to x = 1e9",
            r##"<path d="M20 150 L1e9 160" stroke="#000" stroke-width="4" fill="none"/>"##,
            "reaches far outside the view",
        ),
        (
            "scale(1000)",
            r##"<path d="M10 180 L40 150 L60 195 Z" fill="#000" transform="scale(1000)"/>"##,
            "lies far outside the view: left out",
        ),
        (
            "skewX(89.999)",
            r##"<path d="M10 180 L40 150 L60 195 Z" fill="#000" transform="skewX(89.999)"/>"##,
            "lies far outside the view: left out",
        ),
        (
            "a transform past f32",
            r##"<path d="M10 180 L4e10 150 L60 195 Z" transform="scale(1e30)"/>
                <path d="M10 180 L40 150 L60 195 Z" transform="matrix(1e38 0 0 1e38 0 0)"/>"##,
            "automatic mode",
        ),
    ];
    for (what, extra, note) in cases {
        let dir = tempfile::tempdir().unwrap();
        for (command, out) in [("frame", "f.png"), ("morph", "m.svg")] {
            let args: &[&str] = if command == "morph" {
                &["--frames", "10"]
            } else {
                &[]
            };
            let (r, written) = morph(dir.path(), &icon(extra), command, out, args);
            assert_eq!(r.code, Some(0), "{what}, {command}: {}", r.stderr);
            assert!(written, "{what}, {command}");
            assert!(r.stderr.contains(note), "{what}, {command}: {}", r.stderr);
            assert_bounded(&r, what);
        }
    }
}

/// Row 7: `--density 50` is refused before any mesh is built, in one line naming the limit and
/// `--max-vertices`, leaving no output; the same drawing at the default density morphs.
#[test]
fn a_density_past_the_vertex_budget_is_one_line_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let marked = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
<path id="boundary" d="M20 20 H180 V180 H20 Z" fill="#c33"/></svg>"##;
    for source in [icon(""), marked.to_string()] {
        let (r, written) = morph(dir.path(), &source, "frame", "d.svg", &["--density", "50"]);
        assert_eq!(r.code, Some(1), "{}", r.stderr);
        assert!(!written);
        let lines: Vec<&str> = r.stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{}", r.stderr);
        assert!(
            lines[0].starts_with("error: ")
                && lines[0].contains("over the limit of 200000 vertices")
                && lines[0].contains("--max-vertices"),
            "{}",
            lines[0]
        );
        assert_bounded(&r, "--density 50");
        assert!(r.secs < 1.0, "refused in {:.2} s", r.secs);
    }
    // At the default density the same pair morphs.
    let (r, written) = morph(dir.path(), &icon(""), "frame", "d.svg", &[]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(written);
}

/// Row 7: a path of 300,000 segments in automatic mode flattens past the default budget and is
/// refused in one line, quickly; `--max-vertices` is the flag that lets it through.
#[test]
fn artwork_past_the_vertex_budget_is_refused_before_it_is_flattened() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = String::from("M100 100");
    let mut x: u32 = 12345;
    for _ in 0..300_000 {
        // A cheap deterministic zigzag inside the view.
        x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        let (a, b) = (20 + (x >> 8) % 160, 20 + (x >> 20) % 160);
        d.push_str(&format!(" L{a} {b}"));
    }
    let source = icon(&format!(
        r##"<path d="{d}" fill="none" stroke="#000" stroke-width="0.1"/>"##
    ));
    let (r, written) = morph(dir.path(), &source, "frame", "a.svg", &[]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(!written);
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(
        r.stderr.contains("artwork flattening to about")
            && r.stderr.contains("--max-vertices")
            && r.stderr.contains("s.svg"),
        "{}",
        r.stderr
    );
    assert_bounded(&r, "300,000 segments");
}
