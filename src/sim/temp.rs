//! Temporary files and folders named `PREFIX` + `PID-…` (the process that made them), and
//! the removal of those a killed run left behind: the next run in the same folder removes
//! every entry whose process is gone. Used by the streaming check
//! ([`super::stream`]), the LinuxCNC runner ([`super::rs274`]) and the command line's
//! output writer.

use std::path::Path;

/// Age after which an entry counts as left behind where process ids cannot be checked
/// (no `/proc`).
pub const STALE_AGE: std::time::Duration = std::time::Duration::from_secs(3600);

/// True when the process `pid` that made `path` no longer runs (Linux: it has no `/proc`
/// entry); elsewhere, when `path` is older than [`STALE_AGE`]. Never true for this process.
pub fn left_behind(pid: u32, path: &Path) -> bool {
    if pid == std::process::id() {
        return false;
    }
    if Path::new("/proc/self").exists() {
        return !Path::new(&format!("/proc/{pid}")).exists();
    }
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_some_and(|age| age > STALE_AGE)
}

/// Removes the files and folders of `dir` named `prefix` + `PID` (optionally followed by
/// `-…`) that killed runs left behind: on Linux, entries whose process no longer runs (no
/// `/proc/PID`); elsewhere, entries older than an hour. This process's own are kept, and
/// errors are ignored: an entry another run still uses is kept.
pub fn remove_left_behind(dir: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(prefix) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let path = e.path();
        if left_behind(pid, &path) {
            let _ = if path.is_dir() {
                std::fs::remove_dir_all(&path)
            } else {
                std::fs::remove_file(&path)
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries of a process that is gone are removed, this process's and other names kept.
    #[test]
    fn removes_only_what_dead_processes_left() {
        let dir = std::env::temp_dir().join(format!("skinpath-temp-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // PID 0 is never a user process (no /proc/0); u32::MAX is beyond pid_max.
        let dead = [".x-4294967295-1", ".x-4294967295-dir"];
        std::fs::write(dir.join(dead[0]), b"1").unwrap();
        std::fs::create_dir_all(dir.join(dead[1]).join("inner")).unwrap();
        let own = format!(".x-{}-0", std::process::id());
        std::fs::write(dir.join(&own), b"1").unwrap();
        std::fs::write(dir.join(".y-4294967295-1"), b"1").unwrap();
        std::fs::write(dir.join(".x-notapid"), b"1").unwrap();
        remove_left_behind(&dir, ".x-");
        let left: std::collections::BTreeSet<String> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        let _ = std::fs::remove_dir_all(&dir);
        if Path::new("/proc/self").exists() {
            let want: std::collections::BTreeSet<String> =
                [own.as_str(), ".y-4294967295-1", ".x-notapid"]
                    .iter()
                    .map(|s| s.to_string())
                    .collect();
            assert_eq!(left, want);
        }
    }
}
