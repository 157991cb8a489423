//! `crmorph batch`: many pairs morphed in parallel, for icon sets and design systems
//! (docs/batch.md).
//!
//! The pairs come from a manifest or two folders ([`manifest`]); `--shard I/N` keeps one part
//! of them ([`shard`]); each pair is morphed exactly as `crmorph morph` does
//! ([`crate::commands::morph_pair`], with a silent progress that keeps its notes), on a rayon
//! pool of `--jobs` threads, a failure or even a panic of one pair becoming a `failed` row of
//! the report ([`report`]) while the others go on. Pairs whose output is up to date are
//! skipped.

pub(crate) mod manifest;
pub(crate) mod report;
pub(crate) mod shard;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::{ArgGroup, Args, ValueEnum};
use rayon::prelude::*;

use crate::commands::{
    Inputs, Look, MethodArg, MorphArgs, Reading, Shapes, Steering, Timing, Usage,
};
use crate::progress::Progress;
use manifest::{Pair, Pairing};
use report::{Journal, Row, Status, Timings};
use shard::Shard;

/// The report's file name when `--report` is not given.
const REPORT_NAME: &str = "batch-report.jsonl";

/// `crmorph batch`: morph many pairs, from a manifest or two folders.
#[derive(Debug, Clone, Args)]
#[command(group(ArgGroup::new("pairs").required(true).args(["manifest", "pairs_from"])))]
pub(crate) struct BatchArgs {
    /// The pairs: a CSV file with a header row `source,target,output`, or JSON lines
    /// (`.jsonl`, `.ndjson`) of {"source":…,"target":…,"output":…}; paths are relative to the
    /// manifest's folder and each output's extension picks its format.
    pub(crate) manifest: Option<PathBuf>,
    /// Pair the drawings (.svg, .svgz) of two folders instead: files of the same name, each
    /// output named like them in --out-dir (or, with --all-pairs, every source with every
    /// target).
    #[arg(long, num_args = 2, value_names = ["SRC_DIR", "TGT_DIR"], requires = "out_dir")]
    pub(crate) pairs_from: Option<Vec<PathBuf>>,
    /// With --pairs-from: every source with every target, each output named `SRC-to-TGT.EXT`
    /// (a file not with itself when both folders are one).
    #[arg(long, requires = "pairs_from")]
    pub(crate) all_pairs: bool,
    /// With --pairs-from: the folder the outputs are written into (created if missing).
    #[arg(long, value_name = "DIR", requires = "pairs_from")]
    pub(crate) out_dir: Option<PathBuf>,
    /// With --pairs-from: the outputs' format.
    #[arg(long, value_enum, default_value_t = BatchFormat::Svg, requires = "pairs_from")]
    pub(crate) format: BatchFormat,
    /// The report (JSON lines, one row per pair). Default: batch-report.jsonl in --out-dir, or
    /// beside the manifest; with --shard I/N it is named batch-report.I-of-N.jsonl.
    #[arg(long, value_name = "FILE")]
    pub(crate) report: Option<PathBuf>,
    /// Pairs morphed at once (default: the number of cores).
    #[arg(
        long,
        short = 'j',
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..=1024),
        allow_hyphen_values = true
    )]
    pub(crate) jobs: Option<u32>,
    /// Morph every pair again, even those whose output is up to date.
    #[arg(long)]
    pub(crate) force: bool,
    /// Run shard I of N (1-based): the pairs at positions k (from 0) with k mod N = I − 1.
    #[arg(long, value_name = "I/N", value_parser = clap::value_parser!(Shard))]
    pub(crate) shard: Option<Shard>,
    #[command(flatten)]
    pub(crate) reading: Reading,
    /// Interpolation method.
    #[arg(long, value_enum, default_value_t = MethodArg::Disc)]
    pub(crate) method: MethodArg,
    #[command(flatten)]
    pub(crate) timing: Timing,
    #[command(flatten)]
    pub(crate) look: Look,
}

/// `--format` of folder mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum BatchFormat {
    /// Animated SVG.
    Svg,
    /// GIF.
    Gif,
    /// Animated PNG.
    Png,
    /// HTML preview page.
    Html,
    /// Every frame's mesh.
    Json,
}

impl BatchFormat {
    fn extension(self) -> &'static str {
        match self {
            BatchFormat::Svg => "svg",
            BatchFormat::Gif => "gif",
            BatchFormat::Png => "png",
            BatchFormat::Html => "html",
            BatchFormat::Json => "json",
        }
    }
}

/// Runs `batch`: every pair (of the shard), the report, and a one-line summary on stderr; an
/// error (exit status 1) when a pair failed.
pub(crate) fn run(a: &BatchArgs, progress: &Progress) -> Result<()> {
    let (pairs, report_dir) = gather(a, progress)?;
    let report_path = report::shard_path(
        &a.report
            .clone()
            .unwrap_or_else(|| report_dir.join(REPORT_NAME)),
        a.shard,
    );
    if let Some(p) = pairs.iter().find(|p| {
        [&p.source, &p.target, &p.output]
            .iter()
            .any(|f| same_path(f, &report_path))
    }) {
        return Err(Usage(format!(
            "{}: the report would overwrite a file of the pair at {}; use --report",
            report_path.display(),
            p.origin
        ))
        .into());
    }
    let selected = shard::select(&pairs, a.shard);
    let options = report::fingerprint(&format!(
        "{:?} {:?} {:?} {:?}",
        a.reading, a.method, a.timing, a.look
    ));
    if let Some(dir) = report_path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    }
    let previous = report::previous(&report_path);
    let template = template(a);
    let journal = Journal::open(&report_path)?;
    let jobs = match a.jobs {
        Some(n) => n as usize,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .context("cannot start the worker threads")?;
    progress.stage("morphing");
    progress.pairs(selected.len() as u64);
    let tick = progress.frame_counter(selected.len() as u64, "writing the report");
    let rows: Vec<Row> = pool.install(|| {
        selected
            .par_iter()
            .map(|&(index, pair)| {
                let prev = previous.get(&shown(&pair.output));
                let mut row = run_pair(pair, &template, &options, prev, a.force);
                row.index = index;
                // A journal line lost (a full disk) only costs a resumed run this pair.
                let _ = journal.append(&row);
                tick();
                row
            })
            .collect()
    });
    progress.frames_done();
    journal.finish(&rows)?;
    let count = |s| rows.iter().filter(|r| r.status == s).count();
    let (ok, skipped, failed) = (
        count(Status::Ok),
        count(Status::Skipped),
        count(Status::Failed),
    );
    let summary = format!(
        "{ok} ok, {skipped} skipped, {failed} failed; report: {}",
        report_path.display()
    );
    if failed > 0 {
        bail!(summary);
    }
    progress.finish();
    eprintln!("{summary}");
    Ok(())
}

/// The pairs of the manifest or of the two folders, and the default report's folder.
fn gather(a: &BatchArgs, progress: &Progress) -> Result<(Vec<Pair>, PathBuf)> {
    if let Some(m) = &a.manifest {
        let dir = m.parent().unwrap_or(Path::new("")).to_path_buf();
        return Ok((manifest::read(m)?, dir));
    }
    let (Some(dirs), Some(out_dir)) = (&a.pairs_from, &a.out_dir) else {
        bail!("internal error: clap let through a batch with no pairs");
    };
    let pairing = if a.all_pairs {
        Pairing::All
    } else {
        Pairing::ByName
    };
    let (pairs, unpaired) =
        manifest::from_folders(&dirs[0], &dirs[1], pairing, out_dir, a.format.extension())?;
    if !unpaired.is_empty() {
        let names: Vec<String> = unpaired
            .iter()
            .take(3)
            .map(|p| p.display().to_string())
            .collect();
        let more = match unpaired.len() {
            n if n > 3 => format!(", … ({n} in all)"),
            _ => String::new(),
        };
        progress.note(&format!(
            "no file of the same name in the other folder: {}{more}",
            names.join(", ")
        ));
    }
    if pairs.is_empty() {
        bail!(
            "{} and {}: no pairs (no drawings{})",
            dirs[0].display(),
            dirs[1].display(),
            if a.all_pairs { "" } else { " of the same name" }
        );
    }
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("{}: cannot create the folder", out_dir.display()))?;
    Ok((pairs, out_dir.clone()))
}

/// The `crmorph morph` arguments every pair shares (its own files go in for each pair); no
/// poses and no frames folder, which belong to one pair.
fn template(a: &BatchArgs) -> MorphArgs {
    MorphArgs {
        inputs: Inputs {
            source: PathBuf::new(),
            target: PathBuf::new(),
            output: PathBuf::new(),
            controls: None,
            reading: a.reading.clone(),
        },
        method: a.method,
        timing: a.timing.clone(),
        look: a.look.clone(),
        steering: Steering::default(),
        frames_dir: None,
        frame_format: Default::default(),
    }
}

/// A path as the report shows it.
fn shown(p: &Path) -> String {
    p.display().to_string()
}

/// Whether two paths name the same file (or are equal, when either does not exist).
fn same_path(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

fn ms(d: Duration) -> u64 {
    d.as_millis() as u64
}

/// What measuring a finished pair found.
struct Measured {
    shapes: Shapes,
    setup: Duration,
    render: Duration,
    check: Duration,
    inverted: u64,
    frames: usize,
}

/// Morphs one pair (unless up to date) and measures it: its report row, never a panic.
fn run_pair(
    pair: &Pair,
    template: &MorphArgs,
    options: &str,
    previous: Option<&Row>,
    force: bool,
) -> Row {
    let started = Instant::now();
    let (source, target, output) = (
        shown(&pair.source),
        shown(&pair.target),
        shown(&pair.output),
    );
    if !force && report::up_to_date(&pair.source, &pair.target, &pair.output, previous, options) {
        // The previous run's figures still describe the output.
        let prev = previous.cloned().unwrap_or_default();
        return Row {
            source,
            target,
            output,
            status: Status::Skipped,
            error: None,
            timings: None,
            options: options.to_string(),
            ..prev
        };
    }
    let mut args = template.clone();
    args.inputs.source = pair.source.clone();
    args.inputs.target = pair.target.clone();
    args.inputs.output = pair.output.clone();
    let progress = Progress::capturing();
    let outcome = catch_unwind(AssertUnwindSafe(|| measure(pair, &args, &progress)));
    let mut row = Row {
        source,
        target,
        output,
        notes: progress.take_notes(),
        options: options.to_string(),
        ..Row::default()
    };
    match outcome {
        Ok(Ok(m)) => {
            row.status = Status::Ok;
            row.timings = Some(Timings {
                setup_ms: ms(m.setup),
                render_ms: ms(m.render),
                check_ms: ms(m.check),
                total_ms: ms(started.elapsed()),
            });
            match m.shapes.auto {
                Some(c) => {
                    row.mode = Some("auto".into());
                    row.shapes = Some(c.shapes);
                    row.lone = Some(c.lone);
                    row.blended = Some(c.blended);
                    row.crisp = Some(c.shapes > 0 && m.shapes.morphing > 0 && c.blended == 0);
                }
                None => {
                    // The boundary and feature curves hold the artwork in correspondence.
                    row.mode = Some("marked".into());
                    row.crisp = Some(true);
                }
            }
            row.morphing = Some(m.shapes.morphing);
            row.inverted_triangles = Some(m.inverted);
            row.frames_checked = Some(m.frames);
        }
        Ok(Err(e)) => {
            row.error = Some(crmorph::error::printable_line(&format!("{e:#}")));
        }
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            row.error = Some(crmorph::error::printable_line(&format!(
                "internal error: {msg} (please report this with the input files)"
            )));
        }
    }
    row
}

/// Morphs the pair of `args` into its output (its folder created if missing) and counts the
/// inverted triangles of its frames.
fn measure(pair: &Pair, args: &MorphArgs, progress: &Progress) -> Result<Measured> {
    if let Some(dir) = pair.output.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
        }
    }
    let m = crate::commands::morph_pair(args, progress)?;
    let checking = Instant::now();
    let frames = m.morph.vertex_frames(&m.timeline);
    let triangles = &m.morph.meshes().triangles;
    let inverted = frames
        .iter()
        .map(|v| crmorph::quality::inverted_triangles(triangles, v) as u64)
        .sum();
    Ok(Measured {
        shapes: m.shapes,
        setup: m.setup,
        render: m.render,
        check: checking.elapsed(),
        inverted,
        frames: frames.len(),
    })
}
