//! The HTML preview page (DESIGN.md §4): the animated SVG inlined in one standalone page with
//! play/pause, a time slider that scrubs the morph, and a toggle that overlays the triangulation
//! (the compatible meshes the morph interpolates, §3–§5 of the paper) as it moves.
//!
//! The page needs no network. The overlay is drawn by a small script from mesh vertex positions
//! embedded in the page: at most [`MAX_SAMPLES`] frames of the timeline, each edge once,
//! coordinates as integers of the rounding step (the first sample absolute, the others as
//! differences from the previous one, which are small for a smooth morph), interpolated
//! linearly between the two samples around the current time.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use super::{Easing, Playback, Timeline};
use crate::Point;

/// At most this many mesh samples (timeline frames) are embedded in the page.
pub const MAX_SAMPLES: usize = 31;

/// The triangulation to overlay on the preview, in the SVG's user space.
#[derive(Debug, Clone, Copy)]
pub struct PreviewMesh<'a> {
    /// The triangles (vertex indices), shared by all frames.
    pub triangles: &'a [[u32; 3]],
    /// `frames[i]`: the mesh vertices at frame `i` of the timeline (animation time
    /// `times()[i]`).
    pub frames: &'a [Vec<Point>],
    /// Rounding step of the embedded coordinates, in user units (a small fraction of the
    /// drawing's size: the overlay is a visual aid, not data).
    pub precision: f64,
    /// More segments to overlay, as pairs of indices into each frame's points: with skeleton
    /// control, the bones between joints appended after the mesh vertices (§4.2).
    pub extra_edges: &'a [[u32; 2]],
}

/// One standalone HTML page previewing the morph: `animated_svg` (an SVG document whose SMIL
/// animations start at time 0, as the animated-SVG writer produces; a leading `<?xml …?>` or
/// doctype is dropped) inlined under `title`, with controls under the drawing:
///
/// - `#crmorph-play` plays and pauses (and replays a finished [`Playback::Once`] morph);
/// - `#crmorph-time`, a slider over the forward morph (`0..1`, animation time `τ · duration`),
///   scrubs it with `pauseAnimations()` / `setCurrentTime()`; an `input` event is all it needs,
///   so a test harness can drive it without user interaction. Dragging is continuous; the
///   arrow keys step one frame of the timeline, Page Up/Down a tenth, Home/End the ends;
/// - `#crmorph-t` shows the morph's `t` (τ through the easing);
/// - `#crmorph-mesh` toggles the triangulation overlay: a thin, semi-transparent,
///   non-scaling-stroke `<path>` appended to the inline `<svg>` (in `#crmorph-stage`),
///   recomputed on every animation frame while playing and on every slider input.
///
/// Loop plays time modulo the duration, yoyo mirrors the second half of its `2 · duration`
/// period. The drawing keeps its own size but scales down to fit the window. Output is
/// deterministic (byte-identical for equal inputs).
pub fn preview_html(
    title: &str,
    animated_svg: &str,
    timeline: &Timeline,
    mesh: &PreviewMesh<'_>,
) -> String {
    let tl = timeline.sanitized();
    let title = escape_html(title);
    let mut page = String::with_capacity(animated_svg.len() + 16 * 1024);
    page.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    page.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    let _ = writeln!(page, "<title>{title}</title>");
    page.push_str(STYLE);
    page.push_str("</head>\n<body>\n");
    let _ = writeln!(page, "<h1>{title}</h1>");
    page.push_str("<div id=\"crmorph-stage\">\n");
    page.push_str(strip_prolog(animated_svg).trim_end());
    page.push_str("\n</div>\n");
    page.push_str(CONTROLS);
    page.push_str("<script>\n");
    page.push_str(&page_data(&tl, mesh));
    page.push_str(SCRIPT);
    page.push_str("</script>\n</body>\n</html>\n");
    page
}

/// `s` with `&`, `<`, `>`, `"` and `'` replaced by character references.
fn escape_html(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The SVG markup without what may precede its root element in a file but not inside HTML: a
/// byte-order mark, the XML declaration, and a doctype (with or without an internal subset).
fn strip_prolog(svg: &str) -> &str {
    let mut s = svg.trim_start_matches('\u{feff}').trim_start();
    if s.starts_with("<?xml") {
        s = s.find("?>").map_or("", |e| &s[e + 2..]).trim_start();
    }
    if s.starts_with("<!DOCTYPE") || s.starts_with("<!doctype") {
        let end = match (s.find('['), s.find('>')) {
            (Some(b), Some(g)) if b < g => s.find("]>").map(|e| e + 2),
            (_, g) => g.map(|e| e + 1),
        };
        s = end.map_or("", |e| &s[e..]).trim_start();
    }
    s
}

/// Indices of at most `max` of `n` samples, evenly spread, the first and last always included.
fn sample_indices(n: usize, max: usize) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    let m = max.max(2) - 1;
    (0..=m).map(|j| (2 * j * (n - 1) + m) / (2 * m)).collect()
}

/// The rounding step: the given one when usable, else 1/10 000 of the first frame's extent.
fn rounding_step(mesh: &PreviewMesh<'_>) -> f64 {
    if mesh.precision.is_finite() && mesh.precision > 0.0 {
        return mesh.precision;
    }
    let pts = mesh.frames.first().map(Vec::as_slice).unwrap_or(&[]);
    let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
    for p in pts.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let extent = (hi - lo).max_element();
    if extent.is_finite() && extent > 0.0 {
        extent / 10_000.0
    } else {
        0.01
    }
}

/// The `const CRMORPH = {…};` line the script reads: timing, and the mesh samples as integers
/// of the rounding step (see the module documentation).
fn page_data(tl: &Timeline, mesh: &PreviewMesh<'_>) -> String {
    let vertices = mesh.frames.first().map_or(0, Vec::len);
    let usable = mesh.frames.iter().all(|f| f.len() == vertices) && vertices > 0;
    let mut edges = BTreeSet::new();
    if usable {
        for t in mesh.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b && (a as usize) < vertices && (b as usize) < vertices {
                    edges.insert((a.min(b), a.max(b)));
                }
            }
        }
    }
    let mut bones = BTreeSet::new();
    if usable {
        for &[a, b] in mesh.extra_edges {
            if a != b && (a as usize) < vertices && (b as usize) < vertices {
                bones.insert((a.min(b), a.max(b)));
            }
        }
    }
    let n = mesh.frames.len();
    let picked = if usable {
        sample_indices(n, MAX_SAMPLES)
    } else {
        Vec::new()
    };
    let step = rounding_step(mesh);
    let quantize = |v: f64| {
        let q = (v / step).round();
        if q.is_finite() {
            q.clamp(-1e15, 1e15) as i64
        } else {
            0
        }
    };

    let mut s = String::new();
    let playback = match tl.playback {
        Playback::Once => "once",
        Playback::Loop => "loop",
        Playback::Yoyo => "yoyo",
    };
    let easing = match tl.easing {
        Easing::Linear => "linear",
        Easing::EaseInOut => "ease-in-out",
    };
    let _ = write!(
        s,
        "const CRMORPH = {{\"duration\": {}, \"frames\": {}, \"playback\": \"{playback}\", \"easing\": \"{easing}\", \"step\": {step:?},\n\"times\": [",
        tl.duration,
        tl.frames.max(2)
    );
    for (k, &i) in picked.iter().enumerate() {
        let tau = if n > 1 {
            i as f64 / (n - 1) as f64
        } else {
            0.0
        };
        let _ = write!(s, "{}{tau}", if k > 0 { "," } else { "" });
    }
    s.push_str("],\n\"edges\": [");
    for (k, (a, b)) in edges.iter().enumerate() {
        let _ = write!(s, "{}{a},{b}", if k > 0 { "," } else { "" });
    }
    s.push_str("],\n\"bones\": [");
    for (k, (a, b)) in bones.iter().enumerate() {
        let _ = write!(s, "{}{a},{b}", if k > 0 { "," } else { "" });
    }
    s.push_str("],\n\"samples\": [");
    let mut prev: Vec<i64> = vec![0; 2 * vertices];
    for (k, &i) in picked.iter().enumerate() {
        s.push_str(if k > 0 { ",\n[" } else { "\n[" });
        for (j, p) in mesh.frames[i].iter().enumerate() {
            for (c, v) in [p.x, p.y].into_iter().enumerate() {
                let q = quantize(v);
                let sep = if j + c > 0 { "," } else { "" };
                let _ = write!(s, "{sep}{}", q - prev[2 * j + c]);
                prev[2 * j + c] = q;
            }
        }
        s.push(']');
    }
    s.push_str("]};\n");
    s
}

/// The page's styling: system fonts, neutral colours, the drawing centred above the controls.
const STYLE: &str = r#"<style>
:root { color-scheme: light; }
* { box-sizing: border-box; }
body { margin: 0; min-height: 100vh; padding: 1.25rem; display: flex; flex-direction: column;
  align-items: center; justify-content: center; gap: 0.9rem; background: #f3f3f4; color: #222;
  font: 14px/1.4 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", sans-serif; }
h1 { margin: 0; font-size: 1rem; font-weight: 600; color: #444; }
#crmorph-stage { max-width: 100%; padding: 0.5rem; background: #fff; border: 1px solid #ddd;
  border-radius: 6px; display: flex; justify-content: center; }
#crmorph-stage > svg { display: block; max-width: 100%; max-height: calc(100vh - 9rem);
  height: auto; }
.crmorph-controls { display: flex; flex-wrap: wrap; align-items: center; justify-content: center;
  gap: 0.75rem; }
.crmorph-controls button { min-width: 5.5rem; padding: 0.3rem 0.9rem; font: inherit;
  color: inherit; background: #fff; border: 1px solid #bbb; border-radius: 4px; cursor: pointer; }
.crmorph-controls button:hover { background: #eee; }
.crmorph-controls input[type=range] { width: min(24rem, 60vw); }
.crmorph-controls output { min-width: 4.5rem; font-variant-numeric: tabular-nums; }
.crmorph-controls label { display: inline-flex; align-items: center; gap: 0.35rem;
  cursor: pointer; }
</style>
"#;

/// The controls under the drawing; the ids are the page's interface for scripts and tests.
const CONTROLS: &str = r#"<div class="crmorph-controls">
<button type="button" id="crmorph-play">Pause</button>
<input type="range" id="crmorph-time" min="0" max="1" step="any" value="0" aria-label="Morph time">
<output id="crmorph-t" for="crmorph-time">t = 0.000</output>
<label><input type="checkbox" id="crmorph-mesh"> show triangulation</label>
</div>
"#;

/// The page's behaviour (reads `CRMORPH`): the SVG's own animation clock drives playback; the
/// slider pauses it and sets its time; the overlay interpolates the embedded mesh samples.
const SCRIPT: &str = r##"(function () {
  "use strict";
  var D = CRMORPH;
  var svg = document.querySelector("#crmorph-stage > svg");
  var play = document.getElementById("crmorph-play");
  var slider = document.getElementById("crmorph-time");
  var label = document.getElementById("crmorph-t");
  var meshBox = document.getElementById("crmorph-mesh");
  var smil = !!(svg && svg.pauseAnimations && svg.setCurrentTime && svg.getCurrentTime);

  // Mesh samples: integers of D.step, each sample relative to the previous one.
  var frames = [], acc = null;
  D.samples.forEach(function (s) {
    var q = new Float64Array(s.length), f = new Float64Array(s.length);
    for (var i = 0; i < s.length; i++) {
      q[i] = (acc ? acc[i] : 0) + s[i];
      f[i] = q[i] * D.step;
    }
    acc = q;
    frames.push(f);
  });
  if (!frames.length || !svg) { meshBox.disabled = true; }

  var overlay = null;
  if (svg && frames.length) {
    overlay = document.createElementNS(svg.namespaceURI, "path");
    overlay.setAttribute("id", "crmorph-mesh-overlay");
    overlay.setAttribute("fill", "none");
    overlay.setAttribute("stroke", "#1f6feb");
    overlay.setAttribute("stroke-opacity", "0.6");
    overlay.setAttribute("stroke-width", "0.75");
    overlay.setAttribute("stroke-linejoin", "round");
    overlay.setAttribute("vector-effect", "non-scaling-stroke");
    overlay.setAttribute("pointer-events", "none");
    overlay.style.display = "none";
    svg.appendChild(overlay);
  }
  // The skeleton each frame carries, when the morph is steered by one: thicker, in teal.
  var bonesPath = null;
  if (overlay && D.bones.length) {
    bonesPath = overlay.cloneNode(false);
    bonesPath.setAttribute("id", "crmorph-skeleton-overlay");
    bonesPath.setAttribute("stroke", "#00acc1");
    bonesPath.setAttribute("stroke-opacity", "0.95");
    bonesPath.setAttribute("stroke-width", "3");
    bonesPath.setAttribute("stroke-linecap", "round");
    svg.appendChild(bonesPath);
    var text = meshBox.parentNode && meshBox.parentNode.lastChild;
    if (text && text.nodeType === 3) { text.nodeValue = " show triangulation and skeleton"; }
  }

  function ease(tau) {
    tau = Math.min(1, Math.max(0, tau));
    return D.easing === "ease-in-out" ? tau * tau * (3 - 2 * tau) : tau;
  }

  // Forward morph progress (0..1) at animation time `sec`.
  function progress(sec) {
    var d = D.duration;
    if (D.playback === "once") { return Math.min(1, Math.max(0, sec / d)); }
    if (D.playback === "loop") { return (sec % d) / d; }
    var ph = sec % (2 * d);
    return ph <= d ? ph / d : 2 - ph / d;
  }

  function drawMesh(tau) {
    if (!overlay) { return; }
    overlay.style.display = meshBox.checked ? "" : "none";
    if (bonesPath) { bonesPath.style.display = overlay.style.display; }
    if (!meshBox.checked) { return; }
    var ts = D.times, k = 0;
    while (k < ts.length - 2 && ts[k + 1] < tau) { k++; }
    var a = frames[k], b = frames[Math.min(k + 1, frames.length - 1)];
    var span = ts.length > 1 ? ts[k + 1] - ts[k] : 0;
    var w = span > 0 ? Math.min(1, Math.max(0, (tau - ts[k]) / span)) : 0;
    function x(i) { return +(a[2 * i] + w * (b[2 * i] - a[2 * i])).toFixed(3); }
    function y(i) { return +(a[2 * i + 1] + w * (b[2 * i + 1] - a[2 * i + 1])).toFixed(3); }
    function segments(e) {
      var parts = [];
      for (var j = 0; j < e.length; j += 2) {
        parts.push("M" + x(e[j]) + " " + y(e[j]) + "L" + x(e[j + 1]) + " " + y(e[j + 1]));
      }
      return parts.join("");
    }
    overlay.setAttribute("d", segments(D.edges));
    if (bonesPath) { bonesPath.setAttribute("d", segments(D.bones)); }
  }

  var playing = smil, wasPlaying = false;

  function show(tau) {
    slider.value = String(tau);
    label.textContent = "t = " + ease(tau).toFixed(3);
    drawMesh(tau);
  }

  function setButton() {
    var ended = D.playback === "once" && +slider.value >= 1;
    play.textContent = playing ? "Pause" : (ended ? "Replay" : "Play");
  }

  function tick() {
    if (!playing) { return; }
    var sec = svg.getCurrentTime();
    if (D.playback === "once" && sec >= D.duration) {
      pause();
      svg.setCurrentTime(D.duration);
      show(1);
      setButton();
      return;
    }
    show(progress(sec));
    requestAnimationFrame(tick);
  }

  function pause() {
    playing = false;
    if (smil) { svg.pauseAnimations(); }
  }

  function resume() {
    if (!smil) { return; }
    if (D.playback === "once" && +slider.value >= 1) {
      svg.setCurrentTime(0);
    }
    playing = true;
    svg.unpauseAnimations();
    requestAnimationFrame(tick);
  }

  play.addEventListener("click", function () {
    if (playing) { pause(); } else { resume(); }
    setButton();
  });

  function seek(tau) {
    tau = Math.min(1, Math.max(0, tau));
    if (smil) { svg.setCurrentTime(tau * D.duration); }
    show(tau);
    setButton();
  }

  slider.addEventListener("input", function () {
    if (playing) { wasPlaying = true; pause(); }
    seek(+slider.value);
  });

  // The keys step whole frames, as in an animation tool: arrows one frame, Page Up/Down a
  // tenth of the morph, Home/End the ends. Stepping pauses playback and leaves it paused.
  slider.addEventListener("keydown", function (e) {
    var last = D.frames - 1, k = Math.round(+slider.value * last);
    var to = { ArrowRight: k + 1, ArrowUp: k + 1, ArrowLeft: k - 1, ArrowDown: k - 1,
      PageUp: k + Math.max(1, Math.round(last / 10)), PageDown: k - Math.max(1, Math.round(last / 10)),
      Home: 0, End: last }[e.key];
    if (to === undefined) { return; }
    if (e.preventDefault) { e.preventDefault(); }
    if (playing) { pause(); }
    wasPlaying = false;
    seek(Math.min(last, Math.max(0, to)) / last);
  });

  slider.addEventListener("change", function () {
    if (wasPlaying) { wasPlaying = false; resume(); setButton(); }
  });

  meshBox.addEventListener("change", function () { drawMesh(+slider.value); });

  if (!smil) { play.disabled = true; }
  show(smil ? progress(svg.getCurrentTime()) : 0);
  setButton();
  if (playing) { requestAnimationFrame(tick); }
})();
"##;

#[cfg(test)]
mod tests {
    use super::*;

    const SVG: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
        xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"200\" height=\"100\" viewBox=\"0 0 200 100\">\
        <path d=\"M0 0H10V10Z\"><animate attributeName=\"d\" dur=\"2s\" values=\"M0 0H10V10Z;M0 0H20V20Z\"/></path></svg>\n";

    /// A square of two triangles drifting right over `n` frames.
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

    fn page(title: &str, n: usize, playback: Playback) -> String {
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
        preview_html(title, SVG, &tl, &mesh)
    }

    #[test]
    fn extra_edges_join_the_overlay() {
        let frames = mesh_frames(3);
        let tris = [[0, 1, 2]];
        let tl = Timeline {
            frames: 3,
            ..Timeline::default()
        };
        let with = |extra: &[[u32; 2]]| {
            let mesh = PreviewMesh {
                triangles: &tris,
                frames: &frames,
                precision: 0.01,
                extra_edges: extra,
            };
            let page = preview_html("t", SVG, &tl, &mesh);
            assert_eq!(
                numbers(&page, "bones"),
                if extra.is_empty() {
                    vec![]
                } else {
                    vec![2.0, 3.0]
                }
            );
            numbers(&page, "edges")
        };
        assert_eq!(with(&[]).len(), 6);
        // A segment to the fourth point (a joint after the mesh vertices) is a bone, kept apart
        // from the mesh edges; one out of range is ignored.
        assert_eq!(with(&[[2, 3], [3, 9]]).len(), 6);
    }

    /// The line holding `"key": [...]` in the page data, as numbers.
    fn numbers(page: &str, key: &str) -> Vec<f64> {
        let start = page.find(&format!("\"{key}\": [")).unwrap() + key.len() + 5;
        let end = start + page[start..].find(']').unwrap();
        page[start..end]
            .split(|c: char| c == ',' || c == '[' || c == ']' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().unwrap())
            .collect()
    }

    #[test]
    fn page_is_standalone_with_the_controls_and_one_svg() {
        let p = page("A <b>&</b> \"morph\"", 100, Playback::Yoyo);
        assert_eq!(p.matches("<svg").count(), 1);
        assert!(!p.contains("<?xml"));
        for id in [
            "crmorph-time",
            "crmorph-play",
            "crmorph-mesh",
            "crmorph-stage",
        ] {
            assert!(p.contains(&format!("id=\"{id}\"")), "{id}");
        }
        assert!(p.contains("<title>A &lt;b&gt;&amp;&lt;/b&gt; &quot;morph&quot;</title>"));
        assert!(!p.contains("<b>"));
        // No network: the only URLs are the SVG's namespace names.
        let mut rest = p.as_str();
        while let Some(i) = rest.find("http") {
            let url = &rest[i..];
            assert!(
                url.starts_with("http://www.w3.org/2000/svg")
                    || url.starts_with("http://www.w3.org/1999/xlink"),
                "{}",
                &url[..url.len().min(40)]
            );
            rest = &rest[i + 4..];
        }
        assert!(p.contains("\"playback\": \"yoyo\""));
        assert_eq!(p, page("A <b>&</b> \"morph\"", 100, Playback::Yoyo));
    }

    #[test]
    fn mesh_samples_are_bounded_deduplicated_and_exact_to_the_step() {
        let p = page("m", 100, Playback::Loop);
        let times = numbers(&p, "times");
        assert_eq!(times.len(), MAX_SAMPLES);
        assert_eq!((times[0], *times.last().unwrap()), (0.0, 1.0));
        // 5 distinct edges of the two triangles (the diagonal once), as pairs.
        assert_eq!(
            numbers(&p, "edges"),
            vec![0., 1., 0., 2., 0., 3., 1., 2., 2., 3.]
        );
        // Samples: cumulative integers of 0.01 reproduce every vertex within half a step.
        let frames = mesh_frames(100);
        let samples_at = p.find("\"samples\": [").unwrap();
        let rows: Vec<Vec<f64>> = p[samples_at..]
            .lines()
            .skip(1)
            .take(MAX_SAMPLES)
            .map(|l| {
                l.trim_matches(|c| c == '[' || c == ']' || c == ',' || c == '}' || c == ';')
                    .split(',')
                    .map(|v| v.parse().unwrap())
                    .collect()
            })
            .collect();
        assert_eq!(rows.len(), MAX_SAMPLES);
        let mut acc = [0.0; 8];
        for (row, &tau) in rows.iter().zip(&times) {
            let i = (tau * 99.0).round() as usize;
            for (k, v) in row.iter().enumerate() {
                acc[k] += v;
                let want = if k % 2 == 0 {
                    frames[i][k / 2].x
                } else {
                    frames[i][k / 2].y
                };
                assert!((acc[k] * 0.01 - want).abs() <= 0.005 + 1e-9, "{i} {k}");
            }
        }
        // Few frames: all of them.
        assert_eq!(numbers(&page("m", 5, Playback::Once), "times").len(), 5);
    }

    #[test]
    fn prolog_and_doctype_are_dropped() {
        let svg = "\u{feff}<?xml version=\"1.0\"?>\n<!DOCTYPE svg [ <!ENTITY a \"b\"> ]>\n<svg/>";
        assert_eq!(strip_prolog(svg), "<svg/>");
        assert_eq!(
            strip_prolog("<!DOCTYPE svg PUBLIC \"x\">\n<svg/>"),
            "<svg/>"
        );
        assert_eq!(strip_prolog("<svg/>"), "<svg/>");
        assert_eq!(sample_indices(3, 31), vec![0, 1, 2]);
        let s = sample_indices(1000, 31);
        assert_eq!((s.len(), s[0], s[30]), (31, 0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn broken_meshes_give_a_page_without_overlay_data() {
        let frames = vec![vec![Point::new(0.0, 0.0)], vec![]];
        let mesh = PreviewMesh {
            triangles: &[[0, 1, 7]],
            frames: &frames,
            precision: f64::NAN,
            extra_edges: &[],
        };
        let p = preview_html("x", SVG, &Timeline::default(), &mesh);
        assert!(p.contains("\"samples\": []"));
        assert!(p.contains("\"edges\": []"));
    }
}
