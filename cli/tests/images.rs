//! Raster images as inputs (issue 14): PNG and JPEG pairs morph, `crmorph init` writes an SVG
//! that morphs, and `--controls` steers an image pair.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/images")
        .join(p)
}

fn run(args: &[&OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crmorph"))
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap()
}

fn os<S: AsRef<OsStr> + ?Sized>(s: &S) -> &OsStr {
    s.as_ref()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The error a run that should fail printed, after checking its exit status (`code`) and that
/// it is one line.
fn one_line_error(o: &Output, code: i32) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    e
}

#[test]
fn a_png_pair_morphs_into_a_gif() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ab.gif");
    for pair in ["faces", "character"] {
        let (s, t) = (
            fixture(&format!("{pair}/source.png")),
            fixture(&format!("{pair}/target.png")),
        );
        let o = run(&[
            os("morph"),
            os(&s),
            os(&t),
            os("-o"),
            os(&out),
            os("--frames"),
            os("4"),
        ]);
        assert!(o.status.success(), "{pair}: {}", stderr(&o));
        assert!(std::fs::read(&out).unwrap().starts_with(b"GIF89a"));
    }
}

#[test]
fn a_jpeg_pair_morphs_too() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ab.gif");
    let (s, t) = (fixture("faces/source.jpg"), fixture("faces/target.jpg"));
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--frames"),
        os("3"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&out).unwrap().starts_with(b"GIF89a"));
}

#[test]
fn init_writes_an_svg_that_morphs() {
    let dir = tempfile::tempdir().unwrap();
    let mut svgs = Vec::new();
    for side in ["source", "target"] {
        let svg = dir.path().join(format!("{side}.svg"));
        let png = fixture(&format!("character/{side}.png"));
        let o = run(&[os("init"), os(&png), os("-o"), os(&svg)]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("<g id=\"controls\" style=\"display:none\">"));
        assert!(text.contains("<path id=\"boundary\""));
        assert!(text.contains("data:image/png;base64,"));
        svgs.push(svg);
    }
    let out = dir.path().join("ab.svg");
    let o = run(&[
        os("morph"),
        os(&svgs[0]),
        os(&svgs[1]),
        os("-o"),
        os(&out),
        os("--frames"),
        os("3"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // init refuses what is not an image, and its own input as output.
    let o = run(&[os("init"), os(&svgs[0]), os("-o"), os(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // (Images are known by their bytes, not their names.)
    let png = dir.path().join("image.svg");
    std::fs::copy(fixture("character/source.png"), &png).unwrap();
    let o = run(&[os("init"), os(&png), os("-o"), os(&png)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("refusing to overwrite"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn controls_steer_an_image_pair() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("faces/source.png"), fixture("faces/target.png"));
    let (sc, tc) = (
        fixture("faces/source-controls.svg"),
        fixture("faces/target-controls.svg"),
    );
    let plain = dir.path().join("plain.json");
    let steered = dir.path().join("steered.json");
    let o = run(&[
        os("frame"),
        os(&s),
        os(&t),
        os("--at"),
        os("0.5"),
        os("-o"),
        os(&plain),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&[
        os("frame"),
        os(&s),
        os(&t),
        os("--at"),
        os("0.5"),
        os("--controls"),
        os(&sc),
        os(&tc),
        os("-o"),
        os(&steered),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&steered).unwrap()).unwrap();
    let names: Vec<&str> = v["curves"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|c| c["name"].as_str())
        .collect();
    for f in [
        "feature-hair",
        "feature-glasses-left",
        "feature-glasses-right",
    ] {
        assert!(names.contains(&f), "{names:?}");
    }
    assert_ne!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&steered).unwrap()
    );
    // The rendered morph too.
    let (a, b) = (dir.path().join("a.gif"), dir.path().join("b.gif"));
    for (out, controls) in [(&a, false), (&b, true)] {
        let mut args = vec![
            os("morph"),
            os(&s),
            os(&t),
            os("-o"),
            os(out),
            os("--frames"),
            os("3"),
        ];
        if controls {
            args.extend([os("--controls"), os(&sc), os(&tc)]);
        }
        let o = run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn controls_on_an_svg_input_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.gif");
    let (s, t) = (fixture("faces/source.svg"), fixture("faces/target.svg"));
    let (sc, tc) = (
        fixture("faces/source-controls.svg"),
        fixture("faces/target-controls.svg"),
    );
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("--controls"),
        os(&sc),
        os(&tc),
        os("-o"),
        os(&out),
    ]);
    let e = one_line_error(&o, 2);
    assert!(
        e.starts_with("error: --controls:") && e.contains("is not an image"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn a_fully_transparent_image_is_a_one_line_error() {
    let dir = tempfile::tempdir().unwrap();
    let clear = dir.path().join("clear.png");
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, 8, 8);
    enc.set_color(png::ColorType::Rgba);
    let mut w = enc.write_header().unwrap();
    w.write_image_data(&[0; 8 * 8 * 4]).unwrap();
    w.finish().unwrap();
    std::fs::write(&clear, &bytes).unwrap();
    let out = dir.path().join("x.svg");
    let o = run(&[os("init"), os(&clear), os("-o"), os(&out)]);
    let e = one_line_error(&o, 1);
    assert!(
        e.starts_with("error: ") && e.contains("clear.png: image: no opaque pixels"),
        "{e}"
    );
}

#[test]
fn a_damaged_picture_is_named_as_one() {
    // Bytes that are no image under an image's name: the error says so, instead of calling the
    // file a broken SVG.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("scan.jpg");
    std::fs::write(&bad, b"\x00\x01 not really a picture").unwrap();
    let out = dir.path().join("x.gif");
    let o = run(&[
        os("morph"),
        os(&bad),
        os(&fixture("faces/source.png")),
        os("-o"),
        os(&out),
    ]);
    let e = one_line_error(&o, 1);
    assert!(
        e.contains("scan.jpg: is named like a JPEG image, but its bytes are neither"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn a_renamed_boundary_id_reaches_image_inputs() {
    // `--boundary-id` names the boundary of drawings; an image drawing's traced boundary takes
    // that name too, with controls or without. Before, the renamed boundary was not found and
    // the pair fell back to automatic mode (no contours: a plain cross-fade).
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("faces/source.png"), fixture("faces/target.png"));
    let (sc, tc) = (
        fixture("faces/source-controls.svg"),
        fixture("faces/target-controls.svg"),
    );
    let (plain, renamed) = (
        dir.path().join("plain.json"),
        dir.path().join("renamed.json"),
    );
    for extra in [vec![], vec![os("--controls"), os(&sc), os(&tc)]] {
        for (out, id) in [(&plain, None), (&renamed, Some("outline"))] {
            let mut args = vec![os("frame"), os(&s), os(&t), os("--at"), os("0.5")];
            args.extend(extra.iter().copied());
            if let Some(id) = id {
                args.extend([os("--boundary-id"), os(id)]);
            }
            args.extend([os("-o"), os(out)]);
            let o = run(&args);
            assert!(o.status.success(), "{extra:?} {id:?}: {}", stderr(&o));
        }
        // The same mesh and frame; only the boundary curve's name differs.
        let (a, b) = (
            std::fs::read_to_string(&plain).unwrap(),
            std::fs::read_to_string(&renamed).unwrap(),
        );
        assert!(a.contains(r#""name":"boundary""#), "{extra:?}");
        assert_eq!(
            b.replace(r#""name":"outline""#, r#""name":"boundary""#),
            a,
            "{extra:?}"
        );
    }
}
