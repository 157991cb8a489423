//! Every SVG crmorph writes renders alike in resvg, librsvg, Chromium and Firefox (DESIGN §4):
//! single frames (a marked-up drawing's cross-dissolve, automatic mode's morphing paths over
//! dissolved detail, gradients) are rendered by each renderer over white and compared with
//! crmorph's own PNG of the same frame; the animated SVG's static values — what a viewer without
//! SMIL (librsvg, resvg, thumbnailers) shows — are compared with the source drawing rendered by
//! the same renderer; and the animated SVG paused in Firefox shows crmorph's frames.
//!
//! Tolerance, as for the Chromium tests: a mean difference of at most 2 of 255 and at most 1 %
//! of pixels off by more than 32 (antialiasing differs between renderers; a missing layer, a
//! half-transparent frame or a frame from the wrong time exceeds it by far).

use std::path::{Path, PathBuf};
use std::process::Command;

use libtest_mimic::Trial;
use tiny_skia::Pixmap;

use crate::{needing, tools};

pub(crate) fn trials() -> Vec<Trial> {
    let rsvg = tools::rsvg(2);
    let firefox = tools::firefox(2);
    let chrome = tools::chromium(1);
    vec![
        Trial::test("renderers::frames_render_alike_in_resvg", || {
            frames_alike(Renderer::Resvg).map_err(Into::into)
        }),
        Trial::test(
            "renderers::animated_svg_base_is_the_source_in_resvg",
            || base_is_source(Renderer::Resvg).map_err(Into::into),
        ),
        needing("renderers::frames_render_alike_in_librsvg", &rsvg, |p| {
            frames_alike(Renderer::Rsvg(p))
        }),
        needing(
            "renderers::animated_svg_base_is_the_source_in_librsvg",
            &rsvg,
            |p| base_is_source(Renderer::Rsvg(p)),
        ),
        needing("renderers::frames_render_alike_in_firefox", &firefox, |p| {
            frames_alike(Renderer::Firefox(p))
        }),
        needing(
            "renderers::animated_svg_paused_in_firefox_shows_crmorphs_frames",
            &firefox,
            paused_in_firefox,
        ),
        needing("renderers::frames_render_alike_in_chromium", &chrome, |p| {
            frames_alike(Renderer::Chromium(p))
        }),
    ]
}

/// Where an SVG document is rendered.
#[derive(Clone, Copy)]
enum Renderer<'a> {
    Resvg,
    Rsvg(&'a Path),
    Firefox(&'a Path),
    Chromium(&'a Path),
}

impl Renderer<'_> {
    fn name(&self) -> &'static str {
        match self {
            Renderer::Resvg => "resvg",
            Renderer::Rsvg(_) => "librsvg",
            Renderer::Firefox(_) => "Firefox",
            Renderer::Chromium(_) => "Chromium",
        }
    }

    /// `svg` (a file) rendered at `size` over white, optionally with a script run first (the
    /// browsers only): the pixels.
    fn render(
        &self,
        svg: &Path,
        size: (u32, u32),
        script: &str,
        work: &Path,
    ) -> Result<Pixmap, String> {
        let out = work.join(format!(
            "{}-{}.png",
            svg.file_stem().unwrap().to_string_lossy(),
            self.name()
        ));
        match self {
            Renderer::Resvg => {
                let text = std::fs::read_to_string(svg).map_err(|e| e.to_string())?;
                let tree = usvg::Tree::from_str(&text, &usvg::Options::default())
                    .map_err(|e| e.to_string())?;
                let mut px = white(size);
                let sx = size.0 as f32 / tree.size().width();
                let sy = size.1 as f32 / tree.size().height();
                resvg::render(
                    &tree,
                    tiny_skia::Transform::from_scale(sx, sy),
                    &mut px.as_mut(),
                );
                return Ok(px);
            }
            Renderer::Rsvg(bin) => {
                let o = Command::new(bin)
                    .args(["-w", &size.0.to_string(), "-h", &size.1.to_string()])
                    .args(["-b", "white", "-o"])
                    .arg(&out)
                    .arg(svg)
                    .output()
                    .map_err(|e| e.to_string())?;
                if !o.status.success() {
                    return Err(String::from_utf8_lossy(&o.stderr).into_owned());
                }
            }
            Renderer::Firefox(bin) | Renderer::Chromium(bin) => {
                let text = std::fs::read_to_string(svg).map_err(|e| e.to_string())?;
                let page = work.join(format!(
                    "{}-{}.html",
                    svg.file_stem().unwrap().to_string_lossy(),
                    self.name()
                ));
                let html = format!(
                    "<!doctype html><html><head><style>html,body{{margin:0;padding:0;\
                     background:#fff;overflow:hidden}}svg{{display:block;width:{}px;height:{}px}}\
                     </style></head><body>{text}<script>{script}</script></body></html>",
                    size.0, size.1
                );
                std::fs::write(&page, html).map_err(|e| e.to_string())?;
                let profile = tempfile::tempdir().map_err(|e| e.to_string())?;
                let mut cmd = Command::new(bin);
                if matches!(self, Renderer::Firefox(_)) {
                    cmd.args(["--headless", "--no-remote", "--profile"])
                        .arg(profile.path())
                        .arg(format!("--window-size={},{}", size.0, size.1))
                        .arg("--screenshot")
                        .arg(&out);
                } else {
                    crate::tools::chromium_screenshot(&mut cmd, profile.path(), size, &out);
                }
                let o = cmd
                    .arg(format!("file://{}", page.display()))
                    .output()
                    .map_err(|e| e.to_string())?;
                if !out.exists() {
                    return Err(format!(
                        "{} wrote no screenshot: {}",
                        self.name(),
                        String::from_utf8_lossy(&o.stderr)
                    ));
                }
            }
        }
        let px = Pixmap::load_png(&out).map_err(|e| e.to_string())?;
        Ok(on_white(&px))
    }
}

fn white(size: (u32, u32)) -> Pixmap {
    let mut p = Pixmap::new(size.0, size.1).unwrap();
    p.fill(tiny_skia::Color::WHITE);
    p
}

/// `p` composited over white.
fn on_white(p: &Pixmap) -> Pixmap {
    let mut w = white((p.width(), p.height()));
    w.draw_pixmap(
        0,
        0,
        p.as_ref(),
        &tiny_skia::PixmapPaint::default(),
        tiny_skia::Transform::identity(),
        None,
    );
    w
}

/// (mean difference, share of pixels off by more than 32) on RGB.
fn difference(a: &Pixmap, b: &Pixmap) -> Result<(f64, f64), String> {
    if (a.width(), a.height()) != (b.width(), b.height()) {
        return Err(format!(
            "sizes differ: {}×{} and {}×{}",
            a.width(),
            a.height(),
            b.width(),
            b.height()
        ));
    }
    let (mut sum, mut over) = (0.0, 0usize);
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        let (p, q) = (p.demultiply(), q.demultiply());
        let d = p
            .red()
            .abs_diff(q.red())
            .max(p.green().abs_diff(q.green()))
            .max(p.blue().abs_diff(q.blue()));
        sum += d as f64;
        over += (d > 32) as usize;
    }
    let n = a.pixels().len() as f64;
    Ok((sum / n, over as f64 / n))
}

fn alike(what: &str, got: &Pixmap, want: &Pixmap) -> Result<(), String> {
    let (mean, over) = difference(got, want)?;
    eprintln!("{what}: mean {mean:.3}, >32 {over:.5}");
    if mean <= 2.0 && over <= 0.01 {
        Ok(())
    } else {
        Err(format!("{what}: differs: mean {mean:.3}, >32 {over:.5}"))
    }
}

fn crmorph(args: &[&std::ffi::OsStr]) -> Result<(), String> {
    let o = Command::new(env!("CARGO_BIN_EXE_crmorph"))
        .args(args)
        .arg("--quiet")
        .output()
        .map_err(|e| e.to_string())?;
    if o.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

fn fixture(name: &str) -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let dir = if name == "gourd" {
        root.join("gourd")
    } else {
        root.join("icons").join(name)
    };
    (dir.join("source.svg"), dir.join("target.svg"))
}

/// The pairs and sizes the frames are checked on: a marked-up drawing, automatic mode with a
/// dissolved detail, automatic mode with gradients.
const PAIRS: [(&str, (u32, u32)); 3] = [
    ("gourd", (400, 400)),
    ("badge-minus-to-dots", (192, 192)),
    ("gradient-badge", (192, 192)),
];

/// Frames at t = 0.3 and 0.5 written as SVG, rendered by `r`, against crmorph's PNG.
fn frames_alike(r: Renderer<'_>) -> Result<(), String> {
    let work = tempfile::tempdir().map_err(|e| e.to_string())?;
    for (name, size) in PAIRS {
        let (s, t) = fixture(name);
        for at in [0.3, 0.5] {
            let svg = work.path().join(format!("{name}-{at}.svg"));
            let png = work.path().join(format!("{name}-{at}.png"));
            let at_s = at.to_string();
            let sz = format!("{}x{}", size.0, size.1);
            for out in [&svg, &png] {
                crmorph(&[
                    "frame".as_ref(),
                    s.as_os_str(),
                    t.as_os_str(),
                    "--at".as_ref(),
                    at_s.as_ref(),
                    "--size".as_ref(),
                    sz.as_ref(),
                    "--background".as_ref(),
                    "white".as_ref(),
                    "-o".as_ref(),
                    out.as_os_str(),
                ])?;
            }
            let want = Pixmap::load_png(&png).map_err(|e| e.to_string())?;
            let got = r.render(&svg, size, "", work.path())?;
            alike(&format!("{name} at t = {at} in {}", r.name()), &got, &want)?;
        }
    }
    Ok(())
}

/// The animated SVG as a viewer without SMIL shows it is the source drawing: both rendered by
/// `r` (at twice the drawings' size, where rounding would show).
fn base_is_source(r: Renderer<'_>) -> Result<(), String> {
    let work = tempfile::tempdir().map_err(|e| e.to_string())?;
    for (name, size) in PAIRS {
        let (s, t) = fixture(name);
        let anim = work.path().join(format!("{name}-anim.svg"));
        crmorph(&[
            "morph".as_ref(),
            s.as_os_str(),
            t.as_os_str(),
            "-o".as_ref(),
            anim.as_os_str(),
        ])?;
        // Strip the animations for renderers that would play them; resvg and librsvg ignore
        // SMIL anyway, so what they draw is the static values.
        let size = (size.0 * 2, size.1 * 2);
        let got = r.render(&anim, size, "", work.path())?;
        let want = r.render(&s, size, "", work.path())?;
        alike(
            &format!("{name}'s animated SVG without SMIL in {}", r.name()),
            &got,
            &want,
        )?;
    }
    Ok(())
}

/// The animated SVG paused in Firefox at t ∈ {0.37, 0.8} shows crmorph's frames there.
fn paused_in_firefox(bin: &Path) -> Result<(), String> {
    let work = tempfile::tempdir().map_err(|e| e.to_string())?;
    let (s, t) = fixture("gourd");
    let anim = work.path().join("gourd-anim.svg");
    crmorph(&[
        "morph".as_ref(),
        s.as_os_str(),
        t.as_os_str(),
        "-o".as_ref(),
        anim.as_os_str(),
        "--duration".as_ref(),
        "2".as_ref(),
        "--size".as_ref(),
        "400x400".as_ref(),
    ])?;
    for at in [0.37, 0.8] {
        let png = work.path().join(format!("gourd-{at}.png"));
        let at_s = at.to_string();
        crmorph(&[
            "frame".as_ref(),
            s.as_os_str(),
            t.as_os_str(),
            "--at".as_ref(),
            at_s.as_ref(),
            "--size".as_ref(),
            "400x400".as_ref(),
            "--background".as_ref(),
            "white".as_ref(),
            "-o".as_ref(),
            png.as_os_str(),
        ])?;
        let want = Pixmap::load_png(&png).map_err(|e| e.to_string())?;
        let script = format!(
            "const s=document.querySelector('svg');s.pauseAnimations();s.setCurrentTime({});",
            at * 2.0
        );
        let copy = work.path().join(format!("gourd-anim-{at}.svg"));
        std::fs::copy(&anim, &copy).map_err(|e| e.to_string())?;
        let got = Renderer::Firefox(bin).render(&copy, (400, 400), &script, work.path())?;
        alike(
            &format!("animated SVG paused in Firefox at t = {at}"),
            &got,
            &want,
        )?;
    }
    Ok(())
}
