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
    for f in ["inspect.svg", "meshes.json", "frames.json"] {
        assert!(
            dir.path().join("crmorph-demo").join(f).exists(),
            "{f} missing"
        );
    }
}
