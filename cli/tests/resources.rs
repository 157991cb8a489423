//! Issue 12, huge output and interruption, as a user meets them: a drawing too large to
//! rasterize is a prompt one-line error (row 4), memory stays flat as `--frames` grows (row 7),
//! and a signal or a kill leaves no temporary behind (row 8). Every run is timed and its peak
//! memory read from `/proc` while it runs.

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(p)
}

fn gourd() -> [PathBuf; 2] {
    [fixture("gourd/source.svg"), fixture("gourd/target.svg")]
}

#[path = "common/measure.rs"]
mod measure;

use measure::{spawn, Outcome as Run};

/// Waits for `child` (no deadline a test should meet: a minute).
fn finish(child: Child, start: Instant) -> Run {
    measure::watch(child, start, 60.0)
}

fn run<S: AsRef<OsStr>>(args: &[S]) -> Run {
    measure::run(args, 60.0)
}

/// Command-line arguments of any string or path type, owned.
fn argv(items: &[&dyn AsRef<OsStr>]) -> Vec<OsString> {
    items.iter().map(|a| a.as_ref().to_owned()).collect()
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A crmorph temporary (`.crmorph-…`) in `dir`, if any.
fn temporary_in(dir: &Path) -> Option<String> {
    listing(dir)
        .into_iter()
        .find(|n| n.starts_with(".crmorph-"))
}

/// Sends `signal` (a name for kill(1): TERM, INT, KILL) to `pid`.
fn signal(pid: u32, signal: &str) {
    let ok = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(pid.to_string())
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill -{signal} {pid}");
}

/// Row 4: a drawing whose own size is 100000 × 100000 px is refused before any pixmap is
/// allocated, for every raster output, in one line naming the drawing and `--max-pixels`.
#[test]
fn a_drawing_too_large_to_rasterize_is_a_prompt_one_line_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let svg = |corner: &str| {
        format!(
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="100000" height="100000" viewBox="0 0 200 200"><path id="boundary" d="M20 20 L{corner} L170 170 L30 160 Z" fill="#4a8"/></svg>"##
        )
    };
    let (src, tgt) = (d.join("huge.svg"), d.join("huge2.svg"));
    std::fs::write(&src, svg("180 30")).unwrap();
    std::fs::write(&tgt, svg("185 40")).unwrap();
    let inputs = listing(d);
    let frames = d.join("frames");
    let cases = [
        argv(&[&"morph", &src, &tgt, &"-o", &d.join("m.png")]),
        argv(&[&"morph", &src, &tgt, &"-o", &d.join("m.gif")]),
        argv(&[
            &"morph",
            &src,
            &tgt,
            &"-o",
            &d.join("m.svg"),
            &"--frames-dir",
            &frames,
            &"--frame-format",
            &"png",
        ]),
        argv(&[
            &"frame",
            &src,
            &tgt,
            &"--at",
            &"0.5",
            &"-o",
            &d.join("f.png"),
        ]),
        // The inspect picture at a width whose height goes over a lowered limit.
        argv(&[
            &"inspect",
            &src,
            &tgt,
            &"-o",
            &d.join("i.png"),
            &"--width",
            &"4000",
            &"--max-pixels",
            &"1000000",
        ]),
    ];
    for args in cases {
        let r = run(&args);
        let err = r.stderr.clone();
        let what = format!("{args:?}");
        assert_eq!(r.code, Some(1), "{what}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
        assert!(
            err.contains("--max-pixels") && err.contains("huge.svg"),
            "{what}: {err}"
        );
        assert!(r.secs < 5.0, "{what}: {} s", r.secs);
        assert!(r.peak_mib() < 1024, "{what}: {} MiB", r.peak_mib());
        assert_eq!(listing(d), inputs, "{what}: nothing left behind");
    }
    // Raising the limit is the way out: the same inspect picture is written.
    let r = run(&argv(&[
        &"inspect",
        &src,
        &tgt,
        &"-o",
        &d.join("i.png"),
        &"--width",
        &"400",
    ]));
    assert!((r.code == Some(0)), "{}", r.stderr);
}

/// Row 7: frames are rendered and encoded a chunk at a time, so the peak memory of a GIF, an
/// APNG and a `--frames-dir` of 600 frames is that of 60 frames (before, every frame was
/// kept: 600 frames of 96² took 30 MB more than 60).
#[test]
fn memory_stays_flat_as_frames_grow() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let [src, tgt] = gourd();
    for (ext, frame_format) in [("gif", None), ("png", None), ("gif", Some("png"))] {
        let what = format!("{ext} {frame_format:?}");
        let peak = |frames: &str| {
            let out = d.join(format!("m.{ext}"));
            let frames_dir = d.join(format!("frames-{frames}"));
            // A long duration keeps every frame shown (no frame is skipped for a short delay).
            let mut args = argv(&[
                &"morph",
                &src,
                &tgt,
                &"-o",
                &out,
                &"--frames",
                &frames,
                &"--duration",
                &"100",
                &"--size",
                &"96x96",
            ]);
            if let Some(ff) = frame_format {
                args.extend(argv(&[
                    &"--frames-dir",
                    &frames_dir,
                    &"--frame-format",
                    &ff,
                ]));
            }
            let r = run(&args);
            assert!((r.code == Some(0)), "{what}: {}", r.stderr);
            assert!(r.secs < 20.0, "{what} {frames}: {} s", r.secs);
            r.peak_mib()
        };
        let (small, large) = (peak("60"), peak("600"));
        println!("{what}: 60 frames {small} MiB, 600 frames {large} MiB");
        assert!(small > 0, "peak memory read from /proc");
        assert!(
            large < small + 12,
            "{what}: 60 frames {small} MiB, 600 frames {large} MiB"
        );
        assert!(temporary_in(d).is_none(), "{:?}", listing(d));
    }
}

/// Spawns a slow morph writing into `dir` and waits until its temporary (`.crmorph-…`)
/// appears; returns the child and the temporary's name.
fn slow_morph_in(dir: &Path, extra: &[&str]) -> (Child, Instant, String) {
    let [src, tgt] = gourd();
    let mut args = argv(&[
        &"morph",
        &src,
        &tgt,
        &"-o",
        &dir.join("m.gif"),
        &"--frames",
        &"3000",
        &"--duration",
        &"100",
    ]);
    args.extend(extra.iter().map(OsString::from));
    let start = Instant::now();
    let mut child = spawn(&args);
    loop {
        if let Some(t) = temporary_in(dir) {
            return (child, start, t);
        }
        if start.elapsed() > Duration::from_secs(20) || child.try_wait().unwrap().is_some() {
            let _ = child.kill();
            let out = finish(child, start);
            panic!("no temporary appeared: {:?}, {}", listing(dir), out.stderr);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Row 8: SIGTERM or SIGINT while the output (or the `--frames-dir` staging folder) is being
/// written removes the temporary and exits with 143 or 130, promptly.
#[test]
fn a_signal_mid_write_leaves_no_temporary() {
    for (sig, code, extra) in [
        ("TERM", 143, &[][..]),
        ("INT", 130, &[][..]),
        (
            "TERM",
            143,
            &["--frames-dir", "frames", "--frame-format", "svg"][..],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let extra: Vec<String> = extra
            .iter()
            .map(|a| match *a {
                "frames" => d.join("frames").display().to_string(),
                a => a.to_string(),
            })
            .collect();
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let (child, _, tmp) = slow_morph_in(d, &extra);
        let sent = Instant::now();
        signal(child.id(), sig);
        let r = finish(child, sent);
        let what = format!("SIG{sig} {extra:?} during {tmp}");
        assert_eq!(r.code, Some(code), "{what}: {}", r.stderr);
        assert!(r.secs < 5.0, "{what}: {} s to stop", r.secs);
        assert!(r.peak_mib() < 1024, "{what}: {} MiB", r.peak_mib());
        assert_eq!(listing(d), Vec::<String>::new(), "{what}: left behind");
    }
}

/// Row 8: a SIGKILL leaves the temporary (nothing can remove it then), named with the dead
/// process's id, and the next run writing into that folder removes it; temporaries of live
/// processes and other files stay.
#[test]
fn temporaries_left_by_a_kill_are_removed_by_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (child, _, tmp) = slow_morph_in(d, &[]);
    let pid = child.id();
    assert!(tmp.contains(&format!("-{pid}-")), "{tmp} names the process");
    signal(pid, "KILL");
    let r = finish(child, Instant::now());
    assert_eq!(r.code, None, "killed");
    assert!(listing(d).contains(&tmp), "SIGKILL leaves {tmp}");
    // A staging folder a killed run left, and a temporary of a live process (this test's).
    let stale_dir = d.join(".crmorph-frames-999999999-abcdef");
    std::fs::create_dir(&stale_dir).unwrap();
    std::fs::write(stale_dir.join("frame_000.svg"), b"<svg/>").unwrap();
    let live = format!(".crmorph-{}-abcdef.tmp", std::process::id());
    std::fs::write(d.join(&live), b"").unwrap();
    std::fs::write(d.join("notes.txt"), b"").unwrap();

    let [src, tgt] = gourd();
    let r = run(&argv(&[
        &"morph",
        &src,
        &tgt,
        &"-o",
        &d.join("m.gif"),
        &"--frames",
        &"4",
        &"--size",
        &"32x32",
    ]));
    assert!((r.code == Some(0)), "{}", r.stderr);
    assert!(r.secs < 10.0, "{} s", r.secs);
    assert_eq!(listing(d), [live.as_str(), "m.gif", "notes.txt"]);
}
