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

mod encoding;
mod entities;
mod file;
pub mod raster;
mod resources;
mod scan;

pub use encoding::decode;
pub use file::read_file;
pub use resources::{local_path, Refusal};

use std::borrow::Cow;
use std::path::Path;

use crate::error::{Error, Result};

/// `text` made safe to parse: its document type declaration removed with the internal
/// entities expanded under the byte limit ([`Limits::input_bytes`]), then checked against the
/// depth, element and segment limits. Every SVG text crmorph parses goes through this first.
pub fn prepare<'a>(name: &str, text: &'a str, limits: &Limits) -> Result<Cow<'a, str>> {
    let text = match entities::expand(name, text, limits)? {
        Some(expanded) => Cow::Owned(expanded),
        None => Cow::Borrowed(text),
    };
    scan::scan(name, &text, limits)?;
    Ok(text)
}

/// The text of the SVG file at `path` under the policy: read with [`read_file`], decoded with
/// [`decode`] and made safe with [`prepare`]. `name` is how errors call it. A raster image
/// (PNG, JPEG, GIF or WebP, by its signature) is read as the drawing that embeds it
/// ([`raster::image_svg`]), its boundary given the id `boundary_id`.
pub fn read_svg(path: &Path, name: &str, boundary_id: &str, limits: &Limits) -> Result<String> {
    let bytes = read_file(path, name, limits)?;
    if let Some(format) = raster::sniff(&bytes) {
        let svg = raster::image_svg(name, &bytes, format, boundary_id, limits)?;
        return Ok(prepare(name, &svg, limits)?.into_owned());
    }
    if let Some(ext) = misnamed_image(path, &bytes) {
        return Err(Error::input(
            name,
            format!(
                "is named like a {ext} image, but its bytes are neither a PNG, JPEG, GIF or WebP \
                 image nor SVG"
            ),
        ));
    }
    let text = decode(name, &bytes, limits)?;
    Ok(prepare(name, &text, limits)?.into_owned())
}

/// The image extension of `path` (upper case: "PNG", "JPEG", …) when `bytes`, which are not
/// a raster image, do not look like markup either (they do not open with `<` after a byte
/// order mark and white space, nor with gzip's signature): a damaged or mislabelled picture,
/// which would otherwise be reported as a broken SVG file.
fn misnamed_image(path: &Path, bytes: &[u8]) -> Option<&'static str> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    let kind = match ext.as_str() {
        "png" => "PNG",
        "jpg" | "jpeg" => "JPEG",
        "gif" => "GIF",
        "webp" => "WebP",
        _ => return None,
    };
    let body = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let first = body.iter().find(|b| !b.is_ascii_whitespace());
    let markup = first == Some(&b'<') || bytes.starts_with(b"\x1f\x8b");
    (!markup).then_some(kind)
}

/// The drawing of the raster image at `image` (named `image_name`) with the control geometry
/// of the SVG file `controls` (named `controls_name`, drawn in the image's pixel coordinates)
/// merged into it ([`raster::merge_controls`]), both read under the policy's `limits`;
/// `boundary_id` is the boundary's id. `None` when `image` is not a raster image.
pub fn read_image_with_controls(
    (image, image_name): (&Path, &str),
    (controls, controls_name): (&Path, &str),
    boundary_id: &str,
    limits: &Limits,
) -> Result<Option<String>> {
    let bytes = read_file(image, image_name, limits)?;
    let Some(format) = raster::sniff(&bytes) else {
        return Ok(None);
    };
    let svg = raster::image_svg(image_name, &bytes, format, boundary_id, limits)?;
    let controls_bytes = read_file(controls, controls_name, limits)?;
    if raster::sniff(&controls_bytes).is_some() {
        return Err(Error::input(
            controls_name,
            "is an image; controls are an SVG drawn in the image's pixel coordinates",
        ));
    }
    let controls_text = decode(controls_name, &controls_bytes, limits)?;
    let controls_text = prepare(controls_name, &controls_text, limits)?;
    let merged =
        raster::merge_controls(image_name, &svg, controls_name, &controls_text, boundary_id)?;
    Ok(Some(prepare(image_name, &merged, limits)?.into_owned()))
}

/// usvg options under `policy` for the drawing `file` in folder `dir`: images resolved by the
/// policy's rules, nested SVG images prepared like drawings.
pub fn usvg_options(
    file: &str,
    dir: Option<&Path>,
    policy: &InputPolicy,
) -> usvg::Options<'static> {
    usvg::Options {
        resources_dir: dir.map(Path::to_path_buf),
        image_href_resolver: resources::resolver(file, dir, policy),
        ..usvg::Options::default()
    }
}

/// The references of `<image>` and `<feImage>` elements in `text` that are not data URIs, each
/// with the element's id if it has one, in document order: what a drawing asks to read.
pub fn image_refs(text: &str) -> Vec<(Option<String>, String)> {
    scan::image_refs(text)
}

/// One note per image of the drawing `file` (folder `dir`) that the policy does not let
/// crmorph read: the image is left out of the artwork, and the note says why.
pub fn refused_images(
    file: &str,
    text: &str,
    dir: Option<&Path>,
    policy: &InputPolicy,
) -> Vec<String> {
    image_refs(text)
        .into_iter()
        .filter_map(|(id, href)| {
            let why = match local_path(&href, dir, policy) {
                Err(why) => why,
                Ok(path) => match std::fs::metadata(&path) {
                    Ok(m) if m.is_file() && m.len() <= policy.limits.input_bytes => return None,
                    Ok(m) if m.is_file() => Refusal::Missing(format!(
                        "it has {} bytes, over the limit of {} (--max-input-bytes)",
                        m.len(),
                        policy.limits.input_bytes
                    )),
                    Ok(_) => Refusal::Missing("it is not a regular file".into()),
                    Err(e) => Refusal::Missing(format!("cannot read it: {e}")),
                },
            };
            let which = match id {
                Some(id) => format!("image '{}'", crate::error::printable(&id)),
                None => "an image".to_string(),
            };
            Some(format!(
                "{file}: {which} ({}) is left out: {why}",
                crate::error::printable(&href)
            ))
        })
        .collect()
}
