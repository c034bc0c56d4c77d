//! Header directives turned into typed settings, with defaults and validation.

use crate::canvas::MAX_OUTPUT_SIZE;
use crate::grammar::ast::{Directive, ExprKind, Grammar, Span};
use crate::grammar::value::{Env, Value, eval};
use crate::motion::{Interp, Lookup};
use crate::tagging::{TagFrom, Units};

use super::EngineError;

/// How a rule is chosen among the candidates of one expansion step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Choice {
    /// One draw per step for every matched slice (the paper's expansion).
    #[default]
    Group,
    /// One draw per shape, so shapes of one tag vary.
    Shape,
}

/// Everything the header can set.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Animation length in seconds.
    pub duration: f64,
    /// Whether the grammar sets `duration` (else a scene with a time of its own, a Lottie
    /// composition, lasts as long as that).
    pub duration_given: bool,
    /// Frames per second.
    pub fps: f64,
    /// Whether the grammar sets `fps` (else a Lottie scene runs at its own rate).
    pub fps_given: bool,
    /// When a Lottie scene's units are measured (`reference_time`), in seconds, and where
    /// it is written.
    pub reference_time: Option<(f64, Span)>,
    /// Default grid columns × rows × keyframes in time (gMotion's n×m×p).
    pub grid: (usize, usize, usize),
    /// Random seed.
    pub seed: u64,
    /// Scene file named by the grammar, as written (callers resolve it relative to the
    /// grammar file), and where it is written.
    pub scene: Option<(String, Span)>,
    /// Width in pixels of every output; `None` follows `height` and the scene's aspect
    /// ratio, or is the scene's own width (see [`crate::canvas::OutputSize`]).
    pub width: Option<u32>,
    /// Height in pixels of every output; `None` follows `width` and the scene's aspect
    /// ratio, or is the scene's own height.
    pub height: Option<u32>,
    /// Grid lookup.
    pub lookup: Lookup,
    /// Temporal interpolation of transforms.
    pub interp: Interp,
    /// Whether the animation loops.
    pub looping: bool,
    /// Expansion bound.
    pub max_steps: usize,
    /// Rule choice granularity.
    pub choice: Choice,
    /// Where the importer reads tags from, if the grammar says.
    pub tag_from: Option<TagFrom>,
    /// Which nodes the importer makes animated units, if the grammar says.
    pub units: Option<Units>,
    /// How deep a group must sit to become a unit, if the grammar says (`unit_depth`).
    pub unit_depth: Option<usize>,
    /// Tag map file named by the grammar (`tags`), as written (callers resolve it relative
    /// to the grammar file), and where it is written.
    pub tags: Option<(String, Span)>,
    /// The `smoothing` directive's value, if any.
    pub smoothing: Option<(Value, Span)>,
    /// The slice tags written as markers (`markers`), each with where it is written.
    pub markers: Vec<(String, Span)>,
    /// The properties given Lottie slots (`slots`).
    pub slots: super::slots::SlotKinds,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            duration: 5.0,
            duration_given: false,
            fps: 30.0,
            fps_given: false,
            reference_time: None,
            grid: (1, 1, 2),
            seed: 0,
            scene: None,
            width: None,
            height: None,
            lookup: Lookup::Nearest,
            interp: Interp::Linear,
            looping: true,
            max_steps: 10_000,
            choice: Choice::Group,
            tag_from: None,
            units: None,
            unit_depth: None,
            tags: None,
            smoothing: None,
            markers: Vec::new(),
            slots: Default::default(),
        }
    }
}

/// An environment without a shape: no variable is known, `rand()` and `noise` give fixed
/// values. Directives need no shape variables (randomness in them is an error), and
/// `gmotion check` evaluates a rule's shape-independent values with it.
pub(crate) struct NoShape;

impl Env for NoShape {
    fn var(&self, _: &str) -> Option<f64> {
        None
    }
    fn rand(&mut self) -> f64 {
        0.5
    }
    fn noise(&self, _: f64, _: f64) -> f64 {
        0.0
    }
}

fn one(d: &Directive) -> Result<&crate::grammar::ast::Expr, EngineError> {
    match d.values.as_slice() {
        [v] => Ok(v),
        _ => Err(EngineError::at(
            d.span,
            format!("`{}` takes exactly one value", d.name),
        )),
    }
}

fn num(d: &Directive) -> Result<f64, EngineError> {
    let e = one(d)?;
    let v = eval(e, &mut NoShape).map_err(EngineError::from)?;
    super::finite_number(&v, e.span, |_| {
        format!("`{}` must be a finite number", d.name)
    })
}

fn positive(d: &Directive) -> Result<f64, EngineError> {
    let x = num(d)?;
    if x <= 0.0 {
        return Err(EngineError::at(
            d.span,
            format!("`{}` must be greater than zero, found {x}", d.name),
        ));
    }
    Ok(x)
}

/// An output size in whole pixels, 1 to [`MAX_OUTPUT_SIZE`].
fn pixels(d: &Directive) -> Result<u32, EngineError> {
    let x = positive(d)?;
    if x.fract() != 0.0 || x > f64::from(MAX_OUTPUT_SIZE) {
        return Err(EngineError::at(
            one(d)?.span,
            format!(
                "`{}` must be a whole number of pixels from 1 to {MAX_OUTPUT_SIZE}, found {x}",
                d.name
            ),
        ));
    }
    Ok(x as u32)
}

fn word(d: &Directive) -> Result<String, EngineError> {
    let e = one(d)?;
    match &e.kind {
        ExprKind::Ident(s) | ExprKind::Str(s) => Ok(s.clone()),
        ExprKind::Num(x) => Ok(x.to_string()),
        _ => Err(EngineError::at(
            e.span,
            format!("`{}` expects a word", d.name),
        )),
    }
}

fn choose<T: Copy>(d: &Directive, options: &[(&str, T)]) -> Result<T, EngineError> {
    let w = word(d)?;
    options
        .iter()
        .find(|(n, _)| *n == w)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<_> = options.iter().map(|(n, _)| format!("`{n}`")).collect();
            // The value is what is wrong: point at it (the parser does too).
            let at = d.values.first().map_or(d.span, |v| v.span);
            EngineError::at(
                at,
                format!(
                    "`{}`: unknown value `{w}`, expected one of {}",
                    d.name,
                    names.join(", ")
                ),
            )
        })
}

/// Reads every directive of `grammar` into settings.
pub fn from_grammar(grammar: &Grammar) -> Result<Settings, EngineError> {
    let mut s = Settings::default();
    for d in &grammar.directives {
        match d.name.as_str() {
            "duration" => {
                s.duration = positive(d)?;
                s.duration_given = true;
            }
            "fps" => {
                s.fps = positive(d)?;
                s.fps_given = true;
            }
            "reference_time" => {
                let x = num(d)?;
                if x < 0.0 {
                    return Err(EngineError::at(
                        d.span,
                        format!("`reference_time` cannot be negative, found {x}"),
                    ));
                }
                s.reference_time = Some((x, one(d)?.span));
            }
            "seed" => {
                let x = num(d)?;
                if x < 0.0 || x.fract() != 0.0 {
                    return Err(EngineError::at(
                        d.span,
                        "`seed` must be a non-negative integer",
                    ));
                }
                s.seed = x as u64;
            }
            "grid" => s.grid = grid_size(d)?,
            "scene" => s.scene = Some((word(d)?, one(d)?.span)),
            "tags" => s.tags = Some((word(d)?, one(d)?.span)),
            "markers" => {
                for v in &d.values {
                    if let ExprKind::Ident(name) = &v.kind
                        && !s.markers.iter().any(|(m, _)| m == name)
                    {
                        s.markers.push((name.clone(), v.span));
                    }
                }
            }
            "slots" => {
                for v in &d.values {
                    let ExprKind::Ident(word) = &v.kind else {
                        return Err(EngineError::at(
                            v.span,
                            "`slots` takes fill, stroke, opacity",
                        ));
                    };
                    s.slots = s.slots.with(word).ok_or_else(|| {
                        EngineError::at(v.span, "`slots` takes fill, stroke, opacity")
                    })?;
                }
            }
            "unit_depth" => s.unit_depth = Some(positive(d)?.round() as usize),
            "width" => s.width = Some(pixels(d)?),
            "height" => s.height = Some(pixels(d)?),
            "lookup" => {
                s.lookup = choose(
                    d,
                    &[
                        ("nearest", Lookup::Nearest),
                        ("bilinear", Lookup::Bilinear),
                        ("exact", Lookup::Exact),
                        ("vertex", Lookup::Vertex),
                    ],
                )?
            }
            "interp" => {
                s.interp = choose(d, &[("linear", Interp::Linear), ("alexa", Interp::Alexa)])?
            }
            "loop" => {
                s.looping = choose(
                    d,
                    &[
                        ("true", true),
                        ("false", false),
                        ("yes", true),
                        ("no", false),
                    ],
                )?
            }
            "max_steps" => s.max_steps = positive(d)?.round() as usize,
            "choice" => {
                s.choice = choose(d, &[("group", Choice::Group), ("shape", Choice::Shape)])?
            }
            "tag_from" => {
                s.tag_from = Some(choose(
                    d,
                    &[
                        ("auto", TagFrom::Auto),
                        ("data-tag", TagFrom::DataTag),
                        ("class", TagFrom::Class),
                        ("label", TagFrom::Label),
                        ("layer", TagFrom::Layer),
                    ],
                )?)
            }
            "units" => {
                s.units = Some(choose(
                    d,
                    &[
                        ("auto", Units::Auto),
                        ("paths", Units::Paths),
                        ("groups", Units::Groups),
                    ],
                )?)
            }
            "smoothing" => {
                let e = one(d)?;
                s.smoothing = Some((eval(e, &mut NoShape).map_err(EngineError::from)?, e.span));
            }
            other => {
                return Err(EngineError::at(
                    d.span,
                    format!("unknown directive `{other}`"),
                ));
            }
        }
    }
    Ok(s)
}

/// A grid size from `4x4`, `4x4x3` or a single number.
pub fn grid_size(d: &Directive) -> Result<(usize, usize, usize), EngineError> {
    let e = one(d)?;
    size_of(e).ok_or_else(|| EngineError::at(e.span, GRID_SIZE))
}

/// How a grid size is written, for errors.
pub const GRID_SIZE: &str = "a grid size is written `NxM` (N, M from 1 to 4096) or `NxMxP` with P keyframes in time (2 to 64), e.g. `4x4` or `1x1x5`";

/// The most keyframes in time a grid may have.
pub const MAX_KEYS: usize = 64;

/// A grid size expression (`4x4`, `4x4x3`), if it is one: columns, rows, keyframes.
pub fn size_of(e: &crate::grammar::ast::Expr) -> Option<(usize, usize, usize)> {
    let side = |a: u32| (1..=4096).contains(&a);
    match &e.kind {
        ExprKind::Size(a, b, p) if side(*a) && side(*b) && (2..=MAX_KEYS as u32).contains(p) => {
            Some((*a as usize, *b as usize, *p as usize))
        }
        ExprKind::Num(n) if *n >= 1.0 && n.fract() == 0.0 && *n <= 4096.0 => {
            Some((*n as usize, *n as usize, 2))
        }
        _ => None,
    }
}
