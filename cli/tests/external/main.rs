//! Tests that need a program outside Rust: headless Chromium and Firefox (what a browser shows),
//! librsvg (the other SVG renderer of the four crmorph's SVG must render alike in), Node (the
//! HTML preview's script) and the Lottie players and schema of `tools/lottie` (npm).
//!
//! This binary has its own harness (libtest-mimic) so that a missing program is reported as what
//! it is: each test that needs it is listed as `ignored`, and one note per program says how to
//! enable it. A plain `cargo test` on a machine without a browser or Node therefore passes
//! with visible skips, not silent passes. `.ci/run` installs the programs and sets
//! `CRMORPH_REQUIRE_TOOLS=1`, which turns a missing program into a failing test.

mod browser;
mod lottie;
mod node;
mod renderers;
mod tools;

use libtest_mimic::{Arguments, Trial};

fn main() {
    let args = Arguments::from_args();
    let mut trials = Vec::new();
    trials.extend(browser::trials());
    trials.extend(node::trials());
    trials.extend(lottie::trials());
    trials.extend(renderers::trials());
    libtest_mimic::run(&args, trials).exit();
}

/// A trial that needs `tool`: run when it was found, else ignored (or, when tools are required,
/// a failure naming what is missing).
pub(crate) fn needing(
    name: &str,
    tool: &tools::Found,
    run: impl Fn(&std::path::Path) -> Result<(), String> + Send + Sync + 'static,
) -> Trial {
    match tool {
        tools::Found::Yes(t) => {
            let t = t.clone();
            Trial::test(name, move || run(&t).map_err(Into::into))
        }
        tools::Found::Missing(why) if tools::required() => {
            let why = why.clone();
            Trial::test(name, move || {
                Err(format!("CRMORPH_REQUIRE_TOOLS is set but {why}").into())
            })
        }
        tools::Found::Missing(_) => Trial::test(name, || Ok(())).with_ignored_flag(true),
    }
}
