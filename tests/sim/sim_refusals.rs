//! Fault corpus of controller refusals (tests/sim_corpus/refusals/): programs LinuxCNC or
//! GRBL refuse, each with the finding expected per dialect (the table below; the README's
//! check section gives the source of each row). A dialect not listed for a program is not
//! asserted; a listed `None` means no finding of severity error or warning at all.
//! When `rs274` (linuxcnc-uspace) is installed, the programs with a LinuxCNC error are also
//! run through it, which must refuse them too.

use skinpath::sim::{self, Backend, CheckConfig, Dialect, Severity};
use std::path::Path;

use Severity::{Error, Warning};

type Expect = Option<(Severity, &'static str, usize)>;

/// (file, [(dialect, expected finding: severity, id, line)]).
const TABLE: &[(&str, &[(Dialect, Expect)])] = &[
    (
        "g1_without_feed.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 3))),
            (Dialect::Grbl, Some((Error, "no-feed-rate", 3))),
            (Dialect::Marlin, Some((Warning, "no-feed-rate", 3))),
            (Dialect::Smoothie, Some((Warning, "no-feed-rate", 3))),
            (Dialect::Generic, Some((Warning, "no-feed-rate", 3))),
        ],
    ),
    (
        "g1_f0.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 2))),
            (Dialect::Grbl, Some((Error, "no-feed-rate", 2))),
            (Dialect::Marlin, Some((Warning, "no-feed-rate", 2))),
            (Dialect::Smoothie, Some((Warning, "no-feed-rate", 2))),
        ],
    ),
    (
        "f0_after_feed.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 3))),
            (Dialect::Grbl, Some((Error, "no-feed-rate", 3))),
            (Dialect::Marlin, Some((Warning, "no-feed-rate", 3))),
        ],
    ),
    (
        "arc_without_feed.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 3))),
            (Dialect::Grbl, Some((Error, "no-feed-rate", 3))),
            (Dialect::Marlin, Some((Warning, "no-feed-rate", 3))),
        ],
    ),
    (
        "drill_cycle_without_feed.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 3))),
            (Dialect::Grbl, Some((Error, "unsupported-code", 3))),
        ],
    ),
    (
        "inverse_time_without_f.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "invalid-value", 4))),
            (Dialect::Grbl, Some((Error, "invalid-value", 4))),
        ],
    ),
    (
        "percent_end_without_start.nc",
        &[
            (
                Dialect::Linuxcnc,
                Some((Warning, "percent-without-start", 3)),
            ),
            (
                Dialect::Generic,
                Some((Warning, "percent-without-start", 3)),
            ),
            (Dialect::Grbl, None),
        ],
    ),
    (
        "parameter.nc",
        &[
            (Dialect::Grbl, Some((Error, "unsupported-code", 1))),
            (Dialect::Marlin, Some((Error, "unsupported-code", 1))),
            (Dialect::Linuxcnc, None),
        ],
    ),
    (
        "o_word.nc",
        &[
            (Dialect::Grbl, Some((Error, "unsupported-code", 2))),
            (Dialect::Linuxcnc, None),
        ],
    ),
    (
        "probe_without_axes.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-axis-words", 3))),
            (Dialect::Generic, Some((Warning, "cannot-simulate", 3))),
        ],
    ),
    (
        "axis_in_canned_cycle.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "axis-in-cycle", 5))),
            (Dialect::Grbl, Some((Error, "unsupported-code", 4))),
            (Dialect::Generic, Some((Warning, "unsupported-code", 5))),
        ],
    ),
    (
        "g1_alone_without_feed.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "no-feed-rate", 4))),
            (Dialect::Grbl, None),
            (Dialect::Marlin, None),
            (Dialect::Generic, None),
        ],
    ),
    (
        "nested_sub_definition.nc",
        &[
            (Dialect::Linuxcnc, Some((Error, "o-word", 3))),
            (Dialect::Generic, Some((Error, "o-word", 3))),
            (Dialect::Grbl, Some((Error, "unknown-word", 3))),
        ],
    ),
    (
        "control_clean.nc",
        &[
            (Dialect::Linuxcnc, None),
            (Dialect::Grbl, None),
            (Dialect::Marlin, None),
            (Dialect::Smoothie, None),
            (Dialect::Generic, None),
        ],
    ),
];

fn source(file: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/sim_corpus/refusals")
        .join(file);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn run(src: &str, dialect: Dialect) -> sim::Report {
    let cfg = CheckConfig {
        dialect,
        ..CheckConfig::default()
    };
    let prog = sim::load(Backend::Builtin, src, &cfg);
    sim::check(&prog, &cfg, &[])
}

#[test]
fn every_refusal_gets_its_finding_per_dialect() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sim_corpus/refusals");
    let files = std::fs::read_dir(&dir).expect("refusal corpus").count();
    assert_eq!(files, TABLE.len(), "every corpus file has a row in TABLE");
    for (file, rows) in TABLE {
        let src = source(file);
        for (dialect, want) in *rows {
            let r = run(&src, *dialect);
            let ctx = format!("{file} --dialect {}:\n{r}", dialect.name());
            match want {
                Some((sev, id, line)) => {
                    assert!(
                        r.findings
                            .iter()
                            .any(|f| f.severity == *sev && f.id == *id && f.lines.contains(line)),
                        "{ctx}\nmissing {sev} {id} at line {line}"
                    );
                    // A refusal is the only kind of error: nothing else is wrong with it.
                    assert!(
                        r.findings
                            .iter()
                            .all(|f| f.severity != Error || *sev == Error),
                        "{ctx}\nan error where only a warning is due"
                    );
                    assert_eq!(r.exit_code(), i32::from(*sev == Error), "{ctx}");
                }
                None => assert!(
                    r.findings.iter().all(|f| f.severity < Warning),
                    "{ctx}\nexpected no error or warning"
                ),
            }
        }
    }
}

/// Total length of the feed moves of `src` (mm), from its motions.
fn feed_length(src: &str, dialect: Dialect) -> (f64, usize) {
    let cfg = CheckConfig {
        dialect,
        ..CheckConfig::default()
    };
    let p = sim::load(Backend::Builtin, src, &cfg);
    let feeds: Vec<_> = p
        .motions
        .iter()
        .filter(|m| m.kind == sim::MotionKind::Feed)
        .collect();
    (feeds.iter().map(|m| m.length()).sum(), feeds.len())
}

#[test]
fn the_estimate_never_invents_a_feed() {
    let src = source("g1_without_feed.nc");
    for d in [Dialect::Linuxcnc, Dialect::Grbl, Dialect::Generic] {
        let r = run(&src, d);
        assert_eq!(r.stats.time.untimed_moves, 1, "{r}");
        assert_eq!(r.stats.time.feed, 0.0, "{r}");
        assert!(r.to_string().contains("time incomplete"), "{r}");
    }
    // Marlin and Smoothieware run the move at their default feed: at least L / v, and
    // (trapezoid with acceleration a) at most L / v + v / a.
    for (d, v) in [
        (Dialect::Marlin, sim::interp::MARLIN_DEFAULT_FEED_MM_MIN),
        (Dialect::Smoothie, sim::interp::SMOOTHIE_DEFAULT_FEED_MM_MIN),
    ] {
        let r = run(&src, d);
        let (len, n) = feed_length(&src, d);
        assert_eq!((n, r.stats.time.untimed_moves), (1, 0), "{r}");
        let (v, a) = (v / 60.0, CheckConfig::default().accel[0]);
        let t = r.stats.time.feed;
        assert!(
            t >= len / v && t <= len / v + v / a,
            "{t} for {len} mm at {v} mm/s"
        );
    }
    // F0 after a feed: Marlin keeps the last feed (500 mm/min) for all 30 mm.
    let src = source("f0_after_feed.nc");
    let r = run(&src, Dialect::Marlin);
    let (len, _) = feed_length(&src, Dialect::Marlin);
    assert_eq!(r.stats.time.untimed_moves, 0);
    assert!(r.stats.time.feed >= len / (500.0 / 60.0), "{r}");
    assert_eq!(run(&src, Dialect::Linuxcnc).stats.time.untimed_moves, 2);
}

#[test]
fn rs274_refuses_the_linuxcnc_errors_too() {
    for (file, rows) in TABLE {
        let refused = rows
            .iter()
            .any(|(d, e)| *d == Dialect::Linuxcnc && matches!(e, Some((Error, _, _))));
        let src = source(file);
        let opts = sim::rs274::Rs274Options {
            timeout: std::time::Duration::from_secs(60),
            ..Default::default()
        };
        let out = match sim::rs274::run(&sim::linuxcnc::number_lines(&src), &opts) {
            Ok(out) => out,
            Err(sim::rs274::Rs274Error::NotRunnable(e)) => {
                eprintln!("rs274 is not installed ({e}): cross-check skipped");
                return;
            }
            Err(e) => panic!("rs274 on {file}: {e}"),
        };
        let p = sim::linuxcnc::parse_canon(&out.combined());
        let errors = p.diagnostics.iter().any(|f| f.severity == Error);
        assert_eq!(errors, refused, "{file}: rs274 said\n{}", out.stderr);
    }
}
