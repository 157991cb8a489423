//! Reading one file under the policy: regular files only, and never more than the byte limit.
//!
//! A path may name `/dev/zero`, a FIFO that never ends, or a socket; `std::fs::read` would read
//! the first forever and block on the second. Here the file is opened without blocking, checked
//! to be a regular file on the open handle (so a swap after the check cannot fool it), and read
//! through a cap one byte past the limit.

use std::io::Read;
use std::path::Path;

use super::{Limit, Limits};
use crate::error::{Error, Result};

/// The bytes of the regular file at `path`, at most `limits.input_bytes` of them; `name` is how
/// errors call it.
pub fn read_file(path: &Path, name: &str, limits: &Limits) -> Result<Vec<u8>> {
    let cannot = |e: std::io::Error| Error::input(name, format!("cannot read the file: {e}"));
    // Refuse what is not a regular file before opening it: opening a FIFO for reading blocks
    // until a writer comes.
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        return Err(not_regular(name, &meta));
    }
    let file = open_nonblocking(path).map_err(cannot)?;
    let meta = file.metadata().map_err(cannot)?;
    if !meta.is_file() {
        return Err(not_regular(name, &meta));
    }
    if meta.len() > limits.input_bytes {
        return Err(too_long(name, "the file", meta.len(), limits));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limits.input_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > limits.input_bytes {
        // The file grew while it was read.
        return Err(too_long(name, "the file", bytes.len() as u64, limits));
    }
    Ok(bytes)
}

/// The error for `len` bytes (read so far, or claimed) over the byte limit; `how` says what
/// was measured ("the file", "decompressed, it", "with its entities expanded, it").
pub(crate) fn too_long(name: &str, how: &str, len: u64, limits: &Limits) -> Error {
    Limit::InputBytes.exceeded(name, &format!("{how} has {len} bytes or more"), limits)
}

fn not_regular(name: &str, meta: &std::fs::Metadata) -> Error {
    let kind = describe(meta.file_type());
    Error::input(
        name,
        format!("cannot read the file: it is {kind}, not a regular file"),
    )
}

fn describe(t: std::fs::FileType) -> &'static str {
    if t.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
    }
    "a special file"
}

#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::File::open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_within_the_limit_only() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.svg");
        std::fs::write(&p, b"<svg/>").unwrap();
        let mut l = Limits::default();
        assert_eq!(read_file(&p, "a.svg", &l).unwrap(), b"<svg/>");
        l.input_bytes = 5;
        let e = read_file(&p, "a.svg", &l).unwrap_err().to_string();
        assert!(e.contains("--max-input-bytes"), "{e}");
        let e = read_file(dir.path(), "d", &l).unwrap_err().to_string();
        assert!(e.contains("a folder"), "{e}");
        #[cfg(unix)]
        {
            let e = read_file(Path::new("/dev/zero"), "z", &Limits::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains("a device, not a regular file"), "{e}");
        }
    }
}
