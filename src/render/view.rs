//! The view every frame shows: the source drawing's viewBox, grown to hold everything the
//! morph draws (`--view fit`, the default) and padded (`--padding`).
//!
//! A morph can swing outside the source's view — a fish turning 170° sweeps its tail below
//! the frame, U → S bulges sideways mid-morph — and a view that stays put cuts it off. Growing
//! the view keeps the scale: the output gets more pixels (at the drawing's own pixels per
//! unit), or, with a fixed output size, the view is widened to that size's aspect ratio so
//! pixels stay square. A morph that stays inside keeps the source's view exactly, so icons keep
//! their box.

use super::FrameOptions;
use crate::artwork::Bounds;
use crate::geometry::Point;

/// Room around the view on every side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Padding {
    /// In user units.
    Units(f64),
    /// As a percentage of the view's larger side.
    Percent(f64),
}

impl Default for Padding {
    fn default() -> Self {
        Padding::Units(0.0)
    }
}

/// Margin added on each side the view grew by, as a fraction of the source view's diagonal:
/// the frames between the sampled ones reach a little further.
const GROWTH_MARGIN: f64 = 0.01;

impl FrameOptions {
    /// These options with the view grown to hold `drawn` (when given), with a margin of 1 % of
    /// the view's diagonal on each side it grew by, then `padding` on every side. Without
    /// `fixed_size` the size grows with the view at the same pixels per unit; with it, the
    /// view grows further on one axis, centred, to the size's aspect ratio. Unchanged when
    /// `drawn` lies inside the view and there is no padding.
    pub fn fitted(&self, drawn: Bounds, padding: Padding, fixed_size: Option<(u32, u32)>) -> Self {
        let (lo0, hi0) = self.view_box;
        let extent = hi0 - lo0;
        if !(extent.x > 0.0 && extent.y > 0.0 && extent.is_finite()) {
            return *self;
        }
        let margin = GROWTH_MARGIN * extent.length();
        let (mut lo, mut hi) = (lo0, hi0);
        if let Some((a, b)) = drawn.filter(|(a, b)| a.is_finite() && b.is_finite()) {
            if a.x < lo.x {
                lo.x = a.x - margin;
            }
            if a.y < lo.y {
                lo.y = a.y - margin;
            }
            if b.x > hi.x {
                hi.x = b.x + margin;
            }
            if b.y > hi.y {
                hi.y = b.y + margin;
            }
        }
        let pad = match padding {
            Padding::Units(u) => u,
            Padding::Percent(p) => p / 100.0 * (hi - lo).max_element(),
        };
        if pad.is_finite() && pad > 0.0 {
            lo -= Point::splat(pad);
            hi += Point::splat(pad);
        }
        if (lo, hi) == (lo0, hi0) && fixed_size.is_none_or(|s| s == self.size) {
            return *self;
        }
        let px = |x: f64| x.ceil().clamp(1.0, u32::MAX as f64) as u32;
        let size = match fixed_size {
            Some(s) => {
                // Widen the view, centred, to the output's aspect ratio.
                let (w, h) = (s.0 as f64, s.1 as f64);
                let d = hi - lo;
                let want = w / h;
                if d.x / d.y < want {
                    let grow = d.y * want - d.x;
                    lo.x -= grow / 2.0;
                    hi.x += grow / 2.0;
                } else {
                    let grow = d.x / want - d.y;
                    lo.y -= grow / 2.0;
                    hi.y += grow / 2.0;
                }
                s
            }
            None => {
                // The same pixels per unit as the drawing's own size.
                let scale =
                    Point::new(self.size.0 as f64 / extent.x, self.size.1 as f64 / extent.y);
                let d = hi - lo;
                (px(d.x * scale.x), px(d.y * scale.y))
            }
        };
        FrameOptions {
            view_box: (lo, hi),
            size,
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> FrameOptions {
        FrameOptions {
            view_box: (Point::ZERO, Point::new(100.0, 100.0)),
            size: (200, 200),
            background: None,
            max_pixels: u64::MAX,
        }
    }

    #[test]
    fn a_morph_inside_the_view_keeps_it() {
        let f = square();
        let inside = Some((Point::new(5.0, 5.0), Point::new(95.0, 95.0)));
        assert_eq!(f.fitted(inside, Padding::default(), None), f);
        assert_eq!(f.fitted(None, Padding::Units(0.0), Some((200, 200))), f);
    }

    #[test]
    fn a_morph_leaving_the_view_grows_it_at_the_same_scale() {
        let f = square();
        // A tail 30 units below the frame.
        let drawn = Some((Point::new(10.0, 10.0), Point::new(90.0, 130.0)));
        let g = f.fitted(drawn, Padding::default(), None);
        let margin = 0.01 * 100.0 * 2f64.sqrt();
        assert_eq!(g.view_box.0, Point::ZERO);
        assert!((g.view_box.1.y - (130.0 + margin)).abs() < 1e-9);
        assert_eq!(g.view_box.1.x, 100.0);
        assert_eq!(g.size, (200, (2.0 * (130.0 + margin)).ceil() as u32));
        assert!((g.scale() / f.scale() - 1.0).abs() < 0.01);
    }

    #[test]
    fn padding_and_a_fixed_size_keep_pixels_square() {
        let f = square();
        let g = f.fitted(None, Padding::Percent(10.0), None);
        assert_eq!(g.view_box, (Point::splat(-10.0), Point::splat(110.0)));
        assert_eq!(g.size, (240, 240));
        let h = f.fitted(None, Padding::Units(0.0), Some((400, 200)));
        assert_eq!(h.size, (400, 200));
        assert_eq!(
            h.view_box,
            (Point::new(-50.0, 0.0), Point::new(150.0, 100.0))
        );
    }
}
