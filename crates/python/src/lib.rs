//! The native module of the `ecles` Python package (`ecles._ecles`): the host library's
//! [`Session`] for Python, nothing implemented twice. Exact values go in as text (`"7/3"`,
//! `"-12"`, decimals read exactly) and come back as (numerator, denominator) ints; the Python
//! layer (`python/ecles`) turns them into and from `int` and `fractions.Fraction` and refuses
//! floats where a value must be exact.
//! Long exact work runs on the session's own thread with the GIL released; a panic there
//! becomes a Python exception ("internal error …"), never an abort, and the session goes on.

mod spline;

use api::exact::Exact;
use api::{format_rational, parse_rational, PlannedStep, Rational};
use host::runfile::{CriterionChoice, GenericEdit, MeasureName, ValueText};
use host::session::{ActiveEdit, PlannedEdit, Planning, Session};
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::{mpsc, Arc};

pyo3::create_exception!(
    _ecles,
    InputError,
    PyValueError,
    "Bad input: a run file, an equation, a name, a value; the message names the file with line:column or the item."
);
pyo3::create_exception!(
    _ecles,
    Unsolvable,
    PyException,
    "An edit the constraints forbid: args are (message, conflicting row labels, explanation lines)."
);

/// Exact values by name, each coordinate as (numerator, denominator) in lowest terms.
type ExactValues = Vec<(String, Vec<(num_bigint::BigInt, num_bigint::BigInt)>)>;

/// The largest input file read, as the command line's default (`--max-input-bytes`).
const DEFAULT_INPUT_LIMIT: u64 = 256 << 20;

/// Bad input as `ecles.InputError`, with the host's message.
pub(crate) fn input_error(message: impl ToString) -> PyErr {
    InputError::new_err(message.to_string())
}

/// An exact value from its text.
fn exact(what: &str, text: &str) -> PyResult<Rational> {
    parse_rational(text).map_err(|e| input_error(format!("{what} {text:?}: {e}")))
}

/// A parameter's value as written in a run file.
fn value_text(what: &str, texts: &[String]) -> PyResult<ValueText> {
    let values = texts
        .iter()
        .map(|t| exact(what, t).map(Exact))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(ValueText::Vector(values))
}

/// A RON string literal (Rust's debug form of a string is one).
fn ron_string(text: &str) -> String {
    format!("{text:?}")
}

/// A job for the thread that owns a session.
type Job = Box<dyn FnOnce(&mut Session) + Send>;

/// The thread that owns a session (a session holds its sources, which need not be `Send`, so
/// it stays on one thread): every call sends it a job and waits for the answer with the GIL
/// released. A job that panics answers with an exception; the thread goes on.
#[derive(Clone)]
struct Worker {
    jobs: mpsc::Sender<Job>,
}

impl Worker {
    /// Starts the thread and builds its session there.
    fn start(
        py: Python<'_>,
        build: impl FnOnce() -> Result<Session, host::error::RunError> + Send + 'static,
    ) -> PyResult<Worker> {
        let (jobs, queue) = mpsc::channel::<Job>();
        let (ready, built) = mpsc::channel();
        std::thread::Builder::new()
            .name("ecles-session".into())
            .spawn(move || {
                let mut session = match catch_unwind(AssertUnwindSafe(build)) {
                    Ok(Ok(session)) => session,
                    Ok(Err(e)) => {
                        let _ = ready.send(Err(input_error(e)));
                        return;
                    }
                    Err(panic) => {
                        let _ = ready.send(Err(panic_error(panic.as_ref())));
                        return;
                    }
                };
                let _ = ready.send(Ok(()));
                while let Some(job) = next_job(&queue) {
                    job(&mut session);
                }
            })
            .map_err(|e| PyException::new_err(format!("cannot start the session thread: {e}")))?;
        match py.detach(move || built.recv()) {
            Ok(Ok(())) => Ok(Worker { jobs }),
            Ok(Err(e)) => Err(e),
            Err(_) => Err(PyException::new_err("the session thread stopped")),
        }
    }

    /// Runs `job` on the session, the GIL released while it runs. A `KeyboardInterrupt` (or
    /// any signal handler's exception) raised meanwhile is raised at once; the job finishes
    /// on the session's thread and its answer is dropped — for jobs that change nothing
    /// (analyses, updates, evaluations). Jobs that commit use [`Worker::run_to_end`].
    fn run<T: Send + 'static>(
        &self,
        py: Python<'_>,
        job: impl FnOnce(&mut Session) -> PyResult<T> + Send + 'static,
    ) -> PyResult<T> {
        self.run_with(py, job, true)
    }

    /// [`Worker::run`] for a job that changes the session: it is waited for to the end, so a
    /// commit is never half-known; signals are handled when it returns.
    fn run_to_end<T: Send + 'static>(
        &self,
        py: Python<'_>,
        job: impl FnOnce(&mut Session) -> PyResult<T> + Send + 'static,
    ) -> PyResult<T> {
        self.run_with(py, job, false)
    }

    fn run_with<T: Send + 'static>(
        &self,
        py: Python<'_>,
        job: impl FnOnce(&mut Session) -> PyResult<T> + Send + 'static,
        interruptible: bool,
    ) -> PyResult<T> {
        let (answer, answered) = mpsc::sync_channel(1);
        let job: Job = Box::new(move |session: &mut Session| {
            let outcome = catch_unwind(AssertUnwindSafe(|| job(session)))
                .unwrap_or_else(|panic| Err(panic_error(panic.as_ref())));
            let _ = answer.send(outcome);
        });
        self.jobs
            .send(job)
            .map_err(|_| PyException::new_err("the session thread stopped"))?;
        let mut receiver = answered;
        loop {
            let (received, back) = py.detach(move || {
                let received = match spin_receive(&receiver) {
                    Some(outcome) => Ok(outcome),
                    None => receiver.recv_timeout(SIGNAL_CHECK_INTERVAL),
                };
                (received, receiver)
            });
            receiver = back;
            match received {
                Ok(outcome) => return outcome,
                Err(mpsc::RecvTimeoutError::Timeout) if interruptible => py.check_signals()?,
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(PyException::new_err("the session thread stopped"))
                }
            }
        }
    }
}

/// How long the session's thread and a waiting caller poll before they sleep: a parked
/// thread takes tens of microseconds to wake, more than a small update costs, and calls come
/// in bursts (the frames of a drag).
const SPIN: std::time::Duration = std::time::Duration::from_micros(200);

/// A message from `receiver` if one comes within [`SPIN`], polling (with `yield_now`) rather
/// than sleeping.
fn spin_receive<T>(receiver: &mpsc::Receiver<T>) -> Option<T> {
    let start = std::time::Instant::now();
    loop {
        match receiver.try_recv() {
            Ok(message) => return Some(message),
            Err(mpsc::TryRecvError::Disconnected) => return None,
            Err(mpsc::TryRecvError::Empty) if start.elapsed() < SPIN => std::thread::yield_now(),
            Err(mpsc::TryRecvError::Empty) => return None,
        }
    }
}

/// The session thread's next job: one that comes within [`SPIN`] of the last is taken at once,
/// else the thread sleeps until one comes; `None` once the session is dropped.
fn next_job(queue: &mpsc::Receiver<Job>) -> Option<Job> {
    spin_receive(queue).or_else(|| queue.recv().ok())
}

/// How often a waiting call looks for a `KeyboardInterrupt`.
const SIGNAL_CHECK_INTERVAL: std::time::Duration = std::time::Duration::from_millis(50);

/// A panic's message as an exception.
fn panic_error(panic: &(dyn std::any::Any + Send)) -> PyErr {
    let message = panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into());
    PyException::new_err(format!("internal error (a panic in ecles): {message}"))
}

/// A session: the constraint system of one or more sources, its current values, and the
/// edits committed to it.
#[pyclass(name = "Session", module = "ecles._ecles", frozen)]
struct PySession {
    worker: Worker,
}

impl PySession {
    /// A session of run-file text read from the working directory.
    fn of_text(py: Python<'_>, text: String, name: &'static str) -> PyResult<PySession> {
        let worker = Worker::start(py, move || {
            Session::build_text(&text, name, Path::new("."), DEFAULT_INPUT_LIMIT)
        })?;
        Ok(PySession { worker })
    }
}

#[pymethods]
impl PySession {
    /// The session of a run file (its sources built; its edits are not run).
    #[staticmethod]
    #[pyo3(signature = (path, max_input_bytes = DEFAULT_INPUT_LIMIT))]
    fn from_run_file(py: Python<'_>, path: String, max_input_bytes: u64) -> PyResult<PySession> {
        let worker = Worker::start(py, move || {
            Session::build(Path::new(&path), max_input_bytes)
        })?;
        Ok(PySession { worker })
    }

    /// The session of run-file text (relative paths from the working directory).
    #[staticmethod]
    fn from_run_text(py: Python<'_>, text: String) -> PyResult<PySession> {
        PySession::of_text(py, text, "run text")
    }

    /// A `linear` source named `source` in matrix form: `matrix · p = rhs` over integers
    /// (decimal text of any size), with optional names and exact initial values.
    #[staticmethod]
    #[pyo3(signature = (matrix, rhs, names = None, values = None, source = "m".to_string()))]
    fn from_matrix(
        py: Python<'_>,
        matrix: Vec<Vec<String>>,
        rhs: Vec<String>,
        names: Option<Vec<String>>,
        values: Option<Vec<String>>,
        source: String,
    ) -> PyResult<PySession> {
        let list = |items: &[String]| -> String {
            let quoted: Vec<String> = items.iter().map(|t| ron_string(t)).collect();
            format!("[{}]", quoted.join(", "))
        };
        let rows: Vec<String> = matrix.iter().map(|row| list(row)).collect();
        let mut config = format!("matrix: [{}], rhs: {}", rows.join(", "), list(&rhs));
        if let Some(names) = &names {
            config.push_str(&format!(", names: {}", list(names)));
        }
        if let Some(values) = &values {
            config.push_str(&format!(", values: {}", list(values)));
        }
        let text = format!(
            "(sources: [(name: {}, plugin: \"linear\", config: ({config}))])",
            ron_string(&source)
        );
        PySession::of_text(py, text, "matrix")
    }

    /// A `linear` source named `source` from parameters (name, exact initial value, in order)
    /// and equations (`"p1 + 2 p2 = 3"`).
    #[staticmethod]
    #[pyo3(signature = (parameters, equations, source = "eq".to_string()))]
    fn from_equations(
        py: Python<'_>,
        parameters: Vec<(String, String)>,
        equations: Vec<String>,
        source: String,
    ) -> PyResult<PySession> {
        let params: Vec<String> = parameters
            .iter()
            .map(|(n, v)| format!("{}: {}", ron_string(n), ron_string(v)))
            .collect();
        let eqs: Vec<String> = equations.iter().map(|e| ron_string(e)).collect();
        let text = format!(
            "(sources: [(name: {}, plugin: \"linear\", config: (parameters: {{{}}}, equations: [{}]))])",
            ron_string(&source),
            params.join(", "),
            eqs.join(", ")
        );
        PySession::of_text(py, text, "equations")
    }

    /// The analysis of the whole system as `report.json` gives it (JSON text).
    fn analyze(&self, py: Python<'_>) -> PyResult<String> {
        self.worker.run(py, |session| {
            serde_json::to_string(&session.analyze())
                .map_err(|e| PyException::new_err(e.to_string()))
        })
    }

    /// Every parameter: (name, dimension), in id order.
    fn parameters(&self, py: Python<'_>) -> PyResult<Vec<(String, usize)>> {
        self.worker.run(py, |session| {
            Ok(session
                .system()
                .params()
                .iter()
                .map(|p| (p.name.to_string(), p.dim))
                .collect())
        })
    }

    /// Every parameter's current value: (name, exact coordinates as (numerator, denominator)).
    fn values(&self, py: Python<'_>) -> PyResult<ExactValues> {
        self.worker.run(py, |session| {
            Ok(session
                .system()
                .params()
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let value = session.values().get(api::ParamId(i as u32));
                    (
                        p.name.to_string(),
                        value
                            .iter()
                            .map(|r| (r.numer().clone(), r.denom().clone()))
                            .collect(),
                    )
                })
                .collect())
        })
    }

    /// Why a parameter (or coordinate `name[k]`) is fixed, limited or free: lines of text.
    fn explain(&self, py: Python<'_>, name: String) -> PyResult<Vec<String>> {
        self.worker.run(py, move |session| {
            session.explain(&name).map_err(input_error)
        })
    }

    /// Initialises an ECLES edit (checked as a run file's `Ecles(...)` is): anchors and their
    /// values, derived parameters, hints, weights, the change criterion (`"L2"`, `"L1"`,
    /// `"Fewest"`) and primary parameters.
    #[pyo3(signature = (anchors, derived, hints, weights, criterion, primary, strong))]
    #[allow(clippy::too_many_arguments)]
    fn edit(
        &self,
        py: Python<'_>,
        anchors: Vec<(String, Vec<String>)>,
        derived: Vec<String>,
        hints: Vec<(String, Vec<String>)>,
        weights: Vec<(String, String)>,
        criterion: &str,
        primary: Vec<String>,
        strong: bool,
    ) -> PyResult<PyEdit> {
        let measure = measure(criterion)?;
        if !hints.is_empty() && measure != MeasureName::L2 {
            return Err(input_error(
                "hints belong to least squares: L1 and Fewest measure the change from the current values",
            ));
        }
        let mut anchor_map = BTreeMap::new();
        for (name, value) in &anchors {
            if anchor_map
                .insert(name.clone(), value_text("anchor", value)?)
                .is_some()
            {
                return Err(input_error(format!("anchor {name:?} is given twice")));
            }
        }
        let mut hint_map = BTreeMap::new();
        for (name, value) in &hints {
            hint_map.insert(name.clone(), value_text("hint", value)?);
        }
        let mut weight_map = BTreeMap::new();
        for (name, w) in &weights {
            weight_map.insert(name.clone(), Exact(exact("weight", w)?));
        }
        let generic = GenericEdit {
            anchors: anchor_map,
            derived,
            hints: hint_map,
            weights: weight_map,
            strong,
        };
        let choice = CriterionChoice { measure, primary };
        let state = self.worker.run(py, move |session| {
            let criterion = session.criterion(&choice).map_err(input_error)?;
            let plan = session.plan_generic(&generic).map_err(input_error)?;
            let active = session
                .initialize(&plan)
                .map_err(|e| unsolvable(session, &plan, &e))?;
            Ok(EditState {
                entry: entry_text(&generic, &choice),
                plan,
                active,
                criterion,
            })
        })?;
        Ok(PyEdit {
            worker: self.worker.clone(),
            state: Arc::new(state),
        })
    }

    /// `ψ` of spline source `source` at the current values, at each point; `None` outside
    /// the mesh. Floats: for drawing and deforming, never for exact values.
    fn evaluate(
        &self,
        py: Python<'_>,
        source: String,
        points: Vec<(f64, f64)>,
    ) -> PyResult<Vec<Option<(f64, f64)>>> {
        self.worker.run(py, move |session| {
            spline::Deformation::of(session, &source)?.evaluate(&points)
        })
    }

    /// The bottom and top heights of terrain source `source` at each point (`None` outside
    /// the mesh). Floats.
    fn heights(
        &self,
        py: Python<'_>,
        source: String,
        points: Vec<(f64, f64)>,
    ) -> PyResult<Vec<Option<(f64, f64)>>> {
        self.worker.run(py, move |session| {
            spline::Deformation::of(session, &source)?.heights(&points)
        })
    }

    /// Model vertices deformed by source `source`'s `ψ` (a spline's: `(x, y[, z])`, z kept; a
    /// terrain's: `(x, y, z)`), and how many lie outside (left where they are, as is every
    /// vertex `ψ` leaves exactly in place).
    fn deform(
        &self,
        py: Python<'_>,
        source: String,
        vertices: Vec<Vec<f64>>,
    ) -> PyResult<(Vec<Vec<f64>>, usize)> {
        self.worker.run(py, move |session| {
            spline::Deformation::of(session, &source)?.deform(&vertices)
        })
    }

    /// Plans an operation of source `source` (RON text in its schema, as in run files) on the
    /// current values: its anchors and derived parameters (2DSD Select and ExpandDerived).
    fn plan(
        &self,
        py: Python<'_>,
        source: String,
        operation: String,
    ) -> PyResult<(Vec<String>, Vec<String>)> {
        self.worker.run(py, move |session| {
            let plan = planned(session, &source, &operation)?;
            let name = |id: &api::ParamId| session.system().params()[id.index()].name.to_string();
            Ok((
                plan.spec.anchors.iter().map(name).collect(),
                plan.spec.derived.iter().map(name).collect(),
            ))
        })
    }

    /// Runs and commits an operation of source `source` under `criterion` (`"L2"`, `"L1"`,
    /// `"Fewest"`): the values of its anchors and derived parameters.
    fn operate(
        &self,
        py: Python<'_>,
        source: String,
        operation: String,
        criterion: String,
    ) -> PyResult<ExactValues> {
        let measure = measure(&criterion)?;
        self.worker.run_to_end(py, move |session| {
            let plan = planned(session, &source, &operation)?;
            let criterion = measure.criterion();
            let active = session
                .initialize(&plan)
                .map_err(|e| unsolvable(session, &plan, &e))?;
            let step = plan
                .steps
                .last()
                .ok_or_else(|| input_error("the operation planned no step"))?;
            let result = if criterion.is_least_squares() {
                active.update(step)
            } else {
                let hints = session.criterion_hints(&criterion, &plan.spec, step);
                active.update_by(&criterion, step, &hints).map(|(r, _)| r)
            }
            .map_err(|e| unsolvable(session, &plan, &e))?;
            let suffix = match measure {
                MeasureName::L2 => String::new(),
                other => format!(", criterion: {other:?}"),
            };
            let entry = format!(
                "Source(source: {}, operation: {}{suffix})",
                ron_string(&source),
                operation.trim()
            );
            session
                .apply(&active, &result, entry)
                .map_err(input_error)?;
            Ok(PyEdit::named(session, &result))
        })
    }

    /// Restores the state before the last applied edit; `False` when there is none.
    fn undo(&self, py: Python<'_>) -> PyResult<bool> {
        self.worker.run_to_end(py, |session| Ok(session.undo()))
    }
}

/// A change criterion by name.
fn measure(name: &str) -> PyResult<MeasureName> {
    match name {
        "L2" => Ok(MeasureName::L2),
        "L1" => Ok(MeasureName::L1),
        "Fewest" => Ok(MeasureName::Fewest),
        other => Err(input_error(format!(
            "criterion {other:?}: expected \"L2\", \"L1\" or \"Fewest\""
        ))),
    }
}

/// A source's plan of an operation; a source's refusal is bad input.
fn planned(session: &Session, source: &str, operation: &str) -> PyResult<PlannedEdit> {
    match session
        .plan_operation(source, operation)
        .map_err(input_error)?
    {
        Planning::Planned(plan) => Ok(plan),
        Planning::Refused(message) => Err(input_error(format!(
            "source {source:?} refused the operation: {message}"
        ))),
    }
}

/// The run-file entry of a generic edit (what a saved session would repeat).
fn entry_text(edit: &GenericEdit, choice: &CriterionChoice) -> String {
    let value = |v: &ValueText| -> String {
        let texts: Vec<String> = v
            .coordinates()
            .iter()
            .map(|r| ron_string(&format_rational(r)))
            .collect();
        format!("({})", texts.join(", "))
    };
    let anchors: Vec<String> = edit
        .anchors
        .iter()
        .map(|(n, v)| format!("{}: {}", ron_string(n), value(v)))
        .collect();
    let derived: Vec<String> = edit.derived.iter().map(|n| ron_string(n)).collect();
    let mut text = format!(
        "Ecles(anchors: {{{}}}, derived: [{}]",
        anchors.join(", "),
        derived.join(", ")
    );
    if choice.measure != MeasureName::L2 {
        text.push_str(&format!(", criterion: {:?}", choice.measure));
    }
    if !choice.primary.is_empty() {
        let primary: Vec<String> = choice.primary.iter().map(|n| ron_string(n)).collect();
        text.push_str(&format!(", primary: [{}]", primary.join(", ")));
    }
    text.push(')');
    text
}

/// The Python exception for a refused edit: the message, the labels of the rows in the way,
/// the explanation.
fn unsolvable(session: &Session, plan: &PlannedEdit, e: &ecles::EditError<Rational>) -> PyErr {
    match e {
        ecles::EditError::Criterion(_) | ecles::EditError::Backend(_) => input_error(e),
        _ => {
            let (labels, explanation) = session.conflict_details(&plan.spec, e);
            Unsolvable::new_err((e.to_string(), labels, explanation))
        }
    }
}

/// An initialised edit and what it was planned with.
struct EditState {
    plan: PlannedEdit,
    active: ActiveEdit,
    criterion: ecles::Criterion,
    entry: String,
}

/// An initialised ECLES edit: update it as often as needed, apply one result.
#[pyclass(name = "Edit", module = "ecles._ecles", frozen)]
struct PyEdit {
    worker: Worker,
    /// Shared with the jobs that use it (on the session's thread).
    state: Arc<EditState>,
}

impl PyEdit {
    /// The step for new anchor values and hints (the edit's own when `None`), in the edit's
    /// order, checked for completeness.
    fn step(
        state: &EditState,
        session: &Session,
        anchors: Option<Vec<(String, Vec<String>)>>,
        hints: Option<Vec<(String, Vec<String>)>>,
    ) -> PyResult<PlannedStep> {
        let planned = state
            .plan
            .steps
            .last()
            .ok_or_else(|| input_error("the edit has no step"))?
            .clone();
        let name = |id: &api::ParamId| session.system().params()[id.index()].name.to_string();
        let ordered = |what: &str,
                       ids: &[api::ParamId],
                       given: Option<Vec<(String, Vec<String>)>>,
                       default: Vec<Vec<Rational>>,
                       all: bool|
         -> PyResult<Vec<Vec<Rational>>> {
            let Some(given) = given else {
                return Ok(default);
            };
            let mut by_name: BTreeMap<String, Vec<Rational>> = BTreeMap::new();
            for (n, texts) in given {
                let values = texts
                    .iter()
                    .map(|t| exact(what, t))
                    .collect::<PyResult<Vec<_>>>()?;
                if !ids.iter().any(|id| name(id) == n) {
                    return Err(input_error(format!(
                        "{n:?} is not one of the edit's {what}s"
                    )));
                }
                by_name.insert(n, values);
            }
            ids.iter()
                .zip(default)
                .map(|(id, d)| match by_name.remove(&name(id)) {
                    Some(v) => Ok(v),
                    None if all => Err(input_error(format!("no value for {what} {:?}", name(id)))),
                    None => Ok(d),
                })
                .collect()
        };
        Ok(PlannedStep {
            anchors: ordered(
                "anchor",
                &state.plan.spec.anchors,
                anchors,
                planned.anchors,
                true,
            )?,
            hints: ordered(
                "hint",
                &state.plan.spec.derived,
                hints,
                planned.hints,
                false,
            )?,
        })
    }

    /// The exact update for a step, under the edit's criterion.
    fn solve(
        state: &EditState,
        session: &Session,
        step: &PlannedStep,
    ) -> PyResult<ecles::UpdateResult<Rational>> {
        let result = if state.criterion.is_least_squares() {
            state.active.update(step)
        } else {
            let hints = session.criterion_hints(&state.criterion, &state.plan.spec, step);
            state
                .active
                .update_by(&state.criterion, step, &hints)
                .map(|(result, _)| result)
        };
        result.map_err(|e| unsolvable(session, &state.plan, &e))
    }

    /// The values of an update by name, each coordinate as (numerator, denominator): Python
    /// ints, cheaper to turn into `Fraction`s than text.
    fn named(session: &Session, result: &ecles::UpdateResult<Rational>) -> ExactValues {
        result
            .anchors
            .iter()
            .chain(&result.derived)
            .map(|(id, v)| {
                (
                    session.system().params()[id.index()].name.to_string(),
                    v.iter()
                        .map(|r| (r.numer().clone(), r.denom().clone()))
                        .collect(),
                )
            })
            .collect()
    }
}

#[pymethods]
impl PyEdit {
    /// ECLES.Update: the exact values of the anchors and derived parameters for new anchor
    /// values (every anchor) and hints (any derived parameters; the others keep the edit's).
    #[pyo3(signature = (anchors = None, hints = None))]
    fn update(
        &self,
        py: Python<'_>,
        anchors: Option<Vec<(String, Vec<String>)>>,
        hints: Option<Vec<(String, Vec<String>)>>,
    ) -> PyResult<ExactValues> {
        let state = Arc::clone(&self.state);
        self.worker.run(py, move |session| {
            let step = PyEdit::step(&state, session, anchors, hints)?;
            let result = PyEdit::solve(&state, session, &step)?;
            Ok(PyEdit::named(session, &result))
        })
    }

    /// The same verdict as `update`, the values rounded to floats (cheaper: for drawing).
    #[pyo3(signature = (anchors = None, hints = None))]
    fn preview(
        &self,
        py: Python<'_>,
        anchors: Option<Vec<(String, Vec<String>)>>,
        hints: Option<Vec<(String, Vec<String>)>>,
    ) -> PyResult<Vec<(String, Vec<f64>)>> {
        let state = Arc::clone(&self.state);
        self.worker.run(py, move |session| {
            let step = PyEdit::step(&state, session, anchors, hints)?;
            let name = |id: &api::ParamId| session.system().params()[id.index()].name.to_string();
            let to_f64 = |v: &[Rational]| -> Vec<f64> {
                v.iter().map(api::exact::rational_to_f64).collect()
            };
            let anchors: Vec<(String, Vec<f64>)> = state
                .plan
                .spec
                .anchors
                .iter()
                .zip(&step.anchors)
                .map(|(id, v)| (name(id), to_f64(v)))
                .collect();
            let derived: Vec<Vec<f64>> = if state.criterion.is_least_squares() {
                state
                    .active
                    .preview(&step)
                    .map_err(|e| unsolvable(session, &state.plan, &e))?
            } else {
                PyEdit::solve(&state, session, &step)?
                    .derived
                    .iter()
                    .map(|(_, v)| to_f64(v))
                    .collect()
            };
            Ok(anchors
                .into_iter()
                .chain(state.plan.spec.derived.iter().map(name).zip(derived))
                .collect())
        })
    }

    /// Commits an update: the session's values take its exact values (`Session.undo` restores
    /// them). Returns the values committed.
    #[pyo3(signature = (anchors = None, hints = None))]
    fn apply(
        &self,
        py: Python<'_>,
        anchors: Option<Vec<(String, Vec<String>)>>,
        hints: Option<Vec<(String, Vec<String>)>>,
    ) -> PyResult<ExactValues> {
        let state = Arc::clone(&self.state);
        self.worker.run_to_end(py, move |session| {
            let step = PyEdit::step(&state, session, anchors, hints)?;
            let result = PyEdit::solve(&state, session, &step)?;
            session
                .apply(&state.active, &result, state.entry.clone())
                .map_err(input_error)?;
            Ok(PyEdit::named(session, &result))
        })
    }

    /// The anchors, derived parameters, and the rank of the edit's reduced system.
    fn describe(&self, py: Python<'_>) -> PyResult<(Vec<String>, Vec<String>, usize)> {
        let state = Arc::clone(&self.state);
        self.worker.run(py, move |session| {
            let name = |id: &api::ParamId| session.system().params()[id.index()].name.to_string();
            let report = state.active.edit().report();
            let (_, rank, _) = host::session::equation_counts(session.system(), &report);
            Ok((
                state.plan.spec.anchors.iter().map(name).collect(),
                state.plan.spec.derived.iter().map(name).collect(),
                rank,
            ))
        })
    }
}

/// The native module.
#[pymodule]
fn _ecles(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySession>()?;
    m.add_class::<PyEdit>()?;
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("Unsolvable", m.py().get_type::<Unsolvable>())?;
    Ok(())
}
