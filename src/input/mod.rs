//! The input policy: what crmorph reads, how much, and from where, enforced in one place.
//!
//! crmorph runs on drawings from the internet, in batch jobs and behind upload forms, so a file
//! must not make it read other files, read without end, or work without bound:
//!
//! - **Data URIs** (`<image href="data:image/png;base64,…">`) are always read.
//! - **Local files** named by a drawing (`<image href="photo.png">`) are read only when
//!   [`InputPolicy::local_files`] names a folder (the CLI's `--allow-local-files[=DIR]`). The
//!   reference is resolved against the drawing's folder and must stay inside the allowed one:
//!   `..` is refused and symbolic links are followed before the check. URLs (`http:`, `file:`,
//!   …) are never read. A reference that is not read leaves the image out, with a note.
//! - **Every file** (drawings, pose files, images) is read through [`read_file`]: regular files
//!   only (no devices, FIFOs or sockets) and at most [`Limits::input_bytes`].
//! - **Fonts** are the system's, found by fontdb; SVG has no way to make crmorph load a font
//!   file.
//! - **Resource limits** ([`Limits`]) bound the text before it is parsed ([`prepare`]).

mod limits;

pub use limits::{Limit, Limits};

use std::path::PathBuf;

/// Which local files a drawing may make crmorph read (`<image href="photo.png">`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum LocalFiles {
    /// None: only data URIs (the default).
    #[default]
    Refused,
    /// Files inside the drawing's own folder (`--allow-local-files`).
    BesideDrawing,
    /// Files inside this folder (`--allow-local-files=DIR`).
    Within(PathBuf),
}

/// What crmorph may read while reading a drawing, and how much work the drawing may cause.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct InputPolicy {
    /// Which local files a drawing may name. Default: none.
    pub local_files: LocalFiles,
    /// Resource limits. Default: [`Limits::default`].
    pub limits: Limits,
}
