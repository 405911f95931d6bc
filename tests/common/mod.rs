//! What several integration tests share: the list of shipped examples (examples/*.toml,
//! kept in step with the folder by `cli::every_example_is_listed`), a fresh temporary
//! directory, a run of the built binary and the header of a check-corpus program. Each
//! test crate uses only part of it.
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

/// The setup a check-corpus program (tests/sim_corpus) carries in its `;` comments: the
/// `; config <toml line>` lines as one CheckConfig, and each
/// `; design outside|inside|either x,y x,y ...` line as a design boundary for the gouge
/// check.
pub fn corpus_header(
    src: &str,
) -> (
    skinpath::sim::CheckConfig,
    Vec<skinpath::sim::DesignBoundary>,
) {
    use skinpath::sim::{DesignBoundary, KeepSide};
    let mut toml_cfg = String::new();
    let mut design = Vec::new();
    for line in src.lines() {
        let Some(d) = line.trim().strip_prefix(';') else {
            continue;
        };
        let d = d.trim();
        if let Some(t) = d.strip_prefix("config ") {
            toml_cfg.push_str(t);
            toml_cfg.push('\n');
        } else if let Some(t) = d.strip_prefix("design ") {
            let (side, pts) = t.split_once(' ').expect("design side");
            let keep = match side {
                "outside" => KeepSide::Outside,
                "inside" => KeepSide::Inside,
                _ => KeepSide::Either,
            };
            let v: Vec<f64> = pts
                .split([' ', ','])
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().unwrap_or_else(|_| panic!("bad number {t:?}")))
                .collect();
            let p: Vec<_> = v
                .chunks(2)
                .map(|q| skinpath::geom::DVec2::new(q[0], q[1]))
                .collect();
            design.push(DesignBoundary::new(&p, keep));
        }
    }
    (toml::from_str(&toml_cfg).expect("config lines"), design)
}
