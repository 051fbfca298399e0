//! Whole-system analysis: exact rank, redundant rows with their combinations, consistency with a
//! certificate, and the float backend's view of the same matrix.

use crate::report::{CrossCheckReport, Margin, RedundantRow, Term};
use api::{
    format_rational, ConstraintSystem, Factorization, IntMatrix, Integer, LinearBackend, Rational,
    RowBody, RowId, Values,
};
use exact_ldu::sparse::{eliminate_blockwise, Combinations};
use float_qr::FloatQr;
use std::collections::BTreeSet;

/// Largest connected component (rows × columns) the float cross-check factors by the dense
/// column-pivoted QR (whose pivoting orders rows by new direction, the best rank decision);
/// larger components go to the sparse Givens QR ([`float_qr::sparse_row_rank`]), so the
/// cross-check never gives up.
pub const DENSE_LIMIT: usize = 250_000;

/// Up to this many nonzeros the float cross-check runs beside the exact elimination.
pub const CONCURRENT_CROSS_CHECK_NONZEROS: usize = 1_000_000;

/// Combinations of more terms than this are written compactly: runs of consecutive rows with
/// one coefficient become one term (`row`, `through`, `rows`).
pub const COMPACT_ABOVE: usize = 256;

/// The exact facts about a system.
#[derive(Debug, Clone, Default)]
pub struct Analysis {
    /// Scalar parameters.
    pub parameters: usize,
    /// Scalar rows.
    pub constraints: usize,
    /// Exact rank (scalar).
    pub rank: usize,
    /// Whether `R p = q` is solvable.
    pub consistent: bool,
    /// Redundant rows.
    pub redundant: Vec<RedundantRow>,
    /// Labels of a minimal conflicting set.
    pub conflict: Option<Vec<String>>,
    /// Labels of rows violated by the current values.
    pub violated: Vec<String>,
    /// Float view.
    pub cross_check: CrossCheckReport,
    /// Structural view.
    pub structure: Option<crate::structural::StructureReport>,
}

/// The matrix analysed, with row labels and column names.
pub struct SystemMatrix {
    /// The matrix analysed.
    pub matrix: IntMatrix,
    /// Right-hand sides (integers, as every row's), one column per coordinate.
    pub rhs: Vec<Vec<Integer>>,
    /// Label of each row.
    pub labels: Vec<String>,
    /// Name of each column: a parameter, or `name[k]` for coordinate `k` of a vector parameter.
    pub columns: Vec<String>,
    /// Coordinates per matrix row (the scalar count is rows × this).
    pub copies: usize,
}

/// The matrix the analysis works on: one column per parameter when every row is a vector row
/// of the parameters' common dimension (the coordinates then share one matrix), one column per
/// coordinate otherwise.
pub fn shape(system: &ConstraintSystem) -> SystemMatrix {
    match vector_dimension(system) {
        Some(d) => {
            let rows = system
                .rows()
                .iter()
                .map(|r| match &r.body {
                    RowBody::Vector { terms, .. } => {
                        terms.iter().map(|(p, c)| (p.index(), c.clone())).collect()
                    }
                    RowBody::Scalar { .. } => Vec::new(),
                })
                .collect();
            let matrix = IntMatrix::from_sparse(system.params().len(), rows)
                .expect("parameter ids were validated");
            let rhs = (0..d)
                .map(|k| {
                    system
                        .rows()
                        .iter()
                        .map(|r| match &r.body {
                            RowBody::Vector { rhs, .. } => rhs[k].clone(),
                            RowBody::Scalar { rhs, .. } => rhs.clone(),
                        })
                        .collect()
                })
                .collect();
            SystemMatrix {
                matrix,
                rhs,
                labels: system.rows().iter().map(|r| r.label.clone()).collect(),
                columns: system.params().iter().map(|p| p.name.to_string()).collect(),
                copies: d,
            }
        }
        None => scalar_shape(system),
    }
}

/// [`shape`] taking the system: the coefficients, right-hand sides, labels and names move into
/// the matrix instead of being copied (for `ecles analyze`, where the system is released after;
/// at a whole mesh the copy was a fifth of the peak memory).
pub fn shape_owned(system: ConstraintSystem) -> SystemMatrix {
    let Some(d) = vector_dimension(&system) else {
        return scalar_shape(&system);
    };
    let (params, rows) = system.into_parts();
    let columns: Vec<String> = params.into_iter().map(|p| p.name.to_string()).collect();
    let mut rhs: Vec<Vec<Integer>> = (0..d).map(|_| Vec::with_capacity(rows.len())).collect();
    let mut labels = Vec::with_capacity(rows.len());
    let matrix_rows = rows
        .into_iter()
        .map(|row| {
            labels.push(row.label);
            match row.body {
                RowBody::Vector { terms, rhs: q } => {
                    for (column, value) in rhs.iter_mut().zip(q) {
                        column.push(value);
                    }
                    terms.into_iter().map(|(p, c)| (p.index(), c)).collect()
                }
                // Not met (every row is a vector row here); kept as `shape` has it.
                RowBody::Scalar { rhs: q, .. } => {
                    for column in &mut rhs {
                        column.push(q.clone());
                    }
                    Vec::new()
                }
            }
        })
        .collect();
    let matrix =
        IntMatrix::from_sparse(columns.len(), matrix_rows).expect("parameter ids were validated");
    SystemMatrix {
        matrix,
        rhs,
        labels,
        columns,
        copies: d,
    }
}

/// The common dimension when every row is a vector row of the parameters' one dimension (or the
/// system has no parameters), so the coordinates share one matrix; `None` otherwise.
fn vector_dimension(system: &ConstraintSystem) -> Option<usize> {
    let dims: BTreeSet<usize> = system.params().iter().map(|p| p.dim).collect();
    match (dims.len(), dims.iter().next()) {
        (1, Some(&d)) => system
            .rows()
            .iter()
            .all(|r| matches!(&r.body, RowBody::Vector { rhs, .. } if rhs.len() == d))
            .then_some(d),
        (0, _) => Some(1),
        _ => None,
    }
}

/// The matrix with one column per coordinate (see [`shape`]).
fn scalar_shape(system: &ConstraintSystem) -> SystemMatrix {
    let (matrix, rhs, origin) = system.scalar_matrix();
    let labels = origin
        .iter()
        .map(|(row, k)| label(system, *row, Some(*k)))
        .collect();
    let columns = system
        .params()
        .iter()
        .flat_map(|p| {
            (0..p.dim).map(move |k| {
                if p.dim == 1 {
                    p.name.to_string()
                } else {
                    format!("{}[{k}]", p.name)
                }
            })
        })
        .collect();
    SystemMatrix {
        matrix,
        rhs: vec![rhs],
        labels,
        columns,
        copies: 1,
    }
}

/// A row's label, with the coordinate for split vector rows.
pub fn label(system: &ConstraintSystem, row: RowId, component: Option<usize>) -> String {
    let r = &system.rows()[row.index()];
    match (&r.body, component) {
        (RowBody::Vector { rhs, .. }, Some(k)) if rhs.len() > 1 => format!("{}[{k}]", r.label),
        _ => r.label.clone(),
    }
}

/// What the analysis needs from the system itself rather than from its graph: the scalar
/// counts and the rows the values violate. Once these are taken, the graph alone carries the
/// analysis (the system and the values may be released).
pub struct SystemFacts {
    /// Scalar parameters.
    pub parameters: usize,
    /// Scalar rows.
    pub constraints: usize,
    /// Labels of rows violated by the values.
    pub violated: Vec<String>,
}

impl SystemFacts {
    /// The facts of `system` at `values`.
    pub fn of(system: &ConstraintSystem, values: &Values) -> SystemFacts {
        let mut seen = BTreeSet::new();
        SystemFacts {
            parameters: system.coordinate_count(),
            constraints: system.rows().iter().map(|r| r.body.scalar_rows()).sum(),
            violated: system
                .violations(values)
                .into_iter()
                .filter(|(row, _, _)| seen.insert(*row))
                .map(|(row, _, _)| system.rows()[row.index()].label.clone())
                .collect(),
        }
    }
}

/// Analyses a system from its `facts` and its graph `graph` with the exact backend and, when
/// `tolerance` is given, the float one.
pub fn analyze(
    facts: SystemFacts,
    graph: &crate::structural::SystemGraph,
    tolerance: Option<f64>,
) -> Analysis {
    analyze_with(facts, &graph.shape, tolerance, |elimination| {
        crate::structural::report(graph, elimination)
    })
}

/// [`analyze`] taking the graph, for a caller that needs nothing after (`ecles analyze`):
/// the bipartite graph, its matching and its Dulmage–Mendelsohn decomposition are released
/// once the structure section is made, before the float cross-check of a large matrix (at a
/// whole mesh they were a seventh of its peak memory).
pub fn analyze_owned(
    facts: SystemFacts,
    graph: crate::structural::SystemGraph,
    tolerance: Option<f64>,
) -> Analysis {
    let crate::structural::SystemGraph {
        shape,
        graph,
        matching,
        dm,
    } = graph;
    analyze_with(facts, &shape, tolerance, |elimination| {
        let report =
            crate::structural::report_of_parts(&shape, &graph, &matching, &dm, elimination);
        drop((graph, matching, dm));
        report
    })
}

/// The analysis of `shape`, with `structure` making the structure section from the exact
/// elimination (before the float view when the two run one after the other).
fn analyze_with(
    facts: SystemFacts,
    shape: &SystemMatrix,
    tolerance: Option<f64>,
    structure: impl FnOnce(&exact_ldu::sparse::SparseElimination) -> crate::structural::StructureReport,
) -> Analysis {
    let mut analysis = Analysis {
        parameters: facts.parameters,
        constraints: facts.constraints,
        violated: facts.violated,
        ..Analysis::default()
    };
    // Exact: sparse fraction-free elimination per connected component (identical components,
    // such as the x and y coordinates, once). Scales to large meshes.
    // The float view does not depend on the exact one until they are compared: both run at
    // once, unless the matrix is so large that holding both working sets would double the peak
    // memory of whole-mesh runs.
    let exact = || eliminate_blockwise(&shape.matrix, &shape.rhs, Combinations::Exact);
    let float = || tolerance.map(|tol| float_view(shape, tol));
    let (elimination, structure, float_view) =
        if shape.matrix.nnz() <= CONCURRENT_CROSS_CHECK_NONZEROS {
            let (elimination, float_view) = rayon::join(exact, float);
            let structure = structure(&elimination);
            (elimination, structure, float_view)
        } else {
            let elimination = exact();
            let structure = structure(&elimination);
            (elimination, structure, float())
        };
    analysis.rank = elimination.rank * shape.copies;
    analysis.structure = Some(structure);
    // A row is redundant only if its whole equation, right-hand side included, is the
    // combination; a row whose left side is a combination but whose right side differs
    // contradicts the others and belongs in `conflict`.
    analysis.redundant = elimination
        .redundant
        .iter()
        .filter(|red| red.inconsistent_columns.is_empty())
        .map(|red| RedundantRow {
            row: shape.labels[red.row].clone(),
            equations: shape.copies,
            combination: red.combination.as_ref().map(|w| terms(w, &shape.labels)),
        })
        .collect();
    analysis.consistent = elimination.consistent();
    if let Some(red) = elimination
        .redundant
        .iter()
        .find(|r| !r.inconsistent_columns.is_empty())
    {
        let mut rows: Vec<usize> = red
            .combination
            .as_ref()
            .map(|w| w.iter().map(|(i, _)| *i).collect())
            .unwrap_or_default();
        rows.push(red.row);
        rows.sort_unstable();
        analysis.conflict = Some(rows.iter().map(|&i| shape.labels[i].clone()).collect());
    }
    if let Some(mut report) = float_view {
        if report.skipped.is_none() && report.float_rank != Some(elimination.rank * shape.copies) {
            report.disagreements.insert(
                0,
                format!(
                    "rank: exact {}, float {}",
                    elimination.rank * shape.copies,
                    report.float_rank.unwrap_or(0)
                ),
            );
        }
        report.agree = report
            .skipped
            .is_none()
            .then_some(report.disagreements.is_empty());
        analysis.cross_check = report;
    }
    analysis
}

/// The terms of a combination `(row, coefficient)` (increasing rows); above
/// [`COMPACT_ABOVE`] terms, runs of consecutive rows with one coefficient are one term.
fn terms(w: &[(usize, Rational)], labels: &[String]) -> Vec<Term> {
    let single = |i: usize, c: &Rational| Term {
        row: labels[i].clone(),
        through: None,
        rows: None,
        coefficient: format_rational(c),
    };
    if w.len() <= COMPACT_ABOVE {
        return w.iter().map(|(i, c)| single(*i, c)).collect();
    }
    let mut out = Vec::new();
    let mut k = 0;
    while k < w.len() {
        let (first, c) = &w[k];
        let mut end = k + 1;
        while end < w.len() && w[end].0 == first + (end - k) && w[end].1 == *c {
            end += 1;
        }
        let mut term = single(*first, c);
        if end - k > 1 {
            term.through = Some(labels[w[end - 1].0].clone());
            term.rows = Some(end - k);
        }
        out.push(term);
        k = end;
    }
    out
}

/// The float rank of the component of `matrix` with rows `rows` and columns `cols`: the dense
/// QR for small components (on a copy), the sparse QR for large ones (read from `matrix`
/// directly: a whole mesh is one component, and a copy of it was a tenth of the peak memory).
/// Returns the rank, the independent rows (indices into `rows`), the margin and the method.
fn float_component_rank(
    matrix: &IntMatrix,
    rows: &[usize],
    cols: &[usize],
    tolerance: f64,
) -> Result<(usize, Vec<usize>, api::RankMargin, &'static str), String> {
    if rows.len().saturating_mul(cols.len()) <= DENSE_LIMIT {
        let local = exact_ldu::submatrix(matrix, rows, cols);
        let backend = FloatQr::new(tolerance).map_err(|e| e.to_string())?;
        let f = backend
            .factor(&local)
            .map_err(|e| format!("float factoring failed: {e}"))?;
        let margin = f.rank_margin().unwrap_or(api::RankMargin {
            smallest_kept: 1.0,
            largest_dropped: 0.0,
            tolerance,
        });
        Ok((f.rank(), f.independent_rows(), margin, "dense QR"))
    } else {
        let r = float_qr::sparse_part_row_rank(matrix, rows, cols, tolerance)
            .map_err(|e| format!("float factoring failed: {e}"))?;
        Ok((r.rank, r.independent, r.margin, "sparse QR"))
    }
}

/// The float backend's view of the whole matrix, per connected component (the dense QR for
/// small ones, the sparse QR for large ones), and whether the rows it kept are independent
/// exactly (naming those that are not); the caller compares its rank with the exact one.
fn float_view(shape: &SystemMatrix, tolerance: f64) -> CrossCheckReport {
    let mut report = CrossCheckReport {
        enabled: true,
        tolerance: Some(tolerance),
        ..CrossCheckReport::default()
    };
    let mut rank = 0;
    let mut independent: Vec<usize> = Vec::new();
    let (mut smallest_kept, mut largest_dropped) = (1.0_f64, 0.0_f64);
    let mut methods = BTreeSet::new();
    for (rows, cols) in exact_ldu::components(&shape.matrix) {
        if rows.is_empty() {
            continue;
        }
        match float_component_rank(&shape.matrix, &rows, &cols, tolerance) {
            Ok((r, kept, margin, method)) => {
                rank += r;
                independent.extend(kept.iter().map(|&k| rows[k]));
                smallest_kept = smallest_kept.min(margin.smallest_kept);
                largest_dropped = largest_dropped.max(margin.largest_dropped);
                methods.insert(method);
            }
            Err(why) => {
                report.skipped = Some(why);
                return report;
            }
        }
    }
    report.method = Some(methods.into_iter().collect::<Vec<_>>().join(", "));
    report.float_rank = Some(rank * shape.copies);
    report.margin = Some(Margin {
        smallest_kept,
        largest_dropped,
    });
    independent.sort_unstable();
    let sub = select_rows(&shape.matrix, &independent);
    let exact = eliminate_blockwise(&sub, &[], Combinations::Skip);
    if exact.rank != independent.len() {
        let named: Vec<&str> = exact
            .redundant
            .iter()
            .take(5)
            .map(|r| shape.labels[independent[r.row]].as_str())
            .collect();
        report.disagreements.push(format!(
            "the float backend kept {} rows as independent, but only {} of them are (exact combinations of the others: {}{})",
            independent.len(),
            exact.rank,
            named.join("; "),
            if exact.redundant.len() > named.len() { "; …" } else { "" }
        ));
    }
    report
}

fn select_rows(matrix: &IntMatrix, rows: &[usize]) -> IntMatrix {
    let cols: Vec<usize> = (0..matrix.cols()).collect();
    matrix.select(rows, &cols)
}

/// Largest absolute residual over all rows, as exact text (`"0"` when every row holds).
pub fn max_residual(system: &ConstraintSystem, values: &Values) -> String {
    system
        .violations(values)
        .into_iter()
        .map(|(_, _, r)| {
            if r < Rational::from_integer(Integer::from(0)) {
                -r
            } else {
                r
            }
        })
        .max()
        .map(|r| format_rational(&r))
        .unwrap_or_else(|| "0".to_string())
}
