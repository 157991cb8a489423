//! Images a drawing names, read under the policy: usvg's image resolvers replaced by ones that
//! read data URIs always, local files only inside the allowed folder, and URLs never.
//!
//! Raster images are checked against the pixel limit by their header before anything decodes
//! them (a few kilobytes of PNG can claim 50,000 × 50,000 pixels), and nested SVG images go
//! through the same [`prepare`](super::prepare) as a drawing.

use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use usvg::{ImageHrefResolver, ImageKind};

use super::{InputPolicy, LocalFiles};

/// Why a reference to a local file is not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// It is a URL (`http:`, `file:`, …): crmorph never reads those.
    Url,
    /// Local files are not allowed (no `--allow-local-files`).
    NotAllowed,
    /// It climbs out with `..`.
    ParentDir,
    /// It resolves outside the allowed folder (an absolute path, or a symbolic link out).
    Outside(PathBuf),
    /// It names no readable file.
    Missing(String),
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Url => write!(f, "it is a URL, and crmorph never reads URLs"),
            Refusal::NotAllowed => write!(
                f,
                "crmorph reads local files only with --allow-local-files (data URIs always)"
            ),
            Refusal::ParentDir => write!(f, "a path with '..' is never read"),
            Refusal::Outside(root) => write!(
                f,
                "it lies outside {}, the folder local files are read from",
                root.display()
            ),
            Refusal::Missing(why) => write!(f, "{why}"),
        }
    }
}

/// Where the image reference `href` of a drawing in folder `dir` may be read from under
/// `policy`, or why it may not.
pub fn local_path(
    href: &str,
    dir: Option<&Path>,
    policy: &InputPolicy,
) -> Result<PathBuf, Refusal> {
    if is_url(href) {
        return Err(Refusal::Url);
    }
    let root = match &policy.local_files {
        LocalFiles::Refused => return Err(Refusal::NotAllowed),
        LocalFiles::BesideDrawing => dir.map(Path::to_path_buf).unwrap_or_else(|| ".".into()),
        LocalFiles::Within(root) => root.clone(),
    };
    let rel = Path::new(href);
    if rel.components().any(|c| c == Component::ParentDir) {
        return Err(Refusal::ParentDir);
    }
    let path = match dir {
        Some(d) => d.join(rel),
        None => rel.to_path_buf(),
    };
    let missing = |e: std::io::Error| Refusal::Missing(format!("cannot read it: {e}"));
    let real_root = root.canonicalize().map_err(missing)?;
    let real = path.canonicalize().map_err(missing)?;
    if !real.starts_with(&real_root) {
        return Err(Refusal::Outside(root));
    }
    Ok(real)
}

/// Whether `href` has a URL scheme (`http:`, `file:`, `data:` …); a Windows drive letter
/// (`C:`) is a path.
fn is_url(href: &str) -> bool {
    match href.split_once(':') {
        Some((scheme, _)) => {
            scheme.len() > 1
                && scheme.starts_with(|c: char| c.is_ascii_alphabetic())
                && scheme
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        }
        None => false,
    }
}

/// usvg's image resolvers under `policy`, for a drawing named `file` in folder `dir`.
pub(crate) fn resolver(
    file: &str,
    dir: Option<&Path>,
    policy: &InputPolicy,
) -> ImageHrefResolver<'static> {
    let (p1, p2) = (policy.clone(), policy.clone());
    let (f1, f2) = (file.to_string(), file.to_string());
    let dir = dir.map(Path::to_path_buf);
    ImageHrefResolver {
        resolve_data: Box::new(move |mime, data, opts| image(&f1, mime, data, opts, &p1)),
        resolve_string: Box::new(move |href, opts| {
            let path = local_path(href, dir.as_deref(), &p2).ok()?;
            let name = format!("{f2}: image '{href}'");
            let bytes = super::read_file(&path, &name, &p2.limits).ok()?;
            let mime = match imagesize::image_type(&bytes) {
                Ok(imagesize::ImageType::Png) => "image/png",
                Ok(imagesize::ImageType::Jpeg) => "image/jpeg",
                Ok(imagesize::ImageType::Gif) => "image/gif",
                Ok(imagesize::ImageType::Webp) => "image/webp",
                _ => "image/svg+xml",
            };
            image(&f2, mime, Arc::new(bytes), opts, &p2)
        }),
    }
}

/// An image's bytes as usvg's image kind, under the pixel limit; nested SVG prepared and parsed
/// with `opts` (whose resolvers never read a file).
fn image(
    file: &str,
    mime: &str,
    data: Arc<Vec<u8>>,
    opts: &usvg::Options<'_>,
    policy: &InputPolicy,
) -> Option<ImageKind> {
    let raster = match mime {
        "image/png" => Some(ImageKind::PNG(data.clone())),
        "image/jpg" | "image/jpeg" => Some(ImageKind::JPEG(data.clone())),
        "image/gif" => Some(ImageKind::GIF(data.clone())),
        "image/webp" => Some(ImageKind::WEBP(data.clone())),
        _ => None,
    };
    let raster = raster.or_else(|| match imagesize::image_type(&data) {
        Ok(imagesize::ImageType::Png) => Some(ImageKind::PNG(data.clone())),
        Ok(imagesize::ImageType::Jpeg) => Some(ImageKind::JPEG(data.clone())),
        Ok(imagesize::ImageType::Gif) => Some(ImageKind::GIF(data.clone())),
        Ok(imagesize::ImageType::Webp) => Some(ImageKind::WEBP(data.clone())),
        _ => None,
    });
    if let Some(kind) = raster {
        let size = imagesize::blob_size(&data).ok()?;
        let pixels = (size.width as u64).saturating_mul(size.height as u64);
        if pixels == 0 || pixels > policy.limits.pixels {
            log::warn!(
                "{file}: an image of {} × {} px is over the limit of {} pixels; left out",
                size.width,
                size.height,
                policy.limits.pixels
            );
            return None;
        }
        return Some(kind);
    }
    let name = format!("{file}: nested SVG image");
    let text = super::decode(&name, &data, &policy.limits).ok()?;
    let text = super::prepare(&name, &text, &policy.limits).ok()?;
    usvg::Tree::from_data_nested(text.as_bytes(), opts)
        .ok()
        .map(ImageKind::SVG)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_files_only_inside_the_allowed_folder() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("art");
        std::fs::create_dir(&dir).unwrap();
        std::fs::write(dir.join("a.png"), b"x").unwrap();
        std::fs::write(root.path().join("secret.png"), b"x").unwrap();
        let mut policy = InputPolicy::default();
        let d = Some(dir.as_path());
        assert_eq!(local_path("a.png", d, &policy), Err(Refusal::NotAllowed));
        assert_eq!(local_path("https://x/a.png", d, &policy), Err(Refusal::Url));
        assert_eq!(
            local_path("file:///etc/passwd", d, &policy),
            Err(Refusal::Url)
        );
        policy.local_files = LocalFiles::BesideDrawing;
        assert_eq!(
            local_path("a.png", d, &policy).unwrap(),
            dir.join("a.png").canonicalize().unwrap()
        );
        assert_eq!(
            local_path("../secret.png", d, &policy),
            Err(Refusal::ParentDir)
        );
        let abs = root.path().join("secret.png");
        assert!(matches!(
            local_path(abs.to_str().unwrap(), d, &policy),
            Err(Refusal::Outside(_))
        ));
        assert!(matches!(
            local_path("missing.png", d, &policy),
            Err(Refusal::Missing(_))
        ));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&abs, dir.join("link.png")).unwrap();
            assert!(matches!(
                local_path("link.png", d, &policy),
                Err(Refusal::Outside(_))
            ));
        }
        policy.local_files = LocalFiles::Within(root.path().to_path_buf());
        assert!(local_path(abs.to_str().unwrap(), d, &policy).is_ok());
        assert!(!is_url("C:\\art\\a.png"));
    }
}
