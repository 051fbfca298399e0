//! Introspection (Brenner 3.2): why an unknown cannot move, traced back through the collapsed
//! block graph `H`, and where a set of conflicting rows sits in the decomposition.

use crate::bipartite::Bipartite;
use crate::dm::{DmDecomposition, PartKind};
use crate::error::StructureError;
use crate::matching::maximum_matching;
use serde::Serialize;
use std::collections::VecDeque;

/// Names listed in one line of text before the rest is summarised as "… and N more"; the
/// structured fields always list everything.
const TEXT_LIST_LIMIT: usize = 20;

/// One step of an explanation: a group of rows that fixes (or, for the under-determined part,
/// fails to fix) a group of unknowns once its inputs are known.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ChainStep {
    /// Where the step lies: a well block, a connected piece of the over-determined part, or a
    /// connected piece of the under-determined part.
    pub part: PartKind,
    /// The block index (into [`DmDecomposition::blocks`]) for a well step.
    pub block: Option<usize>,
    /// The step's rows, increasing.
    pub rows: Vec<usize>,
    /// The unknowns the step's rows fix (for the under part: the unknowns of the piece),
    /// increasing.
    pub cols: Vec<usize>,
    /// Unknowns outside the step that its rows also involve (fixed by earlier steps),
    /// increasing.
    pub inputs: Vec<usize>,
    /// Labels of `rows`.
    pub row_labels: Vec<String>,
    /// Names of `cols`.
    pub col_names: Vec<String>,
    /// Names of `inputs`.
    pub input_names: Vec<String>,
}

/// Why an unknown can or cannot move, as structure sees it.
///
/// For a determined unknown, `chain` lists the steps that fix it in solve order (its own step
/// last); `text` reads the chain backwards from the unknown, as Brenner's introspection does.
/// Structure speaks for generic coefficients: the exact rank may still reveal a dependency
/// inside a block.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Explanation {
    /// The unknown explained.
    pub column: usize,
    /// Its name.
    pub name: String,
    /// The part it lies in.
    pub part: PartKind,
    /// Its block, when it lies in the well part.
    pub block: Option<usize>,
    /// The steps that determine it, in solve order (for a free unknown: the under-determined
    /// piece it lies in).
    pub chain: Vec<ChainStep>,
    /// Lines a user can follow.
    pub text: Vec<String>,
}

/// Rows or columns of a row set that share a part (and block).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Group {
    /// The part.
    pub part: PartKind,
    /// The block, for well rows or columns.
    pub block: Option<usize>,
    /// Row or column indices, increasing.
    pub members: Vec<usize>,
    /// Their labels or names.
    pub names: Vec<String>,
}

/// Where a set of rows (for instance the certificate of a contradiction found by the exact
/// backend) sits in the decomposition, and whether structure alone explains their dependency.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RowsExplanation {
    /// The rows, increasing and without repeats.
    pub rows: Vec<usize>,
    /// Their labels.
    pub row_labels: Vec<String>,
    /// The unknowns they involve, increasing.
    pub cols: Vec<usize>,
    /// Names of `cols`.
    pub col_names: Vec<String>,
    /// Structural rank of these rows alone (maximum matching of their subgraph).
    pub structural_rank: usize,
    /// Whether the rows are dependent for every choice of coefficients
    /// (`structural_rank < rows.len()`); otherwise a dependency among them comes from the
    /// coefficient values.
    pub structurally_dependent: bool,
    /// The rows grouped by part and block (over, then blocks in solve order, then under).
    pub row_groups: Vec<Group>,
    /// The unknowns grouped the same way.
    pub col_groups: Vec<Group>,
    /// Lines a user can follow.
    pub text: Vec<String>,
}

fn label(labels: &[String], i: usize, fallback: &str) -> String {
    labels
        .get(i)
        .cloned()
        .unwrap_or_else(|| format!("{fallback} {i}"))
}

fn row_names(labels: &[String], rows: &[usize]) -> Vec<String> {
    rows.iter().map(|&i| label(labels, i, "row")).collect()
}

fn col_names_of(names: &[String], cols: &[usize]) -> Vec<String> {
    cols.iter().map(|&j| label(names, j, "column")).collect()
}

/// "a, b, c" (at most [`TEXT_LIST_LIMIT`] names, then "… and N more").
fn comma_list(names: &[String]) -> String {
    if names.len() > TEXT_LIST_LIMIT {
        format!(
            "{} … and {} more",
            names[..TEXT_LIST_LIMIT].join(", "),
            names.len() - TEXT_LIST_LIMIT
        )
    } else {
        names.join(", ")
    }
}

/// "a", "a and b", "a, b and c" (long lists as in [`comma_list`]).
fn and_list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        _ if names.len() > TEXT_LIST_LIMIT => comma_list(names),
        [init @ .., last] => format!("{} and {}", init.join(", "), last),
    }
}

fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("{n} {one}")
    } else {
        format!("{n} {many}")
    }
}

/// Columns of `rows` outside `cols` (both sorted), sorted.
fn inputs_of(graph: &Bipartite, rows: &[usize], cols: &[usize]) -> Vec<usize> {
    let mut inputs: Vec<usize> = rows
        .iter()
        .flat_map(|&r| graph.row(r).iter().copied())
        .filter(|c| cols.binary_search(c).is_err())
        .collect();
    inputs.sort_unstable();
    inputs.dedup();
    inputs
}

/// The connected piece of part `kind` (rows and columns of that part only) holding column
/// `start`: breadth-first, no recursion. `seen` marks columns already taken by other pieces.
fn piece(
    dm: &DmDecomposition,
    graph: &Bipartite,
    kind: PartKind,
    start: usize,
    seen_cols: &mut [bool],
    seen_rows: &mut [bool],
) -> (Vec<usize>, Vec<usize>) {
    let mut rows = Vec::new();
    let mut cols = vec![start];
    seen_cols[start] = true;
    let mut queue = VecDeque::from([start]);
    while let Some(j) = queue.pop_front() {
        for &i in graph.col(j) {
            if seen_rows[i] || dm.part_of_row(i) != Some(kind) {
                continue;
            }
            seen_rows[i] = true;
            rows.push(i);
            for &k in graph.row(i) {
                if !seen_cols[k] && dm.part_of_col(k) == Some(kind) {
                    seen_cols[k] = true;
                    cols.push(k);
                    queue.push_back(k);
                }
            }
        }
    }
    rows.sort_unstable();
    cols.sort_unstable();
    (rows, cols)
}

fn step(
    graph: &Bipartite,
    part: PartKind,
    block: Option<usize>,
    rows: Vec<usize>,
    cols: Vec<usize>,
    row_labels: &[String],
    col_names: &[String],
) -> ChainStep {
    let inputs = inputs_of(graph, &rows, &cols);
    ChainStep {
        part,
        block,
        row_labels: row_names(row_labels, &rows),
        col_names: col_names_of(col_names, &cols),
        input_names: col_names_of(col_names, &inputs),
        rows,
        cols,
        inputs,
    }
}

/// "x1 and x2 are fixed by f1, f2[ together with x0]" for a step.
fn fixed_line(step: &ChainStep) -> String {
    let verb = if step.cols.len() == 1 { "is" } else { "are" };
    let mut line = format!(
        "{} {verb} fixed by {}",
        and_list(&step.col_names),
        comma_list(&step.row_labels)
    );
    if !step.inputs.is_empty() {
        line.push_str(&format!(" together with {}", comma_list(&step.input_names)));
    }
    line
}

fn over_line(step: &ChainStep) -> String {
    format!(
        "over-constrained: more constraints than unknowns here: {} ({} on {})",
        comma_list(&step.row_labels),
        plural(step.rows.len(), "constraint", "constraints"),
        plural(step.cols.len(), "unknown", "unknowns"),
    )
}

fn check_dm(dm: &DmDecomposition, graph: &Bipartite) -> Result<(), StructureError> {
    if dm.rows() != graph.rows() || dm.cols() != graph.cols() {
        return Err(StructureError::MatchingSize {
            rows: graph.rows(),
            cols: graph.cols(),
            matching_rows: dm.rows(),
            matching_cols: dm.cols(),
        });
    }
    Ok(())
}

/// Why unknown `column` can or cannot move (Brenner 3.2).
///
/// * well part: the chain of blocks that fix it, traced back through
///   [`crate::Block::depends_on`] from its block ("x3 is fixed by f3, f4 together with x1, x2;
///   x1 and x2 are fixed by f1, f2"), including the pieces of the over part whose unknowns
///   those blocks use;
/// * over part: the connected piece of the over part that fixes it, and that this piece has
///   more constraints than unknowns;
/// * under part: that it is free, with the size of the connected piece of the under part it
///   lies in.
///
/// `row_labels` and `col_names` name rows and columns in the text; missing entries are shown
/// as "row i" / "column j".
///
/// # Errors
/// [`StructureError::NoSuchColumn`] for a column outside the graph;
/// [`StructureError::MatchingSize`] if `dm` was computed for a graph of another size.
pub fn explain(
    dm: &DmDecomposition,
    graph: &Bipartite,
    column: usize,
    row_labels: &[String],
    col_names: &[String],
) -> Result<Explanation, StructureError> {
    check_dm(dm, graph)?;
    graph.check_col(column)?;
    let name = label(col_names, column, "column");
    let part = dm.part_of_col(column).unwrap_or(PartKind::Under);
    let block = dm.block_of_col(column);
    let mut seen_cols = vec![false; graph.cols()];
    let mut seen_rows = vec![false; graph.rows()];
    let mut chain = Vec::new();
    let mut text = Vec::new();

    match (part, block) {
        (PartKind::Well, Some(target)) => {
            // Blocks the target depends on, transitively: a search over `depends_on`.
            let mut needed = vec![false; dm.blocks.len()];
            needed[target] = true;
            let mut stack = vec![target];
            while let Some(b) = stack.pop() {
                for &d in &dm.blocks[b].depends_on {
                    if !needed[d] {
                        needed[d] = true;
                        stack.push(d);
                    }
                }
            }
            // Pieces of the over part whose columns these blocks use come first.
            let mut over_cols: Vec<usize> = (0..dm.blocks.len())
                .filter(|&b| needed[b])
                .flat_map(|b| dm.blocks[b].over_inputs.iter().copied())
                .collect();
            over_cols.sort_unstable();
            over_cols.dedup();
            let mut over_steps = Vec::new();
            for c in over_cols {
                if !seen_cols[c] {
                    let (rows, cols) =
                        piece(dm, graph, PartKind::Over, c, &mut seen_cols, &mut seen_rows);
                    over_steps.push(step(
                        graph,
                        PartKind::Over,
                        None,
                        rows,
                        cols,
                        row_labels,
                        col_names,
                    ));
                }
            }
            over_steps.sort_by_key(|s| (s.rows.first().copied(), s.cols.first().copied()));
            chain.extend(over_steps);
            for (b, blk) in dm.blocks.iter().enumerate() {
                if needed[b] {
                    chain.push(step(
                        graph,
                        PartKind::Well,
                        Some(b),
                        blk.rows.clone(),
                        blk.cols.clone(),
                        row_labels,
                        col_names,
                    ));
                }
            }
            // Read back from the target (the last step).
            for (k, s) in chain.iter().enumerate().rev() {
                if k + 1 == chain.len() {
                    let mut line = format!("{name} is fixed by {}", comma_list(&s.row_labels));
                    if !s.inputs.is_empty() {
                        line.push_str(&format!(" together with {}", comma_list(&s.input_names)));
                    }
                    if s.cols.len() > 1 {
                        line.push_str(&format!(
                            " ({} fix {} jointly)",
                            comma_list(&s.row_labels),
                            and_list(&s.col_names)
                        ));
                    }
                    text.push(line);
                } else {
                    text.push(fixed_line(s));
                }
                if s.part == PartKind::Over {
                    text.push(over_line(s));
                }
            }
        }
        (PartKind::Over, _) => {
            let (rows, cols) = piece(
                dm,
                graph,
                PartKind::Over,
                column,
                &mut seen_cols,
                &mut seen_rows,
            );
            let s = step(
                graph,
                PartKind::Over,
                None,
                rows,
                cols,
                row_labels,
                col_names,
            );
            let mut line = format!("{name} is fixed by {}", comma_list(&s.row_labels));
            if s.cols.len() > 1 {
                line.push_str(&format!(
                    " ({} fix {} jointly)",
                    comma_list(&s.row_labels),
                    and_list(&s.col_names)
                ));
            }
            text.push(line);
            text.push(over_line(&s));
            chain.push(s);
        }
        _ => {
            let (rows, cols) = piece(
                dm,
                graph,
                PartKind::Under,
                column,
                &mut seen_cols,
                &mut seen_rows,
            );
            let s = step(
                graph,
                PartKind::Under,
                None,
                rows,
                cols,
                row_labels,
                col_names,
            );
            if graph.col(column).is_empty() {
                text.push(format!("{name} is free: no constraint involves it"));
            } else {
                text.push(format!(
                    "{name} is free: not determined by the constraints alone (it lies in the under-determined part with {} and {})",
                    plural(s.cols.len(), "unknown", "unknowns"),
                    plural(s.rows.len(), "constraint", "constraints"),
                ));
                text.push(format!(
                    "constraints there: {}; unknowns there: {}",
                    comma_list(&s.row_labels),
                    comma_list(&s.col_names)
                ));
            }
            chain.push(s);
        }
    }
    if chain.len() > 1 {
        let order: Vec<String> = chain
            .iter()
            .map(|s| {
                format!(
                    "[{} → {}]",
                    comma_list(&s.row_labels),
                    comma_list(&s.col_names)
                )
            })
            .collect();
        text.push(format!("solve order: {}", order.join(" then ")));
    }
    Ok(Explanation {
        column,
        name,
        part,
        block,
        chain,
        text,
    })
}

/// Where a set of rows sits: the unknowns they involve, the parts and blocks of both, and
/// whether structure alone makes them dependent.
///
/// Meant for the rows of a minimal contradiction or redundancy found by the exact backend: if
/// they are structurally dependent (fewer unknowns can be matched than there are rows), the
/// graph explains the conflict; if not, the dependency comes from the coefficient values.
/// Repeated rows count once.
///
/// # Errors
/// [`StructureError::NoSuchRow`] for a row outside the graph;
/// [`StructureError::MatchingSize`] if `dm` was computed for a graph of another size.
pub fn explain_rows(
    dm: &DmDecomposition,
    graph: &Bipartite,
    rows: &[usize],
    row_labels: &[String],
    col_names: &[String],
) -> Result<RowsExplanation, StructureError> {
    check_dm(dm, graph)?;
    for &r in rows {
        graph.check_row(r)?;
    }
    let mut rows = rows.to_vec();
    rows.sort_unstable();
    rows.dedup();
    let cols = inputs_of(graph, &rows, &[]);

    // Structural rank of the rows alone.
    let pattern: Vec<Vec<usize>> = rows.iter().map(|&r| graph.row(r).to_vec()).collect();
    let sub = Bipartite::from_pattern(graph.cols(), &pattern)?;
    let structural_rank = maximum_matching(&sub).size;
    let structurally_dependent = structural_rank < rows.len();

    let group = |members: &[usize],
                 part_of: &dyn Fn(usize) -> (PartKind, Option<usize>),
                 names: &dyn Fn(&[usize]) -> Vec<String>|
     -> Vec<Group> {
        let mut keyed: Vec<((PartKind, Option<usize>), usize)> =
            members.iter().map(|&x| (part_of(x), x)).collect();
        keyed.sort_unstable();
        let mut out: Vec<Group> = Vec::new();
        for ((part, block), x) in keyed {
            match out.last_mut() {
                Some(g) if g.part == part && g.block == block => g.members.push(x),
                _ => out.push(Group {
                    part,
                    block,
                    members: vec![x],
                    names: Vec::new(),
                }),
            }
        }
        for g in &mut out {
            g.names = names(&g.members);
        }
        out
    };
    let row_groups = group(
        &rows,
        &|r| {
            (
                dm.part_of_row(r).unwrap_or(PartKind::Under),
                dm.block_of_row(r),
            )
        },
        &|m| row_names(row_labels, m),
    );
    let col_groups = group(
        &cols,
        &|c| {
            (
                dm.part_of_col(c).unwrap_or(PartKind::Under),
                dm.block_of_col(c),
            )
        },
        &|m| col_names_of(col_names, m),
    );
    let labels = row_names(row_labels, &rows);
    let names = col_names_of(col_names, &cols);

    let mut text = Vec::new();
    text.push(format!(
        "{} {} {}: {}",
        comma_list(&labels),
        if rows.len() == 1 {
            "involves"
        } else {
            "involve"
        },
        plural(cols.len(), "unknown", "unknowns"),
        comma_list(&names)
    ));
    if structurally_dependent {
        text.push(format!(
            "structurally dependent: these {} can be matched with only {} distinct {}, so they are dependent whatever the coefficients",
            plural(rows.len(), "constraint", "constraints"),
            structural_rank,
            if structural_rank == 1 { "unknown" } else { "unknowns" },
        ));
    } else if !rows.is_empty() {
        text.push(
            "structurally independent: each constraint can be paired with an unknown of its own, so any dependency among them comes from the values of the coefficients"
                .to_string(),
        );
    }
    let describe = |g: &Group| -> String {
        let verb = if g.members.len() == 1 { "lies" } else { "lie" };
        match (g.part, g.block) {
            (PartKind::Well, Some(b)) => {
                let blk = &dm.blocks[b];
                format!(
                    "{} {verb} in block {b} of the solve order ({} fix {})",
                    comma_list(&g.names),
                    comma_list(&row_names(row_labels, &blk.rows)),
                    and_list(&col_names_of(col_names, &blk.cols)),
                )
            }
            (PartKind::Over, _) => format!(
                "{} {verb} in the over-determined part ({} on {} in all)",
                comma_list(&g.names),
                plural(dm.over.rows.len(), "constraint", "constraints"),
                plural(dm.over.cols.len(), "unknown", "unknowns"),
            ),
            _ => format!(
                "{} {verb} in the under-determined part ({} and {} in all)",
                comma_list(&g.names),
                plural(dm.under.cols.len(), "unknown", "unknowns"),
                plural(dm.under.rows.len(), "constraint", "constraints"),
            ),
        }
    };
    for g in &row_groups {
        text.push(describe(g));
    }
    for g in &col_groups {
        text.push(describe(g));
    }
    Ok(RowsExplanation {
        rows,
        row_labels: labels,
        cols,
        col_names: names,
        structural_rank,
        structurally_dependent,
        row_groups,
        col_groups,
        text,
    })
}
