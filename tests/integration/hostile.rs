//! Hostile drawings in-process (issue 12, item 8): the fuzz target's regression corpus
//! replayed, and a proptest generator of hostile SVG (extreme numbers, degenerate transforms,
//! deep groups, `<use>` fan-out, the conventions' ids in the wrong places) through reading →
//! mesh → one frame. Every case must end in success or a one-line input error: no panic, no
//! internal error, and no case slower than a few seconds.
//!
//! The coverage-guided fuzzer is `fuzz/` (cargo-fuzz); its findings go into
//! `tests/hostile-corpus/` so that they are replayed here.

mod harness;

use std::time::Instant;

use proptest::prelude::*;

/// One case through the harness: a panic, an internal error or a multi-line error fails it.
fn survive(name: &str, source: &[u8], target: &[u8]) {
    let started = Instant::now();
    let run = std::panic::catch_unwind(|| harness::morph_once(source, target));
    let secs = started.elapsed().as_secs_f64();
    match run {
        Ok(Ok(())) => eprintln!("STAT ok"),
        Ok(Err(e)) => {
            eprintln!("STAT err {e}");
            assert!(e.is_input(), "{name}: {e}");
            assert!(!e.to_string().contains('\n'), "{name}: one line: {e}");
        }
        Err(_) => panic!("{name}: panicked"),
    }
    assert!(secs < 10.0, "{name}: took {secs:.1} s");
}

#[test]
fn the_regression_corpus_is_survived() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile-corpus");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/hostile-corpus exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().is_some_and(|n| n != "README.md"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "the corpus holds its cases");
    for f in files {
        let data = std::fs::read(&f).unwrap();
        let (s, t) = harness::split(&data);
        survive(&f.display().to_string(), s, t);
    }
}

/// Numbers a hostile file writes: ordinary, tiny, huge, at the f32 edge, not numbers at all.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        16 => (-50i32..150).prop_map(|v| v.to_string()),
        1 => Just("0".to_string()),
        1 => Just("1e-300".to_string()),
        1 => Just("1e5".to_string()),
        1 => Just("-1e6".to_string()),
        1 => Just("3.4e38".to_string()),
        1 => Just("1e308".to_string()),
        1 => Just("NaN".to_string()),
        1 => Just("inf".to_string()),
        1 => Just("7.000000000001".to_string()),
    ]
}

fn transform() -> impl Strategy<Value = String> {
    prop_oneof![
        12 => Just(String::new()),
        1 => Just(r#" transform="scale(1000)""#.to_string()),
        1 => Just(r#" transform="skewX(89.999)""#.to_string()),
        1 => Just(r#" transform="scale(0)""#.to_string()),
        1 => Just(r#" transform="matrix(1e30 0 0 1e-30 0 0)""#.to_string()),
        1 => (number(), number()).prop_map(|(a, b)| format!(r#" transform="translate({a} {b}) rotate({a})""#)),
    ]
}

fn id() -> impl Strategy<Value = String> {
    prop_oneof![
        16 => Just(String::new()),
        1 => Just(r#" id="boundary""#.to_string()),
        1 => Just(r#" id="feature-a""#.to_string()),
        1 => Just(r#" id="anchor-a""#.to_string()),
        1 => Just(r#" id="skeleton""#.to_string()),
        1 => Just(r#" id="u""#.to_string()),
        1 => Just(" id=\"Feature_\u{1b}[31ma\"".to_string()),
    ]
}

fn shape() -> impl Strategy<Value = String> {
    let paint = prop_oneof![
        Just(r#" fill="red""#),
        Just(r#" fill="none" stroke="black" stroke-width="3""#),
        Just(r#" fill-rule="evenodd" fill="url(#missing)""#),
        Just(r#" fill="blue" opacity="0.5""#),
    ];
    let numbers = prop::collection::vec(number(), 4..12);
    (0..6u8, numbers, transform(), id(), paint).prop_map(|(kind, n, tr, id, paint)| {
        let a = |k: usize| n[k % n.len()].clone();
        match kind {
            0 => format!(
                r#"<rect x="{}" y="{}" width="{}" height="{}"{tr}{id}{paint}/>"#,
                a(0),
                a(1),
                a(2),
                a(3)
            ),
            1 => format!(
                r#"<circle cx="{}" cy="{}" r="{}"{tr}{id}{paint}/>"#,
                a(0),
                a(1),
                a(2)
            ),
            2 => format!(r#"<polyline points="{}"{tr}{id}{paint}/>"#, n.join(" ")),
            3 => format!(
                r#"<path d="M{} {} C{} {} {} {} {} {} Q{} {} {} {} Z"{tr}{id}{paint}/>"#,
                a(0),
                a(1),
                a(2),
                a(3),
                a(4),
                a(5),
                a(6),
                a(7),
                a(8),
                a(9),
                a(10),
                a(11)
            ),
            4 => format!(
                r#"<path d="M{} {} A{} {} 0 1 0 {} {} z m 5 5 l 10 0 0 10 z"{tr}{id}{paint}/>"#,
                a(0),
                a(1),
                a(2),
                a(3),
                a(4),
                a(5)
            ),
            _ => format!(
                r#"<line x1="{}" y1="{}" x2="{}" y2="{}"{tr}{id}{paint}/>"#,
                a(0),
                a(1),
                a(2),
                a(3)
            ),
        }
    })
}

/// Groups of shapes nested a few deep, with `<use>` copying an element by id.
fn content() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        6 => shape(),
        1 => Just(r##"<use href="#u"/>"##.to_string()),
        1 => Just(r##"<use href="#u" transform="scale(1000)"/>"##.to_string()),
        1 => Just(r#"<image href="/etc/passwd" width="10" height="10"/>"#.to_string()),
        1 => Just(r#"<text x="10" y="20">&amp;x</text>"#.to_string()),
    ];
    leaf.prop_recursive(4, 24, 6, |inner| {
        (prop::collection::vec(inner, 0..6), transform(), id())
            .prop_map(|(kids, tr, id)| format!("<g{tr}{id}>{}</g>", kids.concat()))
    })
}

fn drawing() -> impl Strategy<Value = String> {
    let view = prop_oneof![
        12 => Just(r#" viewBox="0 0 100 100""#.to_string()),
        1 => Just(String::new()),
        1 => Just(r#" width="100000" height="100000""#.to_string()),
        1 => Just(r#" viewBox="0 0 0 0""#.to_string()),
        1 => Just(r#" viewBox="-1e300 0 1e300 1e300""#.to_string()),
        1 => (number(), number()).prop_map(|(w, h)| format!(r#" viewBox="0 0 {w} {h}""#)),
    ];
    let guides = prop_oneof![
        3 => Just(String::new()),
        1 => content().prop_map(|c| format!(r#"<g id="controls" style="display:none">{c}</g>"#)),
    ];
    (view, prop::collection::vec(content(), 1..4), guides).prop_map(|(view, body, guides)| {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg"{view}>{}{guides}</svg>"#,
            body.concat()
        )
    })
}

/// Cases per run: 48, or `PROPTEST_CASES` for a long hunt.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(48)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn hostile_drawings_are_survived(source in drawing(), target in prop_oneof![
        1 => Just(harness::CIRCLE.to_string()),
        2 => drawing(),
    ]) {
        survive("generated", source.as_bytes(), target.as_bytes());
    }
}
