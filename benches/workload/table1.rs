//! gMotion's Table 1, row by row, with the example files that re-create each animation:
//! shared by the engine benchmark (which times them next to the paper) and the gallery
//! test (which holds the files to the paper's counts).

/// One animation of the paper's Table 1.
#[derive(Debug)]
pub struct Row {
    /// The paper's name for it.
    pub paper_name: &'static str,
    /// The example re-creating it: `grammars/FILE.gm` on `grammars/FILE.svg`.
    pub file: &'static str,
    /// Rules, as the paper reports them.
    pub rules: usize,
    /// Shapes.
    pub shapes: usize,
    /// Duration in seconds.
    pub duration: f64,
    /// Expansion steps.
    pub steps: usize,
    /// Time to expand and evaluate, in seconds (the paper's prototype).
    pub seconds: f64,
}

/// The eight rows, in the paper's order.
pub const TABLE1: [Row; 8] = [
    row("teaser", "teaser", 44, 208, 6.0, 60, 0.04),
    row("cube", "cube", 13, 54, 6.0, 16, 0.04),
    row("abstract", "abstract", 19, 68, 5.0, 22, 0.03),
    row("panel", "panel", 19, 106, 8.0, 40, 0.02),
    row("crack", "crack", 53, 358, 4.0, 55, 0.46),
    row("statue", "statue", 56, 896, 4.0, 108, 0.22),
    row(
        "intersections mini",
        "intersections_mini",
        105,
        44,
        4.0,
        161,
        0.07,
    ),
    row("intersections", "intersections", 105, 8214, 8.0, 161, 22.0),
];

const fn row(
    paper_name: &'static str,
    file: &'static str,
    rules: usize,
    shapes: usize,
    duration: f64,
    steps: usize,
    seconds: f64,
) -> Row {
    Row {
        paper_name,
        file,
        rules,
        shapes,
        duration,
        steps,
        seconds,
    }
}
