//! Parsing (TOML or JSON, chosen by the file name's extension) and writing of designs. The
//! library never reads files: callers pass the text and the file name used in messages.

use super::error::{DesignError, ErrorKind};
use super::model::{Design, VERSION};
use super::validate::validate;

/// A design file's syntax.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// TOML (`.toml`), the format of the examples in [`crate::design`].
    Toml,
    /// JSON (`.json`) with the same keys.
    Json,
}

impl Format {
    /// The format for a file name's extension (`.toml` or `.json`, any case).
    #[must_use]
    pub fn from_file_name(file_name: &str) -> Option<Format> {
        let ext = std::path::Path::new(file_name)
            .extension()?
            .to_str()?
            .to_ascii_lowercase();
        match ext.as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// Parse and validate a design, choosing the format by `file_name`'s extension; an `.svg`
/// file is imported (with the `svg-import` feature; without it an `.svg` file is
/// an [`ErrorKind::FeatureOff`] error).
pub fn load(text: &str, file_name: &str) -> Result<Design, DesignError> {
    load_noted(text, file_name).map(|(d, _)| d)
}

/// [`load`], with the lines an SVG import has to say (skipped elements and warnings, see
/// `load_svg_noted`); none for design files.
pub fn load_noted(text: &str, file_name: &str) -> Result<(Design, Vec<String>), DesignError> {
    if file_name.to_ascii_lowercase().ends_with(".svg") {
        #[cfg(feature = "svg-import")]
        return super::svg::load_svg_noted(text, file_name);
        #[cfg(not(feature = "svg-import"))]
        return Err(DesignError::file(
            file_name,
            ErrorKind::FeatureOff {
                what: "SVG import",
                feature: "svg-import",
            },
        ));
    }
    let format = Format::from_file_name(file_name)
        .ok_or_else(|| DesignError::file(file_name, ErrorKind::UnknownFormat))?;
    Ok((from_str(text, format, file_name)?, Vec::new()))
}

/// Parse and validate a design in `format`; `file_name` names the file in errors.
pub fn from_str(text: &str, format: Format, file_name: &str) -> Result<Design, DesignError> {
    let mut design = match format {
        Format::Toml => parse_toml(text, file_name)?,
        Format::Json => parse_json(text, file_name)?,
    };
    design.file = file_name.to_string();
    design.expand()?;
    super::neon::validate(&design)?;
    super::neon::apply_defaults(&mut design);
    validate(&design)?;
    design.normalize_colors();
    Ok(design)
}

/// 1-based (line, column) of byte offset `pos` in `text`; the column counts characters.
#[must_use]
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let mut pos = pos.min(text.len());
    while !text.is_char_boundary(pos) {
        pos -= 1;
    }
    let before = &text[..pos];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

fn toml_error(text: &str, file_name: &str, e: &toml::de::Error) -> DesignError {
    let (line, column) = match e.span() {
        Some(s) => {
            let (l, c) = line_col(text, s.start);
            (Some(l), Some(c))
        }
        None => (None, None),
    };
    DesignError::file(
        file_name,
        ErrorKind::Parse {
            line,
            column,
            message: e.message().trim().to_string(),
        },
    )
}

fn check_version(found: Option<String>, file_name: &str) -> Result<(), DesignError> {
    match found {
        None => Err(DesignError::file(file_name, ErrorKind::MissingVersion)),
        Some(v) if v == VERSION.to_string() => Ok(()),
        Some(v) => Err(DesignError::file(file_name, ErrorKind::Version(v))),
    }
}

fn parse_toml(text: &str, file_name: &str) -> Result<Design, DesignError> {
    // The version is checked first, on the untyped table, so a file of another version is
    // reported as such rather than by its first unknown key.
    let table: toml::Table = text.parse().map_err(|e| toml_error(text, file_name, &e))?;
    check_version(table.get("version").map(|v| v.to_string()), file_name)?;
    toml::from_str(text).map_err(|e| toml_error(text, file_name, &e))
}

fn json_error(file_name: &str, e: &serde_json::Error) -> DesignError {
    let (line, column) = if e.line() > 0 {
        (Some(e.line()), Some(e.column()))
    } else {
        (None, None)
    };
    // serde_json appends " at line L column C" to its messages; the location is ours.
    let full = e.to_string();
    let message = match full.rfind(" at line ") {
        Some(i) => full[..i].to_string(),
        None => full,
    };
    DesignError::file(
        file_name,
        ErrorKind::Parse {
            line,
            column,
            message,
        },
    )
}

fn parse_json(text: &str, file_name: &str) -> Result<Design, DesignError> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| json_error(file_name, &e))?;
    let Some(obj) = value.as_object() else {
        return Err(DesignError::file(
            file_name,
            ErrorKind::Parse {
                line: None,
                column: None,
                message: "a design is a JSON object".to_string(),
            },
        ));
    };
    check_version(obj.get("version").map(|v| v.to_string()), file_name)?;
    serde_json::from_str(text).map_err(|e| json_error(file_name, &e))
}

impl Design {
    /// A design of format [`VERSION`](super::VERSION) in millimetres with no item or
    /// operation, named `file` (for designs built in code: a text, an import).
    #[must_use]
    pub fn empty(file: &str) -> Design {
        Design {
            version: super::VERSION,
            units: super::Units::Mm,
            outline: None,
            stroke: Vec::new(),
            circles: Vec::new(),
            shape: Vec::new(),
            text: Vec::new(),
            operation: Vec::new(),
            file: file.to_string(),
            corners: Vec::new(),
            neon: None,
            output: Vec::new(),
        }
    }

    /// The design as TOML text (format v1).
    pub fn to_toml_string(&self) -> Result<String, DesignError> {
        toml::to_string(self)
            .map_err(|e| DesignError::file(&self.file, ErrorKind::Serialize(e.to_string())))
    }

    /// The design as pretty-printed JSON text (format v1).
    pub fn to_json_string(&self) -> Result<String, DesignError> {
        serde_json::to_string_pretty(self)
            .map_err(|e| DesignError::file(&self.file, ErrorKind::Serialize(e.to_string())))
    }

    /// The design in `format`.
    pub fn to_string_as(&self, format: Format) -> Result<String, DesignError> {
        match format {
            Format::Toml => self.to_toml_string(),
            Format::Json => self.to_json_string(),
        }
    }
}
