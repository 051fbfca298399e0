//! The decimal text of an edit's values for its report, each distinct denominator converted
//! once.
//!
//! Converting a big integer to decimal is quadratic in its length, and the exact optimum of a
//! large edit has values of thousands of digits. Their denominators are few (reduced from one
//! common denominator, they differ by small factors): the figure mesh at δ_max = 40 has 10 432
//! values over 1 202 distinct denominators of ~13 000 digits each, half the report's text. Each
//! distinct denominator is converted once, then every numerator, all in one batch each by
//! [`exact_ldu::decimal_texts`] (with one table of powers per batch: eight integers at a time in
//! IFMA lanes where the processor has them, by word products elsewhere) on all cores.

use api::{Integer, Rational};
use num_traits::One;
use std::collections::HashMap;

/// The text of every value, as [`api::format_rational`] writes it (`p`, or `p/q` in lowest
/// terms), per entry of `values`.
pub(super) fn value_texts(values: &[&[Rational]]) -> Vec<Vec<String>> {
    let (distinct, slots) = distinct_denominators(values);
    let denominators = exact_ldu::decimal_texts(&distinct);
    let numerators: Vec<&Integer> = values
        .iter()
        .flat_map(|entry| entry.iter().map(Rational::numer))
        .collect();
    let mut numerators = exact_ldu::decimal_texts(&numerators).into_iter();
    let mut slots = slots.into_iter();
    values
        .iter()
        .map(|entry| {
            entry
                .iter()
                .zip(numerators.by_ref())
                .zip(slots.by_ref())
                .map(|((_, numerator), slot)| match slot {
                    // Grown in place (short texts fit the numerator's block).
                    Some(k) => {
                        let mut text = numerator;
                        text.push('/');
                        text.push_str(&denominators[k]);
                        text
                    }
                    None => numerator,
                })
                .collect()
        })
        .collect()
}

/// Distinct denominators up to which they are looked up one by one (a small edit's values
/// share one or a few); beyond, in a hash table.
const LINEAR_LOOKUP_UP_TO: usize = 8;

/// The distinct denominators other than 1, in order of first appearance, and for each value
/// (all entries in order) the index of its denominator among them (`None` for 1).
fn distinct_denominators<'v>(values: &[&'v [Rational]]) -> (Vec<&'v Integer>, Vec<Option<usize>>) {
    // foldhash, not SipHash: the keys are the edit's own values, and on a small edit SipHash
    // was a fifth of this function's instructions.
    let mut index: HashMap<&Integer, usize, foldhash::fast::RandomState> = HashMap::default();
    let mut distinct: Vec<&Integer> = Vec::new();
    let mut slots = Vec::with_capacity(values.iter().map(|entry| entry.len()).sum());
    for v in values.iter().flat_map(|entry| entry.iter()) {
        let d = v.denom();
        if d.is_one() {
            slots.push(None);
            continue;
        }
        let known = if distinct.len() <= LINEAR_LOOKUP_UP_TO {
            distinct.iter().position(|x| *x == d)
        } else {
            if index.is_empty() {
                index.extend(distinct.iter().enumerate().map(|(k, x)| (*x, k)));
            }
            index.get(d).copied()
        };
        let k = known.unwrap_or_else(|| {
            distinct.push(d);
            // Once the table is made, it holds every distinct denominator.
            if !index.is_empty() {
                index.insert(d, distinct.len() - 1);
            }
            distinct.len() - 1
        });
        slots.push(Some(k));
    }
    (distinct, slots)
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

    /// Denominators numbered by first appearance, looked up one by one and then in the table:
    /// one seen before the table is made and again after, one seen only after, integers.
    #[test]
    fn denominators_are_numbered_by_first_appearance() {
        let mut entry: Vec<Rational> = (2..=14).map(|d| q("1", &d.to_string())).collect();
        entry.extend([
            q("5", "1"),
            q("3", "7"),
            q("1", "15"),
            q("2", "15"),
            q("9", "2"),
        ]);
        let (distinct, slots) = distinct_denominators(&[&entry[..5], &entry[5..]]);
        let expected: Vec<Integer> = (2..=15).map(Integer::from).collect();
        assert_eq!(distinct.into_iter().cloned().collect::<Vec<_>>(), expected);
        let mut expected_slots: Vec<Option<usize>> = (0..13).map(Some).collect();
        expected_slots.extend([None, Some(5), Some(13), Some(13), Some(0)]);
        assert_eq!(slots, expected_slots);
    }

    /// Values long enough for the batch conversion (numerators and denominators of ~2 000
    /// digits, enough of them for the batch's table), among short ones and integers.
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
