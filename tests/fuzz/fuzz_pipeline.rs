//! Fuzz target: random valid designs through outline → build → G-code → check, by the
//! library API. Errors are allowed (they must name the file); panics are crashes. See
//! tests/support/fuzz.rs for the generator and the env variables.

use crate::support;
use skinpath::design::{CircleSeq, Design, Operation, OperationKind, Stroke, Units, validate};
use skinpath::emit::{GcodeOptions, gcode};
use skinpath::job::build::{BuildOptions, build_toolpath};
use skinpath::job::check::check_config;
use skinpath::job::outline::{OutlineOptions, outline_document};
use skinpath::machine::builtin_profile;
use skinpath::sim::{Backend, check_text};
use support::fuzz::{Rng, Stats, cases, run_one, seed};

fn random_design(rng: &mut Rng) -> Design {
    let mut strokes = Vec::new();
    for i in 0..1 + rng.below(2) {
        let n = 2 + rng.below(5);
        let (ox, oy) = (rng.range(20.0, 120.0), rng.range(20.0, 120.0));
        let disks: Vec<[f64; 3]> = (0..n)
            .map(|_| {
                [
                    ox + rng.range(-25.0, 25.0),
                    oy + rng.range(-25.0, 25.0),
                    rng.range(0.5, 4.0),
                ]
            })
            .collect();
        let mut s = Stroke::from_disks(&format!("s{i}"), disks);
        s.degree = 1 + rng.below(3);
        s.closed = n >= 3 && rng.below(4) == 0;
        strokes.push(s);
    }
    let mut circles = Vec::new();
    if rng.below(3) == 0 {
        let (ox, oy) = (rng.range(20.0, 120.0), rng.range(20.0, 120.0));
        let list = (0..2 + rng.below(3))
            .map(|k| {
                [
                    ox + 6.0 * k as f64,
                    oy + rng.range(-2.0, 2.0),
                    rng.range(1.0, 3.0),
                ]
            })
            .collect();
        circles.push(CircleSeq {
            name: "c".into(),
            closed: false,
            circles: list,
        });
    }
    let mut operation = Vec::new();
    match rng.below(4) {
        0 => {}
        1 => {
            let mut o = Operation::new(OperationKind::Profile);
            o.depth = Some(rng.range(0.5, 3.0));
            operation.push(o);
        }
        2 => {
            let mut o = Operation::new(OperationKind::Channel);
            o.width = Some(rng.range(2.0, 6.0));
            o.depth = Some(1.0);
            operation.push(o);
        }
        _ => {
            let mut o = Operation::new(OperationKind::Fill);
            o.spacing = Some(rng.range(0.5, 2.0));
            operation.push(o);
        }
    }
    Design {
        version: 1,
        units: Units::Mm,
        outline: None,
        stroke: strokes,
        circles,
        shape: Vec::new(),
        operation,
        text: Vec::new(),
        corners: Vec::new(),
        neon: None,
        output: Vec::new(),
        file: "fuzz.toml".into(),
    }
}

fn pipeline(d: &Design, machine: &str) -> bool {
    if validate(d).is_err() {
        return false;
    }
    if let Err(e) = outline_document(d, &OutlineOptions::default()) {
        assert!(e.to_string().contains("fuzz.toml"), "{e}");
        return false;
    }
    let profile = builtin_profile(machine).unwrap().unwrap();
    let built = match build_toolpath(d, &profile, &BuildOptions::default()) {
        Ok(b) => b,
        Err(e) => {
            assert!(e.to_string().contains("fuzz.toml"), "{e}");
            return false;
        }
    };
    let opts = GcodeOptions {
        job: "fuzz".into(),
        input_units: skinpath::machine::Units::Mm,
        tolerance: BuildOptions::default().tolerance * 0.1,
        check_work_area: false,
    };
    let Ok(g) = gcode(&built.toolpath, &profile, &opts) else {
        return false;
    };
    let r = profile.default_tool().map(|t| t.radius()).unwrap_or(0.0);
    let report = check_text(Backend::Builtin, &g, &check_config(&profile, r), &[]);
    let _ = report.to_string();
    true
}

#[test]
fn fuzz_random_designs_through_the_pipeline() {
    let mut rng = Rng::new(seed("pipeline"));
    let mut stats = Stats::default();
    let n = cases(4);
    for k in 0..n {
        let d = random_design(&mut rng);
        let text = d.to_toml_string().unwrap();
        let machine = if k % 2 == 0 {
            "grbl-laser"
        } else {
            "grbl-router"
        };
        run_one("pipeline", &text, &mut stats, |_| pipeline(&d, machine));
    }
    println!(
        "pipeline: {} executions, {} built and checked, slowest {:?}, 0 crashes",
        stats.executions, stats.accepted, stats.slowest
    );
    assert_eq!(stats.executions, n);
}
