//! Writing outputs safely: to a temporary file beside the target, renamed into place, so that a
//! failed run never leaves a partial file; frames for `--frames-dir` staged in a temporary
//! folder and moved in only after the main output succeeded; and never over an input.

use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::interrupt::{self, Registered};

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
    /// `.lottie.json`: Lottie JSON.
    Lottie,
    /// `.lottie`: a dotLottie archive.
    DotLottie,
}

impl Format {
    /// The format named by `path`'s extension, if crmorph knows it.
    pub(crate) fn of(path: &Path) -> Option<Format> {
        let name = path.file_name()?.to_str()?.to_ascii_lowercase();
        if name.ends_with(".lottie.json") {
            return Some(Format::Lottie);
        }
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "lottie" => Format::DotLottie,
            "svg" => Format::Svg,
            "json" => Format::Json,
            "png" | "apng" => Format::Png,
            "gif" => Format::Gif,
            "html" | "htm" => Format::Html,
            _ => return None,
        })
    }

    /// The extension that names the format, with its dot, for messages.
    pub(crate) fn extension(self) -> &'static str {
        match self {
            Format::Svg => ".svg",
            Format::Json => ".json",
            Format::Png => ".png",
            Format::Gif => ".gif",
            Format::Html => ".html",
            Format::Lottie => ".lottie.json",
            Format::DotLottie => ".lottie",
        }
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
    write_streamed(path, |w| {
        // An error here is recorded by the sink and reported by `write_streamed`.
        w.write_all(bytes)
            .map_err(|_| crmorph::Error::internal("write failed"))
    })
}

/// The temporary file an output is written to, seekable (APNG patches its frame count),
/// recording the first I/O error so that a full disk is reported as such, not as an encoder
/// failure.
pub(crate) struct Sink<'a> {
    file: std::io::BufWriter<&'a mut std::fs::File>,
    error: Option<std::io::Error>,
    /// Bytes that may still be written, and why no more (see [`Sink::cap`]).
    cap: Option<(u64, String)>,
}

impl Sink<'_> {
    /// Refuses to write more than `limit` bytes: an output too large for its readers (JSON
    /// over 2 GiB) fails as it grows, with `hint`, rather than once it is complete.
    pub(crate) fn cap(&mut self, limit: u64, hint: &str) {
        let size = match limit {
            l if l >= 1 << 30 && l % (1 << 30) == 0 => format!("{} GiB", l >> 30),
            l => format!("{l} bytes"),
        };
        let why = format!("the output would be larger than {size}; {hint}");
        self.cap = Some((limit, why));
    }

    fn record<T>(&mut self, r: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &r {
            if self.error.is_none() {
                self.error = Some(std::io::Error::new(e.kind(), e.to_string()));
            }
        }
        r
    }
}

impl Write for Sink<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if let Some((left, why)) = &mut self.cap {
            if buf.len() as u64 > *left {
                let e = Err(std::io::Error::other(why.clone()));
                return self.record(e);
            }
        }
        let r = self.file.write(buf);
        if let (Ok(n), Some((left, _))) = (&r, &mut self.cap) {
            *left -= *n as u64;
        }
        self.record(r)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.file.flush();
        self.record(r)
    }
}

impl Seek for Sink<'_> {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        let r = self.file.seek(pos);
        self.record(r)
    }
}

/// A temporary file registered for removal on a signal; the file goes first on drop.
struct Temporary {
    file: tempfile::NamedTempFile,
    _registered: Registered,
}

/// Writes the output at `path` with `write`, streamed into a temporary file in the same folder
/// (`.crmorph-<pid>-XXXXXX.tmp`, removed on failure or on a signal) and renamed into place
/// once complete, so that a failed or interrupted run leaves no partial file. Temporaries that
/// killed runs left in that folder are removed first.
pub(crate) fn write_streamed(
    path: &Path,
    write: impl FnOnce(&mut Sink) -> crmorph::Result<()>,
) -> Result<()> {
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
    interrupt::clean_stale(&dir);
    let mut tmp = interrupt::atomically(|list| -> Result<Temporary> {
        let file = tempfile::Builder::new()
            .prefix(&interrupt::file_prefix())
            .suffix(".tmp")
            .tempfile_in(&dir)
            .with_context(|| format!("{}: cannot create a temporary file", path.display()))?;
        list.push(file.path().to_path_buf());
        Ok(Temporary {
            _registered: Registered(file.path().to_path_buf()),
            file,
        })
    })?;
    let mut sink = Sink {
        file: std::io::BufWriter::new(tmp.file.as_file_mut()),
        error: None,
        cap: None,
    };
    let written = write(&mut sink).and_then(|()| {
        sink.flush()
            .map_err(|_| crmorph::Error::internal("write failed"))
    });
    if let Some(e) = sink.error.take() {
        return Err(e).with_context(|| format!("{}: cannot write", path.display()));
    }
    drop(sink);
    written?;
    // Temporary files are private (0600); a finished output gets the usual permissions: those
    // of the file it replaces, else read-write for the owner and readable by everyone.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = match std::fs::metadata(path) {
            Ok(m) => m.permissions(),
            Err(_) => std::fs::Permissions::from_mode(0o644),
        };
        tmp.file
            .as_file()
            .set_permissions(mode)
            .with_context(|| format!("{}: cannot set permissions", path.display()))?;
    }
    let Temporary { file, _registered } = tmp;
    let tmp_path = file.path().to_path_buf();
    interrupt::atomically(|list| {
        let r = file.persist(path);
        list.retain(|p| p != &tmp_path);
        r
    })
    .map_err(|e| e.error)
    .with_context(|| {
        format!(
            "{}: cannot move the finished file into place",
            path.display()
        )
    })?;
    Ok(())
}

/// Frames written one by one into a staging folder, moved into the frames folder by
/// [`FramesDir::commit`] once the main output is in place, so that a failed or interrupted run
/// leaves no frames behind. The staging folder (a hidden `.crmorph-frames-<pid>-…` temporary
/// folder) is removed when this is dropped without a commit, and on a signal.
pub(crate) struct FramesDir {
    /// The staging folder: beside the frames folder when that does not exist yet (the commit
    /// renames it into place in one step), inside it otherwise (the commit moves the files).
    staging: tempfile::TempDir,
    /// Its registration for removal on a signal (after `staging`: dropped second).
    registered: Registered,
    /// The frames folder.
    dir: PathBuf,
    /// Whether the frames folder existed before.
    existed: bool,
    /// The frames' file names.
    names: Vec<std::ffi::OsString>,
}

impl FramesDir {
    /// An empty staging folder for the frames folder `dir`, creating `dir`'s parent folders if
    /// needed (and removing what killed runs left there). Nothing is in `dir` yet.
    pub(crate) fn create(dir: &Path) -> Result<Self> {
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
        interrupt::clean_stale(&home);
        let (staging, registered) = interrupt::atomically(|list| -> Result<_> {
            let staging = tempfile::Builder::new()
                .prefix(&interrupt::folder_prefix())
                .tempdir_in(&home)
                .with_context(|| format!("{}: cannot create a temporary folder", dir.display()))?;
            list.push(staging.path().to_path_buf());
            let registered = Registered(staging.path().to_path_buf());
            Ok((staging, registered))
        })?;
        Ok(FramesDir {
            staging,
            registered,
            dir: dir.to_path_buf(),
            existed,
            names: Vec::new(),
        })
    }

    /// Writes `bytes` as the frame `file` (a path in the frames folder) into the staging
    /// folder.
    pub(crate) fn add(&mut self, file: &Path, bytes: &[u8]) -> Result<()> {
        let name = file
            .file_name()
            .with_context(|| format!("{}: not a file name", file.display()))?;
        // Written holding the registry's lock: a signal that is removing the staging folder
        // would otherwise race a frame appearing in it, and the folder's removal fail on a
        // folder that is not empty (seen under load: the staging folder left behind).
        let path = self.staging.path().join(name);
        interrupt::atomically(|_| std::fs::write(&path, bytes))
            .with_context(|| format!("{}: cannot write", file.display()))?;
        self.names.push(name.to_owned());
        Ok(())
    }

    /// Moves the staged frames into the frames folder: the staging folder renamed to it when
    /// it did not exist, else each file renamed into it (the frames moved so far are removed
    /// again if one fails). A signal waits until this is done.
    pub(crate) fn commit(self) -> Result<()> {
        let FramesDir {
            staging,
            registered,
            dir,
            existed,
            names,
        } = self;
        let cannot = |what: &str| format!("{}: cannot {what}", dir.display());
        let done = interrupt::atomically(|list| -> Result<()> {
            if !existed {
                #[cfg(unix)]
                {
                    use std::os::unix::fs::PermissionsExt;
                    // Temporary folders are private (0700); the frames folder gets the usual
                    // mode.
                    std::fs::set_permissions(
                        staging.path(),
                        std::fs::Permissions::from_mode(0o755),
                    )
                    .with_context(|| cannot("set permissions"))?;
                }
                std::fs::rename(staging.path(), &dir)
                    .with_context(|| cannot("move the frames into place"))?;
                list.retain(|p| p != staging.path());
                // Renamed away: nothing is left for the temporary folder to remove.
                let _ = staging.keep();
                return Ok(());
            }
            for (k, name) in names.iter().enumerate() {
                if let Err(e) = std::fs::rename(staging.path().join(name), dir.join(name)) {
                    for moved in &names[..k] {
                        let _ = std::fs::remove_file(dir.join(moved));
                    }
                    return Err(e).with_context(|| cannot("move the frames into place"));
                }
            }
            Ok(())
        });
        drop(registered);
        done
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
        assert_eq!(
            Format::of(Path::new("a/x.Lottie.JSON")),
            Some(Format::Lottie)
        );
        assert_eq!(Format::of(Path::new("x.json")), Some(Format::Json));
        assert_eq!(Format::of(Path::new("x.lottie")), Some(Format::DotLottie));
    }

    #[test]
    fn a_capped_output_fails_as_it_grows_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.json");
        let e = write_streamed(&p, |w| {
            w.cap(10, "use fewer frames");
            for _ in 0..4 {
                w.write_all(b"12345")
                    .map_err(|_| crmorph::Error::internal("write failed"))?;
            }
            Ok(())
        })
        .unwrap_err();
        let e = format!("{e:#}");
        assert!(
            e.contains("big.json: cannot write: the output would be larger than 10 bytes"),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    fn stage(dir: &Path, files: &[PathBuf], contents: &[Vec<u8>]) -> FramesDir {
        let mut staged = FramesDir::create(dir).unwrap();
        for (f, c) in files.iter().zip(contents) {
            staged.add(f, c).unwrap();
        }
        staged
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
        let staged = stage(&new, &files(&new), &contents);
        assert!(!new.exists());
        staged.commit().unwrap();
        assert_eq!(listing(&new), ["frame_000.svg", "frame_001.svg"]);
        assert_eq!(listing(&root.path().join("out")), ["frames"]);
        // An existing folder: its other files stay, the frames arrive on commit only.
        let old = root.path().join("old");
        std::fs::create_dir(&old).unwrap();
        std::fs::write(old.join("keep.txt"), b"").unwrap();
        let staged = stage(&old, &files(&old), &contents);
        assert_eq!(listing(&old).len(), 2, "keep.txt and the staging folder");
        drop(staged);
        assert_eq!(
            listing(&old),
            ["keep.txt"],
            "dropped without a commit: nothing left"
        );
        stage(&old, &files(&old), &contents).commit().unwrap();
        assert_eq!(
            listing(&old),
            ["frame_000.svg", "frame_001.svg", "keep.txt"]
        );
        assert_eq!(std::fs::read(old.join("frame_001.svg")).unwrap(), b"b");
    }
}
