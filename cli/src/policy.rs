//! The input-policy flags shared by every command: which local files a drawing may name, and
//! the resource limits (`crmorph::input`).

use std::path::PathBuf;

use clap::Args;
use crmorph::input::{InputPolicy, Limits, LocalFiles};

/// `--allow-local-files` and the `--max-…` limits.
#[derive(Debug, Clone, Args)]
#[command(next_help_heading = "Input safety")]
pub(crate) struct Safety {
    /// Read local files that a drawing names (`<image href="photo.png">`): inside the drawing's
    /// own folder, or inside DIR. Without it, only data URIs are read; URLs never are.
    #[arg(long, value_name = "DIR", num_args = 0..=1, require_equals = true)]
    pub(crate) allow_local_files: Option<Option<PathBuf>>,
    /// Largest file read (after .svgz decompression and entity expansion), in bytes; K, M and
    /// G suffixes are powers of 1024.
    #[arg(long, value_name = "BYTES", default_value = "32M", value_parser = parse_bytes)]
    pub(crate) max_input_bytes: u64,
    /// Most elements in one drawing.
    #[arg(long, value_name = "N", default_value_t = Limits::default().elements)]
    pub(crate) max_elements: usize,
    /// Deepest element nesting in one drawing.
    #[arg(long, value_name = "N", default_value_t = Limits::default().depth)]
    pub(crate) max_depth: usize,
    /// Most path segments in one drawing.
    #[arg(long, value_name = "N", default_value_t = Limits::default().segments)]
    pub(crate) max_segments: usize,
    /// Most pixels in one rendered frame.
    #[arg(long, value_name = "N", default_value_t = Limits::default().pixels)]
    pub(crate) max_pixels: u64,
    /// Most vertices of one drawing's curves after flattening.
    #[arg(long, value_name = "N", default_value_t = Limits::default().vertices)]
    pub(crate) max_vertices: usize,
    /// Most shapes of one drawing that automatic mode pairs.
    #[arg(long, value_name = "N", default_value_t = Limits::default().shapes)]
    pub(crate) max_shapes: usize,
}

impl Safety {
    /// The library's input policy for these flags.
    pub(crate) fn policy(&self) -> InputPolicy {
        let mut limits = Limits::default();
        limits.input_bytes = self.max_input_bytes;
        limits.elements = self.max_elements;
        limits.depth = self.max_depth;
        limits.segments = self.max_segments;
        limits.pixels = self.max_pixels;
        limits.vertices = self.max_vertices;
        limits.shapes = self.max_shapes;
        let mut policy = InputPolicy::default();
        policy.limits = limits;
        policy.local_files = match &self.allow_local_files {
            None => LocalFiles::Refused,
            Some(None) => LocalFiles::BesideDrawing,
            Some(Some(dir)) => LocalFiles::Within(dir.clone()),
        };
        policy
    }
}

/// A byte count: digits with an optional K, M or G (powers of 1024).
fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (num, shift) = match t.char_indices().last() {
        Some((i, 'K' | 'k')) => (&t[..i], 10),
        Some((i, 'M' | 'm')) => (&t[..i], 20),
        Some((i, 'G' | 'g')) => (&t[..i], 30),
        _ => (t, 0),
    };
    let n: u64 = num
        .parse()
        .map_err(|_| format!("'{s}' is not a byte count, e.g. 32M"))?;
    n.checked_mul(1 << shift)
        .filter(|&b| b > 0)
        .ok_or_else(|| format!("'{s}' must be a byte count from 1 to 16E"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts() {
        assert_eq!(parse_bytes("32M"), Ok(32 << 20));
        assert_eq!(parse_bytes("100"), Ok(100));
        assert_eq!(parse_bytes("2g"), Ok(2 << 30));
        assert!(parse_bytes("0").is_err());
        assert!(parse_bytes("x").is_err());
        assert!(parse_bytes("99999999999999G").is_err());
    }
}
