//! A minimal element tree read with quick-xml: names, attributes and children, nothing else.
//!
//! usvg drops what it does not render (guides in a hidden `controls` group, paths without fill
//! and stroke), so control geometry is read from this raw tree instead (DESIGN.md §1).

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

/// Refuse documents with more elements than this (usvg has a similar guard): a bound on work.
const MAX_ELEMENTS: usize = 1_000_000;

/// One XML element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Element {
    /// Local name (`path`, `g`, …), namespace prefix stripped.
    pub(crate) name: String,
    /// Attributes in document order, names with namespace prefix stripped except `xlink:`.
    pub(crate) attrs: Vec<(String, String)>,
    /// Child elements in document order.
    pub(crate) children: Vec<Element>,
}

impl Element {
    /// The value of attribute `name`, if present.
    pub(crate) fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The element's `id`, if any.
    pub(crate) fn id(&self) -> Option<&str> {
        self.attr("id")
    }
}

/// Why a document could not be read as XML.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum XmlProblem {
    /// Zero bytes, or only whitespace.
    Empty,
    /// Not XML at all, or broken XML; the message says where.
    Malformed(String),
    /// The document ends before its elements are closed.
    Truncated(String),
    /// The root element is not `<svg>`.
    NotSvg(String),
    /// More elements than [`MAX_ELEMENTS`].
    TooLarge,
}

impl std::fmt::Display for XmlProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            XmlProblem::Empty => write!(f, "the file is empty"),
            XmlProblem::Malformed(m) => write!(f, "not a well-formed SVG file: {m}"),
            XmlProblem::Truncated(m) => write!(f, "the file is truncated: it ends inside <{m}>"),
            XmlProblem::NotSvg(m) => {
                write!(f, "not an SVG file: the root element is <{m}>, not <svg>")
            }
            XmlProblem::TooLarge => write!(f, "the file has more than {MAX_ELEMENTS} elements"),
        }
    }
}

fn local(name: &str) -> String {
    match name.split_once(':') {
        Some(("xlink", _)) => name.to_string(),
        Some((_, l)) => l.to_string(),
        None => name.to_string(),
    }
}

fn element(e: &BytesStart<'_>) -> Result<Element, XmlProblem> {
    let mut attrs = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| XmlProblem::Malformed(err.to_string()))?;
        let v = a
            .normalized_value(quick_xml::XmlVersion::Implicit1_0)
            .map_err(|err| XmlProblem::Malformed(err.to_string()))?;
        attrs.push((local(a.key.as_ref()), v.into_owned()));
    }
    Ok(Element {
        name: local(e.name().as_ref()),
        attrs,
        children: Vec::new(),
    })
}

/// Parses `text` into the root element, which must be `<svg>`.
pub(crate) fn parse(text: &str) -> Result<Element, XmlProblem> {
    if text.trim().is_empty() {
        return Err(XmlProblem::Empty);
    }
    let mut reader = Reader::from_str(text);
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    let mut count = 0usize;
    loop {
        let ev = reader.read_event().map_err(|e| {
            let pos = reader.error_position() as usize;
            let msg = e.to_string();
            // An error at the very end of the text means the file was cut off.
            if msg.contains("end of input") || pos + 1 >= text.len() {
                let open = stack
                    .last()
                    .map(|e| e.name.clone())
                    .unwrap_or_else(|| "svg".into());
                XmlProblem::Truncated(open)
            } else {
                XmlProblem::Malformed(format!("{msg} (at byte {pos})"))
            }
        })?;
        match ev {
            Event::Start(_) | Event::Empty(_) if root.is_some() && stack.is_empty() => {
                return Err(XmlProblem::Malformed(
                    "content after the root element".into(),
                ));
            }
            Event::Start(e) => {
                count += 1;
                stack.push(element(&e)?);
            }
            Event::Empty(e) => {
                count += 1;
                let el = element(&e)?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => root = Some(el),
                }
            }
            Event::End(_) => {
                let el = stack
                    .pop()
                    .ok_or_else(|| XmlProblem::Malformed("unexpected closing tag".into()))?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => root = Some(el),
                }
            }
            Event::Text(t)
                if stack.is_empty()
                    && root.is_none()
                    && !t
                        .xml_content(quick_xml::XmlVersion::Implicit1_0)
                        .trim()
                        .is_empty() =>
            {
                return Err(XmlProblem::NotSvg("text".into()));
            }
            Event::Eof => break,
            _ => {}
        }
        if count > MAX_ELEMENTS {
            return Err(XmlProblem::TooLarge);
        }
    }
    if let Some(open) = stack.first() {
        let innermost = stack
            .last()
            .map(|e| e.name.clone())
            .unwrap_or_else(|| open.name.clone());
        return Err(XmlProblem::Truncated(innermost));
    }
    let root = root.ok_or_else(|| XmlProblem::NotSvg("nothing".into()))?;
    if root.name != "svg" {
        return Err(XmlProblem::NotSvg(root.name));
    }
    Ok(root)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_nested_elements_and_styles() {
        let r = parse(r#"<?xml version="1.0"?><svg xmlns="http://www.w3.org/2000/svg"><g id="a" style="display: none ; fill:red"><path id="p" d="M0 0"/></g></svg>"#).unwrap();
        assert_eq!(r.name, "svg");
        assert_eq!(r.children[0].id(), Some("a"));
        assert_eq!(r.children[0].children[0].attr("d"), Some("M0 0"));
    }

    #[test]
    fn problems_are_classified() {
        assert_eq!(parse("   "), Err(XmlProblem::Empty));
        assert!(matches!(parse("hello world"), Err(XmlProblem::NotSvg(_))));
        assert!(matches!(
            parse("<svg><g><path d='M0 0'/>"),
            Err(XmlProblem::Truncated(_))
        ));
        assert!(matches!(parse("<html></html>"), Err(XmlProblem::NotSvg(_))));
        assert!(matches!(
            parse("<svg><g></svg>"),
            Err(XmlProblem::Malformed(_))
        ));
    }
}
