//! Tests of the design format: every validation error names its culprit, TOML and JSON round
//! trips, geometry built from designs, and the example designs.

use super::*;
use crate::dbsc::{DiskBSpline, Side};
use crate::geom::{Circle, DVec2};

const FILE: &str = "sign.toml";

/// A valid design with two strokes (the second is the one tests break), circles and an
/// operation. `{S2}` is replaced by the body of stroke "b".
const TEMPLATE: &str = r#"version = 1
units = "mm"

[[stroke]]
name = "a"
disks = [[0.0, 0.0, 2.0], [10.0, 5.0, 3.0], [20.0, 0.0, 2.0], [30.0, 4.0, 1.5]]

[[stroke]]
name = "b"
{S2}

[[circles]]
name = "c"
circles = [[0.0, 20.0, 2.0], [6.0, 21.0, 2.5], [12.0, 20.0, 2.0]]
"#;

const GOOD_B: &str = "disks = [[0.0, 10.0, 2.0], [10.0, 15.0, 3.0], [20.0, 10.0, 2.0], \
                      [30.0, 14.0, 1.5], [40.0, 10.0, 1.0]]";

fn with_b(body: &str) -> String {
    TEMPLATE.replace("{S2}", body)
}

fn err_of(text: &str) -> String {
    match from_str(text, Format::Toml, FILE) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The message names the file, stroke 1 "b" and the given part.
fn assert_names(msg: &str, part: &str, what: &str) {
    assert!(msg.starts_with(FILE), "{msg}");
    assert!(msg.contains("stroke 1 \"b\""), "{msg}");
    assert!(msg.contains(part), "missing `{part}` in: {msg}");
    assert!(msg.contains(what), "missing `{what}` in: {msg}");
}

#[test]
fn template_is_valid() {
    let d = from_str(&with_b(GOOD_B), Format::Toml, FILE).unwrap();
    assert_eq!(d.stroke.len(), 2);
    assert_eq!(d.stroke[1].degree, DEFAULT_DEGREE);
    assert_eq!(d.file, FILE);
    assert_eq!(d.strokes().unwrap().len(), 2);
    assert_eq!(d.circle_sequences()[0].len(), 3);
}

#[test]
fn non_finite_disk() {
    let b = GOOD_B.replace("[20.0, 10.0, 2.0]", "[20.0, nan, 2.0]");
    assert_names(&err_of(&with_b(&b)), "disk 2", "not finite");
    let b = GOOD_B.replace("[30.0, 14.0, 1.5]", "[30.0, 14.0, inf]");
    assert_names(&err_of(&with_b(&b)), "disk 3", "not finite");
}

#[test]
fn non_positive_radius() {
    let b = GOOD_B.replace("[10.0, 15.0, 3.0]", "[10.0, 15.0, 0.0]");
    assert_names(&err_of(&with_b(&b)), "disk 1", "radius 0 must be positive");
    let b = GOOD_B.replace("[40.0, 10.0, 1.0]", "[40.0, 10.0, -1.5]");
    assert_names(&err_of(&with_b(&b)), "disk 4", "radius -1.5");
}

#[test]
fn too_few_disks_for_degree() {
    // With `knots` the degree is fixed: degree + 1 disks are needed.
    let msg = err_of(&with_b(&format!(
        "degree = 5\n{GOOD_B}\nknots = [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1]"
    )));
    assert_names(&msg, "stroke 1", "needs at least 6 disks, got 5");
    // Without, two disks suffice (three closed).
    let msg = err_of(&with_b("disks = [[0.0, 0.0, 1.0]]"));
    assert_names(&msg, "stroke 1", "needs at least 2 disks, got 1");
    let b = "closed = true\ndisks = [[0.0, 0.0, 1.0], [10.0, 0.0, 1.0]]";
    assert_names(
        &err_of(&with_b(b)),
        "stroke 1",
        "needs at least 3 disks, got 2",
    );
    let msg = err_of(&with_b("degree = 0\ndisks = [[0.0, 0.0, 1.0]]"));
    assert_names(&msg, "key `degree`", "outside 1..=10");
    let msg = err_of(&with_b(&format!("degree = 11\n{GOOD_B}")));
    assert_names(&msg, "key `degree`", "outside 1..=10");
}

/// Short lists lower the degree to one less than their length: a 2-disk stroke is the
/// straight line of its disks, a 3-disk stroke a quadratic with the disks as control disks.
#[test]
fn short_strokes_lower_the_degree() {
    let d = from_str(
        &with_b("disks = [[0.0, 10.0, 1.0], [10.0, 10.0, 2.0]]"),
        Format::Toml,
        FILE,
    )
    .unwrap();
    assert_eq!(d.stroke[1].effective_degree(), 1);
    let c = &d.strokes().unwrap()[1];
    assert_eq!(c.degree(), 1);
    // The midpoint of a line between the two disks.
    let m = c.circle_at(0.5);
    assert!((m.c - DVec2::new(5.0, 10.0)).length() < 1e-12, "{m:?}");
    assert!((m.r - 1.5).abs() < 1e-12);
    // Three disks: degree 2, Bézier midpoint (b0 + 2 b1 + b2) / 4.
    let d = from_str(
        &with_b("disks = [[0.0, 10.0, 1.0], [10.0, 20.0, 2.0], [20.0, 10.0, 1.0]]"),
        Format::Toml,
        FILE,
    )
    .unwrap();
    let c = &d.strokes().unwrap()[1];
    assert_eq!(c.degree(), 2);
    let m = c.circle_at(0.5);
    assert!((m.c - DVec2::new(10.0, 15.0)).length() < 1e-12, "{m:?}");
    assert!((m.r - 1.5).abs() < 1e-12);
    // Three points interpolated, closed three disks.
    let b = "points = [[0.0, 0.0, 1.0], [5.0, 3.0, 1.5], [10.0, 0.0, 1.0]]";
    let d = from_str(&with_b(b), Format::Toml, FILE).unwrap();
    let c = &d.strokes().unwrap()[1];
    assert_eq!(c.degree(), 2);
    let m = c.circle_at(c.domain().0);
    assert!((m.c - DVec2::ZERO).length() < 1e-9, "{m:?}");
    let b = "closed = true\ndisks = [[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], [5.0, 8.0, 1.0]]";
    let d = from_str(&with_b(b), Format::Toml, FILE).unwrap();
    assert_eq!(d.strokes().unwrap()[1].degree(), 2);
}

/// Values out of range and near-repeats name the item, the part and the limit.
#[test]
fn ranges_and_near_repeats() {
    let b = GOOD_B.replace("[20.0, 10.0, 2.0]", "[1e38, 10.0, 2.0]");
    assert_names(&err_of(&with_b(&b)), "disk 2", "beyond ±10000000");
    let b = GOOD_B.replace("[20.0, 10.0, 2.0]", "[20.0, 10.0, 1e-5]");
    assert_names(&err_of(&with_b(&b)), "disk 2", "below the smallest radius");
    let b = "disks = [[1e-15, 0, 2], [0, 0, 2], [10, 5, 2], [20, 0, 2]]";
    assert_names(&err_of(&with_b(b)), "disk 1", "nearly repeats");
    // A disk of 4 values is a syntax error at its line and column.
    let b = GOOD_B.replace("[20.0, 10.0, 2.0]", "[20.0, 10.0, 2.0, 7.0]");
    let msg = err_of(&with_b(&b));
    assert!(msg.starts_with("sign.toml:10:"), "{msg}");
    assert!(msg.contains("exactly 3 numbers"), "{msg}");
    let msg = err_of(
        &TEMPLATE
            .replace("[12.0, 20.0, 2.0]", "[12.0, 20.0]")
            .replace("{S2}", GOOD_B),
    );
    assert!(msg.contains("exactly 3 numbers"), "{msg}");
    // An empty design.
    let msg = err_of("version = 1\n");
    assert!(msg.contains("no [[stroke]] and no [[circles]]"), "{msg}");
    // Degree beyond any limit, through JSON (TOML integers stop at i64::MAX).
    let json = r#"{"version": 1, "stroke": [{"name": "d", "degree": 18446744073709551615,
        "fit": "approximate", "control_disks": 4,
        "points": [[0, 0, 1], [5, 3, 1.5], [10, 0, 1], [15, 2, 1.2]]}]}"#;
    let msg = from_str(json, Format::Json, "d.json")
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("stroke 0 \"d\", key `degree`: degree = 18446744073709551615"),
        "{msg}"
    );
    // Operations: every number has a range.
    for (op, key, what) in [
        (
            "kind = \"vcarve\"\nangle = 60\ndepth = 1e300",
            "depth",
            "above the limit",
        ),
        (
            "kind = \"vcarve\"\nangle = 60\npasses = 4294967295",
            "passes",
            "outside 1..=1000",
        ),
        (
            "kind = \"fill\"\nspacing = 1\nfeed = 1e300",
            "feed",
            "above the limit",
        ),
        (
            "kind = \"profile\"\npasses = 1000000000",
            "passes",
            "outside 1..=1000",
        ),
        (
            "kind = \"profile\"\ntabs = { count = 1000000000, width = 2, height = 1 }",
            "tabs.count",
            "outside 1..=100",
        ),
        (
            "kind = \"profile\"\ndepth = 10\nstep_down = 0.001",
            "step_down",
            "raise step_down",
        ),
        (
            "kind = \"fill\"\nspacing = 1\nangle = 1e9",
            "angle",
            "out of range",
        ),
    ] {
        let msg = err_of(&format!("{}\n[[operation]]\n{op}\n", with_b(GOOD_B)));
        assert!(msg.contains("operation 0 ("), "{msg}");
        assert!(msg.contains(&format!("key `{key}`")), "{msg}");
        assert!(msg.contains(what), "{msg}");
    }
}

#[test]
fn knot_vector_wrong_length() {
    // 5 disks, degree 3: 9 knots expected.
    let b = format!("{GOOD_B}\nknots = [0, 0, 0, 0, 1, 1, 1, 1]");
    assert_names(&err_of(&with_b(&b)), "key `knots`", "8 knots, expected 9");
    let b = format!("{GOOD_B}\nclosed = true\nknots = [0, 1, 2, 3, 4]");
    assert_names(&err_of(&with_b(&b)), "key `knots`", "5 knots, expected 6");
}

#[test]
fn knot_vector_decreasing() {
    let b = format!("{GOOD_B}\nknots = [0, 0, 0, 0, 0.6, 0.4, 1, 1, 1]");
    assert_names(&err_of(&with_b(&b)), "knot 5", "0.4 does not follow 0.6");
    // Closed breakpoints must increase strictly.
    let b = format!("{GOOD_B}\nclosed = true\nknots = [0, 1, 2, 2, 3, 4]");
    assert_names(&err_of(&with_b(&b)), "knot 3", "2 does not follow 2");
}

#[test]
fn knot_not_finite_or_too_multiple() {
    let b = format!("{GOOD_B}\nknots = [0, 0, 0, 0, inf, 1, 1, 1, 1]");
    assert_names(&err_of(&with_b(&b)), "knot 4", "not finite");
    let b = format!("{GOOD_B}\nknots = [0, 0, 0, 0, 0, 1, 1, 1, 1]");
    assert_names(&err_of(&with_b(&b)), "knot 0", "repeated 5 times");
}

#[test]
fn repeated_consecutive_disks() {
    let b = GOOD_B.replace("[20.0, 10.0, 2.0]", "[10.0, 15.0, 3.0]");
    assert_names(&err_of(&with_b(&b)), "disk 2", "repeats the one before it");
    // A closed list whose last disk repeats the first.
    let b = "closed = true\ndegree = 2\ndisks = [[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], \
             [5.0, 8.0, 1.0], [0.0, 0.0, 1.0]]";
    assert_names(&err_of(&with_b(b)), "disk 0", "repeats");
}

#[test]
fn unknown_keys_with_line_and_column() {
    // Line 10 of the template is the body of stroke "b".
    let msg = err_of(&with_b(&format!("colour = \"red\"\n{GOOD_B}")));
    assert!(msg.starts_with("sign.toml:10:1:"), "{msg}");
    assert!(msg.contains("colour"), "{msg}");
    let text = with_b(&format!(
        "{GOOD_B}\n[stroke.attributes]\n  speed = [1, 2, 3, 4, 5]"
    ));
    let msg = err_of(&text);
    assert!(msg.starts_with("sign.toml:12:3:"), "{msg}");
    assert!(msg.contains("speed"), "{msg}");
    let msg = err_of(&format!("frobnicate = 3\n{}", with_b(GOOD_B)));
    assert!(msg.starts_with("sign.toml:1:1:"), "{msg}");
    // A disk with two numbers: the error points into that array.
    let b = GOOD_B.replace("[40.0, 10.0, 1.0]", "[40.0, 10.0]");
    let msg = err_of(&with_b(&b));
    assert!(msg.starts_with("sign.toml:10:"), "{msg}");
}

#[test]
fn duplicate_names() {
    let text = with_b(GOOD_B).replace("name = \"b\"", "name = \"a\"");
    let msg = err_of(&text);
    assert!(msg.starts_with(FILE), "{msg}");
    assert!(msg.contains("stroke 1 \"a\""), "{msg}");
    assert!(msg.contains("already used by stroke 0 \"a\""), "{msg}");
    let text = with_b(GOOD_B).replace("name = \"c\"", "name = \"b\"");
    let msg = err_of(&text);
    assert!(msg.contains("circles 0 \"b\""), "{msg}");
    assert!(msg.contains("already used by stroke 1 \"b\""), "{msg}");
}

#[test]
fn attribute_counts_and_values() {
    let b = format!("{GOOD_B}\n[stroke.attributes]\npower = [10, 20, 30, 40]");
    assert_names(
        &err_of(&with_b(&b)),
        "attributes.power",
        "has 4 values, expected 5",
    );
    let b = format!("{GOOD_B}\n[stroke.attributes]\nfeed = [100, 200, 0, 400, 500]");
    assert_names(
        &err_of(&with_b(&b)),
        "attribute feed value 2",
        "outside (0, 1000000]",
    );
    let b = format!("{GOOD_B}\n[stroke.attributes]\npower = [10, 20, 30, 140, 50]");
    assert_names(&err_of(&with_b(&b)), "attribute power value 3", "0..=100");
    let b = format!("{GOOD_B}\n[stroke.attributes]\ndepth = [1, 1, nan, 1, 1]");
    assert_names(
        &err_of(&with_b(&b)),
        "attribute depth value 2",
        "not finite",
    );
    // Approximations count control disks, not points.
    let b = "points = [[0.0, 0.0, 1.0], [5.0, 3.0, 1.5], [10.0, 0.0, 1.0], [15.0, 2.0, 1.2], \
             [20.0, 0.0, 1.0]]\nfit = \"approximate\"\ncontrol_disks = 4\n\
             [stroke.attributes]\ndepth = [1, 2, 2, 1, 1]";
    assert_names(&err_of(&with_b(b)), "attributes.depth", "expected 4");
}

#[test]
fn operation_unknown_stroke_and_keys() {
    let op = "\n[[operation]]\nkind = \"channel\"\nwidth = 6.0\nstrokes = [\"a\", \"zz\"]\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.starts_with(FILE), "{msg}");
    assert!(msg.contains("operation 0 (channel)"), "{msg}");
    assert!(msg.contains("unknown stroke \"zz\""), "{msg}");
    // Circle sequences can be named too.
    let op = "\n[[operation]]\nkind = \"channel\"\nwidth = 6.0\nstrokes = [\"a\", \"c\"]\n";
    assert!(from_str(&format!("{}{op}", with_b(GOOD_B)), Format::Toml, FILE).is_ok());
    let op = "\n[[operation]]\nkind = \"holes\"\ndiameter = 3\n\
              [[operation]]\nkind = \"profile\"\nwidth = 6.0\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.contains("operation 1 (profile), key `width`"), "{msg}");
    let op = "\n[[operation]]\nkind = \"vcarve\"\nmax_depth = 3\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.contains("operation 0 (vcarve), key `angle`"), "{msg}");
    let op = "\n[[operation]]\nkind = \"vcarve\"\nangle = 190\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.contains("key `angle`"), "{msg}");
    let op = "\n[[operation]]\nkind = \"fill\"\nspacing = -0.2\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.contains("operation 0 (fill), key `spacing`"), "{msg}");
    let op = "\n[[operation]]\nkind = \"backboard\"\nlaser = true\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.starts_with("sign.toml:18:1:"), "{msg}");
    let op = "\n[[operation]]\nkind = \"profile\"\ntabs = { count = 0, width = 2, height = 1 }\n";
    let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
    assert!(msg.contains("key `tabs.count`"), "{msg}");
    // Tabs and the skin route belong to the cuts that free a part; elsewhere they would be
    // ignored, so they are refused.
    for (kind, extra) in [
        ("channel", "width = 6.0\n"),
        ("fill", "spacing = 0.5\n"),
        ("holes", "diameter = 3\n"),
        ("vcarve", "angle = 60\n"),
    ] {
        for key in [
            "tabs = { count = 2, width = 2, height = 1 }",
            "method = \"re\"",
        ] {
            let op = format!("\n[[operation]]\nkind = \"{kind}\"\n{extra}{key}\n");
            let msg = err_of(&format!("{}{op}", with_b(GOOD_B)));
            let name = key.split(' ').next().unwrap_or_default();
            assert!(
                msg.contains(&format!("operation 0 ({kind}), key `{name}`"))
                    && msg.contains("does not apply"),
                "{msg}"
            );
        }
    }
    for kind in ["profile", "backboard"] {
        let op = format!(
            "\n[[operation]]\nkind = \"{kind}\"\ntabs = {{ count = 2, width = 2, height = 1 }}\n\
             method = \"re\"\n"
        );
        assert!(from_str(&format!("{}{op}", with_b(GOOD_B)), Format::Toml, FILE).is_ok());
    }
}

#[test]
fn versions() {
    let text = with_b(GOOD_B).replace("version = 1", "version = 2");
    let msg = err_of(&text);
    assert_eq!(
        msg,
        "sign.toml: unsupported design file version 2: this skinpath reads version 1"
    );
    // Checked before unknown keys of a newer format.
    let msg = err_of(&format!("{text}\n[future]\nx = 1\n"));
    assert!(msg.contains("version 2"), "{msg}");
    let msg = err_of(&with_b(GOOD_B).replace("version = 1", ""));
    assert_eq!(msg, "sign.toml: missing `version = 1`");
    let e = load(r#"{"version": "1"}"#, "x.json").unwrap_err();
    assert!(
        e.to_string()
            .contains("x.json: unsupported design file version \"1\"")
    );
}

#[test]
fn circles_errors() {
    let text = with_b(GOOD_B).replace("[6.0, 21.0, 2.5]", "[6.0, 21.0, -2.5]");
    let msg = err_of(&text);
    assert!(
        msg.contains("sign.toml: circles 0 \"c\", circle 1: radius -2.5"),
        "{msg}"
    );
    let text = with_b(GOOD_B).replace(
        "circles = [[0.0, 20.0, 2.0], [6.0, 21.0, 2.5], [12.0, 20.0, 2.0]]",
        "closed = true\ncircles = [[0.0, 20.0, 2.0], [6.0, 21.0, 2.5]]",
    );
    let msg = err_of(&text);
    assert!(
        msg.contains("circles 0 \"c\": needs at least 3 circles, got 2"),
        "{msg}"
    );
}

#[test]
fn points_stroke_errors() {
    let pts = "points = [[0.0, 0.0, 1.0], [5.0, 3.0, 1.5], [10.0, 0.0, 1.0], [15.0, 2.0, 1.2]]";
    assert_names(
        &err_of(&with_b(&format!("{GOOD_B}\n{pts}"))),
        "stroke 1",
        "not both",
    );
    assert_names(&err_of(&with_b("degree = 2")), "stroke 1", "needs `disks`");
    let b = format!("{pts}\nfit = \"approximate\"");
    assert_names(&err_of(&with_b(&b)), "key `control_disks`", "needs");
    let b = format!("{pts}\nfit = \"approximate\"\ncontrol_disks = 5");
    assert_names(&err_of(&with_b(&b)), "key `control_disks`", "between");
    let b = format!("{pts}\ncontrol_disks = 4");
    assert_names(&err_of(&with_b(&b)), "key `control_disks`", "approximate");
    let b = format!("{pts}\nknots = [0, 0, 0, 0, 1, 1, 1, 1]");
    assert_names(&err_of(&with_b(&b)), "key `knots`", "a fit chooses");
    let b = format!("{GOOD_B}\nparametrization = \"centripetal\"");
    assert_names(&err_of(&with_b(&b)), "key `parametrization`", "points");
    let b = pts.replace("[10.0, 0.0, 1.0]", "[5.0, 3.0, 1.5]");
    assert_names(&err_of(&with_b(&b)), "point 2", "centre of the one before");
    // Same centre, other radius: still a zero chord for the fit.
    let b = pts.replace("[10.0, 0.0, 1.0]", "[5.0, 3.0, 2.5]");
    assert_names(&err_of(&with_b(&b)), "point 2", "centre of the one before");
    let b = "points = [[0.0, 0.0, 1.0]]";
    assert_names(&err_of(&with_b(b)), "stroke 1", "at least 2 points, got 1");
}

#[test]
fn file_level_errors() {
    let e = load("version = 1", "design.yaml").unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnknownFormat);
    assert!(e.to_string().starts_with("design.yaml: "));
    let e = load(
        "{\n  \"version\": 1,\n  \"stroke\": [\n    {\"nam\": \"x\"}\n  ]\n}",
        "d.json",
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("d.json:4:"), "{msg}");
    assert!(msg.contains("nam"), "{msg}");
    let e = load("{\"version\": 1,", "d.json").unwrap_err();
    assert!(e.to_string().starts_with("d.json:1:"), "{e}");
    let text = format!("{}\n[outline]\ntolerance = 0.0\n", with_b(GOOD_B));
    assert!(err_of(&text).contains("sign.toml: outline, key `tolerance`"));
    let text = format!("{}\n[outline]\nmethod = \"spline\"\n", with_b(GOOD_B));
    assert!(err_of(&text).starts_with("sign.toml:17:10:"));
}

#[test]
fn line_col_counts_characters() {
    let text = "ab\ncdé\nxyz";
    assert_eq!(line_col(text, 0), (1, 1));
    assert_eq!(line_col(text, 2), (1, 3));
    assert_eq!(line_col(text, 3), (2, 1));
    // 'é' is two bytes; the 'x' after the newline is line 3 column 1.
    let x = text.find('x').unwrap();
    assert_eq!(line_col(text, x), (3, 1));
    assert_eq!(line_col(text, x - 1), (2, 4));
    assert_eq!(line_col(text, 10_000), (3, 4));
}

/// A design using every key of the format.
fn full_design() -> Design {
    let mut s1 = Stroke::from_disks(
        "s1",
        vec![
            [0.0, 0.0, 2.0],
            [10.0, 5.0, 3.0],
            [20.0, 0.0, 2.0],
            [30.0, 4.0, 1.5],
        ],
    );
    s1.knots = Some(vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
    s1.attributes = Attributes {
        power: Some(vec![10.0, 20.0, 30.0, 40.5]),
        depth: Some(vec![1.0, 1.5, 2.0, 0.25]),
        feed: Some(vec![500.0, 600.0, 700.0, 800.0]),
    };
    let mut s2 = Stroke::from_disks(
        "ring",
        vec![
            [0.0, 0.0, 1.0],
            [10.0, 0.1, 1.1],
            [10.0, 10.0, 1.2],
            [0.3, 10.0, 1.0 / 3.0],
        ],
    );
    s2.closed = true;
    s2.degree = 2;
    s2.knots = Some(vec![0.0, 0.1, 0.5, 0.7, 1.0]);
    let mut s3 = Stroke::from_disks("fit", vec![]);
    s3.disks = None;
    s3.points = Some(vec![
        [0.0, 0.0, 1.0],
        [5.0, 3.0, 1.5],
        [10.0, 0.0, 1.0],
        [15.0, 2.0, 1.2],
        [20.0, 1.0, 0.8],
    ]);
    s3.fit = Some(Fit::Approximate);
    s3.parametrization = Some(Parametrization::Centripetal);
    s3.control_disks = Some(4);
    s1.layer = Some("cut".into());
    s1.color = Some("#ff0000".into());
    let mut ops = Vec::new();
    let mut p = Operation::new(OperationKind::Profile);
    p.name = Some("outside".into());
    p.layers = Some(vec!["cut".into()]);
    p.colors = Some(vec!["#ff0000".into()]);
    p.side = Some(ProfileSide::Outside);
    p.passes = Some(3);
    p.step_down = Some(1.0);
    p.depth = Some(3.0);
    p.feed = Some(900.0);
    p.tabs = Some(Tabs {
        count: 4,
        width: 3.0,
        height: 1.0,
    });
    p.lead_in = Some(2.0);
    ops.push(p);
    let mut c = Operation::new(OperationKind::Channel);
    c.width = Some(6.0);
    c.depth = Some(8.0);
    c.strokes = Some(vec!["s1".into(), "c1".into()]);
    ops.push(c);
    let mut b = Operation::new(OperationKind::Backboard);
    b.margin = Some(5.0);
    b.min_inner_radius = Some(1.5);
    ops.push(b);
    let mut h = Operation::new(OperationKind::Holes);
    h.diameter = Some(4.0);
    h.at = Some(HoleAt::Ends);
    ops.push(h);
    let mut f = Operation::new(OperationKind::Fill);
    f.pattern = Some(FillPattern::Hatch);
    f.angle = Some(45.0);
    f.spacing = Some(0.1);
    f.cross_hatch = Some(true);
    f.alternate = Some(false);
    f.power = Some(35.0);
    ops.push(f);
    let mut v = Operation::new(OperationKind::Vcarve);
    v.angle = Some(60.0);
    v.max_depth = Some(4.0);
    ops.push(v);
    Design {
        version: VERSION,
        units: Units::Inch,
        outline: Some(Outline {
            method: Some(OutlineMethod::Mph),
            tolerance: Some(0.01),
        }),
        stroke: vec![s1, s2, s3],
        circles: vec![CircleSeq {
            name: "c1".into(),
            closed: true,
            circles: vec![[0.0, 0.0, 2.0], [6.0, 1.0, 2.5], [12.0, 0.0, 2.0]],
        }],
        shape: vec![],
        text: vec![],
        operation: ops,
        file: "round.trip".into(),
        corners: vec![],
        neon: None,
        output: vec![Output {
            name: "board".into(),
            machine: "grbl-router".into(),
            operations: Some(vec![
                OperationRef::Index(1),
                OperationRef::Name("fill".into()),
            ]),
            layers: Some(vec!["cut".into()]),
            colors: Some(vec!["#ff0000".into()]),
            file: Some("{stem}-{name}.nc".into()),
        }],
    }
}

#[test]
fn toml_round_trip() {
    let d = full_design();
    validate(&d).unwrap();
    let text = d.to_toml_string().unwrap();
    let back = from_str(&text, Format::Toml, "round.trip").unwrap();
    assert_eq!(back, d, "{text}");
    // Twice: the text is a fixed point.
    assert_eq!(back.to_toml_string().unwrap(), text);
}

#[test]
fn json_round_trip() {
    let d = full_design();
    let text = d.to_json_string().unwrap();
    let back = from_str(&text, Format::Json, "round.trip").unwrap();
    assert_eq!(back, d, "{text}");
    // Across formats: TOML → model → JSON → model.
    let via = from_str(&d.to_toml_string().unwrap(), Format::Toml, "round.trip").unwrap();
    let again = from_str(&via.to_json_string().unwrap(), Format::Json, "round.trip").unwrap();
    assert_eq!(again, d);
}

#[test]
fn defaults_are_filled_in() {
    let d = from_str(
        "version = 1\n[[stroke]]\nname = \"s\"\ndisks = [[0,0,1],[1,1,1],[2,0,1],[3,1,1]]\n",
        Format::Toml,
        FILE,
    )
    .unwrap();
    assert_eq!(d.units, Units::Mm);
    assert_eq!(d.stroke[0].degree, 3);
    assert!(!d.stroke[0].closed);
    assert!(d.operation.is_empty() && d.outline.is_none());
    // Integers in the file are read as floats.
    assert_eq!(d.stroke[0].disks.as_ref().unwrap()[1], [1.0, 1.0, 1.0]);
}

fn disks(v: &[[f64; 3]]) -> Vec<Circle> {
    v.iter().map(|&a| Circle::from_xyr(a)).collect()
}

#[test]
fn strokes_match_direct_construction() {
    let d = full_design();
    let built = d.stroke[0].to_dbsc(FILE, 0).unwrap();
    let direct = DiskBSpline::open(
        3,
        &disks(d.stroke[0].disks.as_ref().unwrap()),
        d.stroke[0].knots.clone(),
    )
    .unwrap();
    assert_eq!(built, direct);
    // Clamped: the curve starts and ends on its end disks.
    let c = built.circle_at(0.0);
    assert!((c.c - DVec2::new(0.0, 0.0)).length() < 1e-12 && (c.r - 2.0).abs() < 1e-12);
    let c = built.circle_at(1.0);
    assert!((c.c - DVec2::new(30.0, 4.0)).length() < 1e-12 && (c.r - 1.5).abs() < 1e-12);
}

#[test]
fn closed_breakpoints_are_affine_invariant() {
    // Breakpoints [0, .1, .5, .7, 1] and their image under u ↦ 3u + 2 give the same curve
    // at corresponding parameters, and the closed curve meets itself at the seam.
    let d = full_design();
    let mut s = d.stroke[1].clone();
    let a = s.to_dbsc(FILE, 1).unwrap();
    s.knots = Some(vec![2.0, 2.3, 3.5, 4.1, 5.0]);
    let b = s.to_dbsc(FILE, 1).unwrap();
    for i in 0..=40 {
        let t = i as f64 / 40.0;
        let (ca, cb) = (a.circle_at(t), b.circle_at(3.0 * t + 2.0));
        assert!((ca.c - cb.c).length() < 1e-9 && (ca.r - cb.r).abs() < 1e-9);
    }
    let (c0, c1) = (a.circle_at(0.0), a.circle_at(1.0 - 1e-12));
    assert!((c0.c - c1.c).length() < 1e-9);
    assert_eq!(a.breakpoints(), vec![0.0, 0.1, 0.5, 0.7, 1.0]);
}

#[test]
fn attribute_curve_blends_like_the_disks() {
    // wu-2021 eq. 18: attributes blend with the same basis as the disks, so a channel
    // holding each control disk's x (or r) reproduces q(t).x (or r(t)); constant values
    // stay constant (partition of unity). Open, closed, uniform and explicit knots.
    let d = full_design();
    for (i, s) in d.stroke.iter().take(2).enumerate() {
        let curve = s.to_dbsc(FILE, i).unwrap();
        let ds = s.disks.as_ref().unwrap();
        let xs: Vec<f64> = ds.iter().map(|v| v[0]).collect();
        let rs: Vec<f64> = ds.iter().map(|v| v[2]).collect();
        let ax = attribute_curve(&curve, &xs).unwrap();
        let ar = attribute_curve(&curve, &rs).unwrap();
        let ac = attribute_curve(&curve, &vec![7.5; ds.len()]).unwrap();
        let (lo, hi) = curve.domain();
        for k in 0..=50 {
            let t = lo + (hi - lo) * k as f64 / 50.0;
            assert!((ax.eval(t) - curve.center(t).x).abs() < 1e-12);
            assert!((ar.eval(t) - curve.radius(t)).abs() < 1e-12);
            assert!((ac.eval(t) - 7.5).abs() < 1e-12);
        }
    }
}

#[test]
fn find_names() {
    let d = full_design();
    assert_eq!(
        d.find("ring"),
        Some(Item::Stroke {
            index: 1,
            name: "ring".into()
        })
    );
    assert_eq!(
        d.find("c1"),
        Some(Item::Circles {
            index: 0,
            name: "c1".into()
        })
    );
    assert_eq!(d.find("nope"), None);
}

/// The example designs shipped in examples/.
const EXAMPLES: &[(&str, &str)] = &[
    ("brush.toml", include_str!("../../examples/brush.toml")),
    ("ring_o.toml", include_str!("../../examples/ring_o.toml")),
    ("loop.toml", include_str!("../../examples/loop.toml")),
    (
        "seahorse.toml",
        include_str!("../../examples/seahorse.toml"),
    ),
    ("snake.toml", include_str!("../../examples/snake.toml")),
    ("gclef.toml", include_str!("../../examples/gclef.toml")),
    (
        "neon_word.toml",
        include_str!("../../examples/neon_word.toml"),
    ),
    (
        "calligraphy.toml",
        include_str!("../../examples/calligraphy.toml"),
    ),
    ("circles.toml", include_str!("../../examples/circles.toml")),
];

/// Samples per knot span when scanning an example's envelope.
const SCAN_PER_SPAN: usize = 64;

#[test]
fn examples_load_and_have_sign_sizes() {
    for (name, text) in EXAMPLES {
        let d = load(text, name).unwrap_or_else(|e| panic!("{e}"));
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        let mut grow = |c: Circle| {
            lo = lo.min(c.c - DVec2::splat(c.r));
            hi = hi.max(c.c + DVec2::splat(c.r));
        };
        for curve in d.strokes().unwrap_or_else(|e| panic!("{e}")) {
            let (a, b) = curve.domain();
            for k in 0..=200 {
                grow(curve.circle_at(a + (b - a) * k as f64 / 200.0));
            }
        }
        for seq in d.circle_sequences() {
            seq.into_iter().for_each(&mut grow);
        }
        let size = (hi - lo).max_element();
        assert!((50.0..=300.0).contains(&size), "{name}: size {size} mm");
    }
}

/// min over samples of τ±(t) / (‖q′‖²) on both sides, and whether the envelope exists.
fn min_tau(curve: &DiskBSpline) -> (f64, bool) {
    let bp = curve.breakpoints();
    let mut worst = f64::INFINITY;
    let mut exists = true;
    for w in bp.windows(2) {
        for k in 0..SCAN_PER_SPAN {
            let t = w[0] + (w[1] - w[0]) * (k as f64 + 0.5) / SCAN_PER_SPAN as f64;
            let q1 = curve.derivs(t, 1)[1].0.length_squared();
            for side in [Side::Left, Side::Right] {
                match curve.tau(side, t) {
                    Some(tau) => worst = worst.min(tau / q1),
                    None => exists = false,
                }
            }
        }
    }
    (worst, exists)
}

#[test]
fn examples_envelopes_are_loop_free_except_loop_toml() {
    for (name, text) in EXAMPLES {
        let d = load(text, name).unwrap();
        let curves = d.strokes().unwrap();
        let taus: Vec<(f64, bool)> = curves.iter().map(min_tau).collect();
        for (i, &(tau, exists)) in taus.iter().enumerate() {
            assert!(exists, "{name}: stroke {i} has no envelope somewhere");
            if *name != "loop.toml" {
                assert!(tau > 0.0, "{name}: stroke {i} envelope loops (tau {tau})");
            }
        }
        if *name == "loop.toml" {
            assert!(taus.iter().any(|&(t, _)| t < 0.0), "loop.toml has no loop");
        }
    }
}

#[test]
fn examples_round_trip_and_reverse() {
    for (name, text) in EXAMPLES {
        let d = load(text, name).unwrap();
        let back = from_str(&d.to_toml_string().unwrap(), Format::Toml, name).unwrap();
        assert_eq!(back, d, "{name}");
        let back = from_str(&d.to_json_string().unwrap(), Format::Json, name).unwrap();
        assert_eq!(back, d, "{name}");
        // Reversing a stroke swaps its sides; loops stay loops and loop-free stays so.
        for curve in d.strokes().unwrap() {
            let rev = DiskBSpline::from_curve(curve.curve().reversed());
            let (a, b) = (min_tau(&curve), min_tau(&rev));
            assert_eq!(a.1, b.1, "{name}");
            assert_eq!(a.0 > 0.0, b.0 > 0.0, "{name}: {} vs {}", a.0, b.0);
        }
    }
}

/// Relative error, in units of f64::EPSILON, that serde_json's fast float parser may add.
const JSON_ULPS: f64 = 2.0;

/// Finite numbers over many magnitudes, as a design might hold them.
fn coord() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![-1e4f64..1e4, -1e-3f64..1e-3, (-1e7f64..1e7)]
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// Any valid disk list survives TOML bit for bit, and JSON to within serde_json's
    /// default float parser (which can be one ulp off without its `float_roundtrip`
    /// feature).
    #[test]
    fn random_designs_round_trip(
        pts in proptest::collection::vec((coord(), coord(), 1e-3f64..1e3), 4..12),
        closed in proptest::prelude::any::<bool>(),
    ) {
        let disks: Vec<[f64; 3]> = pts.iter().map(|&(x, y, r)| [x, y, r]).collect();
        // Neighbours apart by more than the near-repeat tolerance (validation refuses them).
        let size = disks.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
        let apart = |a: &[f64; 3], b: &[f64; 3]| {
            (a[0] - b[0]).hypot(a[1] - b[1]) + (a[2] - b[2]).abs() > NEAR_FRACTION * size
        };
        proptest::prop_assume!(disks.windows(2).all(|w| apart(&w[0], &w[1])));
        proptest::prop_assume!(!closed || apart(&disks[0], &disks[disks.len() - 1]));
        let mut s = Stroke::from_disks("p", disks.clone());
        s.closed = closed;
        s.attributes.depth = Some(disks.iter().map(|d| d[2]).collect());
        let d = Design {
            version: VERSION,
            units: Units::Mm,
            outline: None,
            stroke: vec![s],
            circles: vec![CircleSeq { name: "q".into(), closed, circles: disks }],
            shape: vec![],
            text: vec![],
            operation: vec![],
            file: "p.toml".into(),
            corners: vec![],
            neon: None,
            output: vec![],
        };
        validate(&d).unwrap();
        let t = from_str(&d.to_toml_string().unwrap(), Format::Toml, "p.toml").unwrap();
        proptest::prop_assert_eq!(&t, &d);
        let mut j = from_str(&d.to_json_string().unwrap(), Format::Json, "p.toml").unwrap();
        let flat = |d: &Design| -> Vec<f64> {
            let s = &d.stroke[0];
            let mut v: Vec<f64> = s.disks.iter().flatten().flatten().copied().collect();
            v.extend(s.attributes.depth.iter().flatten());
            v.extend(d.circles[0].circles.iter().flatten());
            v
        };
        for (a, b) in flat(&j).into_iter().zip(flat(&d)) {
            proptest::prop_assert!((a - b).abs() <= JSON_ULPS * f64::EPSILON * b.abs(), "{a} {b}");
        }
        j.stroke = d.stroke.clone();
        j.circles = d.circles.clone();
        proptest::prop_assert_eq!(&j, &d);
    }
}

/// Data points of a points stroke as circles.
fn data(s: &Stroke) -> Vec<Circle> {
    disks(s.points.as_ref().unwrap())
}

#[test]
fn points_strokes_interpolate_their_data() {
    // The interpolant's disk at the data parameter t_i is data point i (wu-2021
    // "Interpolation"); the parameters are recomputed independently of the build.
    let pts = "points = [[0.0, 0.0, 2.0], [30.0, 15.0, 2.5], [60.0, 10.0, 2.2], \
               [85.0, 30.0, 3.0], [70.0, 60.0, 2.5], [30.0, 55.0, 2.2]]";
    for closed in [false, true] {
        for (name, kind) in [
            ("chord", crate::spline::fit::Parametrization::ChordLength),
            (
                "centripetal",
                crate::spline::fit::Parametrization::Centripetal,
            ),
            ("uniform", crate::spline::fit::Parametrization::Uniform),
        ] {
            let body = format!("{pts}\nclosed = {closed}\nparametrization = \"{name}\"");
            let d = from_str(&with_b(&body), Format::Toml, FILE).unwrap();
            let curve = &d.strokes().unwrap()[1];
            assert_eq!(curve.is_closed(), closed);
            assert_eq!(
                curve.control_disks().len(),
                d.stroke[1].control_disk_count()
            );
            let data = data(&d.stroke[1]);
            let t = crate::dbsc::disk_parameters(&data, closed, kind).unwrap();
            for (i, c) in data.iter().enumerate() {
                let got = curve.circle_at(t[i]);
                assert!((got.c - c.c).length() < 1e-9, "{name} {closed} point {i}");
                assert!((got.r - c.r).abs() < 1e-9, "{name} {closed} point {i}");
            }
        }
    }
}

#[test]
fn points_strokes_approximate() {
    let d = full_design();
    let curves = d.strokes().unwrap();
    let s = &d.stroke[2];
    let c = &curves[2];
    assert_eq!(c.control_disks().len(), 4);
    // Open approximations keep the end disks (P&T Sec. 9.4.1).
    let data = data(s);
    let (lo, hi) = c.domain();
    for (t, want) in [(lo, data[0]), (hi, data[data.len() - 1])] {
        let got = c.circle_at(t);
        assert!((got.c - want.c).length() < 1e-9 && (got.r - want.r).abs() < 1e-9);
    }
    // Least squares: no worse than the chord through the end disks at the data.
    let t =
        crate::dbsc::disk_parameters(&data, false, s.parametrization.unwrap().to_fit()).unwrap();
    let err: f64 = data
        .iter()
        .zip(&t)
        .map(|(d, &ti)| (c.circle_at(ti).c - d.c).length_squared())
        .sum();
    let line: f64 = data
        .iter()
        .zip(&t)
        .map(|(d, &ti)| (data[0].c.lerp(data[4].c, ti) - d.c).length_squared())
        .sum();
    assert!(err < line, "{err} vs {line}");
    // An interpolation's attribute channels count one value per point.
    let b = "points = [[0.0, 0.0, 1.0], [5.0, 3.0, 1.5], [10.0, 0.0, 1.0], [15.0, 2.0, 1.2], \
             [20.0, 0.0, 1.0]]\n[stroke.attributes]\npower = [10, 20, 30, 40, 50]";
    let d = from_str(&with_b(b), Format::Toml, FILE).unwrap();
    let curve = &d.strokes().unwrap()[1];
    let chans = d.stroke[1].attribute_curves(curve, FILE, 1).unwrap();
    assert_eq!(chans.len(), 1);
    let (name, a) = &chans[0];
    assert_eq!(*name, "power");
    assert!((a.eval(curve.domain().0) - 10.0).abs() < 1e-12);
    assert!((a.eval(curve.domain().1) - 50.0).abs() < 1e-12);
}

#[test]
fn fit_failure_names_the_stroke() {
    // Radii jumping 1 → 6 → 1 between close points: the interpolant's control radius
    // overshoots below zero, which the fit reports.
    let b = "points = [[0.0, 0.0, 1.0], [4.0, 0.0, 1.0], [8.0, 0.0, 6.0], [12.0, 0.0, 1.0], \
             [16.0, 0.0, 1.0], [20.0, 0.0, 6.0], [24.0, 0.0, 1.0]]";
    let msg = err_of(&with_b(b));
    assert_names(&msg, "stroke 1", "fitting `points`");
    assert!(msg.contains("non-positive radius"), "{msg}");
}

#[test]
fn attribute_curves_reject_a_mismatched_curve() {
    // Attribute counts are validated against the stroke; used with another stroke's curve
    // the channel no longer fits, and the error names the stroke and the channel.
    let mut d = full_design();
    let other = d.stroke[1].to_dbsc(FILE, 1).unwrap();
    d.stroke[0].attributes.power = Some(vec![1.0; 7]);
    let e = d.stroke[0].attribute_curves(&other, FILE, 0).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.starts_with("sign.toml: stroke 0 \"s1\", key `attributes.power`"),
        "{msg}"
    );
}
