//! A deliberately small XML tag scanner, sufficient for the VTK/PVD headers
//! this module writes (and for similar hand-written files). It understands
//! start, end and empty-element tags with quoted attributes, skips the XML
//! declaration, comments, processing instructions and DOCTYPE, decodes the
//! predefined and numeric character entities, and keeps the text that
//! follows each tag. It does not validate nesting.

/// Kind of a scanned tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TagKind {
    /// `<name ...>`
    Start,
    /// `</name>`
    End,
    /// `<name .../>`
    Empty,
}

/// One scanned tag.
#[derive(Debug, Clone)]
pub(crate) struct Tag {
    /// Element name.
    pub name: String,
    /// Start, end or empty-element tag.
    pub kind: TagKind,
    /// Attributes in document order, values entity-decoded.
    pub attrs: Vec<(String, String)>,
    /// Character data between this tag and the next markup (not decoded
    /// beyond entities; may be whitespace).
    pub text: String,
}

impl Tag {
    /// Value of attribute `key`, if present.
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

/// Escapes text for use inside a double-quoted attribute value or as
/// character data.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

/// Decodes the predefined and numeric character entities.
pub(crate) fn unescape(s: &str) -> Result<String, String> {
    if !s.contains('&') {
        return Ok(s.to_owned());
    }
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let end = after
            .find(';')
            .ok_or_else(|| format!("unterminated entity in {s:?}"))?;
        let ent = &after[..end];
        let c = match ent {
            "amp" => '&',
            "lt" => '<',
            "gt" => '>',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = if let Some(hex) = ent.strip_prefix("#x").or(ent.strip_prefix("#X")) {
                    u32::from_str_radix(hex, 16).ok()
                } else if let Some(dec) = ent.strip_prefix('#') {
                    dec.parse::<u32>().ok()
                } else {
                    None
                };
                code.and_then(char::from_u32)
                    .ok_or_else(|| format!("unknown entity &{ent};"))?
            }
        };
        out.push(c);
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

fn is_name_char(c: char) -> bool {
    c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | ':')
}

/// Scans all tags of `doc`.
pub(crate) fn scan(doc: &str) -> Result<Vec<Tag>, String> {
    let mut tags: Vec<Tag> = Vec::new();
    let mut pos = match doc.find('<') {
        Some(p) => p,
        None => return Ok(tags),
    };
    while pos < doc.len() {
        let rest = &doc[pos..];
        // Skip declarations, comments, processing instructions.
        let skip_to = if rest.starts_with("<!--") {
            Some(("-->", 4))
        } else if rest.starts_with("<?") {
            Some(("?>", 2))
        } else if rest.starts_with("<!") {
            Some((">", 2))
        } else {
            None
        };
        let tag_end;
        if let Some((terminator, start)) = skip_to {
            let close = rest[start..]
                .find(terminator)
                .ok_or_else(|| format!("unterminated markup at byte {pos}"))?;
            tag_end = pos + start + close + terminator.len();
        } else {
            let (tag, len) = parse_tag(rest).map_err(|e| format!("{e} at byte {pos}"))?;
            tags.push(tag);
            tag_end = pos + len;
        }
        let next = doc[tag_end..].find('<').map_or(doc.len(), |off| tag_end + off);
        if let Some(last) = tags.last_mut()
            && last.text.is_empty()
        {
            last.text = unescape(&doc[tag_end..next])?;
        }
        pos = next;
    }
    Ok(tags)
}

/// Parses one tag at the start of `s` (which begins with `<`), returning the
/// tag and its length in bytes.
fn parse_tag(s: &str) -> Result<(Tag, usize), String> {
    let mut i = 1;
    let bytes = s.as_bytes();
    let mut kind = TagKind::Start;
    if bytes.get(1) == Some(&b'/') {
        kind = TagKind::End;
        i = 2;
    }
    let name_len = s[i..].find(|c: char| !is_name_char(c)).unwrap_or(s.len() - i);
    if name_len == 0 {
        return Err("missing element name".into());
    }
    let name = s[i..i + name_len].to_owned();
    i += name_len;
    let mut attrs = Vec::new();
    loop {
        let trimmed = s[i..].trim_start();
        i = s.len() - trimmed.len();
        if trimmed.is_empty() {
            return Err(format!("unterminated tag <{name}"));
        }
        if trimmed.starts_with("/>") {
            if kind == TagKind::End {
                return Err(format!("malformed end tag </{name}"));
            }
            kind = TagKind::Empty;
            i += 2;
            break;
        }
        if trimmed.starts_with('>') {
            i += 1;
            break;
        }
        if kind == TagKind::End {
            return Err(format!("attributes in end tag </{name}"));
        }
        let key_len = trimmed.find(|c: char| !is_name_char(c)).unwrap_or(trimmed.len());
        if key_len == 0 {
            return Err(format!("unexpected character in tag <{name}"));
        }
        let key = trimmed[..key_len].to_owned();
        let after_key = trimmed[key_len..].trim_start();
        let after_eq = after_key
            .strip_prefix('=')
            .ok_or_else(|| format!("attribute {key} without value in <{name}"))?
            .trim_start();
        let quote = after_eq
            .chars()
            .next()
            .filter(|c| *c == '"' || *c == '\'')
            .ok_or_else(|| format!("unquoted attribute {key} in <{name}"))?;
        let body = &after_eq[1..];
        let close = body
            .find(quote)
            .ok_or_else(|| format!("unterminated attribute {key} in <{name}"))?;
        attrs.push((key, unescape(&body[..close])?));
        let consumed = trimmed.len() - body[close + 1..].len();
        i += consumed;
    }
    Ok((
        Tag {
            name,
            kind,
            attrs,
            text: String::new(),
        },
        i,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scans_tags() {
        let doc = r#"<?xml version="1.0"?><!-- c --><A x="1" y='a&amp;b'><B z="&#65;"/>text&lt;</A>"#;
        let tags = scan(doc).unwrap();
        assert_eq!(tags.len(), 3);
        assert_eq!(tags[0].name, "A");
        assert_eq!(tags[0].attr("y"), Some("a&b"));
        assert_eq!(tags[1].kind, TagKind::Empty);
        assert_eq!(tags[1].attr("z"), Some("A"));
        assert_eq!(tags[1].text, "text<");
        assert_eq!(tags[2].kind, TagKind::End);
    }

    #[test]
    fn rejects_garbage() {
        for bad in [
            "<",
            "<A",
            "<A x>",
            "<A x=1>",
            "<A x=\"1>",
            "</A x=\"1\">",
            "<A &foo;>",
        ] {
            assert!(scan(bad).is_err(), "{bad}");
        }
        assert!(unescape("&bogus;").is_err());
        assert_eq!(escape("<a&\"'>"), "&lt;a&amp;&quot;&apos;&gt;");
    }
}
