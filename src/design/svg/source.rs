//! What is read from the source document rather than usvg's tree: the CSS cascade of
//! presentation properties, Inkscape layers, element names and path-data errors.

use super::*;

/// The value of the inherited presentation property `name` on `n`: from its `style`
/// attribute, else the last rule of the highest specificity of the style `sheet` that
/// matches it, else the attribute itself (the CSS cascade of SVG 1.1 §6.4, without
/// `!important`), else from the nearest ancestor that sets it.
pub(super) fn inherited<'a>(
    n: roxmltree::Node<'a, 'a>,
    name: &str,
    sheet: &[simplecss::Rule<'a>],
) -> Option<&'a str> {
    n.ancestors().filter(|a| a.is_element()).find_map(|a| {
        let styled = a.attribute("style").and_then(|st| {
            st.split(';').find_map(|decl| {
                let (k, v) = decl.split_once(':')?;
                (k.trim() == name).then_some(v)
            })
        });
        let css = || {
            sheet
                .iter()
                .filter(|r| r.selector.matches(&XmlElement(a)))
                .filter_map(|r| {
                    let d = r.declarations.iter().rev().find(|d| d.name == name)?;
                    Some((r.selector.specificity(), d.value))
                })
                .fold(None, |best: Option<([u8; 3], &str)>, (sp, v)| match best {
                    Some((b, _)) if b > sp => best,
                    _ => Some((sp, v)),
                })
                .map(|(_, v)| v)
        };
        styled.or_else(css).or_else(|| a.attribute(name))
    })
}

/// The rules of every `<style>` element of the document, in document order.
pub(super) fn style_rules<'a>(xml: &'a roxmltree::Document<'a>) -> Vec<simplecss::Rule<'a>> {
    let mut sheet = simplecss::StyleSheet::new();
    for n in xml.descendants().filter(|n| n.has_tag_name("style")) {
        for t in n.children().filter_map(|c| c.text()) {
            sheet.parse_more(t);
        }
    }
    sheet.rules
}

/// A source element as CSS selectors see it.
#[derive(Clone, Copy)]
struct XmlElement<'a>(roxmltree::Node<'a, 'a>);

impl simplecss::Element for XmlElement<'_> {
    fn parent_element(&self) -> Option<Self> {
        self.0.parent_element().map(XmlElement)
    }

    fn prev_sibling_element(&self) -> Option<Self> {
        self.0.prev_sibling_element().map(XmlElement)
    }

    fn has_local_name(&self, name: &str) -> bool {
        self.0.tag_name().name() == name
    }

    fn attribute_matches(&self, local_name: &str, operator: simplecss::AttributeOperator) -> bool {
        self.0
            .attribute(local_name)
            .is_some_and(|v| operator.matches(v))
    }

    fn pseudo_class_matches(&self, class: simplecss::PseudoClass) -> bool {
        matches!(class, simplecss::PseudoClass::FirstChild)
            && self.0.prev_sibling_element().is_none()
    }
}

/// The label of an Inkscape layer (`inkscape:groupmode="layer"`, its `inkscape:label`, else
/// its id), `None` for any other element.
pub(super) fn layer_label<'a>(n: roxmltree::Node<'a, 'a>) -> Option<&'a str> {
    if n.attribute((INKSCAPE_NS, "groupmode")) != Some("layer") {
        return None;
    }
    n.attribute((INKSCAPE_NS, "label"))
        .or_else(|| n.attribute("id"))
        .filter(|l| !l.is_empty())
}

/// How an element of the source is named in the lists: its id, or `<tag> at line L`.
pub(super) fn source_name(xml: &roxmltree::Document<'_>, n: roxmltree::Node<'_, '_>) -> String {
    match n.attribute("id") {
        Some(id) if !id.is_empty() => id.to_string(),
        _ => {
            let p = xml.text_pos_at(n.range().start);
            format!("<{}> at line {}", n.tag_name().name(), p.row)
        }
    }
}

/// Where the path data `d` stops being valid SVG path syntax, in words (`None` when it is
/// valid throughout), by svgtypes' path parser, the one usvg reads `d` with.
pub(super) fn path_data_error(d: &str) -> Option<String> {
    svgtypes::PathParser::from(d)
        .find_map(Result::err)
        .map(|e| format!("is malformed ({e})"))
}
