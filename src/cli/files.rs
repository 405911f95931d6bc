//! Reading programs and subroutine files for `check` that may not be files: only regular files are
//! opened (a FIFO would block the reader forever, `/dev/zero` or a symlink to it never
//! ends), and no more than a size cap is read.
//!
//! The kind of file is taken from `stat` (symlinks followed) before opening, so a FIFO is
//! never opened, and again from the open handle; what is read is bounded by the cap even
//! when the file grows in between.

use std::io::Read;
use std::path::Path;

/// Largest subroutine file read (bytes): called files are held in memory whole, as a
/// program below the streaming threshold is ([`skinpath::sim::STREAM_ABOVE_BYTES`]).
pub const MAX_SUB_FILE_BYTES: u64 = skinpath::sim::STREAM_ABOVE_BYTES;

/// Why a path cannot be read as a program or subroutine file.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The path names something other than a regular file.
    #[error("{path}: {kind}, not a regular file")]
    NotRegular {
        /// The path as given.
        path: String,
        /// What it is (`a FIFO`, `a character device`, ...).
        kind: &'static str,
    },
    /// The file is larger than the cap.
    #[error("{path}: larger than {max} bytes")]
    TooLarge {
        /// The path as given.
        path: String,
        /// The cap, bytes.
        max: u64,
    },
    /// The operating system's error.
    #[error("{path}: {source}")]
    Io {
        /// The path as given.
        path: String,
        /// The error.
        source: std::io::Error,
    },
}

/// What a file type is, in words, for [`FileError::NotRegular`].
fn kind_of(t: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

/// Fails unless `path` (symlinks followed) is a regular file; its size otherwise.
pub fn regular_file_size(path: &Path) -> Result<u64, FileError> {
    let name = || path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|source| FileError::Io {
        path: name(),
        source,
    })?;
    if !meta.file_type().is_file() {
        return Err(FileError::NotRegular {
            path: name(),
            kind: kind_of(meta.file_type()),
        });
    }
    Ok(meta.len())
}

/// The bytes of regular file `path`, at most `max` of them: an error for anything that is
/// not a regular file (checked before opening, so a FIFO is never opened) and for a file
/// longer than `max`.
pub fn read_regular(path: &Path, max: u64) -> Result<Vec<u8>, FileError> {
    let name = || path.display().to_string();
    let io = |source| FileError::Io {
        path: name(),
        source,
    };
    let size = regular_file_size(path)?;
    if size > max {
        return Err(FileError::TooLarge { path: name(), max });
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.file_type().is_file() {
        return Err(FileError::NotRegular {
            path: name(),
            kind: kind_of(meta.file_type()),
        });
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > max {
        return Err(FileError::TooLarge { path: name(), max });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_and_capped() {
        let dir = std::env::temp_dir().join(format!("skinpath-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap_or_default();
        let f = dir.join("a.ngc");
        std::fs::write(&f, b"G0 X1\n").unwrap_or_default();
        assert_eq!(read_regular(&f, 100).ok(), Some(b"G0 X1\n".to_vec()));
        assert!(matches!(
            read_regular(&f, 3),
            Err(FileError::TooLarge { max: 3, .. })
        ));
        assert!(matches!(
            read_regular(&dir, 100),
            Err(FileError::NotRegular {
                kind: "a folder",
                ..
            })
        ));
        let e = read_regular(Path::new("/dev/zero"), 100);
        assert!(
            matches!(
                e,
                Err(FileError::NotRegular {
                    kind: "a character device",
                    ..
                })
            ),
            "{e:?}"
        );
        assert!(matches!(
            read_regular(&dir.join("none.ngc"), 100),
            Err(FileError::Io { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap_or_default();
    }
}
