//! `check` reads any text file (issue #18 item 4): a byte-order mark is skipped, invalid
//! UTF-8 is read lossily with a warning naming the line, modal-group conflicts are errors,
//! nothing after the closing `%` is interpreted, an empty file gets one clear message and
//! exit status 2.

use std::path::PathBuf;
use std::process::Command;

fn tmpfile(name: &str, bytes: &[u8]) -> PathBuf {
    let d = std::env::temp_dir().join(format!("skinpath-sim-input-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    let f = d.join(name);
    std::fs::write(&f, bytes).expect("write");
    f
}

fn check(bytes: &[u8], name: &str, extra: &[&str]) -> (i32, String) {
    let f = tmpfile(name, bytes);
    let o = Command::new(env!("CARGO_BIN_EXE_skinpath"))
        .arg("check")
        .arg(&f)
        .args(extra)
        .output()
        .expect("run skinpath");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr),
    )
}

#[test]
fn byte_order_mark_is_skipped() {
    let (code, out) = check(b"\xEF\xBB\xBFG21 G0 X1\nM2\n", "bom.nc", &[]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings"), "{out}");
}

#[test]
fn latin1_comment_is_read_with_a_warning_naming_the_line() {
    let (code, out) = check(b"G21\n(caf\xE9 1)\nG0 X1\nM2\n", "latin1.nc", &[]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("warning [invalid-utf8] line 2"), "{out}");
    assert!(out.contains("1 moves"), "{out}");
}

#[test]
fn empty_file_one_message_exit_2() {
    for (name, bytes) in [("empty.nc", &b""[..]), ("blank.nc", &b"\n  \n"[..])] {
        let (code, out) = check(bytes, name, &[]);
        assert_eq!(code, 2, "{out}");
        assert_eq!(out.lines().count(), 2, "{out}");
        assert!(
            out.starts_with("input is not a usable G-code program: the file"),
            "{out}"
        );
        assert!(!out.contains("warnings"), "{out}");
        let (jcode, json) = check(bytes, name, &["--json"]);
        assert_eq!(jcode, 2);
        let v: serde_json::Value = serde_json::from_str(&json).expect("json");
        assert_eq!(v["usable"], false);
        assert!(v["reason"].as_str().unwrap_or("").starts_with("the file"));
    }
}

#[test]
fn modal_conflicts_and_closing_percent() {
    let (code, out) = check(b"G21\nG90 G91 G0 X1\nG20 G21\nM2\n", "modal.nc", &[]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("error [modal-conflict] line 2:5: G90 and G91"),
        "{out}"
    );
    assert!(
        out.contains("error [modal-conflict] line 3:5: G20 and G21"),
        "{out}"
    );
    let (code, out) = check(b"%\nG21 G0 X1\n%\nG0 X500 Y500\n", "percent.nc", &[]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("bounds x 0.000..1.000"), "{out}");
    assert!(out.contains("warning [after-program-end] line 4"), "{out}");
}

#[test]
fn dialect_flag_and_not_supported_messages() {
    let src = b"G21\n#1 = 2\nG0 X#1\nM2\n";
    let (code, out) = check(src, "ngc.nc", &[]);
    assert_eq!(code, 0, "{out}");
    let (code, out) = check(src, "grbl.nc", &["--dialect", "grbl"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("line 2:1: parameters (#) not supported in this dialect"),
        "{out}"
    );
    let (code, out) = check(b"G21\nG0 X1\nG5.2 X2\nM2\n", "g52.nc", &[]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("line 3: G5.2 is not supported"), "{out}");
}

/// M2/M30 reached with the spindle on is a warning naming the M2 line; an M5 before it, or
/// in the same block (it runs before the stop), is not. The tool is on through the stop
/// block's own moves, so the state is taken where the stop happens, not at the block start.
#[test]
fn program_end_with_the_tool_on_is_a_warning() {
    for (text, warned) in [
        ("G21 G90\nM3 S1000\nG1 X10 F100\nM2\n", true),
        ("G21 G90\nM3 S1000\nG1 X10 F100\nM30\n", true),
        ("G21 G90\nM3 S1000\nG1 X10 F100\nM5\nM2\n", false),
        ("G21 G90\nM3 S1000\nG1 X10 F100\nM5 M2\n", false),
        ("G21 G90\nG1 X10 F100\nM2\n", false),
    ] {
        let (_, out) = check(text.as_bytes(), "end.nc", &[]);
        let line = text.lines().count();
        let want = format!("warning [tool-on-at-end] line {line}");
        assert_eq!(out.contains(&want), warned, "{text}\n{out}");
        assert_eq!(out.contains("tool-on-at-end"), warned, "{text}\n{out}");
    }
}
