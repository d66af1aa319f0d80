//! Command-line overrides (`--set KEY=VALUE`, `--end-time T`).
//!
//! KEY is a dotted path (`solver.dt`, `fluid.gravity`, `fluid_box.0.max`);
//! a segment made of digits indexes an array (of tables or of values). Quoted
//! key segments are not supported. VALUE is parsed as a TOML value (`1e-4`,
//! `[0.0, -9.81]`, `"x"`, `true`, `{ interval = 0.1 }`); text that is not a
//! TOML value is taken as a bare string, so `solver.kind=wcsph` works.
//! Missing intermediate tables are created; keys unknown to the schema are
//! rejected later by deserialization, reported at `--set KEY`.

use toml::{Table, Value};

use super::{KeyPath, Location, Problem, SceneError, Seg};

/// Applies `sets` (each `KEY=VALUE`) to `doc` in order.
///
/// All malformed overrides are reported together, each naming the override
/// (location [`Location::Override`]): no `=`, an empty key or key segment,
/// indexing something that is not an array, an index out of range, or
/// descending into a value that is not a table.
/// `--end-time T` is `solver.end_time=T`.
pub fn apply_overrides(doc: &mut Table, sets: &[String]) -> Result<(), SceneError> {
    let mut problems = Vec::new();
    for set in sets {
        let result = split(set).and_then(|(key, value)| {
            let path = parse_path(key)?;
            set_in_table(doc, &path.0, parse_value(value), "").map_err(|reason| (key.to_string(), reason))
        });
        if let Err((key, reason)) = result {
            problems.push(Problem {
                key: key.clone(),
                location: Location::Override(key),
                reason: format!("bad override {set:?}: {reason}"),
            });
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            origin: "command line".into(),
            problems,
        })
    }
}

/// Key paths of the well-formed overrides with their KEY text as written.
pub(crate) fn override_paths(sets: &[String]) -> Vec<(KeyPath, String)> {
    sets.iter()
        .filter_map(|set| {
            let (key, _) = split(set).ok()?;
            Some((parse_path(key).ok()?, key.to_string()))
        })
        .collect()
}

/// Splits `KEY=VALUE` at the first `=`; the key is trimmed.
fn split(set: &str) -> Result<(&str, &str), (String, String)> {
    let Some((key, value)) = set.split_once('=') else {
        return Err((set.trim().to_string(), "expected KEY=VALUE (no '=' found)".into()));
    };
    let key = key.trim();
    if key.is_empty() {
        return Err((String::new(), "empty KEY before '='".into()));
    }
    Ok((key, value))
}

/// Parses a dotted key; all-digit segments are array indices.
fn parse_path(key: &str) -> Result<KeyPath, (String, String)> {
    let mut segs = Vec::new();
    for part in key.split('.') {
        let part = part.trim();
        if part.is_empty() {
            return Err((key.to_string(), "empty segment in dotted KEY".into()));
        }
        if part.bytes().all(|b| b.is_ascii_digit()) {
            let i = part
                .parse::<usize>()
                .map_err(|_| (key.to_string(), format!("index {part} is too large")))?;
            segs.push(Seg::Index(i));
        } else {
            segs.push(Seg::Key(part.to_string()));
        }
    }
    Ok(KeyPath(segs))
}

/// A TOML value, or the raw text as a string if it is not one.
fn parse_value(text: &str) -> Value {
    let trimmed = text.trim();
    trimmed
        .parse::<Value>()
        .unwrap_or_else(|_| Value::String(trimmed.to_string()))
}

fn join(prefix: &str, seg: &Seg) -> String {
    let p = KeyPath(vec![seg.clone()]).to_string();
    match seg {
        Seg::Key(_) if !prefix.is_empty() => format!("{prefix}.{p}"),
        _ => format!("{prefix}{p}"),
    }
}

fn set_in_table(t: &mut Table, path: &[Seg], value: Value, prefix: &str) -> Result<(), String> {
    let Some((first, rest)) = path.split_first() else {
        return Err("empty KEY".into());
    };
    let Seg::Key(k) = first else {
        let what = if prefix.is_empty() { "the document" } else { prefix };
        return Err(format!("{what} is a table, not an array; cannot index it"));
    };
    let here = join(prefix, first);
    if rest.is_empty() {
        t.insert(k.clone(), value);
        return Ok(());
    }
    if !t.contains_key(k.as_str()) {
        match rest.first() {
            Some(Seg::Index(i)) => {
                return Err(format!(
                    "`{here}` does not exist, so it cannot be indexed with {i}"
                ));
            }
            _ => {
                t.insert(k.clone(), Value::Table(Table::new()));
            }
        }
    }
    match t.get_mut(k.as_str()) {
        Some(v) => set_in_value(v, rest, value, &here),
        None => Err(format!("`{here}` could not be created")),
    }
}

fn set_in_value(v: &mut Value, path: &[Seg], value: Value, prefix: &str) -> Result<(), String> {
    let Some((first, rest)) = path.split_first() else {
        *v = value;
        return Ok(());
    };
    match (v, first) {
        (Value::Table(t), Seg::Key(_)) => set_in_table(t, path, value, prefix),
        (Value::Table(_), Seg::Index(i)) => Err(format!(
            "`{prefix}` is a table, not an array; cannot index it with {i}"
        )),
        (Value::Array(a), Seg::Index(i)) => {
            let len = a.len();
            let here = join(prefix, first);
            match a.get_mut(*i) {
                Some(elem) => set_in_value(elem, rest, value, &here),
                None => Err(format!("index {i} out of range: `{prefix}` has {len} element(s)")),
            }
        }
        (Value::Array(_), Seg::Key(k)) => Err(format!(
            "`{prefix}` is an array; expected a numeric index instead of `{k}`"
        )),
        (other, seg) => Err(format!(
            "`{prefix}` is {}, not a table or array; cannot descend into `{}`",
            with_article(other.type_str()),
            KeyPath(vec![seg.clone()])
        )),
    }
}

fn with_article(word: &str) -> String {
    let vowel = word.starts_with(['a', 'e', 'i', 'o', 'u']);
    format!("{} {word}", if vowel { "an" } else { "a" })
}
