//! `[[output]]`: the layers of a job. A sign is often cut on more than one machine (the
//! channel board routed, the acrylic face or backer laser-cut): each output is one program
//! of some of the design's operations, for its own machine profile, named by the layer.
//!
//! ```toml
//! [[operation]]
//! name = "channels"
//! kind = "channel"
//! width = 6.5
//! depth = 10.0
//!
//! [[operation]]
//! name = "face"
//! kind = "backboard"
//! margin = 6.0
//!
//! [[output]]
//! name = "board"              # required: letters, digits, `-`, `_`; unique
//! machine = "grbl-router"     # required: a shipped profile or a .toml path
//! operations = ["channels", 2] # operation names, kinds, or 1-based [[operation]] numbers
//! # layers = ["cut"]          # also: the operations whose `layers` name one of these
//! # colors = ["#ff0000"]      # and those whose `colors` name one of these
//! # file = "{stem}-{name}.nc" # default "{stem}.{name}.{ext}"
//! ```
//!
//! Selection: an output with none of `operations`, `layers`, `colors` takes every operation
//! (a design without operations: its default ones); otherwise an operation is taken when
//! any selector names it, in design order. A string in `operations` names the operations
//! with that `name`, or, when none has it, every operation of that `kind`; a number n is the
//! n-th `[[operation]]` table. Every entry, layer and colour must select some operation.
//!
//! `file` is the output's file name in the folder of the build's `-o` (or the current
//! folder): `{stem}` is `-o`'s file stem (or the design's), `{name}` the output's name,
//! `{ext}` the profile's natural extension (`gcode`, or `svg` for SVG laser profiles). Its
//! extension picks the format as `-o`'s does. It is a plain file name: no folder, no
//! leading dot.

use super::error::{DesignError, ErrorKind, Item, Part};
use super::model::Design;
use super::select::normalize_color;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Longest output name, in bytes: it becomes part of a file name.
pub const MAX_NAME_LEN: usize = 64;

/// The default [`Output::file`] template.
pub const DEFAULT_FILE: &str = "{stem}.{name}.{ext}";

/// The placeholders of a [`Output::file`] template.
pub const PLACEHOLDERS: [&str; 3] = ["{stem}", "{name}", "{ext}"];

/// One entry of an output's `operations`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum OperationRef {
    /// The n-th `[[operation]]` table (1-based, as error messages number them).
    Index(usize),
    /// The operations with this `name`, or else those of this `kind`.
    Name(String),
}

impl std::fmt::Display for OperationRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OperationRef::Index(n) => write!(f, "{n}"),
            OperationRef::Name(s) => write!(f, "\"{s}\""),
        }
    }
}

/// An `[[output]]` table (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// `name` (required): ASCII letters, digits, `-` and `_`, at most `MAX_NAME_LEN`
    /// bytes; unique among outputs.
    pub name: String,
    /// `machine` (required): a shipped profile's name or the path of a profile file
    /// (relative to the design file's folder).
    pub machine: String,
    /// `operations`: operation names, kinds or 1-based numbers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operations: Option<Vec<OperationRef>>,
    /// `layers`: the operations whose `layers` selector names one of these.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<Vec<String>>,
    /// `colors`: the operations whose `colors` selector names one of these (`#rrggbb`,
    /// any case).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colors: Option<Vec<String>>,
    /// `file`: the file name template; unset: `DEFAULT_FILE`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

impl Output {
    /// Whether none of `operations`, `layers`, `colors` is given (every operation).
    fn takes_all(&self) -> bool {
        self.operations.is_none() && self.layers.is_none() && self.colors.is_none()
    }

    /// The 0-based indices of the design's operations `r` names (empty when none).
    fn resolve(d: &Design, r: &OperationRef) -> Vec<usize> {
        match r {
            OperationRef::Index(n) if (1..=d.operation.len()).contains(n) => vec![n - 1],
            OperationRef::Index(_) => Vec::new(),
            OperationRef::Name(s) => {
                let named: Vec<usize> = (d.operation.iter().enumerate())
                    .filter(|(_, op)| op.name.as_deref() == Some(s.as_str()))
                    .map(|(i, _)| i)
                    .collect();
                if !named.is_empty() {
                    return named;
                }
                (d.operation.iter().enumerate())
                    .filter(|(_, op)| op.kind.as_str() == s)
                    .map(|(i, _)| i)
                    .collect()
            }
        }
    }

    /// The 0-based indices, in design order, of the operations this output builds; `None`
    /// when it takes every operation (also the default operations of a design without any).
    pub fn operations_of(&self, d: &Design) -> Option<Vec<usize>> {
        if self.takes_all() {
            return None;
        }
        let mut take = vec![false; d.operation.len()];
        for r in self.operations.iter().flatten() {
            for i in Self::resolve(d, r) {
                take[i] = true;
            }
        }
        for (i, op) in d.operation.iter().enumerate() {
            let on_layer =
                (self.layers.iter().flatten()).any(|l| op.layers.iter().flatten().any(|m| m == l));
            let in_color = (self.colors.iter().flatten())
                .any(|c| (op.colors.iter().flatten()).any(|m| m.eq_ignore_ascii_case(c)));
            take[i] |= on_layer || in_color;
        }
        Some((0..take.len()).filter(|&i| take[i]).collect())
    }

    /// The output's file name: its `file` template (or `DEFAULT_FILE`) with `{stem}`,
    /// `{name}` and `{ext}` replaced.
    #[must_use]
    pub fn file_name(&self, stem: &str, ext: &str) -> String {
        self.file
            .as_deref()
            .unwrap_or(DEFAULT_FILE)
            .replace("{stem}", stem)
            .replace("{name}", &self.name)
            .replace("{ext}", ext)
    }
}

fn invalid(file: &str, index: usize, o: &Output, key: &str, message: String) -> DesignError {
    DesignError::at(
        file,
        Item::Output {
            index,
            name: o.name.clone(),
        },
        Some(Part::Key(key.into())),
        ErrorKind::Invalid(message),
    )
}

/// A `file` template's problem, if it has one: empty, a folder part, a leading dot, or a
/// `{...}` other than [`PLACEHOLDERS`].
fn template_problem(t: &str) -> Option<String> {
    if t.trim().is_empty() {
        return Some("`file` is empty (leave it out for the default)".into());
    }
    if t.contains(['/', '\\']) {
        return Some(format!(
            "`file` {t:?} names a folder: give a plain file name (it is written beside -o)"
        ));
    }
    if t.starts_with('.') {
        return Some(format!(
            "`file` {t:?} starts with a dot (a hidden file): start it with {{stem}} or a name"
        ));
    }
    let mut rest = t;
    while let Some(i) = rest.find('{') {
        let after = &rest[i..];
        match PLACEHOLDERS.iter().find(|p| after.starts_with(*p)) {
            Some(p) => rest = &after[p.len()..],
            None => {
                let word: String = after.chars().take_while(|&c| c != '}').collect();
                return Some(format!(
                    "`file` {t:?}: unknown placeholder {word}}}; use {{stem}}, {{name}} or \
                     {{ext}}"
                ));
            }
        }
    }
    if rest.contains('}') {
        return Some(format!("`file` {t:?} has a `}}` without its `{{`"));
    }
    None
}

/// Checks the outputs and the operations' names (see the module docs): names valid and
/// unique, a machine given, every selector entry selecting an operation, templates valid.
pub fn validate(d: &Design) -> Result<(), DesignError> {
    let file = d.file.as_str();
    for (index, op) in d.operation.iter().enumerate() {
        if op.name.as_deref().is_some_and(|n| n.trim().is_empty()) {
            return Err(DesignError::at(
                file,
                Item::Operation {
                    index,
                    kind: op.kind.as_str().to_string(),
                },
                Some(Part::Key("name".into())),
                ErrorKind::Invalid("`name` is empty (leave it out, or name the operation)".into()),
            ));
        }
    }
    let mut names: HashMap<&str, usize> = HashMap::new();
    for (index, o) in d.output.iter().enumerate() {
        let bad = |key: &str, message: String| invalid(file, index, o, key, message);
        let good_char = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
        if o.name.is_empty() || o.name.len() > MAX_NAME_LEN || !o.name.chars().all(good_char) {
            return Err(bad(
                "name",
                format!(
                    "output name {:?} must be 1 to {MAX_NAME_LEN} ASCII letters, digits, `-` or \
                     `_` (it becomes part of the file name)",
                    o.name
                ),
            ));
        }
        if let Some(&first) = names.get(o.name.as_str()) {
            return Err(DesignError::at(
                file,
                Item::Output {
                    index,
                    name: o.name.clone(),
                },
                Some(Part::Key("name".into())),
                ErrorKind::DuplicateName {
                    first: Item::Output {
                        index: first,
                        name: o.name.clone(),
                    }
                    .to_string(),
                },
            ));
        }
        names.insert(&o.name, index);
        if o.machine.trim().is_empty() {
            return Err(bad(
                "machine",
                "`machine` is empty: name a profile (see `skinpath machines`) or a .toml file"
                    .into(),
            ));
        }
        if let Some(t) = &o.file
            && let Some(m) = template_problem(t)
        {
            return Err(bad("file", m));
        }
        check_selectors(d, index, o)?;
    }
    Ok(())
}

/// Every selector of output `index` names some operation, and together they name one.
fn check_selectors(d: &Design, index: usize, o: &Output) -> Result<(), DesignError> {
    let file = d.file.as_str();
    let bad = |key: &str, message: String| invalid(file, index, o, key, message);
    if o.takes_all() {
        return Ok(());
    }
    if d.operation.is_empty() {
        return Err(bad(
            "operations",
            "the design has no [[operation]] to select: leave out `operations`, `layers` and \
             `colors` (the output then builds the default operations), or add operations"
                .into(),
        ));
    }
    if let Some(refs) = &o.operations {
        if refs.is_empty() {
            return Err(bad(
                "operations",
                "`operations` names no operation (leave it out for every operation)".into(),
            ));
        }
        if let Some(r) = refs.iter().find(|r| Output::resolve(d, r).is_empty()) {
            let names: Vec<String> = (d.operation.iter())
                .filter_map(|op| op.name.as_ref().map(|n| format!("\"{n}\"")))
                .collect();
            return Err(bad(
                "operations",
                format!(
                    "{r} names no operation: give an operation's `name` ({}), a kind (e.g. \
                     \"channel\") or a number 1..={}",
                    if names.is_empty() {
                        "the design's operations have none".to_string()
                    } else {
                        names.join(", ")
                    },
                    d.operation.len()
                ),
            ));
        }
    }
    if let Some(layers) = &o.layers {
        let known =
            |l: &String| (d.operation.iter()).any(|op| op.layers.iter().flatten().any(|m| m == l));
        if let Some(l) = layers.iter().find(|l| !known(l)) {
            return Err(bad(
                "layers",
                format!("no operation selects layer \"{l}\" (with `layers = [...]`)"),
            ));
        }
    }
    if let Some(colors) = &o.colors {
        for c in colors {
            if normalize_color(c).is_none() {
                return Err(bad("colors", format!("colour {c:?} is not #rrggbb")));
            }
            let known = (d.operation.iter())
                .any(|op| (op.colors.iter().flatten()).any(|m| m.eq_ignore_ascii_case(c)));
            if !known {
                return Err(bad(
                    "colors",
                    format!("no operation selects colour {c} (with `colors = [...]`)"),
                ));
            }
        }
    }
    if o.operations_of(d).is_some_and(|v| v.is_empty()) {
        return Err(bad("operations", "the output selects no operation".into()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A design with two strokes on layers, three operations (one named, one on a layer,
    /// one by colour) and `outputs` appended.
    fn design(outputs: &str) -> Result<Design, DesignError> {
        let text = format!(
            r##"version = 1
[[stroke]]
name = "a"
layer = "cut"
color = "#FF0000"
disks = [[0.0, 0.0, 2.0], [10.0, 0.0, 2.0]]
[[stroke]]
name = "b"
disks = [[0.0, 10.0, 2.0], [10.0, 10.0, 2.0]]
[[operation]]
kind = "channel"
name = "chan"
width = 3.0
depth = 2.0
[[operation]]
kind = "profile"
layers = ["cut"]
depth = 2.0
[[operation]]
kind = "profile"
colors = ["#ff0000"]
depth = 2.0
{outputs}"##
        );
        crate::design::load(&text, "o.toml")
    }

    fn selection(outputs: &str) -> Vec<Option<Vec<usize>>> {
        let d = design(outputs).unwrap();
        d.output.iter().map(|o| o.operations_of(&d)).collect()
    }

    fn error(outputs: &str) -> String {
        design(outputs).unwrap_err().to_string()
    }

    #[test]
    fn selectors_pick_operations_in_design_order() {
        let sel = selection(
            r##"[[output]]
name = "all"
machine = "grbl-router"
[[output]]
name = "by-name-and-number"
machine = "grbl-router"
operations = [3, "chan"]
[[output]]
name = "by_kind"
machine = "grbl-laser"
operations = ["profile"]
[[output]]
name = "layer"
machine = "grbl-laser"
layers = ["cut"]
[[output]]
name = "Colour2"
machine = "grbl-laser"
colors = ["#FF0000"]
"##,
        );
        assert_eq!(
            sel,
            vec![
                None,
                Some(vec![0, 2]),
                Some(vec![1, 2]),
                Some(vec![1]),
                Some(vec![2])
            ]
        );
    }

    #[test]
    fn a_name_wins_over_a_kind() {
        // An operation named "profile" is selected by that name, not every profile.
        let d = design("").unwrap();
        let mut d2 = d.clone();
        d2.operation[0].name = Some("profile".into());
        let o = Output {
            name: "x".into(),
            machine: "grbl-router".into(),
            operations: Some(vec![OperationRef::Name("profile".into())]),
            layers: None,
            colors: None,
            file: None,
        };
        assert_eq!(o.operations_of(&d2), Some(vec![0]));
        assert_eq!(o.operations_of(&d), Some(vec![1, 2]));
    }

    #[test]
    fn errors_name_the_output_and_the_key() {
        let out = |body: &str| format!("[[output]]\nname = \"ok\"\nmachine = \"m\"\n{body}");
        let cases: [(String, &[&str]); 10] = [
            (
                out("[[output]]\nname = \"ok\"\nmachine = \"n\"\n"),
                &["output 1 \"ok\"", "name already used by output 0 \"ok\""],
            ),
            (
                "[[output]]\nname = \"a b\"\nmachine = \"m\"\n".into(),
                &["output 0 \"a b\", key `name`", "ASCII letters"],
            ),
            (
                "[[output]]\nname = \"\"\nmachine = \"m\"\n".into(),
                &["output 0 \"\", key `name`"],
            ),
            (
                "[[output]]\nname = \"x\"\nmachine = \" \"\n".into(),
                &["output 0 \"x\", key `machine`", "is empty"],
            ),
            (
                out("operations = [\"chan\", 4]\n"),
                &[
                    "output 0 \"ok\", key `operations`",
                    "4 names no operation",
                    "\"chan\"",
                ],
            ),
            (
                out("operations = [\"nope\"]\n"),
                &["key `operations`", "\"nope\" names no operation"],
            ),
            (out("operations = []\n"), &["names no operation"]),
            (
                out("layers = [\"engrave\"]\n"),
                &["key `layers`", "no operation selects layer \"engrave\""],
            ),
            (
                out("colors = [\"#00ff00\"]\n"),
                &["key `colors`", "no operation selects colour #00ff00"],
            ),
            (
                out("file = \"../{name}.nc\"\n"),
                &["key `file`", "names a folder"],
            ),
        ];
        for (body, wanted) in &cases {
            let e = error(body);
            assert!(e.starts_with("o.toml: "), "{e}");
            for w in *wanted {
                assert!(e.contains(w), "{body}\n{e}\nmissing {w:?}");
            }
        }
    }

    #[test]
    fn file_templates_are_checked() {
        assert_eq!(template_problem("{stem}.{name}.{ext}"), None);
        assert_eq!(template_problem("sign-{name}.dxf"), None);
        for bad in [
            "",
            ".{name}.nc",
            "a/b.nc",
            "a\\b.nc",
            "{stem}.{nme}.nc",
            "x}.nc",
        ] {
            assert!(template_problem(bad).is_some(), "{bad:?}");
        }
        let o = Output {
            name: "face".into(),
            machine: "svg-laser".into(),
            operations: None,
            layers: None,
            colors: None,
            file: None,
        };
        assert_eq!(o.file_name("sign", "svg"), "sign.face.svg");
    }

    #[test]
    fn a_design_without_operations_takes_no_selector() {
        let text = "version = 1\n[[stroke]]\nname = \"a\"\ndisks = [[0,0,1],[5,0,1]]\n\
                    [[output]]\nname = \"r\"\nmachine = \"grbl-router\"\n";
        let d = crate::design::load(text, "e.toml").unwrap();
        assert_eq!(d.output[0].operations_of(&d), None);
        let e = crate::design::load(&format!("{text}operations = [1]\n"), "e.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("has no [[operation]] to select"), "{e}");
    }

    #[test]
    fn an_empty_operation_name_is_refused() {
        let text = "version = 1\n[[stroke]]\nname = \"a\"\ndisks = [[0,0,1],[5,0,1]]\n\
                    [[operation]]\nkind = \"profile\"\nname = \" \"\n";
        let e = crate::design::load(text, "e.toml").unwrap_err().to_string();
        assert!(e.contains("operation 0 (profile), key `name`"), "{e}");
    }
}
