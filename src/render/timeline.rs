//! When each frame of an exported morph is shown: frame count, duration, easing and playback.
//!
//! A sequence of `N` frames samples the morph at uniform *times* `τ_i = i / (N − 1)` of the
//! animation; frame `i` shows the morph at `t_i = ease(τ_i)`. With linear easing `t_i = τ_i`, the
//! frames DESIGN.md §3 names (the first at t = 0, the last at t = 1). Every exporter (animated SVG,
//! GIF, APNG, HTML preview, frame folders) reads its timing from one [`Timeline`], so they agree.

/// How the morph's progress `t` follows the animation's time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Easing {
    /// `t` grows at a constant rate.
    #[default]
    Linear,
    /// `t` starts and ends slowly (cubic smoothstep `3τ² − 2τ³`: zero speed at both ends, the
    /// same shape as CSS `ease-in-out` without its asymmetry).
    EaseInOut,
}

impl Easing {
    /// The morph's progress at animation time `tau` in [0, 1]; exactly 0 at 0 and 1 at 1.
    pub fn apply(self, tau: f64) -> f64 {
        let tau = if tau.is_nan() {
            0.0
        } else {
            tau.clamp(0.0, 1.0)
        };
        match self {
            Easing::Linear => tau,
            Easing::EaseInOut => tau * tau * (3.0 - 2.0 * tau),
        }
    }

    /// The slope `dt/dτ` of [`Easing::apply`] at `tau` (clamped like it): what a player that
    /// eases between two keyframes needs to follow this easing exactly (Lottie's bezier
    /// easing, [`crate::export::lottie`]).
    pub fn slope(self, tau: f64) -> f64 {
        let tau = if tau.is_nan() {
            0.0
        } else {
            tau.clamp(0.0, 1.0)
        };
        match self {
            Easing::Linear => 1.0,
            Easing::EaseInOut => 6.0 * tau * (1.0 - tau),
        }
    }
}

/// What happens when the morph reaches the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Playback {
    /// Play once and stay on the target.
    #[default]
    Once,
    /// Start again from the source, forever.
    Loop,
    /// Play back to the source, then forwards again, forever.
    Yoyo,
}

/// The timing of an exported morph.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timeline {
    /// Number of frames from the source to the target, both included (at least 2).
    pub frames: usize,
    /// Seconds from the source to the target.
    pub duration: f64,
    /// How `t` follows time.
    pub easing: Easing,
    /// What happens at the end.
    pub playback: Playback,
}

impl Default for Timeline {
    /// 60 frames over 2 seconds, linear, played once.
    fn default() -> Self {
        Timeline {
            frames: 60,
            duration: 2.0,
            easing: Easing::Linear,
            playback: Playback::Once,
        }
    }
}

/// Keyframes per second of an animated SVG at most: twice the 60 Hz most displays run at, and
/// the rate of the fastest common ones.
pub const MAX_KEYFRAMES_PER_SECOND: f64 = 120.0;

impl Timeline {
    /// Frame count clamped to at least 2 and duration to a positive finite number of seconds,
    /// so that every derived quantity is well defined.
    pub fn sanitized(self) -> Self {
        Timeline {
            frames: self.frames.max(2),
            duration: if self.duration.is_finite() && self.duration > 0.0 {
                self.duration
            } else {
                Timeline::default().duration
            },
            ..self
        }
    }

    /// The timeline an animation whose player interpolates between keyframes (SMIL) needs:
    /// at most [`MAX_KEYFRAMES_PER_SECOND`] keyframes per second of `duration`, since a browser
    /// draws no more than that; a timeline within the rate comes back as it is. Memory and
    /// file size then stop growing with `frames` (issue 12, item 4).
    pub fn keyframes(self) -> Self {
        let tl = self.sanitized();
        let most = (tl.duration * MAX_KEYFRAMES_PER_SECOND).ceil() as usize + 1;
        Timeline {
            frames: tl.frames.min(most.max(2)),
            ..tl
        }
    }

    /// The animation time of each frame as a fraction of `duration`: `i / (N − 1)`.
    pub fn times(&self) -> Vec<f64> {
        let n = self.frames.max(2);
        (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
    }

    /// The morph's `t` of each frame: [`Timeline::times`] through the easing.
    pub fn morph_times(&self) -> Vec<f64> {
        self.times()
            .into_iter()
            .map(|tau| self.easing.apply(tau))
            .collect()
    }

    /// The order in which frames are shown in one period of playback: `0..N` forwards, and for
    /// [`Playback::Yoyo`] then `N − 2` down to `1` (the ends are not shown twice in a row).
    pub fn sequence(&self) -> Vec<usize> {
        let n = self.frames.max(2);
        let mut seq: Vec<usize> = (0..n).collect();
        if self.playback == Playback::Yoyo {
            seq.extend((1..n - 1).rev());
        }
        seq
    }

    /// Seconds between two consecutive frames: `duration / (N − 1)`.
    pub fn frame_interval(&self) -> f64 {
        self.duration / (self.frames.max(2) - 1) as f64
    }

    /// Seconds of one period: `duration`, or twice that for [`Playback::Yoyo`].
    pub fn period(&self) -> f64 {
        match self.playback {
            Playback::Yoyo => 2.0 * self.duration,
            _ => self.duration,
        }
    }

    /// Whether the animation repeats forever.
    pub fn repeats(&self) -> bool {
        self.playback != Playback::Once
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyframes_stop_at_what_a_display_draws() {
        let tl = |frames, duration| Timeline {
            frames,
            duration,
            ..Timeline::default()
        };
        assert_eq!(
            tl(60, 2.0).keyframes(),
            tl(60, 2.0),
            "within the rate: as it is"
        );
        assert_eq!(tl(10_000, 2.0).keyframes().frames, 241);
        assert_eq!(tl(10_000, 0.01).keyframes().frames, 3);
        assert_eq!(tl(500, 100.0).keyframes().frames, 500);
    }

    #[test]
    fn easing_is_exact_at_the_ends_and_monotone() {
        for e in [Easing::Linear, Easing::EaseInOut] {
            assert_eq!(e.apply(0.0), 0.0);
            assert_eq!(e.apply(1.0), 1.0);
            assert_eq!(e.apply(-3.0), 0.0);
            assert_eq!(e.apply(f64::NAN), 0.0);
            let mut last = 0.0;
            for i in 1..=100 {
                let v = e.apply(i as f64 / 100.0);
                assert!(v > last, "{e:?} not increasing at {i}");
                last = v;
            }
        }
        // Ease-in-out is slow at the ends, symmetric about the middle.
        let e = Easing::EaseInOut;
        assert!(e.apply(0.1) < 0.1 && e.apply(0.9) > 0.9);
        assert!((e.apply(0.5) - 0.5).abs() < 1e-15);
        assert!((e.apply(0.3) + e.apply(0.7) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn frames_span_source_to_target() {
        let tl = Timeline {
            frames: 5,
            ..Timeline::default()
        };
        assert_eq!(tl.times(), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        assert_eq!(tl.morph_times(), tl.times());
        assert_eq!(tl.sequence(), vec![0, 1, 2, 3, 4]);
        assert!((tl.frame_interval() - 0.5).abs() < 1e-15);
        assert_eq!(tl.period(), 2.0);
        assert!(!tl.repeats());
    }

    #[test]
    fn yoyo_plays_back_without_doubling_the_ends() {
        let tl = Timeline {
            frames: 4,
            duration: 3.0,
            playback: Playback::Yoyo,
            ..Timeline::default()
        };
        assert_eq!(tl.sequence(), vec![0, 1, 2, 3, 2, 1]);
        assert_eq!(tl.period(), 6.0);
        // One period shows every interval twice: 6 intervals of 1 s.
        assert!((tl.sequence().len() as f64 * tl.frame_interval() - tl.period()).abs() < 1e-12);
        assert!(tl.repeats());
    }

    #[test]
    fn sanitized_fixes_degenerate_settings() {
        let tl = Timeline {
            frames: 0,
            duration: f64::NAN,
            ..Timeline::default()
        }
        .sanitized();
        assert_eq!(tl.frames, 2);
        assert_eq!(tl.duration, 2.0);
        assert_eq!(tl.times(), vec![0.0, 1.0]);
    }
}
