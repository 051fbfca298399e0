//! Small symmetric positive definite systems solved by fraction-free elimination in machine
//! words (values below `2^62`, products in `i128`):
//! the normal equations of edits of a few points, where Dixon's lifting
//! ([`crate::dixon::LiftingSolver`]) spends most of its time preparing (a fill-reducing order, a
//! modular factoring, bounds) and reconstructing, for answers of a few dozen bits.
//!
//! Bareiss' one-step elimination (E. H. Bareiss, "Sylvester's identity and multistep
//! integer-preserving Gaussian elimination", Math. Comp. 22, 1968): with `M⁽⁰⁾ = A`,
//!
//! ```text
//! M⁽ᵏ⁾ᵢⱼ = (M⁽ᵏ⁻¹⁾ₖₖ M⁽ᵏ⁻¹⁾ᵢⱼ − M⁽ᵏ⁻¹⁾ᵢₖ M⁽ᵏ⁻¹⁾ₖⱼ) / M⁽ᵏ⁻²⁾ₖ₋₁,ₖ₋₁     (i, j > k),
//! ```
//!
//! every division exact and every entry a minor of `A` (Sylvester's identity), so the numbers
//! stay as small as the answer's. The pivots are leading principal minors: positive for a
//! positive definite `A`, so no pivoting. The right-hand side follows the same recurrence, and
//! back substitution gives `y = det(A) · x` (integers, Cramer) by exact divisions.
//!
//! Every value is checked against `2^62`: a larger one (or a zero pivot, a matrix that is not
//! positive definite) answers `None`, and the caller lifts instead. No result is ever rounded,
//! so nothing needs verifying.

use api::words::all_fit;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::ToPrimitive;

/// The largest order solved this way: the factored matrix is kept dense (`n²` words), and
/// beyond a few dozen unknowns the minors outgrow a word on most systems anyway.
pub(crate) const MAX_ORDER: usize = 48;

/// Every stored value is below `2^62` in magnitude: then `a b − c d` of four of them is below
/// `2^125` and is computed in `i128` by plain widening multiplications, with no overflow check
/// (a checked `i128` product is a library call, most of the elimination's time).
const WORD_LIMIT: u64 = 1 << 62;

/// `v` when it is below [`WORD_LIMIT`] in magnitude.
#[inline]
fn word(v: i128) -> Option<i64> {
    (v.unsigned_abs() < u128::from(WORD_LIMIT)).then_some(v as i64)
}

/// `a b − c d` exactly (all four below `2^62` in magnitude).
#[inline]
fn cross(a: i64, b: i64, c: i64, d: i64) -> i128 {
    i128::from(a) * i128::from(b) - i128::from(c) * i128::from(d)
}

/// `A` factored one connected component at a time (the graph of its nonzero off-diagonal
/// entries): the normal matrix of an edit whose x and y coordinates are tied by the same rows
/// is two identical blocks, factored once. The solution of `A x = b` is unique, so solving
/// block by block and bringing the blocks' lowest terms over the least common multiple of
/// their denominators gives exactly what one elimination of `A` gives (and smaller minors on
/// the way: a block's are not multiplied by the other blocks' determinants).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct SmallBareiss {
    n: usize,
    /// The distinct blocks, eliminated.
    blocks: Vec<DenseBareiss>,
    /// Each component's indices (increasing) and its block in `blocks`; empty when `A` is one
    /// component (then `blocks` holds `A` itself).
    parts: Vec<(Vec<usize>, usize)>,
}

impl SmallBareiss {
    /// Eliminates `A` (`n × n`, `n ≤ MAX_ORDER`, both triangles given as sparse rows). `None`
    /// when `n` is too large, `A` is not symmetric, or in some block a value reaches `2^62`
    /// or a pivot is zero.
    pub(crate) fn factor(n: usize, rows: &[Vec<(usize, i64)>]) -> Option<Self> {
        if n == 0 || n > MAX_ORDER || rows.len() != n {
            return None;
        }
        let components = components(n, rows)?;
        if components.len() == 1 {
            let mut m = vec![0i64; n * n];
            for (i, row) in rows.iter().enumerate() {
                for &(j, v) in row {
                    m[i * n + j] = v;
                }
            }
            return Some(SmallBareiss {
                n,
                blocks: vec![DenseBareiss::factor(n, m)?],
                parts: Vec::new(),
            });
        }
        // Each index's position in its component: the components' indices increase, so a
        // row's entries keep their order. Components whose rows are entry for entry the same
        // in those positions are the same matrix and share a block.
        let mut local = vec![0usize; n];
        for indices in &components {
            for (at, &i) in indices.iter().enumerate() {
                local[i] = at;
            }
        }
        let nonzeros = |i: usize| {
            rows[i]
                .iter()
                .filter(|(_, v)| *v != 0)
                .map(|&(j, v)| (local[j], v))
        };
        let same = |a: &[usize], b: &[usize]| {
            a.len() == b.len() && a.iter().zip(b).all(|(&i, &j)| nonzeros(i).eq(nonzeros(j)))
        };
        let mut blocks = Vec::new();
        let mut parts: Vec<(Vec<usize>, usize)> = Vec::with_capacity(components.len());
        for indices in components {
            let twin = parts.iter().find(|(other, _)| same(other, &indices));
            let block = match twin {
                Some((_, block)) => *block,
                None => {
                    let k = indices.len();
                    let mut m = vec![0i64; k * k];
                    for (at, &i) in indices.iter().enumerate() {
                        for (j, v) in nonzeros(i) {
                            m[at * k + j] = v;
                        }
                    }
                    blocks.push(DenseBareiss::factor(k, m)?);
                    blocks.len() - 1
                }
            };
            parts.push((indices, block));
        }
        Some(SmallBareiss { n, blocks, parts })
    }

    /// The exact solution of `A x = b` as `(numerators, denominator)` with the smallest
    /// positive common denominator (what lifting with rational reconstruction gives); `None`
    /// when `b` or a value on the way reaches `2^62`.
    pub(crate) fn solve(&self, b: &[BigInt]) -> Option<(Vec<BigInt>, BigInt)> {
        // `solve_words` checks the bound of every entry.
        let b = all_fit(b.len(), b.iter().map(ToPrimitive::to_i64))?;
        let (numerators, denominator) = self.solve_words(&b)?;
        Some((
            numerators.into_iter().map(BigInt::from).collect(),
            BigInt::from(denominator),
        ))
    }

    /// [`SmallBareiss::solve`] for a right-hand side of machine words, answering in words.
    pub(crate) fn solve_words(&self, b: &[i64]) -> Option<(Vec<i64>, i64)> {
        if self.parts.is_empty() {
            return self.blocks[0].solve_words(b);
        }
        // Each block in lowest terms, then all over the least common multiple `l` of their
        // denominators: a prime's highest power in `l` comes from a block whose numerators
        // are not all multiples of it, and that block is scaled by a cofactor without it, so
        // the whole is in lowest terms too.
        let mut solved = Vec::with_capacity(self.parts.len());
        let mut l: u64 = 1;
        let mut gathered = Vec::new();
        for (indices, block) in &self.parts {
            gathered.clear();
            gathered.extend(indices.iter().map(|&i| b[i]));
            // A block without right-hand side (an anchor's response reaches one coordinate's
            // block) is solved by zeros over 1.
            if gathered.iter().all(|&v| v == 0) {
                solved.push((vec![0; indices.len()], 1));
                continue;
            }
            let (y, d) = self.blocks[*block].solve_words(&gathered)?;
            let d = d.unsigned_abs();
            l = (l / l.gcd(&d)).checked_mul(d)?;
            if l >= WORD_LIMIT {
                return None;
            }
            solved.push((y, d));
        }
        let mut x = vec![0i64; self.n];
        for ((indices, _), (y, d)) in self.parts.iter().zip(solved) {
            let scale = i128::from(l / d);
            for (&i, v) in indices.iter().zip(y) {
                x[i] = word(i128::from(v) * scale)?;
            }
        }
        Some((x, l as i64))
    }
}

/// The connected components of the symmetric pattern of `rows` (`i` and `j` joined by a
/// nonzero entry `(i, j)`), each as its increasing indices, ordered by their first index, by
/// depth-first search; `None` when an entry's column is not below `n`, or an entry joins a
/// component found before (the pattern is not symmetric).
fn components(n: usize, rows: &[Vec<(usize, i64)>]) -> Option<Vec<Vec<usize>>> {
    let mut label = vec![usize::MAX; n];
    let mut count = 0;
    let mut stack = Vec::new();
    for start in 0..n {
        if label[start] != usize::MAX {
            continue;
        }
        label[start] = count;
        stack.push(start);
        while let Some(i) = stack.pop() {
            for &(j, v) in &rows[i] {
                if j >= n {
                    return None;
                }
                if v == 0 || label[j] == count {
                    continue;
                }
                if label[j] != usize::MAX {
                    return None;
                }
                label[j] = count;
                stack.push(j);
            }
        }
        count += 1;
    }
    let mut components = vec![Vec::new(); count];
    for (i, &c) in label.iter().enumerate() {
        components[c].push(i);
    }
    Some(components)
}

/// One block after Bareiss' elimination: on and above the diagonal the rows of the last step
/// that changed them (`U`, with `U_{n−1,n−1} = det A`; `U_{k,i}` is also the multiplier of row
/// `i` at step `k`, by symmetry); below it `A`'s own entries, not read.
#[derive(Debug, Clone, PartialEq, Eq)]
struct DenseBareiss {
    n: usize,
    m: Vec<i64>,
    /// The exact divisor of each pivot `U_kk`, for the solves.
    pivots: Vec<ExactDivisor>,
}

impl DenseBareiss {
    /// Eliminates the dense `n × n` matrix `m` (row-major). `None` when it is not symmetric,
    /// a value reaches `2^62` or a pivot is zero.
    fn factor(n: usize, mut m: Vec<i64>) -> Option<Self> {
        debug_assert_eq!(m.len(), n * n);
        if m.iter().any(|&v| word(i128::from(v)).is_none()) {
            return None;
        }
        // Symmetric (else the caller lifts): then every step keeps the trailing block
        // symmetric (an entry is the minor of the leading rows and columns with row `i` and
        // column `j` added), so only the upper triangle is eliminated, and the multiplier
        // `M⁽ᵏ⁻¹⁾ᵢₖ` of row `i` is read as `M⁽ᵏ⁻¹⁾ₖᵢ`, row `k`'s entry, final since step `k − 1`.
        if (0..n).any(|i| (i + 1..n).any(|j| m[i * n + j] != m[j * n + i])) {
            return None;
        }
        let mut previous = ExactDivisor::new(1);
        let mut pivots = Vec::with_capacity(n);
        for k in 0..n {
            let pivot = m[k * n + k];
            if pivot == 0 {
                return None;
            }
            for i in k + 1..n {
                let below = m[k * n + i];
                for j in i..n {
                    let (own, across) = (m[i * n + j], m[k * n + j]);
                    // Zero stays zero (the matrices of edits are sparse).
                    if own == 0 && (below == 0 || across == 0) {
                        continue;
                    }
                    let value = cross(pivot, own, below, across);
                    m[i * n + j] = previous.quotient(value)?;
                }
            }
            previous = ExactDivisor::new(pivot);
            pivots.push(previous);
        }
        Some(DenseBareiss { n, m, pivots })
    }

    /// `A x = b` in lowest terms (see [`SmallBareiss::solve`]), in words.
    fn solve_words(&self, b: &[i64]) -> Option<(Vec<i64>, i64)> {
        let n = self.n;
        let at = |i: usize, j: usize| self.m[i * n + j];
        let mut c = all_fit(b.len(), b.iter().map(|&v| word(i128::from(v))))?;
        // The right-hand side through the same steps.
        let one = ExactDivisor::new(1);
        for k in 0..n {
            let pivot = at(k, k);
            let previous = if k == 0 { &one } else { &self.pivots[k - 1] };
            for i in k + 1..n {
                // The multiplier, by symmetry (see `factor`).
                let below = at(k, i);
                if c[i] == 0 && (below == 0 || c[k] == 0) {
                    continue;
                }
                c[i] = previous.quotient(cross(pivot, c[i], below, c[k]))?;
            }
        }
        // U x = c with U_{n−1,n−1} = det: y = det · x by exact divisions, last entry first.
        // Each product is below 2^124 and at most 48 are summed (checked: a sum may overflow).
        let det = at(n - 1, n - 1);
        let mut y = vec![0i64; n];
        for i in (0..n).rev() {
            let mut sum = i128::from(det) * i128::from(c[i]);
            for (u, yj) in self.m[i * n + i + 1..(i + 1) * n].iter().zip(&y[i + 1..]) {
                sum = sum.checked_sub(i128::from(*u) * i128::from(*yj))?;
            }
            y[i] = self.pivots[i].quotient(sum)?;
        }
        // Lowest common denominator: divide by the content of (det, y).
        let mut g = det.unsigned_abs();
        for v in &y {
            if g == 1 {
                break;
            }
            g = g.gcd(&v.unsigned_abs());
        }
        let sign: i64 = if det < 0 { -1 } else { 1 };
        let g = i64::try_from(g).ok()?;
        if g == 1 {
            if sign < 0 {
                y.iter_mut().for_each(|v| *v = -*v);
            }
            return Some((y, sign * det));
        }
        Some((
            y.into_iter().map(|v| sign * (v / g)).collect(),
            sign * (det / g),
        ))
    }
}

/// Exact division by one stored value `b` (`0 < |b| < 2^62`) without a hardware division:
/// `b = ±2^s · odd`, and a multiple `a` of `b` divided by `2^s` is `q · odd` (times the sign),
/// so modulo `2^64` the quotient is that times `odd⁻¹` — exactly `q` when `|q| < 2^63`. The
/// quotient is wanted only below `2^62` ([`word`]), which `|a| < 2^62 |b|` decides before it is
/// computed. Each elimination step divides by one previous pivot `(n − k)²` times: the inverse
/// is found once (a 64-bit division is tens of cycles, most of a small factoring's time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ExactDivisor {
    negative: bool,
    shift: u32,
    odd_inverse: u64,
    /// `2^62 |b|`: quotients of smaller dividends are words.
    limit: u128,
}

impl ExactDivisor {
    fn new(b: i64) -> Self {
        debug_assert!(b != 0 && b.unsigned_abs() < WORD_LIMIT);
        let magnitude = b.unsigned_abs();
        let shift = magnitude.trailing_zeros();
        ExactDivisor {
            negative: b < 0,
            shift,
            odd_inverse: crate::word_division::word_inverse(magnitude >> shift),
            limit: u128::from(magnitude) << 62,
        }
    }

    /// `a / b` for a multiple `a` of `b` (`|a| < 2^127`) when it is below `2^62` in magnitude.
    #[inline]
    fn quotient(&self, a: i128) -> Option<i64> {
        if a.unsigned_abs() >= self.limit {
            return None;
        }
        // `a >> s` is exact; its low 64 bits times `odd⁻¹` are `±q` modulo 2^64.
        let q = ((a >> self.shift) as u64).wrapping_mul(self.odd_inverse) as i64;
        Some(if self.negative { -q } else { q })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_rational::BigRational;
    use num_traits::Zero;
    use proptest::prelude::*;

    fn dense_rows(a: &[Vec<i64>]) -> Vec<Vec<(usize, i64)>> {
        a.iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0)
                    .map(|(j, v)| (j, *v))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn solves_a_small_system_in_lowest_terms() {
        // [[2, 1], [1, 2]] x = [1, 0]: x = (2/3, −1/3).
        let f = SmallBareiss::factor(2, &dense_rows(&[vec![2, 1], vec![1, 2]])).expect("SPD");
        let (num, den) = f.solve(&[BigInt::from(1), BigInt::from(0)]).expect("small");
        assert_eq!(num, [BigInt::from(2), BigInt::from(-1)]);
        assert_eq!(den, BigInt::from(3));
        // A negative determinant (symmetric, not definite: pivots 1 and −3) still answers
        // over a positive denominator: x = (−1/3, 2/3).
        let g = SmallBareiss::factor(2, &dense_rows(&[vec![1, 2], vec![2, 1]])).expect("pivots");
        assert_eq!(g.solve_words(&[1, 0]), Some((vec![-1, 2], 3)));
        // An integer answer has denominator one.
        let (num, den) = f.solve(&[BigInt::from(3), BigInt::from(3)]).expect("small");
        assert_eq!(
            (num, den),
            (vec![BigInt::from(1), BigInt::from(1)], BigInt::from(1))
        );
    }

    #[test]
    fn refuses_what_it_cannot_do_exactly() {
        // A matrix that is not symmetric (its multipliers are read off the upper triangle).
        assert!(SmallBareiss::factor(2, &dense_rows(&[vec![2, 1], vec![0, 2]])).is_none());
        assert!(SmallBareiss::factor(2, &dense_rows(&[vec![2, 0], vec![1, 2]])).is_none());
        // A zero pivot (not positive definite), too large an order.
        assert!(SmallBareiss::factor(2, &dense_rows(&[vec![0, 1], vec![1, 0]])).is_none());
        assert!(SmallBareiss::factor(MAX_ORDER + 1, &vec![Vec::new(); MAX_ORDER + 1]).is_none());
        // An entry, or a minor, of 2^62 or more.
        assert!(SmallBareiss::factor(1, &dense_rows(&[vec![1 << 62]])).is_none());
        let big = 1i64 << 40;
        assert!(SmallBareiss::factor(2, &dense_rows(&[vec![big, 1], vec![1, big]])).is_none());
        // A right-hand side, or a value on the way, of 2^62 or more.
        let f = SmallBareiss::factor(2, &dense_rows(&[vec![2, 1], vec![1, 2]])).expect("small");
        assert!(f.solve(&[BigInt::from(1) << 62, BigInt::from(0)]).is_none());
        assert!(f
            .solve(&[BigInt::from(1) << 130, BigInt::from(0)])
            .is_none());
        let near = (1i64 << 61) + 1;
        assert!(f
            .solve(&[BigInt::from(-near), BigInt::from(near)])
            .is_none());
        // Just below the limit: solved.
        let (num, den) = f
            .solve(&[BigInt::from(3 << 20), BigInt::from(0)])
            .expect("small");
        assert_eq!(
            (num, den),
            (
                vec![BigInt::from(2 << 20), BigInt::from(-1 << 20)],
                BigInt::from(1)
            )
        );
    }

    /// The quotient by multiplication is the quotient, for divisors with and without powers
    /// of two, both signs, and quotients on both sides of the `2^62` limit.
    #[test]
    fn exact_divisors_divide_exactly() {
        let limit = 1i128 << 62;
        for b in [
            1i64,
            -1,
            2,
            -2,
            3,
            12,
            -40,
            7 << 20,
            (1 << 61) + 1,
            -((1 << 62) - 1),
        ] {
            let divisor = ExactDivisor::new(b);
            for q in [
                0i128,
                1,
                -1,
                5,
                -977,
                limit - 1,
                -(limit - 1),
                limit,
                -limit,
            ] {
                let a = q * i128::from(b);
                let expected = (q.unsigned_abs() < limit.unsigned_abs()).then_some(q as i64);
                assert_eq!(divisor.quotient(a), expected, "{a} / {b}");
            }
        }
    }

    /// `f`'s solution of `A x = rhs` for `A = a`: exact (`A · num = den · rhs`, `den > 0`) and
    /// over the smallest common denominator (the lcm of the entries' own denominators).
    fn solved_exactly_in_lowest_terms(
        a: &[Vec<i64>],
        f: &SmallBareiss,
        rhs: &[i64],
    ) -> Result<(Vec<BigInt>, BigInt), TestCaseError> {
        let b: Vec<BigInt> = rhs.iter().map(|v| BigInt::from(*v)).collect();
        let (num, den) = f.solve(&b).expect("small");
        prop_assert!(den > BigInt::zero());
        for (i, row) in a.iter().enumerate() {
            let lhs: BigInt = row
                .iter()
                .zip(&num)
                .map(|(aij, x)| BigInt::from(*aij) * x)
                .sum();
            prop_assert_eq!(lhs, &den * &b[i]);
        }
        let lcm = num.iter().fold(BigInt::from(1), |l, x| {
            l.lcm(BigRational::new(x.clone(), den.clone()).denom())
        });
        prop_assert_eq!(&lcm, &den);
        Ok((num, den))
    }

    proptest! {
        /// Random exact quotients: the multiplication by the inverse gives the division's.
        #[test]
        fn exact_divisors_agree_with_division(
            b in (1i64 << 61) * -2 + 1..(1i64 << 61) * 2,
            q in -(1i128 << 64)..(1i128 << 64),
        ) {
            prop_assume!(b != 0);
            let divisor = ExactDivisor::new(b);
            let expected = (q.unsigned_abs() < 1u128 << 62).then_some(q as i64);
            prop_assert_eq!(divisor.quotient(q * i128::from(b)), expected);
        }

        /// On random positive definite `A = Bᵀ B + I`: `A x = b` exactly, `x` in lowest terms
        /// over the smallest common denominator.
        #[test]
        fn solutions_are_exact_and_in_lowest_terms(
            n in 1usize..8,
            entries in proptest::collection::vec(-9i64..10, 64),
            rhs in proptest::collection::vec(-1000i64..1000, 8),
        ) {
            let b_mat = |i: usize, j: usize| entries[i * 8 + j];
            let a: Vec<Vec<i64>> = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| (0..8).map(|k| b_mat(k, i) * b_mat(k, j)).sum::<i64>() + i64::from(i == j))
                        .collect()
                })
                .collect();
            let f = SmallBareiss::factor(n, &dense_rows(&a)).expect("SPD and small");
            solved_exactly_in_lowest_terms(&a, &f, &rhs[..n])?;
        }

        /// Block-diagonal `A` with its blocks' indices interleaved, identical blocks among
        /// them: factored block by block (identical blocks once), solved exactly, in lowest
        /// terms, and equal to one elimination of the whole matrix whenever that fits words.
        #[test]
        fn blocks_are_solved_as_the_whole_matrix(
            sizes in proptest::collection::vec(1usize..5, 1..4),
            twins in proptest::collection::vec(any::<bool>(), 4),
            entries in proptest::collection::vec(0i64..7, 3 * 25),
            order in Just(()).prop_perturb(|_, mut rng| rng.next_u64()),
            rhs in proptest::collection::vec(-1000i64..1000, 16),
        ) {
            // Block t is `Bᵀ B + T` of its own random nonnegative `B` (`T` tridiagonal, 3 on
            // the diagonal and 1 beside it: positive definite and one component), or a copy of
            // block t − 1.
            let mut blocks: Vec<Vec<Vec<i64>>> = Vec::new();
            for (t, &k) in sizes.iter().enumerate() {
                let twin = t > 0 && twins[t];
                let block = if twin {
                    blocks[t - 1].clone()
                } else {
                    let e = |i: usize, j: usize| entries[t * 25 + i * 5 + j];
                    (0..k)
                        .map(|i| {
                            (0..k)
                                .map(|j| {
                                    let t = match i.abs_diff(j) {
                                        0 => 3,
                                        1 => 1,
                                        _ => 0,
                                    };
                                    (0..5).map(|r| e(r, i) * e(r, j)).sum::<i64>() + t
                                })
                                .collect()
                        })
                        .collect()
                };
                blocks.push(block);
            }
            let n: usize = blocks.iter().map(Vec::len).sum();
            // A pseudo-random interleaving of the blocks' indices, each block's in its own
            // order (as the x and y rows of an edit are).
            let mut owner: Vec<usize> = blocks
                .iter()
                .enumerate()
                .flat_map(|(t, block)| std::iter::repeat_n(t, block.len()))
                .collect();
            let mut state = order | 1;
            for i in (1..n).rev() {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                owner.swap(i, (state >> 33) as usize % (i + 1));
            }
            let mut place = vec![0usize; n];
            let mut starts: Vec<usize> = blocks
                .iter()
                .scan(0, |start, block| {
                    let s = *start;
                    *start += block.len();
                    Some(s)
                })
                .collect();
            for (slot, &t) in owner.iter().enumerate() {
                place[starts[t]] = slot;
                starts[t] += 1;
            }
            let mut a = vec![vec![0i64; n]; n];
            let mut start = 0;
            for block in &blocks {
                for (i, row) in block.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        a[place[start + i]][place[start + j]] = *v;
                    }
                }
                start += block.len();
            }
            let f = SmallBareiss::factor(n, &dense_rows(&a)).expect("SPD blocks and small");
            let distinct = (0..blocks.len())
                .filter(|&t| !blocks[..t].contains(&blocks[t]))
                .count();
            if blocks.len() > 1 {
                prop_assert_eq!(f.blocks.len(), distinct);
                prop_assert_eq!(f.parts.len(), blocks.len());
            }
            // Each block solved alone, brought over the lcm of the denominators in big
            // integers: the answer when the lcm and every numerator are below 2^62, else the
            // solve refuses (as one elimination of the whole matrix, whose determinant is the
            // blocks' product, would).
            let mut expected_den = BigInt::from(1);
            let mut per_block = Vec::new();
            let mut start = 0;
            for block in &blocks {
                let k = block.len();
                let local: Vec<i64> = (0..k).map(|i| rhs[place[start + i]]).collect();
                let alone = DenseBareiss::factor(k, block.iter().flatten().copied().collect())
                    .and_then(|d| d.solve_words(&local));
                if let Some((_, d)) = &alone {
                    expected_den = expected_den.lcm(&BigInt::from(*d));
                }
                per_block.push((start, alone));
                start += k;
            }
            let mut expected_num = vec![BigInt::zero(); n];
            let mut fits = per_block.iter().all(|(_, alone)| alone.is_some());
            for (start, alone) in per_block.iter().filter_map(|(s, a)| Some((s, a.as_ref()?))) {
                let (y, d) = alone;
                for (i, v) in y.iter().enumerate() {
                    expected_num[place[start + i]] = BigInt::from(*v) * (&expected_den / BigInt::from(*d));
                }
            }
            let limit = BigInt::from(1i64 << 62);
            fits &= expected_den < limit && expected_num.iter().all(|v| v.magnitude() < limit.magnitude());
            let Some((words, word_den)) = f.solve_words(&rhs[..n]) else {
                prop_assert!(!fits, "refused a solution that fits words");
                return Ok(());
            };
            prop_assert!(fits);
            prop_assert_eq!(words.iter().map(|v| BigInt::from(*v)).collect::<Vec<_>>(), expected_num);
            prop_assert_eq!(BigInt::from(word_den), expected_den);
            let (num, den) = solved_exactly_in_lowest_terms(&a, &f, &rhs[..n])?;
            let whole = a.iter().flatten().copied().collect();
            if let Some(whole) = DenseBareiss::factor(n, whole) {
                let b: Vec<i64> = rhs[..n].to_vec();
                if let Some((wn, wd)) = whole.solve_words(&b) {
                    prop_assert_eq!(wn.iter().map(|v| BigInt::from(*v)).collect::<Vec<_>>(), num);
                    prop_assert_eq!(BigInt::from(wd), den);
                }
            }
        }
    }

    /// Explicit zeros naming another component are not placed; a zero right-hand side of a
    /// block is zero over denominator one.
    #[test]
    fn explicit_zeros_and_zero_blocks() {
        // Components {0, 2} and {1}; row 1 holds an explicit zero at column 2.
        let rows = vec![
            vec![(0, 2), (2, 1)],
            vec![(1, 2), (2, 0)],
            vec![(0, 1), (2, 2)],
        ];
        let f = SmallBareiss::factor(3, &rows).expect("SPD blocks");
        assert_eq!(f.parts.len(), 2);
        // [[2, 1], [1, 2]] y = [1, 0] and 2 z = 0: (2/3, 0, −1/3).
        let (num, den) = f.solve_words(&[1, 0, 0]).expect("small");
        assert_eq!((num, den), (vec![2, 0, -1], 3));
        // 2 z = 1 and the other block zero: (0, 1/2, 0).
        let (num, den) = f.solve_words(&[0, 1, 0]).expect("small");
        assert_eq!((num, den), (vec![0, 1, 0], 2));
        // Both: (2/3, 1/2, −1/3) over 6, and (2/3, 1, −1/3) over 3.
        let (num, den) = f.solve_words(&[1, 1, 0]).expect("small");
        assert_eq!((num, den), (vec![4, 3, -2], 6));
        let (num, den) = f.solve_words(&[1, 2, 0]).expect("small");
        assert_eq!((num, den), (vec![2, 3, -1], 3));
    }
}
