//! Expression evaluation: what an operator argument is worth for one shape.
//!
//! The engine evaluates each argument once per matched shape with an [`Env`] that supplies
//! the shape's variables (`id`, `cx`, …), its random stream and a noise field, then reads
//! the [`Value`] with the accessor for the type it needs (`as_num`, `as_color`, …). Errors
//! carry the span of the offending sub-expression, so the CLI can put a caret under it.

use std::fmt;

use kurbo::{Affine, Point, Vec2};

use super::ast::{Arg, BinOp, Expr, ExprKind, Span};
use super::diagnostics::Diagnostic;
use crate::color::Color;
use crate::motion::Component;

/// The value of an expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number (units already folded in: seconds, degrees, fractions for `%`).
    Num(f64),
    /// A string (path data, file names).
    Str(String),
    /// A colour.
    Color(Color),
    /// A point, from a tuple `(x, y)` or `point(x, y)`.
    Point(Point),
    /// A product of transform components, leftmost applied last (as in SVG).
    Transform(Vec<Component>),
    /// A name that is neither a variable nor a constant (`affine`, `world`, `ease-in`,
    /// `red`); the operator decides what it means.
    Keyword(String),
    /// A call to a function the evaluator does not know (`cubic(0.4, 0, 0.2, 1)`,
    /// `spring(0.3, 0.1)`), with its arguments evaluated.
    Call {
        /// Function name.
        name: String,
        /// Evaluated arguments.
        args: Vec<Value>,
    },
    /// A grid size `NxM` or `NxMxP` (columns, rows, keyframes in time).
    Size(u32, u32, u32),
}

/// What the evaluator needs from the engine: the shape's variables, randomness and noise.
pub trait Env {
    /// The value of variable `name` for the current shape, if it is one.
    fn var(&self, name: &str) -> Option<f64>;
    /// A uniform draw in `[0, 1)`; each call is a new draw.
    fn rand(&mut self) -> f64;
    /// Coherent noise at `(x, y)`, in `[-1, 1]`.
    fn noise(&self, x: f64, y: f64) -> f64;
}

/// Every variable a rule's expressions may name, in the timeslice or the group grammar
/// (`u` only in a motion keyed in time; `k` and `count` only in the timeslice grammar), and the constant `pi`: a `let` cannot rename them.
pub const VARIABLES: &[&str] = &[
    "id", "n", "k", "count", "cx", "cy", "w", "h", "x0", "y0", "z", "group", "t0", "d", "step",
    "W", "H", "u", "pi", "line_id", "word_id",
];

/// The variables every shape has from its geometry: `cx`, `cy` (centroid), `w`, `h`,
/// `x0`, `y0` (bounding box), `W`, `H` (the canvas). Shared by the timeslice and the group
/// grammars' environments so the two cannot drift apart.
pub fn geometry_var(
    name: &str,
    centroid: kurbo::Point,
    bbox: kurbo::Rect,
    canvas: (f64, f64),
) -> Option<f64> {
    Some(match name {
        "cx" => centroid.x,
        "cy" => centroid.y,
        "w" => bbox.width(),
        "h" => bbox.height(),
        "x0" => bbox.x0,
        "y0" => bbox.y0,
        "W" => canvas.0,
        "H" => canvas.1,
        _ => return None,
    })
}

/// An error while evaluating an expression, at the sub-expression that caused it.
#[derive(Clone, Debug, PartialEq)]
pub struct EvalError {
    /// The offending sub-expression.
    pub span: Span,
    /// What is wrong.
    pub message: String,
    /// How to fix it, when there is an obvious fix.
    pub help: Option<String>,
}

impl EvalError {
    /// An error at `span`.
    pub fn new(span: Span, message: impl Into<String>) -> EvalError {
        EvalError {
            span,
            message: message.into(),
            help: None,
        }
    }

    fn with_help(mut self, help: impl Into<String>) -> EvalError {
        self.help = Some(help.into());
        self
    }
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.span.line, self.span.col, self.message)
    }
}

impl std::error::Error for EvalError {}

impl From<EvalError> for Diagnostic {
    fn from(e: EvalError) -> Diagnostic {
        Diagnostic {
            span: e.span,
            message: e.message,
            expected: Vec::new(),
            help: e.help,
        }
    }
}

/// A value of the wrong type: "expected a number, found a colour".
#[derive(Clone, Debug, PartialEq)]
pub struct TypeError {
    /// What was needed, with its article ("a number").
    pub expected: &'static str,
    /// What was there (see [`Value::describe`]).
    pub found: String,
}

impl TypeError {
    /// This error located at `span` (the expression the value came from).
    pub fn at(self, span: Span) -> EvalError {
        EvalError::new(span, self.to_string())
    }
}

impl fmt::Display for TypeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expected {}, found {}", self.expected, self.found)
    }
}

impl std::error::Error for TypeError {}

impl Value {
    /// How the value is named in messages: "a number", "the keyword `world`", ….
    pub fn describe(&self) -> String {
        match self {
            Value::Num(_) => "a number".into(),
            Value::Str(_) => "a string".into(),
            Value::Color(_) => "a colour".into(),
            Value::Point(_) => "a point".into(),
            Value::Transform(_) => "a transform".into(),
            Value::Keyword(k) => format!("the name `{k}`"),
            Value::Call { name, .. } => format!("a call to `{name}`"),
            Value::Size(..) => "a size".into(),
        }
    }

    fn mismatch(&self, expected: &'static str) -> TypeError {
        TypeError {
            expected,
            found: self.describe(),
        }
    }

    /// The number.
    pub fn as_num(&self) -> Result<f64, TypeError> {
        match self {
            Value::Num(v) => Ok(*v),
            _ => Err(self.mismatch("a number")),
        }
    }

    /// The colour; a keyword or string that names a colour (`red`, `"#f80"`) counts too.
    pub fn as_color(&self) -> Result<Color, TypeError> {
        match self {
            Value::Color(c) => Ok(*c),
            Value::Keyword(s) | Value::Str(s) => {
                Color::parse(s).ok_or_else(|| self.mismatch("a colour"))
            }
            _ => Err(self.mismatch("a colour")),
        }
    }

    /// The point.
    pub fn as_point(&self) -> Result<Point, TypeError> {
        match self {
            Value::Point(p) => Ok(*p),
            _ => Err(self.mismatch("a point")),
        }
    }

    /// The transform components, leftmost applied last.
    pub fn as_transform(&self) -> Result<&[Component], TypeError> {
        match self {
            Value::Transform(cs) => Ok(cs),
            _ => Err(self.mismatch("a transform")),
        }
    }

    /// The keyword; a string counts too, so the papers' `animate("affine", "world", …)`
    /// reads the same as `animate(affine, world, …)`.
    pub fn as_keyword(&self) -> Result<&str, TypeError> {
        match self {
            Value::Keyword(k) | Value::Str(k) => Ok(k),
            _ => Err(self.mismatch("a name")),
        }
    }

    /// The string.
    pub fn as_str(&self) -> Result<&str, TypeError> {
        match self {
            Value::Str(s) => Ok(s),
            _ => Err(self.mismatch("a string")),
        }
    }

    /// The call's name and arguments; a bare keyword counts as a call without arguments,
    /// so `ease-in` and `ease-in()` read the same.
    pub fn as_call(&self) -> Result<(&str, &[Value]), TypeError> {
        match self {
            Value::Call { name, args } => Ok((name, args)),
            Value::Keyword(k) => Ok((k, &[])),
            _ => Err(self.mismatch("a function such as `cubic(0.4, 0, 0.2, 1)`")),
        }
    }

    /// The size (columns, rows, keyframes in time).
    pub fn as_size(&self) -> Result<(u32, u32, u32), TypeError> {
        match self {
            Value::Size(c, r, p) => Ok((*c, *r, *p)),
            _ => Err(self.mismatch("a size such as `4x4`")),
        }
    }

    /// True when every number in the value is finite.
    fn is_finite(&self) -> bool {
        match self {
            Value::Num(v) => v.is_finite(),
            Value::Point(p) => p.is_finite(),
            Value::Transform(cs) => cs.iter().all(Component::is_finite),
            Value::Call { args, .. } => args.iter().all(Value::is_finite),
            Value::Str(_) | Value::Color(_) | Value::Keyword(_) | Value::Size(..) => true,
        }
    }
}

/// Evaluates `expr` for the shape `env` describes.
pub fn eval(expr: &Expr, env: &mut dyn Env) -> Result<Value, EvalError> {
    let span = expr.span;
    let value = match &expr.kind {
        ExprKind::Num(v) => Value::Num(*v),
        ExprKind::Str(s) => Value::Str(s.clone()),
        ExprKind::Color(c) => Value::Color(*c),
        ExprKind::Size(c, r, p) => Value::Size(*c, *r, *p),
        ExprKind::Ident(name) => ident(name, span, env)?,
        ExprKind::Call { name, args } => call(name, args, span, env)?,
        ExprKind::Tuple(items) => {
            let [x, y] = items.as_slice() else {
                return Err(EvalError::new(
                    span,
                    format!("a point has two coordinates, found {}", items.len()),
                ));
            };
            Value::Point(Point::new(num(x, env)?, num(y, env)?))
        }
        ExprKind::Neg(inner) => match eval(inner, env)? {
            Value::Num(v) => Value::Num(-v),
            Value::Point(p) => Value::Point(Point::new(-p.x, -p.y)),
            other => {
                return Err(EvalError::new(
                    span,
                    format!("cannot negate {}", other.describe()),
                ));
            }
        },
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (eval(lhs, env)?, eval(rhs, env)?);
            binary(*op, a, b, span, rhs.span)?
        }
    };
    if value.is_finite() {
        Ok(value)
    } else {
        Err(EvalError::new(span, "the result is not a finite number"))
    }
}

/// Evaluates `expr` and reads it as a number.
fn num(expr: &Expr, env: &mut dyn Env) -> Result<f64, EvalError> {
    if let Some(x) = arithmetic(expr, env) {
        return Ok(x);
    }
    eval(expr, env)?.as_num().map_err(|e| e.at(expr.span))
}

/// `expr` by the arithmetic-only route: numbers, variables, `pi`, unary minus, the
/// binary operators on numbers and the numeric functions (`noise`, `floor`, `min`, …) on
/// positional numbers, each step computed exactly as [`eval`] computes it. `None` when the
/// expression needs [`eval`]: `rand`, any other call, a tuple, a name that is not a
/// variable, division by zero, an argument a function refuses, a result that is not finite.
/// It has no side effects (no `rand()` draws), so [`eval`] can then start over and give the
/// value or the located error. Per-shape expressions such as `0.01 * (id % 30)` or
/// `noise(floor(cx / 64), 0)` are evaluated for every shape at every step; this route
/// skips building and matching [`Value`]s for them.
pub fn arithmetic(expr: &Expr, env: &dyn Env) -> Option<f64> {
    let x = match &expr.kind {
        ExprKind::Num(v) => *v,
        ExprKind::Ident(name) if name == "pi" => std::f64::consts::PI,
        ExprKind::Ident(name) => env.var(name)?,
        ExprKind::Neg(inner) => -arithmetic(inner, env)?,
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (arithmetic(lhs, env)?, arithmetic(rhs, env)?);
            match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div | BinOp::Rem if b == 0.0 => return None,
                BinOp::Div => a / b,
                BinOp::Rem => a - b * (a / b).floor(),
                BinOp::Pow => a.powf(b),
            }
        }
        ExprKind::Call { name, args } => numeric_call(name, args, env)?,
        _ => return None,
    };
    x.is_finite().then_some(x)
}

/// A numeric function of [`call`] by the arithmetic route: the same arithmetic on the same
/// numbers, `None` wherever [`call`] would build anything else or refuse (a named argument,
/// a wrong count, a square root of a negative number, reversed clamp bounds, …).
fn numeric_call(name: &str, args: &[Arg], env: &dyn Env) -> Option<f64> {
    let arg = |i: usize| -> Option<f64> {
        let a = args.get(i)?;
        if a.name.is_some() {
            return None;
        }
        arithmetic(&a.value, env)
    };
    let n = args.len();
    let one = || if n == 1 { arg(0) } else { None };
    Some(match name {
        "noise" if n == 2 => env.noise(arg(0)?, arg(1)?),
        "sin" => one()?.sin(),
        "cos" => one()?.cos(),
        "tan" => one()?.tan(),
        "rad" => one()?.to_radians(),
        "abs" => one()?.abs(),
        "floor" => one()?.floor(),
        "ceil" => one()?.ceil(),
        "round" => one()?.round(),
        "exp" => one()?.exp(),
        "sqrt" => {
            let x = one()?;
            (x >= 0.0).then(|| x.sqrt())?
        }
        "ln" => {
            let x = one()?;
            (x > 0.0).then(|| x.ln())?
        }
        "pow" if n == 2 => arg(0)?.powf(arg(1)?),
        "min" | "max" if n >= 1 => {
            let pick = if name == "min" { f64::min } else { f64::max };
            let mut acc = arg(0)?;
            for i in 1..n {
                acc = pick(acc, arg(i)?);
            }
            acc
        }
        "clamp" if n == 3 => {
            let (x, lo, hi) = (arg(0)?, arg(1)?, arg(2)?);
            (lo <= hi).then(|| x.clamp(lo, hi))?
        }
        _ => return None,
    })
}

/// A variable, `pi`, or else a keyword.
fn ident(name: &str, span: Span, env: &mut dyn Env) -> Result<Value, EvalError> {
    if name == "pi" {
        return Ok(Value::Num(std::f64::consts::PI));
    }
    if let Some(v) = env.var(name) {
        return Ok(Value::Num(v));
    }
    // `w-h` lexes as one name (names may contain `-` before a letter); when every piece is a
    // variable the writer almost surely meant a subtraction.
    if name.contains('-')
        && name
            .split('-')
            .all(|part| part == "pi" || env.var(part).is_some())
    {
        let spaced = name.replace('-', " - ");
        return Err(EvalError::new(
            span,
            format!("`{name}` is read as one name, not a subtraction"),
        )
        .with_help(format!("put spaces around `-` to subtract: `{spaced}`")));
    }
    Ok(Value::Keyword(name.to_string()))
}

fn binary(op: BinOp, a: Value, b: Value, span: Span, rhs_span: Span) -> Result<Value, EvalError> {
    use Value::{Num, Point as P, Str, Transform as T};
    let value = match (op, a, b) {
        (BinOp::Add, Num(x), Num(y)) => Num(x + y),
        (BinOp::Sub, Num(x), Num(y)) => Num(x - y),
        (BinOp::Mul, Num(x), Num(y)) => Num(x * y),
        (BinOp::Div | BinOp::Rem, Num(_), Num(0.0)) => {
            let what = if op == BinOp::Div {
                "division"
            } else {
                "remainder"
            };
            return Err(EvalError::new(rhs_span, format!("{what} by zero")));
        }
        (BinOp::Div, Num(x), Num(y)) => Num(x / y),
        // Floored, so the result has the divisor's sign: `-1 % 3` is 2, handy for cycling.
        (BinOp::Rem, Num(x), Num(y)) => Num(x - y * (x / y).floor()),
        (BinOp::Pow, Num(x), Num(y)) => Num(x.powf(y)),
        (BinOp::Add, P(p), P(q)) => P(p + q.to_vec2()),
        (BinOp::Sub, P(p), P(q)) => P(p - q.to_vec2()),
        (BinOp::Mul, P(p), Num(k)) | (BinOp::Mul, Num(k), P(p)) => P((p.to_vec2() * k).to_point()),
        (BinOp::Div, P(_), Num(0.0)) => return Err(EvalError::new(rhs_span, "division by zero")),
        (BinOp::Div, P(p), Num(k)) => P((p.to_vec2() / k).to_point()),
        (BinOp::Mul, T(mut l), T(r)) => {
            l.extend(r);
            T(l)
        }
        (BinOp::Add, Str(mut l), Str(r)) => {
            l.push_str(&r);
            Str(l)
        }
        (op, a, b) => {
            let symbol = op.symbol();
            let e = EvalError::new(
                span,
                format!(
                    "cannot apply `{symbol}` to {} and {}",
                    a.describe(),
                    b.describe()
                ),
            );
            let scaled_transform = matches!((&a, &b), (T(_), Num(_)) | (Num(_), T(_)));
            return Err(if scaled_transform {
                e.with_help("to scale a transform, multiply by `scale(k)`")
            } else {
                e
            });
        }
    };
    Ok(value)
}

/// Evaluated arguments of a built-in, with their spans, named ones refused.
struct Args {
    name: String,
    span: Span,
    values: Vec<(Value, Span)>,
}

impl Args {
    fn new(name: &str, args: &[Arg], span: Span, env: &mut dyn Env) -> Result<Args, EvalError> {
        let mut values = Vec::with_capacity(args.len());
        for arg in args {
            if let Some(n) = &arg.name {
                return Err(EvalError::new(
                    arg.span,
                    format!("`{name}` takes no named argument `{n}`"),
                )
                .with_help(
                    "named arguments belong to rule operators; write this one by position",
                ));
            }
            values.push((eval(&arg.value, env)?, arg.value.span));
        }
        Ok(Args {
            name: name.to_string(),
            span,
            values,
        })
    }

    /// The arguments as numbers, when their count is one of `counts`.
    fn nums(&self, counts: &[usize], usage: &str) -> Result<Vec<f64>, EvalError> {
        if !counts.contains(&self.values.len()) {
            return Err(EvalError::new(
                self.span,
                format!("wrong number of arguments to `{}`", self.name),
            )
            .with_help(format!("write `{usage}`")));
        }
        self.values
            .iter()
            .map(|(v, s)| v.as_num().map_err(|e| e.at(*s)))
            .collect()
    }

    fn error(&self, message: impl Into<String>) -> EvalError {
        EvalError::new(self.span, message)
    }
}

/// A call: a built-in function, or else a [`Value::Call`] for the operator to interpret.
fn call(name: &str, args: &[Arg], span: Span, env: &mut dyn Env) -> Result<Value, EvalError> {
    let a = Args::new(name, args, span, env)?;
    let one = |usage: &str| a.nums(&[1], usage).map(|v| v[0]);
    let value = match name {
        "rand" => match a.nums(&[0, 2], "rand() or rand(a, b)")?[..] {
            [lo, hi] => Value::Num(lo + (hi - lo) * env.rand()),
            _ => Value::Num(env.rand()),
        },
        "noise" => {
            let v = a.nums(&[2], "noise(x, y)")?;
            Value::Num(env.noise(v[0], v[1]))
        }
        "sin" => Value::Num(one("sin(radians)")?.sin()),
        "cos" => Value::Num(one("cos(radians)")?.cos()),
        "tan" => Value::Num(one("tan(radians)")?.tan()),
        "rad" => Value::Num(one("rad(degrees)")?.to_radians()),
        "abs" => Value::Num(one("abs(x)")?.abs()),
        "floor" => Value::Num(one("floor(x)")?.floor()),
        "ceil" => Value::Num(one("ceil(x)")?.ceil()),
        "round" => Value::Num(one("round(x)")?.round()),
        "exp" => Value::Num(one("exp(x)")?.exp()),
        "sqrt" => {
            let x = one("sqrt(x)")?;
            if x < 0.0 {
                return Err(a.error(format!("square root of a negative number ({x})")));
            }
            Value::Num(x.sqrt())
        }
        "ln" => {
            let x = one("ln(x)")?;
            if x <= 0.0 {
                return Err(a.error(format!("logarithm of a number that is not positive ({x})")));
            }
            Value::Num(x.ln())
        }
        "pow" => {
            let v = a.nums(&[2], "pow(x, y)")?;
            Value::Num(v[0].powf(v[1]))
        }
        "min" | "max" => {
            if a.values.is_empty() {
                return Err(a.error(format!("`{name}` needs at least one number")));
            }
            let v = a.nums(&[a.values.len()], "")?;
            let pick = if name == "min" { f64::min } else { f64::max };
            Value::Num(v.into_iter().reduce(pick).unwrap_or(0.0))
        }
        "clamp" => {
            let v = a.nums(&[3], "clamp(x, lo, hi)")?;
            if v[1] > v[2] {
                return Err(a.error(format!("clamp bounds are reversed: {} > {}", v[1], v[2])));
            }
            Value::Num(v[0].clamp(v[1], v[2]))
        }
        "lerp" => lerp(&a)?,
        "point" => {
            let v = a.nums(&[2], "point(x, y)")?;
            Value::Point(Point::new(v[0], v[1]))
        }
        // `tran` is gMotion Fig. 4's shorthand.
        "translate" | "tran" => {
            let d = match a.values.as_slice() {
                [(Value::Point(p), _)] => p.to_vec2(),
                _ => match a.nums(&[1, 2], "translate(x) or translate(x, y)")?[..] {
                    [x, y] => Vec2::new(x, y),
                    [x] => Vec2::new(x, 0.0),
                    _ => Vec2::ZERO,
                },
            };
            Value::Transform(vec![Component::Translate(d)])
        }
        "rotate" => match a.nums(&[1, 3], "rotate(degrees) or rotate(degrees, cx, cy)")?[..] {
            [deg, cx, cy] => {
                let c = Vec2::new(cx, cy);
                Value::Transform(vec![
                    Component::Translate(c),
                    Component::Rotate(deg),
                    Component::Translate(-c),
                ])
            }
            [deg] => Value::Transform(vec![Component::Rotate(deg)]),
            _ => Value::Transform(Vec::new()),
        },
        "scale" => {
            let k = match a.nums(&[1, 2], "scale(s) or scale(sx, sy)")?[..] {
                [sx, sy] => Vec2::new(sx, sy),
                [s] => Vec2::new(s, s),
                _ => Vec2::new(1.0, 1.0),
            };
            Value::Transform(vec![Component::Scale(k)])
        }
        // gMotion Fig. 4's `rot_scale(degrees, s)`: a turn and a uniform scale, which
        // commute, so their order does not matter.
        "rot_scale" => {
            let v = a.nums(&[2], "rot_scale(degrees, s)")?;
            Value::Transform(vec![
                Component::Rotate(v[0]),
                Component::Scale(Vec2::new(v[1], v[1])),
            ])
        }
        "skew" => {
            let v = a.nums(&[2], "skew(ax, ay)")?;
            Value::Transform(vec![Component::Skew(v[0], v[1])])
        }
        "skewX" => Value::Transform(vec![Component::Skew(one("skewX(degrees)")?, 0.0)]),
        "skewY" => Value::Transform(vec![Component::Skew(0.0, one("skewY(degrees)")?)]),
        "matrix" => {
            let v = a.nums(&[6], "matrix(a, b, c, d, e, f)")?;
            Value::Transform(vec![Component::Matrix(Affine::new([
                v[0], v[1], v[2], v[3], v[4], v[5],
            ]))])
        }
        "rgb" | "rgba" => {
            let (counts, usage): (&[usize], _) = if name == "rgb" {
                (&[3], "rgb(r, g, b) with r, g, b in 0..255")
            } else {
                (&[4], "rgba(r, g, b, alpha)")
            };
            let v = a.nums(counts, usage)?;
            for (i, channel) in ["red", "green", "blue"].iter().enumerate() {
                if !(0.0..=255.0).contains(&v[i]) {
                    return Err(a.error(format!("{channel} must lie in 0..255, found {}", v[i])));
                }
            }
            let alpha = alpha(&a, v.get(3).copied())?;
            Value::Color(Color {
                r: (v[0] / 255.0) as f32,
                g: (v[1] / 255.0) as f32,
                b: (v[2] / 255.0) as f32,
                a: alpha,
            })
        }
        "hsl" | "hsla" => {
            let (counts, usage): (&[usize], _) = if name == "hsl" {
                (&[3], "hsl(hue, saturation%, lightness%)")
            } else {
                (&[4], "hsla(hue, s%, l%, alpha)")
            };
            let v = a.nums(counts, usage)?;
            for (i, what) in [(1, "saturation"), (2, "lightness")] {
                if !(0.0..=1.0).contains(&v[i]) {
                    return Err(a
                        .error(format!("{what} must lie in 0%..100%, found {}", v[i]))
                        .with_help(format!(
                            "write it as a percentage, e.g. `{}%`",
                            v[i].clamp(0.0, 100.0)
                        )));
                }
            }
            let mut c = hsl(v[0], v[1], v[2]);
            c.a = alpha(&a, v.get(3).copied())?;
            Value::Color(c)
        }
        _ => Value::Call {
            name: name.to_string(),
            args: a.values.into_iter().map(|(v, _)| v).collect(),
        },
    };
    Ok(value)
}

/// Checks an optional alpha in `[0, 1]` (1 when absent).
fn alpha(a: &Args, alpha: Option<f64>) -> Result<f32, EvalError> {
    match alpha {
        None => Ok(1.0),
        Some(x) if (0.0..=1.0).contains(&x) => Ok(x as f32),
        Some(x) => Err(a.error(format!("alpha must lie in 0..1, found {x}"))),
    }
}

/// `lerp(a, b, t)` on numbers, points or colours.
fn lerp(a: &Args) -> Result<Value, EvalError> {
    let [(from, _), (to, _), (t, t_span)] = a.values.as_slice() else {
        return Err(a
            .error("wrong number of arguments to `lerp`")
            .with_help("write `lerp(a, b, t)`"));
    };
    let t = t.as_num().map_err(|e| e.at(*t_span))?;
    Ok(match (from, to) {
        (Value::Num(x), Value::Num(y)) => Value::Num(x + (y - x) * t),
        (Value::Point(p), Value::Point(q)) => Value::Point(p.lerp(*q, t)),
        (x, y) => match (x.as_color(), y.as_color()) {
            // Clamped: colour components must stay in [0, 1].
            (Ok(c), Ok(d)) => Value::Color(c.lerp(d, t.clamp(0.0, 1.0) as f32)),
            _ => {
                return Err(a.error(format!(
                    "`lerp` blends two numbers, points or colours, found {} and {}",
                    x.describe(),
                    y.describe()
                )));
            }
        },
    })
}

/// HSL (hue in degrees, saturation and lightness in `[0, 1]`) to an opaque sRGB colour.
fn hsl(h: f64, s: f64, l: f64) -> Color {
    let h = h.rem_euclid(360.0) / 60.0;
    let chroma = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let x = chroma * (1.0 - (h % 2.0 - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (chroma, x, 0.0),
        1 => (x, chroma, 0.0),
        2 => (0.0, chroma, x),
        3 => (0.0, x, chroma),
        4 => (x, 0.0, chroma),
        _ => (chroma, 0.0, x),
    };
    let m = l - chroma / 2.0;
    Color::rgb((r + m) as f32, (g + m) as f32, (b + m) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grammar::ast::Arg;
    use crate::grammar::parse;

    /// A shape with a few variables, a scripted random stream and a noise that records its
    /// inputs in its output.
    struct TestEnv {
        draws: Vec<f64>,
    }

    impl Env for TestEnv {
        fn var(&self, name: &str) -> Option<f64> {
            match name {
                "id" => Some(3.0),
                "n" => Some(10.0),
                "w" => Some(40.0),
                "h" => Some(30.0),
                _ => None,
            }
        }
        fn rand(&mut self) -> f64 {
            self.draws.remove(0)
        }
        fn noise(&self, x: f64, y: f64) -> f64 {
            (x - y) / 100.0
        }
    }

    /// The first argument of the only rule of `op(<src>) : a -> []`.
    fn arg(src: &str) -> Arg {
        let g = parse(&format!("op({src}) : a -> []"))
            .unwrap_or_else(|d| panic!("{}", d.render("t", src)));
        g.rules[0].args[0].clone()
    }

    fn eval_str(src: &str) -> Result<Value, EvalError> {
        eval(
            &arg(src).value,
            &mut TestEnv {
                draws: vec![0.25, 0.75],
            },
        )
    }

    fn num(src: &str) -> f64 {
        eval_str(src)
            .unwrap_or_else(|e| panic!("{src}: {e}"))
            .as_num()
            .unwrap()
    }

    fn err(src: &str) -> EvalError {
        match eval_str(src) {
            Ok(v) => panic!("{src} evaluated to {v:?}"),
            Err(e) => e,
        }
    }

    /// The arithmetic route gives exactly what `eval` gives, and declines (leaving `eval` to
    /// decide) wherever `eval` fails or needs more than arithmetic: built from every
    /// operator, variables, `pi`, nesting, zero divisors, overflow and non-arithmetic parts.
    #[test]
    fn arithmetic_route_agrees_with_eval() {
        let atoms = [
            "0",
            "-0",
            "2.5",
            "id",
            "w",
            "pi",
            "(h - 30)",
            "1e300",
            "rand(1, 2)",
            "nope",
            "floor(id / 2)",
            "noise(w, id * 0.9)",
            "sqrt(id - 4)",
            "ln(id - 3)",
            "min(id, -w, 2)",
            "clamp(id, w, h)",
            "pow(id, 1 / 2)",
            "abs(-sin(rad(id)))",
            "noise(id)",
            "scale(2)",
        ];
        let ops = ["+", "-", "*", "/", "%", "^"];
        let mut taken = 0;
        for a in atoms {
            for op in ops {
                for b in atoms {
                    for src in [format!("{a} {op} {b}"), format!("-({a} {op} {b}) * id % 7")] {
                        let expr = arg(&src).value;
                        let env = TestEnv {
                            draws: vec![0.5; 4],
                        };
                        let fast = arithmetic(&expr, &env);
                        let slow = eval(
                            &expr,
                            &mut TestEnv {
                                draws: vec![0.5; 4],
                            },
                        );
                        match (fast, slow) {
                            (Some(x), Ok(Value::Num(y))) => {
                                assert_eq!(x.to_bits(), y.to_bits(), "{src}");
                                taken += 1;
                            }
                            (Some(x), other) => panic!("{src}: arithmetic {x}, eval {other:?}"),
                            (None, Ok(Value::Num(_))) => assert!(
                                src.contains("rand") || src.contains("nope"),
                                "{src}: arithmetic declined what eval computes"
                            ),
                            (None, _) => {}
                        }
                    }
                }
            }
        }
        assert!(
            taken > 500,
            "only {taken} expressions took the arithmetic route"
        );
    }

    #[test]
    fn arithmetic_follows_precedence() {
        assert_eq!(num("1 + 2 * 3"), 7.0);
        assert_eq!(num("(1 + 2) * 3"), 9.0);
        assert_eq!(num("2 ^ 3 ^ 2"), 512.0);
        assert_eq!(num("-2 ^ 2"), -4.0);
        assert_eq!(num("10 - 4 - 3"), 3.0);
        assert_eq!(num("7 % 3"), 1.0);
        assert_eq!(num("-1 % 3"), 2.0);
        assert_eq!(num("id * 100ms"), 0.30000000000000004);
        assert_eq!(num("50% * n"), 5.0);
    }

    #[test]
    fn variables_constants_and_functions() {
        assert_eq!(num("w - h"), 10.0);
        assert_eq!(num("pi"), std::f64::consts::PI);
        assert!((num("sin(rad(30))") - 0.5).abs() < 1e-12);
        assert_eq!(num("cos(0)"), 1.0);
        assert_eq!(
            num("sqrt(16) + abs(-2) + floor(1.7) + ceil(1.2) + round(2.5)"),
            4.0 + 2.0 + 1.0 + 2.0 + 3.0
        );
        assert_eq!(num("min(4, 2, 8) + max(1, 5)"), 7.0);
        assert_eq!(num("clamp(12, 0, 10)"), 10.0);
        assert_eq!(num("lerp(10, 20, 25%)"), 12.5);
        assert_eq!(num("pow(2, 10)"), 1024.0);
        assert!((num("ln(exp(2))") - 2.0).abs() < 1e-12);
        assert_eq!(num("noise(30, 10)"), 0.2);
    }

    #[test]
    fn rand_draws_from_the_env_each_call() {
        // Draws 0.25 then 0.75.
        assert_eq!(num("rand() + rand(10, 20)"), 0.25 + 17.5);
    }

    #[test]
    fn transforms_concatenate_in_writing_order() {
        let v = eval_str("translate(10, 0) rotate(30) scale(2) * skewX(5)").unwrap();
        assert_eq!(
            v.as_transform().unwrap(),
            &[
                Component::Translate(Vec2::new(10.0, 0.0)),
                Component::Rotate(30.0),
                Component::Scale(Vec2::new(2.0, 2.0)),
                Component::Skew(5.0, 0.0),
            ]
        );
        let about = eval_str("rotate(90, 10, 0)").unwrap();
        let m = crate::motion::component::product_at(about.as_transform().unwrap(), 1.0);
        // The centre stays put; the origin swings around it.
        let c = m * Point::new(10.0, 0.0);
        let o = m * Point::new(0.0, 0.0);
        assert!((c - Point::new(10.0, 0.0)).hypot() < 1e-9);
        assert!((o - Point::new(10.0, -10.0)).hypot() < 1e-9);
    }

    #[test]
    fn colours_points_keywords_and_calls() {
        assert_eq!(
            eval_str("#ff8000").unwrap().as_color().unwrap().to_hex(),
            "#ff8000"
        );
        assert_eq!(
            eval_str("rgb(255, 128, 0)")
                .unwrap()
                .as_color()
                .unwrap()
                .to_hex(),
            "#ff8000"
        );
        assert_eq!(
            eval_str("hsl(120, 100%, 25%)")
                .unwrap()
                .as_color()
                .unwrap()
                .to_hex(),
            "#008000"
        );
        assert_eq!(
            eval_str("rgba(0, 0, 255, 0.5)")
                .unwrap()
                .as_color()
                .unwrap()
                .a,
            0.5
        );
        assert_eq!(
            eval_str("steelblue").unwrap().as_color().unwrap().to_hex(),
            "#4682b4"
        );
        assert_eq!(
            eval_str("lerp(#000000, #ffffff, 0.5)")
                .unwrap()
                .as_color()
                .unwrap()
                .to_hex(),
            "#808080"
        );
        assert_eq!(
            eval_str("(1, 2) + point(3, 4) * 2")
                .unwrap()
                .as_point()
                .unwrap(),
            Point::new(7.0, 10.0)
        );
        assert_eq!(
            eval_str("ease-in-out").unwrap().as_keyword().unwrap(),
            "ease-in-out"
        );
        assert_eq!(
            eval_str("\"world\"").unwrap().as_keyword().unwrap(),
            "world"
        );
        let v = eval_str("cubic(0.4, 0, 0.2, id)").unwrap();
        let (name, args) = v.as_call().unwrap();
        assert_eq!(
            (name, args),
            (
                "cubic",
                &[
                    Value::Num(0.4),
                    Value::Num(0.0),
                    Value::Num(0.2),
                    Value::Num(3.0)
                ][..]
            )
        );
        assert_eq!(
            eval_str("linear").unwrap().as_call().unwrap(),
            ("linear", &[][..])
        );
        assert_eq!(eval_str("4x2").unwrap().as_size().unwrap(), (4, 2, 2));
        assert_eq!(eval_str("4x2x5").unwrap().as_size().unwrap(), (4, 2, 5));
        assert_eq!(
            eval_str("\"M0 0\" + \"L1 1\"").unwrap().as_str().unwrap(),
            "M0 0L1 1"
        );
    }

    #[test]
    fn errors_point_at_the_culprit() {
        let e = err("1 / (id - 3)");
        assert_eq!((e.message.as_str(), e.span.col), ("division by zero", 8));
        let e = err("translate(#fff, 2)");
        assert_eq!(
            (e.message.as_str(), e.span.col),
            ("expected a number, found a colour", 14)
        );
        let e = err("sqrt(-1)");
        assert!(e.message.contains("negative"), "{}", e.message);
        let e = err("(-8) ^ 0.5");
        assert_eq!(e.message, "the result is not a finite number");
        let e = err("10 ^ 400");
        assert_eq!(e.message, "the result is not a finite number");
        let e = err("scale(2) * 3");
        assert!(
            e.message
                .contains("cannot apply `*` to a transform and a number"),
            "{}",
            e.message
        );
        assert!(e.help.is_some());
        let e = err("w-h");
        assert!(e.help.unwrap().contains("`w - h`"));
        let e = err("rotate(1, 2)");
        assert!(
            e.message.contains("wrong number of arguments"),
            "{}",
            e.message
        );
        let e = err("rgb(300, 0, 0)");
        assert!(e.message.contains("red"), "{}", e.message);
        let e = err("hsl(0, 50, 50)");
        assert!(e.help.unwrap().contains('%'));
        let e = err("(1, 2, 3)");
        assert!(e.message.contains("two coordinates"), "{}", e.message);
        let e = err("rotate(a = 1)");
        assert!(e.message.contains("named"), "{}", e.message);
        assert!(
            eval_str("\"x\"").unwrap().as_num().unwrap_err().to_string()
                == "expected a number, found a string"
        );
    }

    #[test]
    fn eval_errors_render_with_a_caret() {
        let src = "op(1 / 0) : a -> []";
        let g = parse(src).unwrap();
        let e = eval(&g.rules[0].args[0].value, &mut TestEnv { draws: vec![] }).unwrap_err();
        let text = Diagnostic::from(e).render("g", src);
        assert!(text.contains("g:1:8: error: division by zero"), "{text}");
        assert!(text.contains("  |        ^\n"), "{text}");
    }
}
