//! The `structure` section of the report and `ecles explain`: connected components, the
//! Dulmage–Mendelsohn parts and blocks (crate `structure`), and where the exact rank falls short
//! of the structural rank.

use crate::analysis::SystemMatrix;
use exact_ldu::sparse::{eliminate, Combinations, SparseElimination};
use serde::Serialize;
use structure::{
    components, decompose, dulmage_mendelsohn, explain, maximum_matching, Bipartite,
    DmDecomposition, Matching, PartKind,
};

/// Names listed per part or block before the report says "and N more".
const LIST_LIMIT: usize = 50;
/// Blocks listed in solve order before the report stops listing.
const BLOCK_LIMIT: usize = 200;

/// The structural view of the whole system.
#[derive(Debug, Clone, Serialize)]
pub struct StructureReport {
    /// `"parameters"` when vector parameters share one matrix, `"coordinates"` otherwise.
    pub columns_are: String,
    /// Connected components of the constraint graph.
    pub components: usize,
    /// Maximum matching size, in scalar rows.
    pub structural_rank: usize,
    /// Exact rank, in scalar rows.
    pub exact_rank: usize,
    /// `structural_rank − exact_rank`: dependencies that come from the coefficient values, not
    /// from the pattern.
    pub numerical_dependency: usize,
    /// Over-determined part (more constraints than unknowns).
    pub over: PartReport,
    /// Well-determined part (square, perfectly matched).
    pub well: PartReport,
    /// Under-determined part (free unknowns).
    pub under: PartReport,
    /// Irreducible blocks of the well part in solve order (the first 200).
    pub blocks: Vec<BlockReport>,
    /// Number of blocks.
    pub blocks_total: usize,
    /// Components and blocks whose exact rank is below their structural rank.
    pub dependent: Vec<DependentReport>,
}

/// One Dulmage–Mendelsohn part.
#[derive(Debug, Clone, Serialize)]
pub struct PartReport {
    /// Constraint rows in the part.
    pub rows: usize,
    /// Columns (parameters or coordinates) in the part.
    pub columns: usize,
    /// Row labels (the first 50).
    pub row_labels: Vec<String>,
    /// Column names (the first 50).
    pub column_names: Vec<String>,
}

/// One irreducible block.
#[derive(Debug, Clone, Serialize)]
pub struct BlockReport {
    /// Position in the solve order.
    pub index: usize,
    /// Its rows.
    pub rows: Vec<String>,
    /// Its columns.
    pub columns: Vec<String>,
    /// Blocks solved before it that it uses.
    pub depends_on: Vec<usize>,
}

/// A component or block carrying numerical dependency.
#[derive(Debug, Clone, Serialize)]
pub struct DependentReport {
    /// `"component 2"` or `"block 7"`.
    pub place: String,
    /// Structural rank there.
    pub structural_rank: usize,
    /// Exact rank there.
    pub exact_rank: usize,
    /// Labels of its rows found redundant (the first 50).
    pub redundant_rows: Vec<String>,
}

fn capped(names: impl Iterator<Item = String>) -> Vec<String> {
    names.take(LIST_LIMIT).collect()
}

fn part(shape: &SystemMatrix, dm: &DmDecomposition, kind: PartKind) -> PartReport {
    let p = dm.part(kind);
    PartReport {
        rows: p.rows.len(),
        columns: p.cols.len(),
        row_labels: capped(p.rows.iter().map(|&i| shape.labels[i].clone())),
        column_names: capped(p.cols.iter().map(|&j| shape.columns[j].clone())),
    }
}

/// The whole system's matrix ([`SystemMatrix`]), its bipartite graph, a maximum matching and the
/// Dulmage–Mendelsohn decomposition: computed once per run, for the report, `explain` and
/// pictures coloured by part.
pub struct SystemGraph {
    /// The matrix analysed, with labels and column names.
    pub shape: SystemMatrix,
    /// Its bipartite constraint graph.
    pub graph: Bipartite,
    /// A maximum matching (Hopcroft–Karp).
    pub matching: Matching,
    /// The Dulmage–Mendelsohn parts and blocks.
    pub dm: DmDecomposition,
}

impl SystemGraph {
    /// The graph and decomposition of `system`'s matrix.
    pub fn new(system: &api::ConstraintSystem) -> SystemGraph {
        SystemGraph::of_shape(crate::analysis::shape(system))
    }

    /// The graph and decomposition of an analysed matrix (see [`crate::analysis::shape`] and
    /// [`crate::analysis::shape_owned`]).
    pub fn of_shape(shape: SystemMatrix) -> SystemGraph {
        let graph = Bipartite::from_matrix(&shape.matrix);
        let matching = maximum_matching(&graph);
        let dm = dulmage_mendelsohn(&graph, &matching)
            .expect("the matching of maximum_matching is a valid maximum matching");
        SystemGraph {
            shape,
            graph,
            matching,
            dm,
        }
    }
}

/// The structure section of the system, with the exact elimination of the same matrix.
pub fn report(system: &SystemGraph, exact: &SparseElimination) -> StructureReport {
    report_of_parts(
        &system.shape,
        &system.graph,
        &system.matching,
        &system.dm,
        exact,
    )
}

/// [`report`] from the parts of a [`SystemGraph`], for a caller that has taken it apart (to
/// release the graph before the float cross-check while keeping the matrix).
pub fn report_of_parts(
    shape: &SystemMatrix,
    graph: &Bipartite,
    matching: &Matching,
    dm: &DmDecomposition,
    exact: &SparseElimination,
) -> StructureReport {
    let comps = components(graph);
    let mut is_pivot = vec![false; shape.matrix.rows()];
    for (row, _) in &exact.pivots {
        is_pivot[*row] = true;
    }
    let matched: Vec<bool> = matching.row_to_col.iter().map(Option::is_some).collect();
    let mut dependent = Vec::new();
    for (k, c) in comps.components.iter().enumerate() {
        let structural = c.rows.iter().filter(|&&i| matched[i]).count();
        let exact_rank = c.rows.iter().filter(|&&i| is_pivot[i]).count();
        if exact_rank < structural {
            dependent.push(DependentReport {
                place: format!("component {k}"),
                structural_rank: structural * shape.copies,
                exact_rank: exact_rank * shape.copies,
                redundant_rows: capped(
                    c.rows
                        .iter()
                        .filter(|&&i| !is_pivot[i])
                        .map(|&i| shape.labels[i].clone()),
                ),
            });
        }
    }
    // Square blocks: exact rank of each block's own submatrix.
    for (b, block) in dm.blocks.iter().enumerate() {
        let sub = shape.matrix.select(&block.rows, &block.cols);
        let rank = eliminate(&sub, &[], Combinations::Skip).rank;
        if rank < block.rows.len() {
            dependent.push(DependentReport {
                place: format!("block {b}"),
                structural_rank: block.rows.len() * shape.copies,
                exact_rank: rank * shape.copies,
                redundant_rows: capped(block.rows.iter().map(|&i| shape.labels[i].clone())),
            });
        }
    }
    StructureReport {
        columns_are: if shape.copies > 1 || shape.columns.iter().all(|c| !c.ends_with(']')) {
            "parameters".into()
        } else {
            "coordinates".into()
        },
        components: comps.components.len(),
        structural_rank: dm.structural_rank * shape.copies,
        exact_rank: exact.rank * shape.copies,
        numerical_dependency: (dm.structural_rank - exact.rank.min(dm.structural_rank))
            * shape.copies,
        over: part(shape, dm, PartKind::Over),
        well: part(shape, dm, PartKind::Well),
        under: part(shape, dm, PartKind::Under),
        blocks: dm
            .blocks
            .iter()
            .take(BLOCK_LIMIT)
            .enumerate()
            .map(|(index, b)| BlockReport {
                index,
                rows: capped(b.rows.iter().map(|&i| shape.labels[i].clone())),
                columns: capped(b.cols.iter().map(|&j| shape.columns[j].clone())),
                depends_on: b.depends_on.clone(),
            })
            .collect(),
        blocks_total: dm.blocks.len(),
        dependent,
    }
}

/// Lines explaining why the columns named `name` (a parameter, or one coordinate `name[k]`)
/// are fixed, limited or free.
pub fn explain_parameter(system: &SystemGraph, name: &str) -> Option<Vec<String>> {
    let shape = &system.shape;
    let targets: Vec<usize> = shape
        .columns
        .iter()
        .enumerate()
        .filter(|(_, c)| {
            *c == name
                || c.strip_prefix(name)
                    .is_some_and(|rest| rest.starts_with('['))
        })
        .map(|(j, _)| j)
        .collect();
    if targets.is_empty() {
        return None;
    }
    let mut lines = Vec::new();
    for j in targets {
        match explain(&system.dm, &system.graph, j, &shape.labels, &shape.columns) {
            Ok(e) => lines.extend(e.text),
            Err(e) => lines.push(format!("{}: {e}", shape.columns[j])),
        }
    }
    Some(lines)
}

/// The parts of the whole system by parameter and row, for pictures coloured by part.
pub fn parts(system: &api::ConstraintSystem, graph: &SystemGraph) -> api::StructureParts {
    let (shape, dm) = (&graph.shape, &graph.dm);
    // Column → parameter, row → system row.
    let param_of_column: Vec<api::ParamId> = if shape.columns.len() == system.params().len() {
        (0..system.params().len() as u32)
            .map(api::ParamId)
            .collect()
    } else {
        system
            .params()
            .iter()
            .enumerate()
            .flat_map(|(i, p)| std::iter::repeat_n(api::ParamId(i as u32), p.dim))
            .collect()
    };
    let row_of: Vec<api::RowId> = if shape.labels.len() == system.rows().len() {
        (0..system.rows().len() as u32).map(api::RowId).collect()
    } else {
        system
            .rows()
            .iter()
            .enumerate()
            .flat_map(|(i, r)| std::iter::repeat_n(api::RowId(i as u32), r.body.scalar_rows()))
            .collect()
    };
    let collect_params = |cols: &[usize]| -> Vec<api::ParamId> {
        let set: std::collections::BTreeSet<api::ParamId> =
            cols.iter().map(|&j| param_of_column[j]).collect();
        set.into_iter().collect()
    };
    let collect_rows = |rows: &[usize]| -> Vec<api::RowId> {
        let set: std::collections::BTreeSet<api::RowId> = rows.iter().map(|&i| row_of[i]).collect();
        set.into_iter().collect()
    };
    let over = collect_params(&dm.over.cols);
    let well: Vec<api::ParamId> = collect_params(&dm.well.cols)
        .into_iter()
        .filter(|p| over.binary_search(p).is_err())
        .collect();
    api::StructureParts {
        over,
        well,
        over_rows: collect_rows(&dm.over.rows),
        well_rows: collect_rows(&dm.well.rows),
    }
}

/// The structure of an edit's relevant subsystem `R_ED` (rows: relevant constraints split per
/// coordinate; columns: coordinates of the derived parameters).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Default)]
pub struct EditStructure {
    /// Scalar equations.
    pub equations: usize,
    /// Scalar unknowns.
    pub unknowns: usize,
    /// Maximum matching size.
    pub structural_rank: usize,
    /// Labels of the relevant constraints in the over-determined part: more of them than derived
    /// unknowns they involve, so some anchor moves cannot be absorbed whatever the values.
    pub over_determined: Vec<String>,
}

/// Dulmage–Mendelsohn view of the edit's `R_ED` — exactly the matrix ECLES factors
/// ([`ecles::ReducedSystem`]) — counted per coordinate: in the vector layout every row and
/// column stands for one per coordinate, and the decomposition of the copies is the copy of
/// the decomposition.
///
/// `independent_rows` says that the exact factoring found `R_ED`'s rows independent (its rank
/// is its number of rows). Then no matching is needed: the structural rank lies between the
/// rank and the number of rows, so it is the number of rows, a maximum matching leaves no row
/// unmatched, and the over-determined part (the rows reached from unmatched rows) is empty.
/// Most edits are such; their matching and decomposition were a tenth of a 10-point edit.
pub fn edit_structure(
    system: &api::ConstraintSystem,
    reduced: &ecles::ReducedSystem,
    independent_rows: bool,
) -> EditStructure {
    let copies = match reduced.layout() {
        ecles::Layout::Vector { dim } => dim,
        ecles::Layout::Scalar => 1,
    };
    if independent_rows {
        return EditStructure {
            equations: reduced.r_ed().rows() * copies,
            unknowns: reduced.r_ed().cols() * copies,
            structural_rank: reduced.r_ed().rows() * copies,
            over_determined: Vec::new(),
        };
    }
    let graph = Bipartite::from_matrix(reduced.r_ed());
    let dm = decompose(&graph);
    let mut over: Vec<String> = Vec::new();
    for &i in &dm.over.rows {
        let row = reduced.rows()[i];
        if copies > 1 {
            over.extend((0..copies).map(|k| crate::analysis::label(system, row.row, Some(k))));
        } else {
            over.push(crate::analysis::label(system, row.row, row.component));
        }
    }
    over.dedup();
    EditStructure {
        equations: reduced.r_ed().rows() * copies,
        unknowns: reduced.r_ed().cols() * copies,
        structural_rank: dm.structural_rank * copies,
        over_determined: capped(over.into_iter()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{
        ConstraintRow, ConstraintSystem, Coord, Factorization, Integer, LinearBackend, Origin,
        ParamId, RowBody, Values,
    };

    /// A chain of `n` parameters of dimension `dim` (`2 p_i − p_{i−1} − p_{i+1} = 0`, vector rows
    /// when `dim > 1`), with `extra` rows appended, and the edit moving `p_{n/2}`.
    fn chain(
        n: usize,
        dim: usize,
        extra: &[&[(usize, i64)]],
    ) -> (ConstraintSystem, ecles::EditSpec) {
        let mut s = ConstraintSystem::new();
        let p: Vec<ParamId> = (0..n)
            .map(|i| s.add_parameter(format!("p{i}"), dim).expect("fresh"))
            .collect();
        let mut add = |label: String, terms: &[(usize, i64)]| {
            let body = if dim == 1 {
                RowBody::Scalar {
                    terms: terms
                        .iter()
                        .map(|(i, c)| {
                            let coord = Coord {
                                param: p[*i],
                                component: 0,
                            };
                            (coord, Integer::from(*c))
                        })
                        .collect(),
                    rhs: Integer::from(0),
                }
            } else {
                RowBody::Vector {
                    terms: terms
                        .iter()
                        .map(|(i, c)| (p[*i], Integer::from(*c)))
                        .collect(),
                    rhs: vec![Integer::from(0); dim],
                }
            };
            s.add_row(ConstraintRow {
                label,
                origin: Origin::default(),
                body,
            })
            .expect("a valid row");
        };
        for i in 1..n - 1 {
            add(format!("mid{i}"), &[(i - 1, -1), (i, 2), (i + 1, -1)]);
        }
        for (k, terms) in extra.iter().enumerate() {
            add(format!("extra{k}"), terms);
        }
        let anchor = p[n / 2];
        let spec = ecles::EditSpec {
            anchors: vec![anchor],
            derived: p.iter().copied().filter(|q| *q != anchor).collect(),
            weights: None,
            strong: false,
        };
        (s, spec)
    }

    /// Independent rows (the exact rank is the number of rows) give the structure the
    /// matching and the decomposition give: the structural rank is the number of equations
    /// and nothing is over-determined. Dependent rows still go through the decomposition.
    #[test]
    fn independent_rows_need_no_matching() {
        for dim in [1, 2] {
            for (extra, independent) in [
                (&[][..], true),
                (&[&[(0, 1), (3, -1)][..]][..], true),
                // Dependent: the chain's first row again, and a row over p0 and p1 only, which
                // with the first two rows over-determines them.
                (
                    &[&[(0, -1), (1, 2), (2, -1)][..], &[(0, 1), (1, 1)][..]][..],
                    false,
                ),
            ] {
                let (system, spec) = chain(7, dim, extra);
                let values = Values::zeros(&system);
                let (_, reduced) =
                    ecles::reduce_edit::<api::Rational>(&system, &values, &spec).expect("reduced");
                let rank = exact_ldu::ExactLdu::default()
                    .factor(reduced.r_ed())
                    .expect("factored")
                    .rank();
                assert_eq!(rank == reduced.r_ed().rows(), independent, "dim {dim}");
                let decomposed = edit_structure(&system, &reduced, false);
                if independent {
                    assert_eq!(edit_structure(&system, &reduced, true), decomposed);
                    assert_eq!(decomposed.structural_rank, decomposed.equations);
                    assert!(decomposed.over_determined.is_empty());
                } else {
                    assert!(!decomposed.over_determined.is_empty(), "dim {dim}");
                }
            }
        }
    }
}
