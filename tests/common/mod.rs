//! What several integration tests share: the list of shipped examples (examples/*.toml,
//! kept in step with the folder by `cli::every_example_is_listed`), a fresh temporary
//! directory and a run of the built binary. Each test crate uses only part of it.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The crate's root folder.
pub const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The names of the shipped example designs, without `.toml`.
pub const EXAMPLES: [&str; 9] = [
    "brush",
    "calligraphy",
    "circles",
    "gclef",
    "loop",
    "neon_word",
    "ring_o",
    "seahorse",
    "snake",
];

/// A fresh, empty directory unique to this process and call.
pub fn tmpdir(tag: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("skinpath-itest-{}-{tag}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the built `skinpath` binary in the crate's root folder.
pub fn skinpath(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .args(args)
        .current_dir(ROOT)
        .output()
        .expect("run skinpath")
}
