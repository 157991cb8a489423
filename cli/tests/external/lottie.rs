//! crmorph's Lottie export as players and the specification see it (issue 15): the JSON
//! validates against the Lottie JSON schema (lottie-specs), and two players — lottie-web (its
//! SVG renderer) and dotlottie-web (`ThorVG`, WebAssembly, playing the `.lottie` archive) — show
//! at frame `t · duration · fps` what `crmorph frame --at t` renders.
//!
//! The players and the schema are npm packages pinned in `tools/lottie` (`npm ci --prefix
//! tools/lottie`); the pages are served by `tools/lottie/serve.mjs` on 127.0.0.1, since module
//! scripts and WebAssembly are refused from file:// pages.
//!
//! Tolerance: the players antialias differently from resvg, and Lottie's keyframes are cubics
//! within a quarter pixel of the warp (as the animated SVG's). Measured on the gourd at 400 px
//! the mean difference is about 1.7 of 255 and 0.2 % of pixels differ by more than 32; the test
//! allows a mean of 3, 1 % of pixels beyond 32 and 0.5 % beyond 64. The middle frame must not
//! match either end, so a player stuck on a keyframe, or at the wrong time, fails.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use libtest_mimic::Trial;
use tiny_skia::Pixmap;

use crate::{needing, tools};

pub(crate) fn trials() -> Vec<Trial> {
    let schema = tools::all(&[tools::node(1), tools::lottie_packages(1)]);
    let players = tools::all(&[
        tools::chromium(2),
        tools::node(2),
        tools::lottie_packages(2),
    ]);
    vec![
        needing(
            "lottie::exports_validate_against_the_lottie_schema",
            &schema,
            exports_validate,
        ),
        needing(
            "lottie::lottie_web_in_chromium_shows_crmorphs_frames",
            &players,
            |chrome| players_show_frames(chrome, Player::LottieWeb),
        ),
        needing(
            "lottie::dotlottie_web_plays_the_archive_as_crmorphs_frames",
            &players,
            |chrome| players_show_frames(chrome, Player::DotLottie),
        ),
    ]
}

const SIZE: (u32, u32) = (400, 400);
/// Lottie frames per second of a crmorph export, and its default duration.
const FPS: f64 = 60.0;
const DURATION: f64 = 2.0;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn lottie_dir() -> PathBuf {
    repo().join("tools/lottie")
}

fn crmorph(args: &[&std::ffi::OsStr]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_crmorph"))
        .args(args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `crmorph morph` of `fixtures/NAME` to `out`, 400 px on white, with `extra` options; its
/// notes.
fn export(name: &str, out: &Path, extra: &[&str]) -> String {
    let dir = repo().join("fixtures").join(name);
    let (s, t) = (dir.join("source.svg"), dir.join("target.svg"));
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let mut args: Vec<&std::ffi::OsStr> = vec!["morph".as_ref(), s.as_ref(), t.as_ref()];
    args.extend(["-o".as_ref(), out.as_os_str()]);
    let common = ["--size", size.as_str(), "--background", "white"];
    for a in common.iter().chain(extra) {
        args.push(a.as_ref());
    }
    crmorph(&args)
}

/// crmorph's own frame of `fixtures/NAME` at `t`, 400 px on white.
fn reference(name: &str, t: f64, work: &Path) -> Pixmap {
    let dir = repo().join("fixtures").join(name);
    let (s, tg) = (dir.join("source.svg"), dir.join("target.svg"));
    let png = work.join(format!("{}-{t}.png", name.replace('/', "-")));
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let at = t.to_string();
    let mut args: Vec<&std::ffi::OsStr> = vec!["frame".as_ref(), s.as_ref(), tg.as_ref()];
    args.extend(["--at".as_ref(), at.as_ref(), "-o".as_ref(), png.as_os_str()]);
    for a in ["--size", &size, "--background", "white", "--quiet"] {
        args.push(a.as_ref());
    }
    crmorph(&args);
    Pixmap::load_png(&png).unwrap()
}

fn exports_validate(node: &Path) -> Result<(), String> {
    let work = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    // Marked-up drawings (gradients, strokes, translucent groups), automatic-mode icons
    // (morphing paths with mixed paints, a gradient badge), easing and yoyo.
    let cases: [(&str, &[&str]); 5] = [
        ("gourd", &[]),
        ("gourd", &["--easing", "ease-in-out", "--yoyo"]),
        ("icons/gradient-badge", &[]),
        ("icons/github-to-gitlab", &[]),
        ("icons/sun-to-moon", &["--loop"]),
    ];
    for (k, (name, extra)) in cases.iter().enumerate() {
        let out = work.path().join(format!("case{k}.lottie.json"));
        export(name, &out, extra);
        files.push(out);
    }
    let validate = |files: &[PathBuf]| {
        Command::new(node)
            .arg(lottie_dir().join("validate.mjs"))
            .args(files)
            .output()
            .unwrap()
    };
    let o = validate(&files);
    let report = String::from_utf8_lossy(&o.stdout).into_owned();
    eprintln!("{report}");
    assert!(o.status.success(), "schema errors:\n{report}");
    assert_eq!(
        report.matches(": 0 errors").count(),
        files.len(),
        "{report}"
    );
    // The validator can fail: a width that is not an integer is an error.
    let text = std::fs::read_to_string(&files[0]).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["w"] = serde_json::json!("wide");
    let bad = work.path().join("bad.lottie.json");
    std::fs::write(&bad, doc.to_string()).unwrap();
    assert!(
        !validate(&[bad]).status.success(),
        "a broken file is refused"
    );
    Ok(())
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Player {
    LottieWeb,
    DotLottie,
}

/// `serve.mjs` serving `tools/lottie` and `work` (under /work/), stopped when dropped.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start(work: &Path) -> Server {
        let node = match tools::node(0) {
            tools::Found::Yes(p) => p,
            tools::Found::Missing(why) => panic!("{why}"),
        };
        let mut child = Command::new(node)
            .arg(lottie_dir().join("serve.mjs"))
            .arg(lottie_dir())
            .arg(work)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let port = line.trim().parse().expect("serve.mjs prints its port");
        Server { child, port }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The player's frame `frame` of the animation at `/work/FILE`, screenshotted.
fn shot(
    chrome: &Path,
    server: &Server,
    player: Player,
    file: &str,
    frame: f64,
    work: &Path,
) -> Pixmap {
    let name = match player {
        Player::LottieWeb => "lottie-web",
        Player::DotLottie => "dotlottie",
    };
    let png = work.join(format!("shot-{name}-{file}-{frame}.png"));
    let profile = tempfile::tempdir().unwrap();
    let url = format!(
        "http://127.0.0.1:{}/player.html?player={name}&src=/work/{file}&frame={frame}&w={}&h={}",
        server.port, SIZE.0, SIZE.1
    );
    let out = tools::chromium_screenshot(&mut Command::new(chrome), profile.path(), SIZE, &png)
        .arg("--virtual-time-budget=10000")
        .arg(url)
        .output()
        .unwrap();
    assert!(
        png.exists(),
        "Chromium wrote no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Pixmap::load_png(&png).unwrap()
}

fn matches(shot: &Pixmap, reference: &Pixmap) -> bool {
    let (mean, over32, over64) = tools::difference(shot, reference);
    mean <= 3.0 && over32 <= 0.01 && over64 <= 0.005
}

fn players_show_frames(chrome: &Path, player: Player) -> Result<(), String> {
    let work = tempfile::tempdir().unwrap();
    let server = Server::start(work.path());
    let ext = match player {
        Player::LottieWeb => "lottie.json",
        Player::DotLottie => "lottie",
    };
    // The gourd (a marked-up drawing: gradients, strokes, the dissolve) at both ends and in
    // between, and two automatic-mode icons (morphing paths) in the middle.
    let cases: [(&str, &[f64]); 3] = [
        ("gourd", &[0.0, 0.37, 1.0]),
        ("icons/gradient-badge", &[0.5]),
        ("icons/github-to-gitlab", &[0.5]),
    ];
    for (name, times) in cases {
        let file = format!("{}.{ext}", name.replace('/', "-"));
        export(name, &work.path().join(&file), &["--quiet"]);
        let refs: Vec<Pixmap> = times
            .iter()
            .map(|&t| reference(name, t, work.path()))
            .collect();
        for (&t, r) in times.iter().zip(&refs) {
            let frame = t * DURATION * FPS;
            let s = shot(chrome, &server, player, &file, frame, work.path());
            let (mean, over32, over64) = tools::difference(&s, r);
            eprintln!(
                "{player:?} {name} at t = {t}: mean {mean:.3}, >32 {over32:.5}, >64 {over64:.5}"
            );
            assert!(
                matches(&s, r),
                "{player:?} shows {name} at t = {t} unlike crmorph: mean {mean:.3}, \
                 >32 {over32:.5}, >64 {over64:.5}"
            );
            if t == 0.37 {
                assert!(
                    !matches(&s, &refs[0]) && !matches(&s, &refs[2]),
                    "the comparison tells the middle from the ends"
                );
            }
        }
    }
    Ok(())
}
