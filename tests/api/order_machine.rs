//! Cut order in machine coordinates (issue 42, item 5): the order, the seams of closed
//! contours and the travel figures are chosen from the machine's origin after placement
//! and scale, so that a design moved before placement builds to the same program byte for
//! byte, and the travel the summary prints is the travel of the written program.

use crate::support;

use std::path::Path;
use support::{skinpath, tmpdir};

/// The shift of the moved design, as in the issue.
const MOVE: [f64; 2] = [10000.0, -5000.0];

/// A design of several items whose order matters: two closed rings, an open stroke between
/// them and a short one above, each given as disks (x, y, r) shifted by `d`.
fn design(d: [f64; 2]) -> String {
    let items: [(&str, bool, &[[f64; 3]]); 4] = [
        (
            "ring_a",
            true,
            &[
                [45.0, 30.0, 3.0],
                [30.0, 45.0, 4.0],
                [15.0, 30.0, 3.5],
                [30.0, 15.0, 4.5],
            ],
        ),
        (
            "ring_b",
            true,
            &[
                [110.0, 40.0, 4.0],
                [90.0, 61.3, 3.0],
                [70.4, 40.0, 5.0],
                [90.0, 19.7, 3.5],
            ],
        ),
        (
            "wave",
            false,
            &[
                [12.0, 80.0, 2.0],
                [40.0, 95.5, 3.5],
                [70.0, 78.0, 4.0],
                [104.0, 92.0, 2.5],
            ],
        ),
        (
            "dash",
            false,
            &[[30.0, 118.0, 2.0], [55.0, 123.7, 3.0], [80.0, 117.0, 2.0]],
        ),
    ];
    let mut s = String::from("version = 1\nunits = \"mm\"\n");
    for (name, closed, disks) in items {
        s.push_str(&format!(
            "\n[[stroke]]\nname = \"{name}\"\ndegree = {}\nclosed = {closed}\ndisks = [\n",
            if disks.len() > 3 { 3 } else { 2 }
        ));
        for [x, y, r] in disks {
            // Written as a person would write the moved design: the shifted values in
            // decimal, read back as the nearest doubles.
            s.push_str(&format!("  [{}, {}, {r}],\n", x + d[0], y + d[1]));
        }
        s.push_str("]\n");
    }
    s
}

/// Builds `toml` (saved as `job.toml` in `dir`, so that the job name is the same) with
/// `args`: the program and the summary printed.
fn build(dir: &Path, toml: &str, args: &[&str]) -> (String, String) {
    std::fs::create_dir_all(dir).expect("create dir");
    let f = dir.join("job.toml");
    std::fs::write(&f, toml).expect("write design");
    let out = dir.join("job.gcode");
    let (fs, os) = (f.to_string_lossy(), out.to_string_lossy());
    let mut all = vec!["build", fs.as_ref(), "-o", os.as_ref()];
    all.extend_from_slice(args);
    let o = skinpath(&all);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "build {args:?}: {stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    (std::fs::read_to_string(&out).expect("program"), stdout)
}

/// The design moved by (10000, −5000) gives the same program as the design, byte for byte,
/// on lasers and routers of four dialects, placed at the lower-left corner or the centre,
/// with a margin, scaled by a factor or to fit a size.
#[test]
fn moved_design_builds_to_the_same_program() {
    let d = tmpdir("order-moved");
    let (here, moved) = (design([0.0, 0.0]), design(MOVE));
    let cases: &[&[&str]] = &[
        &["--machine", "grbl-laser"],
        &["--machine", "marlin-laser"],
        &["--machine", "grbl-router"],
        &["--machine", "linuxcnc-router"],
        &["--machine", "grbl-laser", "--place", "center"],
        &["--machine", "grbl-router", "--place", "center"],
        &["--machine", "smoothie-laser", "--scale", "0.5"],
        &["--machine", "grbl-laser", "--margin", "7.5"],
        &["--machine", "grbl-laser", "--fit", "60x50"],
    ];
    for args in cases {
        let (a, _) = build(&d.join("here"), &here, args);
        let (b, _) = build(&d.join("moved"), &moved, args);
        assert!(a.lines().count() > 20, "{args:?}: {a}");
        if a != b {
            let first = a.lines().zip(b.lines()).position(|(x, y)| x != y);
            panic!(
                "{args:?}: the moved design's program differs from line {:?}:\n{:?}\nvs\n{:?}",
                first.map(|i| i + 1),
                first.and_then(|i| a.lines().nth(i)),
                first.and_then(|i| b.lines().nth(i))
            );
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Length of the rapid moves (G0) of a program, read independently of the checker: modal
/// motion words (G0–G3), absolute X Y Z words, comments in parentheses or after `;`. The
/// tool starts at x = y = 0 (the program's origin, where the summary's travel starts); its
/// height is unknown until the first Z word, so a move that sets the height for the first
/// time counts in xy only. Returns (xy length, length with z).
fn rapid_length(program: &str) -> (f64, f64) {
    let mut pos = [0.0f64, 0.0, 0.0];
    let mut z_known = false;
    let mut mode = 0u32;
    let (mut xy, mut xyz) = (0.0, 0.0);
    for raw in program.lines() {
        let line = raw.split(';').next().unwrap_or("");
        let mut clean = String::new();
        let mut depth = 0;
        for c in line.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ if depth == 0 => clean.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let mut to = pos;
        let mut moved = false;
        let mut sets_z = false;
        let words: Vec<(char, &str)> = split_words(&clean);
        for (letter, value) in words {
            let v: f64 = value.parse().unwrap_or(f64::NAN);
            match letter {
                'G' if [0.0, 1.0, 2.0, 3.0].contains(&v) => mode = v as u32,
                'X' | 'Y' | 'Z' => {
                    to["XYZ".find(letter).unwrap_or(0)] = v;
                    moved = true;
                    sets_z |= letter == 'Z';
                }
                _ => {}
            }
        }
        if moved {
            if mode == 0 {
                let dxy = (to[0] - pos[0]).hypot(to[1] - pos[1]);
                xy += dxy;
                xyz += if z_known {
                    dxy.hypot(to[2] - pos[2])
                } else {
                    dxy
                };
            }
            z_known |= sets_z;
            pos = to;
        }
    }
    (xy, xyz)
}

/// The words of a G-code line without comments: (letter, number text).
fn split_words(line: &str) -> Vec<(char, &str)> {
    let mut out = Vec::new();
    let b = line.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_alphabetic() {
            let start = i + 1;
            let mut j = start;
            while j < b.len() && (b[j].is_ascii_digit() || b"+-.".contains(&b[j])) {
                j += 1;
            }
            out.push((b[i] as char, &line[start..j]));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// A number following `key` in `text` (`travel 22.0` → 22.0), every occurrence.
fn numbers_after(text: &str, key: &str) -> Vec<f64> {
    text.match_indices(key)
        .filter_map(|(i, _)| {
            let rest = &text[i + key.len()..];
            let n: String = rest
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
                .collect();
            n.parse().ok()
        })
        .collect()
}

/// The travel the summary prints is the travel of the written program (the sum of its
/// rapid moves): the whole job's (`cut length …, travel T`) and, on a laser whose one
/// operation has no leads, the ordering's (`ordering …: travel A -> B`, the sum of B over
/// operations). Both in mm with one decimal; the program's coordinates are rounded to
/// 0.001 mm. For the moved design as well, where the order was once chosen from 11 km away.
#[test]
fn summary_travel_is_the_programs_travel() {
    let d = tmpdir("order-travel");
    for (k, toml) in [design([0.0, 0.0]), design(MOVE)].iter().enumerate() {
        for machine in ["grbl-laser", "marlin-laser", "smoothie-laser"] {
            for place in ["lower-left", "center"] {
                let dir = d.join(format!("{k}-{machine}-{place}"));
                let (g, summary) = build(&dir, toml, &["--machine", machine, "--place", place]);
                let (xy, xyz) = rapid_length(&g);
                assert!(xy > 10.0, "{machine} {place}: travel {xy}\n{g}");
                // Lasers move in xy only.
                assert!((xy - xyz).abs() < 1e-9);
                let rapids = g.lines().filter(|l| l.starts_with("G0")).count() as f64;
                // Each rapid's ends are rounded by up to 0.0005 mm per axis.
                let rounding = 0.05 + rapids * 2e-3;
                let total = numbers_after(&summary, ", travel ");
                assert_eq!(total.len(), 1, "{summary}");
                assert!(
                    (total[0] - xy).abs() <= rounding,
                    "{machine} {place}: summary travel {} vs program {xy}\n{summary}",
                    total[0]
                );
                let ordered: Vec<f64> = numbers_after(&summary, " -> ");
                assert!(!ordered.is_empty(), "{summary}");
                let sum: f64 = ordered.iter().sum();
                assert!(
                    (sum - xy).abs() <= rounding + 0.05 * ordered.len() as f64,
                    "{machine} {place}: ordering travel {sum} vs program {xy}\n{summary}"
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The independent reading of rapids on a program whose travel is known: from the origin to
/// (3, 4) is 5; a cut to (9, 4); a rapid to (9, 12) that sets z for the first time (8, in
/// xy only); a modal rapid continuing in z only (2, counted with z).
#[test]
fn rapid_length_reads_modal_rapids() {
    let g = "G21 G90 (start)\nG0 X3 Y4\nG1 X9 F100 ; cut\nG0 X9 Z5 Y12\nZ7\nG1 X0\n";
    let (xy, xyz) = rapid_length(g);
    assert!((xy - 13.0).abs() < 1e-12, "{xy}");
    assert!((xyz - 15.0).abs() < 1e-12, "{xyz}");
}
