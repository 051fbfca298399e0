//! Reading the RON text a host forwards to a source (its configuration, an operation, an
//! output request) with errors that carry a position.
//!
//! A run file embeds each source's configuration, operations and outputs as RON fragments; the
//! host forwards the fragment's text as written. [`from_ron`] parses it straight into the
//! source's own serde types (no detour through `ron::Value`, which would lose positions and
//! let duplicate map keys overwrite each other) and puts the line and column *within the
//! fragment* into [`SourceError::at`]; the host translates that into run-file coordinates
//! with [`TextPosition::within`]. Unknown fields are refused by the source's types
//! (`#[serde(deny_unknown_fields)]`); [`unique_map`] refuses duplicate map keys.
//!
//! Optional fields may be written without `Some(..)` (RON's `implicit_some` extension), as
//! everywhere in run files. Values a schema cannot check alone are checked with messages
//! naming their field: counts ([`bounded_count`]) and output file names
//! ([`check_output_file_name`]).

use crate::source::SourceError;
use serde::de::{self, DeserializeOwned, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

/// A 1-based line and column (in characters) in a text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct TextPosition {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
}

impl TextPosition {
    /// The start of a text.
    pub const START: TextPosition = TextPosition { line: 1, column: 1 };

    /// This position (in a fragment) as a position in the text the fragment starts at
    /// `origin` of: lines after the first keep their column, the first line is shifted.
    pub fn within(self, origin: TextPosition) -> TextPosition {
        if self.line <= 1 {
            TextPosition {
                line: origin.line,
                column: origin.column + self.column.saturating_sub(1),
            }
        } else {
            TextPosition {
                line: origin.line + self.line - 1,
                column: self.column,
            }
        }
    }

    /// The position just after `text` when `text` starts at [`TextPosition::START`]: the
    /// position of byte `text.len()` of a longer text that starts with `text`.
    pub fn after(text: &str) -> TextPosition {
        let line = 1 + text.matches('\n').count();
        let last_line = text.rsplit('\n').next().unwrap_or(text);
        TextPosition {
            line,
            column: 1 + last_line.chars().count(),
        }
    }
}

impl fmt::Display for TextPosition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// The RON options of run files and of the fragments forwarded to sources.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// Parses RON text into `T`. On error the message is `"{what}: {parser's message}"` and
/// [`SourceError::at`] the position within `text`.
pub fn from_ron<T: DeserializeOwned>(text: &str, what: &str) -> Result<T, SourceError> {
    ron_options().from_str(text).map_err(|e| {
        SourceError::new(format!("{what}: {}", e.code)).with_position(TextPosition {
            line: e.position.line,
            column: e.position.col,
        })
    })
}

/// `deserialize_with` for maps whose keys must be unique: a key written twice is an error
/// (naming the key) instead of the last value silently winning.
pub fn unique_map<'de, D, K, V>(deserializer: D) -> Result<BTreeMap<K, V>, D::Error>
where
    D: Deserializer<'de>,
    K: Deserialize<'de> + Ord + fmt::Debug,
    V: Deserialize<'de>,
{
    struct UniqueMapVisitor<K, V>(PhantomData<(K, V)>);
    impl<'de, K, V> Visitor<'de> for UniqueMapVisitor<K, V>
    where
        K: Deserialize<'de> + Ord + fmt::Debug,
        V: Deserialize<'de>,
    {
        type Value = BTreeMap<K, V>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a map with distinct keys")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<K>()? {
                if out.contains_key(&key) {
                    return Err(de::Error::custom(format!("{key:?} is given twice")));
                }
                let value = map.next_value::<V>()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }
    deserializer.deserialize_map(UniqueMapVisitor(PhantomData))
}

/// `deserialize_with` for a present optional field: `Some(value)` without RON's `Some(..)`
/// wrapper (kept for sources whose fields predate [`ron_options`]'s `implicit_some`).
pub fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    deserializer: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(deserializer).map(Some)
}

/// A count written in a configuration (`steps: 4`, `degree: 5`), refused with a message naming
/// the field and the limit when it is negative, not an integer, or above `max`.
pub fn bounded_count(value: u64, field: &str, min: u64, max: u64) -> Result<usize, String> {
    if value < min || value > max {
        return Err(format!(
            "{field} is {value}, but must be between {min} and {max}"
        ));
    }
    usize::try_from(value).map_err(|_| format!("{field} {value} does not fit this machine"))
}

/// An output file name written in a configuration (`picture: "worm.svg"`), refused with a
/// message naming the field unless it is a plain file name (no directories, not hidden, so the
/// host writes it into the output directory) ending in `.{ext}` (any case) after a non-empty
/// stem.
pub fn check_output_file_name(name: &str, field: &str, ext: &str) -> Result<(), String> {
    let plain = !name.is_empty()
        && !name.starts_with('.')
        && !name.contains(['/', '\\'])
        && Path::new(name).file_name().is_some_and(|f| f == name);
    if !plain {
        return Err(format!(
            "{field} {name:?} must be a plain file name (no directories), written to the output directory"
        ));
    }
    let has_ext = Path::new(name)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext));
    let stem_ok = Path::new(name).file_stem().is_some_and(|s| !s.is_empty());
    if !has_ext || !stem_ok {
        return Err(format!(
            "{field} {name:?} must end in .{ext} (the file is written as {})",
            ext.to_uppercase()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Sample {
        #[serde(default, deserialize_with = "unique_map")]
        map: BTreeMap<String, u32>,
        #[serde(default)]
        count: Option<u32>,
    }

    #[test]
    fn positions_are_within_the_fragment_and_translate_to_the_file() {
        let err = from_ron::<Sample>("(\n  map: {},\n  cuont: 3,\n)", "phi config")
            .expect_err("unknown field");
        assert!(err.message.starts_with("phi config: "), "{}", err.message);
        assert!(err.message.contains("cuont"), "{}", err.message);
        let at = err.at.expect("position");
        assert_eq!(at.line, 3);
        let origin = TextPosition {
            line: 10,
            column: 20,
        };
        assert_eq!(at.within(origin).line, 12);
        assert_eq!(at.within(origin).column, at.column);
        let first = TextPosition { line: 1, column: 5 };
        assert_eq!(
            first.within(origin),
            TextPosition {
                line: 10,
                column: 24
            }
        );
    }

    #[test]
    fn duplicate_keys_are_refused_with_their_position() {
        let err = from_ron::<Sample>("(map: {\"a\": 1,\n \"a\": 2})", "x").expect_err("dup");
        assert!(
            err.message.contains("\"a\" is given twice"),
            "{}",
            err.message
        );
        assert_eq!(err.at.map(|p| p.line), Some(2));
        let ok: Sample = from_ron("(map: {\"a\": 1, \"b\": 2}, count: 3)", "x").expect("valid");
        assert_eq!(ok.map.len(), 2);
        assert_eq!(ok.count, Some(3));
    }

    #[test]
    fn after_counts_characters() {
        assert_eq!(TextPosition::after(""), TextPosition::START);
        assert_eq!(
            TextPosition::after("ab\nçd"),
            TextPosition { line: 2, column: 3 }
        );
    }

    #[test]
    fn counts_are_bounded() {
        assert_eq!(bounded_count(4, "steps", 1, 10), Ok(4));
        let message = bounded_count(0, "steps", 1, 10).expect_err("zero");
        assert_eq!(message, "steps is 0, but must be between 1 and 10");
        assert!(bounded_count(u64::MAX, "steps", 1, 10).is_err());
    }

    #[test]
    fn output_file_names_are_plain_with_the_extension() {
        assert_eq!(check_output_file_name("a.svg", "picture", "svg"), Ok(()));
        assert_eq!(check_output_file_name("A.SVG", "picture", "svg"), Ok(()));
        for (name, needle) in [
            ("../a.svg", "plain file name"),
            ("dir/a.svg", "plain file name"),
            (".svg", "plain file name"),
            ("", "plain file name"),
            ("a.png", "must end in .svg (the file is written as SVG)"),
            ("a", "must end in .svg"),
        ] {
            let message = check_output_file_name(name, "picture", "svg").expect_err(name);
            assert!(message.contains(needle), "{name}: {message}");
            assert!(message.starts_with("picture "), "{message}");
        }
    }
}
