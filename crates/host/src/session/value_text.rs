//! The decimal text of an edit's values for its report, each distinct denominator converted
//! once.
//!
//! Converting a big integer to decimal is quadratic in its length in `num-bigint` (and in
//! `dashu`: 0.27 against 0.24 ms for 13 000 digits), and the exact optimum of a large edit has
//! values of thousands of digits. Their denominators are few (reduced from one common
//! denominator, they differ by small factors): the figure mesh at δ_max = 40 has 10 432 values
//! over 1 202 distinct denominators of ~13 000 digits each, half the report's text. Each
//! distinct denominator is converted once, then every numerator; both on all cores.

use api::{Integer, Rational};
use num_traits::One;
use rayon::prelude::*;
use std::collections::HashMap;

/// The text of every value, as [`api::format_rational`] writes it (`p`, or `p/q` in lowest
/// terms), per entry of `values`.
pub(super) fn value_texts(values: &[&[Rational]]) -> Vec<Vec<String>> {
    let mut index: HashMap<&Integer, usize> = HashMap::new();
    let mut distinct: Vec<&Integer> = Vec::new();
    for v in values.iter().flat_map(|entry| entry.iter()) {
        let d = v.denom();
        if !d.is_one() {
            index.entry(d).or_insert_with(|| {
                distinct.push(d);
                distinct.len() - 1
            });
        }
    }
    let denominators: Vec<String> = distinct.par_iter().map(|d| d.to_string()).collect();
    values
        .par_iter()
        .map(|entry| {
            entry
                .iter()
                .map(|v| match index.get(v.denom()) {
                    Some(&k) => format!("{}/{}", v.numer(), denominators[k]),
                    None => v.numer().to_string(),
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::format_rational;

    fn q(n: &str, d: &str) -> Rational {
        Rational::new(n.parse().expect("n"), d.parse().expect("d"))
    }

    /// The same text as one conversion per value: integers, negative values, shared and
    /// distinct denominators (some of them long), empty entries.
    #[test]
    fn texts_are_those_of_format_rational() {
        let long = format!("1{}", "7".repeat(300));
        let entries: Vec<Vec<Rational>> = vec![
            vec![q("3", "1"), q("-6", "4")],
            vec![],
            vec![q("1", &long), q("-22", &long), q("0", "5")],
            vec![q(&format!("-9{}", "1".repeat(200)), "3"), q("5", "-15")],
        ];
        let slices: Vec<&[Rational]> = entries.iter().map(Vec::as_slice).collect();
        let texts = value_texts(&slices);
        let expected: Vec<Vec<String>> = entries
            .iter()
            .map(|e| e.iter().map(format_rational).collect())
            .collect();
        assert_eq!(texts, expected);
        assert_eq!(texts[0], ["3", "-3/2"]);
        assert_eq!(texts[3][1], "-1/3");
    }
}
