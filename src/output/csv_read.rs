//! The one CSV reader: every CSV file the program reads back (its own logs, `sph sweep`'s
//! table, the experimental reference records) goes through [`CsvFile::read`], on the `csv`
//! crate (RFC 4180: quoted fields, doubled quotes, CRLF line ends, a UTF-8 byte-order mark).
//!
//! A file is a header row and data rows. Columns are found by header name, never by position
//! ([`CsvFile::column`]). Fields are trimmed of surrounding blanks and empty lines are skipped.
//! Every row must have as many fields as the header. Bad input is a [`CsvReadError`] that names
//! the file, the line (counted from 1; the header is line 1) and the column; nothing here
//! panics on input.

use std::path::{Path, PathBuf};

/// The largest CSV file read \[bytes\]: 1 GiB. A run's own logs grow with its steps and
/// probes (a probe row of 20 values every step for 10⁶ steps is about 200 MB); reference
/// records and wave-maker series are kilobytes to megabytes. The table is held in memory while
/// it is read, so a bound keeps a mistaken path from exhausting it.
pub const MAX_CSV_BYTES: u64 = 1 << 30;

/// Errors reading a CSV file; each names the file, and the line and column where there is one.
#[derive(Debug, thiserror::Error)]
pub enum CsvReadError {
    /// The file was not read: missing, unreadable, not a regular file, or larger than
    /// [`MAX_CSV_BYTES`] (`crate::bounded_read`).
    #[error(transparent)]
    File(#[from] crate::bounded_read::BoundedReadError),
    /// The file has no header row (it is empty or blank).
    #[error("{}:1: no header row", path.display())]
    NoHeader {
        /// The file being read.
        path: PathBuf,
    },
    /// The header row has no column of this name.
    #[error("{}:1: no column `{column}` in the header ({})", path.display(), header.join(","))]
    MissingColumn {
        /// The file being read.
        path: PathBuf,
        /// The column that was looked for.
        column: String,
        /// The columns the header has.
        header: Vec<String>,
    },
    /// A cell that must hold a number does not.
    #[error(
        "{}:{line}: column {position} `{column}`: `{text}` is not a number",
        path.display()
    )]
    BadNumber {
        /// The file being read.
        path: PathBuf,
        /// Line number, counted from 1 (the header is line 1).
        line: u64,
        /// Name of the column.
        column: String,
        /// Position of the column, counted from 1.
        position: usize,
        /// The offending cell, as written (trimmed).
        text: String,
    },
    /// A row has more or fewer fields than the header.
    #[error(
        "{}:{line}: {found} fields, the header has {expected} (first {} column: {position})",
        path.display(),
        if found < expected { "missing" } else { "extra" }
    )]
    Ragged {
        /// The file being read.
        path: PathBuf,
        /// Line number, counted from 1.
        line: u64,
        /// Number of columns in the header.
        expected: usize,
        /// Number of fields in the row.
        found: usize,
        /// The first column missing from the row, or the first extra field, counted from 1.
        position: usize,
    },
    /// Two header columns share a name: columns are found by name, so which one is meant is
    /// ambiguous.
    #[error("{}:1: columns {first} and {second} are both named `{column}`", path.display())]
    DuplicateColumn {
        /// The file being read.
        path: PathBuf,
        /// The name.
        column: String,
        /// The positions of its first two columns, counted from 1.
        first: usize,
        /// See `first`.
        second: usize,
    },
    /// The text is not CSV the reader can parse (invalid UTF-8, say).
    #[error("{}:{line}: {reason}", path.display())]
    Malformed {
        /// The file being read.
        path: PathBuf,
        /// Line number, counted from 1.
        line: u64,
        /// What is wrong.
        reason: String,
    },
}

/// A CSV file read whole: its header and data rows, each row with its line number.
#[derive(Debug, Clone)]
pub struct CsvFile {
    path: PathBuf,
    header: Vec<String>,
    rows: Vec<csv::StringRecord>,
    /// The line each row starts on (counted from 1).
    lines: Vec<u64>,
}

impl CsvFile {
    /// Reads `path` and checks its shape (a header, every row as long as the header); the
    /// values are checked when they are asked for.
    ///
    /// # Errors
    /// [`CsvReadError::File`] (only a regular file of at most [`MAX_CSV_BYTES`] is read),
    /// [`CsvReadError::NoHeader`], [`CsvReadError::DuplicateColumn`], [`CsvReadError::Ragged`],
    /// [`CsvReadError::Malformed`].
    pub fn read(path: &Path) -> Result<Self, CsvReadError> {
        let bytes = crate::bounded_read::read_regular_file(path, MAX_CSV_BYTES)?;
        Self::parse(path, &bytes)
    }

    /// Parses `bytes` as the contents of the file `path` (named in errors), as [`Self::read`].
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Self, CsvReadError> {
        let mut lines = LineCounter::new(bytes);
        let malformed = |e: csv::Error, line: u64| CsvReadError::Malformed {
            path: path.to_path_buf(),
            line,
            reason: e.to_string(),
        };
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(bytes);
        let mut records = reader.records();
        let header: Vec<String> = loop {
            match records.next() {
                None => {
                    return Err(CsvReadError::NoHeader {
                        path: path.to_path_buf(),
                    });
                }
                Some(record) => {
                    let record = record.map_err(|e| malformed(e, 1))?;
                    if record.iter().any(|f| !f.is_empty()) {
                        let mut names: Vec<String> = record.iter().map(String::from).collect();
                        if let Some(first) = names.first_mut() {
                            *first = first.trim_start_matches('\u{feff}').trim().to_string();
                        }
                        break names;
                    }
                }
            }
        };
        for (second, name) in header.iter().enumerate() {
            if let Some(first) = header[..second].iter().position(|h| h == name && !h.is_empty()) {
                return Err(CsvReadError::DuplicateColumn {
                    path: path.to_path_buf(),
                    column: name.clone(),
                    first: first + 1,
                    second: second + 1,
                });
            }
        }
        let mut rows = Vec::new();
        let mut row_lines = Vec::new();
        let mut last_line = 1;
        for record in records {
            let record = record.map_err(|e| malformed(e, last_line + 1))?;
            let line = lines.line_of(&record);
            last_line = line;
            // A line of blanks only (the reader skips truly empty lines itself).
            if record.len() == 1 && record[0].is_empty() {
                continue;
            }
            if record.len() != header.len() {
                return Err(CsvReadError::Ragged {
                    path: path.to_path_buf(),
                    line,
                    expected: header.len(),
                    found: record.len(),
                    position: record.len().min(header.len()) + 1,
                });
            }
            rows.push(record);
            row_lines.push(line);
        }
        Ok(CsvFile {
            path: path.to_path_buf(),
            header,
            rows,
            lines: row_lines,
        })
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The column names, in file order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// Number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether the file has no data rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Index of the column named `name`.
    ///
    /// # Errors
    /// [`CsvReadError::MissingColumn`].
    pub fn column(&self, name: &str) -> Result<usize, CsvReadError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| CsvReadError::MissingColumn {
                path: self.path.clone(),
                column: name.to_string(),
                header: self.header.clone(),
            })
    }

    /// Line number of data row `row` in the file (counted from 1; the header is line 1).
    pub fn line(&self, row: usize) -> u64 {
        self.lines.get(row).copied().unwrap_or(0)
    }

    /// The text of column `column` in data row `row` (trimmed); empty when either is out of
    /// range.
    pub fn text(&self, row: usize, column: usize) -> &str {
        self.rows.get(row).and_then(|r| r.get(column)).unwrap_or_default()
    }

    /// Column `column` of data row `row` as a number (`NaN` and `inf` as Rust reads them, which
    /// is how the writers write non-finite values).
    ///
    /// # Errors
    /// [`CsvReadError::BadNumber`] for text that is not a number, an empty cell included.
    pub fn number(&self, row: usize, column: usize) -> Result<f64, CsvReadError> {
        let text = self.text(row, column);
        text.parse::<f64>().map_err(|_| self.bad_number(row, column))
    }

    /// As [`Self::number`], and the number must be finite (reference data).
    pub fn finite_number(&self, row: usize, column: usize) -> Result<f64, CsvReadError> {
        match self.number(row, column) {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.bad_number(row, column)),
        }
    }

    /// As [`Self::number`], with an empty cell read as `None` (a value that was not measured).
    pub fn optional_number(&self, row: usize, column: usize) -> Result<Option<f64>, CsvReadError> {
        if self.text(row, column).is_empty() {
            Ok(None)
        } else {
            self.number(row, column).map(Some)
        }
    }

    /// Every value of column `column`, in row order ([`Self::number`]).
    pub fn numbers(&self, column: usize) -> Result<Vec<f64>, CsvReadError> {
        (0..self.len()).map(|r| self.number(r, column)).collect()
    }

    /// The points `(x, y)` of columns `x` and `y` over the rows for which `keep` holds (given
    /// the row index).
    pub fn points(
        &self,
        x: usize,
        y: usize,
        keep: impl Fn(usize) -> bool,
    ) -> Result<Vec<(f64, f64)>, CsvReadError> {
        (0..self.len())
            .filter(|&r| keep(r))
            .map(|r| Ok((self.number(r, x)?, self.number(r, y)?)))
            .collect()
    }

    fn bad_number(&self, row: usize, column: usize) -> CsvReadError {
        CsvReadError::BadNumber {
            path: self.path.clone(),
            line: self.line(row),
            column: self.header.get(column).cloned().unwrap_or_default(),
            position: column + 1,
            text: self.text(row, column).to_string(),
        }
    }
}

/// Line numbers of records, counted from the bytes: the `csv` crate's own line count skips
/// lines after blank lines and CRLF ends, and its byte position of a record is where it began
/// reading, before the line ends it skips.
struct LineCounter<'a> {
    bytes: &'a [u8],
    /// A byte offset and the line it lies on; records come in file order.
    at: (usize, u64),
}

impl<'a> LineCounter<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: (0, 1) }
    }

    /// The line (from 1) on which `record`'s first field starts.
    fn line_of(&mut self, record: &csv::StringRecord) -> u64 {
        let mut start = record.position().map_or(self.at.0, |p| p.byte() as usize);
        start = start.clamp(self.at.0, self.bytes.len());
        while start < self.bytes.len() && matches!(self.bytes[start], b'\r' | b'\n') {
            start += 1;
        }
        let newlines = self.bytes[self.at.0..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.at = (start, self.at.1 + newlines as u64);
        self.at.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<CsvFile, CsvReadError> {
        CsvFile::parse(Path::new("x.csv"), text.as_bytes())
    }

    #[test]
    fn quotes_blank_lines_bom_and_crlf() {
        let f = parse("\u{feff}t_s, solid ,fx_N\r\n\r\n0.5,\"a,b \"\"c\"\"\",1e-3\r\n\n1,b,2\n").unwrap();
        assert_eq!(f.header(), ["t_s", "solid", "fx_N"]);
        assert_eq!(f.len(), 2);
        assert_eq!(f.text(0, 1), "a,b \"c\"");
        assert_eq!(f.number(0, 2).unwrap(), 1e-3);
        assert_eq!((f.line(0), f.line(1)), (3, 5));
        // A quoted field over two lines, then a blank line: the next record is on line 5.
        let f = parse("a,b\n1,\"x\ny\"\r\n\r\n2,3\n").unwrap();
        assert_eq!(f.text(0, 1), "x\ny");
        assert_eq!((f.line(0), f.line(1)), (2, 5));
    }

    #[test]
    fn errors_name_line_and_column() {
        let f = parse("a,b\n1,2\n3,x\n").unwrap();
        let e = f.number(1, 1).unwrap_err().to_string();
        assert_eq!(e, "x.csv:3: column 2 `b`: `x` is not a number");
        let e = parse("a,b,c\n1,2,3\n4\n").unwrap_err().to_string();
        assert_eq!(e, "x.csv:3: 1 fields, the header has 3 (first missing column: 2)");
        let e = f.column("c").unwrap_err().to_string();
        assert_eq!(e, "x.csv:1: no column `c` in the header (a,b)");
        assert!(matches!(parse("\n \n"), Err(CsvReadError::NoHeader { .. })));
        let e = parse("t_s,p_Pa,x,p_Pa\n0,1,2,3\n").unwrap_err().to_string();
        assert_eq!(e, "x.csv:1: columns 2 and 4 are both named `p_Pa`");
    }
}
