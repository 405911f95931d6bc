//! Reading the XML of an SVG file as found in the wild: a `<!DOCTYPE …>` with an internal
//! subset (Illustrator, CorelDRAW and Batik write one) is read, internal entities are
//! expanded within a budget checked before parsing, external entities (`SYSTEM`/`PUBLIC`)
//! are never resolved, and the element count and nesting depth are bounded so the later
//! stages (usvg's converter and the import walk recurse per level) run in bounded stack and
//! memory.

use super::super::error::{DesignError, ErrorKind};

/// Most characters that entity references may expand to in one document (16 Mi). A
/// drawing's entities are a few short names (Illustrator's `&ns_svg;`); a "billion laughs"
/// document (entities of entities) asks for far more and is refused before parsing.
pub const MAX_ENTITY_EXPANSION: u64 = 16 << 20;

/// Most XML nodes (elements, text, comments) in one document: 10⁵ paths with their text
/// nodes fit with room; the parsed tree costs a few hundred bytes per node.
pub const MAX_NODES: u32 = 4_000_000;

/// Deepest element nesting read (usvg converts groups recursively; drawing programs nest
/// layers and groups a few tens deep).
pub const MAX_DEPTH: usize = 256;

/// Most CSS rules in a document's `<style>` elements: usvg's style resolution grows with
/// the square of the rule count; drawing programs write one rule per distinct style, a few
/// hundred at most.
pub const MAX_CSS_RULES: usize = 2_000;

/// Deepest nesting of entity definitions followed when sizing the expansion (roxmltree
/// stops at 10 levels of references too).
const MAX_ENTITY_NESTING: usize = 16;

fn parse_error(file: &str, line: Option<usize>, column: Option<usize>, m: String) -> DesignError {
    DesignError::file(
        file,
        ErrorKind::Parse {
            line,
            column,
            message: m,
        },
    )
}

/// One `<!ENTITY name "value">` (internal) or `<!ENTITY name SYSTEM "uri">` (external) of
/// the internal subset.
struct Entity<'a> {
    name: &'a str,
    /// The replacement text; `None` for an external entity.
    value: Option<&'a str>,
}

/// The entity declarations of the DOCTYPE's internal subset and the byte offset where the
/// document after the DOCTYPE starts (0 without a DOCTYPE). A scan, not a validating
/// parser: roxmltree parses the DTD itself; this finds what the expansion budget needs.
fn entities(text: &str) -> (Vec<Entity<'_>>, usize) {
    let Some(start) = text.find("<!DOCTYPE") else {
        return (Vec::new(), 0);
    };
    let mut out = Vec::new();
    let mut rest = &text[start..];
    let mut offset = start;
    // The internal subset, if any, is between '[' and "]>".
    let Some(open) = rest.find(['[', '>']) else {
        return (out, text.len());
    };
    if rest.as_bytes()[open] == b'>' {
        return (out, offset + open + 1);
    }
    rest = &rest[open + 1..];
    offset += open + 1;
    while let Some(k) = rest.find(['<', ']']) {
        if rest.as_bytes()[k] == b']' {
            let end = rest[k..].find('>').map_or(rest.len(), |e| k + e + 1);
            return (out, offset + end);
        }
        let decl = &rest[k..];
        let skip = if let Some(body) = decl.strip_prefix("<!ENTITY") {
            let (entity, used) = entity_decl(body);
            out.extend(entity);
            "<!ENTITY".len() + used
        } else if decl.starts_with("<!--") {
            decl.find("-->").map_or(decl.len(), |e| e + 3)
        } else {
            quoted_end(decl)
        };
        rest = &decl[skip..];
        offset += k + skip;
    }
    (out, text.len())
}

/// The length of a markup declaration up to its closing '>' outside quotes.
fn quoted_end(decl: &str) -> usize {
    let mut quote = None;
    for (i, c) in decl.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '>') => return i + 1,
            _ => {}
        }
    }
    decl.len()
}

/// An entity declaration body (after `<!ENTITY`): the entity (none for a parameter entity
/// `%`, which roxmltree does not expand) and the bytes used.
fn entity_decl(body: &str) -> (Option<Entity<'_>>, usize) {
    let used = quoted_end(body);
    let decl = body[..used].trim_end_matches('>').trim_start();
    if decl.starts_with('%') {
        return (None, used);
    }
    let name_end = decl.find(char::is_whitespace).unwrap_or(decl.len());
    let name = &decl[..name_end];
    let def = decl[name_end..].trim_start();
    let value = def
        .chars()
        .next()
        .filter(|c| *c == '"' || *c == '\'')
        .and_then(|q| {
            let inner = &def[1..];
            inner.find(q).map(|e| &inner[..e])
        });
    (Some(Entity { name, value }), used)
}

/// The entity references `&name;` in `s` (character references `&#…;` left out).
fn references(s: &str) -> impl Iterator<Item = &str> {
    s.split('&').skip(1).filter_map(|t| {
        let end = t.find(';')?;
        let name = &t[..end];
        (!name.starts_with('#') && !name.is_empty() && !name.contains(char::is_whitespace))
            .then_some(name)
    })
}

/// Characters `name` expands to (saturating; `u64::MAX` for a reference cycle or nesting
/// deeper than [`MAX_ENTITY_NESTING`]): its replacement text's length with every reference
/// replaced by its own expansion, memoised per entity.
fn expansion(
    name: &str,
    defs: &[Entity<'_>],
    memo: &mut std::collections::HashMap<String, u64>,
    depth: usize,
) -> u64 {
    if let Some(&n) = memo.get(name) {
        return n;
    }
    let Some(value) = defs.iter().find(|e| e.name == name).and_then(|e| e.value) else {
        return name.len() as u64 + 2; // predefined, external or unknown: left to the parser
    };
    if depth >= MAX_ENTITY_NESTING {
        return u64::MAX;
    }
    let mut n = value.len() as u64;
    for r in references(value) {
        // The reference `&r;` is replaced by its expansion.
        n = n
            .saturating_sub(r.len() as u64 + 2)
            .saturating_add(expansion(r, defs, memo, depth + 1));
    }
    memo.insert(name.to_string(), n);
    n
}

/// Parse `text` as XML for usvg: DTD allowed, entity expansion within
/// [`MAX_ENTITY_EXPANSION`] (sized before parsing: the sum over the document's references
/// of each entity's expansion), external entities never read (referring to one is an error
/// naming it), at most [`MAX_NODES`] nodes and [`MAX_DEPTH`] levels of elements.
pub fn parse<'a>(text: &'a str, file: &str) -> Result<roxmltree::Document<'a>, DesignError> {
    let (defs, body) = entities(text);
    if !defs.is_empty() {
        let mut memo = std::collections::HashMap::new();
        let mut total: u64 = 0;
        for r in references(&text[body..]) {
            if let Some(e) = defs.iter().find(|e| e.name == r)
                && e.value.is_none()
            {
                return Err(parse_error(
                    file,
                    None,
                    None,
                    format!(
                        "entity &{r}; is external (SYSTEM or PUBLIC): external entities, files \
                         and URLs are never read"
                    ),
                ));
            }
            total = total.saturating_add(expansion(r, &defs, &mut memo, 0));
            if total > MAX_ENTITY_EXPANSION {
                return Err(parse_error(
                    file,
                    None,
                    None,
                    format!(
                        "entity references expand to more than {MAX_ENTITY_EXPANSION} \
                         characters (an entity bomb?); not read"
                    ),
                ));
            }
        }
    }
    let opts = roxmltree::ParsingOptions {
        allow_dtd: true,
        nodes_limit: MAX_NODES,
        // No resolver: roxmltree discards every external entity (never reads it).
        entity_resolver: None,
    };
    let xml = roxmltree::Document::parse_with_options(text, opts).map_err(|e| {
        let p = e.pos();
        let m = match e {
            roxmltree::Error::NodesLimitReached => {
                format!("more than {MAX_NODES} XML nodes; not read")
            }
            roxmltree::Error::EntityReferenceLoop(_) => {
                "entity references nest too deep or too often (an entity bomb?); not read"
                    .to_string()
            }
            e => format!("not a well-formed SVG file: {e}"),
        };
        parse_error(file, Some(p.row as usize), Some(p.col as usize), m)
    })?;
    // Nesting depth, without recursion: depth of each element from its parent's.
    let mut stack: Vec<(roxmltree::Node<'_, '_>, usize)> = vec![(xml.root(), 0)];
    while let Some((n, d)) = stack.pop() {
        if d > MAX_DEPTH {
            let p = xml.text_pos_at(n.range().start);
            return Err(parse_error(
                file,
                Some(p.row as usize),
                Some(p.col as usize),
                format!("elements nest more than {MAX_DEPTH} levels deep; not read"),
            ));
        }
        stack.extend(n.children().filter(|c| c.is_element()).map(|c| (c, d + 1)));
    }
    // CSS rules, counted as the opening braces of the style sheets.
    let rules: usize = xml
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "style")
        .flat_map(|n| n.children().filter_map(|c| c.text()))
        .map(|t| t.matches('{').count())
        .sum();
    if rules > MAX_CSS_RULES {
        return Err(parse_error(
            file,
            None,
            None,
            format!(
                "style sheets of {rules} CSS rules, more than the limit {MAX_CSS_RULES}; not read"
            ),
        ));
    }
    Ok(xml)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entity_expansion_is_sized_from_the_declarations() {
        let text = r#"<!DOCTYPE svg [ <!ENTITY a "xyz"> <!ENTITY b "&a;&a;-"> <!-- c --> <!ENTITY % p "q"> ]><svg>&b;&b;</svg>"#;
        let (defs, body) = entities(text);
        assert_eq!(defs.len(), 2);
        assert_eq!(&text[body..body + 5], "<svg>");
        let mut memo = Default::default();
        // b = "xyz" + "xyz" + "-": 7 characters.
        assert_eq!(expansion("b", &defs, &mut memo, 0), 7);
        assert_eq!(references(&text[body..]).count(), 2);
    }

    #[test]
    fn a_cycle_has_unbounded_expansion() {
        let text = r#"<!DOCTYPE svg [ <!ENTITY a "&b;"> <!ENTITY b "&a;"> ]><svg/>"#;
        let (defs, _) = entities(text);
        assert_eq!(expansion("a", &defs, &mut Default::default(), 0), u64::MAX);
    }
}
