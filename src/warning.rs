//! One warning type for every layer: an importer that dropped an element, the engine that
//! met degenerate geometry, an exporter that approximated what its format cannot say. The
//! work goes on; the caller decides how to show it.

use std::fmt;

use crate::grammar::ast::Span;

/// Something that could not be done exactly as asked, and what was done instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// What it is about: a shape (`tag:id`), a source element, or nothing in particular.
    pub subject: Option<String>,
    /// The grammar rule concerned, when a rule caused it.
    pub span: Option<Span>,
    /// What happened.
    pub message: String,
}

impl Warning {
    /// A warning about nothing in particular.
    pub fn new(message: impl Into<String>) -> Warning {
        Warning {
            subject: None,
            span: None,
            message: message.into(),
        }
    }

    /// A warning about `subject` (a shape or an element).
    pub fn about(subject: impl Into<String>, message: impl Into<String>) -> Warning {
        Warning {
            subject: Some(subject.into()),
            span: None,
            message: message.into(),
        }
    }

    /// A warning about the grammar rule at `span`.
    pub fn at(span: Option<Span>, message: impl Into<String>) -> Warning {
        Warning {
            subject: None,
            span,
            message: message.into(),
        }
    }
}

impl From<String> for Warning {
    fn from(message: String) -> Warning {
        Warning::new(message)
    }
}

/// `line:col: subject: message`, leaving out what is unknown.
impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(s) = self.span {
            write!(f, "{}:{}: ", s.line, s.col)?;
        }
        if let Some(s) = &self.subject {
            write!(f, "{s}: ")?;
        }
        f.write_str(&self.message)
    }
}
