use super::*;

#[test]
fn builtin_profiles_load_and_are_named_after_their_files() {
    let profiles = builtin_profiles().unwrap();
    assert_eq!(profiles.len(), BUILTIN_SOURCES.len());
    for (p, (file, _)) in profiles.iter().zip(BUILTIN_SOURCES.iter()) {
        assert_eq!(format!("{}.toml", p.name), *file);
        assert_eq!(builtin_profile(&p.name).as_ref(), Ok(p));
        match p.kind {
            MachineKind::Laser | MachineKind::Router => {
                let g = p.gcode.as_ref().unwrap();
                let want = if p.units == Units::Mm { 3 } else { 4 };
                assert_eq!(g.decimals, want, "{}", p.name);
            }
            MachineKind::Svg => assert!(p.svg.is_some()),
        }
    }
    let e = builtin_profile("no-such-machine").unwrap_err();
    assert_eq!(
        e.kind,
        ProfileErrorKind::UnknownBuiltin {
            name: "no-such-machine".to_string()
        }
    );
    assert!(e.is_unknown_builtin());
    // The message names the name asked for and every shipped profile.
    let shown = e.to_string();
    assert!(shown.starts_with("no-such-machine: "), "{shown}");
    for (file, _) in BUILTIN_SOURCES {
        assert!(shown.contains(file.trim_end_matches(".toml")), "{shown}");
    }
    // A faulty profile text is not an unknown name.
    assert!(
        !Profile::from_toml("version = 1", "x.toml")
            .unwrap_err()
            .is_unknown_builtin()
    );
    // At least one inch profile and one R-format profile ship.
    assert!(profiles.iter().any(|p| p.units == Units::Inch));
    assert!(
        profiles
            .iter()
            .any(|p| p.gcode.as_ref().is_some_and(|g| g.arcs == ArcFormat::R))
    );
}

fn grbl_text() -> &'static str {
    BUILTIN_SOURCES[0].1
}

fn load_err(text: &str) -> ProfileError {
    Profile::from_toml(text, "shop.toml").unwrap_err()
}

#[test]
fn unknown_key_is_named_with_file_and_line() {
    let text = grbl_text().replace("[laser]\n", "[laser]\nwattage = 5\n");
    let e = load_err(&text);
    assert_eq!(e.file, "shop.toml");
    assert_eq!(e.key, "wattage");
    let line = e.line.unwrap();
    assert!(
        text.lines().nth(line - 1).unwrap().contains("wattage"),
        "{e}"
    );
    assert!(e.to_string().starts_with("shop.toml:"));
}

#[test]
fn wrong_version_is_rejected() {
    let e = load_err(&grbl_text().replace("version = 1", "version = 2"));
    assert_eq!(e.key, "version");
    assert!(e.message.contains('2'));
}

#[test]
fn missing_key_and_wrong_type_are_named() {
    let e = load_err(&grbl_text().replace("name = \"grbl-laser\"\n", ""));
    assert_eq!(e.key, "name");
    let e = load_err(&grbl_text().replace("decimals = 3", "decimals = \"three\""));
    assert_eq!(e.key, "decimals", "{e}");
    let e = load_err(&grbl_text().replace("arcs = \"ij\"", "arcs = \"spline\""));
    assert_eq!(e.key, "arcs", "{e}");
}

#[test]
fn semantic_errors_name_the_dotted_key() {
    let router = BUILTIN_SOURCES[1].1;
    let e = load_err(&router.replace("safe_z = 5.0", "safe_z = 500.0"));
    assert_eq!(e.key, "router.safe_z");
    let e = load_err(&router.replace("safe_z = 5.0", "safe_z = -1.0"));
    assert_eq!(e.key, "router.safe_z");
    let e = load_err(&router.replace("plunge_feed = 200.0", "plunge_feed = 900.0"));
    assert_eq!(e.key, "router.plunge_feed");
    let e = load_err(&router.replace("angle = 60.0", "angle = 200.0"));
    assert_eq!(e.key, "tools[1].angle");
    let e = load_err(&router.replace("[router]", "[routerx]"));
    assert_eq!(e.key, "routerx");
    let e = load_err(&router.replace("x = [0.0, 300.0]", "x = [300.0, 0.0]"));
    assert_eq!(e.key, "work_area.x");
    let e = load_err(&grbl_text().replace("preamble = \"\"", "preamble = \"G0 Z{safez}\""));
    assert_eq!(e.key, "gcode.preamble");
    assert!(e.message.contains("safez"));
    let e = load_err(&grbl_text().replace("program_end = \"M2\"", "program_end = \"M99\""));
    assert_eq!(e.key, "gcode.program_end");
    let smoothie = BUILTIN_SOURCES[4].1;
    let e = load_err(&smoothie.replace("inline_power = true", "inline_power = false"));
    assert_eq!(e.key, "laser.needs_on_command");
    let svg = BUILTIN_SOURCES[5].1;
    let e = load_err(&svg.replace("fill = \"#000000\"", "fill = \"black\""));
    assert_eq!(e.key, "svg.colors.fill");
    let e = load_err(&svg.replace("[svg]\nstroke_width = 0.01\n\n[svg.colors]", "[x]"));
    assert!(!e.key.is_empty(), "{e}");
}

#[test]
fn kind_needs_its_section() {
    let text = grbl_text();
    let start = text.find("[laser]").unwrap();
    let e = load_err(&text[..start]);
    assert_eq!(e.key, "laser");
}

#[test]
fn number_formatting() {
    assert_eq!(format_number(-0.0004, 3), "0");
    assert_eq!(format_number(-0.0, 3), "0");
    assert_eq!(format_number(12.5, 3), "12.5");
    assert_eq!(format_number(12.0, 3), "12");
    assert_eq!(format_number(-1.23456, 4), "-1.2346");
    assert_eq!(format_number(0.0005, 3), "0.001");
    assert_eq!(format_number(1000.0, 0), "1000");
    // Round trip: the printed value is within half a unit of the last place.
    for i in 0..1000 {
        let v = (i as f64 - 500.0) * 0.123_456_7;
        let s = format_number(v, 3);
        let back: f64 = s.parse().unwrap();
        assert!((back - v).abs() <= 0.0005 + 1e-12, "{v} {s}");
        assert!(!s.starts_with("-0") || s.starts_with("-0."));
    }
}

/// The integer route of `format_number` gives the same text as `format!` (the exact
/// decimal expansion, ties to even) on random values, on values a few ulps either side of
/// every kind of rounding tie, and at the limits of the route; and it is the route taken
/// for ordinary coordinates.
#[test]
fn number_formatting_matches_exact_formatting() {
    let mut state = 0x5EED_F0F0_u64;
    let mut next = || {
        // splitmix64
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let check = |v: f64, d: u32| {
        assert_eq!(
            format_number(v, d),
            super::format_number_std(v, d),
            "{v:e} ({:#x}) to {d} places",
            v.to_bits()
        );
    };
    let (mut fast, mut total) = (0usize, 0usize);
    for _ in 0..200_000 {
        let r = next();
        let d = (r % 13) as u32;
        let mag = 10f64.powi(((r >> 8) % 18) as i32 - 8);
        let u = (next() >> 11) as f64 / (1u64 << 53) as f64;
        let v = if r & (1 << 40) != 0 {
            -u * mag
        } else {
            u * mag
        };
        check(v, d);
        // Coordinates (below 10⁴) to at most 6 places take the integer route.
        if d <= 6 && mag <= 1e4 {
            total += 1;
            fast += usize::from(super::rounded_scaled(v.abs(), d).is_some());
        }
        // Near a tie: (k + ½)/10^d and its neighbours a few ulps away.
        let k = (next() % 1_000_000) as f64;
        let tie = (k + 0.5) / 10f64.powi(d as i32);
        let mut t = tie;
        for _ in 0..4 {
            t = f64::from_bits(t.to_bits() - 1);
        }
        for _ in 0..9 {
            check(t, d);
            check(-t, d);
            t = f64::from_bits(t.to_bits() + 1);
        }
    }
    for v in [
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        5e-324,
        4_503_599_627_370_495.5,
        4_503_599_627_370_496.0,
        9_007_199_254_740_993.0,
        1e300,
        0.125,
        0.375,
        2.5,
        -2.5,
        999_999.999_5,
    ] {
        for d in 0..=12 {
            check(v, d);
        }
    }
    assert!(fast * 1000 >= total * 999, "{fast} of {total}");
}

/// Numbers outside their documented ranges and preambles that would end the program or
/// start the spindle are refused, naming the file, the key and the tool.
#[test]
fn ranges_and_forbidden_words_are_refused() {
    let router = BUILTIN_SOURCES[1].1;
    for bad in ["1e-9", "1e308", "1e-308", "0.0009", "1001.0"] {
        let e = load_err(&router.replace("diameter = 3.175", &format!("diameter = {bad}")));
        assert_eq!(e.key, "tools[0].diameter", "{e}");
        assert!(e.message.contains("0.001..=1000 mm"), "{e}");
        assert!(
            e.to_string()
                .starts_with("shop.toml: key `tools[0].diameter`: tool \""),
            "{e}"
        );
    }
    // In an inch profile the range is converted: 0.001 mm is 3.9e-5 in, so 1e-4 in is fine.
    let inch = BUILTIN_SOURCES[3].1;
    assert!(inch.contains("units = \"inch\""));
    let d = inch.lines().find(|l| l.starts_with("diameter = ")).unwrap();
    Profile::from_toml(&inch.replacen(d, "diameter = 0.0001", 1), "shop.toml").unwrap();
    let e = load_err(&inch.replacen(d, "diameter = 40.0", 1));
    assert!(e.key.ends_with(".diameter"), "{e}");
    let e = load_err(&grbl_text().replace("kerf = 0.08", "kerf = 1e-9"));
    assert_eq!(e.key, "tools[0].kerf");
    for (key, text) in [
        ("gcode.preamble", "preamble = \"G4 P1\\nM30\""),
        ("gcode.preamble", "preamble = \"m 2 (stop)\""),
        ("gcode.preamble", "preamble = \"M3 S{power_max}\""),
        ("gcode.postamble", "postamble = \"G0 X0\\nM04\""),
    ] {
        let field = key.trim_start_matches("gcode.");
        let t = grbl_text().replace(&format!("{field} = \"\""), text);
        let e = load_err(&t);
        assert_eq!(e.key, key, "{e}");
        assert!(e.message.contains("would"), "{e}");
    }
    // M2 in a comment, M5 and M21 are fine.
    let ok = grbl_text().replace("preamble = \"\"", "preamble = \"(M2 later) M5 ; M3\\nM21\"");
    Profile::from_toml(&ok, "shop.toml").unwrap();
    let e = load_err(&router.replace("spindle_dwell = 3.0", "spindle_dwell = 1e9"));
    assert_eq!(e.key, "router.spindle_dwell");
    let e = load_err(&router.replace("x = 2000.0", "x = 1e300"));
    assert_eq!(e.key, "max_feed.x");
    let e = load_err(&router.replace("x = [0.0, 300.0]", "x = [0.0, 1e30]"));
    assert_eq!(e.key, "work_area.x");
    // A router without tools says so.
    let start = router.find("[[tools]]").unwrap();
    let end = router.find("[gcode]").unwrap();
    let e = load_err(&format!("{}{}", &router[..start], &router[end..]));
    assert_eq!(e.key, "tools");
    assert!(e.message.contains("at least one [[tools]]"), "{e}");
}
