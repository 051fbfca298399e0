//! The decimal text of an edit's values for its report, each distinct denominator converted
//! once.
//!
//! Converting a big integer to decimal is quadratic in its length, and the exact optimum of a
//! large edit has values of thousands of digits. Their denominators are few (reduced from one
//! common denominator, they differ by small factors): the figure mesh at δ_max = 40 has 10 432
//! values over 1 202 distinct denominators of ~13 000 digits each, half the report's text. Each
//! distinct denominator is converted once, then every numerator, all in one batch each by
//! [`exact_ldu::decimal_texts`] (eight integers at a time in IFMA lanes where the processor has
//! them) on all cores.

use api::{Integer, Rational};
use num_traits::One;
use std::collections::HashMap;

/// The text of every value, as [`api::format_rational`] writes it (`p`, or `p/q` in lowest
/// terms), per entry of `values`.
pub(super) fn value_texts(values: &[&[Rational]]) -> Vec<Vec<String>> {
    // foldhash, not SipHash: the keys are the edit's own values, and on a small edit SipHash
    // was a fifth of this function's instructions.
    let mut index: HashMap<&Integer, usize, foldhash::fast::RandomState> = HashMap::default();
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
    let denominators = exact_ldu::decimal_texts(&distinct);
    let numerators: Vec<&Integer> = values
        .iter()
        .flat_map(|entry| entry.iter().map(Rational::numer))
        .collect();
    let mut numerators = exact_ldu::decimal_texts(&numerators).into_iter();
    values
        .iter()
        .map(|entry| {
            entry
                .iter()
                .zip(numerators.by_ref())
                .map(|(v, mut numerator)| {
                    if let Some(&k) = index.get(v.denom()) {
                        numerator.push('/');
                        numerator.push_str(&denominators[k]);
                    }
                    numerator
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

    /// Values long enough for the batch conversion (numerators and denominators of ~2 000
    /// digits, enough of them for the lanes), among short ones and integers.
    #[test]
    fn long_values_are_written_as_format_rational_writes_them() {
        let denominator: Integer = Integer::from(3).pow(4_001) * 7;
        let entries: Vec<Vec<Rational>> = (0..24i32)
            .map(|i| {
                let numerator = Integer::from(10).pow(1_990 + i as u32) * (2 * i + 1) - i;
                vec![
                    Rational::new(numerator.clone(), denominator.clone()),
                    Rational::new(-numerator, Integer::from(i + 2)),
                    Rational::from_integer(Integer::from(5).pow(3_000) * i),
                ]
            })
            .collect();
        let slices: Vec<&[Rational]> = entries.iter().map(Vec::as_slice).collect();
        let texts = value_texts(&slices);
        for (entry, text) in entries.iter().zip(&texts) {
            let expected: Vec<String> = entry.iter().map(format_rational).collect();
            assert_eq!(text, &expected);
        }
        assert!(texts[5][0].len() > 3_900);
    }
}
