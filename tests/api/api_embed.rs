//! The library API a Rust program embeds (`skinpath::Job`): the same code as
//! examples/embed.rs and the crate-level doc test, strokes made in code, progress reports,
//! scaling of text, and the typed refusal of an unchecked program.

use crate::support::ROOT;
use skinpath::geom::DVec2;
use skinpath::job::build::scaled_design;
use skinpath::{
    Circle, DiskBSpline, Job, JobError, JobOptions, OutputFormat, Scale, Stage, builtin_profile,
    design_of_strokes,
};
use std::sync::Mutex;

fn wave() -> DiskBSpline {
    let disks: Vec<Circle> = [
        (0.0, 0.0, 2.0),
        (15.0, 12.0, 3.0),
        (30.0, 0.0, 2.5),
        (45.0, -10.0, 3.5),
        (60.0, 5.0, 2.0),
    ]
    .iter()
    .map(|&(x, y, r)| Circle::new(DVec2::new(x, y), r))
    .collect();
    DiskBSpline::open(3, &disks, None).unwrap()
}

#[test]
fn a_stroke_made_in_code_builds_checked_gcode_for_grbl_router() {
    let wave = wave();
    let design = design_of_strokes("wave", &[("wave", &wave)], &[]).unwrap();
    let profile = builtin_profile("grbl-router").unwrap().unwrap();
    let seen = Mutex::new(Vec::new());
    let progress = |p: skinpath::Progress| seen.lock().unwrap().push(p);
    let out = Job {
        design: &design,
        profile: &profile,
        options: JobOptions {
            name: "wave",
            progress: Some(&progress),
            ..JobOptions::default()
        },
    }
    .run()
    .unwrap();
    let report = out.report.as_ref().unwrap();
    assert_eq!(report.errors(), 0, "{:?}", report.findings);
    assert!(out.explanations.is_empty());
    assert!(
        out.program.contains("wave"),
        "the job's name is in the header"
    );
    let s = out.summary(&profile);
    assert_eq!(s.machine, "grbl-router");
    assert_eq!(s.design, "wave");
    assert_eq!(s.operations.len(), 1);
    assert!(s.cut_length > 0.0 && s.time.with_acceleration.is_some());
    // Placed at the work area's lower-left corner (the default), inside the work area.
    assert!(s.placement.min[0] >= 0.0 && s.placement.min[1] >= 0.0);
    // The summary serialises with the keys `build --json` prints.
    let v = serde_json::to_value(&s).unwrap();
    for key in [
        "design",
        "machine",
        "outputs",
        "operations",
        "bounds",
        "placement",
    ] {
        assert!(v.get(key).is_some(), "no {key} in {v}");
    }
    // Progress: stages in pipeline order, fractions in [0, 1], skinning reaches 1.
    let seen = seen.into_inner().unwrap();
    assert!(!seen.is_empty());
    assert!(
        seen.windows(2).all(|w| w[0].stage <= w[1].stage),
        "{seen:?}"
    );
    assert!(seen.iter().all(|p| (0.0..=1.0).contains(&p.fraction)));
    assert!(
        seen.iter()
            .any(|p| p.stage == Stage::Skin && p.fraction == 1.0)
    );
    for st in [Stage::Skin, Stage::Toolpath, Stage::Emit, Stage::Check] {
        assert!(seen.iter().any(|p| p.stage == st), "no {st:?} report");
        assert!(
            out.timings.stages.iter().any(|(s, _)| *s == st),
            "no {st:?} time"
        );
    }
}

#[test]
fn strokes_made_in_code_keep_their_curve() {
    let open = wave();
    let ring_disks: Vec<Circle> = (0..6)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 6.0;
            Circle::new(
                DVec2::new(20.0 * a.cos(), 20.0 * a.sin()),
                2.0 + 0.2 * k as f64,
            )
        })
        .collect();
    let ring = DiskBSpline::closed(3, &ring_disks, None).unwrap();
    let dots = [
        Circle::new(DVec2::new(0.0, 40.0), 2.0),
        Circle::new(DVec2::new(6.0, 42.0), 2.5),
        Circle::new(DVec2::new(12.0, 40.0), 2.0),
    ];
    let design = design_of_strokes(
        "code",
        &[("wave", &open), ("ring", &ring)],
        &[("dots", &dots, false)],
    )
    .unwrap();
    assert_eq!(design.circles.len(), 1);
    let back = design.strokes().unwrap();
    for (orig, b) in [&open, &ring].into_iter().zip(&back) {
        assert_eq!(orig.is_closed(), b.is_closed());
        let (t0, t1) = orig.domain();
        let (u0, u1) = b.domain();
        for k in 0..=20 {
            let f = k as f64 / 20.0;
            let c0 = orig.circle_at(t0 + f * (t1 - t0));
            let c1 = b.circle_at(u0 + f * (u1 - u0));
            assert!(c0.c.distance(c1.c) < 1e-9 && (c0.r - c1.r).abs() < 1e-9);
        }
    }
}

#[test]
fn scaling_scales_text_and_keeps_its_corners_joints() {
    let path = format!("{ROOT}/examples/gallery/neon_open.toml");
    // The smooth sans "OPEN" has curves and straight legs but no corner within a stroke
    // (issue 41 item 9): a 5 adds two (its top bar meets its stem at 84°, the stem its
    // bowl at 141°).
    let sign = std::fs::read_to_string(&path).unwrap();
    let text = sign.replace("text = \"OPEN\"", "text = \"5OPEN\"");
    assert_ne!(text, sign);
    let design = skinpath::design::load(&text, &path).unwrap();
    assert!(!design.corners.is_empty(), "the letters have corners");
    let half = scaled_design(&design, 0.5);
    for (a, b) in design.corners.iter().zip(&half.corners) {
        assert_eq!([0.5 * a.at[0], 0.5 * a.at[1]], b.at);
    }
    // Text not yet laid out scales too.
    let mut raw: skinpath::Design = toml::from_str(&text).unwrap();
    raw.file = path.clone();
    let h = raw.text[0].height;
    let w = raw.text[0].width;
    let scaled = scaled_design(&raw, 2.0);
    assert_eq!(scaled.text[0].height, 2.0 * h);
    assert_eq!(scaled.text[0].width, 2.0 * w);
    // Neon holes go at the letters' stroke ends only, not at the corners between pieces:
    // as many at half size as at full size.
    let profile = builtin_profile("grbl-laser").unwrap().unwrap();
    let holes = |scale: Scale| {
        let out = Job {
            design: &design,
            profile: &profile,
            options: JobOptions {
                scale,
                write_unchecked: true,
                ..JobOptions::default()
            },
        }
        .run()
        .unwrap();
        let op = out
            .built
            .toolpath
            .operations
            .iter()
            .find(|o| o.design_index == Some(1))
            .unwrap();
        (op.cuts.len(), out.placement.size)
    };
    let (n1, size1) = holes(Scale::None);
    let (n2, size2) = holes(Scale::By(0.5));
    assert!(n1 > 0);
    assert_eq!(n1, n2, "holes at full and half size");
    assert!(size2[0] < 0.6 * size1[0], "{size1:?} {size2:?}");
}

#[test]
fn an_svg_profile_cannot_write_gcode_and_bad_options_are_typed() {
    let wave = wave();
    let design = design_of_strokes("wave", &[("wave", &wave)], &[]).unwrap();
    let svg = builtin_profile("svg-laser").unwrap().unwrap();
    let job = |profile, options| {
        Job {
            design: &design,
            profile,
            options,
        }
        .run()
    };
    let e = job(&svg, JobOptions::default()).unwrap_err();
    assert!(matches!(e, JobError::Options(_)), "{e}");
    assert!(e.to_string().contains("SVG/DXF upload"));
    let ok = job(
        &svg,
        JobOptions {
            format: OutputFormat::Svg,
            ..JobOptions::default()
        },
    )
    .unwrap();
    assert!(ok.program.starts_with("<?xml") || ok.program.contains("<svg"));
    assert!(ok.report.is_none());
    let router = builtin_profile("grbl-router").unwrap().unwrap();
    for bad in [
        Scale::By(0.0),
        Scale::Fit {
            width: -1.0,
            height: 2.0,
        },
    ] {
        let e = job(
            &router,
            JobOptions {
                scale: bad,
                ..JobOptions::default()
            },
        )
        .unwrap_err();
        assert!(matches!(e, JobError::Options(_)), "{e}");
    }
}

#[test]
fn an_unchecked_program_names_its_findings() {
    let e = JobError::Unchecked {
        file: "a.toml".into(),
        errors: 2,
        explanations: vec!["a.toml: x".into()],
    };
    assert_eq!(
        e.to_string(),
        "a.toml: the program failed 2 check(s) (listed above with the operation and stroke \
         that made each); nothing was written (--write-unchecked writes it anyway, at the risk \
         named above)"
    );
}

/// Strokes, circle sequences and operations are built in parallel: the gallery's neon sign
/// (three operations: channel, holes, backboard, and an exact-route profile of its
/// strokes added here, whose RE route is refused and noted) gives the same program and the same route notes, operation by
/// operation, in a one-thread pool and a four-thread pool.
#[test]
fn a_parallel_build_equals_a_serial_one() {
    let path = format!("{ROOT}/examples/gallery/neon_open.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = format!(
        "{text}\n[[operation]]\nkind = \"profile\"\nside = \"outside\"\ndepth = 1.0\nmethod = \"re\"\n"
    );
    let design = skinpath::design::load(&text, &path).unwrap();
    let profile = builtin_profile("grbl-router").unwrap().unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool
            .install(|| {
                Job {
                    design: &design,
                    profile: &profile,
                    options: JobOptions {
                        name: "neon",
                        ..JobOptions::default()
                    },
                }
                .run()
            })
            .unwrap();
        let routes: Vec<(String, String, String)> = (out.summary(&profile).routes.iter())
            .map(|r| (r.operation.clone(), r.route.clone(), r.detail.clone()))
            .collect();
        (out.program, routes)
    };
    let (serial, serial_routes) = run(1);
    let (parallel, parallel_routes) = run(4);
    assert_eq!(serial_routes.len(), 2, "{serial_routes:?}");
    assert_eq!(serial_routes, parallel_routes);
    assert!(serial == parallel, "the programs differ");
}
