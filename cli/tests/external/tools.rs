//! Finding the external programs, and the note printed when one is missing.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A program found on this machine, or why it was not.
#[derive(Debug, Clone)]
pub(crate) enum Found {
    Yes(PathBuf),
    Missing(String),
}

/// Whether missing programs are failures (`CRMORPH_REQUIRE_TOOLS=1`, set by `.ci/run`).
pub(crate) fn required() -> bool {
    std::env::var_os("CRMORPH_REQUIRE_TOOLS").is_some_and(|v| !v.is_empty() && v != "0")
}

/// `names` looked up on the PATH, in order.
fn on_path(names: &[&str]) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| names.iter().map(move |n| dir.join(n)))
        .find(|p| p.is_file())
}

/// Whether `program --version` runs (a binary on the PATH may be a broken stub).
fn runs(program: &Path) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Prints the one-line note for a missing program (once per program, on stderr, which cargo
/// shows for harness-less test binaries).
fn note(what: &str, tests: usize, how: &str) {
    eprintln!(
        "note: {tests} test(s) that need {what} are skipped (listed as ignored): {how}; \
         CRMORPH_REQUIRE_TOOLS=1 makes a missing program a failure"
    );
}

/// A program: `$env` if set, else the first of `names` on the PATH; `what` and `install` word
/// the note when it is missing.
fn find(env: &str, names: &[&str], what: &str, install: &str, tests: usize) -> Found {
    let found = match std::env::var_os(env) {
        Some(p) => Some(PathBuf::from(p)),
        None => on_path(names),
    };
    match found {
        Some(p) if runs(&p) => Found::Yes(p),
        other => {
            let why = match other {
                Some(p) => format!("{} does not run", p.display()),
                None => format!("no {what} was found"),
            };
            if !required() && tests > 0 {
                note(
                    what,
                    tests,
                    &format!("{why}; install it (Debian: apt-get install {install}) or set {env}=/path/to/it"),
                );
            }
            Found::Missing(why)
        }
    }
}

/// Headless Chromium: `$CRMORPH_CHROMIUM`, else `chromium`, `chromium-browser` or
/// `google-chrome` on the PATH.
pub(crate) fn chromium(tests: usize) -> Found {
    find(
        "CRMORPH_CHROMIUM",
        &["chromium", "chromium-browser", "google-chrome"],
        "headless Chromium",
        "chromium",
        tests,
    )
}

/// Node.js: `$CRMORPH_NODE`, else `node` on the PATH.
pub(crate) fn node(tests: usize) -> Found {
    find(
        "CRMORPH_NODE",
        &["node", "nodejs"],
        "Node.js",
        "nodejs",
        tests,
    )
}

/// librsvg's command line: `$CRMORPH_RSVG`, else `rsvg-convert` on the PATH.
pub(crate) fn rsvg(tests: usize) -> Found {
    find(
        "CRMORPH_RSVG",
        &["rsvg-convert"],
        "librsvg (rsvg-convert)",
        "librsvg2-bin",
        tests,
    )
}

/// Headless Firefox: `$CRMORPH_FIREFOX`, else `firefox-esr` or `firefox` on the PATH.
pub(crate) fn firefox(tests: usize) -> Found {
    find(
        "CRMORPH_FIREFOX",
        &["firefox-esr", "firefox"],
        "Firefox",
        "firefox-esr",
        tests,
    )
}

/// The arguments that make headless Chromium screenshot a page at `size` pixels into `out`,
/// with a fresh profile in `profile`: no sandbox, GPU or background network, no scrollbars, one
/// device pixel per CSS pixel. The page's URL goes last.
pub(crate) fn chromium_screenshot<'a>(
    cmd: &'a mut Command,
    profile: &Path,
    size: (u32, u32),
    out: &Path,
) -> &'a mut Command {
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--no-first-run",
        "--hide-scrollbars",
        "--force-device-scale-factor=1",
    ])
    .arg(format!("--user-data-dir={}", profile.display()))
    .arg(format!("--window-size={},{}", size.0, size.1))
    .arg(format!("--screenshot={}", out.display()))
}

/// The npm packages of `tools/lottie` (lottie-web, dotlottie-web, the Lottie schema), installed
/// by `npm ci --prefix tools/lottie`: the folder when all are there.
pub(crate) fn lottie_packages(tests: usize) -> Found {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/lottie");
    let packages = [
        "lottie-web",
        "@lottiefiles/dotlottie-web",
        "@lottie-animation-community/lottie-specs",
    ];
    let missing: Vec<&str> = packages
        .iter()
        .copied()
        .filter(|p| {
            !dir.join("node_modules")
                .join(p)
                .join("package.json")
                .is_file()
        })
        .collect();
    if missing.is_empty() {
        return Found::Yes(dir);
    }
    let why = format!("the npm packages {} were not found", missing.join(", "));
    if !required() && tests > 0 {
        note(
            "the Lottie players and schema",
            tests,
            &format!("{why}; run `npm ci --prefix tools/lottie` (needs Node.js)"),
        );
    }
    Found::Missing(why)
}

/// Every one of `found`: the first one's path when all were found, else the first missing.
pub(crate) fn all(found: &[Found]) -> Found {
    match found.iter().find(|f| matches!(f, Found::Missing(_))) {
        Some(missing) => missing.clone(),
        None => found
            .first()
            .cloned()
            .unwrap_or_else(|| Found::Missing("no program asked for".into())),
    }
}

/// (mean difference, share of pixels off by more than 32, by more than 64) of two images of
/// one size: per pixel the largest difference of the demultiplied red, green and blue.
pub(crate) fn difference(a: &tiny_skia::Pixmap, b: &tiny_skia::Pixmap) -> (f64, f64, f64) {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    let (mut sum, mut over32, mut over64) = (0.0, 0usize, 0usize);
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        let (p, q) = (p.demultiply(), q.demultiply());
        let d = [
            p.red().abs_diff(q.red()),
            p.green().abs_diff(q.green()),
            p.blue().abs_diff(q.blue()),
        ]
        .into_iter()
        .max()
        .unwrap_or(0);
        sum += d as f64;
        over32 += (d > 32) as usize;
        over64 += (d > 64) as usize;
    }
    let n = a.pixels().len().max(1) as f64;
    (sum / n, over32 as f64 / n, over64 as f64 / n)
}
