//! The grammar language: syntax tree, parser, expression evaluation.

pub mod ast;
