//! Writing outputs safely: to a temporary file beside the target, renamed into place, so that a
//! failed run never leaves a partial file; frames for `--frames-dir` staged in a temporary
//! folder and moved in only after the main output succeeded; and never over an input.

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

/// Frames written into a staging folder, moved into the frames folder by [`FramesDir::commit`]
/// once the main output is in place, so that a failed run leaves no frames behind. The staging
/// folder (a hidden `.crmorph-frames-…` temporary folder) is removed when this is dropped
/// without a commit.
pub(crate) struct FramesDir {
    /// The staging folder: beside the frames folder when that does not exist yet (the commit
    /// renames it into place in one step), inside it otherwise (the commit moves the files).
    staging: tempfile::TempDir,
    /// The frames folder.
    dir: PathBuf,
    /// Whether the frames folder existed before.
    existed: bool,
    /// The frames' file names.
    names: Vec<std::ffi::OsString>,
}

impl FramesDir {
    /// Writes `contents[i]` as the file `files[i]` (all in the folder `dir`) into a staging
    /// folder, creating `dir`'s parent folders if needed. Nothing is in `dir` yet.
    pub(crate) fn stage(dir: &Path, files: &[PathBuf], contents: &[Vec<u8>]) -> Result<Self> {
        let existed = dir.is_dir();
        if dir.exists() && !existed {
            bail!("{}: exists and is not a folder", dir.display());
        }
        let home = if existed {
            dir.to_path_buf()
        } else {
            let parent = match dir.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            std::fs::create_dir_all(&parent)
                .with_context(|| format!("{}: cannot create the folder", parent.display()))?;
            parent
        };
        let staging = tempfile::Builder::new()
            .prefix(".crmorph-frames-")
            .tempdir_in(&home)
            .with_context(|| format!("{}: cannot create a temporary folder", dir.display()))?;
        let mut names = Vec::with_capacity(files.len());
        for (file, bytes) in files.iter().zip(contents) {
            let name = file
                .file_name()
                .with_context(|| format!("{}: not a file name", file.display()))?;
            std::fs::write(staging.path().join(name), bytes)
                .with_context(|| format!("{}: cannot write", file.display()))?;
            names.push(name.to_owned());
        }
        Ok(FramesDir {
            staging,
            dir: dir.to_path_buf(),
            existed,
            names,
        })
    }

    /// Moves the staged frames into the frames folder: the staging folder renamed to it when
    /// it did not exist, else each file renamed into it (the frames moved so far are removed
    /// again if one fails).
    pub(crate) fn commit(self) -> Result<()> {
        let cannot = |what: &str| format!("{}: cannot {what}", self.dir.display());
        if !self.existed {
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                // Temporary folders are private (0700); the frames folder gets the usual mode.
                std::fs::set_permissions(
                    self.staging.path(),
                    std::fs::Permissions::from_mode(0o755),
                )
                .with_context(|| cannot("set permissions"))?;
            }
            std::fs::rename(self.staging.path(), &self.dir)
                .with_context(|| cannot("move the frames into place"))?;
            // Renamed away: nothing is left for the temporary folder to remove.
            let _ = self.staging.keep();
            return Ok(());
        }
        for (k, name) in self.names.iter().enumerate() {
            if let Err(e) = std::fs::rename(self.staging.path().join(name), self.dir.join(name)) {
                for moved in &self.names[..k] {
                    let _ = std::fs::remove_file(self.dir.join(moved));
                }
                return Err(e).with_context(|| cannot("move the frames into place"));
            }
        }
        Ok(())
    }
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

    #[test]
    fn staged_frames_appear_only_on_commit() {
        let root = tempfile::tempdir().unwrap();
        let files = |dir: &Path| vec![dir.join("frame_000.svg"), dir.join("frame_001.svg")];
        let contents = vec![b"a".to_vec(), b"b".to_vec()];
        let listing = |dir: &Path| -> Vec<String> {
            let mut v: Vec<String> = std::fs::read_dir(dir)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        };
        // A new folder, nested: renamed into place in one step.
        let new = root.path().join("out/frames");
        let staged = FramesDir::stage(&new, &files(&new), &contents).unwrap();
        assert!(!new.exists());
        staged.commit().unwrap();
        assert_eq!(listing(&new), ["frame_000.svg", "frame_001.svg"]);
        assert_eq!(listing(&root.path().join("out")), ["frames"]);
        // An existing folder: its other files stay, the frames arrive on commit only.
        let old = root.path().join("old");
        std::fs::create_dir(&old).unwrap();
        std::fs::write(old.join("keep.txt"), b"").unwrap();
        let staged = FramesDir::stage(&old, &files(&old), &contents).unwrap();
        assert_eq!(listing(&old).len(), 2, "keep.txt and the staging folder");
        drop(staged);
        assert_eq!(
            listing(&old),
            ["keep.txt"],
            "dropped without a commit: nothing left"
        );
        FramesDir::stage(&old, &files(&old), &contents)
            .unwrap()
            .commit()
            .unwrap();
        assert_eq!(
            listing(&old),
            ["frame_000.svg", "frame_001.svg", "keep.txt"]
        );
        assert_eq!(std::fs::read(old.join("frame_001.svg")).unwrap(), b"b");
    }
}
