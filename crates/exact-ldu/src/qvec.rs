//! Rational vectors over one common denominator.
//!
//! Exact solves keep every entry as `num[k] / den` with a shared positive `den`: sums and
//! triangular substitutions then run on integers only, and each result entry is reduced once at
//! the end instead of after every operation.

use crate::ring::{gcd_all, lcm, Ring};
use api::Rational as BigRational;
use num_bigint::BigInt;
use num_traits::One;

/// A rational vector `num / den` with `den > 0`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QVec<R: Ring> {
    /// Numerators.
    pub num: Vec<R>,
    /// The common denominator, positive.
    pub den: R,
}

impl<R: Ring> QVec<R> {
    /// An integer vector (denominator 1).
    pub fn from_integers(num: Vec<R>) -> Self {
        QVec { num, den: R::one() }
    }

    /// The zero vector of length `n`.
    pub fn zeros(n: usize) -> Self {
        QVec::from_integers(vec![R::zero(); n])
    }

    /// Brings rationals to their least common denominator.
    pub fn from_rationals(values: &[BigRational]) -> Self {
        // Entries usually come in runs over one denominator (positions on one grid): the lcm
        // and the scale factor are computed once per run, not once per entry.
        let mut den_big = BigInt::from(1);
        let mut last: Option<&BigInt> = None;
        for v in values {
            let d = v.denom();
            if !One::is_one(d) && last != Some(d) {
                den_big = num_integer::Integer::lcm(&den_big, d);
                last = Some(d);
            }
        }
        let mut num = Vec::with_capacity(values.len());
        let mut scale: Option<(&BigInt, BigInt)> = None;
        for v in values {
            let d = v.denom();
            if One::is_one(d) {
                num.push(R::from_bigint(&(v.numer() * &den_big)));
                continue;
            }
            if scale.as_ref().is_none_or(|(of, _)| *of != d) {
                scale = Some((d, &den_big / d));
            }
            if let Some((_, factor)) = &scale {
                num.push(R::from_bigint(&(v.numer() * factor)));
            }
        }
        QVec {
            num,
            den: R::from_bigint(&den_big),
        }
    }

    /// The entries as reduced rationals ([`crate::reduce_over`]).
    pub fn to_rationals(&self) -> Vec<BigRational> {
        crate::reduce::reduce_over(
            self.num.iter().map(Ring::to_bigint).collect(),
            &self.den.to_bigint(),
        )
    }

    /// Length.
    pub fn len(&self) -> usize {
        self.num.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.num.is_empty()
    }

    /// `−v`, over the same denominator.
    pub fn negated(&self) -> Self {
        QVec {
            num: self.num.iter().map(Ring::neg).collect(),
            den: self.den.clone(),
        }
    }

    /// Sets entry `k` to `s / (den · divisor)` and rescales the other entries so that all keep
    /// one denominator. `divisor` must be nonzero.
    pub fn divide_entry(&mut self, k: usize, s: R, divisor: &R) {
        // A zero entry and a unit divisor keep the denominator: no GCD (substitutions on
        // sparse factors meet both at most steps).
        if s.is_zero() || divisor.is_one() {
            self.num[k] = s;
            return;
        }
        let g = s.gcd(divisor);
        let mut f = divisor.div_exact(&g);
        let mut q = s.div_exact(&g);
        if f.is_negative() {
            f = f.neg();
            q = q.neg();
        }
        if !f.is_one() {
            for (j, v) in self.num.iter_mut().enumerate() {
                if j != k && !v.is_zero() {
                    *v = v.mul(&f);
                }
            }
            self.den = self.den.mul(&f);
        }
        self.num[k] = q;
    }

    /// Divides numerators and denominator by their common factor.
    pub fn normalize(&mut self) {
        let g = gcd_all(&self.num).gcd(&self.den);
        if !g.is_one() && !g.is_zero() {
            for v in self.num.iter_mut() {
                *v = v.div_exact(&g);
            }
            self.den = self.den.div_exact(&g);
        }
    }

    /// Rewrites the vector over the denominator `target`, a multiple of the current one.
    pub fn rescale_to(&mut self, target: &R) {
        if target == &self.den {
            return;
        }
        let f = target.div_exact(&self.den);
        for v in self.num.iter_mut() {
            *v = v.mul(&f);
        }
        self.den = target.clone();
    }

    /// The least common multiple of the denominators of several vectors.
    pub fn common_denominator<'a>(vectors: impl IntoIterator<Item = &'a QVec<R>>) -> R {
        vectors
            .into_iter()
            .fold(R::one(), |acc, v| lcm(&acc, &v.den))
    }

    /// The primitive integer vector in the direction of this one (a positive multiple).
    pub fn primitive_integers(&self) -> Vec<R> {
        let g = gcd_all(&self.num);
        if g.is_zero() || g.is_one() {
            return self.num.clone();
        }
        self.num.iter().map(|v| v.div_exact(&g)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::Int;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    #[test]
    fn round_trips_and_divides() {
        let values = vec![q(1, 2), q(-2, 3), q(5, 1)];
        let mut v = QVec::<Int>::from_rationals(&values);
        assert_eq!(v.den, Int::from_i64(6));
        assert_eq!(v.to_rationals(), values);
        v.divide_entry(1, Int::from_i64(-4), &Int::from_i64(-6));
        assert_eq!(v.to_rationals(), vec![q(1, 2), q(1, 9), q(5, 1)]);
        v.normalize();
        assert_eq!(v.to_rationals(), vec![q(1, 2), q(1, 9), q(5, 1)]);
        assert_eq!(
            QVec::from_integers(vec![Int::from_i64(4), Int::from_i64(-6)]).primitive_integers(),
            vec![Int::from_i64(2), Int::from_i64(-3)]
        );
    }

    use proptest::strategy::Just;

    proptest::proptest! {
        /// Runs of one denominator, alternating ones and integers all come back exactly, over
        /// the least common denominator.
        #[test]
        fn round_trips_any_denominators(
            entries in proptest::collection::vec((-50i64..=50, 1i64..=12, 1usize..=3), 0..12)
        ) {
            let values: Vec<BigRational> = entries
                .iter()
                .flat_map(|&(n, d, run)| std::iter::repeat_n(q(n, d), run))
                .collect();
            let v = QVec::<Int>::from_rationals(&values);
            let lcm = values
                .iter()
                .fold(BigInt::from(1), |acc, x| num_integer::Integer::lcm(&acc, x.denom()));
            proptest::prop_assert_eq!(v.den.to_bigint(), lcm);
            proptest::prop_assert_eq!(v.to_rationals(), values);
        }

        /// Entry `k` becomes `s / (den · divisor)` and the others keep their values over a
        /// positive denominator, for zero entries and unit divisors (the shortcuts) as for any.
        #[test]
        fn dividing_an_entry_changes_that_entry_alone(
            entries in proptest::collection::vec((-30i64..=30, 1i64..=9), 1..8),
            k in 0usize..8,
            s in proptest::prop_oneof![Just(0i64), -40i64..=40],
            divisor in proptest::prop_oneof![Just(1i64), Just(-1i64), -12i64..=12],
        ) {
            proptest::prop_assume!(divisor != 0);
            let values: Vec<BigRational> = entries.iter().map(|&(n, d)| q(n, d)).collect();
            let k = k % values.len();
            let mut v = QVec::<Int>::from_rationals(&values);
            let expected_k = q(s, 1) / (BigRational::from_integer(v.den.to_bigint()) * q(divisor, 1));
            v.divide_entry(k, Int::from_i64(s), &Int::from_i64(divisor));
            proptest::prop_assert!(!v.den.is_negative() && !v.den.is_zero());
            let mut expected = values;
            expected[k] = expected_k;
            proptest::prop_assert_eq!(v.to_rationals(), expected);
        }
    }
}
