//! Problems found in a scene and where they are: [`Problem`] with its [`Location`] (a line
//! and column of the file, or the `--set` override), [`SceneError`], the key paths
//! (`fluid_box[1].max`) that name them, and the index from key paths to spans of the text.

use std::fmt;
use std::ops::Range;
use std::path::PathBuf;

use toml::de::{DeTable, DeValue};

use super::*;

/// Where a [`Problem`] is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    /// 1-based line and column (in characters) in the scene text.
    Line {
        /// 1-based line.
        line: usize,
        /// 1-based column, counted in characters.
        column: usize,
    },
    /// The value comes from the command-line override `--set KEY=...`; holds KEY.
    Override(String),
    /// No position is known (e.g. a missing top-level key).
    Unknown,
}

/// One thing wrong with a scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// Key path such as `particles.spacing` or `fluid_box[1].max`; empty for
    /// TOML syntax errors that are not inside any key.
    pub key: String,
    /// Where the key is.
    pub location: Location,
    /// What is wrong.
    pub reason: String,
}

impl Problem {
    /// Renders the problem as `origin:LINE:COL: key: reason` (or
    /// `origin: --set KEY: key: reason`, or `origin: key: reason`).
    pub fn render(&self, origin: &str) -> String {
        let key = if self.key.is_empty() {
            String::new()
        } else {
            format!("{}: ", self.key)
        };
        match &self.location {
            Location::Line { line, column } => {
                format!("{origin}:{line}:{column}: {key}{}", self.reason)
            }
            Location::Override(k) => format!("{origin}: --set {k}: {key}{}", self.reason),
            Location::Unknown => format!("{origin}: {key}{}", self.reason),
        }
    }
}

pub(super) fn render_problems(origin: &str, problems: &[Problem]) -> String {
    if problems.is_empty() {
        return format!("{origin}: invalid scene");
    }
    let lines: Vec<String> = problems.iter().map(|p| p.render(origin)).collect();
    lines.join("\n")
}

/// Errors from loading, validating or generating a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read (missing, a directory, unreadable).
    #[error("cannot read scene file {}: {source}", path.display())]
    Io {
        /// The path given.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The scene file is larger than [`MAX_SCENE_BYTES`] (refused before parsing).
    #[error(
        "scene file {} is too large: {}, the limit is {} bytes (16 MiB); a scene is a few kilobytes of TOML",
        path.display(),
        size.map_or_else(|| format!("more than {MAX_SCENE_BYTES} bytes could be read from it"), |n| format!("{n} bytes")),
        MAX_SCENE_BYTES
    )]
    TooLarge {
        /// The path given.
        path: PathBuf,
        /// Its metadata length [bytes], or `None` when the length was only found by reading
        /// (a device or a pipe, whose metadata length is 0).
        size: Option<u64>,
    },
    /// The scene is malformed or invalid; one line per problem.
    #[error("{}", render_problems(origin, problems))]
    Invalid {
        /// File name (or `--set`, `generate`) shown in messages.
        origin: String,
        /// Everything found wrong, in discovery order (never empty).
        problems: Vec<Problem>,
    },
    /// [`generate()`] was asked for a dimension other than the scene's.
    #[error("scene is {scene}-dimensional but {requested}-dimensional particles were requested")]
    Dimension {
        /// `dimension` of the scene.
        scene: usize,
        /// The `D` requested.
        requested: usize,
    },
}

impl SceneError {
    /// The problems of an [`SceneError::Invalid`] error (empty otherwise).
    pub fn problems(&self) -> &[Problem] {
        match self {
            SceneError::Invalid { problems, .. } => problems,
            _ => &[],
        }
    }
}

/// `message` with every run of more than 15 digits (a huge number the TOML reader spelled out)
/// in exponent form, so a problem stays one readable line.
pub(super) fn short_numbers(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let digits = rest[start..]
            .find(|c: char| !c.is_ascii_digit())
            .map_or(rest.len() - start, |n| n);
        let run = &rest[start..start + digits];
        if digits > 15 {
            out.push_str(&format!("{}.{}e{}", &run[..1], &run[1..4], digits - 1));
            rest = &rest[start + digits..];
            // Drop a trailing ".0" of a spelled-out float.
            if let Some(r) = rest.strip_prefix(".0")
                && !r.starts_with(|c: char| c.is_ascii_digit())
            {
                rest = r;
            }
        } else {
            out.push_str(run);
            rest = &rest[start + digits..];
        }
    }
    out.push_str(rest);
    out
}

/// Converts a TOML / serde error on `text` into a [`Problem`]. The key path
/// comes from the error span; the location from the span when `use_span`
/// (and the error is not a missing field), else from `relocate(path)`.
pub(super) fn toml_problem(
    e: &toml::de::Error,
    text: &str,
    index: &SpanIndex,
    relocate: &dyn Fn(&KeyPath) -> Location,
    use_span: bool,
) -> Problem {
    let message = e.message().trim();
    let span = e.span();
    let mut path = span.as_ref().map(|s| index.path_at(s)).unwrap_or_default();
    let missing = missing_field(message);
    if let Some(field) = missing {
        path.0.push(Seg::Key(field.to_string()));
    }
    let location = match &span {
        Some(s) if use_span && missing.is_none() => {
            let (line, column) = line_col(text, s.start);
            Location::Line { line, column }
        }
        _ if path.0.is_empty() => Location::Unknown,
        _ => relocate(&path),
    };
    let reason = if message.is_empty() {
        "invalid TOML".to_string()
    } else {
        short_numbers(message)
    };
    Problem {
        key: path.to_string(),
        location,
        reason,
    }
}

/// The field name in serde's "missing field `x`" message.
pub(super) fn missing_field(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("missing field `")?;
    rest.split('`').next()
}

/// Location of `path`: an override when an override key is a prefix of it,
/// else its position (or that of its longest present prefix) in the file.
pub(super) fn locate(
    path: &KeyPath,
    text: &str,
    index: &SpanIndex,
    overrides: &[(KeyPath, String)],
) -> Location {
    if let Some((_, raw)) = overrides.iter().find(|(o, _)| path.starts_with(o)) {
        return Location::Override(raw.clone());
    }
    if let Some(span) = index.span_of(path) {
        let (line, column) = line_col(text, span.start);
        return Location::Line { line, column };
    }
    if let Some((_, raw)) = overrides.iter().find(|(o, _)| o.starts_with(path)) {
        return Location::Override(raw.clone());
    }
    Location::Unknown
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let (mut line, mut column) = (1, 1);
    for (i, c) in text.char_indices() {
        if i >= offset {
            break;
        }
        if c == '\n' {
            line += 1;
            column = 1;
        } else {
            column += 1;
        }
    }
    (line, column)
}

/// One step of a key path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Seg {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

/// A key path such as `fluid_box[1].max`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct KeyPath(pub(crate) Vec<Seg>);

impl KeyPath {
    /// Path of a single top-level key.
    pub(crate) fn key(k: &str) -> Self {
        KeyPath(vec![Seg::Key(k.to_string())])
    }

    /// This path extended by a key.
    pub(crate) fn k(&self, k: &str) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_string()));
        p
    }

    /// This path extended by an index.
    pub(crate) fn i(&self, i: usize) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }

    fn starts_with(&self, prefix: &KeyPath) -> bool {
        self.0.starts_with(&prefix.0)
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (n, seg) in self.0.iter().enumerate() {
            match seg {
                Seg::Key(k) if n == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(i) => write!(f, "[{i}]")?,
            }
        }
        Ok(())
    }
}

/// Byte spans of every key and value in a TOML document.
pub(crate) struct SpanIndex {
    /// (path, span of the key or array element, span of the value).
    entries: Vec<(KeyPath, Range<usize>, Range<usize>)>,
}

impl SpanIndex {
    /// Indexes `text`, recovering what it can from malformed TOML.
    pub(crate) fn build(text: &str) -> Self {
        let (doc, _errors) = DeTable::parse_recoverable(text);
        let mut entries = Vec::new();
        index_table(doc.get_ref(), &KeyPath::default(), &mut entries);
        SpanIndex { entries }
    }

    /// Span of `path`'s key (or array element), or of its longest indexed prefix.
    pub(crate) fn span_of(&self, path: &KeyPath) -> Option<Range<usize>> {
        (0..=path.0.len()).rev().find_map(|n| {
            let prefix = path.0.get(..n)?;
            self.entries
                .iter()
                .find(|(p, _, _)| p.0 == prefix && !p.0.is_empty())
                .map(|(_, key, _)| key.clone())
        })
    }

    /// The deepest path whose key or value span contains the whole `span`
    /// (the root for an empty span at the start, as for missing top-level keys).
    fn path_at(&self, span: &Range<usize>) -> KeyPath {
        if span.is_empty() && span.start == 0 {
            return KeyPath::default();
        }
        let hit = |r: &Range<usize>| r.start <= span.start && span.end <= r.end;
        self.entries
            .iter()
            .filter(|(_, k, v)| hit(k) || hit(v))
            .max_by_key(|(p, _, _)| p.0.len())
            .map(|(p, _, _)| p.clone())
            .unwrap_or_default()
    }
}

pub(super) fn index_table(
    table: &DeTable<'_>,
    prefix: &KeyPath,
    out: &mut Vec<(KeyPath, Range<usize>, Range<usize>)>,
) {
    for (key, value) in table.iter() {
        let path = prefix.k(key.get_ref());
        // Position of a key: its start, or the `[header]` for a table.
        let (k, v) = (key.span(), value.span());
        let start = k.start.min(v.start);
        out.push((path.clone(), start..k.end.max(start), v));
        index_value(value.get_ref(), &path, out);
    }
}

pub(super) fn index_value(
    value: &DeValue<'_>,
    path: &KeyPath,
    out: &mut Vec<(KeyPath, Range<usize>, Range<usize>)>,
) {
    match value {
        DeValue::Table(t) => index_table(t, path, out),
        DeValue::Array(a) => {
            for (i, elem) in a.iter().enumerate() {
                let p = path.i(i);
                out.push((p.clone(), elem.span(), elem.span()));
                index_value(elem.get_ref(), &p, out);
            }
        }
        _ => {}
    }
}
