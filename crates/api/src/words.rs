//! Machine-word arithmetic shared by the exact fast paths (residual checks, Gram matrices,
//! affine combinations): values kept in `i128` while they fit, the big-integer path answering
//! when they do not.

/// `a · b`, or `None` when it leaves an `i128`. Operands that fit an `i64` (nearly all of them
/// in the fast paths) take one widening product, which cannot overflow; the general checked
/// product of two `i128`s is a sequence of about sixty instructions.
#[inline]
pub fn checked_mul_i128(a: i128, b: i128) -> Option<i128> {
    match (i64::try_from(a), i64::try_from(b)) {
        (Ok(x), Ok(y)) => Some(i128::from(x) * i128::from(y)),
        _ => a.checked_mul(b),
    }
}

/// The values of `items` when every one fits (is `Some`), in one allocation of `len` (the
/// number of items expected): `collect::<Option<Vec<_>>>()` cannot know how many items come
/// (its size hint starts at zero), so it grows its vector four times on the way to twenty
/// entries. Small edits collect vectors like this dozens of times.
pub fn all_fit<T>(len: usize, items: impl IntoIterator<Item = Option<T>>) -> Option<Vec<T>> {
    let mut out = Vec::with_capacity(len);
    for item in items {
        out.push(item?);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::strategy::Strategy;

    proptest::proptest! {
        /// The widening product is the checked product, in and beyond the `i64` range.
        #[test]
        fn checked_products_agree(
            a in proptest::prop_oneof![
                proptest::num::i64::ANY.prop_map(i128::from),
                proptest::num::i128::ANY
            ],
            b in proptest::prop_oneof![
                proptest::num::i64::ANY.prop_map(i128::from),
                proptest::num::i128::ANY
            ],
        ) {
            proptest::prop_assert_eq!(checked_mul_i128(a, b), a.checked_mul(b));
        }
    }

    #[test]
    fn all_fit_is_every_value_or_none() {
        assert_eq!(all_fit(3, [Some(1), Some(2), Some(3)]), Some(vec![1, 2, 3]));
        assert_eq!(all_fit(3, [Some(1), None, Some(3)]), None);
        assert_eq!(all_fit(0, [Some(7), Some(8)]), Some(vec![7, 8]));
        assert_eq!(all_fit::<u8>(4, []), Some(vec![]));
        let exact = all_fit(20, (0..20).map(Some)).expect("all fit");
        assert_eq!(exact.capacity(), 20);
    }

    #[test]
    fn extremes() {
        let (min, max) = (i128::from(i64::MIN), i128::from(i64::MAX));
        assert_eq!(checked_mul_i128(min, min), Some(min * min));
        assert_eq!(checked_mul_i128(max, min), Some(max * min));
        assert_eq!(checked_mul_i128(i128::MAX, 2), None);
        assert_eq!(checked_mul_i128(i128::MIN, -1), None);
        assert_eq!(checked_mul_i128(1 << 64, 1 << 62), Some(1 << 126));
        assert_eq!(checked_mul_i128(1 << 64, 1 << 63), None);
    }
}
