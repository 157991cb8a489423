//! Draws the barycenter-based shape model's intermediate curves of a fixture at t = 0, 0.1, …, 1
//! into one SVG, for looking at the curves the composite mapping follows.
//! Run: `cargo run --release --example bsm -- fixtures/u-to-s /tmp/bsm.svg`.

use crmorph::Side;
use std::fmt::Write as _;
use std::path::Path;

use crmorph::compatible::{curve_pairs, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::mapping::ShapeModel;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = Path::new(&args[1]);
    let o = ReadOptions::default();
    let s = Drawing::open(&dir.join("source.svg"), &o).unwrap();
    let t = Drawing::open(&dir.join("target.svg"), &o).unwrap();
    let (_, pairs) = curve_pairs(&s, &t, &MorphOptions::default()).unwrap();
    let model = ShapeModel::new(&pairs, Side::Source).unwrap();
    let mut svg = String::from("<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 2400 1000' width='2400' height='1000'><rect width='2400' height='1000' fill='white'/>");
    let mut out = Vec::new();
    for k in 0..=10 {
        let tt = k as f64 / 10.0;
        model.curves_at(tt, &mut out);
        let col = format!("hsl({},70%,45%)", k * 25);
        let (ox, oy) = ((k % 6) as f64 * 400.0, (k / 6) as f64 * 500.0);
        let _ = write!(
            svg,
            "<g transform='translate({ox} {oy})'><text x='10' y='30' font-size='24'>t={tt}</text>"
        );
        for (ci, c) in out.iter().enumerate() {
            let mut d = String::new();
            for (i, p) in c.iter().enumerate() {
                let _ = write!(d, "{}{:.2} {:.2}", if i == 0 { 'M' } else { 'L' }, p.x, p.y);
            }
            if pairs[ci].closed {
                d.push('Z');
            }
            let _ = write!(
                svg,
                "<path d='{d}' fill='none' stroke='{col}' stroke-width='{}'/>",
                if ci == 0 { 1.5 } else { 1.0 }
            );
            let p0 = c[0];
            let _ = write!(
                svg,
                "<circle cx='{:.1}' cy='{:.1}' r='3' fill='{col}'/>",
                p0.x, p0.y
            );
        }
        svg.push_str("</g>");
    }
    svg.push_str("</svg>");
    std::fs::write(&args[2], svg).unwrap();
}
