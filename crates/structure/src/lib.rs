//! Structural analysis of a constraint system: the bipartite graph of constraint rows and
//! unknowns, what is under-, well- or over-constrained, in which order blocks can be solved,
//! and why an unknown cannot move — the structural companion of the exact rank computed by
//! `exact-ldu` (Brenner, *Constraints for modelling complex objects*, 2.1 and 3.2).
//!
//! * [`Bipartite`]: the constraint graph of an [`api::IntMatrix`] (an edge per nonzero);
//! * [`components`]: connected components (parts that cannot influence each other);
//! * [`maximum_matching`]: Hopcroft–Karp, iterative; its size is the structural rank;
//! * [`dulmage_mendelsohn`] / [`decompose`]: over-, well- and under-determined parts and the
//!   irreducible blocks of the well part in solve order, with the collapsed graph `H`;
//! * [`explain`], [`explain_rows`]: introspection in text and structured form.
//!
//! Everything is linear or near-linear in the number of nonzeros and free of recursion, so a
//! C1 spline system with 10^5 unknowns is analysed in milliseconds.
//!
//! ```
//! use api::IntMatrix;
//! use structure::{decompose, explain, Bipartite};
//!
//! // f1(x1, x2), f2(x1, x2), f3(x2, x3): x3 is fixed by f3 once f1, f2 fix x1 and x2.
//! let m = IntMatrix::from_dense(3, &[vec![1, 1, 0], vec![1, -1, 0], vec![0, 2, 3]]).unwrap();
//! let g = Bipartite::from_matrix(&m);
//! let dm = decompose(&g);
//! assert!(dm.is_well_constrained());
//! assert_eq!(dm.blocks.len(), 2);
//! let rows: Vec<String> = ["f1", "f2", "f3"].map(String::from).to_vec();
//! let cols: Vec<String> = ["x1", "x2", "x3"].map(String::from).to_vec();
//! let e = explain(&dm, &g, 2, &rows, &cols).unwrap();
//! assert_eq!(e.text[0], "x3 is fixed by f3 together with x2");
//! assert_eq!(e.text[1], "x1 and x2 are fixed by f1, f2");
//! ```

mod bipartite;
mod components;
mod dm;
mod error;
mod explain;
mod matching;

pub use bipartite::{Bipartite, Node};
pub use components::{components, Component, Components};
pub use dm::{decompose, dulmage_mendelsohn, Block, DmDecomposition, Part, PartKind};
pub use error::StructureError;
pub use explain::{explain, explain_rows, ChainStep, Explanation, Group, RowsExplanation};
pub use matching::{maximum_matching, Matching};
