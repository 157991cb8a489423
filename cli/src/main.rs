//! `crmorph`: morph one SVG drawing into another, rigidly, with interior features aligned.
//!
//! Exit status: 0 on success, 1 on bad input (one line `error: …` naming the file, the element id
//! and the problem), 2 on bad usage. Outputs are written atomically.

mod batch;
mod commands;
mod demo;
mod docs;
mod interrupt;
mod output;
mod policy;
mod progress;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use commands::{FrameArgs, InitArgs, InspectArgs, MorphArgs, SkeletonArgs, Usage};
use docs::{CompletionsArgs, ManArgs};
use progress::Progress;

/// The markup conventions, shown after `crmorph --help` (docs/conventions.md has the details).
const CONVENTIONS: &str = "\
Marking up a drawing (control geometry is found by element id):
  boundary          the shape's closed outline (default: the viewBox rectangle)
  feature-NAME      a feature curve inside it, matched by NAME in the other file
  anchor-NAME       a point pinning the nearest curve points of the two files together
  skeleton[-NAME]   source only: polylines whose vertices are joints (for --pose)
  <g id=\"controls\"> guides inside this group are never drawn
Rename them with --boundary-id, --feature-prefix and --skeleton-id. Two files with neither a
boundary nor a feature curve morph in automatic mode: filled shapes and strokes pair with
those of the other file, each pair on its own compatible triangulation.

Shell completions: crmorph completions bash|zsh|fish|elvish|powershell
Manual page:       crmorph man [COMMAND]";

/// crmorph morphs one SVG drawing into another the way an animator would: rigidly, with interior
/// feature curves kept aligned (CR-Morph). With no command, it morphs the bundled demo into
/// ./crmorph-demo/.
#[derive(Debug, Parser)]
#[command(
    name = "crmorph",
    version,
    about,
    long_about = None,
    propagate_version = true,
    after_help = CONVENTIONS
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Show no progress on stderr.
    #[arg(long, short, global = true)]
    quiet: bool,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Morph SRC into TGT; the output's extension picks the format: .svg (animated), .gif, .png
    /// (APNG), .html (preview), .lottie.json (Lottie), .lottie (dotLottie), .json (every
    /// frame's mesh).
    Morph(MorphArgs),
    /// One frame at time T: .png or .svg (the rendered frame) or .json (the mesh at T).
    Frame(FrameArgs),
    /// The compatible triangulations side by side (.svg/.png) or the meshes (.json).
    Inspect(InspectArgs),
    /// The derived skeleton at time T drawn over that frame (.svg), to edit into a --pose file.
    Skeleton(SkeletonArgs),
    /// An image (PNG, JPEG, GIF, WebP) as an SVG to draw controls on: the image embedded, its
    /// boundary (the image rectangle, or the outline of its opaque pixels) in a hidden
    /// `controls` group where feature-NAME curves go.
    Init(InitArgs),
    /// Morph many pairs in parallel, from a manifest (CSV or JSON lines) or two folders, with
    /// a JSON-lines report; pairs whose output is up to date are skipped (docs/batch.md).
    Batch(batch::BatchArgs),
    /// Print a shell completion script to stdout, e.g. `crmorph completions bash >
    /// ~/.local/share/bash-completion/completions/crmorph`.
    Completions(CompletionsArgs),
    /// Print the manual page (roff) to stdout, e.g. `crmorph man | man -l -`; with a COMMAND,
    /// that command's page.
    Man(ManArgs),
}

fn run(cli: &Cli) -> anyhow::Result<()> {
    // Without the handler a signal still stops the run, only leaving its temporary behind.
    let _ = interrupt::install();
    let progress = Progress::new(cli.quiet);
    let r = match &cli.command {
        None => demo::run(std::path::Path::new("crmorph-demo"), &progress).map(|s| println!("{s}")),
        Some(Command::Morph(a)) => commands::morph(a, &progress),
        Some(Command::Frame(a)) => commands::frame(a, &progress),
        Some(Command::Inspect(a)) => commands::inspect(a, &progress),
        Some(Command::Skeleton(a)) => commands::skeleton(a, &progress),
        Some(Command::Init(a)) => commands::init(a),
        Some(Command::Batch(a)) => batch::run(a, &progress),
        Some(Command::Completions(a)) => docs::completions(a, &mut std::io::stdout().lock()),
        Some(Command::Man(a)) => docs::man(a, &mut std::io::stdout().lock()),
    };
    progress.finish();
    r
}

fn main() -> ExitCode {
    let cli = Cli::parse(); // exits with status 2 on bad usage
                            // A panic is a bug in crmorph: report it as one line, never as a backtrace.
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(|| run(&cli));
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            // One line, whatever the inputs' names and ids hold (control characters escaped).
            let one_line = crmorph::error::printable_line(&format!("{e:#}"));
            eprintln!("error: {one_line}");
            if e.downcast_ref::<Usage>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            eprintln!("error: internal error: {msg} (please report this with the input files)");
            ExitCode::from(1)
        }
    }
}
