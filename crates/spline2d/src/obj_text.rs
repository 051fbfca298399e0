//! Wavefront OBJ text as both OBJ readers of this crate see it: the exact reference-mesh reader
//! ([`crate::mesh_io::parse_obj`]) and the float model reader ([`crate::model::parse_model`]).
//!
//! They share the lexical layer: statements line by line with comments cut off
//! ([`statements`]), whitespace-separated tokens with their character columns ([`tokens`]),
//! and face corners `i`, `i/t`, `i//n`, `i/t/n` with the vertex index resolved
//! ([`FaceCorner`]). What each reader accepts beyond that, and the messages it gives, stay its
//! own: the mesh reader is strict (texture and normal indices must be integers, every error is
//! located by column), the model reader lenient (only the vertex index is read).

use std::str::CharIndices;

/// The lines of OBJ text as `(line number, statement)`: numbered from 1, a leading byte order
/// mark removed, a comment (`#` to the end of the line) cut off. Blank statements are kept (so
/// the numbering is the file's).
pub(crate) fn statements(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.lines().enumerate().map(|(number, line)| {
        let statement = match line.find('#') {
            Some(hash) => &line[..hash],
            None => line,
        };
        (number + 1, statement)
    })
}

/// The whitespace-separated tokens of a line, each with the 1-based column (in characters) of
/// its first character, without allocating.
pub(crate) fn tokens(line: &str) -> Tokens<'_> {
    Tokens {
        line,
        chars: line.char_indices(),
        column: 0,
    }
}

/// The iterator of [`tokens`].
#[derive(Debug, Clone)]
pub(crate) struct Tokens<'a> {
    line: &'a str,
    chars: CharIndices<'a>,
    /// Column of the last character read.
    column: usize,
}

impl<'a> Iterator for Tokens<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<(usize, &'a str)> {
        let (start, column) = loop {
            let (byte, c) = self.chars.next()?;
            self.column += 1;
            if !c.is_whitespace() {
                break (byte, self.column);
            }
        };
        for (byte, c) in self.chars.by_ref() {
            self.column += 1;
            if c.is_whitespace() {
                return Some((column, &self.line[start..byte]));
            }
        }
        Some((column, &self.line[start..]))
    }
}

/// A face corner as written: `i`, `i/t`, `i//n` or `i/t/n` (vertex, texture and normal
/// indices), split at its first slash.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FaceCorner<'a> {
    /// The vertex index as written (before the first `/`).
    pub(crate) index: &'a str,
    /// What follows the first `/`, if anything: the texture and normal indices.
    references: Option<&'a str>,
}

/// Why the vertex index of a face corner names no vertex at all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum IndexError {
    /// Not `[+-]digits`.
    NotAnInteger,
    /// `0`: OBJ indices start at 1 (and `-1` is the last vertex defined).
    Zero,
    /// An integer beyond `i64`, positive or `negative`.
    TooLarge {
        /// Whether it is written with a minus sign.
        negative: bool,
    },
}

impl<'a> FaceCorner<'a> {
    /// Splits a corner token at its first `/`.
    pub(crate) fn new(token: &'a str) -> Self {
        match token.split_once('/') {
            Some((index, references)) => FaceCorner {
                index,
                references: Some(references),
            },
            None => FaceCorner {
                index: token,
                references: None,
            },
        }
    }

    /// Whether the texture and normal indices are well formed: at most two, each empty or an
    /// integer (`i/t`, `i//n`, `i/t/n`). The readers ignore their values.
    pub(crate) fn references_are_integers(&self) -> bool {
        self.references.is_none_or(|rest| {
            let mut parts = rest.split('/');
            parts.clone().count() <= 2 && parts.all(|p| p.is_empty() || is_integer_text(p))
        })
    }

    /// The 0-based vertex the index names when `defined` vertices precede the face: `i − 1`
    /// for a positive index (it may name a vertex defined later, or none: the caller checks
    /// once all vertices are known), `defined + i` for a negative one (relative; below 0 when
    /// it reaches before the first vertex).
    pub(crate) fn vertex(&self, defined: usize) -> Result<i64, IndexError> {
        // Checked first: `i64` parsing reports an overflow before a bad character after it.
        if !is_integer_text(self.index) {
            return Err(IndexError::NotAnInteger);
        }
        match self.index.parse::<i64>() {
            Ok(0) => Err(IndexError::Zero),
            Ok(i) if i > 0 => Ok(i - 1),
            // A vertex count fits an i64 (it is bounded by the input size).
            Ok(i) => Ok(defined as i64 + i),
            Err(_) => Err(IndexError::TooLarge {
                negative: self.index.starts_with('-'),
            }),
        }
    }
}

impl FaceCorner<'_> {
    /// The 0-based normal the corner names when `defined` normals precede the face (`i/t/n`,
    /// `i//n`; a negative index is relative), `None` when it names none; an error when the
    /// normal index is not an integer, is 0 or reaches before the first normal. Whether it
    /// names a normal defined at all is the caller's check.
    pub(crate) fn normal_index(&self, defined: usize) -> Option<Result<usize, IndexError>> {
        let (_, normal) = self.references?.split_once('/')?;
        if normal.is_empty() {
            return None;
        }
        Some(match FaceCorner::new(normal).vertex(defined) {
            Ok(i) => usize::try_from(i).map_err(|_| IndexError::Zero),
            Err(e) => Err(e),
        })
    }
}

/// True for `[+-]digits`.
fn is_integer_text(text: &str) -> bool {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_have_character_columns() {
        fn all(line: &str) -> Vec<(usize, &str)> {
            tokens(line).collect()
        }
        assert_eq!(all("  é b\tc "), vec![(3, "é"), (5, "b"), (7, "c")]);
        assert!(all("   ").is_empty());
        assert_eq!(all("f 1/2/3"), vec![(1, "f"), (3, "1/2/3")]);
    }

    #[test]
    fn statements_lose_comments_and_the_byte_order_mark() {
        let all: Vec<_> = statements("\u{feff}v 1 2 # a\n# all comment\r\nf 1 2 3").collect();
        assert_eq!(all, vec![(1, "v 1 2 "), (2, ""), (3, "f 1 2 3")]);
    }

    #[test]
    fn corners_resolve_relative_and_absolute_indices() {
        let vertex = |token: &str, defined| FaceCorner::new(token).vertex(defined);
        assert_eq!(vertex("3", 0), Ok(2));
        assert_eq!(vertex("+3/1", 0), Ok(2));
        assert_eq!(vertex("-1//4", 5), Ok(4));
        assert_eq!(vertex("-6", 5), Ok(-1));
        assert_eq!(vertex("0", 5), Err(IndexError::Zero));
        assert_eq!(vertex("x/1", 5), Err(IndexError::NotAnInteger));
        assert_eq!(vertex("", 5), Err(IndexError::NotAnInteger));
        assert_eq!(
            vertex("99999999999999999999+1", 5),
            Err(IndexError::NotAnInteger)
        );
        assert_eq!(
            vertex("99999999999999999999", 5),
            Err(IndexError::TooLarge { negative: false })
        );
        assert_eq!(
            vertex("-99999999999999999999", 5),
            Err(IndexError::TooLarge { negative: true })
        );
        for (token, valid) in [
            ("1", true),
            ("1/2", true),
            ("1//3", true),
            ("1/2/3", true),
            ("1/", true),
            ("1/2/3/4", false),
            ("1/a", false),
            ("1//-", false),
        ] {
            assert_eq!(
                FaceCorner::new(token).references_are_integers(),
                valid,
                "{token}"
            );
        }
    }
}
