//! Changing one field of a RON text (a source's configuration, an output request) and keeping
//! the rest exactly as written: comments, layout and every other value. What the editor does
//! when a person switches a spline's continuity or loads another mesh or model: the saved
//! session then shows the user's own text with one value changed.
//!
//! Written by hand rather than by parsing into `ron::Value` and printing it again: a printed
//! value loses comments and struct names (`ron` prints a struct as a map, which a struct's
//! deserializer refuses), and the host does not know a plugin's schema to print it properly.

/// A field's name and value as found in the text: byte ranges.
struct FieldAt {
    /// The value's text, from its first character to its last.
    value: std::ops::Range<usize>,
    /// The innermost `(` around the field: the struct that holds it.
    holder_open: usize,
}

/// Walks the code of `text`: calls `visit(index, byte)` for each byte outside comments and
/// strings, and for the two quotes of each string (`"` for a raw string's ends too), skipping
/// comments and what strings hold.
fn walk_code(text: &str, mut visit: impl FnMut(usize, u8)) {
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                // RON's block comments nest.
                let mut depth = 0usize;
                while i < bytes.len() {
                    if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        i += 2;
                    } else if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                continue;
            }
            b'"' => {
                visit(i, b);
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                // The closing quote.
                visit(i.min(bytes.len().saturating_sub(1)), b'"');
                i += 1;
                continue;
            }
            b'r' if raw_string_hashes(&bytes[i..]).is_some() => {
                let hashes = raw_string_hashes(&bytes[i..]).unwrap_or(0);
                visit(i, b'"');
                let close: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                i += 2 + hashes;
                while i < bytes.len() && !bytes[i..].starts_with(&close) {
                    i += 1;
                }
                i += close.len();
                visit(i.min(bytes.len()).saturating_sub(1), b'"');
                continue;
            }
            _ => visit(i, b),
        }
        i += 1;
    }
}

/// `r"`, `r#"`, `r##"`…: the number of hashes when `bytes` starts a raw string.
fn raw_string_hashes(bytes: &[u8]) -> Option<usize> {
    let hashes = bytes[1..].iter().take_while(|&&b| b == b'#').count();
    (bytes.get(1 + hashes) == Some(&b'"')).then_some(hashes)
}

/// Every occurrence of `field:` (the identifier as a whole word, outside comments and
/// strings) with its value's range and the struct that holds it.
fn find_fields(text: &str, field: &str) -> Vec<FieldAt> {
    let bytes = text.as_bytes();
    // Code bytes in order; a string is its two quotes.
    let mut code: Vec<(usize, u8)> = Vec::new();
    walk_code(text, |i, b| code.push((i, b)));
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut found = Vec::new();
    let mut opens: Vec<usize> = Vec::new();
    let mut k = 0;
    while k < code.len() {
        let (i, b) = code[k];
        match b {
            b'(' | b'[' | b'{' => opens.push(i),
            b')' | b']' | b'}' => {
                opens.pop();
            }
            _ => {}
        }
        let starts_word = ident(b) && (k == 0 || !ident(code[k - 1].1) || code[k - 1].0 + 1 != i);
        if starts_word && text[i..].starts_with(field) {
            let end = i + field.len();
            let whole = bytes.get(end).is_none_or(|&c| !ident(c));
            let after = text[end..].trim_start();
            let colon = after.starts_with(':') && !after.starts_with("::");
            if whole && colon {
                let value_start = end + (text[end..].len() - after.len()) + 1;
                let skipped = text[value_start..].len() - text[value_start..].trim_start().len();
                let start = value_start + skipped;
                let value_end = value_end(text, start);
                let holder_open = opens
                    .iter()
                    .rev()
                    .copied()
                    .find(|&o| bytes[o] == b'(')
                    .unwrap_or(0);
                found.push(FieldAt {
                    value: start..value_end,
                    holder_open,
                });
            }
        }
        k += 1;
    }
    found
}

/// The end (exclusive) of the value starting at `start`: the first `,` or closing bracket at
/// its own depth, outside strings and comments, with trailing spaces left out.
fn value_end(text: &str, start: usize) -> usize {
    let mut depth = 0usize;
    let mut end = text.len();
    let mut last_code = start;
    let mut done = false;
    walk_code(&text[start..], |i, b| {
        if done {
            return;
        }
        let at = start + i;
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' if depth == 0 => {
                end = at;
                done = true;
                return;
            }
            b')' | b']' | b'}' => depth -= 1,
            b',' if depth == 0 => {
                end = at;
                done = true;
                return;
            }
            _ => {}
        }
        if !b.is_ascii_whitespace() {
            last_code = at;
        }
    });
    if done {
        last_code + 1
    } else {
        end.min(last_code + 1)
    }
}

/// `text` with the value of `field` replaced by `value` (RON text). The field must appear
/// once; when it does not appear, it is added first in the struct that holds `holder` (which
/// must appear once), as `field: value, `. Comments and every other character are kept.
pub fn set_field(text: &str, field: &str, value: &str, holder: &str) -> Result<String, String> {
    let found = find_fields(text, field);
    match found.as_slice() {
        [one] => Ok(format!(
            "{}{value}{}",
            &text[..one.value.start],
            &text[one.value.end..]
        )),
        [] => {
            let holders = find_fields(text, holder);
            let [at] = holders.as_slice() else {
                return Err(format!(
                    "the configuration has no field {field:?} and {} fields {holder:?} to place it beside",
                    holders.len()
                ));
            };
            let open = at.holder_open;
            if text.as_bytes().get(open) != Some(&b'(') {
                return Err(format!("the field {holder:?} is not inside a struct"));
            }
            Ok(format!(
                "{}{field}: {value}, {}",
                &text[..=open],
                &text[open + 1..]
            ))
        }
        more => Err(format!(
            "the configuration has {} fields {field:?}: which one to change is unclear",
            more.len()
        )),
    }
}

/// The value of `field` as written (its text), when it appears exactly once.
pub fn field_text<'a>(text: &'a str, field: &str) -> Option<&'a str> {
    match find_fields(text, field).as_slice() {
        [one] => Some(&text[one.value.clone()]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_is_replaced_and_everything_else_kept() {
        let text =
            r#"(mesh: "meshes/worm.obj", /* smoothness: 7 */ degree: 5, smoothness: 1) // C1"#;
        assert_eq!(
            set_field(text, "smoothness", "0", "mesh").expect("set"),
            r#"(mesh: "meshes/worm.obj", /* smoothness: 7 */ degree: 5, smoothness: 0) // C1"#
        );
        assert_eq!(
            set_field(text, "mesh", "\"new.obj\"", "mesh").expect("set"),
            r#"(mesh: "new.obj", /* smoothness: 7 */ degree: 5, smoothness: 1) // C1"#
        );
        assert_eq!(field_text(text, "degree"), Some("5"));
    }

    #[test]
    fn nested_values_strings_and_words_that_contain_the_name_are_handled() {
        let text = "(spline: (mesh: (vertices: [(0, 0), (1, 0)], triangles: [(0, 1, 2)]), degree: 5),\n  premesh: \"mesh: x\", meshes: 2)";
        let changed = set_field(text, "mesh", "\"m.obj\"", "mesh").expect("set");
        assert_eq!(
            changed,
            "(spline: (mesh: \"m.obj\", degree: 5),\n  premesh: \"mesh: x\", meshes: 2)"
        );
        // Absent: added beside the holder, in its struct.
        assert_eq!(
            set_field(&changed, "smoothness", "2", "mesh").expect("set"),
            "(spline: (smoothness: 2, mesh: \"m.obj\", degree: 5),\n  premesh: \"mesh: x\", meshes: 2)"
        );
        // Raw strings and block comments hide what they hold.
        let raw = r##"(a: r#"smoothness: 1"#, /* (smoothness: 3) */ smoothness: 4)"##;
        assert_eq!(
            set_field(raw, "smoothness", "0", "a").expect("set"),
            r##"(a: r#"smoothness: 1"#, /* (smoothness: 3) */ smoothness: 0)"##
        );
    }

    #[test]
    fn unclear_texts_are_refused() {
        let twice = "(a: (smoothness: 1), b: (smoothness: 2))";
        assert!(set_field(twice, "smoothness", "0", "a")
            .expect_err("twice")
            .contains("2 fields"));
        assert!(set_field("(degree: 5)", "smoothness", "0", "mesh")
            .expect_err("no holder")
            .contains("no field"));
        assert_eq!(field_text(twice, "smoothness"), None);
    }
}
