//! From a spatial rule's argument expressions to an [`Op`] with typed parameters, for one
//! shape: arguments are evaluated per shape, so `outline(2 + id % 3)` varies across a group.

use kurbo::{Affine, BezPath, Point, Rect};

use super::TangleError;
use super::boolean::normalize;
use super::noise::{Rng, perlin};
use super::ops::grouping::RegroupMode;
use super::ops::regular_split::{Curve, SplitParams};
use super::ops::stipple::{StippleKind, StippleParams};
use super::ops::text::TextSplit;
use super::ops::{Op, StreamKind};
use super::place::{PlaceParams, PlaceShape};
use super::polygon::{Grid, flatten_rings};
use crate::grammar::ast::{Arg, Rule, Span};
use crate::grammar::value::{Env, Value, eval, geometry_var};
use crate::scene::FillRule;

/// The variables a spatial rule's arguments can read, for one shape.
#[derive(Clone, Copy, Debug)]
pub struct ShapeVars {
    /// Id within the group (gTangle's s).
    pub sid: usize,
    /// Number of shapes the rule is applied to (the group's size).
    pub n: usize,
    /// Group id.
    pub group: usize,
    /// Area centroid.
    pub centroid: Point,
    /// Bounding box.
    pub bbox: Rect,
    /// Canvas size.
    pub canvas: (f64, f64),
    /// How many rules made the shape (0 for imported shapes): its own step count, which
    /// rules for other tags do not change.
    pub step: usize,
    /// Its line and word in the text it came from (`line_id`, `word_id`; 0 and 0 for a
    /// shape that did not come from text).
    pub text: (usize, usize),
}

/// The evaluation environment of one shape: its variables, its own random stream and the
/// expansion's noise field.
pub struct ShapeEnv {
    vars: ShapeVars,
    rng: Rng,
    noise_seed: u64,
}

/// Only the noise seed: the variables and the random stream's state are not worth printing.
impl std::fmt::Debug for ShapeEnv {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShapeEnv")
            .field("noise_seed", &self.noise_seed)
            .finish_non_exhaustive()
    }
}

impl ShapeEnv {
    /// An environment for `vars`, with draws from `key` and noise seeded by `noise_seed`.
    pub fn new(vars: ShapeVars, key: u64, noise_seed: u64) -> ShapeEnv {
        ShapeEnv {
            vars,
            rng: Rng::new(key),
            noise_seed,
        }
    }
}

impl Env for ShapeEnv {
    fn var(&self, name: &str) -> Option<f64> {
        let v = &self.vars;
        Some(match name {
            "id" => v.sid as f64,
            "n" => v.n as f64,
            "group" => v.group as f64,
            "step" => v.step as f64,
            "line_id" => v.text.0 as f64,
            "word_id" => v.text.1 as f64,
            _ => return geometry_var(name, v.centroid, v.bbox, v.canvas),
        })
    }

    fn rand(&mut self) -> f64 {
        self.rng.next_f64()
    }

    fn noise(&self, x: f64, y: f64) -> f64 {
        perlin(self.noise_seed, x, y)
    }
}

/// The spatial operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Ungroup,
    Regroup,
    RegularSplit,
    Outline,
    StreamlineSplit,
    Place,
    Fill,
    Stipple,
    Invert,
    Perturb,
    Text(TextSplit),
}

impl Kind {
    /// The operator a rule names (aliases included).
    fn of(name: &str) -> Option<Kind> {
        Some(match name {
            "ungroup" => Kind::Ungroup,
            "regroup" => Kind::Regroup,
            "regularSplit" => Kind::RegularSplit,
            "outline" => Kind::Outline,
            "streamlineSplit" => Kind::StreamlineSplit,
            "place" => Kind::Place,
            "fill" => Kind::Fill,
            // gTangle's Fig. 9 spells it `stipling`.
            "stipple" | "stippling" | "stipling" => Kind::Stipple,
            "invert" => Kind::Invert,
            "perturb" => Kind::Perturb,
            "letters" => Kind::Text(TextSplit::Letters),
            "words" => Kind::Text(TextSplit::Words),
            "lines" => Kind::Text(TextSplit::Lines),
            _ => return None,
        })
    }

    /// Its parameters, positional order first.
    fn params(self) -> &'static [&'static str] {
        match self {
            Kind::Ungroup | Kind::Invert | Kind::Text(_) => &[],
            Kind::Regroup => &["k", "mode"],
            Kind::RegularSplit => &["curve", "offsets", "dual", "angle"],
            Kind::Outline => &["d"],
            Kind::StreamlineSplit => &["type", "offset", "center"],
            Kind::Place => &["shape", "size", "distance"],
            Kind::Fill => &["color"],
            Kind::Stipple => &["kind", "density", "size"],
            Kind::Perturb => &["amplitude", "scale"],
        }
    }
}

/// Every spatial operator name, for error messages.
pub const OPERATORS: &str = "ungroup, regroup, regularSplit, outline, streamlineSplit, place, fill, stipple, invert, perturb, letters, words, lines";

/// A rule's arguments matched to its operator's parameters.
struct Args<'a> {
    rule: &'a Rule,
    slots: Vec<Option<&'a Arg>>,
    names: &'static [&'static str],
}

impl<'a> Args<'a> {
    fn new(
        rule: &'a Rule,
        op: &str,
        names: &'static [&'static str],
    ) -> Result<Args<'a>, TangleError> {
        let mut slots: Vec<Option<&Arg>> = vec![None; names.len()];
        let mut next = 0;
        for arg in &rule.args {
            let i = match &arg.name {
                None => {
                    let i = next;
                    next += 1;
                    if i >= names.len() {
                        let takes = if names.is_empty() {
                            "no arguments".to_string()
                        } else {
                            format!("at most {} arguments ({})", names.len(), names.join(", "))
                        };
                        return Err(TangleError::arg(arg.span, format!("`{op}` takes {takes}")));
                    }
                    i
                }
                Some(n) => names.iter().position(|p| p == n).ok_or_else(|| {
                    TangleError::arg(
                        arg.span,
                        format!(
                            "`{op}` has no parameter `{n}`; its parameters are {}",
                            names.join(", ")
                        ),
                    )
                })?,
            };
            if slots[i].is_some() {
                return Err(TangleError::arg(
                    arg.span,
                    format!("parameter `{}` given twice", names[i]),
                ));
            }
            slots[i] = Some(arg);
        }
        Ok(Args { rule, slots, names })
    }

    fn get(&self, name: &str) -> Option<&'a Arg> {
        self.names
            .iter()
            .position(|p| *p == name)
            .and_then(|i| self.slots[i])
    }

    fn value(&self, name: &str, env: &mut dyn Env) -> Result<Option<(Value, Span)>, TangleError> {
        let Some(arg) = self.get(name) else {
            return Ok(None);
        };
        let v = eval(&arg.value, env).map_err(|e| TangleError::arg(e.span, e.message))?;
        Ok(Some((v, arg.value.span)))
    }

    fn required(&self, name: &str, env: &mut dyn Env) -> Result<(Value, Span), TangleError> {
        self.value(name, env)?.ok_or_else(|| {
            TangleError::arg(
                self.rule.op_span,
                format!("`{}` needs its `{name}` argument", self.rule.op),
            )
        })
    }

    fn num(&self, name: &str, default: Option<f64>, env: &mut dyn Env) -> Result<f64, TangleError> {
        match (self.value(name, env)?, default) {
            (Some((v, span)), _) => v
                .as_num()
                .map_err(|e| TangleError::arg(span, e.to_string())),
            (None, Some(d)) => Ok(d),
            (None, None) => Err(TangleError::arg(
                self.rule.op_span,
                format!("`{}` needs its `{name}` argument", self.rule.op),
            )),
        }
    }

    fn keyword(
        &self,
        name: &str,
        default: &str,
        env: &mut dyn Env,
    ) -> Result<(String, Span), TangleError> {
        match self.value(name, env)? {
            Some((v, span)) => Ok((
                v.as_keyword()
                    .map_err(|e| TangleError::arg(span, e.to_string()))?
                    .to_string(),
                span,
            )),
            None => Ok((default.to_string(), self.rule.op_span)),
        }
    }
}

fn positive(v: f64, what: &str, span: Span) -> Result<f64, TangleError> {
    if v > 0.0 {
        Ok(v)
    } else {
        Err(TangleError::arg(
            span,
            format!("{what} must be positive, not {v}"),
        ))
    }
}

/// Path data flattened to its rings (in its own coordinates).
fn path_rings(data: &str, span: Span) -> Result<Vec<Vec<Point>>, TangleError> {
    let path = BezPath::from_svg(data)
        .map_err(|e| TangleError::arg(span, format!("bad path data: {e}")))?;
    let bb = kurbo::Shape::bounding_box(&path);
    let grid = Grid::for_bounds(bb)
        .ok_or_else(|| TangleError::arg(span, "path coordinates are not finite"))?;
    let tol = (bb.width().max(bb.height()) / 200.0).max(grid.quantum());
    Ok(flatten_rings(&path, Affine::IDENTITY, tol, &grid))
}

/// The open polyline of path data (its first subpath), for split curves.
fn path_polyline(data: &str, span: Span) -> Result<Vec<Point>, TangleError> {
    let path = BezPath::from_svg(data)
        .map_err(|e| TangleError::arg(span, format!("bad path data: {e}")))?;
    let bb = kurbo::Shape::bounding_box(&path);
    let tol = (bb.width().max(bb.height()) / 200.0).max(1e-6);
    // The first subpath only; a closing segment returns to its start.
    let mut pts: Vec<Point> = Vec::new();
    let mut done = false;
    kurbo::flatten(path, tol, |el| {
        if done {
            return;
        }
        match el {
            kurbo::PathEl::MoveTo(p) if pts.is_empty() => pts.push(p),
            kurbo::PathEl::LineTo(p) => pts.push(p),
            kurbo::PathEl::ClosePath => {
                if let Some(&first) = pts.first() {
                    pts.push(first);
                }
                done = true;
            }
            _ => done = !pts.is_empty(),
        }
    });
    if pts.len() < 2 {
        return Err(TangleError::arg(
            span,
            "the split curve needs at least two points",
        ));
    }
    Ok(pts)
}

/// Binds `rule`'s arguments for one shape.
///
/// # Errors
/// An unknown operator, a wrong argument (count, name, type or range), with its location.
pub fn bind(rule: &Rule, env: &mut dyn Env) -> Result<Op, TangleError> {
    let kind = Kind::of(&rule.op).ok_or_else(|| {
        if crate::engine::rules::TIME_OPERATORS.contains(&rule.op.as_str()) {
            // A timeslice operator written with one tag list: say what its lists are
            // rather than suggest the very name the user wrote.
            return TangleError::arg(
                rule.op_span,
                format!(
                    "`{}` is a timeslice operator: it matches a timeslice and shapes, \
                     `[SLICE, SHAPES]` (`[all, {}]` for a shape's whole timeline); \
                     a single tag list is a spatial rule's",
                    rule.op,
                    rule.shape_tags
                        .first()
                        .map_or("SHAPES", |t| t.name.as_str())
                ),
            );
        }
        let names = OPERATORS
            .split(", ")
            .chain(crate::engine::rules::TIME_OPERATORS);
        let hint = crate::grammar::diagnostics::did_you_mean(&rule.op, names)
            .map(|close| format!(" (did you mean `{close}`?)"))
            .unwrap_or_default();
        TangleError::arg(
            rule.op_span,
            format!(
                "unknown spatial operator `{}`; expected one of {OPERATORS}{hint}",
                rule.op
            ),
        )
    })?;
    let op = rule.op.as_str();
    let a = Args::new(rule, op, kind.params())?;
    Ok(match kind {
        Kind::Ungroup => Op::Ungroup,
        Kind::Invert => Op::Invert,
        Kind::Text(split) => Op::Text(split),
        Kind::Regroup => {
            let (k, span) = a.required("k", env)?;
            let k = k
                .as_num()
                .map_err(|e| TangleError::arg(span, e.to_string()))?;
            if !(k >= 1.0 && k.fract() == 0.0) {
                return Err(TangleError::arg(
                    span,
                    format!("regroup needs a whole number of groups ≥ 1, not {k}"),
                ));
            }
            let (mode, span) = a.keyword("mode", "id", env)?;
            let mode = RegroupMode::from_name(&mode).ok_or_else(|| {
                TangleError::arg(span, format!("unknown regroup mode `{mode}`; expected id, chessboard, columns, rows or random"))
            })?;
            Op::Regroup {
                k: k as usize,
                mode,
            }
        }
        Kind::RegularSplit => {
            let (curve, span) = a.required("curve", env)?;
            let curve = match &curve {
                Value::Keyword(k) if k == "line" => Curve::Line,
                Value::Str(s) => Curve::Polyline(path_polyline(s, span)?),
                other => {
                    return Err(TangleError::arg(
                        span,
                        format!(
                            "expected `line` or path data such as \"M0 0 L5 3 L10 0\", found {}",
                            other.describe()
                        ),
                    ));
                }
            };
            let (offsets, span) = a.required("offsets", env)?;
            let offsets = match &offsets {
                Value::Num(v) => vec![*v],
                Value::Point(p) => vec![p.x, p.y],
                Value::Str(s) => s
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .filter(|t| !t.is_empty())
                    .map(|t| {
                        t.parse::<f64>()
                            .map_err(|_| TangleError::arg(span, format!("`{t}` is not a number")))
                    })
                    .collect::<Result<Vec<f64>, _>>()?,
                other => {
                    return Err(TangleError::arg(
                        span,
                        format!(
                            "expected an offset, two offsets `(a, b)` or a list \"a b c\", found {}",
                            other.describe()
                        ),
                    ));
                }
            };
            if offsets.is_empty() {
                return Err(TangleError::arg(
                    span,
                    "regularSplit needs at least one offset",
                ));
            }
            for &o in &offsets {
                positive(o, "an offset", span)?;
            }
            let dual = match a.value("dual", env)? {
                None => false,
                Some((Value::Num(v), _)) => v != 0.0,
                Some((Value::Keyword(k), _)) if k == "true" || k == "dual" => true,
                Some((Value::Keyword(k), _)) if k == "false" => false,
                Some((v, span)) => {
                    return Err(TangleError::arg(
                        span,
                        format!("expected 0 or 1 for `dual`, found {}", v.describe()),
                    ));
                }
            };
            let angle = a.num("angle", Some(0.0), env)?;
            Op::RegularSplit {
                params: SplitParams {
                    curve,
                    offsets,
                    dual,
                },
                angle,
            }
        }
        Kind::Outline => {
            let (d, span) = a.required("d", env)?;
            let d = d
                .as_num()
                .map_err(|e| TangleError::arg(span, e.to_string()))?;
            Op::Outline {
                distance: positive(d, "the outline distance", span)?,
            }
        }
        Kind::StreamlineSplit => {
            let (kind, span) = a.keyword("type", "outline", env)?;
            let center = match a.value("center", env)? {
                None => None,
                Some((v, span)) => Some(
                    v.as_point()
                        .map_err(|e| TangleError::arg(span, e.to_string()))?,
                ),
            };
            let kind = match kind.as_str() {
                "outline" | "smooth" => StreamKind::Outline,
                "strip" => StreamKind::Strip,
                "circular" => StreamKind::Circular(center),
                other => {
                    return Err(TangleError::arg(
                        span,
                        format!(
                            "unknown streamline field `{other}`; expected outline, strip or circular"
                        ),
                    ));
                }
            };
            let (o, span) = a.required("offset", env)?;
            let o = o
                .as_num()
                .map_err(|e| TangleError::arg(span, e.to_string()))?;
            Op::StreamlineSplit {
                kind,
                spacing: positive(o, "the streamline offset", span)?,
            }
        }
        Kind::Place => {
            let (shape, size, distance) = match a.value("shape", env)? {
                // `place(20, 25)` as in gTangle's Fig. 9: circles of size 20, 25 apart.
                Some((Value::Num(size), size_span)) => {
                    let (d, span) = a.required("size", env)?;
                    let d = d
                        .as_num()
                        .map_err(|e| TangleError::arg(span, e.to_string()))?;
                    if let Some(extra) = a.get("distance") {
                        return Err(TangleError::arg(
                            extra.span,
                            "`place(size, distance)` takes no third argument; name the shape first: place(circle, size, distance)",
                        ));
                    }
                    (
                        PlaceShape::Circle,
                        positive(size, "the size", size_span)?,
                        positive(d, "the distance", span)?,
                    )
                }
                shape => {
                    let shape = match shape {
                        None => PlaceShape::Circle,
                        Some((Value::Keyword(k), _)) if k == "circle" => PlaceShape::Circle,
                        Some((Value::Keyword(k), _)) if k == "square" => PlaceShape::Square,
                        Some((Value::Str(s), span)) => {
                            let rings = path_rings(&s, span)?;
                            let bb = super::polygon::bbox_of(rings.iter().flatten().copied());
                            let grid = Grid::for_bounds(bb).ok_or_else(|| {
                                TangleError::arg(span, "path coordinates are not finite")
                            })?;
                            let region = normalize(&rings, FillRule::NonZero, &grid);
                            if region.area() <= 0.0 {
                                return Err(TangleError::arg(
                                    span,
                                    "the placed path encloses no area",
                                ));
                            }
                            PlaceShape::Path(region)
                        }
                        Some((other, span)) => {
                            return Err(TangleError::arg(
                                span,
                                format!(
                                    "expected circle, square or path data, found {}",
                                    other.describe()
                                ),
                            ));
                        }
                    };
                    let span_of = |n: &str| a.get(n).map_or(rule.op_span, |x| x.value.span);
                    let size = positive(a.num("size", None, env)?, "the size", span_of("size"))?;
                    let distance = positive(
                        a.num("distance", None, env)?,
                        "the distance",
                        span_of("distance"),
                    )?;
                    (shape, size, distance)
                }
            };
            Op::Place(PlaceParams {
                shape,
                size,
                distance,
            })
        }
        Kind::Fill => {
            let (c, span) = a.required("color", env)?;
            Op::Fill(
                c.as_color()
                    .map_err(|e| TangleError::arg(span, e.to_string()))?,
            )
        }
        Kind::Stipple => {
            let (kind, span) = a.keyword("kind", "dots", env)?;
            let kind = match kind.as_str() {
                "dots" => StippleKind::Dots,
                "dashes" => StippleKind::Dashes,
                "curves" => StippleKind::Curves,
                other => {
                    return Err(TangleError::arg(
                        span,
                        format!("unknown stipple `{other}`; expected dots, dashes or curves"),
                    ));
                }
            };
            let density = a.num("density", Some(1.0), env)?;
            let size = a.num("size", Some(1.0), env)?;
            let span = rule.op_span;
            Op::Stipple(StippleParams {
                kind,
                density: positive(density, "the density", span)?,
                size: positive(size, "the size", span)?,
            })
        }
        Kind::Perturb => {
            let amplitude = a.num("amplitude", None, env)?;
            let scale = a.num("scale", None, env)?;
            if amplitude < 0.0 {
                return Err(TangleError::arg(
                    rule.op_span,
                    "the amplitude must not be negative",
                ));
            }
            Op::Perturb {
                amplitude,
                scale: positive(scale, "the scale", rule.op_span)?,
            }
        }
    })
}
