//! Height fields: terrains given as a regular grid of heights, read from a GeoTIFF (`.tif`,
//! see [`crate::geotiff`]), an ESRI ASCII grid (`.asc`) or a plain whitespace grid, and turned
//! into a triangulated [`Model`].
//!
//! # ESRI ASCII grid
//! ```text
//! ncols         33
//! nrows         33
//! xllcorner     -0.625      (or xllcenter: the centre of the lower-left sample)
//! yllcorner     -0.625      (or yllcenter)
//! cellsize      1.25        (or dx and dy: cells that are not square, as GDAL writes them)
//! NODATA_value  -9999       (optional; `nan` as GDAL writes it for float grids)
//! 3.5 3.75 ...              nrows × ncols heights, the first row is the northernmost
//! ```
//! Keywords are case-insensitive and may come in any order before the data. Heights are samples
//! at the cell centres: with `xllcorner` the centre of the lower-left cell is at
//! `xllcorner + cellsize/2` (`+ dx/2`, `+ dy/2`). Values may be split over lines freely;
//! exactly `nrows · ncols` values must follow the header.
//!
//! Missing samples: a value equal to `NODATA_value` (exactly), and `nan` (any case, with or
//! without a sign) wherever it appears. Without `NODATA_value` no number is special — as GDAL
//! reads such a grid, `-9999` is then a height — while `nan`, which is not a height at all, is
//! still a missing sample (GDAL gives it as a NaN value, which no terrain can use).
//!
//! # Plain grid
//! One row of heights per line, every row with the same number of values, the first line the
//! northernmost row (as in an ESRI grid without its header); samples are one unit apart and the
//! lower-left sample is at `(0, 0)`. Empty lines and `#` comments are ignored.
//!
//! Every number (header and heights) is read exactly ([`api::parse_rational`]): sample
//! positions `x0 + column · cellsize` are computed exactly and rounded to the nearest `f64`
//! once, heights likewise (so a height written back as its shortest decimal reads back to the
//! same `f64`), and a height equals `NODATA_value` exactly or not at all. Errors name the file, the line and the
//! column.

use api::exact::rational_to_f64_nearest;
use api::{parse_rational, Rational};
use num_traits::{Signed, Zero};
use spline2d::model::Model;
use std::path::Path;

/// Why a height field could not be read. File, line and column are 1-based.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum HeightFieldError {
    /// The file could not be read (missing, not a regular file, too large).
    #[error("{file}: {message}")]
    Io {
        /// The file.
        file: String,
        /// The underlying error.
        message: String,
    },
    /// Something wrong at a place in the text.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// The file (or the name given to the parser).
        file: String,
        /// Line of the offending item.
        line: usize,
        /// Column (in characters) of the offending item.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// Something missing at the end of the text (a header keyword, values).
    #[error("{file}: {message}")]
    Incomplete {
        /// The file.
        file: String,
        /// What is missing.
        message: String,
    },
}

/// Most samples a height field may have (about 800 MB of heights and positions).
pub const MAX_SAMPLES: usize = 50_000_000;

/// `columns × rows`, checked for overflow and against [`MAX_SAMPLES`].
fn grid_size(columns: usize, rows: usize) -> Result<usize, String> {
    columns
        .checked_mul(rows)
        .filter(|&n| n <= MAX_SAMPLES)
        .ok_or_else(|| {
            format!(
                "ncols × nrows = {columns} × {rows} is more than the limit of {MAX_SAMPLES} samples"
            )
        })
}

/// A regular grid of heights.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightField {
    /// Samples per row (west to east).
    pub columns: usize,
    /// Rows (south to north).
    pub rows: usize,
    /// Position of the south-west sample, exact.
    pub origin: [Rational; 2],
    /// Distance between neighbouring samples west to east and south to north, exact and
    /// positive (equal for square cells).
    pub cell: [Rational; 2],
    /// Heights row by row from the south-west sample (`rows · columns` entries), `None` where
    /// the file has `NODATA_value`.
    pub heights: Vec<Option<f64>>,
    /// An ESRI grid's text, where each value is in it (file order: the northernmost row
    /// first) and its `NODATA_value` as written, for writing the grid back with other heights
    /// ([`HeightField::write_esri`]).
    esri: Option<EsriText>,
    /// A GeoTIFF's sample type, raw samples and georeferencing tags, for writing it back
    /// ([`HeightField::write_geotiff`]).
    geotiff: Option<crate::geotiff::GeoTiff>,
}

/// An ESRI grid as written: its text, the range of each value (file order) and the text of its
/// `NODATA_value`, if any.
#[derive(Debug, Clone, PartialEq)]
struct EsriText {
    text: String,
    ranges: Vec<std::ops::Range<usize>>,
    nodata: Option<String>,
}

/// A token of the text with its 1-based line and column.
#[derive(Debug, Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

/// Splits `line` (number `line_number`) into whitespace-separated tokens, stopping at `#` when
/// `comments` is set.
fn tokens(line: &str, line_number: usize, comments: bool) -> Vec<Token<'_>> {
    let content = if comments {
        line.split('#').next().unwrap_or("")
    } else {
        line
    };
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte, column)
    for (column, (byte, c)) in content.char_indices().enumerate() {
        match (c.is_whitespace(), start) {
            (true, Some((from, col))) => {
                out.push(Token {
                    text: &content[from..byte],
                    line: line_number,
                    column: col + 1,
                });
                start = None;
            }
            (false, None) => start = Some((byte, column)),
            _ => {}
        }
    }
    if let Some((from, col)) = start {
        out.push(Token {
            text: &content[from..],
            line: line_number,
            column: col + 1,
        });
    }
    out
}

impl HeightField {
    /// Reads a height field from a file of at most `limit` bytes: a GeoTIFF for `.tif` and
    /// `.tiff` (see [`crate::geotiff`]), an ESRI ASCII grid when the extension is `.asc` (any
    /// case), a plain grid otherwise. Only regular text files are read
    /// (see [`api::input`]).
    pub fn read(path: &Path, limit: u64) -> Result<HeightField, HeightFieldError> {
        let file = path.display().to_string();
        if crate::geotiff::is_geotiff(path) {
            let bytes =
                api::input::read_regular_file(path, "height field", limit).map_err(|e| {
                    HeightFieldError::Io {
                        file: file.clone(),
                        message: format!("the height field {}", e.reason()),
                    }
                })?;
            return crate::geotiff::parse(&bytes, &file);
        }
        let text = api::input::read_text_file(path, "height field", limit).map_err(|e| match e
            .position()
        {
            Some((line, column)) => HeightFieldError::Syntax {
                file: file.clone(),
                line,
                column,
                message: format!("the height field {}", e.reason()),
            },
            None => HeightFieldError::Io {
                file: file.clone(),
                message: format!("the height field {}", e.reason()),
            },
        })?;
        if is_esri(path) {
            Self::parse_esri(&text, &file)
        } else {
            Self::parse_plain(&text, &file)
        }
    }

    /// Reads an ESRI ASCII grid from text; `file` names it in errors.
    pub fn parse_esri(text: &str, file: &str) -> Result<HeightField, HeightFieldError> {
        let syntax = |t: &Token<'_>, message: String| HeightFieldError::Syntax {
            file: file.to_string(),
            line: t.line,
            column: t.column,
            message,
        };
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut header: Vec<(String, Token<'_>, Token<'_>)> = Vec::new();
        let mut data: Vec<Token<'_>> = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let toks = tokens(line, number + 1, false);
            let Some(first) = toks.first() else { continue };
            // A row of data may begin with `nan`; anything else that begins with a letter is
            // a header line (unknown keywords are refused below).
            let is_keyword = first
                .text
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic())
                && !is_nan(first.text);
            if !is_keyword {
                data.extend(toks);
                continue;
            }
            if !data.is_empty() {
                return Err(syntax(
                    first,
                    format!(
                        "header keyword {:?} after the first height value (the header comes first)",
                        first.text
                    ),
                ));
            }
            let key = first.text.to_ascii_lowercase();
            match toks.as_slice() {
                [k, v] => {
                    if header.iter().any(|(existing, _, _)| *existing == key) {
                        return Err(syntax(
                            k,
                            format!("header keyword {:?} given twice", k.text),
                        ));
                    }
                    header.push((key, *k, *v));
                }
                [k] => {
                    return Err(syntax(
                        k,
                        format!("header keyword {:?} has no value", k.text),
                    ))
                }
                [_, _, extra, ..] => {
                    return Err(syntax(
                        extra,
                        format!("unexpected {:?} after the header value", extra.text),
                    ))
                }
                [] => {}
            }
        }
        let known = [
            "ncols",
            "nrows",
            "xllcorner",
            "xllcenter",
            "yllcorner",
            "yllcenter",
            "cellsize",
            "dx",
            "dy",
            "nodata_value",
        ];
        if let Some((_, k, _)) = header
            .iter()
            .find(|(key, _, _)| !known.contains(&key.as_str()))
        {
            return Err(syntax(
                k,
                format!(
                    "unknown header keyword {:?} (expected ncols, nrows, xllcorner or xllcenter, \
                     yllcorner or yllcenter, cellsize or dx and dy, NODATA_value)",
                    k.text
                ),
            ));
        }
        let find = |key: &str| header.iter().find(|(k, _, _)| k == key).map(|(_, _, v)| *v);
        let missing = |what: &str| HeightFieldError::Incomplete {
            file: file.to_string(),
            message: format!("the header has no {what}"),
        };
        let count = |key: &str| -> Result<usize, HeightFieldError> {
            let v = find(key).ok_or_else(|| missing(key))?;
            v.text
                .parse::<usize>()
                .ok()
                .filter(|n| *n >= 2)
                .ok_or_else(|| {
                    syntax(
                        &v,
                        format!("{key} must be an integer of at least 2, got {:?}", v.text),
                    )
                })
        };
        let columns = count("ncols")?;
        let rows = count("nrows")?;
        let number = |v: &Token<'_>| -> Result<Rational, HeightFieldError> {
            parse_rational(v.text).map_err(|e| HeightFieldError::Syntax {
                file: file.to_string(),
                line: v.line,
                column: v.column + e.column - 1,
                message: format!("invalid number {:?}: {}", v.text, e.message),
            })
        };
        let positive = |token: Token<'_>, key: &str| -> Result<Rational, HeightFieldError> {
            let value = number(&token)?;
            if value.is_positive() {
                Ok(value)
            } else {
                Err(syntax(&token, format!("{key} must be positive")))
            }
        };
        let cell = match (find("cellsize"), find("dx"), find("dy")) {
            (Some(c), None, None) => {
                let c = positive(c, "cellsize")?;
                [c.clone(), c]
            }
            (None, Some(dx), Some(dy)) => [positive(dx, "dx")?, positive(dy, "dy")?],
            (Some(_), Some(d), _) | (Some(_), _, Some(d)) => {
                return Err(syntax(&d, "give cellsize or dx and dy, not both".into()))
            }
            (None, Some(_), None) => return Err(missing("dy (dx is given)")),
            (None, None, Some(_)) => return Err(missing("dx (dy is given)")),
            (None, None, None) => return Err(missing("cellsize (or dx and dy)")),
        };
        let two = Rational::from_integer(2.into());
        let mut origin = Vec::with_capacity(2);
        for (axis, step) in ["x", "y"].into_iter().zip(&cell) {
            let half = step / &two;
            let corner = find(&format!("{axis}llcorner"));
            let center = find(&format!("{axis}llcenter"));
            origin.push(match (corner, center) {
                (Some(v), None) => number(&v)? + &half,
                (None, Some(v)) => number(&v)?,
                (Some(_), Some(v)) => {
                    return Err(syntax(
                        &v,
                        format!("give {axis}llcorner or {axis}llcenter, not both"),
                    ))
                }
                (None, None) => return Err(missing(&format!("{axis}llcorner or {axis}llcenter"))),
            });
        }
        let nodata_text = find("nodata_value").map(|v| v.text.to_string());
        // `None`: no value is special; `Some(None)`: NaN (only `nan` is missing).
        let nodata = match find("nodata_value") {
            Some(v) if is_nan(v.text) => Some(None),
            Some(v) => Some(Some(number(&v)?)),
            None => None,
        };
        let expected =
            grid_size(columns, rows).map_err(|message| HeightFieldError::Incomplete {
                file: file.to_string(),
                message,
            })?;
        if data.len() != expected {
            return match data.get(expected) {
                Some(extra) => Err(syntax(
                    extra,
                    format!(
                        "{} values after the header, but ncols × nrows = {columns} × {rows} = {expected}",
                        data.len()
                    ),
                )),
                None => Err(HeightFieldError::Incomplete {
                    file: file.to_string(),
                    message: format!(
                        "{} values after the header, but ncols × nrows = {columns} × {rows} = {expected}",
                        data.len()
                    ),
                }),
            };
        }
        // The file lists rows from the north; store them from the south.
        let mut heights = vec![None; expected];
        for (k, token) in data.iter().enumerate() {
            let (row_from_top, column) = (k / columns, k % columns);
            let row = rows - 1 - row_from_top;
            if is_nan(token.text) {
                continue;
            }
            let value = number(token)?;
            let missing = matches!(&nodata, Some(Some(n)) if *n == value);
            heights[row * columns + column] = (!missing).then(|| rational_to_f64_nearest(&value));
        }
        let [x, y]: [Rational; 2] = [origin[0].clone(), origin[1].clone()];
        let ranges = data
            .iter()
            .map(|t| {
                let start = t.text.as_ptr() as usize - text.as_ptr() as usize;
                start..start + t.text.len()
            })
            .collect();
        Ok(HeightField {
            columns,
            rows,
            origin: [x, y],
            cell,
            heights,
            esri: Some(EsriText {
                text: text.to_string(),
                ranges,
                nodata: nodata_text,
            }),
            geotiff: None,
        })
    }

    /// Reads a plain whitespace grid from text; `file` names it in errors.
    pub fn parse_plain(text: &str, file: &str) -> Result<HeightField, HeightFieldError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines: Vec<Vec<Token<'_>>> = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let toks = tokens(line, number + 1, true);
            if toks.is_empty() {
                continue;
            }
            if let Some(first) = lines.first() {
                if toks.len() != first.len() {
                    let at = toks.get(first.len()).copied().unwrap_or(Token {
                        text: "",
                        line: number + 1,
                        column: line.chars().count() + 1,
                    });
                    return Err(HeightFieldError::Syntax {
                        file: file.to_string(),
                        line: at.line,
                        column: at.column,
                        message: format!(
                            "this row has {} values, the first row (line {}) has {}",
                            toks.len(),
                            first[0].line,
                            first.len()
                        ),
                    });
                }
            }
            lines.push(toks);
        }
        let columns = lines.first().map_or(0, Vec::len);
        let rows = lines.len();
        if columns < 2 || rows < 2 {
            return Err(HeightFieldError::Incomplete {
                file: file.to_string(),
                message: format!(
                    "a height field needs at least 2 rows of 2 values, found {rows} rows of {columns}"
                ),
            });
        }
        let size = grid_size(columns, rows).map_err(|message| HeightFieldError::Incomplete {
            file: file.to_string(),
            message,
        })?;
        let mut heights = vec![None; size];
        for (row_from_top, line) in lines.iter().enumerate() {
            let row = rows - 1 - row_from_top;
            for (column, token) in line.iter().enumerate() {
                let value = parse_rational(token.text).map_err(|e| HeightFieldError::Syntax {
                    file: file.to_string(),
                    line: token.line,
                    column: token.column + e.column - 1,
                    message: format!("invalid height {:?}: {}", token.text, e.message),
                })?;
                heights[row * columns + column] = Some(rational_to_f64_nearest(&value));
            }
        }
        Ok(HeightField {
            columns,
            rows,
            origin: [Rational::zero(), Rational::zero()],
            cell: [
                Rational::from_integer(1.into()),
                Rational::from_integer(1.into()),
            ],
            heights,
            esri: None,
            geotiff: None,
        })
    }

    /// The exact position of the sample in `column` (from the west) and `row` (from the south).
    pub fn position_exact(&self, column: usize, row: usize) -> [Rational; 2] {
        let step = |axis: usize, k: usize| &self.cell[axis] * Rational::from_integer(k.into());
        [
            &self.origin[0] + step(0, column),
            &self.origin[1] + step(1, row),
        ]
    }

    /// The sample position rounded to `f64` (once, from the exact value).
    pub fn position(&self, column: usize, row: usize) -> [f64; 2] {
        self.position_exact(column, row)
            .map(|c| rational_to_f64_nearest(&c))
    }

    /// The ESRI grid this field was read from, with `heights` (row by row from the south-west,
    /// as [`HeightField::heights`]) in place of its own: the header, layout and every value
    /// whose height did not change as written (byte for byte), a changed height as the
    /// shortest decimal that reads back to it, a sample that loses its data as the grid's
    /// `NODATA_value` as written (`nan` without one, which GDAL and this reader take as
    /// missing). `None` for other height fields, or when `heights` has another length or a
    /// height that is not finite.
    pub fn write_esri(&self, heights: &[Option<f64>]) -> Option<String> {
        let esri = self.esri.as_ref()?;
        if heights.len() != self.heights.len() {
            return None;
        }
        let (text, ranges) = (&esri.text, &esri.ranges);
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        for (k, range) in ranges.iter().enumerate() {
            let (row_from_top, column) = (k / self.columns, k % self.columns);
            let sample = (self.rows - 1 - row_from_top) * self.columns + column;
            let replacement = match (self.heights[sample], heights[sample]) {
                (None, None) => continue,
                (Some(old), Some(new)) if old.to_bits() == new.to_bits() => continue,
                (_, Some(new)) if new.is_finite() => {
                    let new = if new == 0.0 { 0.0 } else { new };
                    format!("{new}")
                }
                (Some(_), None) => esri.nodata.clone().unwrap_or_else(|| "nan".into()),
                _ => return None,
            };
            out.push_str(&text[at..range.start]);
            out.push_str(&replacement);
            at = range.end;
        }
        out.push_str(&text[at..]);
        Some(out)
    }

    /// A height field read from a GeoTIFF (see [`crate::geotiff::parse`]).
    pub(crate) fn from_geotiff(
        columns: usize,
        rows: usize,
        origin: [Rational; 2],
        cell: [Rational; 2],
        heights: Vec<Option<f64>>,
        geotiff: crate::geotiff::GeoTiff,
    ) -> HeightField {
        HeightField {
            columns,
            rows,
            origin,
            cell,
            heights,
            esri: None,
            geotiff: Some(geotiff),
        }
    }

    /// The GeoTIFF this field was read from with `heights` (as [`HeightField::heights`]) in
    /// place of its own; `None` for other height fields.
    pub fn write_geotiff(&self, heights: &[Option<f64>]) -> Option<Result<Vec<u8>, String>> {
        let geotiff = self.geotiff.as_ref()?;
        Some(geotiff.write(self.columns, &self.heights, heights))
    }

    /// Number of samples without data.
    pub fn missing(&self) -> usize {
        self.heights.iter().filter(|h| h.is_none()).count()
    }

    /// The terrain as a model: one vertex `(x, y, height)` per sample with data, numbered row by
    /// row from the south-west, and two counter-clockwise triangles per grid cell (split by the
    /// rising diagonal), leaving out triangles with a corner without data. A full
    /// `n × m` grid gives `n·m` vertices and `2(n−1)(m−1)` triangles.
    pub fn to_model(&self) -> Model {
        let mut index = vec![usize::MAX; self.heights.len()];
        let mut positions = Vec::with_capacity(self.heights.len());
        // Exact positions per column and row, rounded once.
        let xs: Vec<f64> = (0..self.columns).map(|c| self.position(c, 0)[0]).collect();
        let ys: Vec<f64> = (0..self.rows).map(|r| self.position(0, r)[1]).collect();
        for (row, y) in ys.iter().enumerate() {
            for (column, x) in xs.iter().enumerate() {
                let k = row * self.columns + column;
                if let Some(h) = self.heights[k] {
                    index[k] = positions.len();
                    positions.push([*x, *y, h]);
                }
            }
        }
        let mut triangles = Vec::with_capacity(2 * (self.rows - 1) * (self.columns - 1));
        let at = |column: usize, row: usize| index[row * self.columns + column];
        for row in 0..self.rows - 1 {
            for column in 0..self.columns - 1 {
                let (sw, se) = (at(column, row), at(column + 1, row));
                let (nw, ne) = (at(column, row + 1), at(column + 1, row + 1));
                for tri in [[sw, se, ne], [sw, ne, nw]] {
                    if tri.iter().all(|&v| v != usize::MAX) {
                        triangles.push(tri);
                    }
                }
            }
        }
        Model {
            positions,
            triangles,
        }
    }
}

/// True for `nan` in any case, with or without a sign (as GDAL and C libraries write NaN).
fn is_nan(token: &str) -> bool {
    token
        .strip_prefix(['-', '+'])
        .unwrap_or(token)
        .eq_ignore_ascii_case("nan")
}

/// True for a path with the extension `.asc` (any case).
pub fn is_esri(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("asc"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    const SMALL: &str = "ncols 3\nNROWS 2\nxllcorner -0.625\nyllcenter 10\ncellsize 1.25\n\
                         NODATA_value -9999\n1 2 3\n4.5 -9999 0.1\n";

    #[test]
    fn reads_an_esri_grid_exactly() {
        let field = HeightField::parse_esri(SMALL, "small.asc").expect("valid");
        assert_eq!((field.columns, field.rows), (3, 2));
        // xllcorner -0.625 + 1.25/2 = 0 exactly.
        assert_eq!(field.origin, [q(0, 1), q(10, 1)]);
        assert_eq!(field.cell, [q(5, 4), q(5, 4)]);
        // Rows are stored from the south: the last line of the file is row 0.
        assert_eq!(
            field.heights,
            vec![Some(4.5), None, Some(0.1), Some(1.0), Some(2.0), Some(3.0)]
        );
        assert_eq!(field.position(2, 1), [2.5, 11.25]);
        assert_eq!(field.missing(), 1);
        let model = field.to_model();
        assert_eq!(model.positions.len(), 5);
        // Of the 4 triangles of the 2 cells, the 3 touching the missing sample are left out.
        assert_eq!(model.triangles.len(), 1);
        assert_eq!(model.positions[0], [0.0, 10.0, 4.5]);
    }

    #[test]
    fn a_full_grid_has_two_triangles_per_cell() {
        let mut text =
            String::from("ncols 33\nnrows 33\nxllcenter 0\nyllcenter 0\ncellsize 1.25\n");
        for r in 0..33 {
            let row: Vec<String> = (0..33).map(|c| format!("{}.5", r + c)).collect();
            text.push_str(&row.join(" "));
            text.push('\n');
        }
        let model = HeightField::parse_esri(&text, "t.asc")
            .expect("valid")
            .to_model();
        assert_eq!(model.positions.len(), 1089);
        assert_eq!(model.triangles.len(), 2048);
        assert_eq!(model.positions[1088], [40.0, 40.0, 32.5]);
    }

    /// Grids as GDAL writes them: `NODATA_value nan` and rows of `nan` (a row may begin with
    /// one), `dx`/`dy` for cells that are not square; without `NODATA_value`, `-9999` is a
    /// height and `nan` still a missing sample.
    #[test]
    fn reads_gdal_grids_with_nan_and_rectangular_cells() {
        let text = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 10\ndx 2\ndy 0.5\nNODATA_value nan\n\
                    nan NaN -nan\n1 2.5 -9999\n";
        let field = HeightField::parse_esri(text, "gdal.asc").expect("read");
        assert_eq!(field.cell, [q(2, 1), q(1, 2)]);
        assert_eq!(
            field.heights,
            vec![Some(1.0), Some(2.5), Some(-9999.0), None, None, None]
        );
        assert_eq!(field.position(1, 1), [3.0, 10.75]);
        let plain = text
            .replace("NODATA_value nan\n", "")
            .replace("nan NaN -nan", "7 8 nan");
        let field = HeightField::parse_esri(&plain, "gdal.asc").expect("read");
        assert_eq!(field.heights[3..], [Some(7.0), Some(8.0), None]);
        assert_eq!(field.heights[2], Some(-9999.0));
    }

    /// An ESRI grid written back: unchanged, byte for byte; with new heights, only those
    /// values change; a plain grid cannot be written.
    #[test]
    fn esri_grids_are_written_back_with_their_own_text() {
        let field = HeightField::parse_esri(SMALL, "s.asc").expect("read");
        assert_eq!(field.write_esri(&field.heights).as_deref(), Some(SMALL));
        let mut heights = field.heights.clone();
        // The south-west sample (4.5 in the file's last row) and the north-east one (3).
        heights[0] = Some(4.75);
        heights[5] = Some(-0.0);
        assert_eq!(
            field.write_esri(&heights).as_deref(),
            Some(SMALL.replace("1 2 3\n4.5", "1 2 0\n4.75").as_str())
        );
        // A sample may gain data and lose it (written as the grid's NODATA_value as written,
        // `nan` in a grid without one); a height that is not finite cannot be written.
        heights[1] = Some(1.0);
        heights[2] = None;
        assert_eq!(
            field.write_esri(&heights).as_deref(),
            Some(
                SMALL
                    .replace("1 2 3\n4.5 -9999 0.1", "1 2 0\n4.75 1 -9999")
                    .as_str()
            )
        );
        let unmarked = HeightField::parse_esri(&SMALL.replace("NODATA_value -9999\n", ""), "u.asc")
            .expect("read");
        let mut lost = unmarked.heights.clone();
        lost[0] = None;
        assert_eq!(
            unmarked.write_esri(&lost).as_deref(),
            Some(
                SMALL
                    .replace("NODATA_value -9999\n", "")
                    .replace("4.5", "nan")
                    .as_str()
            )
        );
        heights[3] = Some(f64::NAN);
        assert_eq!(field.write_esri(&heights), None, "not finite");
        let plain = HeightField::parse_plain("1 2\n3 4\n", "p.txt").expect("read");
        assert_eq!(plain.write_esri(&plain.heights), None);
    }

    #[test]
    fn reads_a_plain_grid() {
        let field =
            HeightField::parse_plain("# heights\n1 2\n\n3 4 # south row\n", "g.txt").expect("ok");
        assert_eq!(
            field.heights,
            vec![Some(3.0), Some(4.0), Some(1.0), Some(2.0)]
        );
        assert_eq!(field.position(1, 1), [1.0, 1.0]);
        assert_eq!(field.to_model().triangles, vec![[0, 1, 3], [0, 3, 2]]);
    }

    #[test]
    fn malformed_grids_name_file_line_and_column() {
        let header = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
        for (text, expected) in [
            (
                format!("{header}1 2\n3 4x\n"),
                "bad.asc:7:4: invalid number \"4x\"",
            ),
            (
                format!("{header}1 2\n3\n"),
                "bad.asc: 3 values after the header, but ncols × nrows = 2 × 2 = 4",
            ),
            (format!("{header}1 2\n3 4 5\n"), "bad.asc:7:5: 5 values"),
            (
                format!("{header}1 2\ncellsize 2\n3 4\n"),
                "bad.asc:7:1: header keyword \"cellsize\" after",
            ),
            (
                header.replace("nrows 2", "nrows 1"),
                "bad.asc:2:7: nrows must be an integer of at least 2",
            ),
            (
                header.replace("cellsize 1", "cellsize -1"),
                "bad.asc:5:10: cellsize must be positive",
            ),
            (
                header.replace("cellsize 1", "cellsize"),
                "bad.asc:5:1: header keyword \"cellsize\" has no value",
            ),
            (
                header.replace("cellsize 1\n", ""),
                "bad.asc: the header has no cellsize (or dx and dy)",
            ),
            (
                header.replace("ncols 2", "ncols 2\nncols 3"),
                "bad.asc:2:1: header keyword \"ncols\" given twice",
            ),
            (
                header.replace("xllcorner 0", "xllcorner 0\nxllcenter 1"),
                "bad.asc:4:11: give xllcorner or xllcenter",
            ),
            (
                header.replace("yllcorner 0", "dz 1"),
                "bad.asc:4:1: unknown header keyword \"dz\"",
            ),
            (
                header.replace("cellsize 1", "dx 1"),
                "bad.asc: the header has no dy (dx is given)",
            ),
            (
                header.replace("cellsize 1", "cellsize 1\ndy 2"),
                "bad.asc:6:4: give cellsize or dx and dy, not both",
            ),
            (
                header.replace("cellsize 1", "dx 1\ndy 0"),
                "bad.asc:6:4: dy must be positive",
            ),
            (
                format!("{header}1 2\n3 nanx\n"),
                "bad.asc:7:3: invalid number \"nanx\"",
            ),
            (
                header.replace("yllcorner 0", ""),
                "bad.asc: the header has no yllcorner or yllcenter",
            ),
            (
                header.replace("xllcorner 0", "xllcorner 0 1"),
                "bad.asc:3:13: unexpected \"1\"",
            ),
            (
                header.replace("xllcorner 0", "xllcorner 1/0"),
                "bad.asc:3:13: invalid number \"1/0\"",
            ),
        ] {
            let error = HeightField::parse_esri(&text, "bad.asc").expect_err(&text);
            assert!(
                error.to_string().starts_with(expected),
                "{error}\nexpected: {expected}"
            );
        }
        for (text, expected) in [
            (
                "1 2\n3 4 5\n",
                "bad.txt:2:5: this row has 3 values, the first row (line 1) has 2",
            ),
            ("1 2 3\n4 5\n", "bad.txt:2:4: this row has 2 values"),
            ("1 2\n3 -\n", "bad.txt:2:4: invalid height \"-\""),
            ("1 2\n3 1.5.2\n", "bad.txt:2:6: invalid height \"1.5.2\""),
            ("1 2\n", "bad.txt: a height field needs at least 2 rows"),
        ] {
            let error = HeightField::parse_plain(text, "bad.txt").expect_err(text);
            assert!(
                error.to_string().starts_with(expected),
                "{error}\nexpected: {expected}"
            );
        }
        let missing = HeightField::read(
            Path::new("no/such/terrain.asc"),
            api::input::DEFAULT_MAX_INPUT_BYTES,
        )
        .expect_err("missing");
        assert!(
            missing
                .to_string()
                .starts_with("no/such/terrain.asc: the height field cannot be read"),
            "{missing}"
        );
        assert!(is_esri(Path::new("a/B.ASC")) && !is_esri(Path::new("a.txt")));
    }
}
