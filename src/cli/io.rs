//! File input and output for the commands: reading with the path in every error, and
//! atomic writes (temporary file `.skinpath-tmp-PID-NAME` in the target directory, then
//! rename) so that a failed run never leaves a half-written file behind and never touches
//! the input; the outputs of one run are written as a set, and temporary files of killed
//! runs are removed by the next run that writes into their folder.

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
/// ([`skinpath::sim::temp::remove_left_behind`]).
pub fn remove_stale_temporaries(dir: &Path) {
    skinpath::sim::temp::remove_left_behind(dir, TMP_PREFIX);
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

/// Writes several files as a set: every one goes to its temporary file first, and only
/// when all of them are written are they renamed into place (the first, the main output,
/// last, so a reader never sees a preview without its program). On any error no target
/// is touched and every temporary file is removed.
pub fn write_set(files: &[(&Path, Vec<u8>)]) -> Result<()> {
    let mut tmps: Vec<PathBuf> = Vec::new();
    for (path, bytes) in files {
        match write_temporary(path, bytes) {
            Ok(t) => tmps.push(t),
            Err(e) => {
                for t in &tmps {
                    let _ = fs::remove_file(t);
                }
                return Err(e);
            }
        }
    }
    for (k, ((path, _), tmp)) in files.iter().zip(&tmps).enumerate().rev() {
        if let Err(e) = fs::rename(tmp, path) {
            for t in &tmps[..=k] {
                let _ = fs::remove_file(t);
            }
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
