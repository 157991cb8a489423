//! What a real browser shows. The animated SVG and the HTML preview are opened in headless
//! Chromium, paused at t ∈ {0, 0.37, 1}, screenshotted, and compared with crmorph's own PNG of
//! `crmorph frame --at t` (resvg).
//!
//! Tolerance: Chromium (Skia) and resvg (tiny-skia) antialias edges differently, and Chromium
//! renders the blend filter at device resolution; measured on the gourd the mean difference is
//! about 0.4 of 255 and 0.2 % of pixels differ by more than 32. The test allows a mean of 2,
//! 1 % of pixels beyond 32 and 0.2 % beyond 64 — a frame from the wrong time, a missing blend or a
//! snapping `d` animation exceeds these by far.

use std::path::Path;
use std::process::Command;

use libtest_mimic::Trial;
use tiny_skia::Pixmap;

use crate::{needing, tools};

pub(crate) fn trials() -> Vec<Trial> {
    let chrome = tools::chromium(3);
    vec![
        needing(
            "browser::animated_svg_paused_in_chromium_shows_crmorphs_frames",
            &chrome,
            animated_svg_paused_shows_crmorphs_frames,
        ),
        needing(
            "browser::animated_svg_of_a_texture_paused_in_chromium_shows_crmorphs_frames",
            &chrome,
            animated_texture_paused_shows_crmorphs_frames,
        ),
        needing(
            "browser::html_preview_slider_scrubs_to_crmorphs_frames",
            &chrome,
            html_preview_slider_scrubs_to_crmorphs_frames,
        ),
    ]
}

const SIZE: (u32, u32) = (400, 400);
const DURATION: f64 = 2.0;
const TIMES: [f64; 3] = [0.0, 0.37, 1.0];

/// Screenshots `page` at the window size `size` into a pixmap.
fn screenshot(chrome: &Path, page: &Path, size: (u32, u32), work: &Path) -> Pixmap {
    let shot = work.join(format!(
        "{}.png",
        page.file_stem().unwrap().to_string_lossy()
    ));
    let profile = tempfile::tempdir().unwrap();
    let out =
        crate::tools::chromium_screenshot(&mut Command::new(chrome), profile.path(), size, &shot)
            .arg(format!("file://{}", page.display()))
            .output()
            .expect("Chromium runs");
    assert!(
        shot.exists(),
        "Chromium wrote no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Pixmap::load_png(&shot).unwrap()
}

fn matches(shot: &Pixmap, reference: &Pixmap) -> bool {
    let (mean, over32, over64) = tools::difference(shot, reference);
    mean <= 2.0 && over32 <= 0.01 && over64 <= 0.002
}

fn assert_matches(what: &str, shot: &Pixmap, reference: &Pixmap) {
    let (mean, over32, over64) = tools::difference(shot, reference);
    eprintln!("{what}: mean {mean:.3}, >32 {over32:.5}, >64 {over64:.5}");
    assert!(
        matches(shot, reference),
        "{what}: the browser differs from crmorph's frame: mean {mean:.3}, >32 {over32:.5}, >64 {over64:.5}"
    );
}

fn crmorph(args: &[&std::ffi::OsStr]) {
    let o = Command::new(env!("CARGO_BIN_EXE_crmorph"))
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

struct Fixture {
    work: tempfile::TempDir,
    frames: Vec<Pixmap>,
}

/// The gourd morph as an animated SVG and as an HTML preview, and crmorph's PNG frames at
/// [`TIMES`], all 400×400 on white.
fn gourd(outputs: &[&str]) -> Fixture {
    fixture("gourd", outputs)
}

/// [`gourd`] for the pair in `fixtures/NAME`.
fn fixture(name: &str, outputs: &[&str]) -> Fixture {
    let work = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name);
    let (s, t) = (root.join("source.svg"), root.join("target.svg"));
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let duration = DURATION.to_string();
    let common = ["--size", &size, "--background", "white"];
    for out in outputs {
        let o = work.path().join(out);
        let mut args: Vec<&std::ffi::OsStr> = vec!["morph".as_ref(), s.as_ref(), t.as_ref()];
        args.extend(["-o".as_ref(), o.as_os_str(), "--duration".as_ref()]);
        args.push(duration.as_ref());
        args.extend(common.iter().map(std::ffi::OsStr::new));
        crmorph(&args);
    }
    let mut frames = Vec::new();
    for at in TIMES {
        let png = work.path().join(format!("frame-{at}.png"));
        let at = at.to_string();
        let mut args: Vec<&std::ffi::OsStr> = vec!["frame".as_ref(), s.as_ref(), t.as_ref()];
        args.extend(["--at".as_ref(), at.as_ref(), "-o".as_ref(), png.as_os_str()]);
        args.extend(common.iter().map(std::ffi::OsStr::new));
        crmorph(&args);
        frames.push(Pixmap::load_png(&png).unwrap());
    }
    Fixture { work, frames }
}

fn animated_svg_paused_shows_crmorphs_frames(chrome: &Path) -> Result<(), String> {
    paused_svg_shows_frames(chrome, &gourd(&["morph.svg"]))
}

/// Issue 14: an image warped through the mesh, written as clipped, moving pieces of one
/// embedded image, shows in Chromium what crmorph's own texture rasterizer draws (same
/// tolerance as the gourd).
fn animated_texture_paused_shows_crmorphs_frames(chrome: &Path) -> Result<(), String> {
    paused_svg_shows_frames(chrome, &fixture("textures/turn", &["morph.svg"]))
}

/// The animated SVG of `f`, paused at each of [`TIMES`], against crmorph's PNG frames.
fn paused_svg_shows_frames(chrome: &Path, f: &Fixture) -> Result<(), String> {
    let svg = std::fs::read_to_string(f.work.path().join("morph.svg")).unwrap();
    for (at, reference) in TIMES.iter().zip(&f.frames) {
        // The SVG inline in a bare page, its timeline paused at t · duration.
        let page = f.work.path().join(format!("svg-{at}.html"));
        let html = format!(
            "<!doctype html><html><head><style>html,body{{margin:0;padding:0;\
             background:#fff;overflow:hidden}}svg{{display:block}}</style></head><body>{svg}\
             <script>const s=document.querySelector('svg');s.pauseAnimations();\
             s.setCurrentTime({});</script></body></html>",
            at * DURATION
        );
        std::fs::write(&page, html).unwrap();
        let shot = screenshot(chrome, &page, SIZE, f.work.path());
        assert_matches(&format!("animated SVG at t = {at}"), &shot, reference);
        // The comparison tells frames apart: the middle is neither end.
        if *at == 0.37 {
            assert!(!matches(&shot, &f.frames[0]) && !matches(&shot, &f.frames[2]));
        }
    }
    Ok(())
}

fn html_preview_slider_scrubs_to_crmorphs_frames(chrome: &Path) -> Result<(), String> {
    let f = gourd(&["preview.html"]);
    let page = std::fs::read_to_string(f.work.path().join("preview.html")).unwrap();
    assert!(!page.contains("http://") || page.matches("http://").count() <= 2);
    for (at, reference) in TIMES.iter().zip(&f.frames) {
        // Drive the page as a user would — set the slider and fire its input event — then pin
        // the drawing to the window's corner at its own size and hide the chrome around it.
        let harness = format!(
            "<style>html,body{{margin:0;padding:0;background:#fff;overflow:hidden}}\
             h1,.crmorph-controls{{visibility:hidden}}\
             #crmorph-stage{{position:fixed;left:0;top:0;margin:0;padding:0;border:0;\
             border-radius:0}}\
             #crmorph-stage>svg{{width:{w}px;height:{h}px;max-width:none;max-height:none}}\
             </style><script>const s=document.getElementById('crmorph-time');\
             s.value='{at}';s.dispatchEvent(new Event('input'));</script></body>",
            w = SIZE.0,
            h = SIZE.1
        );
        let driven = page.replacen("</body>", &harness, 1);
        assert_ne!(driven, page, "the preview has a </body>");
        let path = f.work.path().join(format!("preview-{at}.html"));
        std::fs::write(&path, driven).unwrap();
        let shot = screenshot(chrome, &path, SIZE, f.work.path());
        assert_matches(&format!("HTML preview at t = {at}"), &shot, reference);
        if *at == 0.37 {
            assert!(!matches(&shot, &f.frames[0]) && !matches(&shot, &f.frames[2]));
        }
    }
    Ok(())
}
