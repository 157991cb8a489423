//! The pairs of a batch: read from a manifest (CSV with a `source,target,output` header, or
//! JSON lines of `{"source":…,"target":…,"output":…}`, paths relative to the manifest's
//! folder) or made from two folders (files of the same name, or every source with every
//! target). Everything is checked before any pair runs: a bad manifest is one error naming the
//! file and the line.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::commands::Usage;
use crate::output::Format;

/// Extensions of the drawings that folder mode picks up (what `crmorph morph` reads).
const DRAWING_EXTENSIONS: &[&str] = &["svg", "svgz"];

/// Largest manifest read, in bytes: a million pairs is far more than a batch needs, and the
/// cap keeps a wrong file (a video named `.csv`) from filling the memory.
const MAX_MANIFEST_BYTES: u64 = 256 << 20;

/// One pair to morph, with where it came from (for errors).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Pair {
    /// The source drawing.
    pub(crate) source: PathBuf,
    /// The target drawing.
    pub(crate) target: PathBuf,
    /// The output; its extension picks the format.
    pub(crate) output: PathBuf,
    /// Where the pair was named: `FILE:LINE` of a manifest, or the two folders' files.
    pub(crate) origin: String,
}

/// A row of a manifest as written, before its paths are resolved.
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize)]
pub(crate) struct Row {
    /// The source drawing, relative to the manifest's folder (or absolute).
    pub(crate) source: String,
    /// The target drawing.
    pub(crate) target: String,
    /// The output file.
    pub(crate) output: String,
    /// The row's line in the manifest, from 1 (not in the manifest's text).
    #[serde(skip)]
    pub(crate) line: u64,
}

/// The kinds of manifest, by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Csv,
    JsonLines,
}

impl Kind {
    fn of(path: &Path) -> Option<Kind> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(Kind::Csv),
            "jsonl" | "ndjson" => Some(Kind::JsonLines),
            _ => None,
        }
    }
}

/// Reads the manifest at `path` and resolves its rows against its folder; checks that every
/// input exists, that every output has a format `crmorph morph` writes and that no two rows
/// write the same output.
pub(crate) fn read(path: &Path) -> Result<Vec<Pair>> {
    let file = path.display().to_string();
    let Some(kind) = Kind::of(path) else {
        return Err(Usage(format!(
            "{file}: unknown manifest extension; use .csv (a source,target,output header) or \
             .jsonl/.ndjson (JSON lines)"
        ))
        .into());
    };
    let meta = std::fs::metadata(path).with_context(|| format!("{file}: cannot read"))?;
    if !meta.is_file() {
        bail!("{file}: not a file");
    }
    if meta.len() > MAX_MANIFEST_BYTES {
        bail!(
            "{file}: larger than {} MiB; split it",
            MAX_MANIFEST_BYTES >> 20
        );
    }
    let bytes = std::fs::read(path).with_context(|| format!("{file}: cannot read"))?;
    let rows = match kind {
        Kind::Csv => parse_csv(&bytes, &file)?,
        Kind::JsonLines => parse_json_lines(&bytes, &file)?,
    };
    if rows.is_empty() {
        bail!("{file}: names no pairs");
    }
    // A manifest in the working folder has the parent "": its paths stay as written.
    let dir = path.parent().unwrap_or(Path::new(""));
    let pairs = rows
        .into_iter()
        .map(|r| resolve(r, dir, &file))
        .collect::<Result<Vec<_>>>()?;
    refuse_shared_outputs(&pairs)?;
    Ok(pairs)
}

/// The rows of a CSV manifest: a header naming the columns `source`, `target` and `output` (in
/// any order, other columns ignored), then one row per pair; quoted fields allowed, blank lines
/// skipped, spaces around fields trimmed.
pub(crate) fn parse_csv(bytes: &[u8], file: &str) -> Result<Vec<Row>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(bytes);
    // The line of a record, counted here: the csv crate's positions start before the blank
    // lines that it skips.
    let line_at = |p: &csv::Position| {
        let mut end = (p.byte() as usize).min(bytes.len());
        while end < bytes.len() && matches!(bytes[end], b'\n' | b'\r') {
            end += 1;
        }
        bytes[..end].iter().filter(|&&b| b == b'\n').count() as u64 + 1
    };
    let at = |e: &csv::Error| match e.position() {
        Some(p) => format!("{file}:{}", line_at(p)),
        None => file.to_string(),
    };
    let headers = reader
        .headers()
        .map_err(|e| anyhow::anyhow!("{}: {}", at(&e), csv_problem(&e)))?
        .clone();
    let column = |name: &str| {
        headers
            .iter()
            .position(|h| h.eq_ignore_ascii_case(name))
            .with_context(|| {
                format!(
                    "{file}:1: the header has no '{name}' column (it needs source,target,output)"
                )
            })
    };
    let (s, t, o) = (column("source")?, column("target")?, column("output")?);
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| anyhow::anyhow!("{}: {}", at(&e), csv_problem(&e)))?;
        let line = record.position().map_or(0, line_at);
        let field = |i: usize, name: &str| -> Result<String> {
            match record.get(i) {
                Some(v) if !v.is_empty() => Ok(v.to_string()),
                Some(_) => bail!("{file}:{line}: the '{name}' field is empty"),
                None => bail!(
                    "{file}:{line}: {} fields, but the header has {}",
                    record.len(),
                    headers.len()
                ),
            }
        };
        rows.push(Row {
            source: field(s, "source")?,
            target: field(t, "target")?,
            output: field(o, "output")?,
            line,
        });
    }
    Ok(rows)
}

/// What is wrong in a CSV error, without the position (the caller names the line).
fn csv_problem(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".to_string(),
        csv::ErrorKind::Io(e) => format!("cannot read: {e}"),
        _ => e.to_string(),
    }
}

/// The rows of a JSON-lines manifest: one object per line with the string fields `source`,
/// `target` and `output` (other fields ignored); blank lines skipped.
pub(crate) fn parse_json_lines(bytes: &[u8], file: &str) -> Result<Vec<Row>> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        anyhow::anyhow!("{file}:{line}: not UTF-8 text")
    })?;
    let mut rows = Vec::new();
    for (k, text) in text.lines().enumerate() {
        let line = k as u64 + 1;
        if text.trim().is_empty() {
            continue;
        }
        let mut row: Row = serde_json::from_str(text).map_err(|e| {
            // serde_json ends its message with the position in the text it was given: one line.
            let msg = e.to_string();
            let msg = msg
                .rsplit_once(" at line ")
                .map_or(msg.as_str(), |(m, _)| m);
            anyhow::anyhow!("{file}:{line}: {msg} (column {})", e.column())
        })?;
        for (name, v) in [
            ("source", &row.source),
            ("target", &row.target),
            ("output", &row.output),
        ] {
            if v.is_empty() {
                bail!("{file}:{line}: the '{name}' field is empty");
            }
        }
        row.line = line;
        rows.push(row);
    }
    Ok(rows)
}

/// A manifest row's paths joined to the manifest's folder, its inputs checked to be files and
/// its output's format known.
fn resolve(r: Row, dir: &Path, file: &str) -> Result<Pair> {
    let origin = format!("{file}:{}", r.line);
    let source = dir.join(&r.source);
    let target = dir.join(&r.target);
    let output = dir.join(&r.output);
    for (name, given, p) in [
        ("source", &r.source, &source),
        ("target", &r.target, &target),
    ] {
        if !p.is_file() {
            bail!("{origin}: {name} '{given}' ({}): no such file", p.display());
        }
    }
    check_output(&output, &origin)?;
    Ok(Pair {
        source,
        target,
        output,
        origin,
    })
}

/// Refuses an output whose extension names no format `crmorph morph` writes.
fn check_output(output: &Path, origin: &str) -> Result<()> {
    match Format::of(output) {
        Some(_) => Ok(()),
        None => bail!(
            "{origin}: output '{}': unknown extension; crmorph morph writes .svg, .gif, .png, \
             .html, .json",
            output.display()
        ),
    }
}

/// Refuses two pairs that write the same output (they would overwrite each other, and the
/// resume rule keys on outputs), and an output that another pair reads (pairs run in
/// parallel: what that pair read would depend on the timing). A pair's output that is its own
/// input is refused when the pair runs, like `crmorph morph` refuses it.
fn refuse_shared_outputs(pairs: &[Pair]) -> Result<()> {
    let mut seen: HashMap<&Path, &str> = HashMap::new();
    for p in pairs {
        if let Some(first) = seen.insert(&p.output, &p.origin) {
            bail!(
                "{}: output '{}' is also written by {first}",
                p.origin,
                p.output.display()
            );
        }
    }
    // Inputs exist: compare canonical paths, and outputs that exist already likewise.
    let canonical = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let mut inputs: HashMap<PathBuf, Vec<&str>> = HashMap::new();
    for p in pairs {
        for i in [&p.source, &p.target] {
            inputs.entry(canonical(i)).or_default().push(&p.origin);
        }
    }
    for p in pairs {
        let reader = [canonical(&p.output), p.output.clone()]
            .iter()
            .filter_map(|o| inputs.get(o))
            .flatten()
            .find(|&&o| o != p.origin.as_str());
        if let Some(reader) = reader {
            bail!(
                "{}: output '{}' is an input of the pair at {reader}",
                p.origin,
                p.output.display()
            );
        }
    }
    Ok(())
}

/// How folder mode pairs the files of the two folders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pairing {
    /// Files of the same name in both folders; output `NAME.EXT`.
    ByName,
    /// Every source with every target (a file not with itself when the folders are one);
    /// output `SRC-to-TGT.EXT`.
    All,
}

/// The pairs of two folders' drawings (`.svg`, `.svgz`; hidden files skipped), sorted by the
/// source's file name, then the target's, written into `out_dir` with extension `ext`. Returns
/// the pairs and, in [`Pairing::ByName`], the files without a namesake in the other folder.
pub(crate) fn from_folders(
    src_dir: &Path,
    tgt_dir: &Path,
    pairing: Pairing,
    out_dir: &Path,
    ext: &str,
) -> Result<(Vec<Pair>, Vec<PathBuf>)> {
    let sources = drawings_in(src_dir)?;
    let targets = drawings_in(tgt_dir)?;
    let same_folder = same_dir(src_dir, tgt_dir);
    for dir in [src_dir, tgt_dir] {
        if same_dir(dir, out_dir) {
            return Err(Usage(format!(
                "--out-dir {}: is an input folder; its outputs would be inputs of the next run",
                out_dir.display()
            ))
            .into());
        }
    }
    let stem = |name: &std::ffi::OsStr| {
        Path::new(name)
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
    };
    let mut pairs = Vec::new();
    let mut unpaired = Vec::new();
    match pairing {
        Pairing::ByName => {
            for s in &sources {
                if targets.contains(s) {
                    pairs.push(Pair {
                        source: src_dir.join(s),
                        target: tgt_dir.join(s),
                        output: out_dir.join(format!("{}.{ext}", stem(s))),
                        origin: format!("{}", src_dir.join(s).display()),
                    });
                } else {
                    unpaired.push(src_dir.join(s));
                }
            }
            unpaired.extend(
                targets
                    .iter()
                    .filter(|t| !sources.contains(t))
                    .map(|t| tgt_dir.join(t)),
            );
        }
        Pairing::All => {
            for s in &sources {
                for t in &targets {
                    if same_folder && s == t {
                        continue;
                    }
                    pairs.push(Pair {
                        source: src_dir.join(s),
                        target: tgt_dir.join(t),
                        output: out_dir.join(format!("{}-to-{}.{ext}", stem(s), stem(t))),
                        origin: format!(
                            "{} × {}",
                            src_dir.join(s).display(),
                            tgt_dir.join(t).display()
                        ),
                    });
                }
            }
        }
    }
    refuse_shared_outputs(&pairs)?;
    Ok((pairs, unpaired))
}

/// The file names of the drawings in `dir`, sorted.
fn drawings_in(dir: &Path) -> Result<Vec<std::ffi::OsString>> {
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot list the folder", dir.display()))?;
    let mut names = Vec::new();
    for e in entries {
        let e = e.with_context(|| format!("{}: cannot list the folder", dir.display()))?;
        let name = e.file_name();
        let p = Path::new(&name);
        let drawing = p
            .extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| DRAWING_EXTENSIONS.contains(&x.to_ascii_lowercase().as_str()));
        let hidden = name.to_string_lossy().starts_with('.');
        if drawing && !hidden && e.path().is_file() {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// Whether two folder paths name the same folder.
fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(r: Result<Vec<Row>>) -> String {
        format!("{:#}", r.unwrap_err())
    }

    #[test]
    fn csv_rows_with_quotes_any_column_order_and_blank_lines() {
        let text = b"target, source ,output,comment\n\
                     b.svg,a.svg,out/a.svg,x\n\
                     \n\
                     \"with, comma.svg\",\"q \"\"x\"\".svg\",o.gif,\n";
        let rows = parse_csv(text, "m.csv").unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(
            (
                rows[0].source.as_str(),
                rows[0].target.as_str(),
                rows[0].line
            ),
            ("a.svg", "b.svg", 2)
        );
        assert_eq!(rows[1].source, "q \"x\".svg");
        assert_eq!(rows[1].target, "with, comma.svg");
        assert_eq!(rows[1].output, "o.gif");
        assert_eq!(rows[1].line, 4);
    }

    #[test]
    fn csv_problems_name_the_file_and_line() {
        let e = err(parse_csv(b"source,target\na,b\n", "m.csv"));
        assert_eq!(
            e,
            "m.csv:1: the header has no 'output' column (it needs source,target,output)"
        );
        let e = err(parse_csv(
            b"source,target,output\na,b,c.svg\na,b\n",
            "m.csv",
        ));
        assert_eq!(e, "m.csv:3: 2 fields, but the header has 3");
        let e = err(parse_csv(b"source,target,output\na,,c.svg\n", "m.csv"));
        assert_eq!(e, "m.csv:2: the 'target' field is empty");
        let e = err(parse_csv(b"source,target,output\na,\xff,c.svg\n", "m.csv"));
        assert!(e.starts_with("m.csv:2: "), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn json_lines_rows_and_problems() {
        let text = b"{\"source\":\"a.svg\",\"target\":\"b.svg\",\"output\":\"o.svg\",\"x\":1}\n\n\
                     {\"output\":\"p.svg\",\"target\":\"c.svg\",\"source\":\"d.svg\"}\n";
        let rows = parse_json_lines(text, "m.jsonl").unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[1].source.as_str(), rows[1].line), ("d.svg", 3));
        let e = err(parse_json_lines(
            b"{\"source\":\"a\",\"target\":\"b\",\"output\":\"o.svg\"}\n{\"source\":\"a\"}\n",
            "m.jsonl",
        ));
        assert!(e.starts_with("m.jsonl:2: missing field `target`"), "{e}");
        let e = err(parse_json_lines(b"not json\n", "m.jsonl"));
        assert!(e.starts_with("m.jsonl:1: expected"), "{e}");
        assert!(!e.contains("at line"), "{e}");
        let e = err(parse_json_lines(
            b"{\"source\":\"\",\"target\":\"b\",\"output\":\"o.svg\"}",
            "m.jsonl",
        ));
        assert_eq!(e, "m.jsonl:1: the 'source' field is empty");
        let e = err(parse_json_lines(b"\n\n\xff", "m.jsonl"));
        assert_eq!(e, "m.jsonl:3: not UTF-8 text");
    }

    #[test]
    fn manifests_resolve_against_their_folder_and_refuse_missing_inputs_and_shared_outputs() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("a.svg"), "<svg/>").unwrap();
        std::fs::write(d.join("b.svg"), "<svg/>").unwrap();
        let m = d.join("m.csv");
        std::fs::write(&m, "source,target,output\na.svg,b.svg,o.svg\n").unwrap();
        let pairs = read(&m).unwrap();
        assert_eq!(pairs[0].source, d.join("a.svg"));
        assert_eq!(pairs[0].output, d.join("o.svg"));
        assert_eq!(pairs[0].origin, format!("{}:2", m.display()));
        std::fs::write(
            &m,
            "source,target,output\na.svg,b.svg,o.svg\nb.svg,a.svg,o.svg\n",
        )
        .unwrap();
        let e = format!("{:#}", read(&m).unwrap_err());
        assert!(
            e.ends_with(":3: output '") || e.contains(":3: output"),
            "{e}"
        );
        assert!(
            e.contains("also written by") && e.contains("m.csv:2"),
            "{e}"
        );
        std::fs::write(
            &m,
            "source,target,output\na.svg,b.svg,o.svg\nb.svg,o.svg,p.svg\n",
        )
        .unwrap();
        std::fs::write(d.join("o.svg"), "<svg/>").unwrap();
        let e = format!("{:#}", read(&m).unwrap_err());
        assert!(
            e.contains("m.csv:2: output") && e.contains("input of the pair at"),
            "{e}"
        );
        assert!(e.ends_with("m.csv:3"), "{e}");
        std::fs::remove_file(d.join("o.svg")).unwrap();
        std::fs::write(&m, "source,target,output\na.svg,c.svg,o.svg\n").unwrap();
        let e = format!("{:#}", read(&m).unwrap_err());
        assert!(
            e.contains("m.csv:2: target 'c.svg'") && e.ends_with("no such file"),
            "{e}"
        );
        std::fs::write(&m, "source,target,output\na.svg,b.svg,o.txt\n").unwrap();
        let e = format!("{:#}", read(&m).unwrap_err());
        assert!(
            e.contains("m.csv:2: output") && e.contains("unknown extension"),
            "{e}"
        );
        std::fs::write(&m, "source,target,output\n").unwrap();
        let e = format!("{:#}", read(&m).unwrap_err());
        assert!(e.ends_with("m.csv: names no pairs"), "{e}");
        let e = read(&d.join("m.txt")).unwrap_err();
        assert!(e.downcast_ref::<Usage>().is_some());
    }

    #[test]
    fn folders_pair_by_name_or_all_sorted() {
        let dir = tempfile::tempdir().unwrap();
        let (s, t, o) = (
            dir.path().join("s"),
            dir.path().join("t"),
            dir.path().join("o"),
        );
        for d in [&s, &t] {
            std::fs::create_dir(d).unwrap();
        }
        for name in ["b.svg", "a.svg", "only-s.svg", "notes.txt", ".hidden.svg"] {
            std::fs::write(s.join(name), "").unwrap();
        }
        for name in ["a.svg", "b.svg", "only-t.svgz"] {
            std::fs::write(t.join(name), "").unwrap();
        }
        let (pairs, unpaired) = from_folders(&s, &t, Pairing::ByName, &o, "gif").unwrap();
        let outs: Vec<_> = pairs.iter().map(|p| p.output.clone()).collect();
        assert_eq!(outs, [o.join("a.gif"), o.join("b.gif")]);
        assert_eq!(unpaired, [s.join("only-s.svg"), t.join("only-t.svgz")]);
        let (pairs, _) = from_folders(&s, &t, Pairing::All, &o, "svg").unwrap();
        assert_eq!(pairs.len(), 9);
        assert_eq!(pairs[0].output, o.join("a-to-a.svg"));
        assert_eq!(pairs[1].output, o.join("a-to-b.svg"));
        assert_eq!(pairs[2].output, o.join("a-to-only-t.svg"));
        // One folder: every ordered pair of distinct files.
        let (pairs, _) = from_folders(&t, &t, Pairing::All, &o, "svg").unwrap();
        assert_eq!(pairs.len(), 6);
        assert!(pairs.iter().all(|p| p.source != p.target));
        let e = from_folders(&s, &t, Pairing::All, &s, "svg").unwrap_err();
        assert!(e.downcast_ref::<Usage>().is_some());
    }
}
