//! `preview`, `inspect` and `check --design` of a design with `[[output]]` tables (issue 41
//! item 8 follow-up): one preview per output on its own machine with its own operations
//! (compared with the preview of the program `build` writes for that output), `--only`,
//! the outputs listed by `inspect`, and `check --design` taking the output's machine.

use crate::support;

use support::{OPEN_SIGN_OUTPUTS, open_sign, skinpath_in, tmpdir};

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The "(N moves, M contours" figures of a `preview` line: (N, M).
fn figures(line: &str) -> (String, String) {
    let moves = line
        .split(" moves")
        .next()
        .unwrap()
        .rsplit([' ', '('])
        .next()
        .unwrap();
    let contours = line
        .split(" contours")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap();
    (moves.to_string(), contours.to_string())
}

#[test]
fn preview_inspect_and_check_follow_the_outputs() {
    let dir = tmpdir("neon-layers");
    std::fs::write(dir.join("sign.toml"), open_sign(None, OPEN_SIGN_OUTPUTS)).unwrap();
    let run = |args: &[&str]| skinpath_in(args, &dir);
    // One preview per output, each the preview of the program `build` writes for it.
    let p = run(&["preview", "sign.toml", "-o", "p.svg"]);
    assert!(p.status.success(), "{}", stderr(&p));
    let lines: Vec<String> = stdout(&p).lines().map(str::to_string).collect();
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert!(dir.join("p.router.svg").exists() && dir.join("p.laser.svg").exists());
    assert!(!dir.join("p.svg").exists());
    let b = run(&["build", "sign.toml", "-o", "sign"]);
    assert!(b.status.success(), "{}", stderr(&b));
    for (line, (name, machine)) in lines
        .iter()
        .zip([("router", "grbl-router"), ("laser", "grbl-laser")])
    {
        assert!(
            line.contains(&format!("output {name}, machine {machine}")),
            "{line}"
        );
        let prog = format!("sign.{name}.gcode");
        let q = run(&["preview", &prog, "--machine", machine, "-o", "q.svg"]);
        assert!(q.status.success(), "{}", stderr(&q));
        // Same contours (the moves may differ by the travel from the origin: `build`
        // places the job at the work area's corner, `preview` keeps the design's place).
        assert_eq!(figures(line).1, figures(&stdout(&q)).1, "{name}");
        assert!(line.contains(" 0 findings"), "{line}");
        // `check --design` takes the output's machine from the program's file name.
        let c = run(&["check", &prog, "--design", "sign.toml", "--json"]);
        let report: serde_json::Value = serde_json::from_slice(&c.stdout).unwrap();
        assert_eq!(report["usable"], true, "{name}");
        if name == "laser" {
            assert!(c.status.success(), "{}", stdout(&c));
        }
    }
    // The face alone, cut by the laser: one contour.
    let f = figures(&lines[1]);
    assert_eq!(f.1, "1");
    // --only: just that output; with --machine, or naming no output: refused, nothing written.
    std::fs::remove_file(dir.join("p.laser.svg")).unwrap();
    std::fs::remove_file(dir.join("p.router.svg")).unwrap();
    let o = run(&["preview", "sign.toml", "-o", "p.svg", "--only", "laser"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("p.laser.svg").exists() && !dir.join("p.router.svg").exists());
    std::fs::remove_file(dir.join("p.laser.svg")).unwrap();
    let e = run(&[
        "preview",
        "sign.toml",
        "-o",
        "p.svg",
        "--only",
        "router,nope",
    ]);
    assert_eq!(e.status.code(), Some(2));
    assert!(stderr(&e).contains("--only nope") && stderr(&e).contains("router, laser"));
    assert!(!dir.join("p.router.svg").exists());
    let e = run(&[
        "preview",
        "sign.toml",
        "-o",
        "p.svg",
        "--only",
        "laser",
        "--machine",
        "grbl-laser",
    ]);
    assert_eq!(e.status.code(), Some(2));
    assert!(stderr(&e).contains("leave out --machine"), "{}", stderr(&e));
    // --machine without --only: the whole design on that machine (both boards), as before.
    let w = run(&[
        "preview",
        "sign.toml",
        "-o",
        "w.svg",
        "--machine",
        "grbl-laser",
    ]);
    assert!(w.status.success(), "{}", stderr(&w));
    assert!(dir.join("w.svg").exists());
    // inspect lists the outputs, their machines and operations.
    let i = run(&["inspect", "sign.toml", "--json"]);
    assert!(i.status.success(), "{}", stderr(&i));
    let info: serde_json::Value = serde_json::from_slice(&i.stdout).unwrap();
    let outs = info["outputs"].as_array().unwrap();
    assert_eq!(outs.len(), 2);
    assert_eq!(outs[0]["machine"], "grbl-router");
    assert_eq!(
        outs[0]["operations"],
        serde_json::json!(["1 channel \"channels\"", "2 holes", "3 backboard \"board\""])
    );
    assert_eq!(
        outs[1]["operations"],
        serde_json::json!(["4 backboard \"face\""])
    );
    let t = run(&["inspect", "sign.toml"]);
    assert!(
        stdout(&t).contains("output \"laser\": machine grbl-laser"),
        "{}",
        stdout(&t)
    );
    // check --design: a program whose name is no output's needs --only (or --machine).
    std::fs::copy(dir.join("sign.laser.gcode"), dir.join("x.gcode")).unwrap();
    let c = run(&["check", "x.gcode", "--design", "sign.toml"]);
    assert_eq!(c.status.code(), Some(2));
    assert!(stderr(&c).contains("--only NAME"), "{}", stderr(&c));
    let c = run(&[
        "check",
        "x.gcode",
        "--design",
        "sign.toml",
        "--only",
        "laser",
    ]);
    assert!(c.status.success(), "{}", stdout(&c));
    let _ = std::fs::remove_dir_all(&dir);
}
