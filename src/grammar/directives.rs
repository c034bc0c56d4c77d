//! The header directives a grammar may set, and what value each takes.
//!
//! This table is the single list of known directives: the parser rejects any other name
//! and checks each value's form here; the engine reads the values. To add a directive, add
//! a line to [`DIRECTIVES`] (and document it in `docs/grammar.md`).

/// The form of a directive's value. Numbers must be literals (units allowed, `-` only
/// where the kind allows negatives): the header is read before any shape exists, so there
/// is nothing to compute with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectiveKind {
    /// A positive duration in seconds; `s` and `ms` suffixes allowed (`6s`, `500ms`, `6`).
    Seconds,
    /// A time in seconds from the start, 0 or more; `s` and `ms` suffixes allowed.
    Instant,
    /// A positive number.
    Positive,
    /// A positive whole number.
    Count,
    /// A whole number from 0 to 2^53 (so it survives the trip through `f64` exactly).
    Seed,
    /// A grid size `NxM` with N, M ≥ 1, or a whole number N for `NxN`.
    Size,
    /// A file path: a string, or a bare path without spaces (`scene art/toy.svg`).
    Path,
    /// One of these keywords.
    OneOf(&'static [&'static str]),
    /// Any expression (an easing or filter call such as `spring(0.3, 0.1)`).
    Expr,
    /// One or more names (slice tags), separated by spaces or commas.
    Names,
    /// One or more of these keywords, each at most once, separated by spaces or commas.
    SomeOf(&'static [&'static str]),
}

/// A known directive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectiveSpec {
    /// Its name.
    pub name: &'static str,
    /// The form of its value (a single one, but for [`DirectiveKind::Names`]).
    pub kind: DirectiveKind,
    /// The value used when the directive is absent, as documented.
    pub default: &'static str,
    /// One line saying what it sets.
    pub summary: &'static str,
}

/// Every known directive, in the order the documentation lists them.
pub const DIRECTIVES: &[DirectiveSpec] = &[
    DirectiveSpec {
        name: "duration",
        kind: DirectiveKind::Seconds,
        default: "5s",
        summary: "length of every shape's timeline (a Lottie scene's: its composition's)",
    },
    DirectiveSpec {
        name: "fps",
        kind: DirectiveKind::Positive,
        default: "30",
        summary: "frames per second of sampled output (a Lottie scene's: its composition's)",
    },
    DirectiveSpec {
        name: "grid",
        kind: DirectiveKind::Size,
        default: "1x1",
        summary: "columns x rows of the spatial grid of every animation",
    },
    DirectiveSpec {
        name: "seed",
        kind: DirectiveKind::Seed,
        default: "0",
        summary: "seed of every random choice and rand()",
    },
    DirectiveSpec {
        name: "scene",
        kind: DirectiveKind::Path,
        default: "none: given on the command line",
        summary: "SVG file to animate, relative to the grammar file (a scene on the command line overrides it)",
    },
    DirectiveSpec {
        name: "width",
        kind: DirectiveKind::Count,
        default: "the scene's width",
        summary: "width in pixels of every output, the art scaled to fit",
    },
    DirectiveSpec {
        name: "height",
        kind: DirectiveKind::Count,
        default: "follows width and the scene's aspect ratio",
        summary: "height in pixels of every output, the art scaled to fit",
    },
    DirectiveSpec {
        name: "lookup",
        kind: DirectiveKind::OneOf(&["nearest", "bilinear", "exact", "vertex"]),
        default: "nearest",
        summary: "how a shape reads the animation grid",
    },
    DirectiveSpec {
        name: "interp",
        kind: DirectiveKind::OneOf(&["linear", "alexa"]),
        default: "linear",
        summary: "how transforms are interpolated in time",
    },
    DirectiveSpec {
        name: "loop",
        kind: DirectiveKind::OneOf(&["true", "false"]),
        default: "true",
        summary: "whether players repeat the animation",
    },
    DirectiveSpec {
        name: "max_steps",
        kind: DirectiveKind::Count,
        default: "10000",
        summary: "expansion steps before the engine gives up",
    },
    DirectiveSpec {
        name: "choice",
        kind: DirectiveKind::OneOf(&["group", "shape"]),
        default: "group",
        summary: "draw the random rule choice once per step, or per shape",
    },
    DirectiveSpec {
        name: "tag_from",
        kind: DirectiveKind::OneOf(&["auto", "data-tag", "class", "label", "layer"]),
        default: "auto",
        summary: "where SVG shapes get their tags (as the CLI's --tag-from)",
    },
    DirectiveSpec {
        name: "units",
        kind: DirectiveKind::OneOf(&["auto", "paths", "groups"]),
        default: "auto",
        summary: "what the animated units are (as the CLI's --units)",
    },
    DirectiveSpec {
        name: "unit_depth",
        kind: DirectiveKind::Count,
        default: "1",
        summary: "how deep a group must sit in the SVG to become a unit (as the CLI's --unit-depth)",
    },
    DirectiveSpec {
        name: "reference_time",
        kind: DirectiveKind::Instant,
        default: "the first frame where every unit draws something with area",
        summary: "when a Lottie scene's units are measured, in seconds from its start (as the CLI's --reference-time)",
    },
    DirectiveSpec {
        name: "tags",
        kind: DirectiveKind::Path,
        default: "none",
        summary: "tag map giving SVG elements tags and units by selector, relative to the grammar file (as the CLI's --tags)",
    },
    DirectiveSpec {
        name: "markers",
        kind: DirectiveKind::Names,
        default: "none",
        summary: "slice tags written as named markers (Lottie `markers`), each spanning the slices that carry the tag or came from one that did",
    },
    DirectiveSpec {
        name: "slots",
        kind: DirectiveKind::SomeOf(&["fill", "stroke", "opacity"]),
        default: "none",
        summary: "gives each tag's solid fill colour, stroke colour or opacity a Lottie slot (`sid`), id `TAG.fill`, `TAG.stroke`, `TAG.opacity`, that a theme can replace",
    },
    DirectiveSpec {
        name: "smoothing",
        kind: DirectiveKind::Expr,
        default: "none",
        summary: "filter applied to every sampled channel, e.g. `spring(0.3, 0.1)`",
    },
];

/// The spec of directive `name`, if it is a known one.
pub fn directive_spec(name: &str) -> Option<&'static DirectiveSpec> {
    DIRECTIVES.iter().find(|d| d.name == name)
}
