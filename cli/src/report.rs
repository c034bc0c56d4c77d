//! Error messages for the terminal: grammar errors with the source line and a caret.

use std::fmt;
use std::path::Path;

use gmotion::engine::EngineError;
use gmotion::grammar::diagnostics::Diagnostic;

/// An error already worded for the user.
#[derive(Debug)]
pub struct CliError(pub String);

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl CliError {
    /// A plain message.
    pub fn msg(m: impl Into<String>) -> CliError {
        CliError(m.into())
    }
}

/// Result of a command.
pub type Result<T> = std::result::Result<T, CliError>;

/// An engine error rendered against the grammar source.
pub fn engine_error(grammar_path: &Path, src: &str, e: &EngineError) -> CliError {
    let name = grammar_path.display().to_string();
    match e.span {
        Some(span) => {
            let mut d = Diagnostic::new(span, e.message.clone());
            if !e.notes.is_empty() {
                d = d.with_help(e.notes.join("\n"));
            }
            CliError(d.render(&name, src).trim_end().to_string())
        }
        None => {
            let mut s = format!("{name}: error: {}", e.message);
            for n in &e.notes {
                s.push_str(&format!("\n  note: {n}"));
            }
            CliError(s)
        }
    }
}
