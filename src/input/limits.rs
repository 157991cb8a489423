//! Resource limits: bounds on the work and memory one input may cause, with defaults that a
//! normal drawing never meets.
//!
//! Every limit is checked before the work it bounds (the text is scanned before it is parsed,
//! the raster size computed before a pixmap is allocated), so crossing one is a prompt one-line
//! error naming the limit and the CLI flag that raises it, never an abort or a long wait.

use crate::error::Error;

/// Bounds on what one input may cost. Each field names the `crmorph` flag that sets it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct Limits {
    /// Bytes read from one file (a drawing, a pose file, an image), after `.svgz` decompression
    /// and after the DTD's internal entities are expanded (`--max-input-bytes`).
    /// Default: 32 MiB.
    pub input_bytes: u64,
    /// Elements in one document (`--max-elements`). Default: 100,000.
    pub elements: usize,
    /// Element nesting depth (`--max-depth`). Default: 256.
    pub depth: usize,
    /// Path segments in one document, summed over every `d` and `points` (`--max-segments`).
    /// Default: 500,000.
    pub segments: usize,
    /// Pixels in one raster frame, from `--size` or the drawing's own size (`--max-pixels`).
    /// Default: 50 million (7,071 × 7,071).
    pub pixels: u64,
    /// Vertices after flattening and correspondence, summed over the curves of one drawing
    /// (`--max-vertices`). Default: 200,000.
    pub vertices: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            input_bytes: 32 << 20,
            elements: 100_000,
            depth: 256,
            segments: 500_000,
            pixels: 50_000_000,
            vertices: 200_000,
        }
    }
}

/// Which limit an input crossed: what it counts and the CLI flag that raises it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Limit {
    /// [`Limits::input_bytes`].
    InputBytes,
    /// [`Limits::elements`].
    Elements,
    /// [`Limits::depth`].
    Depth,
    /// [`Limits::segments`].
    Segments,
    /// [`Limits::pixels`].
    Pixels,
    /// [`Limits::vertices`].
    Vertices,
}

impl Limit {
    /// The CLI flag that sets this limit.
    pub fn flag(self) -> &'static str {
        match self {
            Limit::InputBytes => "--max-input-bytes",
            Limit::Elements => "--max-elements",
            Limit::Depth => "--max-depth",
            Limit::Segments => "--max-segments",
            Limit::Pixels => "--max-pixels",
            Limit::Vertices => "--max-vertices",
        }
    }

    /// What the limit counts, as a noun phrase.
    pub fn counts(self) -> &'static str {
        match self {
            Limit::InputBytes => "bytes",
            Limit::Elements => "elements",
            Limit::Depth => "levels of nesting",
            Limit::Segments => "path segments",
            Limit::Pixels => "pixels per frame",
            Limit::Vertices => "vertices",
        }
    }

    /// The value of this limit in `limits`.
    pub fn of(self, limits: &Limits) -> u64 {
        match self {
            Limit::InputBytes => limits.input_bytes,
            Limit::Elements => limits.elements as u64,
            Limit::Depth => limits.depth as u64,
            Limit::Segments => limits.segments as u64,
            Limit::Pixels => limits.pixels,
            Limit::Vertices => limits.vertices as u64,
        }
    }

    /// The one-line input error for `file` crossing this limit of `limits`; `what` says what
    /// crossed it, with its size ("elements nested 14000 deep", "a frame of 100000 × 100000
    /// px").
    pub fn exceeded(self, file: &str, what: &str, limits: &Limits) -> Error {
        Error::input(
            file,
            format!(
                "{what}: over the limit of {} {}",
                self.of(limits),
                self.counts()
            ),
        )
        .with_hint(format!(
            "raise it with {} if you trust the file",
            self.flag()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_a_limit_names_it_and_its_flag_in_one_line() {
        let l = Limits::default();
        let e = Limit::Depth
            .exceeded("a.svg", "elements nested 14000 deep", &l)
            .to_string();
        assert_eq!(
            e,
            "a.svg: elements nested 14000 deep: over the limit of 256 levels of nesting \
             (hint: raise it with --max-depth if you trust the file)"
        );
        for k in [
            Limit::InputBytes,
            Limit::Elements,
            Limit::Depth,
            Limit::Segments,
            Limit::Pixels,
            Limit::Vertices,
        ] {
            assert!(k.flag().starts_with("--max-"));
            assert!(k.of(&l) > 0);
        }
    }
}
