use super::*;
use crate::machine::builtin_profile;
use crate::toolpath::{Operation, OperationKind};

fn profile(name: &str) -> Profile {
    builtin_profile(name).unwrap().unwrap()
}

fn square(z: f64, power: f64) -> Cut {
    let mv = |x: f64, y: f64| Move {
        kind: MoveKind::Line,
        to: DVec3::new(x, y, z),
        feed: 1000.0,
        power,
    };
    Cut {
        source: Some("sq".into()),
        start: DVec3::new(10.0, 10.0, z),
        moves: vec![
            mv(20.0, 10.0),
            mv(20.0, 20.0),
            mv(10.0, 20.0),
            mv(10.0, 10.0),
        ],
    }
}

fn job(cuts: Vec<Cut>) -> Toolpath {
    Toolpath {
        operations: vec![Operation {
            name: "outline".into(),
            kind: OperationKind::Profile,
            cuts,
        }],
    }
}

#[test]
fn modal_words_are_not_repeated() {
    let out = gcode(
        &job(vec![square(0.0, 0.5)]),
        &profile("grbl-laser"),
        &GcodeOptions::default(),
    )
    .unwrap();
    let g1_lines = out.lines().filter(|l| l.starts_with("G1 ")).count();
    assert_eq!(g1_lines, 1, "{out}");
    assert_eq!(out.matches("F1000").count(), 1, "{out}");
    assert_eq!(out.matches("S500").count(), 1, "{out}");
    // Each of the four sides changes exactly one axis.
    let sides: Vec<&str> = out
        .lines()
        .skip_while(|l| !l.starts_with("G1 "))
        .take(4)
        .collect();
    for s in &sides {
        let axes = s
            .split(' ')
            .filter(|w| w.starts_with('X') || w.starts_with('Y'))
            .count();
        assert_eq!(axes, 1, "{s}");
    }
}

#[test]
fn inch_profile_converts_mm() {
    let out = gcode(
        &job(vec![square(-1.0, 0.5)]),
        &profile("linuxcnc-router"),
        &GcodeOptions::default(),
    )
    .unwrap();
    assert!(out.contains("G20"));
    // 20 mm = 0.7874 in, 1000 mm/min = 39.37 in/min, -1 mm = -0.0394 in.
    assert!(out.contains("X0.7874"), "{out}");
    assert!(out.contains("F39.37"), "{out}");
    assert!(out.contains("Z-0.0394"), "{out}");
}

#[test]
fn out_of_work_area_names_the_move() {
    let mut c = square(0.0, 0.5);
    c.moves[1].to.x = 5000.0;
    let e = gcode(
        &job(vec![c]),
        &profile("grbl-laser"),
        &GcodeOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, EmitError::OutOfWorkArea { axis: 'X', .. }),
        "{e}"
    );
    assert!(e.to_string().contains("move 1"), "{e}");
}

#[test]
fn svg_profile_is_refused() {
    let e = gcode(
        &job(vec![]),
        &profile("svg-laser"),
        &GcodeOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, EmitError::WrongProfile { .. }));
}

#[test]
fn feed_is_clamped_to_the_axis_maximum() {
    let mut c = square(0.0, 0.5);
    for m in &mut c.moves {
        m.feed = 1e6;
    }
    let out = gcode(
        &job(vec![c]),
        &profile("grbl-laser"),
        &GcodeOptions::default(),
    )
    .unwrap();
    assert!(out.contains("F6000"), "{out}");
}

#[test]
fn router_spindle_starts_before_plunge() {
    let out = gcode(
        &job(vec![square(-2.0, 1.0)]),
        &profile("grbl-router"),
        &GcodeOptions::default(),
    )
    .unwrap();
    let m3 = out.find("M3 S12000").unwrap();
    let plunge = out.find("Z-2").unwrap();
    assert!(m3 < plunge, "{out}");
    assert!(out[m3..plunge].contains("G4 P3"), "{out}");
    assert!(out.contains("G1 Z-2 F200"), "{out}");
}
