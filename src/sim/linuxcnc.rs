//! Second backend: LinuxCNC's reference RS274NGC interpreter (`rs274`, Debian package
//! linuxcnc-uspace) run in batch mode, `rs274 -n 0 -g prog.ngc`, prints one canonical
//! machining command per line:
//!
//! ```text
//!    12 N3    STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
//!    14 N5    ARC_FEED(10.0000, 12.0000, 10.0000, 7.0000, -1, -1.0000, 0.0000, 0.0000, 0.0000)
//! ```
//!
//! The library does not run processes (the CLI does). This module only transforms text:
//! [`number_lines`] prefixes every source line with `N<line>` so the canon output carries
//! source line numbers (rs274 prints the block's N word, not the line), and [`parse_canon`]
//! turns the output into the same [`Program`] the built-in interpreter produces. Lines that
//! are not canon commands (rs274's error messages and the offending block it echoes) become
//! `canon-error` findings.

use super::checks::contours::note_group_marks;
use super::findings::{Finding, Severity};
use super::motion::{Motion, MotionKind, Program, ProgramEnd, Spindle, ToolState};
use crate::geom::{Arc, DVec2};
use glam::DVec3;
use std::f64::consts::TAU;

/// Most extra full turns an arc's rotation count adds (a guard against a hostile count: an
/// arc of 10⁶ turns is already far beyond any program).
const MAX_EXTRA_TURNS: f64 = 1e6;

/// Prepares `src` for rs274: prefixes each non-empty line with `N<line number> ` (after a
/// leading `/`), replacing an existing leading N word, and brackets the program in `%`
/// lines (added before the first line and after the last when missing): rs274 in batch mode
/// with `-n 0` repeats "File ended with no percent sign or program end" forever on a file
/// that has neither. `%` lines and blank lines are left alone; line numbers stay those of
/// `src` because they travel in the N words.
#[must_use]
pub fn number_lines(src: &str) -> String {
    let mut out = String::with_capacity(src.len() + src.len() / 4 + 4);
    let first = src.lines().map(str::trim).find(|l| !l.is_empty());
    let marks = src.lines().filter(|l| l.trim().starts_with('%')).count();
    let opened = first.is_some_and(|l| l.starts_with('%'));
    if !opened {
        out.push_str("%\n");
    }
    for (i, raw) in src.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('%') {
            out.push_str(line);
            continue;
        }
        let (slash, rest) = match t.strip_prefix('/') {
            Some(r) => ("/", r.trim_start()),
            None => ("", t),
        };
        let rest = strip_n_word(rest);
        out.push_str(&format!("{slash}N{} {rest}", i + 1));
    }
    if !opened || marks < 2 {
        out.push_str("\n%\n");
    }
    out
}

/// `rest` without a leading `N<digits>` word.
fn strip_n_word(s: &str) -> &str {
    let b = s.as_bytes();
    if b.first().is_some_and(|c| c.eq_ignore_ascii_case(&b'n')) {
        let digits = b[1..]
            .iter()
            .take_while(|c| c.is_ascii_digit() || **c == b' ')
            .count();
        if b[1..1 + digits].iter().any(|c| c.is_ascii_digit()) {
            return s[1 + digits..].trim_start();
        }
    }
    s
}

/// One parsed canon line: source line (from the N field, else the canon sequence number),
/// command name and numeric arguments (non-numeric arguments kept as text).
struct Canon<'a> {
    line: usize,
    has_n: bool,
    name: &'a str,
    args: Vec<&'a str>,
}

fn parse_line(l: &str) -> Option<Canon<'_>> {
    let l = l.trim();
    let (seq, rest) = l.split_once(char::is_whitespace)?;
    let seq: usize = seq.parse().ok()?;
    let rest = rest.trim_start();
    let nfield = rest.strip_prefix('N')?;
    // rs274 prints `N%-5d` then the command: at six digits and more there is no space left
    // between the number and the command (`N100000STRAIGHT_FEED(...)`).
    let nlen = nfield
        .bytes()
        .take_while(|c| c.is_ascii_digit() || *c == b'.')
        .count();
    let (n, cmd) = nfield.split_at(nlen);
    let cmd = cmd.trim();
    let open = cmd.find('(')?;
    let name = &cmd[..open];
    if name.is_empty()
        || !name
            .bytes()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == b'_')
    {
        return None;
    }
    let inner = cmd[open + 1..].strip_suffix(')')?;
    let args = if inner.trim().is_empty() {
        Vec::new()
    } else {
        inner.split([',', ' ']).filter(|s| !s.is_empty()).collect()
    };
    let nline = n.parse::<usize>().ok();
    Some(Canon {
        line: nline.unwrap_or(seq),
        has_n: nline.is_some(),
        name,
        args,
    })
}

/// Parses rs274 canon output into a [`Program`] (mm). Units follow USE_LENGTH_UNITS;
/// arcs are taken in the XY plane only (others give a finding); `rotation` in ARC_FEED
/// adds |rotation| − 1 full turns.
#[must_use]
pub fn parse_canon(text: &str) -> Program {
    let mut prog = Program::default();
    let mut k = 1.0;
    let mut pos = DVec3::ZERO;
    let mut feed = 0.0;
    let mut tool = ToolState::default();
    let mut plane_xy = true;
    let mut block_line = usize::MAX;
    let mut tool_at_block = tool;
    let mut pending_error: Option<Finding> = None;
    // Program → machine coordinates: G5x origin + G92 offset + tool length offset (rs274
    // prints positions in the program's coordinate system and the offsets separately).
    let mut g5x = DVec3::ZERO;
    let mut g92 = DVec3::ZERO;
    let mut tlo = DVec3::ZERO;
    let mut plane = [0usize, 1, 2];
    // The pocket mark in force: the last one read (rs274 prints comments in the order it
    // runs the blocks).
    let mut group: Option<u32> = None;
    for (idx, raw) in text.lines().enumerate() {
        prog.lines = idx + 1;
        let Some(c) = parse_line(raw) else {
            let t = raw.trim();
            if t.is_empty() || t == "executing" {
                continue;
            }
            // rs274 prints its message, then echoes the offending block (which carries the
            // source line in its N word).
            // A line without such an echo is a message ((debug,…), (print,…)).
            match (pending_error.take(), leading_n(t)) {
                (Some(mut f), Some(n)) => {
                    f.message = format!("{} (in `{t}`)", f.message);
                    f.lines = vec![n];
                    prog.diagnostics.push(f);
                }
                (prev, _) => {
                    prog.diagnostics.extend(prev.map(as_message));
                    pending_error = Some(
                        Finding::new("canon-error", Severity::Error, format!("rs274: {t}"))
                            .line(block_line.min(prog.last_line + 1)),
                    )
                }
            }
            continue;
        };
        prog.diagnostics
            .extend(pending_error.take().map(as_message));
        if c.line != block_line {
            block_line = c.line;
            tool_at_block = tool;
        }
        let line = if c.has_n { c.line } else { 0 };
        let num = |i: usize| c.args.get(i).and_then(|s| s.parse::<f64>().ok());
        prog.words += 1;
        match c.name {
            "USE_LENGTH_UNITS" => {
                k = match c.args.first().copied() {
                    Some("CANON_UNITS_INCHES") => 25.4,
                    Some("CANON_UNITS_CM") => 10.0,
                    _ => 1.0,
                }
            }
            "SELECT_PLANE" => {
                plane_xy = c.args.first().copied() == Some("CANON_PLANE_XY");
                // (first, second, linear axis) of ARC_FEED in this plane.
                plane = match c.args.first().copied() {
                    Some("CANON_PLANE_XZ") => [2, 0, 1],
                    Some("CANON_PLANE_YZ") => [1, 2, 0],
                    _ => [0, 1, 2],
                };
            }
            "SET_G5X_OFFSET" => {
                if let (Some(x), Some(y), Some(z)) = (num(1), num(2), num(3)) {
                    g5x = DVec3::new(x, y, z) * k;
                }
            }
            "SET_G92_OFFSET" => {
                if let (Some(x), Some(y), Some(z)) = (num(0), num(1), num(2)) {
                    g92 = DVec3::new(x, y, z) * k;
                }
            }
            "USE_TOOL_LENGTH_OFFSET" => {
                if let (Some(x), Some(y), Some(z)) = (num(0), num(1), num(2)) {
                    tlo = DVec3::new(x, y, z) * k;
                }
            }
            "SET_FEED_RATE" => feed = num(0).unwrap_or(0.0) * k,
            "SET_SPINDLE_SPEED" => {
                let s = num(c.args.len().saturating_sub(1)).unwrap_or(0.0);
                tool.switch(tool.spindle, s);
            }
            "START_SPINDLE_CLOCKWISE" => tool.switch(Spindle::Cw, tool.s),
            "START_SPINDLE_COUNTERCLOCKWISE" => tool.switch(Spindle::Ccw, tool.s),
            "STOP_SPINDLE_TURNING" => tool.switch(Spindle::Off, tool.s),
            "DWELL" => prog.motions.push(Motion {
                kind: MotionKind::Dwell {
                    seconds: num(0).unwrap_or(0.0),
                },
                from: pos,
                to: pos,
                arc: None,
                feed,
                tool,
                line,
                group,
            }),
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" | "STRAIGHT_PROBE" => {
                let (Some(x), Some(y), Some(z)) = (num(0), num(1), num(2)) else {
                    prog.diagnostics.push(bad_args(&c, line));
                    continue;
                };
                let to = DVec3::new(x, y, z) * k + g5x + g92 + tlo;
                let kind = if c.name != "STRAIGHT_TRAVERSE" {
                    MotionKind::Feed
                } else {
                    MotionKind::Rapid
                };
                if to != pos {
                    prog.motions.push(Motion {
                        kind,
                        from: pos,
                        to,
                        arc: None,
                        feed,
                        tool,
                        line,
                        group,
                    });
                }
                pos = to;
            }
            "ARC_FEED" => {
                let (Some(ex), Some(ey), Some(cx), Some(cy), Some(rot), Some(ez)) =
                    (num(0), num(1), num(2), num(3), num(4), num(5))
                else {
                    prog.diagnostics.push(bad_args(&c, line));
                    continue;
                };
                let off = g5x + g92 + tlo;
                let mut to = DVec3::ZERO;
                to[plane[0]] = ex * k + off[plane[0]];
                to[plane[1]] = ey * k + off[plane[1]];
                to[plane[2]] = ez * k + off[plane[2]];
                let center = DVec2::new(cx * k + off[plane[0]], cy * k + off[plane[1]]);
                if !plane_xy {
                    // Chords within CHORD_ANGLE, as the builtin interpreter splits them.
                    let p0 = DVec2::new(pos[plane[0]], pos[plane[1]]);
                    let p1 = DVec2::new(to[plane[0]], to[plane[1]]);
                    let arc = canon_arc(center, p0, p1, rot);
                    let n = ((arc.sweep.abs() / super::interp::CHORD_ANGLE).ceil() as usize)
                        .clamp(1, 1_000_000);
                    let from = pos;
                    for s in 1..=n {
                        let t = s as f64 / n as f64;
                        let q = if s == n { p1 } else { arc.eval(t) };
                        let mut pt = DVec3::ZERO;
                        pt[plane[0]] = q.x;
                        pt[plane[1]] = q.y;
                        pt[plane[2]] = from[plane[2]] + (to[plane[2]] - from[plane[2]]) * t;
                        prog.motions.push(Motion {
                            kind: MotionKind::Feed,
                            from: pos,
                            to: pt,
                            arc: None,
                            feed,
                            tool,
                            line,
                            group,
                        });
                        pos = pt;
                    }
                    pos = to;
                    continue;
                }
                let arc = canon_arc(center, pos.truncate(), to.truncate(), rot);
                prog.motions.push(Motion {
                    kind: MotionKind::Feed,
                    from: pos,
                    to,
                    arc: Some(arc),
                    feed,
                    tool,
                    line,
                    group,
                });
                pos = to;
            }
            "PROGRAM_END" => {
                prog.end = Some(ProgramEnd {
                    line,
                    tool_before: tool_at_block,
                });
            }
            // A comment rs274 passes on: the pocket marks `(skinpath:group N)` that let the
            // cuts of one pocket (and line cuts) cross, as the built-in interpreter reads them.
            "COMMENT" => {
                if let Some(text) = comment_text(raw) {
                    let marks = prog.group_marks.len();
                    note_group_marks(&[text.to_string()], line, &mut prog.group_marks);
                    if let Some(&(_, g)) = prog.group_marks.get(marks..).and_then(|m| m.last()) {
                        group = g;
                    }
                }
            }
            _ => {}
        }
        if line > 0 {
            prog.last_line = prog.last_line.max(line);
        }
    }
    prog.diagnostics.extend(pending_error.map(as_message));
    prog.final_tool = tool;
    prog
}

/// An rs274 output line that no echoed block followed: a message, not an error.
/// The text of a canon `COMMENT("…")` line (rs274 prints the comment as written, quotes
/// and all, so the text is what lies between the first `("` and the last `")`).
fn comment_text(raw: &str) -> Option<&str> {
    let start = raw.find("COMMENT(\"")? + "COMMENT(\"".len();
    let end = raw.rfind("\")")?;
    raw.get(start..end)
}

fn as_message(f: Finding) -> Finding {
    let mut m = Finding::new("canon-message", Severity::Info, f.message);
    m.lines = f.lines;
    m
}

fn bad_args(c: &Canon<'_>, line: usize) -> Finding {
    Finding::new(
        "canon-error",
        Severity::Error,
        format!("{} with unreadable arguments {:?}", c.name, c.args),
    )
    .line(line)
}

/// The `N<digits>` a numbered source line starts with.
fn leading_n(t: &str) -> Option<usize> {
    let t = t.strip_prefix('/').unwrap_or(t).trim_start();
    let d: String = t
        .strip_prefix(['N', 'n'])?
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    d.parse().ok()
}

/// ARC_FEED's arc: counter-clockwise when `rotation` > 0, |rotation| turns counted by
/// LinuxCNC (1 = up to one turn; an end equal to the start is a full turn).
fn canon_arc(center: DVec2, p0: DVec2, p1: DVec2, rotation: f64) -> Arc {
    let ccw = rotation > 0.0;
    let a0 = (p0 - center).to_angle();
    let a1 = (p1 - center).to_angle();
    let mut sweep = (a1 - a0).rem_euclid(TAU);
    if ccw {
        if sweep == 0.0 {
            sweep = TAU;
        }
    } else {
        sweep -= TAU;
    }
    let extra = (rotation.abs().round() - 1.0).clamp(0.0, MAX_EXTRA_TURNS);
    sweep += sweep.signum() * extra * TAU;
    Arc::new(center, p0.distance(center), a0, sweep)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-written sample in rs274's format (as produced by linuxcnc-uspace 2.9 for a
    /// numbered program): inch units, a rapid, a line, a CW quarter, a dwell, spindle and end.
    const SAMPLE: &str = "executing
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    7 N1     USE_LENGTH_UNITS(CANON_UNITS_INCHES)
    8 N2     SET_FEED_RATE(20.0000)
    9 N3     SET_SPINDLE_SPEED(0, 500.0000)
   10 N3     START_SPINDLE_COUNTERCLOCKWISE(0)
   11 N4     STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
   12 N5     STRAIGHT_FEED(2.0000, 0.0000, -0.1000, 0.0000, 0.0000, 0.0000)
   13 N6     ARC_FEED(1.0000, -1.0000, 1.0000, 0.0000, -1, -0.1000, 0.0000, 0.0000, 0.0000)
   14 N7     DWELL(0.5000)
   15 N8     STOP_SPINDLE_TURNING(0)
   16 N9     PROGRAM_END()
Radius to end of arc differs from radius to start
N10 G2 X1 Y1 I5
";

    #[test]
    fn pocket_marks_come_through_comments() {
        let canon = "    1 N1     COMMENT(\"skinpath:group 3\")\n    2 N2     STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n    3 N3     COMMENT(\"skinpath:group none\")\n    4 N4     COMMENT(\"a (note), with \"quotes\"\")\n";
        let p = parse_canon(canon);
        assert_eq!(p.group_marks, vec![(1, Some(3)), (3, None)]);
        // The move between the marks was cut under the first.
        assert_eq!(p.motions.first().map(|m| m.group), Some(Some(3)));
        assert_eq!(
            comment_text(canon.lines().nth(3).unwrap()),
            Some("a (note), with \"quotes\"")
        );
    }

    #[test]
    fn sample_canon() {
        let p = parse_canon(SAMPLE);
        assert_eq!(p.motions.len(), 4);
        let m = p.motions.to_vec();
        assert_eq!(m[0].kind, MotionKind::Rapid);
        assert_eq!(m[0].line, 4);
        assert!((m[0].to - DVec3::new(25.4, 0.0, 0.0)).length() < 1e-12);
        assert!((m[1].to - DVec3::new(50.8, 0.0, -2.54)).length() < 1e-12);
        assert!((m[1].feed - 508.0).abs() < 1e-12);
        assert_eq!(m[1].tool.spindle, Spindle::Ccw);
        assert_eq!(m[1].tool.s, 500.0);
        let a = m[2].arc.unwrap_or(Arc::new(DVec2::ZERO, 0.0, 0.0, 0.0));
        assert!((a.sweep + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((a.radius - 25.4).abs() < 1e-12);
        assert_eq!(m[3].kind, MotionKind::Dwell { seconds: 0.5 });
        assert_eq!(
            p.end.map(|e| (e.line, e.tool_before.is_on())),
            Some((9, false))
        );
        assert_eq!(p.diagnostics.len(), 1, "{:?}", p.diagnostics);
        assert_eq!(p.diagnostics[0].id, "canon-error");
        assert_eq!(p.diagnostics[0].lines, vec![10]);
    }

    #[test]
    fn numbering() {
        let src = "%\nG0 X1\n\nn20 G1 X2\n/ N5 G1 X3 ; c\r\n(comment)";
        assert_eq!(
            number_lines(src),
            "%\nN2 G0 X1\n\nN4 G1 X2\n/N5 G1 X3 ; c\nN6 (comment)\n%\n"
        );
        assert_eq!(number_lines("G0 X1\n"), "%\nN1 G0 X1\n\n%\n");
        assert_eq!(number_lines("%\nG0 X1\n%"), "%\nN2 G0 X1\n%");
        assert_eq!(leading_n("N42 G1"), Some(42));
    }

    #[test]
    fn arcs_with_turns() {
        let c = DVec2::ZERO;
        let p = DVec2::X;
        assert!((canon_arc(c, p, p, 1.0).sweep - TAU).abs() < 1e-15);
        assert!((canon_arc(c, p, p, -1.0).sweep + TAU).abs() < 1e-15);
        assert!((canon_arc(c, p, DVec2::Y, 2.0).sweep - 2.5 * std::f64::consts::PI).abs() < 1e-12);
    }
}
