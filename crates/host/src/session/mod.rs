//! A run: sources built into one system, every edit and output checked before the first edit
//! runs, edits executed with the exact backend and checked against the float backend, outputs
//! rendered.

use crate::analysis;
use crate::error::RunError;
use crate::registry::{self, LoadedFrom};
use crate::report::{Report, SourceReport, Summary};
use crate::runfile::{self, located_source_error, RunFile, Simplify};
use api::config::TextPosition;
use api::{
    BuildRequest, ConstraintSource, ConstraintSystem, Highlight, ParamId, SourceInfo, Values,
};
use exact_ldu::{ExactLdu, Simplification};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

mod check;
mod configure;
mod edit;
mod float_twin;
mod model_swap;
mod propagation;
mod record;
mod render;
mod target_image;
mod value_text;

pub use check::OutputsPlan;
pub use configure::Configured;
pub use edit::{equation_counts, ActiveEdit, PlannedEdit, Planning};
pub use propagation::{EditPropagation, PropagationJson};
pub use target_image::CheckedImage;

/// The label of row `index` (0-based) of source `source` in the system and in reports:
/// `"{source} row {index + 1}: {text}"`, the source's own label as `text` (without the source's name
/// when the source already put it in front). Two rows never share a label, even identical
/// equations from different sources or from one source.
pub fn unique_label(source: &str, index: usize, label: &str) -> String {
    let text = label
        .strip_prefix(source)
        .and_then(|rest| rest.strip_prefix(": "))
        .unwrap_or(label);
    format!("{source} row {}: {text}", index + 1)
}

/// The report of an analysis without edits.
fn whole_system_report(
    run_path: &Path,
    a: analysis::Analysis,
    sources: Vec<SourceReport>,
) -> Report {
    Report {
        run: run_path.display().to_string(),
        parameters: a.parameters,
        constraints: a.constraints,
        rank: a.rank,
        dof: a.parameters - a.rank,
        consistent: a.consistent,
        satisfied: a.violated.is_empty(),
        redundant: a.redundant,
        conflict: a.conflict,
        violated: a.violated,
        sources,
        cross_check: a.cross_check,
        structure: a.structure,
        edits: Vec::new(),
        outputs: Vec::new(),
        output_notes: Vec::new(),
        summary: Summary::default(),
    }
}

/// A built source.
struct Loaded {
    name: String,
    kind: String,
    /// The configuration it was built with (RON text): the run file's, or a later
    /// [`Session::configure`]'s.
    config: String,
    source: Box<dyn ConstraintSource>,
    report: SourceReport,
}

/// Where a configuration given to [`Session::build_source`] is written, for its errors.
enum ConfigPlace {
    /// The source's entry in the run file.
    RunFile,
    /// A `Configure(...)` entry of a file (the run file, or a session being resumed).
    At(String, runfile::Fragment),
    /// Nowhere: made by the editor.
    Unplaced,
}

/// What building the sources makes: replaced as a whole by [`Session::configure`], and kept on
/// the undo stack to be put back.
struct Built {
    sources: Vec<Loaded>,
    system: ConstraintSystem,
    initial: Values,
    graph: std::cell::OnceCell<crate::structural::SystemGraph>,
}

/// A committed edit on the undo or redo stack: the state on the other side of it, and the edit
/// as a run-file entry.
struct Step {
    values: Values,
    highlight: BTreeMap<String, Highlight>,
    /// `Ecles(...)`, `Source(...)` or `Configure(...)`, RON text that repeats the edit in a run
    /// file.
    entry: String,
    /// For a `Configure(...)`: the sources and system on the other side of it.
    build: Option<Built>,
}

/// The state of a run.
pub struct Session {
    /// Run file path as given.
    pub run_path: PathBuf,
    base_dir: PathBuf,
    run: RunFile,
    sources: Vec<Loaded>,
    system: ConstraintSystem,
    initial: Values,
    values: Values,
    exact: ExactLdu,
    tolerance: Option<f64>,
    input_limit: u64,
    /// Every file the run reads: the run file, source inputs, plugin libraries.
    inputs: Vec<PathBuf>,
    /// The whole system's graph and Dulmage–Mendelsohn decomposition, computed once per
    /// system (only a `Configure(...)` changes the system, and it replaces this too).
    graph: std::cell::OnceCell<crate::structural::SystemGraph>,
    /// Each committed edit, with the values and highlights before it, for undo.
    history: Vec<Step>,
    /// Edits undone since the last commit, with the values and highlights they gave, for redo
    /// (a commit clears it).
    undone: Vec<Step>,
    /// Counts commits and undos: an edit initialised at another generation is stale.
    generation: u64,
    /// See [`Session::build_generation`].
    builds: u64,
    last_highlight: BTreeMap<String, Highlight>,
}
impl Session {
    /// Reads the run file (at most `input_limit` bytes, the limit every source's inputs get
    /// too) and builds every source, in order.
    pub fn build(run_path: &Path, input_limit: u64) -> Result<Session, RunError> {
        let run =
            runfile::read(run_path, input_limit).map_err(|e| RunError::input(e.to_string()))?;
        Session::of_run(run_path, run, input_limit)
    }

    /// [`Session::build`] from run-file text rather than a file: `name` stands for the file in
    /// messages and reports, relative paths in it are read from `base_dir` (what a library
    /// caller without a file gives, such as the Python package).
    pub fn build_text(
        text: &str,
        name: &str,
        base_dir: &Path,
        input_limit: u64,
    ) -> Result<Session, RunError> {
        if text.len() as u64 > input_limit {
            return Err(RunError::input(format!(
                "{name}: {} bytes of run text, more than the input limit of {input_limit}",
                text.len()
            )));
        }
        let run = runfile::parse(text, name).map_err(|e| RunError::input(e.to_string()))?;
        Session::of_run(&base_dir.join(name), run, input_limit)
    }

    /// The session of `run`, read from `run_path`, with every source built in order.
    fn of_run(run_path: &Path, run: RunFile, input_limit: u64) -> Result<Session, RunError> {
        let mut session = Session::empty(run_path, run, input_limit);
        let entries = session.run.sources.clone();
        for entry in &entries {
            session.build_source(entry, entry.config.text(), &ConfigPlace::RunFile)?;
        }
        session.initial = session.values.clone();
        Ok(session)
    }

    /// A session of `run` with no source built yet.
    fn empty(run_path: &Path, run: RunFile, input_limit: u64) -> Session {
        let base_dir = run_path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        let method = match run.backend.simplify {
            Simplify::Gcd => Simplification::Gcd,
            Simplify::Turner => Simplification::Turner,
            Simplify::None => Simplification::None,
        };
        Session {
            run_path: run_path.to_path_buf(),
            base_dir,
            tolerance: run.cross_check.map(|c| c.tolerance),
            run,
            sources: Vec::new(),
            system: ConstraintSystem::new(),
            initial: Values::default(),
            values: Values::default(),
            exact: ExactLdu::new(method),
            input_limit,
            inputs: vec![run_path.to_path_buf()],
            graph: std::cell::OnceCell::new(),
            history: Vec::new(),
            undone: Vec::new(),
            generation: 0,
            builds: 0,
            last_highlight: BTreeMap::new(),
        }
    }

    /// Counts the times the sources and system were replaced ([`Session::configure`], its
    /// undo and redo): what was made from them (an editor's views) is stale once it changes.
    pub fn build_generation(&self) -> u64 {
        self.builds
    }

    /// Exchanges the built sources and system with `built`.
    fn swap_build(&mut self, built: &mut Built) {
        self.builds += 1;
        std::mem::swap(&mut self.sources, &mut built.sources);
        std::mem::swap(&mut self.system, &mut built.system);
        std::mem::swap(&mut self.initial, &mut built.initial);
        std::mem::swap(&mut self.graph, &mut built.graph);
    }

    /// The graph of the whole system, built on first use.
    fn graph(&self) -> &crate::structural::SystemGraph {
        self.graph
            .get_or_init(|| crate::structural::SystemGraph::new(&self.system))
    }

    /// The run file's name in messages.
    fn run_name(&self) -> String {
        self.run_path.display().to_string()
    }

    /// A source's refusal of `fragment`, at its run-file position (see
    /// [`located_source_error`]).
    fn source_error(
        &self,
        fragment: &runfile::Fragment,
        context: &str,
        error: &api::SourceError,
    ) -> RunError {
        RunError::input(located_source_error(
            &self.run_name(),
            fragment,
            context,
            error,
        ))
    }

    /// `run.ron:LINE:COL: message`.
    fn at(&self, at: TextPosition, message: impl std::fmt::Display) -> RunError {
        RunError::input(format!("{}:{at}: {message}", self.run_name()))
    }

    /// Builds source `entry` with configuration `config` (RON text: the entry's own, or a
    /// replacement) on the system built so far; `place` says where errors in it are.
    fn build_source(
        &mut self,
        entry: &runfile::SourceEntry,
        config: &str,
        place: &ConfigPlace,
    ) -> Result<(), RunError> {
        let (mut source, origin) = registry::instantiate(&entry.plugin, &self.base_dir)
            .map_err(|e| self.at(entry.at, format!("source {:?}: {e}", entry.name)))?;
        let request = BuildRequest {
            schema: api::SCHEMA_VERSION,
            name: entry.name.clone(),
            config: config.to_string(),
            base_dir: self.base_dir.clone(),
            system: self.system.clone(),
            values: self.values.clone(),
            sources: self
                .sources
                .iter()
                .map(|s| SourceInfo {
                    name: s.name.clone(),
                    kind: s.kind.clone(),
                    config: s.config.clone(),
                })
                .collect(),
            input_limit: self.input_limit,
        };
        let context = format!("source {:?} (plugin {})", entry.name, entry.plugin);
        let mut contribution = source.build(&request).map_err(|e| match place {
            ConfigPlace::RunFile => self.source_error(&entry.config, &context, &e),
            ConfigPlace::At(file, fragment) => {
                RunError::input(located_source_error(file, fragment, &context, &e))
            }
            ConfigPlace::Unplaced => RunError::input(format!("{context}: {}", e.message)),
        })?;
        for (index, row) in contribution.rows.iter_mut().enumerate() {
            row.label = unique_label(&entry.name, index, &row.label);
        }
        let (parameters, rows) = (contribution.parameters.len(), contribution.rows.len());
        let counts = contribution
            .summary
            .iter()
            .map(|s| (s.key.clone(), s.value))
            .collect();
        let warnings = std::mem::take(&mut contribution.warnings);
        self.inputs.extend(contribution.inputs.iter().cloned());
        contribution
            .apply_into(&mut self.system, &mut self.values)
            .map_err(|e| self.at(entry.at, format!("{context} contributed invalid data: {e}")))?;
        let report = SourceReport {
            name: entry.name.clone(),
            plugin: source.kind().to_string(),
            version: source.version().to_string(),
            loaded_from: match origin {
                LoadedFrom::Builtin => "builtin".to_string(),
                LoadedFrom::Library(path) => {
                    self.inputs.push(PathBuf::from(&path));
                    path
                }
            },
            parameters,
            rows,
            counts,
            warnings,
        };
        self.sources.push(Loaded {
            name: entry.name.clone(),
            kind: source.kind().to_string(),
            config: config.to_string(),
            source,
            report,
        });
        Ok(())
    }

    /// The whole-system report without edits.
    pub fn analyze(&self) -> Report {
        let facts = analysis::SystemFacts::of(&self.system, &self.initial);
        whole_system_report(
            &self.run_path,
            analysis::analyze(facts, self.graph(), self.tolerance),
            self.sources.iter().map(|s| s.report.clone()).collect(),
        )
    }

    /// [`Session::analyze`] for a session that does nothing after it (`ecles analyze`): the
    /// sources' own data (a mesh's spline, control points and conditions), then the system and
    /// the values once their graph and facts are taken, are released before the elimination,
    /// which needs neither: on a whole mesh they are most of the memory. The system's rows move
    /// into the analysed matrix rather than being copied.
    pub fn analyze_alone(self) -> Report {
        let Session {
            run_path,
            sources,
            system,
            initial,
            values,
            graph,
            tolerance,
            ..
        } = self;
        let reports: Vec<SourceReport> = sources.into_iter().map(|loaded| loaded.report).collect();
        let facts = analysis::SystemFacts::of(&system, &initial);
        drop((initial, values));
        let graph = match graph.into_inner() {
            Some(graph) => {
                drop(system);
                graph
            }
            // The system's coefficients, labels and names move into the analysed matrix.
            None => crate::structural::SystemGraph::of_shape(analysis::shape_owned(system)),
        };
        whole_system_report(
            &run_path,
            analysis::analyze_owned(facts, graph, tolerance),
            reports,
        )
    }

    /// Why the parameter (or coordinate `name[k]`) is fixed, limited or free, in lines of
    /// text. An unknown parameter, or a coordinate beyond the parameter's dimension, is bad
    /// input.
    pub fn explain(&self, name: &str) -> Result<Vec<String>, RunError> {
        let (base, coordinate) = split_coordinate(name);
        let id = self.system.param_id(base).ok_or_else(|| {
            RunError::input(format!(
                "{}: no parameter named {base:?} (parameters are named source.name, e.g. \"worm.v3\"; one coordinate is name[k])",
                self.run_name()
            ))
        })?;
        let dim = self.system.params()[id.index()].dim;
        if let Some(k) = coordinate {
            if k >= dim {
                return Err(RunError::input(format!(
                    "{}: {name:?}: coordinate {k} is out of range, {base:?} has {dim} coordinate{} (0{})",
                    self.run_name(),
                    if dim == 1 { "" } else { "s" },
                    if dim == 1 { String::new() } else { format!(" to {}", dim - 1) }
                )));
            }
        }
        let shape = &self.graph().shape;
        let mut lines = Vec::new();
        let column = match coordinate {
            // Every row holds per coordinate: the matrix has one column per parameter, and each
            // coordinate is constrained exactly as the whole parameter.
            Some(k) if shape.copies > 1 => {
                lines.push(format!(
                    "every row of this system holds coordinate by coordinate, so {base}[{k}] is constrained as {base} is:"
                ));
                base.to_string()
            }
            Some(_) if dim == 1 => base.to_string(),
            Some(k) => format!("{base}[{k}]"),
            None => base.to_string(),
        };
        lines.extend(
            crate::structural::explain_parameter(self.graph(), &column).unwrap_or_default(),
        );
        Ok(lines)
    }

    /// Number of edits in the run file.
    pub fn edit_count(&self) -> usize {
        self.run.edits.len()
    }

    /// The built source named `name`.
    /// The constraint system of the run (all sources).
    pub fn system(&self) -> &ConstraintSystem {
        &self.system
    }

    /// The current values (exact), after the committed edits.
    pub fn values(&self) -> &Values {
        &self.values
    }

    /// Every file the run reads (the run file, the sources' inputs, plugin libraries).
    pub fn inputs(&self) -> &[PathBuf] {
        &self.inputs
    }

    /// The sources' names, in run-file order.
    pub fn source_names(&self) -> impl Iterator<Item = &str> {
        self.sources.iter().map(|s| s.name.as_str())
    }

    /// True when [`Session::undo`] has an edit to undo, and [`Session::redo`] one to redo.
    pub fn can_undo_redo(&self) -> (bool, bool) {
        (!self.history.is_empty(), !self.undone.is_empty())
    }

    /// The view of source `name` for an interactive editor ([`api::view`]), checked against
    /// the system before it is returned (a plugin's answer is outside data); `None` when the
    /// source draws nothing. The request names the run file's outputs for this source (their
    /// `output` text, in run-file order), so the view carries the models they deform.
    pub fn view(&self, name: &str) -> Result<Option<api::SourceView>, RunError> {
        let outputs = self
            .run
            .outputs
            .iter()
            .filter(|entry| entry.source == name)
            .map(|entry| entry.output.text().to_string())
            .collect();
        self.view_with(name, outputs)
    }

    /// [`Session::view`] without the outputs' models: the spline or prisms alone, for a caller
    /// that evaluates the deformation itself (placing a large model in the mesh is work it
    /// does not need).
    pub fn deformation_view(&self, name: &str) -> Result<Option<api::SourceView>, RunError> {
        self.view_with(name, Vec::new())
    }

    /// The view of source `name` with the models of `outputs`, checked against the system.
    fn view_with(
        &self,
        name: &str,
        outputs: Vec<String>,
    ) -> Result<Option<api::SourceView>, RunError> {
        let loaded = self.loaded(name)?;
        let view = loaded
            .source
            .view(&api::ViewRequest {
                schema: api::SCHEMA_VERSION,
                outputs,
            })
            .map_err(|e| RunError::input(format!("source {name:?} refused its view: {e}")))?;
        if let Some(view) = &view {
            view.validate(&self.system).map_err(|problem| {
                RunError::input(format!(
                    "source {name:?} gave a view that cannot be drawn: {problem}"
                ))
            })?;
        }
        Ok(view)
    }

    fn loaded(&self, name: &str) -> Result<&Loaded, RunError> {
        self.sources
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| RunError::input(format!("{}: unknown source {name:?}", self.run_name())))
    }

    fn param(&self, name: &str) -> Result<ParamId, RunError> {
        self.system
            .param_id(name)
            .ok_or_else(|| RunError::input(format!("unknown parameter {name:?}")))
    }

    /// The name of parameter `id` (`source.local`).
    pub(crate) fn name(&self, id: ParamId) -> std::sync::Arc<str> {
        std::sync::Arc::clone(&self.system.params()[id.index()].name)
    }
}

/// `"name[k]"` as `("name", Some(k))`; any other text as `(text, None)`.
fn split_coordinate(name: &str) -> (&str, Option<usize>) {
    if let Some(inner) = name.strip_suffix(']') {
        if let Some((base, k)) = inner.rsplit_once('[') {
            if let Ok(k) = k.parse::<usize>() {
                return (base, Some(k));
            }
        }
    }
    (name, None)
}

/// A one-line description of a system report; every count in scalar equations and scalar
/// parameters (coordinates).
pub fn describe(report: &Report) -> String {
    let redundant: usize = report.redundant.iter().map(|r| r.equations).sum();
    format!(
        "{} parameters, {} constraints, rank {}, {} redundant, {}",
        report.parameters,
        report.constraints,
        report.rank,
        redundant,
        if report.consistent {
            "consistent".to_string()
        } else {
            format!(
                "INCONSISTENT ({})",
                report.conflict.clone().unwrap_or_default().join(", ")
            )
        }
    )
}
