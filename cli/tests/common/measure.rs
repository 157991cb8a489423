//! Running the CLI as a child and measuring it: exit status, stderr, wall time and peak
//! resident memory (`VmHWM` from `/proc/<pid>/status`, sampled every 2 ms; 0 where `/proc` is
//! missing). A child still running at the deadline is killed and reported with no exit code.

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one run of the CLI did.
#[derive(Debug)]
pub(crate) struct Outcome {
    /// The exit code; `None` when killed (by the deadline or a signal).
    pub(crate) code: Option<i32>,
    /// Everything it wrote to stderr.
    pub(crate) stderr: String,
    /// Wall-clock seconds.
    pub(crate) secs: f64,
    /// Peak resident memory in KiB, as last sampled.
    pub(crate) peak_kib: u64,
}

/// The CLI binary under test.
pub(crate) fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_crmorph"))
}

/// Runs the CLI with `args`, killing it after `deadline_secs`.
pub(crate) fn run(args: &[String], deadline_secs: f64) -> Outcome {
    let mut cmd = bin();
    cmd.args(args);
    run_command(cmd, deadline_secs)
}

/// Runs `cmd` (stdout discarded, stderr captured), killing it after `deadline_secs`.
pub(crate) fn run_command(mut cmd: Command, deadline_secs: f64) -> Outcome {
    let started = Instant::now();
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the CLI starts");
    let mut pipe = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = pipe.read_to_string(&mut s);
        s
    });
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    let status = loop {
        peak = peak.max(vm_hwm(&status_file).unwrap_or(0));
        if let Some(status) = child.try_wait().expect("wait for the CLI") {
            break Some(status);
        }
        if started.elapsed().as_secs_f64() > deadline_secs {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Outcome {
        code: status.and_then(|s| s.code()),
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
