use super::*;
use crate::machine::builtin_profile;
use crate::toolpath::{Operation, OperationKind};

fn profile(name: &str) -> Profile {
    builtin_profile(name).unwrap()
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
        group: None,
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
            design_index: None,
            air_assist: false,
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

fn helix() -> Cut {
    // One and a half turns down from z = 0 to z = -3 about (50, 50), radius 10.
    let c = DVec2::new(50.0, 50.0);
    let m = |x: f64, y: f64, z: f64| Move {
        kind: MoveKind::Arc {
            center: c,
            ccw: true,
        },
        to: DVec3::new(x, y, z),
        feed: 500.0,
        power: 1.0,
    };
    Cut {
        source: None,
        group: None,
        start: DVec3::new(60.0, 50.0, 0.0),
        moves: vec![m(60.0, 50.0, -2.0), m(40.0, 50.0, -3.0)],
    }
}

#[test]
fn helical_arcs_carry_z_and_r_pieces_share_the_descent() {
    let ij = gcode(
        &job(vec![helix()]),
        &profile("grbl-router"),
        &GcodeOptions::default(),
    )
    .unwrap();
    assert!(ij.contains("G3 X60 Y50 Z-2 I-10 J0"), "{ij}");
    assert!(ij.contains("\nX40 Y50 Z-3 I-10 J0\n"), "modal G3: {ij}");
    let text = crate::machine::BUILTIN_SOURCES[1]
        .1
        .replace("arcs = \"ij\"", "arcs = \"r\"");
    let p = Profile::from_toml(&text, "r.toml").unwrap();
    let r = gcode(&job(vec![helix()]), &p, &GcodeOptions::default()).unwrap();
    // The full turn is three 120° pieces, z falling by 2/3 each; the half turn two pieces.
    let zs: Vec<f64> = r
        .lines()
        .filter(|l| l.contains(" R") && !l.starts_with('('))
        .map(|l| {
            let w = l.split(' ').find(|w| w.starts_with('Z')).unwrap();
            w[1..].parse().unwrap()
        })
        .collect();
    let want = [-2.0 / 3.0, -4.0 / 3.0, -2.0, -2.5, -3.0];
    assert_eq!(zs.len(), want.len(), "{r}");
    for (z, w) in zs.iter().zip(want) {
        assert!((z - w).abs() <= 0.0005, "{z} vs {w}\n{r}");
    }
}

#[test]
fn tiny_arcs_never_become_full_circles() {
    // An arc of 1e-5 rad on a radius of 10: its ends round to the same point.
    let c = DVec2::new(50.0, 50.0);
    let a = 1e-5f64;
    let cut = Cut {
        source: None,
        group: None,
        start: DVec3::new(60.0, 50.0, 0.0),
        moves: vec![
            Move {
                kind: MoveKind::Arc {
                    center: c,
                    ccw: true,
                },
                to: DVec3::new(50.0 + 10.0 * a.cos(), 50.0 + 10.0 * a.sin(), 0.0),
                feed: 500.0,
                power: 1.0,
            },
            Move {
                kind: MoveKind::Line,
                to: DVec3::new(70.0, 50.0, 0.0),
                feed: 500.0,
                power: 1.0,
            },
        ],
    };
    let out = gcode(
        &job(vec![cut]),
        &profile("grbl-laser"),
        &GcodeOptions::default(),
    )
    .unwrap();
    assert!(!out.contains("G3 ") && !out.contains("G2 "), "{out}");
    assert!(out.contains("G1 X70"), "{out}");
}

#[test]
fn pierce_dwell_follows_the_laser_on() {
    let text = crate::machine::BUILTIN_SOURCES[2].1.replace(
        "rapid_off = \"m5\"",
        "rapid_off = \"m5\"\npierce_dwell = 0.2",
    );
    let p = Profile::from_toml(&text, "marlin-pierce.toml").unwrap();
    let mut far = square(0.0, 1.0);
    far.start.x += 50.0;
    for m in &mut far.moves {
        m.to.x += 50.0;
    }
    let out = gcode(&job(vec![square(0.0, 1.0), far]), &p, &Default::default()).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    let ons: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("M3"))
        .collect();
    assert_eq!(ons.len(), 2, "{out}");
    for i in ons {
        assert_eq!(lines[i + 1], "G4 P200", "{out}");
    }
}
