//! Replacing the model a source's outputs deform (the editor's "load model"): the model is
//! not part of the system, so the values, the history and the system stay; the run's output
//! entries change, and so what a saved session writes and what the source's view draws.

use super::Session;
use crate::config_text::{field_text, set_field};
use crate::error::RunError;
use crate::runfile::{Fragment, OutputEntry};
use api::config::TextPosition;

impl Session {
    /// Makes `model` (a path relative to the run file, as a run file names it) the model of
    /// source `source`'s outputs: in the first of its outputs that names a model; when none
    /// does, added to its first output; when it has none, as a new output `(model: ...)`. The
    /// new outputs are checked as the run's outputs are before an edit runs (the model read
    /// and validated by its source, errors with the file, line and column) and the source's
    /// view is made with them; when either fails, the outputs are put back and the error is
    /// returned.
    pub fn replace_model(&mut self, source: &str, model: &str) -> Result<(), RunError> {
        self.loaded(source)?;
        let quoted = serde_json::to_string(model)
            .map_err(|e| RunError::input(format!("model path {model:?}: {e}")))?;
        let previous = self.run.outputs.clone();
        let mine = |o: &&OutputEntry| o.source == source;
        let target = self
            .run
            .outputs
            .iter()
            .position(|o| o.source == source && field_text(o.output.text(), "model").is_some())
            .or_else(|| self.run.outputs.iter().position(|o| mine(&o)));
        match target {
            Some(index) => {
                let entry = &mut self.run.outputs[index];
                let old = entry.output.text().to_string();
                let new = if field_text(&old, "model").is_some() {
                    set_field(&old, "model", &quoted, "model")
                } else {
                    add_first_field(&old, "model", &quoted)
                }
                .map_err(|e| RunError::input(format!("output of source {source:?}: {e}")))?;
                entry.text = entry.text.replacen(old.trim(), new.trim(), 1);
                entry.output = Fragment::new(new, entry.output.start());
            }
            None => {
                let output = format!("(model: {quoted})");
                self.run.outputs.push(OutputEntry {
                    source: source.to_string(),
                    text: format!("(source: {}, output: {output})", json_string(source)),
                    output: Fragment::new(output, TextPosition::START),
                    at: TextPosition::START,
                });
            }
        }
        let checked = self.check().and_then(|_| self.view(source).map(|_| ()));
        if let Err(e) = checked {
            self.run.outputs = previous;
            return Err(e);
        }
        Ok(())
    }
}

/// `text`, a struct `( ... )`, with `field: value` first in it.
fn add_first_field(text: &str, field: &str, value: &str) -> Result<String, String> {
    let open = text
        .find('(')
        .ok_or_else(|| "the output is not a struct".to_string())?;
    let rest = text[open + 1..].trim_start();
    let separator = if rest.starts_with(')') { "" } else { ", " };
    Ok(format!(
        "{}{field}: {value}{separator}{}",
        &text[..=open],
        &text[open + 1..]
    ))
}

/// `text` as a RON string literal.
fn json_string(text: &str) -> String {
    serde_json::to_string(text).unwrap_or_else(|_| format!("{text:?}"))
}

#[cfg(test)]
mod tests {
    use crate::testutil::session;

    const WORM: &str = r#"(sources: [(name: "worm", plugin: "spline2d", config: (mesh: "meshes/worm.obj", degree: 3))],
        outputs: [(source: "worm", output: (picture: "worm.svg"))])"#;

    /// A model is added, replaced, and a bad one refused with its line and column, the outputs
    /// kept as they were; the saved session names the model in force.
    #[test]
    fn a_model_is_added_replaced_or_refused_with_its_position() {
        let (dir, mut session) = session(WORM);
        session
            .replace_model("worm", "models/worm-model.obj")
            .expect("the worm's model");
        let view = session.view("worm").expect("view").expect("drawn");
        let api::SourceView::BezierTriangles(v) = view else {
            panic!("a spline view");
        };
        assert_eq!(v.models.len(), 1);
        let text = session.session_run_file("x");
        assert!(
            text.contains(
                r#"(source: "worm", output: (model: "models/worm-model.obj", picture: "worm.svg"))"#
            ),
            "{text}"
        );

        std::fs::write(
            dir.path().join("bad.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
        )
        .expect("write");
        let error = session.replace_model("worm", "bad.obj").expect_err("bad");
        assert!(error.to_string().contains("bad.obj:4:"), "{error}");
        assert_eq!(session.session_run_file("x"), text, "nothing changed");

        std::fs::write(dir.path().join("tri.obj"), "v 1 1\nv 2 1\nv 1 2\nf 1 2 3\n")
            .expect("write");
        session
            .replace_model("worm", "tri.obj")
            .expect("another model");
        assert!(session
            .session_run_file("x")
            .contains(r#"output: (model: "tri.obj", picture: "worm.svg")"#));

        // A source without outputs gets one.
        let (_dir, mut bare) = crate::testutil::session(
            &WORM.replace(r#"[(source: "worm", output: (picture: "worm.svg"))]"#, "[]"),
        );
        bare.replace_model("worm", "models/worm-model.obj")
            .expect("added");
        assert!(bare
            .session_run_file("x")
            .contains(r#"(source: "worm", output: (model: "models/worm-model.obj"))"#));
    }
}
