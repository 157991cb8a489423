//! The document type declaration: the standard SVG 1.0/1.1 `<!DOCTYPE …>` that Illustrator and
//! older Inkscape write, and the internal entities (`<!ENTITY ns_svg "http://…">`) Illustrator
//! uses, expanded here under the byte limit before any parser sees the text.
//!
//! A small file can declare an entity of 100 KB and use it 20,000 times; an XML parser expands
//! that to gigabytes before anything can stop it. Here the expansion is counted as it is
//! written and stops at [`Limits::input_bytes`], and the declaration is then removed, so the
//! parsers downstream (quick-xml, usvg's roxmltree) never see a DTD. External entities
//! (`SYSTEM`, `PUBLIC`) are never read: using one is an error.

use std::collections::HashMap;

use super::Limits;
use crate::error::{Error, Result};

/// Nesting of entity references inside entity values, at most (XML allows cycles to be
/// refused; this also bounds the recursion).
const MAX_ENTITY_DEPTH: usize = 16;

/// `text` with its document type declaration removed and the internal general entities it
/// declares expanded, or `None` when it has no declaration. `name` is how errors call the file.
pub(crate) fn expand(name: &str, text: &str, limits: &Limits) -> Result<Option<String>> {
    let Some((start, end)) = doctype_span(text) else {
        return Ok(None);
    };
    let decl = &text[start..end];
    let entities = declarations(name, decl)?;
    let mut out = Expander {
        name,
        entities: &entities,
        budget: limits.input_bytes as usize,
        work: 0,
        limits,
        out: String::with_capacity(text.len()),
    };
    out.push(&text[..start])?;
    out.body(&text[end..], 0)?;
    Ok(Some(out.out))
}

/// The byte span of `<!DOCTYPE …>` before the root element, including its internal subset.
fn doctype_span(text: &str) -> Option<(usize, usize)> {
    let b = text.as_bytes();
    let mut i = 0;
    loop {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        let rest = &text[i..];
        if rest.starts_with("<?") {
            i += rest.find("?>")? + 2;
        } else if rest.starts_with("<!--") {
            i += rest.find("-->")? + 3;
        } else if rest.starts_with("<!DOCTYPE") {
            return Some((i, i + doctype_len(rest)?));
        } else {
            return None;
        }
    }
}

/// The length of the declaration at the start of `s`: up to the `>` after the internal
/// subset's `]`, skipping quoted strings and comments.
fn doctype_len(s: &str) -> Option<usize> {
    let b = s.as_bytes();
    let mut i = "<!DOCTYPE".len();
    let mut in_subset = false;
    while i < b.len() {
        match b[i] {
            q @ (b'"' | b'\'') => i += 1 + s[i + 1..].find(q as char)?,
            b'<' if s[i..].starts_with("<!--") => i += s[i..].find("-->")? + 2,
            b'[' if !in_subset => in_subset = true,
            b']' if in_subset => in_subset = false,
            b'>' if !in_subset => return Some(i + 1),
            _ => {}
        }
        i += 1;
    }
    None
}

/// An entity declared in the internal subset.
enum Entity {
    /// Replacement text.
    Internal(String),
    /// `SYSTEM` or `PUBLIC`: never read.
    External,
}

/// The general entities declared in `decl` (first declaration wins, as in XML).
fn declarations(name: &str, decl: &str) -> Result<HashMap<String, Entity>> {
    let mut map = HashMap::new();
    let mut rest = decl;
    while let Some(at) = rest.find("<!ENTITY") {
        rest = &rest[at + "<!ENTITY".len()..];
        let malformed = || Error::input(name, "not a well-formed SVG file: a broken <!ENTITY …>");
        let body = rest.trim_start();
        if body.starts_with('%') {
            continue; // a parameter entity: only for the DTD itself
        }
        let ident_len = body
            .find(|c: char| c.is_whitespace())
            .ok_or_else(malformed)?;
        let ident = &body[..ident_len];
        let def = body[ident_len..].trim_start();
        let entity = match def.chars().next() {
            Some(q @ ('"' | '\'')) => {
                let value = &def[1..];
                let close = value.find(q).ok_or_else(malformed)?;
                Entity::Internal(value[..close].to_string())
            }
            _ if def.starts_with("SYSTEM") || def.starts_with("PUBLIC") => Entity::External,
            _ => return Err(malformed()),
        };
        map.entry(ident.to_string()).or_insert(entity);
    }
    Ok(map)
}

struct Expander<'a> {
    name: &'a str,
    entities: &'a HashMap<String, Entity>,
    budget: usize,
    /// Bytes of replacement text visited: bounds the work of entities that expand to little
    /// or nothing but are nested deep.
    work: usize,
    limits: &'a Limits,
    out: String,
}

impl Expander<'_> {
    fn push(&mut self, s: &str) -> Result<()> {
        if self.out.len() + s.len() > self.budget {
            return Err(super::file::too_long(
                self.name,
                "with its entities expanded, it",
                (self.out.len() + s.len()) as u64,
                self.limits,
            ));
        }
        self.out.push_str(s);
        Ok(())
    }

    /// Copies `text`, expanding general entity references outside comments and CDATA.
    fn body(&mut self, text: &str, depth: usize) -> Result<()> {
        let mut rest = text;
        while let Some(at) = rest.find(['&', '<']) {
            self.push(&rest[..at])?;
            rest = &rest[at..];
            if let Some(verbatim) = ["<!--", "<![CDATA["]
                .iter()
                .zip(["-->", "]]>"])
                .find(|(open, _)| rest.starts_with(**open))
                .map(|(_, close)| rest.find(close).map_or(rest.len(), |e| e + close.len()))
            {
                self.push(&rest[..verbatim])?;
                rest = &rest[verbatim..];
                continue;
            }
            if rest.starts_with('<') {
                self.push("<")?;
                rest = &rest[1..];
                continue;
            }
            let reference = rest[1..].find(';').map(|e| &rest[1..1 + e]);
            match reference.and_then(|r| self.entities.get(r).map(|e| (r, e))) {
                Some((r, Entity::Internal(value))) => {
                    if depth >= MAX_ENTITY_DEPTH {
                        return Err(Error::input(
                            self.name,
                            format!("the entity '{r}' refers to itself, or nests too deep"),
                        ));
                    }
                    self.work += r.len() + 2 + value.len();
                    if self.work > self.budget {
                        return Err(super::file::too_long(
                            self.name,
                            "with its entities expanded, it",
                            self.work as u64,
                            self.limits,
                        ));
                    }
                    let value = value.clone();
                    self.body(&value, depth + 1)?;
                    rest = &rest[r.len() + 2..];
                }
                Some((r, Entity::External)) => {
                    return Err(Error::input(
                        self.name,
                        format!("the entity '{r}' is an external file, which crmorph never reads"),
                    ))
                }
                // Predefined entities, character references and undeclared names stay as
                // they are for the XML parser.
                None => {
                    self.push("&")?;
                    rest = &rest[1..];
                }
            }
        }
        self.push(rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str) -> Result<Option<String>> {
        expand("a.svg", text, &Limits::default())
    }

    #[test]
    fn the_standard_doctype_is_removed() {
        let t = "<?xml version=\"1.0\"?>\n<!-- made by hand -->\n<!DOCTYPE svg PUBLIC \
                 \"-//W3C//DTD SVG 1.1//EN\" \"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd\">\n<svg/>";
        assert_eq!(
            run(t).unwrap().unwrap(),
            "<?xml version=\"1.0\"?>\n<!-- made by hand -->\n\n<svg/>"
        );
        assert_eq!(run("<svg/>").unwrap(), None);
    }

    #[test]
    fn internal_entities_expand_like_illustrators() {
        let t = "<!DOCTYPE svg [\n <!ENTITY ns_svg \"http://www.w3.org/2000/svg\">\n <!ENTITY \
                 both '&ns_svg;#'>\n <!ENTITY % pe \"x\">\n]>\n<svg xmlns=\"&ns_svg;\" id=\"&both;&amp;\
                 &#65;\"><!-- &ns_svg; --><style><![CDATA[&both;]]></style></svg>";
        assert_eq!(
            run(t).unwrap().unwrap(),
            "\n<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"http://www.w3.org/2000/svg#&amp;\
             &#65;\"><!-- &ns_svg; --><style><![CDATA[&both;]]></style></svg>"
        );
    }

    #[test]
    fn bombs_loops_and_external_entities_are_refused() {
        // A quadratic bomb: 100 KB used 20,000 times is 2 GB; stopped at the byte limit.
        let big = "x".repeat(100_000);
        let uses = "&e;".repeat(20_000);
        let t = format!("<!DOCTYPE svg [<!ENTITY e \"{big}\">]><svg><text>{uses}</text></svg>");
        let started = std::time::Instant::now();
        let e = run(&t).unwrap_err().to_string();
        assert!(
            e.contains("a.svg: with its entities expanded, it has")
                && e.contains("--max-input-bytes"),
            "{e}"
        );
        assert!(started.elapsed().as_secs_f64() < 2.0);
        // An exponential one (billion laughs).
        let mut decl = String::from("<!ENTITY l0 \"lol\">");
        for k in 1..10 {
            decl += &format!("<!ENTITY l{k} \"{}\">", format!("&l{};", k - 1).repeat(10));
        }
        let t = format!("<!DOCTYPE svg [{decl}]><svg>&l9;</svg>");
        assert!(run(&t)
            .unwrap_err()
            .to_string()
            .contains("--max-input-bytes"));
        // Nested empty entities: no output, exponential work.
        let mut decl = String::from("<!ENTITY l0 \"\">");
        for k in 1..30 {
            decl += &format!("<!ENTITY l{k} \"{}\">", format!("&l{};", k - 1).repeat(10));
        }
        let t = format!("<!DOCTYPE svg [{decl}]><svg>&l15;</svg>");
        let started = std::time::Instant::now();
        assert!(run(&t)
            .unwrap_err()
            .to_string()
            .contains("--max-input-bytes"));
        assert!(started.elapsed().as_secs_f64() < 2.0);
        let t = "<!DOCTYPE svg [<!ENTITY a \"&b;\"><!ENTITY b \"&a;\">]><svg>&a;</svg>";
        assert!(run(t).unwrap_err().to_string().contains("refers to itself"));
        let t = "<!DOCTYPE svg [<!ENTITY x SYSTEM \"/etc/passwd\">]><svg>&x;</svg>";
        assert!(run(t).unwrap_err().to_string().contains("never reads"));
    }
}
