//! The batch report: JSON lines, one object per pair in manifest order (docs/batch.md lists
//! the fields), and the resume rule that reads the previous report.
//!
//! While a batch runs, each finished pair's row is appended to the report file as one line
//! (after the rows of the previous run, which stay readable), so an interrupted batch still
//! leaves the rows that a resumed run needs; once every pair is done, the report is replaced
//! atomically by this run's rows alone, in manifest order. Reading a report, the last row of
//! an output wins and lines that do not parse (a line cut by a kill) are ignored.

use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::SystemTime;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use crate::output::write_atomic;

/// How a pair of the batch went.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum Status {
    /// Morphed and written.
    Ok,
    /// Up to date: not morphed again (see [`up_to_date`]).
    Skipped,
    /// Morphing or writing failed; `error` says why.
    #[default]
    Failed,
}

/// Where the time of one pair went, in milliseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub(crate) struct Timings {
    /// Reading both drawings, the compatible triangulation, the interpolator and binding the
    /// artwork.
    pub(crate) setup_ms: u64,
    /// Rendering the frames and writing the output.
    pub(crate) render_ms: u64,
    /// Counting the frames' inverted triangles.
    pub(crate) check_ms: u64,
    /// All of the pair, from the first read to the report row.
    pub(crate) total_ms: u64,
}

/// One pair's row of the report.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub(crate) struct Row {
    /// The pair's position in the whole batch (from 0, in manifest order, shards counted
    /// together): sorting merged shard reports by it gives the manifest's order.
    pub(crate) index: usize,
    /// The source drawing (resolved against the manifest's folder).
    pub(crate) source: String,
    /// The target drawing.
    pub(crate) target: String,
    /// The output file.
    pub(crate) output: String,
    /// How it went.
    pub(crate) status: Status,
    /// The one-line error of a failed pair.
    pub(crate) error: Option<String>,
    /// The notes `crmorph morph` would have printed (automatic mode's report, near-miss ids).
    pub(crate) notes: Vec<String>,
    /// Where the time went; `null` for a skipped pair.
    pub(crate) timings: Option<Timings>,
    /// `"auto"` (automatic mode: neither drawing marked up) or `"marked"` (a boundary or
    /// feature curves).
    pub(crate) mode: Option<String>,
    /// Automatic mode: pairs of shapes that morph into each other.
    pub(crate) shapes: Option<usize>,
    /// Automatic mode: shapes without a partner (they grow or shrink).
    pub(crate) lone: Option<usize>,
    /// Automatic mode: paths with a paired shape that still cross-fade.
    pub(crate) blended: Option<usize>,
    /// Artwork paths that morph as one path, unblended.
    pub(crate) morphing: Option<usize>,
    /// Whether the morph is crisp (docs/batch.md): automatic mode, at least one shape pair
    /// and one path morph and no paired path cross-fades; marked-up drawings, always.
    pub(crate) crisp: Option<bool>,
    /// Inverted (or collapsed) triangles summed over every frame of the timeline.
    pub(crate) inverted_triangles: Option<u64>,
    /// Frames whose triangles were checked.
    pub(crate) frames_checked: Option<usize>,
    /// The fingerprint of the options the output was made with ([`fingerprint`]).
    pub(crate) options: String,
}

/// The fingerprint of everything besides the inputs that shapes an output: crmorph's version
/// and the options, given as their `Debug` text. A CRC-32 in hex: a change detector for the
/// resume rule, not a security measure.
pub(crate) fn fingerprint(options: &str) -> String {
    let text = format!("crmorph {} {options}", env!("CARGO_PKG_VERSION"));
    format!("{:08x}", crc32fast::hash(text.as_bytes()))
}

/// The rows of a previous report at `path`, by output (the last row of an output wins); none
/// when there is no report. Lines that do not parse are ignored: the report is a cache here.
pub(crate) fn previous(path: &Path) -> HashMap<String, Row> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return HashMap::new();
    };
    text.lines()
        .filter_map(|l| serde_json::from_str::<Row>(l).ok())
        .map(|r| (r.output.clone(), r))
        .collect()
}

/// Whether the output of a pair is up to date, so that it is skipped: its previous row is `ok`
/// or `skipped` with the same options fingerprint, and the output exists and was modified
/// after both inputs.
pub(crate) fn up_to_date(
    source: &Path,
    target: &Path,
    output: &Path,
    previous: Option<&Row>,
    options: &str,
) -> bool {
    let Some(prev) = previous else {
        return false;
    };
    if prev.status == Status::Failed || prev.options != options {
        return false;
    }
    let modified = |p: &Path| -> Option<SystemTime> { std::fs::metadata(p).ok()?.modified().ok() };
    match (modified(output), modified(source), modified(target)) {
        (Some(o), Some(s), Some(t)) => o > s && o > t,
        _ => false,
    }
}

/// The report file while the batch runs: finished rows appended one line each.
pub(crate) struct Journal {
    path: PathBuf,
    file: Mutex<std::fs::File>,
}

impl Journal {
    /// Opens the report at `path` for appending (created if missing).
    pub(crate) fn open(path: &Path) -> Result<Self> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("{}: cannot open the report", path.display()))?;
        Ok(Journal {
            path: path.to_path_buf(),
            file: Mutex::new(file),
        })
    }

    /// Appends `row` as one line, in one write.
    pub(crate) fn append(&self, row: &Row) -> Result<()> {
        let mut line = serde_json::to_string(row).context("cannot encode a report row")?;
        line.push('\n');
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        file.write_all(line.as_bytes())
            .with_context(|| format!("{}: cannot write the report", self.path.display()))
    }

    /// Replaces the report with `rows` alone, atomically.
    pub(crate) fn finish(self, rows: &[Row]) -> Result<()> {
        let mut text = String::new();
        for r in rows {
            text.push_str(&serde_json::to_string(r).context("cannot encode a report row")?);
            text.push('\n');
        }
        drop(self.file);
        write_atomic(&self.path, text.as_bytes())
    }
}

/// The report of `shard` for the report path `path`: `batch-report.jsonl` becomes
/// `batch-report.3-of-8.jsonl`, so that shards never write the same file.
pub(crate) fn shard_path(path: &Path, shard: Option<crate::batch::shard::Shard>) -> PathBuf {
    let Some(shard) = shard else {
        return path.to_path_buf();
    };
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(ext) => format!("{stem}.{shard}.{}", ext.to_string_lossy()),
        None => format!("{stem}.{shard}"),
    };
    path.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::shard::Shard;

    #[test]
    fn shard_reports_have_their_own_names() {
        let p = Path::new("out/batch-report.jsonl");
        assert_eq!(shard_path(p, None), p);
        let s = Some(Shard { index: 3, count: 8 });
        assert_eq!(shard_path(p, s), Path::new("out/batch-report.3-of-8.jsonl"));
        assert_eq!(shard_path(Path::new("r"), s), Path::new("r.3-of-8"));
    }

    #[test]
    fn rows_round_trip_and_the_last_row_of_an_output_wins() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.jsonl");
        let row = |out: &str, status| Row {
            output: out.into(),
            status,
            options: "abc".into(),
            ..Row::default()
        };
        let j = Journal::open(&path).unwrap();
        j.append(&row("a.svg", Status::Failed)).unwrap();
        j.append(&row("a.svg", Status::Ok)).unwrap();
        std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .unwrap()
            .write_all(b"{\"cut\": ")
            .unwrap();
        let prev = previous(&path);
        assert_eq!(prev.len(), 1);
        assert_eq!(prev["a.svg"].status, Status::Ok);
        j.finish(&[row("b.svg", Status::Skipped)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 1);
        let v: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
        assert_eq!(v["status"], "skipped");
        assert_eq!(v["error"], serde_json::Value::Null);
        assert!(previous(&dir.path().join("none.jsonl")).is_empty());
    }

    #[test]
    fn up_to_date_needs_a_newer_output_the_same_options_and_no_failure() {
        let dir = tempfile::tempdir().unwrap();
        let (s, t, o) = (
            dir.path().join("s.svg"),
            dir.path().join("t.svg"),
            dir.path().join("o.svg"),
        );
        for p in [&s, &t, &o] {
            std::fs::write(p, "").unwrap();
        }
        let set = |p: &Path, secs: u64| {
            let time = SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(secs);
            std::fs::File::options()
                .write(true)
                .open(p)
                .unwrap()
                .set_modified(time)
                .unwrap();
        };
        set(&s, 1000);
        set(&t, 1000);
        set(&o, 2000);
        let ok = Row {
            status: Status::Ok,
            options: "f".into(),
            ..Row::default()
        };
        assert!(up_to_date(&s, &t, &o, Some(&ok), "f"));
        assert!(!up_to_date(&s, &t, &o, None, "f"));
        assert!(!up_to_date(&s, &t, &o, Some(&ok), "g"), "options changed");
        let failed = Row {
            status: Status::Failed,
            ..ok.clone()
        };
        assert!(!up_to_date(&s, &t, &o, Some(&failed), "f"));
        set(&t, 2000);
        assert!(
            !up_to_date(&s, &t, &o, Some(&ok), "f"),
            "same time: not newer"
        );
        set(&t, 3000);
        assert!(!up_to_date(&s, &t, &o, Some(&ok), "f"), "target touched");
        std::fs::remove_file(&o).unwrap();
        assert!(!up_to_date(&s, &t, &o, Some(&ok), "f"), "output gone");
    }
}
