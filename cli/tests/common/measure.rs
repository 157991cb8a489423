//! Running the CLI as a child and measuring it: exit status, stderr, wall time and peak
//! resident memory (`VmHWM` from `/proc/<pid>/status`, a high-water mark sampled every 2 ms, so
//! a read shortly before the end holds the peak; 0 where `/proc` is missing). Shared by the
//! tests of hostile and huge input (`hostile.rs`, `far.rs`, `resources.rs`).

#![allow(dead_code)]

use std::ffi::OsStr;
use std::io::Read;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// What one run of the CLI did.
#[derive(Debug)]
pub(crate) struct Outcome {
    /// The exit code; `None` when killed (by a signal, or by the deadline: see `timed_out`).
    pub(crate) code: Option<i32>,
    /// Whether the deadline killed it.
    pub(crate) timed_out: bool,
    /// Everything it wrote to stderr.
    pub(crate) stderr: String,
    /// Wall-clock seconds from the start given to [`watch`].
    pub(crate) secs: f64,
    /// Peak resident memory in KiB, as last sampled.
    pub(crate) peak_kib: u64,
}

impl Outcome {
    /// Peak resident memory in MiB.
    pub(crate) fn peak_mib(&self) -> u64 {
        self.peak_kib / 1024
    }
}

/// Starts the CLI with `args`: stdin and stdout null, stderr piped for [`watch`].
pub(crate) fn spawn<S: AsRef<OsStr>>(args: &[S]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_crmorph"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the CLI starts")
}

/// Runs the CLI with `args`, killing it after `deadline_secs`.
pub(crate) fn run<S: AsRef<OsStr>>(args: &[S], deadline_secs: f64) -> Outcome {
    let started = Instant::now();
    watch(spawn(args), started, deadline_secs)
}

/// Waits for `child` (started by [`spawn`]) while sampling its memory, killing it
/// `deadline_secs` after `started`.
pub(crate) fn watch(mut child: Child, started: Instant, deadline_secs: f64) -> Outcome {
    let mut pipe = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = pipe.read_to_string(&mut s);
        s
    });
    let status_file = format!("/proc/{}/status", child.id());
    let (mut peak, mut timed_out) = (0, false);
    let status = loop {
        peak = peak.max(vm_hwm(&status_file).unwrap_or(0));
        if let Some(status) = child.try_wait().expect("wait for the CLI") {
            break Some(status);
        }
        if started.elapsed().as_secs_f64() > deadline_secs {
            let _ = child.kill();
            let _ = child.wait();
            timed_out = true;
            break None;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Outcome {
        code: status.and_then(|s| s.code()),
        timed_out,
        stderr: reader.join().unwrap_or_default(),
        secs: started.elapsed().as_secs_f64(),
        peak_kib: peak,
    }
}

/// The `VmHWM:` line of a `/proc/<pid>/status` file, in KiB.
fn vm_hwm(path: &str) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}
