//! Rules checked and indexed for expansion: operators resolved, argument counts and output
//! counts validated once, before any shape is touched.

use std::collections::HashMap;

use crate::grammar::ast::{
    Arg, Expr, ExprKind, Grammar, Rule, Span, TagRef, tag_matches, takes_shape,
};

use super::EngineError;

/// What an `animate` rule changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimType {
    /// A product of transforms.
    Affine,
    /// Translation towards a point.
    Towards,
    /// Translation to the closest point of a path.
    Path,
    /// Fill colour.
    Fill,
    /// Stroke colour.
    Border,
    /// Opacity.
    Opacity,
    /// Stroke width.
    StrokeWidth,
    /// The strokes' visible part (trim paths).
    Trim,
    /// Travel along a path by arc length (see [`crate::motion::follow`]).
    Follow,
    /// The outline becomes another shape's (or SVG path data's).
    Morph,
}

impl AnimType {
    /// The papers' long names (gMotion §3.3), accepted as well as [`AnimType::ALL`]'s.
    pub const PAPER_NAMES: [(&'static str, AnimType); 7] = [
        ("affine transform", AnimType::Affine),
        ("move towards", AnimType::Towards),
        ("follow path", AnimType::Path),
        ("fill color", AnimType::Fill),
        ("fill colour", AnimType::Fill),
        ("border color", AnimType::Border),
        ("border colour", AnimType::Border),
    ];

    /// The type a grammar names, in either spelling.
    pub fn named(name: &str) -> Option<AnimType> {
        AnimType::ALL
            .iter()
            .chain(&AnimType::PAPER_NAMES)
            .find(|(n, _)| *n == name)
            .map(|(_, t)| *t)
    }

    /// Every type with its grammar spelling.
    pub const ALL: [(&'static str, AnimType); 10] = [
        ("affine", AnimType::Affine),
        ("towards", AnimType::Towards),
        ("path", AnimType::Path),
        ("fill", AnimType::Fill),
        ("border", AnimType::Border),
        ("opacity", AnimType::Opacity),
        ("stroke-width", AnimType::StrokeWidth),
        ("trim", AnimType::Trim),
        ("follow", AnimType::Follow),
        ("morph", AnimType::Morph),
    ];
}

/// The operator of a timeslice rule, with its arguments checked.
#[derive(Clone, Debug)]
pub enum Op {
    /// `timesplit(c0, …, ck)`.
    Timesplit {
        /// The fractions (expressions over the shape).
        fractions: Vec<Expr>,
    },
    /// `animate(type, ref, offset, value, named…)`, boxed: it is far larger than a split.
    Animate(Box<Animate>),
}

/// The arguments of an `animate` rule.
#[derive(Clone, Debug)]
pub struct Animate {
    /// Animation type.
    pub kind: AnimType,
    /// True for `world`, false for `local`.
    pub world: bool,
    /// Delay within the slice.
    pub offset: Expr,
    /// The value (transform, point, path, colour, number).
    pub value: Expr,
    /// `ease = …`.
    pub ease: Option<Expr>,
    /// `grid = NxM` or `NxMxP`.
    pub grid: Option<(usize, usize, usize)>,
    /// `lookup = …`.
    pub lookup: Option<crate::motion::Lookup>,
    /// `interp = …`.
    pub interp: Option<crate::motion::Interp>,
    /// `orient = auto` (true) or `none`: whether a `follow` turns with its path.
    pub orient: bool,
}

/// A checked timeslice rule.
#[derive(Clone, Debug)]
pub struct CRule {
    /// Index in `Grammar::rules`.
    pub index: usize,
    /// The operator.
    pub op: Op,
    /// Slice tags matched (base names; `inv_` versions match too).
    pub slice_tags: Vec<String>,
    /// Shape tags matched (names or `*` patterns); contains `all` to match every shape.
    pub shape_tags: Vec<String>,
    /// Shape tags left out (`all - background`).
    pub shape_excluded: Vec<String>,
    /// Output tags.
    pub outputs: Vec<TagRef>,
    /// Priority.
    pub priority: i64,
    /// Weight.
    pub weight: f64,
    /// Where the rule is.
    pub span: Span,
}

impl CRule {
    /// Whether the rule takes a shape whose tags (its tag and aliases) are `shape_tags`;
    /// `all` takes it unless it is a rig ([`crate::scene::Shape::rig`]).
    pub fn takes<'t>(
        &self,
        shape_tags: impl IntoIterator<Item = &'t str> + Clone,
        rig: bool,
    ) -> bool {
        takes_shape(&self.shape_tags, &self.shape_excluded, shape_tags, !rig)
    }

    /// Whether the rule names `tag` (or a pattern that matches it) among the shape tags it
    /// takes or leaves out; `all` names no tag.
    pub fn names_shape_tag(&self, tag: &str) -> bool {
        self.shape_tags
            .iter()
            .chain(&self.shape_excluded)
            .any(|t| t != "all" && tag_matches(t, tag))
    }
}

/// What rules can tell of a shape: the tags it answers to (its tag, then the aliases some
/// rule names) and whether it is a rig. Shapes with one key go through the same steps.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct MatchKey {
    /// Whether the shapes are rigs ([`crate::scene::Shape::rig`]), which `all` leaves out.
    pub rig: bool,
    /// The shape tag, then the aliases some rule names.
    pub tags: Vec<String>,
}

/// All rules of a grammar, checked: timeslice rules for [`super::expand`], spatial ones
/// kept aside for the group grammar.
#[derive(Clone, Debug)]
pub struct Program {
    /// Timeslice rules.
    pub rules: Vec<CRule>,
    /// Indices (in `Grammar::rules`) of spatial rules.
    pub spatial: Vec<usize>,
    by_slice_tag: HashMap<String, Vec<usize>>,
}

/// Operators of the timeslice grammar.
pub const TIME_OPERATORS: [&str; 2] = ["timesplit", "animate"];

fn keyword(e: &Expr) -> Option<&str> {
    match &e.kind {
        ExprKind::Ident(s) | ExprKind::Str(s) => Some(s),
        _ => None,
    }
}

fn named<'a>(args: &'a [Arg], name: &str) -> Option<&'a Arg> {
    args.iter().find(|a| a.name.as_deref() == Some(name))
}

impl Program {
    /// Checks every rule.
    pub fn new(grammar: &Grammar) -> Result<Program, EngineError> {
        let mut rules = Vec::new();
        let mut spatial = Vec::new();
        for (index, r) in grammar.rules.iter().enumerate() {
            if r.spatial {
                spatial.push(index);
                continue;
            }
            rules.push(check_rule(index, r)?);
        }
        check_slice_tags(grammar)?;
        let mut by_slice_tag: HashMap<String, Vec<usize>> = HashMap::new();
        for (i, r) in rules.iter().enumerate() {
            for t in &r.slice_tags {
                let v = by_slice_tag.entry(t.clone()).or_default();
                if !v.contains(&i) {
                    v.push(i);
                }
            }
        }
        Ok(Program {
            rules,
            spatial,
            by_slice_tag,
        })
    }

    /// Whether some rule names `tag` among its shape tags (see [`CRule::names_shape_tag`]):
    /// an alias no rule names cannot change what a shape does.
    pub fn names_shape_tag(&self, tag: &str) -> bool {
        self.rules.iter().any(|r| r.names_shape_tag(tag))
    }

    /// Rules whose tags match a slice tag (base name) on the shapes of match key `key`,
    /// highest priority only.
    pub fn candidates(&self, slice_tag: &str, key: &MatchKey) -> Vec<usize> {
        let Some(list) = self.by_slice_tag.get(slice_tag) else {
            return Vec::new();
        };
        let tags = key.tags.iter().map(String::as_str);
        let matching: Vec<usize> = list
            .iter()
            .copied()
            .filter(|&i| self.rules[i].takes(tags.clone(), key.rig))
            .collect();
        let Some(top) = matching.iter().map(|&i| self.rules[i].priority).max() else {
            return Vec::new();
        };
        matching
            .into_iter()
            .filter(|&i| self.rules[i].priority == top)
            .collect()
    }
}

fn positional(r: &Rule) -> Vec<&Arg> {
    r.args.iter().filter(|a| a.name.is_none()).collect()
}

pub(crate) fn check_rule(index: usize, r: &Rule) -> Result<CRule, EngineError> {
    let pos = positional(r);
    let op = match r.op.as_str() {
        "timesplit" => {
            if let Some(a) = r.args.iter().find(|a| a.name.is_some()) {
                return Err(EngineError::at(
                    a.span,
                    "`timesplit` takes no named arguments",
                ));
            }
            // The papers pass the fractions as one list: `timesplit({0.3, 0.4, 0.3})`.
            let fractions: Vec<Expr> = match pos.as_slice() {
                [list] => match &list.value.kind {
                    ExprKind::Tuple(items) => items.clone(),
                    _ => vec![list.value.clone()],
                },
                _ => pos.iter().map(|a| a.value.clone()).collect(),
            };
            if fractions.len() < 2 {
                return Err(EngineError::at(
                    r.op_span,
                    "`timesplit` needs at least two fractions",
                ));
            }
            if fractions.len() != r.outputs.len() {
                return Err(EngineError::at(
                    r.span,
                    format!(
                        "`timesplit` has {} fractions but {} output tags; they must match",
                        fractions.len(),
                        r.outputs.len()
                    ),
                ));
            }
            Op::Timesplit { fractions }
        }
        "animate" => {
            if pos.len() != 4 {
                return Err(EngineError::at(
                    r.op_span,
                    format!(
                        "`animate` takes 4 arguments (type, ref, offset, value), found {}",
                        pos.len()
                    ),
                ));
            }
            let written = keyword(&pos[0].value);
            let kind = written.and_then(AnimType::named).ok_or_else(|| {
                let names: Vec<_> = AnimType::ALL
                    .iter()
                    .map(|(n, _)| format!("`{n}`"))
                    .collect();
                let all = AnimType::ALL.iter().chain(&AnimType::PAPER_NAMES);
                EngineError::at(
                    pos[0].span,
                    format!(
                        "unknown animation type; expected one of {}",
                        names.join(", ")
                    ),
                )
                .suggesting(written, all.map(|(n, _)| *n))
            })?;
            // `single` and `global` are gMotion §3.1's names for the two references.
            let world = match keyword(&pos[1].value) {
                Some("world" | "global") => true,
                Some("local" | "single") => false,
                other => {
                    return Err(EngineError::at(
                        pos[1].span,
                        "the reference is `local` or `world`",
                    )
                    .suggesting(other, ["local", "world", "single", "global"]));
                }
            };
            if r.outputs.len() != 1 {
                return Err(EngineError::at(
                    r.span,
                    "`animate` has exactly one output tag",
                ));
            }
            for a in &r.args {
                if let Some(n) = &a.name
                    && !["ease", "grid", "lookup", "interp", "orient"].contains(&n.as_str())
                {
                    return Err(EngineError::at(
                        a.span,
                        format!(
                            "unknown argument `{n}`; `animate` accepts ease, grid, lookup, interp, orient"
                        ),
                    ));
                }
            }
            let grid = match named(&r.args, "grid") {
                Some(a) => Some(
                    super::settings::size_of(&a.value)
                        .ok_or_else(|| EngineError::at(a.span, super::settings::GRID_SIZE))?,
                ),
                None => None,
            };
            let lookup = match named(&r.args, "lookup") {
                Some(a) => Some(match keyword(&a.value) {
                    Some("nearest") => crate::motion::Lookup::Nearest,
                    Some("bilinear") => crate::motion::Lookup::Bilinear,
                    Some("exact") => crate::motion::Lookup::Exact,
                    Some("vertex") => crate::motion::Lookup::Vertex,
                    _ => {
                        return Err(EngineError::at(
                            a.span,
                            "lookup is one of nearest, bilinear, exact, vertex",
                        ));
                    }
                }),
                None => None,
            };
            let interp = match named(&r.args, "interp") {
                Some(a) => Some(match keyword(&a.value) {
                    Some("linear") => crate::motion::Interp::Linear,
                    Some("alexa") => crate::motion::Interp::Alexa,
                    _ => return Err(EngineError::at(a.span, "interp is `linear` or `alexa`")),
                }),
                None => None,
            };
            let orient = super::follow::orient(kind, named(&r.args, "orient"))?;
            Op::Animate(Box::new(Animate {
                kind,
                orient,
                world,
                offset: pos[2].value.clone(),
                value: pos[3].value.clone(),
                ease: named(&r.args, "ease").map(|a| a.value.clone()),
                grid,
                lookup,
                interp,
            }))
        }
        other => {
            return Err(EngineError::at(
                r.op_span,
                format!(
                    "unknown timeslice operator `{other}`; expected `timesplit` or `animate` (spatial operators take a single tag list)"
                ),
            )
            .suggesting(Some(other), TIME_OPERATORS));
        }
    };
    if r.slice_tags.is_empty() || r.shape_tags.is_empty() {
        return Err(EngineError::at(
            r.span,
            "a timeslice rule matches `[slice tags, shape tags]`",
        ));
    }
    if !(r.weight.is_finite() && r.weight > 0.0) {
        return Err(EngineError::at(r.span, "weight must be a positive number"));
    }
    Ok(CRule {
        index,
        op,
        slice_tags: r.slice_tags.iter().map(|t| t.name.clone()).collect(),
        shape_tags: r.shape_tags.iter().map(|t| t.name.clone()).collect(),
        shape_excluded: r.shape_excluded.iter().map(|t| t.name.clone()).collect(),
        outputs: r.outputs.clone(),
        priority: r.priority,
        weight: r.weight,
        span: r.span,
    })
}

/// Every slice tag a timeslice rule matches must be `all` or produced by some rule;
/// otherwise the rule can never apply, which is almost always a typo.
pub(crate) fn check_slice_tags(grammar: &Grammar) -> Result<(), EngineError> {
    let produced: Vec<&str> = std::iter::once("all")
        .chain(
            grammar
                .rules
                .iter()
                .filter(|r| !r.spatial)
                .flat_map(|r| r.outputs.iter().map(|t| t.name.as_str())),
        )
        .collect();
    for r in grammar.rules.iter().filter(|r| !r.spatial) {
        for t in &r.slice_tags {
            if !produced.contains(&t.name.as_str()) {
                let hint =
                    crate::grammar::diagnostics::did_you_mean(&t.name, produced.iter().copied())
                        .map(|m| format!(" (did you mean `{m}`?)"))
                        .unwrap_or_default();
                return Err(EngineError::at(
                    t.span,
                    format!(
                        "unknown slice tag `{}`: no rule produces it and it is not `all`{hint}",
                        t.name
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Every shape tag a rule names must be `all` or the tag of some shape in the scene.
/// `spatial` selects which rules are checked: the spatial ones (against the scene before
/// the group grammar runs) or the timeslice ones (against the scene it leaves).
pub fn check_shape_tags(
    grammar: &Grammar,
    scene_tags: &[&str],
    spatial: bool,
) -> Result<(), EngineError> {
    for r in grammar.rules.iter().filter(|r| r.spatial == spatial) {
        for t in r.shape_tags.iter().chain(&r.shape_excluded) {
            let known_tag = t.name == "all" || scene_tags.iter().any(|s| tag_matches(&t.name, s));
            if !known_tag {
                let hint =
                    crate::grammar::diagnostics::did_you_mean(&t.name, scene_tags.iter().copied())
                        .map(|m| format!(" (did you mean `{m}`?)"))
                        .unwrap_or_default();
                let mut known: Vec<&str> = scene_tags.to_vec();
                known.sort_unstable();
                known.dedup();
                let what = if t.name.contains('*') {
                    format!("no shape tag in the scene matches the pattern `{}`", t.name)
                } else {
                    format!(
                        "unknown shape tag `{}`: no shape in the scene has it{hint}",
                        t.name
                    )
                };
                let mut e = EngineError::at(t.span, what);
                e.notes
                    .push(format!("the scene's tags: {}", known.join(", ")));
                return Err(e);
            }
        }
    }
    Ok(())
}
