//! The HTML preview's script, run by Node against a stand-in for the few browser objects it
//! touches: it parses, and its slider scrubs the SMIL clock and redraws the mesh overlay.

use std::path::Path;

use crmorph::export::{preview_html, Playback, PreviewMesh, Timeline};
use crmorph::Point;
use libtest_mimic::Trial;

use crate::{needing, tools};

pub(crate) fn trials() -> Vec<Trial> {
    let node = tools::node(2);
    vec![
        needing("node::preview_script_parses", &node, script_parses),
        needing(
            "node::preview_slider_scrubs_and_redraws_the_mesh",
            &node,
            slider_scrubs,
        ),
        needing("node::preview_keys_step_one_frame", &node, keys_step_frames),
    ]
}

const SVG: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
    xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"200\" height=\"100\" viewBox=\"0 0 200 100\">\
    <path d=\"M0 0H10V10Z\"><animate attributeName=\"d\" dur=\"2s\" values=\"M0 0H10V10Z;M0 0H20V20Z\"/></path></svg>\n";

/// A square of two triangles drifting right by 10 over `n` frames.
fn mesh_frames(n: usize) -> Vec<Vec<Point>> {
    (0..n)
        .map(|i| {
            let dx = 10.0 * i as f64 / (n - 1) as f64;
            [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
                .iter()
                .map(|&(x, y)| Point::new(x + dx, y + 0.123456))
                .collect()
        })
        .collect()
}

fn page(n: usize, playback: Playback) -> String {
    let frames = mesh_frames(n);
    let tris = [[0, 1, 2], [0, 2, 3]];
    let tl = Timeline {
        frames: n,
        playback,
        ..Timeline::default()
    };
    let mesh = PreviewMesh {
        triangles: &tris,
        frames: &frames,
        precision: 0.01,
        extra_edges: &[],
    };
    preview_html("m", SVG, &tl, &mesh)
}

fn script_of(p: &str) -> Result<&str, String> {
    let start = p.find("<script>\n").ok_or("the page has no <script>")? + 9;
    let end = p.find("</script>").ok_or("the page has no </script>")?;
    Ok(&p[start..end])
}

/// Runs `js` with Node (`--check` only parses it): (success, stdout + stderr).
fn run(node: &Path, js: &str, check_only: bool) -> Result<(bool, String), String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let file = dir.path().join("page.js");
    std::fs::write(&file, js).map_err(|e| e.to_string())?;
    let mut cmd = std::process::Command::new(node);
    if check_only {
        cmd.arg("--check");
    }
    let out = cmd.arg(&file).output().map_err(|e| e.to_string())?;
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    Ok((out.status.success(), text))
}

fn script_parses(node: &Path) -> Result<(), String> {
    let p = page(40, Playback::Once);
    match run(node, script_of(&p)?, true)? {
        (true, _) => Ok(()),
        (false, msg) => Err(format!("node --check rejected the page script: {msg}")),
    }
}

/// A stand-in for the browser objects the script touches, enough to drive it from Node: a
/// paused SMIL clock, elements with attributes, and event listeners.
const FAKE_DOM: &str = r##"
function El(id) { this.id = id; this.attrs = {}; this.style = {}; this.handlers = {};
  this.value = "0"; this.checked = false; this.disabled = false; this.textContent = ""; }
El.prototype.setAttribute = function (k, v) { this.attrs[k] = String(v); };
El.prototype.addEventListener = function (k, f) { this.handlers[k] = f; };
El.prototype.fire = function (k, key) { this.handlers[k]({ type: k, key: key,
  preventDefault: function () { this.prevented = true; } }); };
var svg = new El("svg"); svg.namespaceURI = "ns"; svg.children = []; svg.clock = 0.7;
svg.paused = false;
svg.appendChild = function (c) { this.children.push(c); };
svg.pauseAnimations = function () { this.paused = true; };
svg.unpauseAnimations = function () { this.paused = false; };
svg.setCurrentTime = function (s) { this.clock = s; };
svg.getCurrentTime = function () { return this.clock; };
var els = {};
["crmorph-play", "crmorph-time", "crmorph-t", "crmorph-mesh"].forEach(function (id) {
  els[id] = new El(id); });
var document = { querySelector: function () { return svg; },
  getElementById: function (id) { return els[id]; },
  createElementNS: function () { return new El("path"); } };
var requestAnimationFrame = function () {};
"##;

/// What the harness prints after driving the page: `label|d|button|paused|clock|effect`.
const DRIVE: &str = r##"
els["crmorph-mesh"].checked = true;
els["crmorph-mesh"].fire("change");
els["crmorph-time"].value = "0.5";
els["crmorph-time"].fire("input");
var o = svg.children[0];
console.log([els["crmorph-t"].textContent, o.attrs.d, els["crmorph-play"].textContent,
  svg.paused, svg.clock, o.attrs["vector-effect"]].join("|"));
"##;

fn slider_scrubs(node: &Path) -> Result<(), String> {
    // Timeline: 2 s; the slider at 0.5 sets the SVG clock to 1 s and pauses it.
    let p = page(100, Playback::Loop);
    let js = format!("{FAKE_DOM}{}{DRIVE}", script_of(&p)?);
    let (ok, out) = run(node, &js, false)?;
    if !ok {
        return Err(out);
    }
    let f: Vec<&str> = out.trim().split('|').collect();
    if f.len() != 6 || f[0] != "t = 0.500" || f[2..] != ["Play", "true", "1", "non-scaling-stroke"]
    {
        return Err(format!("unexpected page state: {out}"));
    }
    // The square moved halfway (dx = 5), its y offset rounded to the 0.01 step.
    let d = f[1];
    if d.matches('M').count() != 5 || !d.starts_with("M5 0.12L15 0.12") {
        return Err(format!("unexpected overlay path: {d}"));
    }
    Ok(())
}

/// What the harness prints after pressing keys on the slider: `t` after each press, then
/// whether playback is paused.
const KEYS: &str = r##"
var out = [];
["ArrowRight", "ArrowRight", "ArrowLeft", "End", "ArrowRight", "PageDown", "Home", "ArrowLeft"]
  .forEach(function (k) {
    els["crmorph-time"].fire("keydown", k);
    out.push(els["crmorph-t"].textContent.slice(4) + "@" + svg.clock.toFixed(4));
  });
console.log(out.join(" ") + "|" + svg.paused);
"##;

fn keys_step_frames(node: &Path) -> Result<(), String> {
    // 5 frames over 2 s: one key press is a quarter of the morph, 0.5 s; Page Down is a tenth
    // of the frames rounded up to one; the ends clamp. The page starts playing at 0.7 s
    // (frame 1.4, so the first press lands on frame 2) and a key press pauses it.
    let p = page(5, Playback::Once);
    let js = format!("{FAKE_DOM}{}{KEYS}", script_of(&p)?);
    let (ok, out) = run(node, &js, false)?;
    if !ok {
        return Err(out);
    }
    let want = "0.500@1.0000 0.750@1.5000 0.500@1.0000 1.000@2.0000 1.000@2.0000 \
                0.750@1.5000 0.000@0.0000 0.000@0.0000|true";
    if out.trim() != want {
        return Err(format!("key steps: got {}, want {want}", out.trim()));
    }
    Ok(())
}
