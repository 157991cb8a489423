//! `crmorph batch` as a user meets it: manifests and folders, the report, failures that do not
//! stop the batch, resuming, shards, and outputs identical to `crmorph morph`'s.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, SystemTime};

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_crmorph"))
}

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(p)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `crmorph batch ARGS` in `dir` with few frames.
fn batch(dir: &Path, args: &[&str]) -> Output {
    bin()
        .current_dir(dir)
        .arg("batch")
        .args(args)
        .args(["--frames", "4", "--quiet"])
        .output()
        .unwrap()
}

/// The rows of a JSON-lines report.
fn read_rows(path: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn statuses(rows: &[Value]) -> Vec<String> {
    rows.iter()
        .map(|r| r["status"].as_str().unwrap().to_string())
        .collect()
}

/// A folder `in/` of small drawings, made an hour old so that outputs are newer: four
/// unmarked icons and the marked-up U and S.
fn drawings(root: &Path) -> PathBuf {
    let dir = root.join("in");
    std::fs::create_dir_all(&dir).unwrap();
    for (from, to) in [
        ("icons/heart-to-star/source.svg", "heart.svg"),
        ("icons/heart-to-star/target.svg", "star.svg"),
        ("icons/circle-to-square/source.svg", "circle.svg"),
        ("icons/circle-to-square/target.svg", "square.svg"),
        ("u-to-s/source.svg", "u.svg"),
        ("u-to-s/target.svg", "s.svg"),
    ] {
        std::fs::copy(fixture(from), dir.join(to)).unwrap();
        set_mtime(&dir.join(to), SystemTime::now() - Duration::from_secs(3600));
    }
    dir
}

fn set_mtime(p: &Path, t: SystemTime) {
    std::fs::File::options()
        .write(true)
        .open(p)
        .unwrap()
        .set_modified(t)
        .unwrap();
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

const CSV: &str = "source,target,output\n\
                   in/heart.svg,in/star.svg,out/heart-star.svg\n\
                   \"in/u.svg\",\"in/s.svg\",\"out/u, s.gif\"\n\
                   in/circle.svg,in/square.svg,out/circle-square.svg\n";

#[test]
fn a_csv_manifest_runs_every_pair_and_reports_them_in_order() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    std::fs::write(root.path().join("pairs.csv"), CSV).unwrap();
    let o = batch(root.path(), &["pairs.csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = root.path().join("batch-report.jsonl");
    assert!(
        stderr(&o).contains("3 ok, 0 skipped, 0 failed; report: batch-report.jsonl"),
        "{}",
        stderr(&o)
    );
    let rows = read_rows(&report);
    let outputs: Vec<&str> = rows.iter().map(|r| r["output"].as_str().unwrap()).collect();
    assert_eq!(
        outputs,
        [
            "out/heart-star.svg",
            "out/u, s.gif",
            "out/circle-square.svg"
        ]
    );
    assert_eq!(statuses(&rows), ["ok", "ok", "ok"]);
    let gif = std::fs::read(root.path().join("out/u, s.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a"));
    // The unmarked heart and star: automatic mode, one shape morphs, nothing cross-fades.
    let r = &rows[0];
    assert_eq!(r["mode"], "auto");
    assert_eq!(
        (r["shapes"].as_u64(), r["blended"].as_u64()),
        (Some(1), Some(0))
    );
    assert_eq!(r["crisp"], true);
    assert!(r["notes"][0].as_str().unwrap().contains("automatic mode"));
    assert_eq!(r["frames_checked"], 4);
    assert_eq!(r["inverted_triangles"], 0);
    assert!(r["error"].is_null());
    let t = &r["timings"];
    assert!(t["total_ms"].as_u64().unwrap() >= t["setup_ms"].as_u64().unwrap());
    // The marked-up U and S.
    assert_eq!(rows[1]["mode"], "marked");
    assert_eq!(rows[1]["crisp"], true);
    assert!(rows[1]["shapes"].is_null());
    assert_eq!(rows[1]["options"], rows[0]["options"]);
}

#[test]
fn a_json_lines_manifest_runs_with_paths_relative_to_its_folder() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    let sub = root.path().join("jobs");
    std::fs::create_dir(&sub).unwrap();
    std::fs::write(
        sub.join("pairs.jsonl"),
        "{\"source\":\"../in/star.svg\",\"target\":\"../in/heart.svg\",\"output\":\"a.json\"}\n\
         \n\
         {\"output\":\"b.html\",\"source\":\"../in/square.svg\",\"target\":\"../in/circle.svg\"}\n",
    )
    .unwrap();
    // Run from elsewhere: the manifest's folder anchors its paths and the report.
    let o = batch(root.path(), &["jobs/pairs.jsonl", "--jobs", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_rows(&sub.join("batch-report.jsonl"));
    assert_eq!(statuses(&rows), ["ok", "ok"]);
    let frames: Value =
        serde_json::from_slice(&std::fs::read(sub.join("a.json")).unwrap()).unwrap();
    assert!(frames.is_object() || frames.is_array());
    let html = std::fs::read_to_string(sub.join("b.html")).unwrap();
    assert!(html.contains("<html") || html.contains("<!DOCTYPE"));
}

#[test]
fn folders_pair_by_name_or_every_source_with_every_target() {
    let root = tempfile::tempdir().unwrap();
    let input = drawings(root.path());
    let (light, dark) = (root.path().join("light"), root.path().join("dark"));
    for d in [&light, &dark] {
        std::fs::create_dir(d).unwrap();
    }
    for (name, l, d) in [
        ("a.svg", "heart.svg", "star.svg"),
        ("b.svg", "circle.svg", "square.svg"),
    ] {
        std::fs::copy(input.join(l), light.join(name)).unwrap();
        std::fs::copy(input.join(d), dark.join(name)).unwrap();
    }
    std::fs::copy(input.join("u.svg"), light.join("only-light.svg")).unwrap();
    let o = batch(
        root.path(),
        &[
            "--pairs-from",
            "light",
            "dark",
            "--out-dir",
            "out",
            "--format",
            "png",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_rows(&root.path().join("out/batch-report.jsonl"));
    let outputs: Vec<&str> = rows.iter().map(|r| r["output"].as_str().unwrap()).collect();
    assert_eq!(outputs, ["out/a.png", "out/b.png"]);
    assert_eq!(rows[0]["source"], "light/a.svg");
    assert_eq!(rows[0]["target"], "dark/a.svg");
    let png = std::fs::read(root.path().join("out/a.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));

    // Every source with every target of one folder: a file never with itself.
    let o = batch(
        root.path(),
        &[
            "--pairs-from",
            "dark",
            "dark",
            "--all-pairs",
            "--out-dir",
            "all",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_rows(&root.path().join("all/batch-report.jsonl"));
    let outputs: Vec<&str> = rows.iter().map(|r| r["output"].as_str().unwrap()).collect();
    assert_eq!(outputs, ["all/a-to-b.svg", "all/b-to-a.svg"]);
    assert!(root.path().join("all/b-to-a.svg").is_file());

    // Outputs into an input folder would be inputs of the next run.
    let o = batch(
        root.path(),
        &["--pairs-from", "light", "dark", "--out-dir", "dark"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn a_failing_pair_is_a_failed_row_and_the_others_still_run() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    std::fs::copy(
        fixture("errors/truncated.svg"),
        root.path().join("in/bad.svg"),
    )
    .unwrap();
    std::fs::write(
        root.path().join("pairs.csv"),
        "source,target,output\n\
         in/heart.svg,in/star.svg,out/1.svg\n\
         in/bad.svg,in/star.svg,out/2.svg\n\
         in/circle.svg,in/square.svg,out/3.svg\n\
         in/u.svg,in/s.svg,in/u.svg\n",
    )
    .unwrap();
    let u = std::fs::read(root.path().join("in/u.svg")).unwrap();
    let o = batch(root.path(), &["pairs.csv"]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(
        err.trim_end(),
        "error: 2 ok, 0 skipped, 2 failed; report: batch-report.jsonl"
    );
    let rows = read_rows(&root.path().join("batch-report.jsonl"));
    assert_eq!(statuses(&rows), ["ok", "failed", "ok", "failed"]);
    let e = rows[1]["error"].as_str().unwrap();
    assert!(e.contains("bad.svg") && !e.contains('\n'), "{e}");
    assert!(rows[1]["crisp"].is_null() && rows[1]["timings"].is_null());
    assert!(!root.path().join("out/2.svg").exists());
    assert!(root.path().join("out/3.svg").is_file());
    // No pair overwrites its input.
    let e = rows[3]["error"].as_str().unwrap();
    assert!(e.contains("refusing to overwrite an input file"), "{e}");
    assert_eq!(std::fs::read(root.path().join("in/u.svg")).unwrap(), u);
    // No temporary left behind.
    let names: Vec<String> = std::fs::read_dir(root.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
}

#[test]
fn a_second_run_skips_up_to_date_outputs_and_reruns_touched_or_changed_ones() {
    let root = tempfile::tempdir().unwrap();
    let input = drawings(root.path());
    std::fs::write(root.path().join("pairs.csv"), CSV).unwrap();
    let report = root.path().join("batch-report.jsonl");
    let out = |name: &str| root.path().join("out").join(name);
    assert!(batch(root.path(), &["pairs.csv"]).status.success());
    let first = read_rows(&report);
    let before = mtime(&out("heart-star.svg"));

    let o = batch(root.path(), &["pairs.csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 ok, 3 skipped, 0 failed"),
        "{}",
        stderr(&o)
    );
    let second = read_rows(&report);
    assert_eq!(statuses(&second), ["skipped", "skipped", "skipped"]);
    assert_eq!(
        mtime(&out("heart-star.svg")),
        before,
        "a skipped output is not written"
    );
    // A skipped row keeps what the run that made the output measured.
    assert_eq!(second[0]["crisp"], first[0]["crisp"]);
    assert_eq!(second[0]["notes"], first[0]["notes"]);
    assert!(second[0]["timings"].is_null());

    // A touched input re-runs its pairs only.
    set_mtime(&input.join("square.svg"), SystemTime::now());
    let rows3 = {
        assert!(batch(root.path(), &["pairs.csv"]).status.success());
        read_rows(&report)
    };
    assert_eq!(statuses(&rows3), ["skipped", "skipped", "ok"]);

    // Other options re-run every pair; --force too.
    let o = bin()
        .current_dir(root.path())
        .args(["batch", "pairs.csv", "--frames", "5", "--quiet"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let rows4 = read_rows(&report);
    assert_eq!(statuses(&rows4), ["ok", "ok", "ok"]);
    assert_ne!(rows4[0]["options"], first[0]["options"]);
    assert!(mtime(&out("heart-star.svg")) > before);
    let o = bin()
        .current_dir(root.path())
        .args(["batch", "pairs.csv", "--frames", "5", "--quiet"])
        .output()
        .unwrap();
    assert!(stderr(&o).contains("0 ok, 3 skipped"), "{}", stderr(&o));
    let o = bin()
        .current_dir(root.path())
        .args(["batch", "pairs.csv", "--frames", "5", "--quiet", "--force"])
        .output()
        .unwrap();
    assert!(stderr(&o).contains("3 ok, 0 skipped"), "{}", stderr(&o));
}

#[test]
fn shards_partition_the_batch_and_write_their_own_reports() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    // Seven pairs: every ordered pair of the unmarked icons but a few.
    let names = ["heart", "star", "circle", "square"];
    let mut csv = String::from("source,target,output\n");
    let mut all = Vec::new();
    for s in names {
        for t in names {
            if s != t && all.len() < 7 {
                let out = format!("out/{s}-{t}.svg");
                csv.push_str(&format!("in/{s}.svg,in/{t}.svg,{out}\n"));
                all.push(out);
            }
        }
    }
    std::fs::write(root.path().join("pairs.csv"), csv).unwrap();
    let mut seen: Vec<String> = Vec::new();
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let o = batch(root.path(), &["pairs.csv", "--shard", &shard]);
        assert!(o.status.success(), "{shard}: {}", stderr(&o));
        let report = root.path().join(format!("batch-report.{i}-of-3.jsonl"));
        let rows = read_rows(&report);
        let part: Vec<String> = rows
            .iter()
            .map(|r| r["output"].as_str().unwrap().to_string())
            .collect();
        // Each row knows its place in the whole batch, to merge the shards' reports in order.
        for (r, out) in rows.iter().zip(&part) {
            let k = all.iter().position(|o| o == out).unwrap();
            assert_eq!(r["index"].as_u64(), Some(k as u64));
        }
        // Pair k (from 0) is in shard k mod 3 + 1.
        let expected: Vec<String> = all.iter().skip(i - 1).step_by(3).cloned().collect();
        assert_eq!(part, expected, "{shard}");
        seen.extend(part);
    }
    assert!(!root.path().join("batch-report.jsonl").exists());
    seen.sort();
    let mut sorted = all.clone();
    sorted.sort();
    assert_eq!(seen, sorted, "every pair in exactly one shard");
    for out in &all {
        assert!(root.path().join(out).is_file(), "{out}");
    }
}

#[test]
fn a_batch_output_is_byte_identical_to_crmorph_morph() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    std::fs::write(
        root.path().join("pairs.jsonl"),
        "{\"source\":\"in/u.svg\",\"target\":\"in/s.svg\",\"output\":\"b/us.gif\"}\n\
         {\"source\":\"in/heart.svg\",\"target\":\"in/star.svg\",\"output\":\"b/hs.svg\"}\n",
    )
    .unwrap();
    let options = [
        "--frames",
        "4",
        "--size",
        "48x48",
        "--easing",
        "ease-in-out",
        "--background",
        "#fa0",
        "--density",
        "1.5",
    ];
    let o = bin()
        .current_dir(root.path())
        .args(["batch", "pairs.jsonl", "--quiet"])
        .args(options)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for (s, t, name) in [("u", "s", "us.gif"), ("heart", "star", "hs.svg")] {
        let single = root.path().join(format!("single-{name}"));
        let o = bin()
            .current_dir(root.path())
            .args([
                "morph",
                &format!("in/{s}.svg"),
                &format!("in/{t}.svg"),
                "-o",
            ])
            .arg(&single)
            .args(options)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            std::fs::read(root.path().join("b").join(name)).unwrap(),
            std::fs::read(&single).unwrap(),
            "{name}"
        );
    }
}

#[test]
fn bad_shards_are_usage_errors() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    std::fs::write(root.path().join("pairs.csv"), CSV).unwrap();
    for bad in ["0/3", "4/3", "1/0", "two/3", "3"] {
        let o = batch(root.path(), &["pairs.csv", "--shard", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        assert!(stderr(&o).contains("--shard"), "{bad}: {}", stderr(&o));
    }
    assert!(!root.path().join("out").exists());
}

#[test]
fn a_malformed_manifest_is_one_error_naming_the_file_and_line_before_any_work() {
    let root = tempfile::tempdir().unwrap();
    drawings(root.path());
    let cases: [(&str, &str, &str); 4] = [
        (
            "pairs.csv",
            "source,target,output\nin/heart.svg,in/star.svg,out/a.svg\n\nin/u.svg,in/s.svg\n",
            "error: pairs.csv:4: 2 fields, but the header has 3",
        ),
        (
            "pairs.csv",
            "source,target,output\nin/heart.svg,in/star.svg,out/a.svg\nin/u.svg,in/missing.svg,out/b.svg\n",
            "error: pairs.csv:3: target 'in/missing.svg' (in/missing.svg): no such file",
        ),
        (
            "pairs.jsonl",
            "{\"source\":\"in/heart.svg\",\"target\":\"in/star.svg\",\"output\":\"out/a.svg\"}\n{\"source\":\"in/u.svg\",\"target\":\"in/s.svg\"}\n",
            "error: pairs.jsonl:2: missing field `output`",
        ),
        (
            "pairs.jsonl",
            "{\"source\":\"in/heart.svg\",\"target\":\"in/star.svg\",\"output\":\"out/a.svg\"}\n{\"source\": \n",
            "error: pairs.jsonl:2: EOF while parsing",
        ),
    ];
    for (name, text, expected) in cases {
        std::fs::write(root.path().join(name), text).unwrap();
        let o = batch(root.path(), &[name]);
        assert_eq!(o.status.code(), Some(1), "{expected}");
        let err = stderr(&o);
        assert!(err.starts_with(expected), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(!root.path().join("out").exists(), "no pair ran: {expected}");
        assert!(!root.path().join("batch-report.jsonl").exists());
    }
    // An output that another pair reads: what it reads would depend on which runs first.
    std::fs::write(
        root.path().join("pairs.csv"),
        "source,target,output\nin/heart.svg,in/star.svg,in/circle.svg\nin/circle.svg,in/square.svg,out/b.svg\n",
    )
    .unwrap();
    let o = batch(root.path(), &["pairs.csv"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o).trim_end(),
        "error: pairs.csv:2: output 'in/circle.svg' is an input of the pair at pairs.csv:3"
    );
    let o = batch(root.path(), &["missing.csv"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).starts_with("error: missing.csv: cannot read"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn inverted_triangles_are_counted_over_the_frames() {
    let root = tempfile::tempdir().unwrap();
    let (s, t) = (
        fixture("leaf-to-butterfly/source.svg"),
        fixture("leaf-to-butterfly/target.svg"),
    );
    std::fs::write(
        root.path().join("pairs.csv"),
        format!(
            "source,target,output\n{},{},leaf.svg\n",
            s.display(),
            t.display()
        ),
    )
    .unwrap();
    let mut counts = Vec::new();
    for method in ["disc", "linear"] {
        let o = batch(root.path(), &["pairs.csv", "--force", "--method", method]);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
        let rows = read_rows(&root.path().join("batch-report.jsonl"));
        assert_eq!(rows[0]["frames_checked"], 4);
        counts.push(rows[0]["inverted_triangles"].as_u64().unwrap());
    }
    // The rigid interpolation inverts nothing here; the linear baseline does (paper §4.1).
    assert_eq!(counts[0], 0);
    assert!(counts[1] > 0, "{counts:?}");
}
