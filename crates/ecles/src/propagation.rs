//! How a change propagates (Brenner, section 3.1): for picked parameters `P` of a system
//! `A x = b`, exactly,
//!
//! * **the case**: in which directions `P` can move at all — the projection onto `P` of the
//!   null space of `A` — fully constrained (none), partially constrained (a basis of the
//!   directions, fewer than `P` has coordinates) or free; for each lost direction, the
//!   constraints that remove it (a combination `yᵀ A` that is zero off `P` and not orthogonal
//!   to the direction: those rows tie `P` there);
//! * **propagation of a move** `δ_P`: the moves `δ` with `A δ = 0` and `δ` equal to `δ_P` on
//!   `P` form an affine set. Per other parameter it is a point — the parameter is *forced* to
//!   move by exactly that (or *stays*, when it is zero) — or an affine subspace of some
//!   dimension, which the parameter *may* leave at zero or, when the subspace misses zero,
//!   *must move with a choice*. A move outside the directions is refused with the rows in the
//!   way (the backend's inconsistency certificate).
//!
//! Only the connected component(s) of `P` (coordinates linked to `P` through rows) are looked
//! at: every other parameter stays whatever `P` does. Coordinates that rows `±x_i ± x_j = 0`
//! tie (coincidences, alignments) are merged first (module `equalities`): the solves below run on
//! the merged `M`, which has the same answers, and only what names rows of `A` uses `A`
//! itself. Everything is read off one exact factorization of `M = [A; E_P]` (the component's
//! rows and one row per picked coordinate):
//!
//! * the directions by at most `|P|` consistency checks of `M δ = [0; m]`
//!   ([`reachable_directions`]): each either reaches `m` or returns a certificate whose `P` part
//!   is a lost direction not orthogonal to `m`;
//! * the move's particular solution by one more solve, its freedom by the null space of `M`,
//!   dense: `n − rank M` vectors of `n` exact values for a component of `n` coordinates;
//! * the rows removing each lost direction by a factorization of `Aᵀ`, only when a direction
//!   is lost.
//!
//! A small `M` (at most [`words::MAX_COLUMNS`] columns) whose values stay in an `i64` is not
//! factored by the backend at all: one fraction-free Gauss–Jordan elimination in machine words
//! gives the directions, the particular solution and the null space at once (module `words`;
//! what the report reads off them is the same for every exact method). A blocked move, or a
//! value outside an `i64`, takes the backend's factorization as above.
//!
//! (The null space of `A` itself, `|P|` vectors more than that of `M` at most, is not formed:
//! its lifted solves were half of every edit's analysis.) The caller gives the most null-space
//! values it accepts ([`EXPLAIN_NULL_SPACE_BUDGET`] for `ecles explain`,
//! [`REPORT_NULL_SPACE_BUDGET`] for every edit's report); a larger component is refused before
//! its null space is formed.

use api::{
    ConstraintSystem, Factorization, IntMatrix, Integer, IntegerNullSpace, LinearBackend, ParamId,
    Rational, RowId, SolveError,
};
use num_traits::{One, Signed, Zero};

mod equalities;
mod words;
use equalities::Equalities;
use words::{WordElimination, WordFraction};

/// Most null-space values (`(n − r)·n`) an explicit analysis forms: about 2·10⁶ (a component
/// of 1 400 free coordinates; seconds and hundreds of MB).
pub const EXPLAIN_NULL_SPACE_BUDGET: usize = 2_000_000;

/// Most null-space values the analysis of every edit in a report forms (milliseconds).
pub const REPORT_NULL_SPACE_BUDGET: usize = 50_000;

/// Why a propagation analysis could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PropagationError {
    /// No parameter was picked, or one twice, or one that does not exist.
    #[error("{0}")]
    Picked(String),
    /// The requested move has another number of coordinates than the picked parameters.
    #[error("the move has {found} coordinates, the picked parameters have {expected}")]
    MoveSize {
        /// Coordinates of the picked parameters.
        expected: usize,
        /// Coordinates given.
        found: usize,
    },
    /// The component's null space has more values than the budget.
    #[error("the picked parameters are tied to {coordinates} coordinates with a null space of {values} values, more than the {budget} this analysis forms")]
    TooLarge {
        /// Coordinates of the component.
        coordinates: usize,
        /// Values of the null space it would form.
        values: usize,
        /// The caller's budget.
        budget: usize,
    },
    /// The backend failed.
    #[error("the backend failed: {0}")]
    Backend(String),
}

/// Brenner's three cases for the picked parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    /// They cannot move at all.
    FullyConstrained,
    /// They can move in some directions only.
    PartiallyConstrained,
    /// They can move in every direction.
    Free,
}

/// A combination of scalar rows: `(row, coordinate of a vector row, multiplier)`.
pub type RowCombination = Vec<(RowId, usize, Rational)>;

/// A direction of the picked coordinates that no move can take, and the rows that remove it.
#[derive(Debug, Clone, PartialEq)]
pub struct LostDirection {
    /// The direction, over the picked coordinates (integers, coprime).
    pub direction: Vec<Integer>,
    /// Rows whose combination `yᵀ A` vanishes off the picked coordinates and is not orthogonal
    /// to the direction.
    pub rows: RowCombination,
}

/// How one other parameter follows a move.
#[derive(Debug, Clone, PartialEq)]
pub enum Follows {
    /// It must move by exactly this (per coordinate).
    Forced(Vec<Rational>),
    /// Its move is free in `freedom` dimensions, and zero is among the possible moves.
    MayStay {
        /// Dimension of its possible moves.
        freedom: usize,
    },
    /// Its move is free in `freedom` dimensions, but zero is not among them.
    MustMoveWithChoice {
        /// Dimension of its possible moves.
        freedom: usize,
    },
}

/// What a requested move does.
#[derive(Debug, Clone, PartialEq)]
pub enum MoveOutcome {
    /// No move of the system takes the picked parameters there: the rows in the way.
    Blocked(RowCombination),
    /// The parameters of the component that do not simply stay (a parameter not listed is
    /// forced to stay), in parameter order.
    Moves(Vec<(ParamId, Follows)>),
}

/// The analysis of picked parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Propagation {
    /// The picked coordinates, `(parameter, coordinate)`, in order.
    pub picked: Vec<(ParamId, usize)>,
    /// Brenner's case.
    pub case: Case,
    /// A basis of the directions the picked coordinates can move in (integers, coprime).
    pub directions: Vec<Vec<Integer>>,
    /// The directions they cannot move in, with the rows that remove each.
    pub lost: Vec<LostDirection>,
    /// Scalar coordinates of the component the picked parameters belong to.
    pub component: usize,
    /// What the requested move does, when one was given.
    pub outcome: Option<MoveOutcome>,
}

/// The propagation analysis of `picked` in `system`, with `backend`; with `requested`, the
/// move of every picked coordinate in order; forming at most `budget` null-space values (see
/// the module documentation).
pub fn analyze_propagation<B>(
    backend: &B,
    system: &ConstraintSystem,
    picked: &[ParamId],
    requested: Option<&[Rational]>,
    budget: usize,
) -> Result<Propagation, PropagationError>
where
    B: LinearBackend,
    B::Factorization: Factorization<Scalar = Rational> + IntegerNullSpace,
{
    analyze(
        backend,
        system,
        picked,
        requested,
        budget,
        Solving {
            merge_equalities: true,
            in_words: true,
        },
    )
}

/// How [`analyze`] solves; the answers are the same either way (tests compare them).
#[derive(Debug, Clone, Copy)]
struct Solving {
    /// On coordinates merged by equalities (module `equalities`).
    merge_equalities: bool,
    /// A small `M` in machine words (module `words`).
    in_words: bool,
}

/// [`analyze_propagation`], solving as `solving` says.
fn analyze<B>(
    backend: &B,
    system: &ConstraintSystem,
    picked: &[ParamId],
    requested: Option<&[Rational]>,
    budget: usize,
    solving: Solving,
) -> Result<Propagation, PropagationError>
where
    B: LinearBackend,
    B::Factorization: Factorization<Scalar = Rational> + IntegerNullSpace,
{
    let params = system.params();
    if picked.is_empty() {
        return Err(PropagationError::Picked(
            "pick at least one parameter".into(),
        ));
    }
    for (k, p) in picked.iter().enumerate() {
        if p.index() >= params.len() {
            return Err(PropagationError::Picked(format!("no parameter {}", p.0)));
        }
        if picked[..k].contains(p) {
            return Err(PropagationError::Picked(format!(
                "{} is picked twice",
                params[p.index()].name
            )));
        }
    }
    let offsets = system.coordinate_offsets();
    let picked_coordinates: Vec<(ParamId, usize)> = picked
        .iter()
        .flat_map(|&p| (0..params[p.index()].dim).map(move |k| (p, k)))
        .collect();
    if let Some(m) = requested {
        if m.len() != picked_coordinates.len() {
            return Err(PropagationError::MoveSize {
                expected: picked_coordinates.len(),
                found: m.len(),
            });
        }
    }
    let Component { a, origin, columns } =
        Component::of(system, &offsets, picked_coordinates.iter().copied())?;
    // A move's null space has at least `n − rows − |P|` vectors (`M` has full row rank at
    // best): refused before anything is factored. Without a move no null space is formed.
    let n = columns.len();
    let least = n.saturating_mul(n.saturating_sub(a.rows() + picked_coordinates.len()));
    if requested.is_some() && least > budget {
        return Err(PropagationError::TooLarge {
            coordinates: n,
            values: least,
            budget,
        });
    }
    let picked_local: Vec<usize> = picked_coordinates
        .iter()
        .map(|&(p, k)| {
            // The component starts from the picked coordinates, so it holds each of them.
            columns
                .binary_search(&(offsets[p.index()] + k))
                .map_err(|_| {
                    PropagationError::Backend("a picked coordinate left its component".into())
                })
        })
        .collect::<Result<_, _>>()?;
    let factor = |m: &IntMatrix| {
        backend
            .factor_for_solves(m)
            .map_err(|e| PropagationError::Backend(e.to_string()))
    };
    let row_of = |i: usize| -> (RowId, usize) { origin[i] };
    let combination = |rows: Vec<(usize, Rational)>| -> RowCombination {
        rows.into_iter()
            .map(|(i, y)| {
                let (row, k) = row_of(i);
                (row, k, y)
            })
            .collect()
    };
    let coordinate_of = |i: usize| {
        let c = columns[i];
        // The parameter and coordinate of component column `i`.
        let p = offsets.partition_point(|&o| o <= c) - 1;
        (ParamId(p as u32), c - offsets[p])
    };
    // M = [A; E_P]: its solves give the directions P can move in (ker A projected on P) and
    // the move's particular solution, its null space the move's freedom.
    let with_picked = |a: &IntMatrix, picked_rows: &[Vec<(usize, Integer)>]| {
        let mut m = a.clone();
        for row in picked_rows {
            m.push_row(row.clone())
                .map_err(|e| PropagationError::Backend(e.to_string()))?;
        }
        factor(&m)
    };
    let whole_picked_rows: Vec<Vec<(usize, Integer)>> = picked_local
        .iter()
        .map(|&c| vec![(c, Integer::one())])
        .collect();
    // The solves run on the coordinates merged by equalities when rows merge any (the same
    // directions and moves; see `equalities`), else on `M` itself.
    let equalities = if solving.merge_equalities {
        Equalities::merge(&a)
    } else {
        None
    };
    // `A` as a matrix, made only when a backend factors it (a blocked move, a value outside
    // words, lost directions).
    let whole = std::cell::OnceCell::new();
    let a_matrix = || whole.get_or_init(|| a.to_matrix());
    let merged_picked_rows: Vec<Vec<(usize, Integer)>>;
    let (m_a, picked_rows) = match &equalities {
        Some(e) => {
            merged_picked_rows = picked_local.iter().map(|&c| e.picked_row(c)).collect();
            (SolvedRows::Merged(e.reduced()), &merged_picked_rows)
        }
        None => (SolvedRows::Whole(&a), &whole_picked_rows),
    };
    let m_a_matrix = || match m_a {
        SolvedRows::Merged(m) => m,
        SolvedRows::Whole(_) => a_matrix(),
    };
    // A small `M` is eliminated in machine words (the same answers, see `words`), unless the
    // move is blocked: the rows in its way are the backend's certificate.
    let in_words = solving
        .in_words
        .then(|| WordElimination::of(&m_a, picked_rows, requested))
        .flatten();
    let solves = match in_words {
        Some(words) if !words.blocked() => Solves::Words(words),
        _ => Solves::Backend(with_picked(m_a_matrix(), picked_rows)?),
    };
    let directions = match &solves {
        Solves::Words(words) => {
            let lost = row_basis(picked_local.len(), words.lost_normals());
            row_basis(
                picked_local.len(),
                orthogonal_complement(&lost, picked_local.len()),
            )
        }
        Solves::Backend(factored) => {
            reachable_directions(factored, m_a.rows(), picked_local.len())?
        }
    };
    let case = match directions.len() {
        0 => Case::FullyConstrained,
        n if n == picked_local.len() => Case::Free,
        _ => Case::PartiallyConstrained,
    };
    // Lost directions: a basis of the orthogonal complement of the directions in P-space.
    // Each `w` (extended by zeros) is orthogonal to ker A, so `Aᵀ y = w` has a solution: the
    // rows of `y` remove `w`.
    let complement = orthogonal_complement(&directions, picked_local.len());
    let mut lost = Vec::new();
    if !complement.is_empty() {
        let transposed = factor(&a_matrix().transpose())?;
        for w in complement {
            let mut rhs = vec![Rational::zero(); columns.len()];
            for (&c, x) in picked_local.iter().zip(&w) {
                rhs[c] = Rational::from_integer(x.clone());
            }
            let y = transposed
                .solve(&rhs)
                .map_err(|e| PropagationError::Backend(e.to_string()))?;
            let rows = y
                .into_iter()
                .enumerate()
                .filter(|(_, m)| !m.is_zero())
                .map(|(i, m)| {
                    let (row, k) = row_of(i);
                    (row, k, m)
                })
                .collect();
            lost.push(LostDirection { direction: w, rows });
        }
    }

    // The move reached: `particular` plus the null space of `M` (of the given nullity, formed
    // by `free` only within the budget), per parameter of the component.
    let reached = |nullity: usize,
                   particular: Particular,
                   free: &dyn Fn() -> Result<NullVectors, PropagationError>|
     -> Result<MoveOutcome, PropagationError> {
        let values = columns.len().saturating_mul(nullity);
        if values > budget {
            return Err(PropagationError::TooLarge {
                coordinates: columns.len(),
                values,
                budget,
            });
        }
        let (n, picked) = (columns.len(), &picked_local);
        let e = equalities.as_ref();
        let free = free()?;
        Ok(MoveOutcome::Moves(match particular {
            Particular::Words(x) => {
                follows_of(n, picked, &expanded_values(e, x), free, e, coordinate_of)
            }
            Particular::Rationals(x) => {
                follows_of(n, picked, &expanded_values(e, x), free, e, coordinate_of)
            }
        }))
    };
    let outcome = match (requested, &solves) {
        (None, _) => None,
        (Some(_), Solves::Words(words)) => Some(reached(
            m_a.cols() - words.rank(),
            Particular::Words(words.particular()),
            &|| match words.null_space() {
                Some(free) => Ok(NullVectors::Words(free)),
                // A null vector outside an `i64`: the backend's, for the same span.
                None => Ok(NullVectors::Integers(
                    with_picked(m_a_matrix(), picked_rows)?.integer_null_space(),
                )),
            },
        )?),
        (Some(moves), Solves::Backend(factored)) => {
            Some(match move_solution(factored, m_a.rows(), moves)? {
                MoveSolution::Reached(particular) => {
                    let particular = Particular::Rationals(particular);
                    reached(factored.cols() - factored.rank(), particular, &|| {
                        Ok(NullVectors::Integers(factored.integer_null_space()))
                    })?
                }
                // The rows in the way are named by the certificate of `M` itself.
                MoveSolution::Blocked(rows) if equalities.is_none() => {
                    MoveOutcome::Blocked(combination(rows))
                }
                MoveSolution::Blocked(_) => {
                    let whole = with_picked(a_matrix(), &whole_picked_rows)?;
                    match move_solution(&whole, a.rows(), moves)? {
                        MoveSolution::Blocked(rows) => MoveOutcome::Blocked(combination(rows)),
                        MoveSolution::Reached(_) => {
                            return Err(PropagationError::Backend(
                                "a move blocked on merged coordinates is not blocked on all".into(),
                            ))
                        }
                    }
                }
            })
        }
    };
    Ok(Propagation {
        picked: picked_coordinates,
        case,
        directions,
        lost,
        component: columns.len(),
        outcome,
    })
}

/// What the directions and the move are read off: `M` eliminated in machine words, or
/// factored by the backend.
enum Solves<F> {
    Words(WordElimination),
    Backend(F),
}

/// A basis of the null space of `M`, in machine words (from [`WordElimination`]) or big
/// integers (from the backend).
enum NullVectors {
    Words(Vec<Vec<i64>>),
    Integers(Vec<Vec<Integer>>),
}

/// The move's particular solution: rationals from the backend, word fractions from the
/// elimination in words (made rationals only where a value is reported).
enum Particular {
    Words(Vec<WordFraction>),
    Rationals(Vec<Rational>),
}

/// A value of a particular solution, as [`follows`] reads it.
trait MoveValue {
    /// Whether the value is zero.
    fn vanishes(&self) -> bool;
    /// The value as a rational in lowest terms.
    fn exact(&self) -> Rational;
}

impl MoveValue for Rational {
    fn vanishes(&self) -> bool {
        self.is_zero()
    }

    fn exact(&self) -> Rational {
        self.clone()
    }
}

impl MoveValue for WordFraction {
    fn vanishes(&self) -> bool {
        self.is_zero()
    }

    fn exact(&self) -> Rational {
        self.to_rational()
    }
}

/// [`follows`] with the null vectors of either kind, expanded over the component's columns.
fn follows_of<V: MoveValue>(
    n: usize,
    picked: &[usize],
    particular: &[V],
    free: NullVectors,
    equalities: Option<&Equalities>,
    coordinate_of: impl Fn(usize) -> (ParamId, usize),
) -> Vec<(ParamId, Follows)> {
    match free {
        NullVectors::Words(free) => follows(
            n,
            picked,
            particular,
            &expanded(equalities, free),
            coordinate_of,
        ),
        NullVectors::Integers(free) => follows(
            n,
            picked,
            particular,
            &expanded(equalities, free),
            coordinate_of,
        ),
    }
}

/// A particular solution over the merged classes of `equalities` as one over the component's
/// columns (itself when nothing was merged).
fn expanded_values<T>(equalities: Option<&Equalities>, values: Vec<T>) -> Vec<T>
where
    T: Clone,
    for<'a> &'a T: std::ops::Neg<Output = T>,
{
    match equalities {
        Some(e) => e.expand(&values),
        None => values,
    }
}

/// `vectors` over the merged classes of `equalities` as vectors over the component's columns
/// (themselves when nothing was merged).
fn expanded<T>(equalities: Option<&Equalities>, vectors: Vec<Vec<T>>) -> Vec<Vec<T>>
where
    T: Clone,
    for<'a> &'a T: std::ops::Neg<Output = T>,
{
    match equalities {
        Some(e) => vectors.iter().map(|v| e.expand(v)).collect(),
        None => vectors,
    }
}

/// A basis of the moves `m` of the picked coordinates that some `δ` with `A δ = 0` and
/// `δ_P = m` takes (ker A projected on `P`), from `m_factored`, the factorization of
/// `[A; E_P]` (`A` its first `rows_of_a` rows), in [`row_basis`]'s form.
///
/// Each trial `m` is orthogonal to every direction reached and every direction found lost so
/// far. Either `[A; E_P] δ = [0; m]` is consistent (`m` is reached), or its certificate `y` has
/// `y_Aᵀ A = −y_Pᵀ E_P`: `y_P` is orthogonal to every reachable move and `y_P · m ≠ 0`, a lost
/// direction outside the span found so far. So each of at most `|P|` checks adds a dimension,
/// and once reached and lost directions span the whole space, the reached ones span the
/// reachable moves.
fn reachable_directions<E>(
    m_factored: &E,
    rows_of_a: usize,
    picked: usize,
) -> Result<Vec<Vec<Integer>>, PropagationError>
where
    E: Factorization<Scalar = Rational>,
{
    let mut reached: Vec<Vec<Integer>> = Vec::new();
    let mut lost: Vec<Vec<Integer>> = Vec::new();
    loop {
        let known = row_basis(picked, reached.iter().chain(&lost).cloned());
        let Some(trial) = orthogonal_complement(&known, picked).into_iter().next() else {
            break;
        };
        let mut rhs = vec![Rational::zero(); rows_of_a];
        rhs.extend(trial.iter().cloned().map(Rational::from_integer));
        // Only consistency is asked: no solution is formed (with independent rows, nothing is
        // solved at all).
        match m_factored.check_consistent(&rhs) {
            Ok(()) => reached.push(trial),
            Err(SolveError::Inconsistent(certificate)) => {
                let mut direction = vec![Rational::zero(); picked];
                for (&i, y) in certificate.rows.iter().zip(certificate.certificate) {
                    if i >= rows_of_a {
                        direction[i - rows_of_a] = y;
                    }
                }
                lost.push(integer_multiple(&direction));
            }
            Err(e) => return Err(PropagationError::Backend(e.to_string())),
        }
    }
    Ok(row_basis(picked, reached))
}

/// What `M δ = [0; m]` gives.
enum MoveSolution {
    /// A particular solution.
    Reached(Vec<Rational>),
    /// No solution: the rows of `A` in the way, `(row of M, multiplier)`.
    Blocked(Vec<(usize, Rational)>),
}

/// `M δ = [0; m]` solved with `factored`, the factorization of `M` (its first `rows_of_a` rows
/// `A`).
fn move_solution<E>(
    factored: &E,
    rows_of_a: usize,
    moves: &[Rational],
) -> Result<MoveSolution, PropagationError>
where
    E: Factorization<Scalar = Rational>,
{
    let mut rhs = vec![Rational::zero(); rows_of_a];
    rhs.extend(moves.iter().cloned());
    match factored.solve(&rhs) {
        Ok(x) => Ok(MoveSolution::Reached(x)),
        // Rows of A in the certificate (the picked rows are the move itself).
        Err(SolveError::Inconsistent(certificate)) => Ok(MoveSolution::Blocked(
            certificate
                .rows
                .into_iter()
                .zip(certificate.certificate)
                .filter(|(i, _)| *i < rows_of_a)
                .collect(),
        )),
        Err(e) => Err(PropagationError::Backend(e.to_string())),
    }
}

/// The move's consequences per parameter of a component of `n` coordinates: the affine set
/// `{δ : A δ = 0, δ_P = m}` is `particular` plus the span of `free` (integer vectors over the
/// component's columns: machine words from the elimination in words, big integers from the
/// backend). `coordinate_of` is nondecreasing in the parameter (the component's columns are
/// sorted), so each parameter's coordinates are one run of columns.
fn follows<V, T>(
    n: usize,
    picked: &[usize],
    particular: &[V],
    free: &[Vec<T>],
    coordinate_of: impl Fn(usize) -> (ParamId, usize),
) -> Vec<(ParamId, Follows)>
where
    V: MoveValue,
    T: Clone + Zero + Into<Integer>,
{
    let mut follows = Vec::new();
    let mut start = 0;
    while start < n {
        let param = coordinate_of(start).0;
        let end = (start + 1..n)
            .find(|&c| coordinate_of(c).0 != param)
            .unwrap_or(n);
        let coordinates = start..end;
        start = end;
        if coordinates.clone().any(|c| picked.contains(&c)) {
            continue;
        }
        // The move's value on the parameter (made rationals only where they are read).
        let value = &particular[coordinates.clone()];
        // The span of the freedom projected on the parameter, formed only while it can still
        // grow and from projections that are not zero (most are, for a parameter far from the
        // move: every edit's analysis projects its whole null space once per parameter).
        let (freedom, whole_space, span) = if coordinates.len() == 1 {
            // A scalar parameter: free exactly when some null vector moves it, and then in
            // every direction of its line.
            let c = coordinates.start;
            let moved = usize::from(free.iter().any(|v| !v[c].is_zero()));
            (moved, moved == 1, None)
        } else {
            let mut span = IntegerEchelon::new(coordinates.len());
            for v in free {
                if span.is_whole_space() {
                    break;
                }
                let mut nonzero = coordinates.clone().filter(|&c| !v[c].is_zero());
                match (nonzero.next(), nonzero.next()) {
                    (None, _) => {}
                    // One nonzero entry spans the line of its unit vector: no rationals scaled.
                    (Some(c), None) => {
                        let mut unit = vec![Integer::zero(); coordinates.len()];
                        unit[c - coordinates.start] = Integer::one();
                        span.insert(unit);
                    }
                    _ => span.insert(coordinates.clone().map(|c| v[c].clone().into()).collect()),
                }
            }
            (span.dimension(), span.is_whole_space(), Some(span))
        };
        let entry = if freedom == 0 {
            if value.iter().all(MoveValue::vanishes) {
                continue;
            }
            Follows::Forced(value.iter().map(MoveValue::exact).collect())
        } else if whole_space
            || span.is_some_and(|span| {
                let value: Vec<Rational> = value.iter().map(MoveValue::exact).collect();
                span.contains(integer_multiple(&value))
            })
        {
            // The move's value minus a free move is zero (always, when the free moves span
            // every direction of the parameter): the parameter may stay.
            Follows::MayStay { freedom }
        } else {
            Follows::MustMoveWithChoice { freedom }
        };
        follows.push((param, entry));
    }
    follows
}

/// Integer vectors of one width in echelon form, each reduced by the rows before it
/// fraction-free and divided by its content: enough to tell the dimension of their span and
/// whether a vector lies in it, without the rationals of a reduced basis.
struct IntegerEchelon {
    width: usize,
    /// Each row with its pivot, the position of its first nonzero entry; every later row is
    /// zero there.
    rows: Vec<(usize, Vec<Integer>)>,
}

impl IntegerEchelon {
    fn new(width: usize) -> Self {
        IntegerEchelon {
            width,
            rows: Vec::new(),
        }
    }

    fn dimension(&self) -> usize {
        self.rows.len()
    }

    fn is_whole_space(&self) -> bool {
        self.rows.len() == self.width
    }

    /// `v` less its part along the rows: zero exactly when `v` is in their span.
    fn reduced(&self, mut v: Vec<Integer>) -> Vec<Integer> {
        debug_assert_eq!(v.len(), self.width);
        for (p, row) in &self.rows {
            if v[*p].is_zero() {
                continue;
            }
            eliminate(&mut v, row, *p);
        }
        v
    }

    /// Adds `v` to the span.
    fn insert(&mut self, v: Vec<Integer>) {
        let v = self.reduced(v);
        if let Some(p) = v.iter().position(|x| !x.is_zero()) {
            self.rows.push((p, v));
        }
    }

    fn contains(&self, v: Vec<Integer>) -> bool {
        self.reduced(v).iter().all(Zero::is_zero)
    }

    /// The rows made zero at every other row's pivot (Gauss–Jordan, fraction-free: from the
    /// last row back, each clears its pivot from the rows before it, which alone can be
    /// nonzero there), primitive with a positive pivot, by increasing pivot.
    fn reduced_basis(mut self) -> Vec<Vec<Integer>> {
        for i in (0..self.rows.len()).rev() {
            let (done, rest) = self.rows.split_at_mut(i);
            let (p, row) = &rest[0];
            for (_, earlier) in done.iter_mut() {
                if !earlier[*p].is_zero() {
                    eliminate(earlier, row, *p);
                }
            }
        }
        self.rows.sort_by_key(|(p, _)| *p);
        self.rows
            .into_iter()
            .map(|(_, row)| primitive_with_positive_lead(row))
            .collect()
    }
}

/// `v ← row[p]·v − v[p]·row` (zero at `p`), then divided by the GCD of its entries.
fn eliminate(v: &mut [Integer], row: &[Integer], p: usize) {
    let (a, b) = (row[p].clone(), v[p].clone());
    for (x, r) in v.iter_mut().zip(row) {
        *x = &a * &*x - &b * r;
    }
    divide_by_content(v);
}

/// `v` divided by the GCD of its entries (unchanged when that is 0 or 1).
fn divide_by_content(v: &mut [Integer]) {
    let content = v
        .iter()
        .fold(Integer::zero(), |g, x| num_integer::Integer::gcd(&g, x));
    if !content.is_zero() && !content.is_one() {
        for x in v.iter_mut() {
            *x = &*x / &content;
        }
    }
}

/// A nonzero integer multiple of `values` (themselves when they are integers).
fn integer_multiple(values: &[Rational]) -> Vec<Integer> {
    if values.iter().all(|v| v.denom().is_one()) {
        values.iter().map(|v| v.numer().clone()).collect()
    } else {
        api::coprime_integers(values.iter())
    }
}

/// The connected component(s) of some coordinates: the scalar equations linked to them
/// through nonzero coefficients, as the matrix `A` (rows in the system's order of scalar
/// equations, columns increasing), where each row of `A` comes from, and the coordinates
/// (columns of the whole system's scalar matrix) that are `A`'s columns.
struct Component<'s> {
    a: ComponentRows<'s>,
    origin: Vec<(RowId, usize)>,
    columns: Vec<usize>,
}

/// Sparse integer rows as the eliminations in words and the merge of equalities read them:
/// a component's rows (their coefficients still the system's) or a matrix.
pub(crate) trait SparseRows {
    /// Number of columns.
    fn cols(&self) -> usize;
    /// Number of rows.
    fn rows(&self) -> usize;
    /// Row `i`'s nonzero entries `(column, coefficient)`, by increasing column.
    fn entries(&self, i: usize) -> impl Iterator<Item = (usize, &Integer)>;
}

impl SparseRows for IntMatrix {
    fn cols(&self) -> usize {
        IntMatrix::cols(self)
    }
    fn rows(&self) -> usize {
        IntMatrix::rows(self)
    }
    fn entries(&self, i: usize) -> impl Iterator<Item = (usize, &Integer)> {
        self.row(i).iter().map(|(c, v)| (*c, v))
    }
}

/// The rows of `A`, a component's scalar equations over its columns, with the coefficients
/// borrowed from the system's rows: a small edit's analysis eliminates them in words without
/// copying a big integer per coefficient, and the backend's factorings take a matrix of them
/// ([`ComponentRows::to_matrix`]) only when they are needed.
#[derive(Debug)]
struct ComponentRows<'s> {
    cols: usize,
    rows: Vec<Vec<(usize, &'s Integer)>>,
}

impl ComponentRows<'_> {
    /// `A` as a matrix (every coefficient copied).
    fn to_matrix(&self) -> IntMatrix {
        IntMatrix::from_sparse(
            self.cols,
            self.rows
                .iter()
                .map(|row| row.iter().map(|(c, v)| (*c, (*v).clone())).collect())
                .collect(),
        )
        .expect("a component's columns are in range")
    }
}

impl SparseRows for ComponentRows<'_> {
    fn cols(&self) -> usize {
        self.cols
    }
    fn rows(&self) -> usize {
        self.rows.len()
    }
    fn entries(&self, i: usize) -> impl Iterator<Item = (usize, &Integer)> {
        self.rows[i].iter().map(|(c, v)| (*c, *v))
    }
}

/// The `A` part of `M` that the solves run on: the coordinates merged by equalities, or the
/// component's own rows.
enum SolvedRows<'m, 's> {
    Merged(&'m IntMatrix),
    Whole(&'m ComponentRows<'s>),
}

impl SparseRows for SolvedRows<'_, '_> {
    fn cols(&self) -> usize {
        match self {
            SolvedRows::Merged(m) => SparseRows::cols(*m),
            SolvedRows::Whole(a) => a.cols(),
        }
    }
    fn rows(&self) -> usize {
        match self {
            SolvedRows::Merged(m) => SparseRows::rows(*m),
            SolvedRows::Whole(a) => a.rows(),
        }
    }
    fn entries(&self, i: usize) -> impl Iterator<Item = (usize, &Integer)> {
        let (merged, whole) = match self {
            SolvedRows::Merged(m) => (Some(m.entries(i)), None),
            SolvedRows::Whole(a) => (None, Some(a.entries(i))),
        };
        merged
            .into_iter()
            .flatten()
            .chain(whole.into_iter().flatten())
    }
}

impl<'s> Component<'s> {
    /// The component of the coordinates `start`, found by walking the rows that touch each
    /// parameter reached ([`ConstraintSystem::rows_of`]): only the component's rows are split
    /// into scalar equations, not the whole system's (which a small edit's report paid for on
    /// every edit).
    fn of(
        system: &'s ConstraintSystem,
        offsets: &[usize],
        start: impl Iterator<Item = (ParamId, usize)>,
    ) -> Result<Self, PropagationError> {
        // Flags indexed by coordinate and by row (a fill of the system's size, far cheaper
        // than hashing every coordinate of a whole-mesh component); per row touched, its
        // scalar equations and which of them the component holds.
        let mut seen_column = vec![false; system.coordinate_count()];
        let mut reached_columns: Vec<usize> = Vec::new();
        let mut equations: Vec<Option<Vec<bool>>> = vec![None; system.rows().len()];
        let mut touched_rows: Vec<RowId> = Vec::new();
        let mut stack: Vec<(ParamId, usize)> = Vec::new();
        let mut reach = |p: ParamId, k: usize, stack: &mut Vec<(ParamId, usize)>| {
            let column = offsets[p.index()] + k;
            if !seen_column[column] {
                seen_column[column] = true;
                reached_columns.push(column);
                stack.push((p, k));
            }
        };
        for (p, k) in start {
            reach(p, k, &mut stack);
        }
        while let Some((p, k)) = stack.pop() {
            for &row in system.rows_of(p) {
                let of_row = system.rows()[row.index()].body.scalar_equations();
                let seen = equations[row.index()].get_or_insert_with(|| {
                    touched_rows.push(row);
                    vec![false; of_row.len()]
                });
                // A system's rows hold no zero coefficients (`ConstraintSystem::add_row`
                // merges them away): every term links its equation and its coordinate.
                for (equation, seen) in of_row.zip(seen.iter_mut()) {
                    if *seen {
                        continue;
                    }
                    // A vector row's equation for coordinate `c` holds coordinate `c` of each of
                    // its parameters (`p` among them); a scalar row's terms are looked at. Each
                    // equation is scanned only until it is reached, so a row of many terms costs
                    // in proportion to them, not to their square.
                    let touches = match equation.component() {
                        Some(c) => c == k,
                        None => equation
                            .terms()
                            .any(|(c, _)| c.param == p && c.component == k),
                    };
                    if !touches {
                        continue;
                    }
                    *seen = true;
                    for (c, _) in equation.terms() {
                        reach(c.param, c.component, &mut stack);
                    }
                }
            }
        }
        touched_rows.sort_unstable();
        let mut columns = reached_columns;
        columns.sort_unstable();
        // Every coordinate of an equation reached was reached with it.
        let lost = |_| PropagationError::Backend("a coordinate left its component".into());
        let held: usize = touched_rows
            .iter()
            .filter_map(|row| equations[row.index()].as_ref())
            .map(|seen| seen.iter().filter(|s| **s).count())
            .sum();
        let mut sparse = Vec::with_capacity(held);
        let mut origin = Vec::with_capacity(held);
        for (row, seen) in touched_rows
            .iter()
            .filter_map(|&row| equations[row.index()].as_ref().map(|e| (row, e)))
        {
            let of_row = system.rows()[row.index()].body.scalar_equations();
            for equation in of_row.zip(seen).filter(|(_, s)| **s).map(|(e, _)| e) {
                let terms = equation.terms();
                let mut entries = Vec::with_capacity(terms.size_hint().0);
                for (c, v) in terms {
                    let l = columns
                        .binary_search(&(offsets[c.param.index()] + c.component))
                        .map_err(lost)?;
                    entries.push((l, v));
                }
                // A row's terms are merged and nonzero (`ConstraintSystem::add_row`); only
                // their order may differ from the columns'.
                entries.sort_unstable_by_key(|(l, _)| *l);
                sparse.push(entries);
                origin.push((row, equation.component().unwrap_or(0)));
            }
        }
        let a = ComponentRows {
            cols: columns.len(),
            rows: sparse,
        };
        Ok(Component { a, origin, columns })
    }
}

/// A basis of the span of `vectors` (each of `width` entries) in reduced echelon form, each
/// row scaled to coprime integers with a positive leading entry: the same span gives the same
/// basis. Once the span is the whole space the rest of `vectors` is not looked at (its basis
/// is the identity whatever they are). Fraction-free ([`IntegerEchelon::reduced_basis`]): a
/// row of the reduced form is determined up to a factor by its zeros at the other pivots.
fn row_basis(width: usize, vectors: impl IntoIterator<Item = Vec<Integer>>) -> Vec<Vec<Integer>> {
    let mut span = IntegerEchelon::new(width);
    for v in vectors {
        if span.is_whole_space() {
            break;
        }
        span.insert(v);
    }
    span.reduced_basis()
}

/// `v` divided by the GCD of its entries, its first nonzero entry made positive.
fn primitive_with_positive_lead(mut v: Vec<Integer>) -> Vec<Integer> {
    divide_by_content(&mut v);
    if v.iter()
        .find(|x| !x.is_zero())
        .is_some_and(Signed::is_negative)
    {
        for x in v.iter_mut() {
            *x = -std::mem::take(x);
        }
    }
    v
}

/// A basis of the vectors orthogonal to every row of `basis` (a reduced echelon basis) in
/// dimension `n`: one per non-pivot position, integers.
fn orthogonal_complement(basis: &[Vec<Integer>], n: usize) -> Vec<Vec<Integer>> {
    // In reduced echelon form the row space's complement is spanned, per free position f,
    // by e_f − Σ_rows (row[f] / row[pivot]) e_pivot.
    let pivots: Vec<usize> = basis
        .iter()
        .map(|r| r.iter().position(|x| !x.is_zero()).unwrap_or(0))
        .collect();
    (0..n)
        .filter(|f| !pivots.contains(f))
        .map(|f| {
            // Times the product of the pivots' entries, every entry is an integer.
            let scale = basis
                .iter()
                .zip(&pivots)
                .fold(Integer::one(), |acc, (row, &p)| acc * &row[p]);
            let mut v = vec![Integer::zero(); n];
            for (row, &p) in basis.iter().zip(&pivots) {
                v[p] = -(&row[f] * &scale) / &row[p];
            }
            v[f] = scale;
            primitive_with_positive_lead(v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{ConstraintRow, Coord, Origin, RowBody};
    use exact_ldu::ExactLdu;

    /// A system of named parameters (with dimensions) and rows, each `(terms, rhs)` over
    /// coordinates `(parameter, coordinate, coefficient)`, or vector rows.
    struct Fixture {
        system: ConstraintSystem,
    }

    impl Fixture {
        fn new(params: &[(&str, usize)]) -> Fixture {
            let mut system = ConstraintSystem::new();
            for (name, dim) in params {
                system.add_parameter(*name, *dim).expect("a parameter");
            }
            Fixture { system }
        }

        fn add_param(&mut self, name: &str, dim: usize) {
            self.system.add_parameter(name, dim).expect("a parameter");
        }

        fn id(&self, name: &str) -> ParamId {
            self.system.param_id(name).expect("declared")
        }

        fn scalar(&mut self, label: &str, terms: &[(&str, usize, i64)], rhs: i64) {
            let terms = terms
                .iter()
                .map(|&(p, k, c)| {
                    (
                        Coord {
                            param: self.id(p),
                            component: k,
                        },
                        Integer::from(c),
                    )
                })
                .collect();
            self.add(
                label,
                RowBody::Scalar {
                    terms,
                    rhs: rhs.into(),
                },
            );
        }

        fn vector(&mut self, label: &str, terms: &[(&str, i64)], dim: usize) {
            let terms = terms
                .iter()
                .map(|&(p, c)| (self.id(p), Integer::from(c)))
                .collect();
            self.add(
                label,
                RowBody::Vector {
                    terms,
                    rhs: vec![Integer::zero(); dim],
                },
            );
        }

        fn add(&mut self, label: &str, body: RowBody) {
            let origin = Origin {
                source: "test".into(),
                item: label.into(),
            };
            self.system
                .add_row(ConstraintRow {
                    label: label.into(),
                    origin,
                    body,
                })
                .expect("a row");
        }

        fn analyze(&self, picked: &[&str], requested: Option<&[i64]>) -> Propagation {
            let picked: Vec<ParamId> = picked.iter().map(|p| self.id(p)).collect();
            let requested: Option<Vec<Rational>> = requested.map(|m| {
                m.iter()
                    .map(|&x| Rational::from_integer(x.into()))
                    .collect()
            });
            analyze_propagation(
                &ExactLdu::default(),
                &self.system,
                &picked,
                requested.as_deref(),
                EXPLAIN_NULL_SPACE_BUDGET,
            )
            .expect("analysed")
        }
    }

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    fn ints(v: &[i64]) -> Vec<Integer> {
        v.iter().map(|&x| Integer::from(x)).collect()
    }

    #[test]
    fn a_point_tied_to_another_is_free_and_drags_it_exactly() {
        let mut f = Fixture::new(&[("p", 2), ("q", 2), ("r", 2)]);
        f.vector("p = q", &[("p", 1), ("q", -1)], 2);
        let a = f.analyze(&["p"], Some(&[1, 2]));
        assert_eq!(a.case, Case::Free);
        assert_eq!(a.directions, vec![ints(&[1, 0]), ints(&[0, 1])]);
        assert!(a.lost.is_empty());
        assert_eq!(
            a.component, 4,
            "r is in no row with p: not in the component"
        );
        assert_eq!(
            a.outcome,
            Some(MoveOutcome::Moves(vec![(
                f.id("q"),
                Follows::Forced(vec![q(1), q(2)])
            )]))
        );
    }

    #[test]
    fn a_point_on_a_vertical_line_moves_only_along_it_and_names_the_line() {
        let mut f = Fixture::new(&[("p", 2)]);
        f.scalar("x = 3", &[("p", 0, 1)], 3);
        let a = f.analyze(&["p"], None);
        assert_eq!(a.case, Case::PartiallyConstrained);
        assert_eq!(a.directions, vec![ints(&[0, 1])]);
        assert_eq!(a.lost.len(), 1);
        assert_eq!(a.lost[0].direction, ints(&[1, 0]));
        let rows: Vec<RowId> = a.lost[0].rows.iter().map(|r| r.0).collect();
        assert_eq!(rows, [RowId(0)]);
        // Sideways is blocked by that row; along the line is fine.
        let sideways = f.analyze(&["p"], Some(&[1, 0]));
        match sideways.outcome {
            Some(MoveOutcome::Blocked(rows)) => {
                assert_eq!(rows.iter().map(|r| r.0).collect::<Vec<_>>(), [RowId(0)])
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            f.analyze(&["p"], Some(&[0, 5])).outcome,
            Some(MoveOutcome::Moves(vec![]))
        );
    }

    #[test]
    fn a_fixed_scalar_is_fully_constrained() {
        let mut f = Fixture::new(&[("a", 1)]);
        f.scalar("a = 0", &[("a", 0, 1)], 0);
        let a = f.analyze(&["a"], None);
        assert_eq!(a.case, Case::FullyConstrained);
        assert!(a.directions.is_empty());
        assert_eq!(a.lost[0].direction, ints(&[1]));
    }

    #[test]
    fn choices_may_stay_or_must_move() {
        // a + b − c = 0: moving a by 1, b and c may each stay (not both).
        let mut f = Fixture::new(&[("a", 1), ("b", 1), ("c", 1), ("r", 2)]);
        f.scalar("a + b = c", &[("a", 0, 1), ("b", 0, 1), ("c", 0, -1)], 0);
        // r[0] + r[1] = a: r must move when a does, along a line that misses its place.
        f.scalar("r0 + r1 = a", &[("r", 0, 1), ("r", 1, 1), ("a", 0, -1)], 0);
        let a = f.analyze(&["a"], Some(&[1]));
        assert_eq!(a.case, Case::Free);
        assert_eq!(
            a.outcome,
            Some(MoveOutcome::Moves(vec![
                (f.id("b"), Follows::MayStay { freedom: 1 }),
                (f.id("c"), Follows::MayStay { freedom: 1 }),
                (f.id("r"), Follows::MustMoveWithChoice { freedom: 1 }),
            ]))
        );
    }

    #[test]
    fn bad_picks_and_moves_are_errors() {
        let f = Fixture::new(&[("a", 1), ("p", 2)]);
        let run = |picked: &[ParamId], m: Option<&[Rational]>| {
            analyze_propagation(
                &ExactLdu::default(),
                &f.system,
                picked,
                m,
                EXPLAIN_NULL_SPACE_BUDGET,
            )
            .expect_err("refused")
        };
        assert!(matches!(run(&[], None), PropagationError::Picked(_)));
        assert!(matches!(
            run(&[f.id("a"), f.id("a")], None),
            PropagationError::Picked(_)
        ));
        assert_eq!(
            run(&[f.id("p")], Some(&[q(1)])),
            PropagationError::MoveSize {
                expected: 2,
                found: 1
            }
        );
    }

    /// The component of `start` read off the whole system's scalar matrix (rows linked to
    /// columns through nonzero entries): the oracle for [`Component::of`].
    fn component_of_whole_matrix(
        system: &ConstraintSystem,
        start: &[usize],
    ) -> (IntMatrix, Vec<(RowId, usize)>, Vec<usize>) {
        let (matrix, _, origin) = system.scalar_matrix();
        let mut seen_column = vec![false; matrix.cols()];
        let mut seen_row = vec![false; matrix.rows()];
        let mut stack: Vec<usize> = start.to_vec();
        for &c in &stack {
            seen_column[c] = true;
        }
        while let Some(c) = stack.pop() {
            for (i, seen) in seen_row.iter_mut().enumerate() {
                if *seen || !matrix.row(i).iter().any(|(j, _)| *j == c) {
                    continue;
                }
                *seen = true;
                for (next, _) in matrix.row(i) {
                    if !seen_column[*next] {
                        seen_column[*next] = true;
                        stack.push(*next);
                    }
                }
            }
        }
        let pick = |seen: &[bool]| -> Vec<usize> { (0..seen.len()).filter(|&i| seen[i]).collect() };
        let (rows, columns) = (pick(&seen_row), pick(&seen_column));
        let a = matrix.select(&rows, &columns);
        (a, rows.iter().map(|&i| origin[i]).collect(), columns)
    }

    proptest::proptest! {
        /// Walking the rows of each parameter finds the component the whole scalar matrix
        /// gives: the same equations in the same order, the same columns, the same origins — on
        /// systems of scalar and vector rows with zero coefficients and several components.
        #[test]
        fn components_found_by_walking_rows_are_those_of_the_whole_matrix(
            rows in proptest::collection::vec(
                (
                    proptest::bool::ANY,
                    proptest::collection::vec((0usize..7, 0usize..2, -1i64..=1), 1..4),
                ),
                0..7,
            ),
            start in (0usize..7, 0usize..2),
        ) {
            // Parameters of dimension 2 (vector rows join them) and 1.
            let dims = [2, 1, 2, 1, 2, 1, 2];
            let names = ["a", "b", "c", "d", "e", "f", "g"];
            let mut f = Fixture::new(&names.iter().zip(dims).map(|(n, d)| (*n, d)).collect::<Vec<_>>());
            for (i, (vector, terms)) in rows.iter().enumerate() {
                let label = format!("row {i}");
                if *vector {
                    let mut vector_terms: Vec<(&str, i64)> = Vec::new();
                    for &(p, _, c) in terms {
                        let p = p - p % 2; // a parameter of dimension 2
                        if !vector_terms.iter().any(|(q, _)| *q == names[p]) {
                            vector_terms.push((names[p], c));
                        }
                    }
                    f.vector(&label, &vector_terms, 2);
                } else {
                    let mut scalar_terms: Vec<(&str, usize, i64)> = Vec::new();
                    for &(p, k, c) in terms {
                        let k = k % dims[p];
                        if !scalar_terms.iter().any(|(q, l, _)| *q == names[p] && *l == k) {
                            scalar_terms.push((names[p], k, c));
                        }
                    }
                    f.scalar(&label, &scalar_terms, 0);
                }
            }
            let (p, k) = (start.0, start.1 % dims[start.0]);
            let offsets = f.system.coordinate_offsets();
            let found = Component::of(&f.system, &offsets, std::iter::once((ParamId(p as u32), k)))
                .expect("a component");
            let (a, origin, columns) = component_of_whole_matrix(&f.system, &[offsets[p] + k]);
            // The same rows as the oracle's matrix, entries already in column order.
            let found_rows: Vec<Vec<(usize, Integer)>> = found
                .a
                .rows
                .iter()
                .map(|row| row.iter().map(|(c, v)| (*c, (*v).clone())).collect())
                .collect();
            let expected_rows: Vec<Vec<(usize, Integer)>> = a.row_iter().map(<[_]>::to_vec).collect();
            proptest::prop_assert_eq!(found.a.cols, a.cols());
            proptest::prop_assert_eq!(found_rows, expected_rows);
            proptest::prop_assert_eq!(found.a.to_matrix(), a);
            proptest::prop_assert_eq!(found.origin, origin);
            proptest::prop_assert_eq!(found.columns, columns);
        }
    }

    /// The analysis with and without merging the coordinates equalities tie.
    fn merged_and_whole(
        f: &Fixture,
        picked: &[ParamId],
        requested: &[Rational],
        budget: usize,
    ) -> (
        Result<Propagation, PropagationError>,
        Result<Propagation, PropagationError>,
    ) {
        let run = |merge_equalities| {
            analyze(
                &ExactLdu::default(),
                &f.system,
                picked,
                Some(requested),
                budget,
                Solving {
                    merge_equalities,
                    in_words: true,
                },
            )
        };
        (run(true), run(false))
    }

    #[test]
    fn a_grid_of_alignments_is_analysed_on_merged_coordinates_with_the_same_answers() {
        // Nine points in a 3 × 3 grid, each row of points horizontal and each column
        // vertical (scalar equalities), one vector coincidence, one diagonal row that is not
        // an equality; then a contradiction: p0's x equal to p8's x and to its opposite.
        let names: Vec<String> = (0..9).map(|i| format!("p{i}")).collect();
        let mut f = Fixture::new(&names.iter().map(|n| (n.as_str(), 2)).collect::<Vec<_>>());
        f.add_param("q", 2);
        for r in 0..3 {
            for c in 0..2 {
                let (a, b) = (&names[3 * r + c], &names[3 * r + c + 1]);
                f.scalar(&format!("h{r}{c}"), &[(a, 1, 1), (b, 1, -1)], 0);
                let (a, b) = (&names[3 * c + r], &names[3 * c + 3 + r]);
                f.scalar(&format!("v{r}{c}"), &[(a, 0, 1), (b, 0, -1)], 0);
            }
        }
        f.vector("q on p4", &[("q", 1), ("p4", -1)], 2);
        f.scalar("diagonal", &[("p0", 0, 1), ("p4", 1, 1), ("p8", 0, -2)], 0);
        let offsets = f.system.coordinate_offsets();
        let start = std::iter::once((f.id("p0"), 0));
        let component = Component::of(&f.system, &offsets, start).expect("a component");
        let merged = Equalities::merge(&component.a).expect("alignments merge");
        assert_eq!(merged.reduced().rows(), 1, "only the diagonal row is left");
        for (picked, m) in [
            (vec!["p0"], vec![3, -2]),
            (vec!["p4", "p8"], vec![1, 1, 2, 5]),
        ] {
            let picked: Vec<ParamId> = picked.iter().map(|p| f.id(p)).collect();
            let m: Vec<Rational> = m.into_iter().map(q).collect();
            let (with, without) = merged_and_whole(&f, &picked, &m, EXPLAIN_NULL_SPACE_BUDGET);
            assert_eq!(with, without);
        }
        f.scalar("x0 = x8", &[("p0", 0, 1), ("p8", 0, -1)], 0);
        f.scalar("x0 = -x8", &[("p0", 0, 1), ("p8", 0, 1)], 0);
        let picked = [f.id("p0")];
        let (with, without) = merged_and_whole(&f, &picked, &[q(3), q(-2)], 1_000);
        assert_eq!(with, without);
        // x0 is forced to stay: the move is blocked, and the rows in the way are those of the
        // whole factoring.
        assert!(matches!(
            with.expect("analysed").outcome,
            Some(MoveOutcome::Blocked(_))
        ));
    }

    proptest::proptest! {
        /// Merging the coordinates that rows `±x_i ± x_j = 0` tie changes no answer: on random
        /// systems of such rows (scalar and vector), other rows and picks, the analysis on
        /// merged coordinates equals the one on all of them — case, directions, lost
        /// directions with their rows, blocked moves with theirs, forced moves, freedoms and
        /// the refusal of a component too large.
        #[test]
        fn merging_equalities_changes_no_answer(
            equalities in proptest::collection::vec(
                (0usize..5, 0usize..2, 0usize..5, 0usize..2, proptest::bool::ANY, proptest::bool::ANY),
                1..7,
            ),
            others in proptest::collection::vec(
                proptest::collection::vec((0usize..5, 0usize..2, -2i64..=2), 1..4),
                0..3,
            ),
            picked in proptest::collection::btree_set(0usize..5, 1..3),
            moves in proptest::collection::vec(-3i64..=3, 4),
            small_budget in proptest::bool::ANY,
        ) {
            let names = ["a", "b", "c", "d", "e"];
            let mut f = Fixture::new(&names.iter().map(|n| (*n, 2)).collect::<Vec<_>>());
            for (i, &(p, k, r, l, negated, vector)) in equalities.iter().enumerate() {
                if p == r && (vector || k == l) {
                    continue;
                }
                let sign = if negated { 1 } else { -1 };
                if vector {
                    f.vector(&format!("eq {i}"), &[(names[p], 1), (names[r], sign)], 2);
                } else {
                    f.scalar(&format!("eq {i}"), &[(names[p], k, 1), (names[r], l, sign)], 0);
                }
            }
            for (i, terms) in others.iter().enumerate() {
                let mut scalar_terms: Vec<(&str, usize, i64)> = Vec::new();
                for &(p, k, c) in terms {
                    if !scalar_terms.iter().any(|(q, l, _)| *q == names[p] && *l == k) {
                        scalar_terms.push((names[p], k, c));
                    }
                }
                f.scalar(&format!("other {i}"), &scalar_terms, 0);
            }
            let picked: Vec<ParamId> = picked.iter().map(|&p| f.id(names[p])).collect();
            let requested: Vec<Rational> =
                moves[..2 * picked.len()].iter().map(|&x| q(x)).collect();
            let budget = if small_budget { 12 } else { EXPLAIN_NULL_SPACE_BUDGET };
            let (with, without) = merged_and_whole(&f, &picked, &requested, budget);
            proptest::prop_assert_eq!(with, without);
        }
    }

    /// The analysis with `M` eliminated in machine words and factored by the backend, both
    /// with and without merging equalities.
    fn in_words_and_by_the_backend(
        f: &Fixture,
        picked: &[ParamId],
        requested: Option<&[Rational]>,
        budget: usize,
    ) -> Vec<(
        Result<Propagation, PropagationError>,
        Result<Propagation, PropagationError>,
    )> {
        let run = |merge_equalities, in_words| {
            analyze(
                &ExactLdu::default(),
                &f.system,
                picked,
                requested,
                budget,
                Solving {
                    merge_equalities,
                    in_words,
                },
            )
        };
        [true, false]
            .into_iter()
            .map(|merge| (run(merge, true), run(merge, false)))
            .collect()
    }

    #[test]
    fn small_components_are_eliminated_in_words_and_large_values_fall_back() {
        // p0 = p1 + p2 (vector), x of p2 tied to p3's with a coefficient: reached moves.
        let mut f = Fixture::new(&[("p0", 2), ("p1", 2), ("p2", 2), ("p3", 1)]);
        f.vector("sum", &[("p0", 1), ("p1", -1), ("p2", -1)], 2);
        f.scalar("tie", &[("p2", 0, 3), ("p3", 0, -2)], 0);
        let offsets = f.system.coordinate_offsets();
        let start = std::iter::once((f.id("p0"), 0)).chain([(f.id("p0"), 1)]);
        let component = Component::of(&f.system, &offsets, start).expect("a component");
        let picked_rows = vec![vec![(0, Integer::one())], vec![(1, Integer::one())]];
        let m = [q(3), Rational::new(Integer::from(-2), Integer::from(7))];
        let words = WordElimination::of(&component.a, &picked_rows, Some(&m))
            .expect("small values stay in words");
        assert!(!words.blocked());
        // The particular solution solves M x = [0; m], each null vector M v = 0.
        let mut with_picked = component.a.to_matrix();
        for row in &picked_rows {
            with_picked.push_row(row.clone()).expect("row");
        }
        let mut rhs = vec![Rational::zero(); component.a.rows()];
        rhs.extend(m.iter().cloned());
        let x: Vec<Rational> = words
            .particular()
            .into_iter()
            .map(|v| v.to_rational())
            .collect();
        for (i, row) in with_picked.row_iter().enumerate() {
            let value: Rational = row
                .iter()
                .map(|(c, v)| &x[*c] * Rational::from_integer(v.clone()))
                .sum();
            assert_eq!(value, rhs[i], "row {i}");
        }
        let free = words.null_space().expect("small null vectors");
        assert_eq!(free.len(), with_picked.cols() - words.rank());
        for v in &free {
            for row in with_picked.row_iter() {
                let value: Integer = row.iter().map(|(c, a)| a * v[*c]).sum();
                assert!(value.is_zero());
            }
        }
        for (with, without) in
            in_words_and_by_the_backend(&f, &[f.id("p0")], Some(&m), EXPLAIN_NULL_SPACE_BUDGET)
        {
            assert_eq!(with, without);
        }
        // A coefficient near 2^62: its products leave an `i64`, and the backend answers.
        let mut big = Fixture::new(&[("p0", 1), ("p1", 1), ("p2", 1)]);
        big.scalar("a", &[("p0", 0, 1 << 62), ("p1", 0, 3), ("p2", 0, 5)], 0);
        big.scalar("b", &[("p1", 0, 1 << 62), ("p2", 0, 7)], 0);
        let offsets = big.system.coordinate_offsets();
        let start = std::iter::once((big.id("p0"), 0));
        let component = Component::of(&big.system, &offsets, start).expect("a component");
        assert!(
            WordElimination::of(&component.a, &[vec![(0, Integer::one())]], Some(&[q(1)]))
                .is_none()
        );
        for (with, without) in
            in_words_and_by_the_backend(&big, &[big.id("p0")], Some(&[q(1)]), 1_000)
        {
            assert_eq!(with, without);
        }
        // Three pivots near 2^62, pairwise coprime, over one free column: the elimination fits
        // an `i64`, the free column's null vector (their least common multiple) does not,
        // and the backend's null space is taken.
        let mut wide = Fixture::new(&[("a", 1), ("b", 1), ("c", 1), ("d", 1), ("e", 1)]);
        for (label, p, k) in [("r1", "a", 1), ("r2", "b", 3), ("r3", "c", 5)] {
            wide.scalar(label, &[(p, 0, (1 << 62) + k), ("d", 0, 1), ("e", 0, 1)], 0);
        }
        let offsets = wide.system.coordinate_offsets();
        let start = std::iter::once((wide.id("e"), 0));
        let component = Component::of(&wide.system, &offsets, start).expect("a component");
        let words = WordElimination::of(&component.a, &[vec![(4, Integer::one())]], Some(&[q(1)]))
            .expect("the elimination fits");
        assert!(words.null_space().is_none());
        let analysed = in_words_and_by_the_backend(&wide, &[wide.id("e")], Some(&[q(1)]), 1_000);
        for (with, without) in analysed {
            let with = with.expect("analysed");
            assert!(matches!(with.outcome, Some(MoveOutcome::Moves(ref m)) if !m.is_empty()));
            assert_eq!(Ok(with), without);
        }
    }

    proptest::proptest! {
        /// Eliminating a small `M` in machine words changes no answer: on random systems of
        /// parameters of dimension 2 and 1 (vector and scalar rows, equalities among them,
        /// coefficients up to ±3 and sometimes near 2^31 so that products leave an `i64`),
        /// picks, moves with denominators or none, and budgets, the analysis in words equals
        /// the backend's — case, directions, lost directions with their rows, blocked moves
        /// with theirs, forced moves, freedoms and refusals.
        #[test]
        fn eliminating_in_words_changes_no_answer(
            rows in proptest::collection::vec(
                (
                    proptest::bool::ANY,
                    proptest::collection::vec((0usize..6, 0usize..2, -3i64..=3), 1..4),
                ),
                1..9,
            ),
            large in proptest::option::of((0usize..9, 0usize..4)),
            picked in proptest::collection::btree_set(0usize..6, 1..3),
            moves in proptest::collection::vec((-4i64..=4, 1i64..=3), 4),
            requested in proptest::bool::ANY,
            small_budget in proptest::bool::ANY,
        ) {
            let dims = [2, 1, 2, 2, 1, 2];
            let names = ["a", "b", "c", "d", "e", "f"];
            let mut f = Fixture::new(&names.iter().zip(dims).map(|(n, d)| (*n, d)).collect::<Vec<_>>());
            for (i, (vector, terms)) in rows.iter().enumerate() {
                let label = format!("row {i}");
                let coefficient = |j: usize, c: i64| match large {
                    Some((row, term)) if row == i && term == j => c * ((1 << 31) + 11),
                    _ => c,
                };
                if *vector {
                    let mut vector_terms: Vec<(&str, i64)> = Vec::new();
                    for (j, &(p, _, c)) in terms.iter().enumerate() {
                        let p = if dims[p] == 2 { p } else { p + 1 };
                        if c != 0 && !vector_terms.iter().any(|(q, _)| *q == names[p]) {
                            vector_terms.push((names[p], coefficient(j, c)));
                        }
                    }
                    if !vector_terms.is_empty() {
                        f.vector(&label, &vector_terms, 2);
                    }
                } else {
                    let mut scalar_terms: Vec<(&str, usize, i64)> = Vec::new();
                    for (j, &(p, k, c)) in terms.iter().enumerate() {
                        let k = k % dims[p];
                        if c != 0 && !scalar_terms.iter().any(|(q, l, _)| *q == names[p] && *l == k) {
                            scalar_terms.push((names[p], k, coefficient(j, c)));
                        }
                    }
                    if !scalar_terms.is_empty() {
                        f.scalar(&label, &scalar_terms, 0);
                    }
                }
            }
            let picked: Vec<ParamId> = picked.iter().map(|&p| f.id(names[p])).collect();
            let coordinates: usize = picked.iter().map(|p| f.system.params()[p.index()].dim).sum();
            let m: Vec<Rational> = moves[..coordinates]
                .iter()
                .map(|&(n, d)| Rational::new(Integer::from(n), Integer::from(d)))
                .collect();
            let budget = if small_budget { 12 } else { EXPLAIN_NULL_SPACE_BUDGET };
            for (with, without) in
                in_words_and_by_the_backend(&f, &picked, requested.then_some(&m[..]), budget)
            {
                proptest::prop_assert_eq!(with, without);
            }
        }
    }

    proptest::proptest! {
        /// On random small systems: every forced value is what every solution of the move
        /// gives (checked against a solution with the other free directions pushed), the
        /// directions and lost directions are complementary, and a blocked move is blocked.
        #[test]
        fn forced_moves_are_forced_and_directions_complement_the_lost(
            entries in proptest::collection::vec(-2i64..=2, 12),
            m in proptest::collection::vec(-3i64..=3, 2),
        ) {
            // Three rows over a (dim 2), b, c, d (dim 1): 5 coordinates.
            let mut f = Fixture::new(&[("a", 2), ("b", 1), ("c", 1), ("d", 1)]);
            let coords = [("a", 0), ("a", 1), ("b", 0), ("c", 0)];
            for (i, row) in entries.chunks(4).enumerate() {
                let mut terms: Vec<(&str, usize, i64)> =
                    coords.iter().zip(row).map(|(&(p, k), &c)| (p, k, c)).collect();
                terms.push(("d", 0, 1));
                f.scalar(&format!("row {i}"), &terms, 0);
            }
            let a = f.analyze(&["a"], Some(&m));
            proptest::prop_assert_eq!(a.directions.len() + a.lost.len(), 2);
            // The directions are ker A projected on a, read off A's own null space.
            let (matrix, _, _) = f.system.scalar_matrix();
            let kernel = ExactLdu::default().factor(&matrix).expect("factored").null_space();
            proptest::prop_assert_eq!(&a.directions, &projected_basis(&kernel, &[0, 1]));
            for lost in &a.lost {
                for d in &a.directions {
                    let dot: Integer = lost.direction.iter().zip(d).map(|(x, y)| x * y).sum();
                    proptest::prop_assert!(dot.is_zero());
                }
            }
            match a.outcome.expect("a move") {
                MoveOutcome::Blocked(rows) => {
                    // yᵀ A vanishes off a, and yᵀ A δ_a ≠ 0: no move reaches m.
                    let mut combined = vec![Rational::zero(); matrix.cols()];
                    for (row, _, y) in &rows {
                        for (c, v) in matrix.row(row.index()) {
                            combined[*c] += y * Rational::from_integer(v.clone());
                        }
                    }
                    proptest::prop_assert!(combined[2..].iter().all(Zero::is_zero));
                    let along = &combined[0] * q(m[0]) + &combined[1] * q(m[1]);
                    proptest::prop_assert!(!along.is_zero());
                }
                MoveOutcome::Moves(follows) => {
                    // Brute force: the forced values are the same for every solution of
                    // [A; E_a] δ = [0; m]: compare with the minimum-norm-free solution through
                    // the backend and with it plus each null direction.
                    let mut with_picked = matrix.clone();
                    with_picked.push_row(vec![(0, Integer::one())]).expect("row");
                    with_picked.push_row(vec![(1, Integer::one())]).expect("row");
                    let factored = ExactLdu::default().factor(&with_picked).expect("factored");
                    let mut rhs = vec![Rational::zero(); matrix.rows()];
                    rhs.extend([q(m[0]), q(m[1])]);
                    let x = factored.solve(&rhs).expect("solvable: not blocked");
                    for v in factored.null_space() {
                        let shifted: Vec<Rational> = x.iter().zip(&v).map(|(a, b)| a + b).collect();
                        for (param, follows) in &follows {
                            if let Follows::Forced(value) = follows {
                                let c = 2 + (param.index() - 1);
                                proptest::prop_assert_eq!(&shifted[c], &value[0]);
                                proptest::prop_assert_eq!(&x[c], &value[0]);
                            }
                        }
                    }
                }
            }
        }
    }

    /// [`row_basis`] of the projections of `vectors` onto `coordinates`, leaving out zero
    /// projections.
    fn projected_basis(vectors: &[Vec<Rational>], coordinates: &[usize]) -> Vec<Vec<Integer>> {
        row_basis(
            coordinates.len(),
            vectors
                .iter()
                .filter(|v| coordinates.iter().any(|&c| !v[c].is_zero()))
                .map(|v| {
                    let projected: Vec<Rational> =
                        coordinates.iter().map(|&c| v[c].clone()).collect();
                    integer_multiple(&projected)
                }),
        )
    }

    proptest::proptest! {
        /// Each parameter's freedom is the rank of the move's free directions projected on it
        /// (plain rational elimination over the null space of `[A; E_P]`), and it may stay
        /// exactly when its value in one solution lies in that span — on random systems of
        /// parameters of dimension 2 and 1, where projections with a single nonzero entry
        /// and whole-space spans both occur.
        #[test]
        fn freedoms_and_choices_are_those_of_the_null_space(
            entries in proptest::collection::vec(-2i64..=2, 21),
            m in proptest::collection::vec(-3i64..=3, 2),
        ) {
            // Three rows over a, b, c (dim 2) and d (dim 1): 7 coordinates.
            let mut f = Fixture::new(&[("a", 2), ("b", 2), ("c", 2), ("d", 1)]);
            let coords = [("a", 0), ("a", 1), ("b", 0), ("b", 1), ("c", 0), ("c", 1), ("d", 0)];
            for (i, row) in entries.chunks(7).enumerate() {
                let terms: Vec<(&str, usize, i64)> = coords
                    .iter()
                    .zip(row)
                    .filter(|(_, &c)| c != 0)
                    .map(|(&(p, k), &c)| (p, k, c))
                    .collect();
                if !terms.is_empty() {
                    f.scalar(&format!("row {i}"), &terms, 0);
                }
            }
            let analysis = f.analyze(&["a"], Some(&m));
            let MoveOutcome::Moves(moves) = analysis.outcome.expect("a move") else {
                return Ok(());
            };
            // [A; E_a] over all 7 coordinates, its null space and one solution of the move.
            let (mut whole, _, _) = f.system.scalar_matrix();
            let rows_of_a = whole.rows();
            for c in [0, 1] {
                whole.push_row(vec![(c, Integer::one())]).expect("in range");
            }
            let factored = ExactLdu::default().factor(&whole).expect("factored");
            let mut rhs = vec![Rational::zero(); rows_of_a];
            rhs.extend(m.iter().map(|&x| q(x)));
            let x = factored.solve(&rhs).expect("reached");
            let free = factored.null_space();
            // The component of a: coordinates linked to a's through rows (the analysis looks
            // at nothing else).
            let mut linked = [false; 7];
            linked[0] = true;
            linked[1] = true;
            for _ in 0..7 {
                for row in whole.row_iter().take(rows_of_a) {
                    if row.iter().any(|(c, _)| linked[*c]) {
                        row.iter().for_each(|(c, _)| linked[*c] = true);
                    }
                }
            }
            for (name, all) in [("b", vec![2, 3]), ("c", vec![4, 5]), ("d", vec![6])] {
                let coordinates: Vec<usize> = all.into_iter().filter(|&c| linked[c]).collect();
                let projected: Vec<Vec<Rational>> = free
                    .iter()
                    .map(|v| coordinates.iter().map(|&c| v[c].clone()).collect())
                    .collect();
                let freedom = plain_rank(&projected);
                let value: Vec<Rational> = coordinates.iter().map(|&c| x[c].clone()).collect();
                let mut with_value = projected.clone();
                with_value.push(value.clone());
                let may_stay = plain_rank(&with_value) == freedom;
                let found = moves.iter().find(|(p, _)| *p == f.id(name)).map(|(_, e)| e);
                match found {
                    None => {
                        proptest::prop_assert_eq!(freedom, 0);
                        proptest::prop_assert!(value.iter().all(Zero::is_zero));
                    }
                    Some(Follows::Forced(by)) => {
                        proptest::prop_assert_eq!(freedom, 0);
                        proptest::prop_assert_eq!(by, &value);
                    }
                    Some(Follows::MayStay { freedom: found }) => {
                        proptest::prop_assert_eq!(*found, freedom);
                        proptest::prop_assert!(freedom > 0 && may_stay);
                    }
                    Some(Follows::MustMoveWithChoice { freedom: found }) => {
                        proptest::prop_assert_eq!(*found, freedom);
                        proptest::prop_assert!(freedom > 0 && !may_stay);
                    }
                }
            }
        }
    }

    /// Rank of rational vectors by plain Gaussian elimination, looking at every vector.
    fn plain_rank(vectors: &[Vec<Rational>]) -> usize {
        let mut rows: Vec<Vec<Rational>> = vectors.to_vec();
        let width = rows.first().map_or(0, Vec::len);
        let mut rank = 0;
        for c in 0..width {
            let Some(p) = (rank..rows.len()).find(|&i| !rows[i][c].is_zero()) else {
                continue;
            };
            rows.swap(rank, p);
            let pivot = rows[rank].clone();
            for row in rows.iter_mut().skip(rank + 1) {
                let f = &row[c] / &pivot[c];
                for (x, y) in row.iter_mut().zip(&pivot) {
                    *x -= &f * y;
                }
            }
            rank += 1;
        }
        rank
    }

    proptest::proptest! {
        /// The basis spans what the vectors span (every vector, the skipped ones after a full
        /// span included, lies in it, and its size is the plain rank), in reduced echelon
        /// form with coprime integer rows and positive leading entries; projections give the
        /// basis of the projected vectors.
        #[test]
        fn row_bases_span_the_vectors(
            entries in proptest::collection::vec(-3i64..=3, 0..40),
            width in 1usize..4,
        ) {
            let vectors: Vec<Vec<Rational>> = entries
                .chunks_exact(width)
                .map(|chunk| chunk.iter().map(|&x| q(x)).collect())
                .collect();
            let basis = row_basis(width, vectors.iter().map(|v| integer_multiple(v)));
            proptest::prop_assert_eq!(basis.len(), plain_rank(&vectors));
            let as_rationals: Vec<Vec<Rational>> = basis
                .iter()
                .map(|r| r.iter().cloned().map(Rational::from_integer).collect())
                .collect();
            for v in &vectors {
                let mut with_v = as_rationals.clone();
                with_v.push(v.clone());
                proptest::prop_assert_eq!(plain_rank(&with_v), basis.len());
            }
            let leads: Vec<usize> = basis
                .iter()
                .map(|r| r.iter().position(|x| !x.is_zero()).expect("no zero row"))
                .collect();
            for (k, row) in basis.iter().enumerate() {
                proptest::prop_assert!(row[leads[k]].is_positive());
                proptest::prop_assert!(k == 0 || leads[k - 1] < leads[k]);
                for (other, &lead) in basis.iter().zip(&leads) {
                    if other != row {
                        proptest::prop_assert!(row[lead].is_zero());
                    }
                }
                let content = row.iter().fold(Integer::zero(), |g, x| num_integer::Integer::gcd(&g, x));
                proptest::prop_assert!(content.is_one());
            }
            // Projected onto the last coordinate (and the first, when there are two or more).
            let coordinates: Vec<usize> = if width > 1 { vec![width - 1, 0] } else { vec![0] };
            let projected: Vec<Vec<Rational>> = vectors
                .iter()
                .map(|v| coordinates.iter().map(|&c| v[c].clone()).collect())
                .collect();
            proptest::prop_assert_eq!(
                projected_basis(&vectors, &coordinates),
                row_basis(coordinates.len(), projected.iter().map(|v| integer_multiple(v)))
            );
        }

        /// The integer echelon's dimension is the plain rank of what was inserted, and it
        /// contains exactly the vectors that do not raise that rank.
        #[test]
        fn integer_echelons_know_their_span(
            entries in proptest::collection::vec(-4i64..=4, 0..40),
            probe in proptest::collection::vec(-4i64..=4, 4),
            width in 1usize..5,
        ) {
            let vectors: Vec<Vec<i64>> =
                entries.chunks_exact(width).map(<[i64]>::to_vec).collect();
            let as_rationals = |v: &[i64]| v.iter().map(|&x| q(x)).collect::<Vec<_>>();
            let mut span = IntegerEchelon::new(width);
            for v in &vectors {
                span.insert(v.iter().map(|&x| Integer::from(x)).collect());
            }
            let rationals: Vec<Vec<Rational>> = vectors.iter().map(|v| as_rationals(v)).collect();
            let rank = plain_rank(&rationals);
            proptest::prop_assert_eq!(span.dimension(), rank);
            proptest::prop_assert_eq!(span.is_whole_space(), rank == width);
            for candidate in vectors.iter().map(Vec::as_slice).chain([&probe[..width]]) {
                let mut with = rationals.clone();
                with.push(as_rationals(candidate));
                proptest::prop_assert_eq!(
                    span.contains(candidate.iter().map(|&x| Integer::from(x)).collect()),
                    plain_rank(&with) == rank
                );
            }
        }
    }
}
