//! A small read-only XML tree built with quick-xml, the one place the master parses XML: every
//! element keeps its local name (namespace prefix dropped), its attributes, its children and
//! its line in the file, so that a message can say `SystemStructure.ssd line 12 <Connection>`.
//! Uses quick-xml and error.rs.

use crate::error::{Error, Result};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

/// One XML element.
#[derive(Debug, Clone)]
pub struct Element {
    /// Local name (`Connection` for `ssd:Connection`).
    pub name: String,
    /// Attributes by local name, in document order.
    pub attrs: Vec<(String, String)>,
    /// Child elements in document order.
    pub children: Vec<Element>,
    /// 1-based line of the start tag.
    pub line: usize,
}

impl Element {
    /// The attribute `key`, if present.
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    /// The children named `name`.
    pub fn all<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.name == name)
    }
    /// The first child named `name`.
    pub fn first(&self, name: &str) -> Option<&Element> {
        self.children.iter().find(|c| c.name == name)
    }
    /// `line N <name>`, for messages.
    pub fn at(&self) -> String {
        format!("line {} <{}>", self.line, self.name)
    }
}

fn element(e: &BytesStart, line: usize) -> Result<Element> {
    let name = String::from_utf8_lossy(e.local_name().as_ref()).into_owned();
    let mut attrs = Vec::new();
    for a in e.attributes() {
        let a =
            a.map_err(|err| Error::new(format!("line {line} <{name}>: bad attribute: {err}")))?;
        let key = String::from_utf8_lossy(a.key.local_name().as_ref()).into_owned();
        let value = a
            .unescape_value()
            .map_err(|err| Error::new(format!("line {line} <{name}>: bad attribute {key}: {err}")))?
            .into_owned();
        attrs.push((key, value));
    }
    Ok(Element {
        name,
        attrs,
        children: Vec::new(),
        line,
    })
}

/// Parses `text` into its root element; a syntax error names its line.
pub fn parse(text: &str) -> Result<Element> {
    let mut reader = Reader::from_str(text);
    let line_of = |pos: usize| {
        text.as_bytes()[..pos.min(text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    };
    let mut stack: Vec<Element> = Vec::new();
    let mut root = None;
    loop {
        let pos = reader.buffer_position() as usize;
        let ev = reader.read_event().map_err(|e| {
            Error::new(format!(
                "not well-formed XML at line {}: {e}",
                line_of(reader.buffer_position() as usize)
            ))
        })?;
        match ev {
            Event::Start(e) => stack.push(element(&e, line_of(pos))?),
            Event::Empty(e) => {
                let el = element(&e, line_of(pos))?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => root = Some(el),
                }
            }
            Event::End(_) => {
                let el = stack.pop().ok_or_else(|| {
                    Error::new(format!("unbalanced end tag at line {}", line_of(pos)))
                })?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => root = Some(el),
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if let Some(open) = stack.last() {
        return Err(Error::new(format!(
            "not well-formed XML: <{}> of line {} is never closed",
            open.name, open.line
        )));
    }
    root.ok_or_else(|| Error::new("not XML: no root element"))
}

/// A required attribute, or an error naming the element and the attribute.
pub fn required<'a>(e: &'a Element, key: &str) -> Result<&'a str> {
    e.attr(key)
        .ok_or_else(|| Error::new(format!("{}: the attribute {key} is missing", e.at())))
}

/// A number attribute, if present; a present non-number is an error.
pub fn number(e: &Element, key: &str) -> Result<Option<f64>> {
    match e.attr(key) {
        None => Ok(None),
        Some(v) => v
            .trim()
            .parse::<f64>()
            .map(Some)
            .map_err(|_| Error::new(format!("{}: {key} = '{v}' is not a number", e.at()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_attributes_and_lines() {
        let x = parse(
            "<?xml version='1.0'?>\n<a:Root xmlns:a='u'>\n  <a:B k='1'/>\n  <C>t</C>\n</a:Root>",
        )
        .unwrap();
        assert_eq!(x.name, "Root");
        assert_eq!(x.children.len(), 2);
        assert_eq!(x.children[0].attr("k"), Some("1"));
        assert_eq!(x.children[0].line, 3);
        assert_eq!(x.children[1].line, 4);
    }

    #[test]
    fn broken_xml_is_refused_with_a_line() {
        let e = parse("<a>\n<b>\n</a>").unwrap_err();
        assert!(e.cause.contains("line"), "{e}");
        assert!(parse("<a><b/>").is_err());
    }
}
