//! Writing outputs safely: to a temporary file beside the target, renamed into place, so that a
//! failed run never leaves a partial file; and never over an input.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// What kind of output a path asks for, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Format {
    /// `.svg`
    Svg,
    /// `.json`
    Json,
    /// `.png`
    Png,
    /// `.gif`
    Gif,
    /// `.html`
    Html,
}

impl Format {
    /// The format named by `path`'s extension, if crmorph knows it.
    pub(crate) fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "svg" => Format::Svg,
            "json" => Format::Json,
            "png" | "apng" => Format::Png,
            "gif" => Format::Gif,
            "html" | "htm" => Format::Html,
            _ => return None,
        })
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Refuses an output path that is one of the inputs.
pub(crate) fn refuse_overwriting_inputs(out: &Path, inputs: &[&Path]) -> Result<()> {
    for i in inputs {
        if same_file(out, i) {
            bail!("{}: refusing to overwrite an input file", out.display());
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, then a rename.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir: PathBuf = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        bail!(
            "{}: the folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    let mut tmp = tempfile::Builder::new()
        .prefix(".crmorph-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .with_context(|| format!("{}: cannot create a temporary file", path.display()))?;
    tmp.write_all(bytes)
        .and_then(|_| tmp.flush())
        .with_context(|| format!("{}: cannot write", path.display()))?;
    // Temporary files are private (0600); a finished output gets the usual permissions: those
    // of the file it replaces, else read-write for the owner and readable by everyone.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = match std::fs::metadata(path) {
            Ok(m) => m.permissions(),
            Err(_) => std::fs::Permissions::from_mode(0o644),
        };
        tmp.as_file()
            .set_permissions(mode)
            .with_context(|| format!("{}: cannot set permissions", path.display()))?;
    }
    tmp.persist(path).map_err(|e| e.error).with_context(|| {
        format!(
            "{}: cannot move the finished file into place",
            path.display()
        )
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_and_refusal() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.json");
        write_atomic(&p, b"{}").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"{}");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&p).unwrap().permissions().mode();
            assert_eq!(
                mode & 0o777,
                0o644,
                "outputs are not private temporary files"
            );
        }
        assert!(refuse_overwriting_inputs(&p, &[&p]).is_err());
        assert!(refuse_overwriting_inputs(&dir.path().join("b.json"), &[&p]).is_ok());
        assert!(write_atomic(&dir.path().join("missing/x.json"), b"").is_err());
        // no temporary files left behind
        let n = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(n, 1);
        assert_eq!(Format::of(Path::new("x.SVG")), Some(Format::Svg));
        assert_eq!(Format::of(Path::new("x.txt")), None);
    }
}
