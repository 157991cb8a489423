//! Rounding an SVG's numbers as optimisers write them (svgo's `floatPrecision`, Inkscape's
//! "numeric precision"): shared by the fold tests and `examples/folds.rs`.

/// `svg` with every decimal number rounded to `decimals` places (`None`: unchanged), as SVG
/// optimisers write it. A number starts after anything but a digit, a point or a letter other
/// than a path command (so ids and colours stay as they are); integers are kept.
pub(crate) fn rounded(svg: &str, decimals: Option<usize>) -> String {
    let Some(d) = decimals else {
        return svg.to_string();
    };
    let b = svg.as_bytes();
    let mut out = String::with_capacity(svg.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let prev = if i > 0 { b[i - 1] } else { b' ' };
        let boundary = !(prev.is_ascii_digit()
            || prev == b'.'
            || prev == b'#'
            || prev.is_ascii_alphabetic() && !b"MmLlHhVvCcSsQqTtAaZz".contains(&prev));
        let number =
            c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        if !(number && boundary) {
            let ch = svg[i..].chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
            continue;
        }
        let mut j = i;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        let fraction = j < b.len() && b[j] == b'.';
        if fraction {
            j += 1;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
        }
        let exponent = j + 1 < b.len()
            && (b[j] == b'e' || b[j] == b'E')
            && (b[j + 1].is_ascii_digit() || b[j + 1] == b'-');
        if fraction && !exponent {
            let v: f64 = svg[i..j].parse().unwrap_or(0.0);
            out.push_str(&format!("{v:.d$}"));
        } else {
            out.push_str(&svg[i..j]);
        }
        i = j;
    }
    out
}
