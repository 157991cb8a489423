//! Hostile and careless input, as an attacker or a hurried user would try it (issue 12): no
//! file leaks, no abort, no hang, bounded memory, one-line errors, no file left behind, and the
//! SVGs editors write read as they are.
//!
//! Each case runs the release CLI as a child and asserts its exit status, its stderr, its time
//! and its peak memory (`VmHWM` from `/proc`, sampled every few milliseconds, so a short final
//! spike may go unseen; the bounds are far above what a correct run uses).

#[path = "common/measure.rs"]
mod measure;

use std::path::Path;

use measure::{run, Outcome};

/// 1 GiB in KiB: the issue's bound on memory for any refused input.
const GIB: u64 = 1 << 20;

/// A small icon to morph the hostile drawings into.
const CIRCLE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><circle cx="50" cy="50" r="30" fill="blue"/></svg>"#;

/// A red square with `extra` inside the root.
fn square_with(extra: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" viewBox="0 0 100 100"><rect x="10" y="10" width="50" height="50" fill="red"/>{extra}</svg>"#
    )
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `crmorph frame SRC CIRCLE --at 0.5 -o OUT` plus `extra` arguments, in `dir`.
fn frame(dir: &Path, src: &Path, out: &str, extra: &[&str]) -> Outcome {
    let tgt = write(dir, "circle.svg", CIRCLE);
    let mut args: Vec<String> = vec![
        "frame".into(),
        src.display().to_string(),
        tgt.display().to_string(),
        "--at".into(),
        "0.5".into(),
        "-o".into(),
        dir.join(out).display().to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    run(&args, 30.0)
}

/// Asserts a refused input: exit 1, one line naming `needle`, quick, small, no output file.
fn assert_refused(o: &Outcome, dir: &Path, out: &str, needle: &str, max_secs: f64) {
    assert_eq!(o.code, Some(1), "{o:?}");
    let lines: Vec<&str> = o
        .stderr
        .lines()
        .filter(|l| !l.starts_with("note:"))
        .collect();
    assert_eq!(lines.len(), 1, "one line: {o:?}");
    assert!(lines[0].starts_with("error: "), "{o:?}");
    assert!(lines[0].contains(needle), "expected {needle:?}: {o:?}");
    assert!(o.secs < max_secs, "took {:.2} s: {o:?}", o.secs);
    assert!(o.peak_kib < GIB, "peak {} KiB: {o:?}", o.peak_kib);
    assert!(!dir.join(out).exists(), "no output on failure");
    leftovers(dir);
}

/// Asserts a run that succeeds: exit 0, quick and small.
fn assert_fine(o: &Outcome, what: &str) {
    assert_eq!(o.code, Some(0), "{what}: {o:?}");
    assert!(o.secs < 10.0 && o.peak_kib < GIB, "{what}: {o:?}");
}

/// No temporary file is left in `dir`.
fn leftovers(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".crmorph"), "left behind: {name}");
    }
}

/// The base64 of `bytes`' first 48 bytes: what an embedded copy of the file would contain.
fn base64_head(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes[..48].chunks(3) {
        let n = (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32;
        for k in (0..4).rev() {
            out.push(A[(n >> (6 * k) & 63) as usize] as char);
        }
    }
    out
}

/// A real PNG: the secret a hostile drawing tries to make crmorph embed.
fn secret_png() -> Vec<u8> {
    let mut px = tiny_skia::Pixmap::new(8, 8).unwrap();
    px.fill(tiny_skia::Color::from_rgba8(200, 30, 30, 255));
    px.encode_png().unwrap()
}

#[test]
fn row1_local_images_are_read_only_when_allowed_and_only_inside_the_folder() {
    let root = tempfile::tempdir().unwrap();
    let art = root.path().join("art");
    std::fs::create_dir(&art).unwrap();
    let png = secret_png();
    std::fs::write(root.path().join("secret.png"), &png).unwrap();
    std::fs::write(art.join("own.png"), &png).unwrap();
    let secret = base64_head(&png);
    let abs = root.path().join("secret.png").display().to_string();
    let image = |href: &str| format!(r#"<image id="pic" href="{href}" width="40" height="40"/>"#);
    for (href, allow) in [
        ("../secret.png", true),
        (abs.as_str(), true),
        ("own.png", false),
        ("file:///etc/passwd", true),
        ("http://127.0.0.1:9/x.png", true),
    ] {
        let src = write(&art, "leak.svg", &square_with(&image(href)));
        let mut extra = vec!["--view", "source"];
        if allow {
            extra.push("--allow-local-files");
        }
        for out in ["f.svg", "f.png"] {
            let o = frame(&art, &src, out, &extra);
            assert_fine(&o, href);
            assert!(
                o.stderr.contains("image 'pic'") && o.stderr.contains("is left out"),
                "{o:?}"
            );
            let written = std::fs::read(art.join(out)).unwrap();
            assert!(
                !String::from_utf8_lossy(&written).contains(&secret),
                "{href} leaked into {out}"
            );
        }
    }
    // Allowed and inside: the image is embedded.
    let src = write(&art, "own.svg", &square_with(&image("own.png")));
    let o = frame(&art, &src, "f.svg", &["--allow-local-files"]);
    assert_eq!(o.code, Some(0), "{o:?}");
    assert!(!o.stderr.contains("left out"), "{o:?}");
    assert!(std::fs::read_to_string(art.join("f.svg"))
        .unwrap()
        .contains(&secret));
    leftovers(&art);
}

#[cfg(unix)]
#[test]
fn row2_devices_and_fifos_are_never_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("fifo.png");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.map(|s| s.success()).unwrap_or(false), "mkfifo");
    for href in ["/dev/zero", "/dev/urandom", "fifo.png"] {
        let src = write(
            d,
            "dev.svg",
            &square_with(&format!(r#"<image href="{href}" width="9" height="9"/>"#)),
        );
        let o = frame(d, &src, "f.png", &["--allow-local-files=/"]);
        assert_fine(&o, href);
        assert!(o.stderr.contains("not a regular file"), "{href}: {o:?}");
    }
    for input in [Path::new("/dev/zero"), fifo.as_path()] {
        let o = frame(d, input, "g.svg", &[]);
        assert_refused(&o, d, "g.svg", "not a regular file", 5.0);
    }
}

#[test]
fn row3_deep_nesting_is_refused_before_parsing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (open, close, n) in [
        ("<g>", "</g>", 14_000),
        ("<a>", "</a>", 20_000),
        ("<switch>", "</switch>", 20_000),
        ("<svg>", "</svg>", 20_000),
    ] {
        let body = format!("{}{}", open.repeat(n), close.repeat(n));
        let src = write(d, "deep.svg", &square_with(&body));
        let o = frame(d, &src, "f.svg", &[]);
        assert_refused(&o, d, "f.svg", "--max-depth", 2.0);
    }
    // Raised, it is read: the limit is the only thing that refused it.
    let body = format!("{}{}", "<g>".repeat(300), "</g>".repeat(300));
    let src = write(d, "deep.svg", &square_with(&body));
    let o = frame(d, &src, "f.svg", &["--max-depth", "400"]);
    assert_eq!(o.code, Some(0), "{o:?}");
}

#[test]
fn row5_entity_expansion_is_bounded_before_parsing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for uses in [20_000, 28_000] {
        let text = format!(
            r#"<!DOCTYPE svg [<!ENTITY e "{}">]>{}"#,
            "x".repeat(100_000),
            square_with(&format!("<text>{}</text>", "&e;".repeat(uses)))
        );
        let src = write(d, "bomb.svg", &text);
        let o = frame(d, &src, "f.svg", &[]);
        assert_refused(&o, d, "f.svg", "--max-input-bytes", 2.0);
    }
    leftovers(d);
}

#[test]
fn row7_element_and_segment_counts_are_limited() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let many = square_with(&"<rect width=\"1\" height=\"1\"/>".repeat(999_990));
    let src = write(d, "many.svg", &many);
    let o = frame(d, &src, "f.svg", &[]);
    assert_refused(&o, d, "f.svg", "--max-elements", 3.0);
    let long = format!(
        r#"<path d="M0 0{}" fill="none" stroke="black"/>"#,
        " l1 1 l-1 -1".repeat(1_000_000)
    );
    let src = write(d, "long.svg", &square_with(&long));
    let o = frame(d, &src, "f.svg", &[]);
    assert_refused(&o, d, "f.svg", "--max-segments", 3.0);
    // <use> that fans out: 100,000 rectangles from a 12 KB file.
    let mut defs = String::from(r#"<defs><rect id="a0" width="1" height="1"/>"#);
    for k in 1..=5 {
        defs += &format!(
            r#"<g id="a{k}">{}</g>"#,
            format!("<use href=\"#a{}\"/>", k - 1).repeat(10)
        );
    }
    defs += "</defs><use href=\"#a5\"/>";
    let src = write(d, "fan.svg", &square_with(&defs));
    let o = frame(d, &src, "f.svg", &[]);
    assert_refused(&o, d, "f.svg", "--max-elements", 3.0);
}

#[test]
fn row9_the_svgs_editors_write_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plain = square_with("<title>café</title>");
    let reference = {
        let src = write(d, "plain.svg", &plain);
        let o = frame(d, &src, "plain-out.svg", &["--quiet"]);
        assert_eq!(o.code, Some(0), "{o:?}");
        std::fs::read(d.join("plain-out.svg")).unwrap()
    };
    let doctype = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" \
         \"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd\">\n{plain}"
    );
    let illustrator = format!(
        "<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" \"svg11.dtd\" [\n\t<!ENTITY ns_svg \
         \"http://www.w3.org/2000/svg\">\n\t<!ENTITY red \"red\">\n]>\n{}",
        plain
            .replace("\"http://www.w3.org/2000/svg\"", "\"&ns_svg;\"")
            .replace("fill=\"red\"", "fill=\"&red;\"")
    );
    let latin1: Vec<u8> = format!("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>{plain}")
        .chars()
        .map(|c| c as u32 as u8)
        .collect();
    let mut utf16 = vec![0xff, 0xfe];
    for u in format!("<?xml version=\"1.0\" encoding=\"UTF-16\"?>{plain}").encode_utf16() {
        utf16.extend_from_slice(&u.to_le_bytes());
    }
    let svgz = {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(plain.as_bytes()).unwrap();
        gz.finish().unwrap()
    };
    for (name, bytes) in [
        ("doctype.svg", doctype.into_bytes()),
        ("illustrator.svg", illustrator.into_bytes()),
        ("latin1.svg", latin1),
        ("utf16.svg", utf16),
        ("icon.svgz", svgz),
    ] {
        let src = d.join(name);
        std::fs::write(&src, bytes).unwrap();
        let o = frame(d, &src, "out.svg", &["--quiet"]);
        assert_fine(&o, name);
        assert_eq!(
            std::fs::read(d.join("out.svg")).unwrap(),
            reference,
            "{name}"
        );
    }
}

#[test]
fn row10_diagnostics_point_at_the_crossing_escape_ids_and_blame_what_exists() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let crossing = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200"><rect id="boundary" width="200" height="200"/><line id="feature-a" x1="20" y1="20" x2="180" y2="180" stroke="black"/><line id="feature-b" x1="20" y1="180" x2="180" y2="20" stroke="black"/></svg>"#;
    let src = write(d, "x.svg", crossing);
    let o = frame(d, &src, "f.svg", &[]);
    assert_refused(&o, d, "f.svg", "near (100.000, 100.000)", 5.0);
    let odd = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><rect id=\"boundary\" width=\"10\" height=\"10\"/><path id=\"feature-\u{1b}[31mred\" d=\"M2 2 L8 8 M2 8 L8 2\"/></svg>";
    let src = write(d, "odd.svg", odd);
    let o = frame(d, &src, "f.svg", &[]);
    assert_eq!(o.code, Some(1), "{o:?}");
    assert!(!o.stderr.contains('\u{1b}'), "escaped: {o:?}");
    assert!(o.stderr.contains("\\u{1b}[31mred"), "{o:?}");
    let huge = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 1e300 1e300"><rect width="5" height="5"/></svg>"#;
    let src = write(d, "huge.svg", huge);
    let o = frame(d, &src, "f.svg", &[]);
    assert_refused(&o, d, "f.svg", "the viewBox", 5.0);
    assert!(!o.stderr.contains("'boundary'"), "{o:?}");
}
