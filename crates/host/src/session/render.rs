//! Rendering the outputs of a run (nothing is written here).

use super::{OutputsPlan, Session};
use crate::error::RunError;
use api::{OutputFile, RenderRequest};

impl Session {
    /// Renders every output; nothing is written here. Each output must produce exactly the
    /// files its check announced (`plan`, from [`Session::check`]).
    pub fn render_outputs(&self, plan: &OutputsPlan) -> Result<Vec<OutputFile>, RunError> {
        let mut files: Vec<OutputFile> = Vec::new();
        let parts = if self.run.outputs.is_empty() {
            None
        } else {
            Some(crate::structural::parts(&self.system, self.graph()))
        };
        for (i, out) in self.run.outputs.iter().enumerate() {
            let loaded = self.loaded(&out.source)?;
            let context = format!("output {i} (source {:?})", out.source);
            let request = RenderRequest {
                schema: api::SCHEMA_VERSION,
                output: out.output.text().to_string(),
                base_dir: self.base_dir.clone(),
                system: self.system.clone(),
                initial: self.initial.clone(),
                values: self.values.clone(),
                highlight: self.last_highlight.get(&out.source).cloned(),
                structure: parts.clone(),
                input_limit: self.input_limit,
            };
            let rendered = loaded
                .source
                .render(&request)
                .map_err(|e| self.source_error(&out.output, &context, &e))?;
            let names: Vec<String> = rendered.iter().map(|f| f.name.clone()).collect();
            if let Some(Some(announced)) = plan.announced.get(i) {
                if *announced != names {
                    return Err(self.at(
                        out.at,
                        format!("{context} wrote {names:?}, but its check announced {announced:?}"),
                    ));
                }
            }
            for file in rendered {
                check_file_name(&file.name).map_err(|m| {
                    self.at(
                        out.at,
                        format!("{context} produced the file {:?}: {m}", file.name),
                    )
                })?;
                if files.iter().any(|f| f.name == file.name) {
                    return Err(self.at(
                        out.at,
                        format!("{context}: two outputs write {:?}", file.name),
                    ));
                }
                files.push(file);
            }
        }
        Ok(files)
    }
}

/// A file name an output may write: plain (no directories), not hidden, not the report.
pub(super) fn check_file_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
        Err("not a plain file name")
    } else if name == crate::outputs::REPORT {
        Err("the run report's name")
    } else {
        Ok(())
    }
}
