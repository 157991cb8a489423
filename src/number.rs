//! Numbers as crmorph writes them into SVG and pose files: short, exact enough for the
//! drawing, never a negative zero. A leaf module, so that every writer (the frame writers in
//! `render`, the pose files of `skeleton`) formats alike without depending on another.

/// `x` with at most `decimals` decimals, trailing zeros dropped, no negative zero.
pub(crate) fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// `x` to 9 significant digits (for scale-free values: opacities, gradient geometry, matrices).
pub(crate) fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".into();
    }
    let r: f64 = format!("{x:.8e}").parse().unwrap_or(x);
    let s = format!("{r}");
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}
