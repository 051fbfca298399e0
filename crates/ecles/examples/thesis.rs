//! Runs the worked examples of the ECLES thesis with the exact backend and prints the results:
//! the factoring of matrix (4.3), the solve (8.17), the least squares (9.9), the pump edit (2.2),
//! the parallelogram edit (figure 2.1) and a rejected, conflicting anchor move.
//!
//! `cargo run --release -p ecles --example thesis`

use api::{
    format_rational, ConstraintRow, ConstraintSystem, Factorization, LinearBackend, Origin,
    ParamId, Rational, RowBody, Values,
};
use backend_contract::thesis;
use ecles::{Edit, EditSpec};
use exact_ldu::{ExactFactorization, ExactLdu, Simplification};
use num_bigint::BigInt;
use std::process::ExitCode;

fn q(n: i64) -> Rational {
    Rational::from_integer(n.into())
}

fn show(values: &[Rational]) -> String {
    let parts: Vec<String> = values.iter().map(format_rational).collect();
    format!("({})", parts.join(", "))
}

fn show_matrix(name: &str, rows: &[Vec<BigInt>]) {
    println!("  {name} =");
    for row in rows {
        let cells: Vec<String> = row.iter().map(|v| format!("{v:>6}")).collect();
        println!("    [{} ]", cells.join(""));
    }
}

fn row(label: &str, terms: &[(ParamId, i64)], rhs: &[i64]) -> ConstraintRow {
    ConstraintRow {
        label: label.into(),
        origin: Origin {
            source: "thesis".into(),
            item: label.into(),
        },
        body: RowBody::Vector {
            terms: terms.iter().map(|(p, c)| (*p, (*c).into())).collect(),
            rhs: rhs.iter().map(|&v| v.into()).collect(),
        },
    }
}

fn factoring_examples() -> Result<(), String> {
    let a = thesis::matrix_4_3();
    let f = ExactLdu::new(Simplification::Turner)
        .factor(&a)
        .map_err(|e| e.to_string())?;
    let ldu = f.ldu().expect("factored fraction-free");
    println!("Matrix (4.3), Turner simplification: rank {}", ldu.rank());
    println!(
        "  row order Π_R = {:?}, column order Π_C = {:?}",
        ldu.row_perm(),
        ldu.col_perm()
    );
    let (l, d, u) = ldu.dense_factors();
    show_matrix("L", &l);
    println!("  D = diag{d:?}");
    show_matrix("U", &u);

    let b = thesis::rhs_8_17();
    let p = f.solve(&b).map_err(|e| e.to_string())?;
    let x: Vec<Rational> = ldu.col_perm().iter().map(|&c| p[c].clone()).collect();
    println!("Solve (8.17): X = Π_C P = {}, P = {}", show(&x), show(&p));

    let p = f
        .least_squares(&b, &thesis::hints_9_11(), &thesis::weights_9_11())
        .map_err(|e| e.to_string())?;
    println!(
        "Least squares (9.9), hints (1, 1, 1, 1): P'' = {}",
        show(&p)
    );
    Ok(())
}

fn pump_example() -> Result<(), String> {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (1..=4)
        .map(|i| s.add_parameter(format!("p{i}"), 1))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    s.add_row(row(
        "p1 + p2 - p3 = 0",
        &[(p[0], 1), (p[1], 1), (p[2], -1)],
        &[0],
    ))
    .map_err(|e| e.to_string())?;
    s.add_row(row("p4 - p3 = 5", &[(p[2], -1), (p[3], 1)], &[5]))
        .map_err(|e| e.to_string())?;
    let mut values = Values::from_vecs(&s, vec![vec![q(1)], vec![q(2)], vec![q(3)], vec![q(8)]])
        .map_err(|e| e.to_string())?;
    let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]);
    let edit: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), &s, &values, &spec).map_err(|e| e.to_string())?;
    let hints: Vec<Vec<Rational>> = p[1..].iter().map(|id| values.get(*id).to_vec()).collect();
    edit.apply(&s, &mut values, &[vec![q(4)]], &hints)
        .map_err(|e| e.to_string())?;
    let all: Vec<Rational> = p.iter().map(|id| values.get(*id)[0].clone()).collect();
    println!(
        "Pumps (2.2): p1 := 4, p2..p4 derived from hints (2, 3, 8): p = {}",
        show(&all)
    );

    // p1 and p3 anchored: p3 = p1 + p2 with p2 derived, p4 fixed: moving p3 alone breaks p4 - p3 = 5.
    let spec = EditSpec::new(vec![p[0], p[2]], vec![p[1]]);
    let edit: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), &s, &values, &spec).map_err(|e| e.to_string())?;
    let before = values.clone();
    match edit.apply(&s, &mut values, &[vec![q(4)], vec![q(10)]], &[vec![q(0)]]) {
        Ok(_) => return Err("a conflicting move was accepted".into()),
        Err(e) => println!("Pumps, p3 := 10 with p4 fixed: rejected: {e}"),
    }
    if values != before {
        return Err("a failed edit changed the values".into());
    }
    Ok(())
}

fn parallelogram_example() -> Result<(), String> {
    let mut s = ConstraintSystem::new();
    let p: Vec<ParamId> = (0..5)
        .map(|i| s.add_parameter(format!("p{i}"), 2))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    s.add_row(row(
        "parallelogram p0 p1 p2 p3",
        &[(p[0], 1), (p[1], -1), (p[2], 1), (p[3], -1)],
        &[0, 0],
    ))
    .map_err(|e| e.to_string())?;
    let pts = [(0, 0), (4, 0), (5, 3), (1, 3), (9, 9)];
    let mut values = Values::from_vecs(&s, pts.iter().map(|&(x, y)| vec![q(x), q(y)]).collect())
        .map_err(|e| e.to_string())?;
    let spec = EditSpec::new(vec![p[0]], vec![p[1], p[2], p[3]]).strong();
    let edit: Edit<ExactFactorization> =
        Edit::initialize(&ExactLdu::default(), &s, &values, &spec).map_err(|e| e.to_string())?;
    let hints: Vec<Vec<Rational>> = p[1..4].iter().map(|id| values.get(*id).to_vec()).collect();
    edit.apply(&s, &mut values, &[vec![q(3), q(-6)]], &hints)
        .map_err(|e| e.to_string())?;
    println!("Parallelogram (figure 2.1): p0 moved to (3, -6):");
    for (i, id) in p.iter().enumerate() {
        println!("  p{i} = {}", show(values.get(*id)));
    }
    Ok(())
}

fn main() -> ExitCode {
    for run in [factoring_examples, pump_example, parallelogram_example] {
        if let Err(e) = run() {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
