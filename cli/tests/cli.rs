//! The command line as a user meets it: exit codes, one-line errors, atomic outputs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_crmorph"))
}

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(p)
}

fn run(args: &[&std::ffi::OsStr]) -> Output {
    bin().args(args).output().unwrap()
}

fn os<S: AsRef<std::ffi::OsStr> + ?Sized>(s: &S) -> &std::ffi::OsStr {
    s.as_ref()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn inspect_writes_svg_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let svg = dir.path().join("tri.svg");
    let o = run(&[
        os("inspect"),
        os(&s),
        os(&t),
        os("-o"),
        os(&svg),
        os("--quiet"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    usvg::Tree::from_str(&text, &usvg::Options::default()).expect("inspect SVG re-parses");
    let json = dir.path().join("m.json");
    let o = run(&[os("inspect"), os(&s), os(&t), os("-o"), os(&json)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let n = v["source"].as_array().unwrap().len();
    assert_eq!(n, v["target"].as_array().unwrap().len());
    assert!(!v["triangles"].as_array().unwrap().is_empty());
    assert_eq!(v["curves"][0]["name"], "boundary");
    // same input, same bytes
    let again = dir.path().join("m2.json");
    let o = run(&[os("inspect"), os(&s), os(&t), os("-o"), os(&again)]);
    assert!(o.status.success());
    assert_eq!(
        std::fs::read(&json).unwrap(),
        std::fs::read(&again).unwrap()
    );
}

#[test]
fn frame_writes_the_mesh_at_t_for_each_method() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    for method in ["disc", "triangle", "linear"] {
        let out = dir.path().join(format!("{method}.json"));
        let o = run(&[
            os("frame"),
            os(&s),
            os(&t),
            os("--at"),
            os("0.5"),
            os("--method"),
            os(method),
            os("-o"),
            os(&out),
        ]);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        assert_eq!(v["t"], 0.5);
        assert!(v["vertices"].as_array().unwrap().len() > 10);
        assert!(v.get("skeleton").is_none(), "the gourd has no skeleton");
    }
}

#[test]
fn bad_usage_exits_2() {
    let o = run(&[os("inspect")]);
    assert_eq!(o.status.code(), Some(2));
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let o = run(&[
        os("inspect"),
        os(&s),
        os(&t),
        os("-o"),
        os(&dir.path().join("x.txt")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = run(&[
        os("frame"),
        os(&s),
        os(&t),
        os("--at"),
        os("1.5"),
        os("-o"),
        os(&dir.path().join("f.json")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // An animation asked of `frame`: the formats it writes, and where the animation comes from.
    let lottie = dir.path().join("f.lottie");
    let o = run(&[
        os("frame"),
        os(&s),
        os(&t),
        os("--at"),
        os("0.5"),
        os("-o"),
        os(&lottie),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("crmorph frame writes .json, .svg, .png, not .lottie"),
        "{e}"
    );
    assert!(e.contains("write it with crmorph morph"), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(!lottie.exists());
}

#[test]
fn bad_input_exits_1_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let good = fixture("errors/square.svg");
    for bad in [
        "open-boundary.svg",
        "truncated.svg",
        "empty.svg",
        "not-svg.svg",
        "features-cross.svg",
        "square-no-line.svg",
    ] {
        let out = dir.path().join("out.json");
        let b = fixture(&format!("errors/{bad}"));
        let o = run(&[os("inspect"), os(&good), os(&b), os("-o"), os(&out)]);
        assert_eq!(o.status.code(), Some(1), "{bad}: {}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.lines().count(), 1, "{bad}: {e}");
        assert!(e.starts_with("error: "), "{e}");
        assert!(!e.contains("panicked"), "{e}");
        assert!(!out.exists(), "{bad}: a partial output was left");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "{bad}: temporary files left"
        );
    }
    let o = run(&[
        os("inspect"),
        os(&dir.path().join("missing.svg")),
        os(&good),
        os("-o"),
        os(&dir.path().join("o.svg")),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("missing.svg"));
}

#[test]
fn an_input_is_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.svg");
    std::fs::copy(fixture("gourd/source.svg"), &s).unwrap();
    let before = std::fs::read(&s).unwrap();
    let o = run(&[
        os("inspect"),
        os(&s),
        os(&fixture("gourd/target.svg")),
        os("-o"),
        os(&s),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("overwrite"));
    assert_eq!(std::fs::read(&s).unwrap(), before);
}

#[test]
fn the_demo_runs_with_no_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let o = bin().current_dir(dir.path()).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "morph.svg",
        "morph.gif",
        "morph.html",
        "middle.png",
        "inspect.svg",
        "meshes.json",
    ] {
        assert!(
            dir.path().join("crmorph-demo").join(f).exists(),
            "{f} missing"
        );
    }
}

/// Runs `crmorph morph` on the gourd with `extra` arguments, asserting success.
fn morph_gourd(out: &Path, extra: &[&str]) {
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let mut args = vec![os("morph"), os(&s), os(&t), os("-o"), os(out), os("-q")];
    args.extend(extra.iter().map(os));
    let o = run(&args);
    assert!(o.status.success(), "{out:?}: {}", stderr(&o));
}

fn gif_frames(p: &Path) -> (usize, Vec<u16>, bool) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(std::fs::File::open(p).unwrap()).unwrap();
    let mut delays = Vec::new();
    while let Some(f) = d.read_next_frame().unwrap() {
        delays.push(f.delay);
    }
    let looping = d.repeat() == gif::Repeat::Infinite;
    (delays.len(), delays, looping)
}

#[test]
fn morph_writes_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    let small = ["--frames", "12", "--size", "160x160", "--duration", "1.1"];
    // Animated SVG: re-parses, byte-identical on a second run.
    morph_gourd(&p("a.svg"), &small);
    morph_gourd(&p("b.svg"), &small);
    let svg = std::fs::read_to_string(p("a.svg")).unwrap();
    assert_eq!(svg, std::fs::read_to_string(p("b.svg")).unwrap());
    usvg::Tree::from_str(&svg, &usvg::Options::default()).expect("animated SVG re-parses");
    assert!(svg.contains("<animate attributeName=\"d\"") && svg.contains("dur=\"1.1s\""));
    assert!(svg.contains("width=\"160\" height=\"160\""));
    // GIF: 12 frames played once, delays of 1.1 s / 11 = 10 cs.
    morph_gourd(&p("m.gif"), &small);
    let (n, delays, looping) = gif_frames(&p("m.gif"));
    assert_eq!(n, 12);
    assert!(!looping);
    assert!(delays.iter().all(|d| *d == 10), "{delays:?}");
    // Yoyo: forwards and back without doubling the ends, forever.
    let mut yoyo = small.to_vec();
    yoyo.push("--yoyo");
    morph_gourd(&p("y.gif"), &yoyo);
    let (n, _, looping) = gif_frames(&p("y.gif"));
    assert_eq!((n, looping), (22, true));
    // APNG with its frame count and a loop.
    let mut looped = small.to_vec();
    looped.push("--loop");
    morph_gourd(&p("m.png"), &looped);
    let d = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(p("m.png")).unwrap(),
    ));
    let r = d.read_info().unwrap();
    let ac = r.info().animation_control.expect("an animated PNG");
    assert_eq!((ac.num_frames, ac.num_plays), (12, 0));
    assert_eq!((r.info().width, r.info().height), (160, 160));
    // HTML preview: standalone, with the animation and the controls.
    morph_gourd(&p("m.html"), &small);
    let html = std::fs::read_to_string(p("m.html")).unwrap();
    for needle in ["<svg", "crmorph-time", "crmorph-play", "crmorph-mesh"] {
        assert!(html.contains(needle), "{needle}");
    }
    // JSON: every frame's mesh, at eased times.
    let mut eased = small.to_vec();
    eased.extend(["--easing", "ease-in-out"]);
    morph_gourd(&p("m.json"), &eased);
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(p("m.json")).unwrap()).unwrap();
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 12);
    let t1 = frames[1]["t"].as_f64().unwrap();
    assert!(t1 > 0.0 && t1 < 1.0 / 11.0, "ease-in starts slowly: {t1}");
}

#[test]
fn frames_dir_holds_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    let out = dir.path().join("m.svg");
    morph_gourd(
        &out,
        &["--frames", "5", "--frames-dir", frames.to_str().unwrap()],
    );
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "frame_000.svg",
            "frame_001.svg",
            "frame_002.svg",
            "frame_003.svg",
            "frame_004.svg"
        ]
    );
    for n in &names {
        let text = std::fs::read_to_string(frames.join(n)).unwrap();
        usvg::Tree::from_str(&text, &usvg::Options::default()).expect("frame re-parses");
    }
    let pngs = dir.path().join("pngs");
    morph_gourd(
        &dir.path().join("m2.svg"),
        &[
            "--frames",
            "3",
            "--size",
            "64x48",
            "--frames-dir",
            pngs.to_str().unwrap(),
            "--frame-format",
            "png",
        ],
    );
    for i in 0..3 {
        let f = pngs.join(format!("frame_00{i}.png"));
        let d = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&f).unwrap()));
        let r = d.read_info().unwrap();
        assert_eq!((r.info().width, r.info().height), (64, 48));
    }
}

/// Issue 13, item 7: when the main output fails, --frames-dir is left as it was: not created
/// when it did not exist, and without new frames (or temporary files) when it did. The main
/// output fails deterministically: its folder does not exist, or its path is a folder.
#[test]
fn a_failed_output_leaves_no_frames_behind() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let existing = dir.path().join("existing");
    std::fs::create_dir(&existing).unwrap();
    std::fs::write(existing.join("notes.txt"), b"mine").unwrap();
    let folder_as_output = dir.path().join("taken.gif");
    std::fs::create_dir(&folder_as_output).unwrap();
    let missing_folder = dir.path().join("no-such-folder/m.gif");
    for (k, out) in [&missing_folder, &folder_as_output].into_iter().enumerate() {
        for format in ["svg", "png"] {
            let fresh = dir.path().join(format!("fresh-{k}-{format}/frames"));
            for frames in [&fresh, &existing] {
                let o = run(&[
                    os("morph"),
                    os(&s),
                    os(&t),
                    os("-o"),
                    os(out),
                    os("--frames"),
                    os("4"),
                    os("--size"),
                    os("64x64"),
                    os("--frames-dir"),
                    os(frames),
                    os("--frame-format"),
                    os(format),
                ]);
                assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
                assert!(
                    !fresh.exists(),
                    "{}: created for a failed run",
                    fresh.display()
                );
                let left: Vec<String> = std::fs::read_dir(&existing)
                    .unwrap()
                    .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect();
                assert_eq!(left, ["notes.txt"], "{}", out.display());
            }
        }
    }
    // Nothing beside the outputs either (no staging folders left in the temporary folder).
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    names.sort();
    assert!(names.is_empty(), "{names:?}");
}

#[test]
fn inspect_renders_png() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let out = dir.path().join("tri.png");
    let o = run(&[
        os("inspect"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--width"),
        os("300"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let d = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let r = d.read_info().unwrap();
    assert_eq!(r.info().width, 300);
    assert!(r.info().height > 50);
}

#[test]
fn inspect_png_has_its_captions() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let (svg, png) = (dir.path().join("tri.svg"), dir.path().join("tri.png"));
    for out in [&svg, &png] {
        let o = run(&[os("inspect"), os(&s), os(&t), os("-o"), os(out)]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // Each panel's caption is a <text> centred under it, in the band below the panels.
    let text = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(text.matches("<text ").count(), 2);
    let img = tiny_skia::Pixmap::load_png(&png).unwrap();
    let (w, h) = (img.width() as usize, img.height() as usize);
    let (panel, band) = (w / 2, h - w / 2); // panels are square, the caption band below them
    assert!(band > 10, "{w}×{h}");
    let dark = |x: usize, y: usize| {
        let p = img.pixel(x as u32, y as u32).unwrap();
        p.alpha() > 200 && p.red() < 128 && p.green() < 128 && p.blue() < 128
    };
    for k in 0..2 {
        let ink: Vec<usize> = (panel..h)
            .flat_map(|y| (k * panel..(k + 1) * panel).map(move |x| (x, y)))
            .filter(|&(x, y)| dark(x, y))
            .map(|(x, _)| x - k * panel)
            .collect();
        // A line of text: hundreds of dark pixels, spread over much of the panel's width and
        // centred under it.
        assert!(ink.len() > 300, "panel {k}: {} caption pixels", ink.len());
        let (lo, hi) = (*ink.iter().min().unwrap(), *ink.iter().max().unwrap());
        assert!(hi - lo > panel / 4, "panel {k}: caption {lo}..{hi}");
        let centre = (lo + hi) as f64 / 2.0;
        assert!(
            (centre - panel as f64 / 2.0).abs() < 0.05 * panel as f64,
            "panel {k}: {centre}"
        );
    }
    // The same picture on every run (the font is bundled, not looked up on the system).
    let again = dir.path().join("again.png");
    let o = run(&[os("inspect"), os(&s), os(&t), os("-o"), os(&again)]);
    assert!(o.status.success());
    assert_eq!(std::fs::read(&png).unwrap(), std::fs::read(&again).unwrap());
}

#[test]
fn morph_usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let out = dir.path().join("m.svg");
    for extra in [
        &["--loop", "--yoyo"][..],
        &["--duration", "0"],
        &["--frames", "1"],
        &["--frame-format", "png"],
        &["--easing", "bouncy"],
        &["--size", "0x10"],
    ] {
        let mut args = vec![os("morph"), os(&s), os(&t), os("-o"), os(&out)];
        args.extend(extra.iter().map(os));
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(!out.exists());
    }
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&dir.path().join("m.bmp")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn skeleton_writes_an_editable_pose_that_steers_the_morph() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("dancer/source.svg"), fixture("dancer/target.svg"));
    let pose = dir.path().join("pose.svg");
    let o = run(&[
        os("skeleton"),
        os(&s),
        os(&t),
        os("--at"),
        os("0.4"),
        os("-o"),
        os(&pose),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&pose).unwrap();
    usvg::Tree::from_str(&text, &usvg::Options::default()).expect("the pose file is valid SVG");
    for id in ["skeleton-body", "skeleton-arms", "skeleton-legs"] {
        assert!(text.contains(&format!("id=\"{id}\"")), "{id}");
    }
    // Unedited, the pose is the derived skeleton: the frame barely changes.
    let json = |extra: &[&str], name: &str| -> Vec<(f64, f64)> {
        let out = dir.path().join(name);
        let mut args = vec![
            os("frame"),
            os(&s),
            os(&t),
            os("--at"),
            os("0.4"),
            os("-o"),
            os(&out),
        ];
        args.extend(extra.iter().map(os));
        let o = run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        v["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect()
    };
    let plain = json(&[], "plain.json");
    // The frame's JSON carries the skeleton (DESIGN.md §3).
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("plain.json")).unwrap()).unwrap();
    assert_eq!(v["skeleton"]["joints"].as_array().unwrap().len(), 18);
    assert_eq!(v["skeleton"]["bones"].as_array().unwrap().len(), 17);
    let pose_arg = format!("0.4={}", pose.display());
    let same = json(&["--pose", &pose_arg], "same.json");
    let worst = plain
        .iter()
        .zip(&same)
        .map(|(a, b)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt())
        .fold(0.0, f64::max);
    assert!(worst < 1.0, "an unedited pose moved a vertex by {worst}");
    // The bundled edited pose makes a different frame.
    let edited = format!("0.5={}", fixture("dancer/pose-0.5.svg").display());
    let kicked = json(&["--pose", &edited], "kicked.json");
    let moved = plain
        .iter()
        .zip(&kicked)
        .map(|(a, b)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt())
        .fold(0.0, f64::max);
    assert!(
        moved > 10.0,
        "the edited pose moved vertices by only {moved}"
    );
}

#[test]
fn pose_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("dancer/source.svg"), fixture("dancer/target.svg"));
    let out = dir.path().join("m.svg");
    // A pose made for the lower-body skeleton does not fit the full one.
    let lower = format!("0.5={}", fixture("dancer/pose-lower-0.5.svg").display());
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--pose"),
        os(&lower),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("pose-lower-0.5.svg") && e.contains("skeleton"),
        "{e}"
    );
    assert_eq!(e.lines().count(), 1);
    assert!(!out.exists());
    // A drawing without a skeleton cannot take poses.
    let (g, h) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let o = run(&[
        os("morph"),
        os(&g),
        os(&h),
        os("-o"),
        os(&out),
        os("--pose"),
        os(&lower),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("has no skeleton"), "{}", stderr(&o));
    // Usage: a time outside (0, 1), the triangle method, a missing file.
    for bad in [&["--pose", "1.0=x.svg"][..], &["--pose", "nonsense"]] {
        let mut args = vec![os("morph"), os(&s), os(&t), os("-o"), os(&out)];
        args.extend(bad.iter().map(os));
        assert_eq!(run(&args).status.code(), Some(2), "{bad:?}");
    }
    let full = format!("0.5={}", fixture("dancer/pose-0.5.svg").display());
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--pose"),
        os(&full),
        os("--method"),
        os("linear"),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--pose"),
        os("0.5=missing.svg"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("missing.svg"), "{}", stderr(&o));
}

#[test]
fn negative_numbers_are_values_reported_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let (s, t) = (fixture("gourd/source.svg"), fixture("gourd/target.svg"));
    let out = dir.path().join("f.json");
    for (flag, value, problem) in [
        ("--at", "-0.1", "must be in [0, 1]"),
        ("--at", "-1e-9", "must be in [0, 1]"),
        ("--density", "-2", "must be a number in (0, 100]"),
    ] {
        let mut args = vec![os("frame"), os(&s), os(&t), os("-o"), os(&out)];
        if flag != "--at" {
            args.extend([os("--at"), os("0.5")]);
        }
        args.extend([os(flag), os(value)]);
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(!e.contains("unexpected argument"), "{e}");
        assert!(
            e.contains(&format!("invalid value '{value}' for '{flag}")) && e.contains(problem),
            "{e}"
        );
        assert!(!out.exists());
    }
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&dir.path().join("m.svg")),
        os("--frames"),
        os("-3"),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("-3 is not in 2..=10000"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn every_command_answers_version() {
    let version = env!("CARGO_PKG_VERSION");
    for args in [
        &["--version"][..],
        &["morph", "--version"],
        &["frame", "-V"],
        &["inspect", "--version"],
        &["skeleton", "--version"],
    ] {
        let o = bin().args(args).output().unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.starts_with("crmorph") && text.trim_end().ends_with(version),
            "{args:?}: {text}"
        );
    }
}

#[test]
fn completions_and_manual_pages_are_printed() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let o = bin().args(["completions", shell]).output().unwrap();
        assert!(o.status.success(), "{shell}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        for c in [
            "morph",
            "frame",
            "inspect",
            "skeleton",
            "batch",
            "completions",
        ] {
            assert!(text.contains(c), "{shell}: no {c}");
        }
    }
    let o = bin().args(["completions", "tcsh"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let o = bin().arg("man").output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let page = String::from_utf8_lossy(&o.stdout);
    assert!(page.contains(".TH crmorph 1"));
    for c in [
        "morph",
        "frame",
        "inspect",
        "skeleton",
        "batch",
        "completions",
        "man",
    ] {
        assert!(page.contains(&format!("crmorph\\-{c}(1)")), "no {c}");
    }
    let o = bin().args(["man", "frame"]).output().unwrap();
    let page = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && page.contains(".TH crmorph-frame 1"));
    assert!(page.contains("\\-\\-at"));
    let o = bin().args(["man", "nonsense"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).starts_with("error: crmorph has no command 'nonsense'"));
    // `--help` tells where to find both, and the markup conventions.
    let o = bin().arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "crmorph completions",
        "crmorph man",
        "feature-NAME",
        "anchor-NAME",
        "id=\"controls\"",
        "--boundary-id",
        "automatic mode",
    ] {
        assert!(help.contains(needle), "--help lacks {needle}");
    }
}

#[test]
fn ids_that_almost_follow_a_convention_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let src = fixture("gourd/source.svg");
    let text = std::fs::read_to_string(fixture("gourd/target.svg")).unwrap();
    let out = dir.path().join("f.svg");
    for (from, to, want) in [
        (
            "id=\"boundary\"",
            "id=\"Boundary\"",
            "has no 'boundary' element, but ",
        ),
        (
            "id=\"feature-vine\"",
            "id=\"feature_vine\"",
            "feature-vine is in ",
        ),
        (
            "id=\"anchor-stem-tip\"",
            "id=\"Anchor-stem-tip\"",
            "'anchor-stem-tip': has no twin in ",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let tgt = dir.path().join("typo.svg");
        std::fs::write(&tgt, text.replace(from, to)).unwrap();
        let o = run(&[
            os("frame"),
            os(&src),
            os(&tgt),
            os("--at"),
            os("0.5"),
            os("-o"),
            os(&out),
        ]);
        assert_eq!(o.status.code(), Some(1), "{to}");
        let e = stderr(&o);
        let wrong = to.trim_start_matches("id=").trim_matches('"');
        let right = from.trim_start_matches("id=").trim_matches('"');
        assert!(e.contains(want), "{e}");
        assert!(
            e.contains(&format!("typo.svg has '{wrong}'"))
                && e.contains(&format!("rename it to '{right}'")),
            "{e}"
        );
        assert!(!out.exists());
    }
    // A misspelt guides group is drawn as artwork: the run succeeds, with a note.
    let tgt = dir.path().join("typo.svg");
    std::fs::write(&tgt, text.replace("id=\"controls\"", "id=\"Controls\"")).unwrap();
    let o = run(&[
        os("frame"),
        os(&src),
        os(&tgt),
        os("--at"),
        os("0.5"),
        os("-o"),
        os(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("typo.svg: element 'Controls' is not read as 'controls'"),
        "{}",
        stderr(&o)
    );
}

/// The `viewBox` and pixel size of an SVG crmorph wrote.
fn view_of(svg: &str) -> ([f64; 4], (u32, u32)) {
    let attr = |name: &str| {
        let start = svg.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        svg[start..start + svg[start..].find('"').unwrap()].to_string()
    };
    let v: Vec<f64> = attr("viewBox")
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    (
        [v[0], v[1], v[2], v[3]],
        (
            attr("width").parse().unwrap(),
            attr("height").parse().unwrap(),
        ),
    )
}

#[test]
fn the_view_grows_to_hold_a_morph_that_leaves_it() {
    // A bar as wide as its 200 × 60 view turns half a turn (the anchor pins its left end to
    // the right end): at t = ½ it stands upright, 190 tall.
    let dir = tempfile::tempdir().unwrap();
    let bar = |fill: &str, ax: u32, ay: u32| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 200 60\" width=\"200\" \
             height=\"60\"><rect id=\"boundary\" x=\"5\" y=\"20\" width=\"190\" height=\"20\" \
             fill=\"{fill}\"/><g id=\"controls\" style=\"display:none\"><circle \
             id=\"anchor-tip\" cx=\"{ax}\" cy=\"{ay}\" r=\"1\"/></g></svg>"
        )
    };
    let (s, t) = (dir.path().join("s.svg"), dir.path().join("t.svg"));
    std::fs::write(&s, bar("#3f51b5", 5, 20)).unwrap();
    std::fs::write(&t, bar("#e91e63", 195, 40)).unwrap();
    let frame = |extra: &[&str]| {
        let out = dir.path().join("f.svg");
        let mut args = vec![
            os("frame"),
            os(&s),
            os(&t),
            os("--at"),
            os("0.5"),
            os("-o"),
            os(&out),
        ];
        args.extend(extra.iter().map(os));
        let o = run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        view_of(&std::fs::read_to_string(&out).unwrap())
    };
    // Default: fit. The view holds the upright bar (−65 … 125) at the drawing's own scale.
    let (v, size) = frame(&[]);
    assert!(v[1] < -65.0 && v[1] + v[3] > 125.0, "{v:?}");
    assert!(v[3] < 200.0, "only a small margin: {v:?}");
    assert_eq!((v[0], v[2]), (0.0, 200.0), "{v:?}");
    assert_eq!(size, (200, v[3].ceil() as u32));
    // --view source keeps the source's view; --padding adds room on every side.
    assert_eq!(
        frame(&["--view", "source"]),
        ([0.0, 0.0, 200.0, 60.0], (200, 60))
    );
    let padded = frame(&["--view", "source", "--padding", "10"]);
    assert_eq!(padded, ([-10.0, -10.0, 220.0, 80.0], (220, 80)));
    let (p, _) = frame(&["--view", "source", "--padding", "5%"]);
    assert_eq!(p, [-10.0, -10.0, 220.0, 80.0]);
    // The animated SVG shows the same view as its frames.
    let out = dir.path().join("m.svg");
    let o = run(&[
        os("morph"),
        os(&s),
        os(&t),
        os("-o"),
        os(&out),
        os("--frames"),
        os("9"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(view_of(&std::fs::read_to_string(&out).unwrap()), (v, size));
    let o = run(&[
        os("frame"),
        os(&s),
        os(&t),
        os("--at"),
        os("0.5"),
        os("-o"),
        os(&out),
        os("--padding"),
        os("-1"),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// Issue 15: `-o NAME.lottie.json` writes Lottie JSON and `-o NAME.lottie` a dotLottie
/// archive holding the same animation and a manifest; a morph of raster images is refused
/// with a one-line error and no file.
#[test]
fn lottie_outputs_are_json_and_a_dotlottie_archive() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("gourd.lottie.json");
    let archive = dir.path().join("gourd.lottie");
    morph_gourd(&json, &[]);
    morph_gourd(&archive, &[]);
    let text = std::fs::read_to_string(&json).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["nm"], "gourd");
    assert!(doc["layers"].as_array().is_some_and(|l| !l.is_empty()));
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&archive).unwrap()).unwrap();
    let mut read = |name: &str| {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut zip.by_name(name).unwrap(), &mut s).unwrap();
        s
    };
    assert_eq!(
        read("animations/gourd.json"),
        text,
        "the archive holds the same JSON"
    );
    let manifest: serde_json::Value = serde_json::from_str(&read("manifest.json")).unwrap();
    assert_eq!(manifest["animations"][0]["id"], "gourd");
    assert_eq!(manifest["animations"][0]["loop"], false);
    let looping = dir.path().join("loop.lottie");
    morph_gourd(&looping, &["--loop"]);
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&looping).unwrap()).unwrap();
    let mut s = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("manifest.json").unwrap(), &mut s).unwrap();
    assert!(s.contains("\"loop\":true"), "{s}");
    // Same input, same bytes: the archive's time stamps are fixed.
    let other = tempfile::tempdir().unwrap();
    let again = other.path().join("gourd.lottie");
    morph_gourd(&again, &[]);
    let same = std::fs::read(&archive).unwrap() == std::fs::read(&again).unwrap();
    assert!(same, "the same morph gives the same archive");
    let raster = dir.path().join("faces.lottie");
    let img = |f: &str| fixture(&format!("images/faces/{f}"));
    let o = run(&[
        os("morph"),
        os(&img("source.png")),
        os(&img("target.png")),
        os("--controls"),
        os(&img("source-controls.svg")),
        os(&img("target-controls.svg")),
        os("-o"),
        os(&raster),
        os("-q"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("cannot be written as Lottie"), "{err}");
    assert!(!raster.exists(), "no output on failure");
}
