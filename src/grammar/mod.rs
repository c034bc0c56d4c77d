//! The grammar language: syntax tree, parser, expression evaluation.
//!
//! [`parse`] turns grammar source into an [`ast::Grammar`] or a [`Diagnostics`] listing
//! every error with its location; [`value::eval`] computes an expression for one shape.
//! The language is documented in `docs/grammar.md`.

pub mod ast;
pub mod diagnostics;
pub mod directives;
mod lexer;
pub mod parser;
pub mod value;

pub use diagnostics::{Diagnostic, Diagnostics};
pub use directives::{DIRECTIVES, DirectiveKind, DirectiveSpec};
pub use parser::parse;
pub use value::{Env, EvalError, TypeError, Value, eval};
