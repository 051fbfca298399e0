//! Tokenizer and parser of hand-written linear equations such as `2 p1 = p2 + 3`.
//!
//! The parser knows nothing about parameters: it returns the names with the columns they were
//! found at, and the caller resolves them. Columns are 1-based and counted in characters of the
//! equation text as written (leading whitespace included).

use api::Integer;
use num_traits::Zero;
use std::fmt;

/// Why an equation could not be read: a message about the character at `column`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EquationError {
    /// 1-based column, in characters, of the offending token (one past the end for a missing
    /// token).
    pub column: usize,
    /// What was wrong there.
    pub message: String,
}

impl EquationError {
    fn new(column: usize, message: impl Into<String>) -> Self {
        EquationError {
            column,
            message: message.into(),
        }
    }
}

/// A parameter name as written in an equation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NameRef {
    /// The name.
    pub name: String,
    /// 1-based column of its first character.
    pub column: usize,
}

/// An equation `Σ c_j name_j = rhs`, with every term moved left and every constant moved right.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ParsedEquation {
    /// Terms in order of appearance (right-hand terms negated); a name may occur several times.
    pub terms: Vec<(NameRef, Integer)>,
    /// The constants of the right side minus those of the left side.
    pub rhs: Integer,
}

/// The message of every non-integer number in an equation.
pub(crate) const NON_INTEGER: &str = "coefficients must be integers; multiply the equation through";

#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    Name(String),
    Int(Integer),
    Plus,
    Minus,
    Star,
    Equals,
    End,
}

#[derive(Debug, Clone, PartialEq, Eq)]
struct Token {
    tok: Tok,
    column: usize,
    /// The text of the token, for messages.
    text: String,
}

impl fmt::Display for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.tok {
            Tok::End => f.write_str("the end of the equation"),
            _ => write!(f, "'{}'", self.text),
        }
    }
}

fn is_name_start(c: char) -> bool {
    c.is_ascii_alphabetic() || c == '_'
}

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '.'
}

/// Whether `name` matches `[A-Za-z_][A-Za-z0-9_.]*`.
pub fn is_valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(is_name_start) && chars.all(is_name_char)
}

/// Splits an equation into tokens, ending with [`Tok::End`].
fn tokenize(text: &str) -> Result<Vec<Token>, EquationError> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    // The run of characters that look like part of a (non-integer) number, for messages.
    let number_run = |from: usize| -> String {
        chars[from..]
            .iter()
            .take_while(|c| c.is_ascii_digit() || **c == '.' || **c == '/')
            .collect()
    };
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let single = |tok: Tok| Token {
            tok,
            column,
            text: c.to_string(),
        };
        match c {
            '+' => tokens.push(single(Tok::Plus)),
            '-' => tokens.push(single(Tok::Minus)),
            '*' => tokens.push(single(Tok::Star)),
            '=' => tokens.push(single(Tok::Equals)),
            '/' => {
                return Err(EquationError::new(
                    column,
                    format!("division is not allowed: {NON_INTEGER}"),
                ))
            }
            '.' if chars.get(i + 1).is_some_and(char::is_ascii_digit) => {
                return Err(EquationError::new(
                    column,
                    format!("{NON_INTEGER} (found '{}')", number_run(i)),
                ))
            }
            '0'..='9' => {
                let start = i;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
                if matches!(chars.get(i), Some('.') | Some('/')) {
                    return Err(EquationError::new(
                        column,
                        format!("{NON_INTEGER} (found '{}')", number_run(start)),
                    ));
                }
                let digits: String = chars[start..i].iter().collect();
                let value: Integer = digits
                    .parse()
                    .map_err(|_| EquationError::new(column, "expected an integer"))?;
                tokens.push(Token {
                    tok: Tok::Int(value),
                    column,
                    text: digits,
                });
                continue;
            }
            c if is_name_start(c) => {
                let start = i;
                while i < chars.len() && is_name_char(chars[i]) {
                    i += 1;
                }
                let name: String = chars[start..i].iter().collect();
                tokens.push(Token {
                    tok: Tok::Name(name.clone()),
                    column,
                    text: name,
                });
                continue;
            }
            other => {
                return Err(EquationError::new(
                    column,
                    format!(
                        "unexpected character '{other}': expected a parameter name \
                         ([A-Za-z_][A-Za-z0-9_.]*), an integer, '+', '-', '*' or '='"
                    ),
                ))
            }
        }
        i += 1;
    }
    tokens.push(Token {
        tok: Tok::End,
        column: chars.len() + 1,
        text: String::new(),
    });
    Ok(tokens)
}

struct Parser {
    tokens: Vec<Token>,
    pos: usize,
    out: ParsedEquation,
}

impl Parser {
    fn peek(&self) -> &Token {
        // The last token is always `End` and is never consumed past.
        &self.tokens[self.pos.min(self.tokens.len() - 1)]
    }

    fn next(&mut self) -> Token {
        let token = self.peek().clone();
        if self.pos < self.tokens.len() - 1 {
            self.pos += 1;
        }
        token
    }

    /// One term with an optional sign; `side` is `1` on the left and `-1` on the right.
    fn term(&mut self, mut sign: i32, side: i32) -> Result<(), EquationError> {
        match self.peek().tok {
            Tok::Plus => {
                self.next();
            }
            Tok::Minus => {
                self.next();
                sign = -sign;
            }
            _ => {}
        }
        let token = self.next();
        let factor = Integer::from(sign * side);
        match token.tok {
            Tok::Name(name) => {
                self.out.terms.push((
                    NameRef {
                        name,
                        column: token.column,
                    },
                    factor,
                ));
                Ok(())
            }
            Tok::Int(value) => {
                let starred = self.peek().tok == Tok::Star;
                if starred {
                    self.next();
                }
                let after = self.peek().clone();
                match after.tok {
                    Tok::Name(name) => {
                        self.next();
                        self.out.terms.push((
                            NameRef {
                                name,
                                column: after.column,
                            },
                            factor * value,
                        ));
                        Ok(())
                    }
                    _ if starred => Err(EquationError::new(
                        after.column,
                        format!("expected a parameter name after '*', found {after}"),
                    )),
                    _ => {
                        // A constant: moved to the right-hand side.
                        self.out.rhs -= factor * value;
                        Ok(())
                    }
                }
            }
            _ => Err(EquationError::new(
                token.column,
                format!("expected a parameter name or a number, found {token}"),
            )),
        }
    }

    /// The terms of one side, up to `=` (left) or the end (right).
    fn side(&mut self, side: i32) -> Result<(), EquationError> {
        self.term(1, side)?;
        loop {
            let token = self.peek().clone();
            match token.tok {
                Tok::Plus => {
                    self.next();
                    self.term(1, side)?;
                }
                Tok::Minus => {
                    self.next();
                    self.term(-1, side)?;
                }
                Tok::Equals if side == 1 => return Ok(()),
                Tok::End if side == -1 => return Ok(()),
                Tok::End => {
                    return Err(EquationError::new(
                        token.column,
                        "expected '=': an equation has exactly one '='",
                    ))
                }
                Tok::Equals => {
                    return Err(EquationError::new(
                        token.column,
                        "found a second '=': an equation has exactly one '='",
                    ))
                }
                Tok::Star => {
                    return Err(EquationError::new(
                        token.column,
                        format!(
                            "expected '+', '-' or {}, found '*' (write the integer coefficient \
                             before the name, as in '3 p1' or '3*p1')",
                            if side == 1 { "'='" } else { "the end" }
                        ),
                    ))
                }
                _ => {
                    return Err(EquationError::new(
                        token.column,
                        format!(
                            "expected '+', '-' or {}, found {token}",
                            if side == 1 { "'='" } else { "the end" }
                        ),
                    ))
                }
            }
        }
    }
}

/// Reads one equation: terms and integer constants on both sides of exactly one `=`.
pub fn parse_equation(text: &str) -> Result<ParsedEquation, EquationError> {
    let mut parser = Parser {
        tokens: tokenize(text)?,
        pos: 0,
        out: ParsedEquation {
            terms: Vec::new(),
            rhs: Integer::zero(),
        },
    };
    parser.side(1)?;
    // Consume the '='.
    parser.next();
    parser.side(-1)?;
    Ok(parser.out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn int(n: i64) -> Integer {
        Integer::from(n)
    }

    /// `(name, column, coefficient)` triples and the right-hand side.
    fn parsed(text: &str) -> (Vec<(String, usize, Integer)>, Integer) {
        let eq = parse_equation(text).unwrap_or_else(|e| panic!("{text:?}: {e:?}"));
        (
            eq.terms
                .into_iter()
                .map(|(n, c)| (n.name, n.column, c))
                .collect(),
            eq.rhs,
        )
    }

    fn error(text: &str) -> (usize, String) {
        let e = parse_equation(text).expect_err(text);
        (e.column, e.message)
    }

    #[test]
    fn reads_terms_and_constants_on_both_sides() {
        let (terms, rhs) = parsed("p1 + p2 - p3 = 0");
        assert_eq!(
            terms,
            vec![
                ("p1".into(), 1, int(1)),
                ("p2".into(), 6, int(1)),
                ("p3".into(), 11, int(-1)),
            ]
        );
        assert_eq!(rhs, int(0));

        let (terms, rhs) = parsed("2 p1 = p2 + 3");
        assert_eq!(
            terms,
            vec![("p1".into(), 3, int(2)), ("p2".into(), 8, int(-1))]
        );
        assert_eq!(rhs, int(3));

        // Constants on the left move right; whitespace is optional; '*' is optional.
        let (terms, rhs) = parsed("3*x+4-2y=-7+z");
        assert_eq!(
            terms,
            vec![
                ("x".into(), 3, int(3)),
                ("y".into(), 8, int(-2)),
                ("z".into(), 13, int(-1)),
            ]
        );
        assert_eq!(rhs, int(-11));

        // A leading sign, a sign after an operator, names with dots and underscores.
        let (terms, rhs) = parsed("  -other.x_1 - -2 * _y = +5");
        assert_eq!(
            terms,
            vec![("other.x_1".into(), 4, int(-1)), ("_y".into(), 21, int(2)),]
        );
        assert_eq!(rhs, int(5));

        // Constants only.
        let (terms, rhs) = parsed("1 = 2");
        assert!(terms.is_empty());
        assert_eq!(rhs, int(1));
    }

    #[test]
    fn reads_arbitrary_size_integers() {
        let big = "123456789012345678901234567890";
        let (terms, rhs) = parsed(&format!("{big} a = -{big}0"));
        let value: Integer = big.parse().expect("digits");
        assert_eq!(terms, vec![("a".into(), 32, value.clone())]);
        assert_eq!(rhs, -value * int(10));
    }

    #[test]
    fn reports_exact_columns() {
        assert_eq!(
            error("p1 + * p2 = 0"),
            (
                6,
                "expected a parameter name or a number, found '*'".to_string()
            )
        );
        assert_eq!(
            error("3 p3 - 5 p4 7"),
            (13, "expected '+', '-' or '=', found '7'".to_string())
        );
        assert_eq!(
            error("p1 + p2"),
            (
                8,
                "expected '=': an equation has exactly one '='".to_string()
            )
        );
        assert_eq!(
            error("a = b = c"),
            (
                7,
                "found a second '=': an equation has exactly one '='".to_string()
            )
        );
        assert_eq!(
            error("= p1"),
            (
                1,
                "expected a parameter name or a number, found '='".to_string()
            )
        );
        assert_eq!(
            error("p1 ="),
            (
                5,
                "expected a parameter name or a number, found the end of the equation".to_string()
            )
        );
        assert_eq!(
            error(""),
            (
                1,
                "expected a parameter name or a number, found the end of the equation".to_string()
            )
        );
        assert_eq!(
            error("2 * = 1"),
            (
                5,
                "expected a parameter name after '*', found '='".to_string()
            )
        );
        assert_eq!(
            error("2 * 3 = 1"),
            (
                5,
                "expected a parameter name after '*', found '3'".to_string()
            )
        );
        assert_eq!(error("p1 * 2 = 1").0, 4);
        assert!(error("p1 * 2 = 1").1.contains("before the name"));
        assert_eq!(
            error("a - - - b = 0"),
            (
                7,
                "expected a parameter name or a number, found '-'".to_string()
            )
        );
        assert_eq!(error("a b = 0").0, 3);
    }

    #[test]
    fn rejects_non_integer_coefficients() {
        let (column, message) = error("p1 + 0.5 p2 = 0");
        assert_eq!(column, 6);
        assert_eq!(
            message,
            "coefficients must be integers; multiply the equation through (found '0.5')"
        );
        assert_eq!(error("x = .5").0, 5);
        assert!(error("x = .5").1.starts_with(NON_INTEGER));
        assert_eq!(error("x = 1/2").0, 5);
        assert!(error("x = 1/2").1.contains(NON_INTEGER));
        assert_eq!(error("x / 2 = 1").0, 3);
        assert!(error("x / 2 = 1").1.starts_with("division is not allowed"));
        assert_eq!(error("3. x = 1").0, 1);
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        // 'é' is two bytes but one column.
        let (column, message) = error("é = 1");
        assert_eq!(column, 1);
        assert!(message.starts_with("unexpected character 'é'"));
        let (column, _) = error("x + é = 1");
        assert_eq!(column, 5);
        let (column, _) = error("x=1 ✓");
        assert_eq!(column, 5);
    }

    #[test]
    fn validates_names() {
        for good in ["p1", "_", "a.b.c", "Pump_3.in", "x."] {
            assert!(is_valid_name(good), "{good}");
        }
        for bad in ["", "1p", ".a", "a-b", "a b", "é", "a[0]"] {
            assert!(!is_valid_name(bad), "{bad}");
        }
    }
}
