//! File input and output for the commands: reading with the path in every error, and
//! atomic writes (temporary file `.skinpath-tmp-PID-NAME` in the target directory, then
//! rename) so that a failed run never leaves a half-written file behind and never touches
//! the input; the outputs of one run are written as a set, and temporary files of killed
//! runs are removed by the next run that writes into their folder. A target that exists
//! and is not a regular file (`-o /dev/null`, a FIFO) is written in place, never replaced:
//! see [`Target`].

use anyhow::{Context, Result, bail};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The whole file as UTF-8 text, with the path in the error.
pub fn read_text(path: &Path) -> Result<String> {
    fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Fail when `out` names the same file as one of the `inputs`.
pub fn refuse_overwriting_inputs(out: &Path, inputs: &[&Path]) -> Result<()> {
    let out_abs = absolute(out);
    for i in inputs {
        if absolute(i) == out_abs {
            bail!(
                "refusing to write {}: it is an input of this run",
                out.display()
            );
        }
    }
    Ok(())
}

fn absolute(p: &Path) -> PathBuf {
    fs::canonicalize(p).unwrap_or_else(|_| {
        std::env::current_dir()
            .map(|d| d.join(p))
            .unwrap_or_else(|_| p.to_path_buf())
    })
}

/// Prefix of the temporary files of a write: `.skinpath-tmp-PID-NAME`, recognisable, and
/// removed by the next run in that folder when the process that made it is gone.
pub const TMP_PREFIX: &str = ".skinpath-tmp-";

/// True when `a` and `b` name the same file (existing or not).
pub fn same_file(a: &Path, b: &Path) -> bool {
    absolute(a) == absolute(b)
}

fn dir_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Removes the temporary files of killed runs ([`TMP_PREFIX`]) from `dir`
/// ([`skinpath::sim::remove_left_behind`]).
pub fn remove_stale_temporaries(dir: &Path) {
    skinpath::sim::remove_left_behind(dir, TMP_PREFIX);
}

/// Writes `bytes` to a temporary file beside `path`, flushed and synced; returns its path.
fn write_temporary(path: &Path, bytes: &[u8]) -> Result<PathBuf> {
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file name", path.display()))?
        .to_string_lossy()
        .into_owned();
    let dir = dir_of(path);
    if !dir.is_dir() {
        bail!(
            "cannot write {}: the folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    remove_stale_temporaries(&dir);
    super::signals::watch_folder(&dir);
    let tmp = dir.join(format!("{TMP_PREFIX}{}-{name}", std::process::id()));
    let result = (|| -> Result<()> {
        let mut f =
            fs::File::create(&tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
        f.write_all(bytes)
            .with_context(|| format!("cannot write {}", tmp.display()))?;
        f.sync_all()
            .with_context(|| format!("cannot sync {}", tmp.display()))?;
        Ok(())
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Write `bytes` to `path` atomically: a temporary file beside it, flushed and synced, then
/// renamed over the target. On any error the temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_set(&[(path, bytes.to_vec())])
}

/// How an output target is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// A regular file or a new name: a temporary file beside it, renamed over it.
    Replace,
    /// An existing character device or FIFO (`/dev/null`, `/dev/stdout`, a named pipe):
    /// opened and written in place, as a shell redirection does. Renaming a temporary file
    /// over it would replace the device with a regular file.
    InPlace,
}

/// How `path` is to be written; an error for targets that are neither regular files nor
/// character devices or FIFOs (a folder, a block device, a socket).
fn target_of(path: &Path) -> Result<Target> {
    let Ok(meta) = fs::metadata(path) else {
        return Ok(Target::Replace);
    };
    let kind = meta.file_type();
    if kind.is_file() {
        return Ok(Target::Replace);
    }
    if kind.is_dir() {
        bail!("cannot write {}: it is a folder", path.display());
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_char_device() || kind.is_fifo() {
            return Ok(Target::InPlace);
        }
    }
    bail!(
        "cannot write {}: it is neither a regular file nor a character device or FIFO",
        path.display()
    )
}

/// Writes `bytes` into the existing non-regular file `path` ([`Target::InPlace`]).
fn write_in_place(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut f = fs::OpenOptions::new()
        .write(true)
        .open(path)
        .with_context(|| format!("cannot open {}", path.display()))?;
    f.write_all(bytes)
        .and_then(|()| f.flush())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Writes several files as a set: every regular target goes to its temporary file first;
/// when all of them are written, the in-place targets ([`Target`]) are written, then the
/// temporary files are renamed into place (the first, the main output, last, so a reader
/// never sees a preview without its program). On any error before the renames no regular
/// target is touched and every temporary file is removed.
pub fn write_set(files: &[(&Path, Vec<u8>)]) -> Result<()> {
    let targets = files
        .iter()
        .map(|(p, _)| target_of(p))
        .collect::<Result<Vec<_>>>()?;
    let mut tmps: Vec<Option<PathBuf>> = Vec::new();
    let remove = |tmps: &[Option<PathBuf>]| {
        for t in tmps.iter().flatten() {
            let _ = fs::remove_file(t);
        }
    };
    for ((path, bytes), target) in files.iter().zip(&targets) {
        if *target == Target::InPlace {
            tmps.push(None);
            continue;
        }
        match write_temporary(path, bytes) {
            Ok(t) => tmps.push(Some(t)),
            Err(e) => {
                remove(&tmps);
                return Err(e);
            }
        }
    }
    for ((path, bytes), target) in files.iter().zip(&targets) {
        if *target == Target::InPlace
            && let Err(e) = write_in_place(path, bytes)
        {
            remove(&tmps);
            return Err(e);
        }
    }
    for (k, ((path, _), tmp)) in files.iter().zip(&tmps).enumerate().rev() {
        let Some(tmp) = tmp else { continue };
        if let Err(e) = fs::rename(tmp, path) {
            remove(&tmps[..=k]);
            return Err(e)
                .with_context(|| format!("cannot move {} to {}", tmp.display(), path.display()));
        }
    }
    Ok(())
}

/// The lower-case extension of `path`, or "" when there is none.
pub fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}
