//! Preamble/postamble templates: G-code lines with `{placeholder}`s.
//!
//! Placeholders: `{name}` (profile name), `{job}` (job name), `{units}` (`G21`/`G20`),
//! `{safe_z}`, `{path_tolerance}`, `{power_max}`. Anything else in braces is an error at load
//! time, so a typo never reaches a machine.

/// The placeholders a template may use.
pub const PLACEHOLDERS: [&str; 6] = [
    "name",
    "job",
    "units",
    "safe_z",
    "path_tolerance",
    "power_max",
];

/// Checks that every `{...}` in `t` is a known placeholder and braces balance.
pub fn check(t: &str) -> Result<(), String> {
    render(t, |_| String::new()).map(|_| ())
}

/// True when `t` uses `{name}`.
pub fn uses(t: &str, name: &str) -> bool {
    t.contains(&format!("{{{name}}}"))
}

/// `t` with each placeholder replaced by `value(name)`.
pub fn render(t: &str, value: impl Fn(&str) -> String) -> Result<String, String> {
    let mut out = String::with_capacity(t.len());
    let mut rest = t;
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let close = after
            .find('}')
            .ok_or_else(|| "unclosed `{` in template".to_string())?;
        let name = &after[..close];
        if !PLACEHOLDERS.contains(&name) {
            return Err(format!("unknown placeholder {{{name}}}"));
        }
        out.push_str(&value(name));
        rest = &after[close + 1..];
    }
    if rest.contains('}') {
        return Err("unmatched `}` in template".to_string());
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_known_placeholders() {
        let out = render("G64 P{path_tolerance}\n(job {job})", |n| match n {
            "path_tolerance" => "0.01".into(),
            "job" => "sign".into(),
            _ => "?".into(),
        })
        .unwrap();
        assert_eq!(out, "G64 P0.01\n(job sign)");
    }

    #[test]
    fn rejects_unknown_and_unbalanced() {
        assert!(check("G0 Z{safez}").unwrap_err().contains("safez"));
        assert!(check("G0 Z{safe_z").is_err());
        assert!(check("G0 Z}").is_err());
        assert!(check("G0 Z{safe_z}").is_ok());
        assert!(uses("G64 P{path_tolerance}", "path_tolerance"));
    }
}
