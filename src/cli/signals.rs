//! Clean exit on SIGINT and SIGTERM: the temporary files this process made are removed
//! before it exits with the conventional status, 128 + the signal's number (130 for
//! SIGINT, 143 for SIGTERM). Without this an interrupted `check` of a large program left
//! its `.skinpath-check-PID-N` segment files (gigabytes) in the temporary folder, and an
//! interrupted write its `.skinpath-tmp-PID-NAME` beside the target, until the next run.
//!
//! The temporary files of every writer carry this process's id after their prefix, so the
//! handler removes them by name: the library's ([`skinpath::sim::TEMP_PREFIXES`], the
//! streaming check's and the LinuxCNC runner's) in the system's
//! temporary folder, and the output writer's ([`super::io::TMP_PREFIX`]) in the folders
//! registered with [`watch_folder`] before a temporary file is made there.

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Exit status base for a run ended by a signal: the status is this plus the signal's
/// number, as shells report it.
pub const EXIT_SIGNAL_BASE: i32 = 128;

/// Folders where this process makes output temporaries ([`super::io::TMP_PREFIX`]).
static FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers `dir` as a folder where this process makes temporary output files, so that a
/// signal removes them there. Call before making the first one.
pub fn watch_folder(dir: &Path) {
    if let Ok(mut f) = FOLDERS.lock()
        && !f.iter().any(|d| d == dir)
    {
        f.push(dir.to_path_buf());
    }
}

/// Installs the handler: a thread waits for SIGINT or SIGTERM, removes this process's
/// temporary files and exits with [`EXIT_SIGNAL_BASE`] + the signal. When the handler
/// cannot be installed the signals keep their default action (the next run still removes
/// what a killed run left behind).
pub fn install() {
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let waiter = std::thread::Builder::new().spawn(move || {
        if let Some(signal) = signals.forever().next() {
            remove_own_temporaries();
            std::process::exit(EXIT_SIGNAL_BASE + signal);
        }
    });
    // A thread that cannot be started (the thread or address-space limit reached) drops
    // `signals` unstarted, which gives the signals their default action back.
    drop(waiter);
}

/// Removes every temporary file and folder of this process (see the module docs).
fn remove_own_temporaries() {
    let pid = std::process::id();
    let tmp = std::env::temp_dir();
    for prefix in skinpath::sim::TEMP_PREFIXES {
        remove_named(&tmp, &format!("{prefix}{pid}-"));
    }
    let folders = FOLDERS.lock().map(|f| f.clone()).unwrap_or_default();
    for dir in folders {
        remove_named(&dir, &format!("{}{pid}-", super::io::TMP_PREFIX));
    }
}

/// Removes the entries of `dir` whose names start with `prefix` (files and folders);
/// errors are ignored, as the process is about to end.
fn remove_named(dir: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        if !e.file_name().to_string_lossy().starts_with(prefix) {
            continue;
        }
        let path = e.path();
        let _ = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
    }
}
