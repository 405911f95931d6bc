//! One backboard around a whole sign (issue 41 item 6) and honest scaling (item 7): the
//! board of "Bar & Grill" read back from the written G-code is one ring around every channel
//! at the margin; mounting holes sit at the stated inset; a shrinking `--fit` warns where a
//! letter's counter fills. (The bridges' width is a unit test of the toolpath module.)

use crate::support;

use skinpath::geom::DVec2;
use support::{skinpath_in, tmpdir};

/// A cutting move of the G-code, its arcs flattened: the points it passes at depth z.
#[derive(Debug)]
struct Cut {
    z: f64,
    points: Vec<DVec2>,
    /// Centre of a G2/G3 arc.
    centre: Option<DVec2>,
}

/// The cutting moves (G1/G2/G3 in xy) of each `(op ...)` section of a G-code program, by
/// the section's name; a G0 or a move in z ends a contour (recorded as `None`).
fn sections(gcode: &str) -> Vec<(String, Vec<Option<Cut>>)> {
    let mut out: Vec<(String, Vec<Option<Cut>>)> = Vec::new();
    let (mut pos, mut z, mut mode) = (DVec2::ZERO, 0.0, 0);
    for line in gcode.lines() {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix("(op ") {
            out.push((rest.trim_end_matches(')').to_string(), Vec::new()));
            continue;
        }
        if line.starts_with('(') || line.is_empty() {
            continue;
        }
        let word = |c: char| {
            line.split_whitespace()
                .find(|w| w.starts_with(c))
                .and_then(|w| w[1..].parse::<f64>().ok())
        };
        if let Some(g) = word('G')
            && [0.0, 1.0, 2.0, 3.0].contains(&g)
        {
            mode = g as i32;
        }
        let (x, y, nz, i, j) = (word('X'), word('Y'), word('Z'), word('I'), word('J'));
        let to = DVec2::new(x.unwrap_or(pos.x), y.unwrap_or(pos.y));
        let Some((_, cuts)) = out.last_mut() else {
            pos = to;
            z = nz.unwrap_or(z);
            continue;
        };
        if let Some(nz) = nz {
            if nz != z {
                cuts.push(None);
            }
            z = nz;
        }
        if to == pos {
            continue;
        }
        match mode {
            1 => cuts.push(Some(Cut {
                z,
                points: vec![pos, to],
                centre: None,
            })),
            2 | 3 => {
                let c = pos + DVec2::new(i.unwrap_or(0.0), j.unwrap_or(0.0));
                let (a0, a1) = ((pos - c).to_angle(), (to - c).to_angle());
                let mut sweep = a1 - a0;
                if mode == 3 && sweep <= 0.0 {
                    sweep += std::f64::consts::TAU;
                }
                if mode == 2 && sweep >= 0.0 {
                    sweep -= std::f64::consts::TAU;
                }
                let r = pos.distance(c);
                let n = ((sweep.abs() * r / 0.05).ceil() as usize).max(2);
                // The written end point closes the arc (its centre is rounded).
                let points = (0..n)
                    .map(|k| c + DVec2::from_angle(a0 + sweep * k as f64 / n as f64) * r)
                    .chain(std::iter::once(to))
                    .collect();
                cuts.push(Some(Cut {
                    z,
                    points,
                    centre: Some(c),
                }));
            }
            _ => cuts.push(None),
        }
        pos = to;
    }
    out
}

/// The closed rings a section cuts at its deepest z: runs of consecutive cutting moves at
/// that depth, each a polyline whose ends meet.
fn deepest_rings(cuts: &[Option<Cut>]) -> Vec<Vec<DVec2>> {
    let zmin = cuts
        .iter()
        .flatten()
        .map(|c| c.z)
        .fold(f64::INFINITY, f64::min);
    let mut rings: Vec<Vec<DVec2>> = Vec::new();
    let mut cur: Vec<DVec2> = Vec::new();
    for c in cuts {
        match c {
            Some(c) if c.z == zmin => {
                if cur.last().is_some_and(|p| p.distance(c.points[0]) > 1e-3) {
                    rings.push(std::mem::take(&mut cur));
                }
                cur.extend(c.points.iter().copied());
            }
            _ => {
                if !cur.is_empty() {
                    rings.push(std::mem::take(&mut cur));
                }
            }
        }
    }
    if !cur.is_empty() {
        rings.push(cur);
    }
    rings
}

/// Winding number of the closed polygon `ring` about `p` (crossings of the ray +x).
fn winding(ring: &[DVec2], p: DVec2) -> i32 {
    let mut w = 0;
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        let side = (b - a).perp_dot(p - a);
        if a.y <= p.y && b.y > p.y && side > 0.0 {
            w += 1;
        } else if a.y > p.y && b.y <= p.y && side < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Distance from `p` to the closed polygon `ring`.
fn distance_to_ring(ring: &[DVec2], p: DVec2) -> f64 {
    (0..ring.len())
        .map(|k| {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            let d = b - a;
            let t = ((p - a).dot(d) / d.length_squared().max(1e-300)).clamp(0.0, 1.0);
            p.distance(a + d * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// grbl-router's end mill: 3.175 mm.
const TOOL_R: f64 = 3.175 / 2.0;

/// Writes "Bar & Grill" with the neon starter's operations (plus `backboard_extra` in the
/// backboard table) and builds it on `machine`; returns the program text and the stdout.
fn bar_and_grill(dir: &std::path::Path, machine: &str, backboard_extra: &str) -> (String, String) {
    let o = skinpath_in(
        &[
            "text",
            "Bar & Grill",
            "--neon",
            "--height",
            "30",
            "-o",
            "bg.toml",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let toml = std::fs::read_to_string(dir.join("bg.toml")).unwrap();
    let toml = toml.replace(
        "kind = \"backboard\"",
        &format!("kind = \"backboard\"\n{backboard_extra}"),
    );
    std::fs::write(dir.join("bg.toml"), toml).unwrap();
    let ext = "bg.gcode";
    let o = skinpath_in(&["build", "bg.toml", "-m", machine, "-o", ext], dir);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(stdout.contains("check: 0 errors, 0 warnings"), "{stdout}");
    // The written program checks clean on its own, with no flags.
    let c = skinpath_in(&["check", ext, "-m", machine], dir);
    let check = String::from_utf8_lossy(&c.stdout).to_string();
    assert!(
        c.status.success(),
        "{check}{}",
        String::from_utf8_lossy(&c.stderr)
    );
    (std::fs::read_to_string(dir.join(ext)).unwrap(), stdout)
}

/// The board of "Bar & Grill" (three words apart) is one ring at full depth, around every
/// channel, and at least the margin (5 mm) from every channel's edge (the channels are
/// 0.5 mm wider than the strokes): the channel tool's centre is margin + 2r from the board
/// tool's centre path.
#[test]
fn bar_and_grill_board_is_one_piece_around_every_channel() {
    let dir = tmpdir("one");
    let (gcode, _) = bar_and_grill(&dir, "grbl-router", "");
    let secs = sections(&gcode);
    let board: Vec<_> = secs
        .iter()
        .filter(|(n, _)| n.ends_with("backboard"))
        .collect();
    assert_eq!(
        board.len(),
        1,
        "{:?}",
        secs.iter().map(|s| &s.0).collect::<Vec<_>>()
    );
    let rings = deepest_rings(&board[0].1);
    assert_eq!(
        rings.len(),
        1,
        "the board is one piece: {} rings",
        rings.len()
    );
    let ring = &rings[0];
    assert!(
        ring[0].distance(ring[ring.len() - 1]) < 1e-2,
        "a closed ring"
    );
    let channel: Vec<DVec2> = secs
        .iter()
        .filter(|(n, _)| n.contains("channel"))
        .flat_map(|(_, c)| c.iter().flatten().flat_map(|c| c.points.clone()))
        .collect();
    assert!(channel.len() > 100);
    let margin = 5.0;
    for p in &channel {
        assert_ne!(winding(ring, *p), 0, "channel point {p} outside the board");
        let d = distance_to_ring(ring, *p);
        assert!(
            d >= margin + 2.0 * TOOL_R - 0.05,
            "channel at {p} is {d} from the board path"
        );
    }
}

/// Mounting holes: four holes whose centres are the inset (8 mm) from the board's edge (the
/// board path less the tool radius), clear of the channels by the wall, in the board.
#[test]
fn mounting_holes_sit_at_the_inset() {
    let dir = tmpdir("mount");
    let (gcode, _) = bar_and_grill(
        &dir,
        "grbl-router",
        "margin = 14.0\nmounting_holes = { count = 4, diameter = 5.0, inset = 8.0 }",
    );
    let secs = sections(&gcode);
    let ring = deepest_rings(
        &secs
            .iter()
            .find(|(n, _)| n.ends_with("3 backboard"))
            .expect("the board's cut")
            .1,
    )
    .remove(0);
    let holes = &secs
        .iter()
        .find(|(n, _)| n.contains("mounting holes"))
        .expect("the mounting holes")
        .1;
    let mut centres: Vec<DVec2> = Vec::new();
    for c in holes.iter().flatten() {
        let p = c.centre.expect("holes are arcs");
        if centres.iter().all(|q| q.distance(p) > 1e-3) {
            centres.push(p);
        }
    }
    assert_eq!(centres.len(), 4, "{centres:?}");
    let channel: Vec<DVec2> = secs
        .iter()
        .filter(|(n, _)| n.contains("channel"))
        .flat_map(|(_, c)| c.iter().flatten().flat_map(|c| c.points.clone()))
        .collect();
    for p in &centres {
        assert_ne!(winding(&ring, *p), 0);
        let edge = distance_to_ring(&ring, *p) - TOOL_R;
        assert!((edge - 8.0).abs() < 0.05, "hole {p}: {edge} from the edge");
        let wall = channel
            .iter()
            .map(|q| q.distance(*p))
            .fold(f64::INFINITY, f64::min)
            - TOOL_R
            - 2.5;
        assert!(wall >= 2.0 - 0.05, "hole {p}: wall {wall} to a channel");
    }
    // Farthest apart, they span the board: one near each end.
    let xs: Vec<f64> = centres.iter().map(|p| p.x).collect();
    let span = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - xs.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(span > 150.0, "{span}");
}

/// On the laser the board is one ring too, and the program checks clean.
#[test]
fn bar_and_grill_board_is_one_piece_on_the_laser() {
    let dir = tmpdir("laser");
    let (gcode, _) = bar_and_grill(&dir, "grbl-laser", "");
    let secs = sections(&gcode);
    let board = secs
        .iter()
        .find(|(n, _)| n.ends_with("backboard"))
        .expect("the board's cut");
    let rings = deepest_rings(&board.1);
    assert_eq!(rings.len(), 1, "{} rings", rings.len());
}

/// A shrinking `--fit` warns where a letter's counter fills (the B's and the &'s), naming
/// the run and stroke; at the design's size there is no merge warning.
#[test]
fn shrinking_fit_warns_where_counters_fill() {
    let dir = tmpdir("fit");
    bar_and_grill(&dir, "grbl-router", "");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "build",
            "bg.toml",
            "-m",
            "grbl-router",
            "-o",
            "f.gcode",
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = skinpath_in(&args, &dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let w = v["neon"]["warnings"].as_array().unwrap().clone();
        w.into_iter()
            .filter(|w| w["kind"] == "merge")
            .map(|w| w["message"].as_str().unwrap().to_string())
            .collect::<Vec<_>>()
    };
    assert!(run(&[]).is_empty());
    let w = run(&["--fit", "120x40"]);
    let counters: Vec<_> = w.iter().filter(|m| m.contains("counter")).collect();
    assert!(counters.iter().any(|m| m.contains(":B/")), "{w:?}");
    assert!(counters.iter().any(|m| m.contains(":u26/")), "{w:?}");
    assert!(
        w.iter().any(|m| m.contains("their channels merge")),
        "{w:?}"
    );
}

/// A ring stroke of radius R (an "O") with a channel of width w: its counter, a disk of
/// radius R − w/2, fills when the scale s makes R·s ≤ w/2 (s ≤ 0.25): none at 0.3, one at 0.2.
#[test]
fn a_ring_counter_fills_below_the_closed_form_scale() {
    let dir = tmpdir("ring");
    let r: f64 = 20.0;
    let n = 36;
    let disks: Vec<String> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            format!(
                "[{:.12}, {:.12}, 2.0]",
                60.0 + r * a.cos(),
                60.0 + r * a.sin()
            )
        })
        .collect();
    let text = format!(
        "version = 1\n[neon]\nflex = \"6mm\"\nmin_bend_radius = 1.0\n[[stroke]]\nname = \"o\"\n\
         closed = true\npoints = [{}]\n[[operation]]\nkind = \"channel\"\nwidth = 10.0\n",
        disks.join(", ")
    );
    std::fs::write(dir.join("o.toml"), text).unwrap();
    let merges = |scale: f64| {
        let s = format!("{scale}");
        let o = skinpath_in(
            &[
                "build",
                "o.toml",
                "-m",
                "grbl-router",
                "-o",
                "o.gcode",
                "--json",
                "--scale",
                &s,
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v["neon"]["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "merge")
            .count()
    };
    // w/2 = 5 = R·s at s = 0.25. At the design's size the counter is a disk of radius
    // R − w/2 = 15, far above the smallest island counted (radius w/4).
    assert_eq!(merges(0.3), 0);
    assert_eq!(merges(0.2), 1);
}

/// The new backboard keys are checked and their errors name the key.
#[test]
fn backboard_keys_are_validated() {
    let base = "version = 1\n[[stroke]]\nname = \"s\"\ndisks = [[0, 0, 2], [50, 0, 2]]\n\
        [[operation]]\n";
    let err = |op: &str| {
        skinpath::design::load(&format!("{base}{op}"), "b.toml")
            .unwrap_err()
            .to_string()
    };
    let e = err("kind = \"backboard\"\nmounting_holes = { count = 0, diameter = 5.0 }\n");
    assert!(e.contains("mounting_holes.count"), "{e}");
    let e = err("kind = \"backboard\"\nmounting_holes = { count = 2, diameter = -5.0 }\n");
    assert!(e.contains("mounting_holes.diameter"), "{e}");
    let e = err("kind = \"backboard\"\nbridge_width = -1.0\n");
    assert!(e.contains("bridge_width"), "{e}");
    let e = err("kind = \"channel\"\nwidth = 3.0\nbridge_width = 5.0\n");
    assert!(e.contains("does not apply"), "{e}");
    let ok = skinpath::design::load(
        &format!(
            "{base}kind = \"backboard\"\nbridge_width = 0.0\nmounting_holes = {{ count = 2, diameter = 4.0, inset = 6.0 }}\n"
        ),
        "b.toml",
    );
    assert!(ok.is_ok(), "{ok:?}");
}

/// Signed circumradii along a closed ring resampled every `h` (arc length): positive where
/// the ring turns with its orientation (a convex corner of the region it bounds).
fn signed_circumradii(ring: &[DVec2], h: f64) -> Vec<(f64, DVec2)> {
    let mut even = vec![ring[0]];
    let mut left = h;
    for w in ring.windows(2) {
        let (mut a, b) = (w[0], w[1]);
        while a.distance(b) >= left {
            a += (b - a).normalize() * left;
            even.push(a);
            left = h;
        }
        left -= a.distance(b);
    }
    let area: f64 = ring.windows(2).map(|w| w[0].perp_dot(w[1])).sum::<f64>();
    let n = even.len();
    (0..n)
        .map(|k| {
            let (a, b, c) = (even[(k + n - 1) % n], even[k], even[(k + 1) % n]);
            let cr = (b - a).perp_dot(c - b);
            let r = if cr == 0.0 {
                f64::INFINITY
            } else {
                a.distance(b) * b.distance(c) * c.distance(a) / (2.0 * cr.abs())
            };
            (if (cr > 0.0) == (area > 0.0) { r } else { -r }, b)
        })
        .collect()
}

/// `corner_radius = 15`: every convex turn of the board's tool path (outside the board by
/// the tool radius) has radius ≥ 15 + r, measured by circumcircles of the path read back
/// from the G-code, while without it the margin's corners (5 + r) are tighter; the board
/// stays one ring around every channel at the margin; concave corners are the tool's (its
/// path's concave turns are cut by a tool of radius r, so the board's are ≥ r).
#[test]
fn corner_radius_rounds_the_board_s_convex_corners() {
    let rc = 15.0;
    let dir = tmpdir("corner");
    let ring_of = |extra: &str| {
        let (gcode, _) = bar_and_grill(&dir, "grbl-router", extra);
        let secs = sections(&gcode);
        let board: Vec<_> = secs
            .iter()
            .filter(|(n, _)| n.ends_with("backboard"))
            .collect();
        let rings = deepest_rings(&board[0].1);
        assert_eq!(rings.len(), 1, "one piece");
        let channel: Vec<DVec2> = secs
            .iter()
            .filter(|(n, _)| n.contains("channel"))
            .flat_map(|(_, c)| c.iter().flatten().flat_map(|c| c.points.clone()))
            .collect();
        (rings[0].clone(), channel)
    };
    let convex_min = |ring: &[DVec2]| {
        signed_circumradii(ring, 2.0)
            .into_iter()
            .filter(|(r, _)| *r > 0.0)
            .map(|(r, _)| r)
            .fold(f64::INFINITY, f64::min)
    };
    let (plain, _) = ring_of("");
    let before = convex_min(&plain);
    assert!(before < rc, "the margin's corners: {before}");
    let (ring, channel) = ring_of(&format!("corner_radius = {rc}"));
    let after = convex_min(&ring);
    assert!(after >= (rc + TOOL_R) * 0.98, "{after}");
    for p in &channel {
        assert_ne!(winding(&ring, *p), 0, "channel point {p} outside the board");
        assert!(distance_to_ring(&ring, *p) >= 5.0 + 2.0 * TOOL_R - 0.05);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
