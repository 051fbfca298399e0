//! Substitution of trivial equalities before factoring: rows of `R_ED` with one or two
//! unknowns and coefficients `±1` (a coincidence `x_u − x_v = b`, a horizontal or vertical
//! alignment, an unknown pinned to a value) are solved by substitution, exactly, the way
//! SolveSpace's `SolveBySubstitution` does in floating point.
//!
//! A row whose right-hand side depends on the anchors is substituted only when it pins one
//! unknown (`±x_u = b − K_i α`: an unknown tied to an anchor, the commonest case in a drag).
//! Such a pin hangs from the ground, so it moves only the unknowns of the ground's trees; the
//! offsets of every group are constants of the edit and the inner least squares sees the same
//! hints in every drag frame. Trivial rows are substituted only when they are at least a
//! quarter of the rows.
//!
//! The unknowns and those rows form a graph (plus a *ground* node for one-unknown rows). A
//! breadth-first spanning forest — from the ground first, then from each remaining unknown in
//! increasing order — gives every unknown the form
//!
//! ```text
//! x_u = σ_u y_g + τ_u      (σ_u = ±1, y_g the unknown of its tree's root)
//! x_u = τ_u − s_u K_r α     (trees hanging from the ground)
//! ```
//!
//! with `τ_u` from the right-hand sides along the tree path and, below a pin on the anchors
//! (row `r`), `s_u = ±1` its sign carried down the path (no anchor term below other pins). The tree rows are
//! independent and hold by construction; every other row — the rows with more unknowns and the
//! trivial rows that close a cycle — keeps its place in the *inner* system over the `y_g`, with
//! `x_u` substituted: `R' y = b'(α)`, integer; a kept row `i` touching pinned unknowns has the
//! anchor coefficients `K_i − Σ_u a_iu s_u K_{r_u}`. Least squares
//! carries over exactly: `Σ_{u∈g} w_u (σ_u y_g + τ_u − h_u)² = W_g (y_g − h̄_g)² + const` with
//! `W_g = Σ w_u` and `h̄_g = Σ w_u σ_u (h_u − τ_u) / W_g`.
//!
//! Answers about the inner system are mapped back to the rows of `R_ED`: the inner rows keep
//! their identity, the tree rows are independent, and a combination or certificate over inner
//! rows, `z = yᵀ A_inner` over the unknowns, is completed by the tree rows that cancel `z`
//! (leaves first, one row per unknown, coefficients `±1`): the same proof over the original
//! rows.

use crate::hint_columns::HintColumn;
use crate::reduce::ReducedSystem;
use api::{
    rational_difference, rational_over_integer, rational_sum, rational_times_integer, IntMatrix,
    Integer, Rational, RhsFamily, Value,
};
use num_traits::{One, Zero};
use std::collections::VecDeque;
use std::sync::Arc;

/// Trivial rows are substituted when they are at least `1 / SUBSTITUTE_FRACTION` of the rows.
const SUBSTITUTE_FRACTION: usize = 4;

/// One row solved by substitution: `child_coef · x_child + parent_coef · x_parent = b_row`
/// (no parent: the row pins `x_child`).
#[derive(Debug, Clone, PartialEq)]
struct TreeRow {
    row: usize,
    child: usize,
    child_coef: i8,
    parent: Option<(usize, i8)>,
}

/// The substitution of one reduced system (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Substitution {
    /// Per unknown of `R_ED`: its group (`None`: pinned through the ground) and `σ_u`.
    group: Vec<Option<usize>>,
    sign: Vec<i8>,
    /// `τ_u` per right-hand-side column `j`: `offset[j][u]`, the constant part of the offset
    /// (`None` for zero, the common case: a zero rational would cost an allocation).
    offset: Vec<Vec<Option<Rational>>>,
    /// Per unknown hanging below a pin on the anchors: that pin's row `r` of `R_ED` and `s_u`,
    /// the anchor part of the offset being `−s_u K_r α`.
    anchor_pin: Vec<Option<(usize, i8)>>,
    /// The rows solved by substitution, parents before children.
    tree: Vec<TreeRow>,
    /// Inner row `k` is row `kept[k]` of `R_ED`.
    kept: Vec<usize>,
    /// The inner system over the groups.
    inner: ReducedSystem,
    /// `W_g`.
    group_weights: Vec<Rational>,
    /// The last hints per column and the groups' hints from them: a drag keeps its hints,
    /// so each frame finds them here.
    hint_memo: HintMemo,
}

/// The memo of [`Substitution::group_hints`]; copies start empty and all memos compare equal
/// (a memo never changes an answer).
#[derive(Debug, Default)]
struct HintMemo(Vec<std::sync::Mutex<Option<HintsAndGroups>>>);

/// Hints of the unknowns and the groups' hints from them (shared: a drag frame reads them
/// without copying).
type HintsAndGroups = (HintColumn, Arc<Vec<Rational>>);

impl Clone for HintMemo {
    fn clone(&self) -> Self {
        HintMemo((0..self.0.len()).map(|_| Default::default()).collect())
    }
}

impl PartialEq for HintMemo {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// `value · sign` for `sign = ±1`: a copy or a negation.
fn signed(value: &Rational, sign: i8) -> Rational {
    if sign > 0 {
        value.clone()
    } else {
        -value
    }
}

/// The coefficient of a trivial row's unknowns (`±1`) as `i8`.
fn unit(v: &Integer) -> Option<i8> {
    if v.is_one() {
        Some(1)
    } else if (-v).is_one() {
        Some(-1)
    } else {
        None
    }
}

impl Substitution {
    /// The substitution of `reduced` with weights `weights` (one per unknown); `None` when no
    /// row is trivial (nothing to substitute).
    pub(crate) fn new(reduced: &ReducedSystem, weights: &[Rational]) -> Option<Self> {
        let r_ed = &reduced.r_ed;
        let (m, n) = (r_ed.rows(), r_ed.cols());
        // Trivial rows: two unknowns and a right-hand side that does not depend on the anchors
        // (groups' offsets are constants of the edit, so the groups' hints do not change from
        // one drag frame to the next and the factored system's memo of its base solution keeps
        // working), or one unknown (a pin, on the anchors or not: it hangs from the ground).
        let trivial: Vec<bool> = r_ed
            .row_iter()
            .zip(reduced.family.coefficients.row_iter())
            .map(|(row, anchors)| {
                let size = if anchors.is_empty() { 1..=2 } else { 1..=1 };
                size.contains(&row.len()) && row.iter().all(|(_, v)| unit(v).is_some())
            })
            .collect();
        // Worth it only when it removes a good part of the rows (a few trivial rows in a large
        // system would cost a pass over every unknown per update for little gain).
        let count = trivial.iter().filter(|t| **t).count();
        if count == 0 || count * SUBSTITUTE_FRACTION < m {
            return None;
        }
        let mut pins: Vec<usize> = Vec::new();
        let mut anchor_pins: Vec<usize> = Vec::new();
        // The trivial rows of two unknowns at each unknown, as flat lists: unknown `u`'s are
        // `row_at[start[u]..start[u + 1]]` (counted, then placed; a list per unknown cost a
        // small edit more than the search).
        let mut start = vec![0usize; n + 1];
        for (i, row) in r_ed.row_iter().enumerate() {
            if !trivial[i] {
                continue;
            }
            match row {
                [_] if reduced.family.coefficients.row(i).is_empty() => pins.push(i),
                [_] => anchor_pins.push(i),
                _ => {
                    for (u, _) in row {
                        start[*u + 1] += 1;
                    }
                }
            }
        }
        for u in 0..n {
            start[u + 1] += start[u];
        }
        let mut row_at = vec![0usize; start[n]];
        let mut filled = start.clone();
        for (i, row) in r_ed.row_iter().enumerate() {
            if trivial[i] && row.len() == 2 {
                for (u, _) in row {
                    row_at[filled[*u]] = i;
                    filled[*u] += 1;
                }
            }
        }
        let rows_of = |u: usize| &row_at[start[u]..start[u + 1]];
        let columns = reduced.family.constant.len();
        let mut group = vec![None; n];
        let mut sign = vec![0i8; n];
        let mut offset: Vec<Vec<Option<Rational>>> = vec![vec![None; n]; columns];
        let mut anchor_pin: Vec<Option<(usize, i8)>> = vec![None; n];
        let mut visited = vec![false; n];
        let mut used = vec![false; m];
        let mut tree = Vec::new();
        let mut groups = 0;
        // x_child from the row and its parent (module documentation).
        let mut attach = |edge: TreeRow,
                          sign: &mut Vec<i8>,
                          group: &mut Vec<Option<usize>>,
                          offset: &mut Vec<Vec<Option<Rational>>>,
                          anchor_pin: &mut Vec<Option<(usize, i8)>>| {
            // b · child_coef, child_coef = ±1.
            let constant = |column: usize| {
                let b = &reduced.family.constant[column][edge.row];
                (!b.is_zero()).then(|| signed(b, edge.child_coef))
            };
            match edge.parent {
                None => {
                    sign[edge.child] = 0;
                    group[edge.child] = None;
                    for (column, t) in offset.iter_mut().enumerate() {
                        t[edge.child] = constant(column);
                    }
                    // x = c (b_i − K_i α) for coefficient c = ±1: s = c.
                    anchor_pin[edge.child] =
                        (!reduced.family.coefficients.row(edge.row).is_empty())
                            .then_some((edge.row, edge.child_coef));
                }
                Some((p, cp)) => {
                    let flip = -edge.child_coef * cp;
                    sign[edge.child] = flip * sign[p];
                    group[edge.child] = group[p];
                    anchor_pin[edge.child] = anchor_pin[p].map(|(r, s)| (r, s * flip));
                    for (column, t) in offset.iter_mut().enumerate() {
                        let carried = t[p].as_ref().map(|v| signed(v, flip));
                        t[edge.child] = match (constant(column), carried) {
                            (Some(a), Some(b)) => {
                                Some(rational_sum(&a, &b)).filter(|v| !v.is_zero())
                            }
                            (a, b) => a.or(b),
                        };
                    }
                }
            }
            tree.push(edge);
        };
        let mut queue = VecDeque::new();
        // Trees hanging from the ground first; pins with constant right-hand sides before those
        // on the anchors (the tree then has constant offsets where it can).
        for &i in pins.iter().chain(&anchor_pins) {
            let (u, v) = &r_ed.row(i)[0];
            if visited[*u] {
                continue;
            }
            visited[*u] = true;
            used[i] = true;
            attach(
                TreeRow {
                    row: i,
                    child: *u,
                    child_coef: unit(v).unwrap_or(1),
                    parent: None,
                },
                &mut sign,
                &mut group,
                &mut offset,
                &mut anchor_pin,
            );
            queue.push_back(*u);
        }
        let mut roots = (0..n).peekable();
        loop {
            while let Some(p) = queue.pop_front() {
                for &i in rows_of(p) {
                    if used[i] {
                        continue;
                    }
                    let row = r_ed.row(i);
                    let (a, b) = (&row[0], &row[1]);
                    let ((c, cv), (q, qv)) = if a.0 == p { (b, a) } else { (a, b) };
                    if *q != p || visited[*c] {
                        continue;
                    }
                    visited[*c] = true;
                    used[i] = true;
                    attach(
                        TreeRow {
                            row: i,
                            child: *c,
                            child_coef: unit(cv).unwrap_or(1),
                            parent: Some((p, unit(qv).unwrap_or(1))),
                        },
                        &mut sign,
                        &mut group,
                        &mut offset,
                        &mut anchor_pin,
                    );
                    queue.push_back(*c);
                }
            }
            let Some(root) = roots.by_ref().find(|&u| !visited[u]) else {
                break;
            };
            visited[root] = true;
            group[root] = Some(groups);
            sign[root] = 1;
            groups += 1;
            queue.push_back(root);
        }
        // The inner system: every row not in the forest, unknowns substituted.
        let kept: Vec<usize> = (0..m).filter(|&i| !used[i]).collect();
        let mut inner_rows = Vec::with_capacity(kept.len());
        let mut inner_k = Vec::with_capacity(kept.len());
        let mut inner_c: Vec<Vec<Rational>> = vec![Vec::with_capacity(kept.len()); columns];
        for &i in &kept {
            let mut entries: Vec<(usize, Integer)> = Vec::new();
            let mut c: Vec<Rational> = (0..columns)
                .map(|column| reduced.family.constant[column][i].clone())
                .collect();
            let mut k = reduced.family.coefficients.row(i).to_vec();
            for (u, a) in r_ed.row(i) {
                if let Some(g) = group[*u] {
                    entries.push((g, a * Integer::from(sign[*u])));
                }
                // a x_u contributes −a s_u K_r α to the left: K_i − a s_u K_r (summed per
                // anchor by `from_sparse`).
                if let Some((r, s)) = anchor_pin[*u] {
                    let factor = a * Integer::from(s);
                    k.extend(
                        reduced
                            .family
                            .coefficients
                            .row(r)
                            .iter()
                            .map(|(j, kr)| (*j, -(&factor * kr))),
                    );
                }
                for (column, cj) in c.iter_mut().enumerate() {
                    if let Some(t) = &offset[column][*u] {
                        *cj = rational_difference(cj, &rational_times_integer(t, a));
                    }
                }
            }
            inner_rows.push(entries);
            inner_k.push(k);
            for (column, cj) in inner_c.iter_mut().zip(c) {
                column.push(cj);
            }
        }
        let mut group_weights = vec![Rational::zero(); groups];
        for (u, g) in group.iter().enumerate() {
            if let Some(g) = g {
                group_weights[*g] = rational_sum(&group_weights[*g], &weights[u]);
            }
        }
        // A group whose members all have zero weight cannot happen: weights are positive.
        let inner = ReducedSystem {
            layout: reduced.layout,
            r_ed: IntMatrix::from_sparse(groups, inner_rows).expect("groups index the columns"),
            family: RhsFamily {
                constant: inner_c,
                coefficients: IntMatrix::from_sparse(reduced.family.coefficients.cols(), inner_k)
                    .expect("anchor columns are those of R_EA"),
            },
            rows: kept.iter().map(|&i| reduced.rows[i]).collect(),
            labels: kept.iter().map(|&i| reduced.labels[i].clone()).collect(),
        };
        Some(Substitution {
            group,
            sign,
            offset,
            anchor_pin,
            tree,
            kept,
            inner,
            group_weights,
            hint_memo: HintMemo((0..columns).map(|_| Default::default()).collect()),
        })
    }

    /// The inner system over the groups.
    pub(crate) fn inner(&self) -> &ReducedSystem {
        &self.inner
    }

    /// `W_g` per group.
    pub(crate) fn group_weights(&self) -> &[Rational] {
        &self.group_weights
    }

    /// Rows solved by substitution (rows of `R_ED`).
    pub(crate) fn tree_rows(&self) -> impl Iterator<Item = usize> + '_ {
        self.tree.iter().map(|t| t.row)
    }

    /// Row `k` of the inner system as a row of `R_ED`.
    pub(crate) fn original_row(&self, k: usize) -> usize {
        self.kept[k]
    }

    /// The hints of the groups, `h̄_g = Σ w_u σ_u (h_u − τ_u) / W_g`, for right-hand-side
    /// column `column`: from the memo when `hints` are the last ones — the same gathering of
    /// hints (a drag), or number for number the same (a comparison of representations: equal
    /// rationals in lowest terms are identical).
    pub(crate) fn group_hints(
        &self,
        weights: &[Rational],
        hints: &HintColumn,
        column: usize,
    ) -> Arc<Vec<Rational>> {
        let memo = &self.hint_memo.0[column];
        if let Ok(guard) = memo.lock() {
            if let Some((last, groups)) = guard.as_ref() {
                if last.same_as(hints) || api::identical_rationals(last, hints) {
                    return Arc::clone(groups);
                }
            }
        }
        let groups = Arc::new(self.compute_group_hints(weights, hints, column));
        if let Ok(mut guard) = memo.lock() {
            *guard = Some((hints.clone(), Arc::clone(&groups)));
        }
        groups
    }

    fn compute_group_hints(
        &self,
        weights: &[Rational],
        hints: &[Rational],
        column: usize,
    ) -> Vec<Rational> {
        let mut sums = vec![Rational::zero(); self.group_weights.len()];
        for (u, g) in self.group.iter().enumerate() {
            let Some(g) = g else {
                continue;
            };
            let shifted = match &self.offset[column][u] {
                None => hints[u].clone(),
                Some(offset) => rational_difference(&hints[u], offset),
            };
            let term = if weights[u].is_one() {
                shifted
            } else {
                &weights[u] * shifted
            };
            sums[*g] = rational_sum(&sums[*g], &signed(&term, self.sign[u]));
        }
        sums.into_iter()
            .zip(&self.group_weights)
            .map(|(s, w)| {
                if w.is_one() {
                    s
                } else if w.is_integer() {
                    rational_over_integer(&s, w.numer())
                } else {
                    s / w
                }
            })
            .collect()
    }

    /// The unknowns of `R_ED` from the groups' values `y` (column `column`, anchor values
    /// `alpha`): `x_u = σ_u y_g + τ_u`, or `τ_u − s_u K_r α` below a pin.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn expand<T: Clone>(
        &self,
        y: &[T],
        column: usize,
        alpha: &[Rational],
        coefficients: &IntMatrix,
        from_rational: impl Fn(&Rational) -> T,
        plus: impl Fn(T, T) -> T,
        negate: impl Fn(T) -> T,
    ) -> Vec<T> {
        self.group
            .iter()
            .enumerate()
            .map(|(u, g)| {
                let offset = &self.offset[column][u];
                match g {
                    None => match self.anchor_pin[u] {
                        None => from_rational(offset.as_ref().unwrap_or(&Rational::zero())),
                        Some((r, s)) => {
                            let mut value = offset.clone().unwrap_or_else(Rational::zero);
                            for (j, k) in coefficients.row(r) {
                                let term = rational_times_integer(&alpha[*j], k);
                                value = if s > 0 {
                                    rational_difference(&value, &term)
                                } else {
                                    rational_sum(&value, &term)
                                };
                            }
                            from_rational(&value)
                        }
                    },
                    Some(g) => {
                        let value = y[*g].clone();
                        let value = if self.sign[u] > 0 {
                            value
                        } else {
                            negate(value)
                        };
                        match offset {
                            None => value,
                            Some(offset) => plus(value, from_rational(offset)),
                        }
                    }
                }
            })
            .collect()
    }

    /// The tree rows completing a combination over rows of `R_ED`: with `z = Σ y_i A_i` (the
    /// given rows, coefficients `S`), the coefficients `f_e` of the tree rows with
    /// `z = Σ f_e A_e` (for the images of inner combinations and certificates `z` is in their
    /// span: its sum over every group, signed, is zero).
    pub(crate) fn complete<S: Value>(
        &self,
        r_ed: &IntMatrix,
        combination: &[(usize, S)],
    ) -> Vec<(usize, S)> {
        let n = self.group.len();
        let mut z: Vec<Option<S>> = vec![None; n];
        for (i, y) in combination {
            for (u, a) in r_ed.row(*i) {
                let term = y.clone() * S::from_rational(&Rational::from_integer(a.clone()));
                z[*u] = Some(match z[*u].take() {
                    Some(v) => v + term,
                    None => term,
                });
            }
        }
        let mut out = Vec::new();
        for edge in self.tree.iter().rev() {
            let Some(zc) = z[edge.child].take() else {
                continue;
            };
            // f_e · child_coef = z_child, child_coef = ±1.
            let f = if edge.child_coef > 0 { zc } else { -zc };
            if let Some((p, cp)) = edge.parent {
                let carried = if cp > 0 { f.clone() } else { -f.clone() };
                z[p] = Some(match z[p].take() {
                    Some(v) => v + -carried,
                    None => -carried,
                });
            }
            out.push((edge.row, f));
        }
        // What is left vanishes (exactly for an exact backend: roots and unknowns outside the
        // forest are not touched by the images of inner combinations and certificates).
        debug_assert!(z
            .iter()
            .flatten()
            .all(|v| v.to_exact().is_none_or(|x| x.is_zero())));
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::edit::Edit;
    use crate::EditSpec;
    use api::{ConstraintRow, ConstraintSystem, Coord, Origin, ParamId, Rational, RowBody, Values};
    use exact_ldu::{ExactFactorization, ExactLdu};
    use num_bigint::BigInt;
    use proptest::prelude::*;

    type Row = Vec<(usize, i64)>;

    /// A system over `n` scalar parameters with values `x` (every row holds): trivial rows
    /// (`±x_u ± x_v = c`, `±x_u = c`, cycles included) mixed with rows of three or four terms.
    fn system(n: usize, x: &[i64], rows: &[Row]) -> (ConstraintSystem, Vec<ParamId>, Values) {
        let mut s = ConstraintSystem::new();
        let params: Vec<ParamId> = (0..n)
            .map(|i| s.add_parameter(format!("p{i}"), 1).expect("fresh"))
            .collect();
        for (k, row) in rows.iter().enumerate() {
            let rhs: i64 = row.iter().map(|(u, a)| a * x[*u]).sum();
            s.add_row(ConstraintRow {
                label: format!("r{k}"),
                origin: Origin::default(),
                body: RowBody::Scalar {
                    terms: row
                        .iter()
                        .map(|(u, a)| {
                            (
                                Coord {
                                    param: params[*u],
                                    component: 0,
                                },
                                BigInt::from(*a),
                            )
                        })
                        .collect(),
                    rhs: BigInt::from(rhs),
                },
            })
            .expect("valid");
        }
        let values = Values::from_vecs(
            &s,
            x.iter()
                .map(|v| vec![Rational::from_integer((*v).into())])
                .collect(),
        )
        .expect("values");
        (s, params, values)
    }

    fn rows(n: usize) -> impl Strategy<Value = Vec<Row>> {
        let sign = prop_oneof![Just(1i64), Just(-1i64)];
        let trivial = prop_oneof![
            (0..n, sign.clone(), 0..n, sign.clone())
                .prop_filter("two unknowns", |(u, _, v, _)| u != v)
                .prop_map(|(u, a, v, b)| vec![(u, a), (v, b)]),
            (0..n, sign).prop_map(|(u, a)| vec![(u, a)]),
        ];
        let general = prop::collection::vec((0..n, -4i64..=4), 3..=4)
            .prop_map(|t| t.into_iter().filter(|(_, a)| *a != 0).collect::<Vec<_>>());
        prop::collection::vec(prop_oneof![3 => trivial, 2 => general], 1..=12)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]

        /// Substituting trivial rows changes nothing an edit answers: the same exact values and
        /// previews, the same rank, redundant rows whose combinations reproduce them, and
        /// refusals with certificates that are proofs over the original rows.
        #[test]
        fn substitution_gives_the_same_answers(
            x in prop::collection::vec(-5i64..=5, 8),
            rows in rows(8),
            anchor in 0usize..8,
            second in prop::option::of(0usize..8),
            moved in (-3i64..=3, -3i64..=3),
            weights in prop::collection::vec(1i64..=4, 7),
            strong in any::<bool>(),
        ) {
            let n = x.len();
            let (s, p, values) = system(n, &x, &rows);
            // One or two anchors (pins on the anchors hang from the ground).
            let mut anchors = vec![anchor];
            anchors.extend(second.filter(|&b| b != anchor));
            let derived: Vec<ParamId> =
                (0..n).filter(|i| !anchors.contains(i)).map(|i| p[i]).collect();
            let mut spec = EditSpec::new(anchors.iter().map(|&a| p[a]).collect(), derived.clone())
                .with_weights(
                    weights[..derived.len()].iter().map(|w| Rational::from_integer((*w).into())).collect(),
                );
            if strong {
                spec = spec.strong();
            }
            let backend = ExactLdu::default();
            // The strong check alone answers as the substituted and plain initialisations do.
            let check = Edit::<ExactFactorization>::check_strongly_solvable(&backend, &s, &values, &spec);
            let plain = Edit::<ExactFactorization>::initialize_with(&backend, &s, &values, &spec, false);
            let subst = Edit::<ExactFactorization>::initialize_with(&backend, &s, &values, &spec, true);
            if strong {
                prop_assert_eq!(check.is_ok(), plain.is_ok());
            }
            let (plain, subst) = match (plain, subst) {
                (Ok(a), Ok(b)) => (a, b),
                (Err(_), Err(_)) => return Ok(()),
                (a, b) => return Err(TestCaseError::fail(format!("{:?} vs {:?}", a.is_ok(), b.is_ok()))),
            };
            let (rp, rs) = (plain.report(), subst.report());
            prop_assert_eq!(rp.rank, rs.rank);
            prop_assert_eq!(rp.redundant.len(), rs.redundant.len());
            // Every reported combination reproduces its row over the derived parameters.
            let derived_set: std::collections::BTreeSet<ParamId> = derived.iter().copied().collect();
            let dense = |row: usize| -> Vec<Rational> {
                let mut v = vec![Rational::from_integer(0.into()); n];
                if let RowBody::Scalar { terms, .. } = &s.rows()[row].body {
                    for (c, a) in terms {
                        if derived_set.contains(&c.param) {
                            v[c.param.index()] += Rational::from_integer(a.clone());
                        }
                    }
                }
                v
            };
            for (t, combination) in &rs.redundant {
                let mut sum = vec![Rational::from_integer(0.into()); n];
                for (k, c) in combination {
                    for (acc, v) in sum.iter_mut().zip(dense(k.row.index())) {
                        *acc += c * v;
                    }
                }
                prop_assert_eq!(sum, dense(t.row.index()));
            }
            let target: Vec<Vec<Rational>> = anchors
                .iter()
                .zip([moved.0, moved.1])
                .map(|(&a, m)| vec![Rational::from_integer((x[a] + m).into())])
                .collect();
            let hints: Vec<Vec<Rational>> = derived.iter().map(|q| values.get(*q).to_vec()).collect();
            match (plain.update(&target, &hints), subst.update(&target, &hints)) {
                (Ok(a), Ok(b)) => {
                    prop_assert_eq!(&a, &b);
                    let preview = subst.preview(&target, &hints).expect("same verdict");
                    let exact: Vec<f64> = b.derived.iter().map(|(_, v)| api::exact::rational_to_f64(&v[0])).collect();
                    prop_assert_eq!(preview.iter().map(|v| v[0]).collect::<Vec<_>>(), exact);
                    let frame = subst.frame(&target, &hints).expect("same verdict");
                    prop_assert_eq!(
                        frame.iter().map(|v| v[0].reduced()).collect::<Vec<_>>(),
                        b.derived.iter().map(|(_, v)| v[0].clone()).collect::<Vec<_>>()
                    );
                }
                (Err(a), Err(b)) => {
                    // The certificate is a proof over the original rows: yᵀ R_ED = 0.
                    if let Some(conflict) = b.conflict() {
                        let mut sum = vec![Rational::from_integer(0.into()); n];
                        for r in &conflict.rows {
                            for (acc, v) in sum.iter_mut().zip(dense(r.row.row.index())) {
                                *acc += &r.multiplier * v;
                            }
                        }
                        prop_assert!(sum.iter().all(|v| *v == Rational::from_integer(0.into())), "{:?}", conflict);
                        prop_assert!(conflict.discrepancy != Rational::from_integer(0.into()));
                    }
                    prop_assert_eq!(a.conflict().is_some(), b.conflict().is_some());
                }
                (a, b) => prop_assert!(false, "{:?} vs {:?}", a.is_ok(), b.is_ok()),
            }
        }
    }
}
