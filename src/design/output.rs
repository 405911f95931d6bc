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
    /// `name` (required): ASCII letters, digits, `-` and `_`, at most [`MAX_NAME_LEN`]
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
    /// `file`: the file name template; unset: [`DEFAULT_FILE`].
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
            OperationRef::Index(n) => (1..=d.operation.len())
                .contains(n)
                .then(|| vec![n - 1])
                .unwrap_or_default(),
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

    /// The output's file name: its `file` template (or [`DEFAULT_FILE`]) with `{stem}`,
    /// `{name}` and `{ext}` replaced.
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
