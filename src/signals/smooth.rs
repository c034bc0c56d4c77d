//! Smoothing sampled channels: a small language of system descriptions, built into
//! [`System`]s at a frame rate.
//!
//! The engine samples each animated channel (a position, an angle, a colour) once per
//! frame and passes the samples through a system, so that jumps in the channel's
//! velocity — slice boundaries, retargets — come out smooth. A [`SmoothSpec`] is the
//! description; [`smooth_samples`] runs it.
//!
//! # Spelling
//!
//! Parsed by [`SmoothSpec::parse`] from text, or built by [`SmoothSpec::from_call`] from
//! a grammar call. Durations are in seconds (`0.3`, `0.3s` and `300ms` are the same).
//!
//! | spelling | system | paper |
//! |---|---|---|
//! | `none` | identity (no smoothing) | |
//! | `simple(easing, duration)` | simple transitions, retargeted on every change (the baseline; stalls under frequent change) | Alg. 1 |
//! | `spline(duration)` | spline transitions | sec. 3 |
//! | `fir(easing, duration)` | discrete FIR filter whose step response is the easing | Alg. 3 |
//! | `arc(aspect, duration)` / `arc(aspect, duration, easing)` | elliptical-arc matrix FIR on 2-D channels, inner easing `poles(4)` by default | sec. 8.2 |
//! | `spring(duration, bounce)` | spring, perceptual parameters (`bounce ∈ (−1, 1)`) | sec. 6 |
//! | `msd(mass, stiffness, damping)` (also `mass_spring_damper`) | spring, physical parameters | sec. 6 |
//! | `lowpass(n, tau)` | `n` one-pole filters in series, time constant `tau` s | sec. 8.2 |
//! | `zoh(sys)`, `impulse(sys)`, `tustin(sys)` (= `bilinear`), `matched(sys)` | discretisation of an IIR `sys` (default `zoh`) | sec. 6, 9 |
//! | `series(a, b, …)` | blocks in series | sec. 7 |
//! | `parallel(w1, a, w2, b, …)` | weighted mix, weights summing to 1 | sec. 7 |
//!
//! Easings are those of [`Easing::from_call`]: `linear`, `ease`, `ease-in`, `ease-out`,
//! `ease-in-out`, `cubic(x1, y1, x2, y2)`, `bspline(k)`, `poles(n)`, `poles(n, tau)`.
//!
//! Examples: `spring(0.5, 0.2)`, `fir(bspline(3), 0.3)`, `tustin(msd(1, 170, 20))`,
//! `series(lowpass(2, 0.05), spring(0.6, 0))`, `arc(0.6, 0.8)`.

use std::fmt;

use super::arc::ArcEasing;
use super::easing::{Ease, Easing};
use super::error::{SignalError, finite, positive, whole};
use super::fir::Fir;
use super::lti::{Discretization, Lti};
use super::spring::Spring;
use super::statespace::MAX_ORDER;
use super::system::{Identity, Sampled, Series, System};
use super::transition::{SimpleTransition, SplineTransition};
use super::vector::Vector;

/// An argument of a call in a system description: a number or a nested call (a bare
/// name such as `linear` is a call without arguments).
#[derive(Clone, Debug, PartialEq)]
pub enum CallArg {
    /// A number (units already folded in: seconds).
    Num(f64),
    /// A call `name(args)`.
    Call(String, Vec<CallArg>),
}

/// The continuous-time IIR systems a description can name.
#[derive(Clone, Debug, PartialEq)]
pub enum IirSystem {
    /// A spring–mass–damper.
    Spring(Spring),
    /// `n` one-pole low-pass filters with time constant `tau` seconds.
    Lowpass {
        /// Number of poles.
        n: u32,
        /// Time constant in seconds.
        tau: f64,
    },
}

impl IirSystem {
    /// The system as poles and zeros.
    pub fn lti(&self) -> Result<Lti, SignalError> {
        match self {
            IirSystem::Spring(s) => Ok(Lti::spring(s)),
            IirSystem::Lowpass { n, tau } => Lti::lowpass(*n, *tau),
        }
    }
}

/// A description of a smoothing system (see the module docs for the spelling).
#[derive(Clone, Debug, PartialEq)]
pub enum SmoothSpec {
    /// No smoothing.
    Identity,
    /// Simple transitions (Alg. 1) retargeted whenever the input changes.
    Simple(Ease),
    /// Spline transitions (sec. 3) with this duration in seconds.
    Spline(f64),
    /// A discrete FIR filter (Alg. 3) whose step response is this easing.
    Fir(Ease),
    /// The elliptical-arc matrix FIR of sec. 8.2 (2-D channels only).
    Arc(ArcEasing),
    /// An IIR system discretised by `method` and run as biquads (Alg. 4).
    Iir {
        /// The continuous-time system.
        system: IirSystem,
        /// How it is discretised.
        method: Discretization,
    },
    /// Blocks in series.
    Series(Vec<SmoothSpec>),
    /// Blocks in parallel with weights summing to 1.
    Parallel(Vec<(f64, SmoothSpec)>),
}

impl SmoothSpec {
    /// Parses a text spelling such as `fir(bspline(3), 0.3)`.
    pub fn parse(text: &str) -> Result<SmoothSpec, SignalError> {
        let mut p = Parser {
            src: text,
            pos: 0,
            depth: 0,
        };
        p.skip_ws();
        let (name, args) = match p.arg()? {
            CallArg::Call(name, args) => (name, args),
            CallArg::Num(_) => {
                return Err(p.error_at(0, "expected a system such as `spring(0.5, 0)`"));
            }
        };
        p.skip_ws();
        if p.pos < p.src.len() {
            return Err(p.error_at(p.pos, "unexpected text after the system description"));
        }
        SmoothSpec::from_call(&name, &args)
    }

    /// Builds a description from a call: `name(args)` (see the module docs).
    pub fn from_call(name: &str, args: &[CallArg]) -> Result<SmoothSpec, SignalError> {
        from_call(name, args).map_err(|e| match e {
            SignalError::Invalid(msg) if msg.starts_with('`') => SignalError::Invalid(msg),
            other => SignalError::Invalid(format!(
                "`{}`: {other}",
                CallArg::Call(name.into(), args.to_vec())
            )),
        })
    }

    /// The system at `fps` frames per second, for signals of type `V`, not yet reset.
    pub fn build<V: Vector>(&self, fps: f64) -> Result<Box<dyn System<V>>, SignalError> {
        positive("frame rate", fps)?;
        Ok(match self {
            SmoothSpec::Identity => Box::new(Identity),
            SmoothSpec::Simple(ease) => Box::new(Sampled::new(
                SimpleTransition::new(ease.clone(), V::zero()),
                fps,
            )?),
            SmoothSpec::Spline(d) => {
                Box::new(Sampled::new(SplineTransition::new(*d, V::zero())?, fps)?)
            }
            SmoothSpec::Fir(ease) => Box::new(Fir::<V>::from_response(ease, fps)?),
            SmoothSpec::Arc(arc) => {
                // An arc is a path in the plane: a colour (four components) has no such
                // path, and taking its first two would bend hue arbitrarily.
                if V::DIM != 2 {
                    return Err(SignalError::Invalid(
                        "`arc` moves along a 2-D path: use it on a position (x, y) channel".into(),
                    ));
                }
                Box::new(Fir::<V>::from_response(arc, fps)?)
            }
            SmoothSpec::Iir { system, method } => {
                Box::new(system.lti()?.discretize::<V>(*method, fps)?)
            }
            SmoothSpec::Series(parts) => {
                let mut it = parts.iter();
                let first = it.next().ok_or_else(|| {
                    SignalError::Invalid("`series` needs at least one block".into())
                })?;
                let mut acc = first.build::<V>(fps)?;
                for p in it {
                    acc = Box::new(Series(acc, p.build::<V>(fps)?));
                }
                acc
            }
            SmoothSpec::Parallel(parts) => {
                check_weights(parts.iter().map(|p| p.0))?;
                let built = parts
                    .iter()
                    .map(|(w, p)| Ok((*w, p.build::<V>(fps)?)))
                    .collect::<Result<Vec<_>, SignalError>>()?;
                Box::new(Mix { parts: built })
            }
        })
    }

    /// A time over which the system forgets its input: the duration of FIR blocks, the
    /// slowest time constant of IIR ones, summed along series and maximal across parallel
    /// branches.
    pub fn time_scale(&self) -> Result<f64, SignalError> {
        Ok(match self {
            SmoothSpec::Identity => 0.0,
            SmoothSpec::Simple(e) | SmoothSpec::Fir(e) => e.duration(),
            SmoothSpec::Spline(d) => *d,
            SmoothSpec::Arc(a) => super::fir::Response::<[f64; 2]>::duration(a),
            SmoothSpec::Iir { system, .. } => system.lti()?.time_constant(),
            SmoothSpec::Series(p) => p
                .iter()
                .map(SmoothSpec::time_scale)
                .sum::<Result<f64, _>>()?,
            SmoothSpec::Parallel(p) => p
                .iter()
                .map(|(_, s)| s.time_scale())
                .try_fold(0.0, |m, t| t.map(|t| f64::max(m, t)))?,
        })
    }

    /// How long after a unit step of the input the output stays within `tolerance` of
    /// it for good (simulated at 240 fps). Errors when that takes more than an hour.
    pub fn settle_time(&self, tolerance: f64) -> Result<f64, SignalError> {
        positive("settling tolerance", tolerance)?;
        const RATE: f64 = 240.0;
        let horizon = 50.0 * self.time_scale()? + 1.0 / RATE;
        if horizon > 3600.0 {
            return Err(SignalError::Invalid(format!(
                "the system takes about {horizon:.0} s to settle, more than an hour"
            )));
        }
        let mut sys = self.build::<[f64; 2]>(RATE)?;
        sys.reset([0.0, 0.0]);
        let mut last_out = 0usize;
        let steps = (horizon * RATE).ceil() as usize;
        for n in 0..steps {
            let y = sys.step([1.0, 0.0]);
            if y.sub([1.0, 0.0]).max_abs() > tolerance {
                last_out = n + 1;
            }
        }
        Ok(last_out as f64 / RATE)
    }
}

/// Smooths a sampled channel: `samples[i]` is the channel's value at frame `i` (time
/// `i / fps`). The system starts at rest on `samples[0]`; the result has one output per
/// input sample (append copies of the last sample to see the tail settle).
pub fn smooth_samples<V: Vector>(
    spec: &SmoothSpec,
    samples: &[V],
    fps: f64,
) -> Result<Vec<V>, SignalError> {
    if let Some(i) = samples.iter().position(|v| !v.is_finite()) {
        return Err(SignalError::Invalid(format!(
            "sample {i} is not finite: {:?}",
            samples[i]
        )));
    }
    let Some(first) = samples.first() else {
        return Ok(Vec::new());
    };
    let mut sys = spec.build::<V>(fps)?;
    sys.reset(*first);
    Ok(samples.iter().map(|&x| sys.step(x)).collect())
}

/// A weighted mix of any number of blocks fed the same input.
struct Mix<V> {
    parts: Vec<(f64, Box<dyn System<V>>)>,
}

impl<V: Vector> System<V> for Mix<V> {
    fn step(&mut self, x: V) -> V {
        self.parts
            .iter_mut()
            .fold(V::zero(), |acc, (w, s)| acc.add_scaled(s.step(x), *w))
    }
    fn reset(&mut self, x: V) {
        for (_, s) in &mut self.parts {
            s.reset(x);
        }
    }
}

fn check_weights(weights: impl Iterator<Item = f64>) -> Result<(), SignalError> {
    let mut sum = 0.0;
    for w in weights {
        sum += finite("parallel weight", w)?;
    }
    if (sum - 1.0).abs() > 1e-9 {
        return Err(SignalError::Invalid(format!(
            "parallel weights must sum to 1 so the diagram stays affine, they sum to {sum}"
        )));
    }
    Ok(())
}

fn num(name: &str, args: &[CallArg], i: usize, what: &str) -> Result<f64, SignalError> {
    match args.get(i) {
        Some(CallArg::Num(v)) => Ok(*v),
        Some(CallArg::Call(n, _)) => Err(SignalError::Invalid(format!(
            "`{name}` argument {} ({what}) must be a number, got `{n}`",
            i + 1
        ))),
        None => Err(SignalError::Invalid(format!(
            "`{name}` is missing argument {} ({what})",
            i + 1
        ))),
    }
}

fn easing(name: &str, arg: Option<&CallArg>) -> Result<Easing, SignalError> {
    match arg {
        Some(CallArg::Call(n, a)) => {
            let nums = a
                .iter()
                .map(|x| match x {
                    CallArg::Num(v) => Ok(*v),
                    CallArg::Call(m, _) => Err(SignalError::Invalid(format!(
                        "easing `{n}` takes numbers, got `{m}`"
                    ))),
                })
                .collect::<Result<Vec<f64>, _>>()?;
            Easing::try_from_call(n, &nums)
        }
        Some(CallArg::Num(v)) => Err(SignalError::Invalid(format!(
            "`{name}` expects an easing such as `bspline(3)` first, got the number {v}"
        ))),
        None => Err(SignalError::Invalid(format!(
            "`{name}` is missing its easing"
        ))),
    }
}

fn arity(
    name: &str,
    args: &[CallArg],
    lo: usize,
    hi: usize,
    usage: &str,
) -> Result<(), SignalError> {
    if args.len() < lo || args.len() > hi {
        return Err(SignalError::Invalid(format!(
            "`{name}` takes {usage}, got {} argument(s)",
            args.len()
        )));
    }
    Ok(())
}

fn sub_spec(arg: &CallArg, name: &str) -> Result<SmoothSpec, SignalError> {
    match arg {
        CallArg::Call(n, a) => from_call(n, a),
        CallArg::Num(v) => Err(SignalError::Invalid(format!(
            "`{name}` expects a system, got the number {v}"
        ))),
    }
}

/// An IIR system discretised the default way; wrapping it in `zoh(…)` and the like picks
/// another method.
fn iir(system: IirSystem) -> SmoothSpec {
    SmoothSpec::Iir {
        system,
        method: Discretization::default(),
    }
}

fn from_call(name: &str, args: &[CallArg]) -> Result<SmoothSpec, SignalError> {
    match name {
        "none" | "identity" => {
            arity(name, args, 0, 0, "no arguments")?;
            Ok(SmoothSpec::Identity)
        }
        "simple" | "fir" => {
            arity(name, args, 2, 2, "an easing and a duration")?;
            let ease = Ease::new(easing(name, args.first())?, num(name, args, 1, "duration")?)?;
            Ok(if name == "simple" {
                SmoothSpec::Simple(ease)
            } else {
                SmoothSpec::Fir(ease)
            })
        }
        "spline" => {
            arity(name, args, 1, 1, "a duration")?;
            Ok(SmoothSpec::Spline(positive(
                "spline duration",
                num(name, args, 0, "duration")?,
            )?))
        }
        "arc" => {
            arity(
                name,
                args,
                2,
                3,
                "an aspect, a duration and optionally an easing",
            )?;
            let inner = match args.get(2) {
                Some(a) => easing(name, Some(a))?,
                None => Easing::poles(4)?,
            };
            Ok(SmoothSpec::Arc(ArcEasing::new(
                num(name, args, 0, "aspect")?,
                inner,
                num(name, args, 1, "duration")?,
            )?))
        }
        "spring" => {
            arity(name, args, 2, 2, "a duration and a bounce")?;
            let s = Spring::from_duration_bounce(
                num(name, args, 0, "duration")?,
                num(name, args, 1, "bounce")?,
            )?;
            Ok(iir(IirSystem::Spring(s)))
        }
        "msd" | "mass_spring_damper" => {
            arity(name, args, 3, 3, "mass, stiffness and damping")?;
            let s = Spring::new(
                num(name, args, 0, "mass")?,
                num(name, args, 1, "stiffness")?,
                num(name, args, 2, "damping")?,
            )?;
            Ok(iir(IirSystem::Spring(s)))
        }
        "lowpass" => {
            arity(name, args, 2, 2, "a number of poles and a time constant")?;
            let n = whole(
                "number of poles",
                num(name, args, 0, "poles")?,
                1,
                MAX_ORDER as u32,
                "1..=16",
            )?;
            let tau = positive(
                "low-pass time constant",
                num(name, args, 1, "time constant")?,
            )?;
            Ok(iir(IirSystem::Lowpass { n, tau }))
        }
        "zoh" | "impulse" | "tustin" | "bilinear" | "matched" => {
            arity(name, args, 1, 1, "one IIR system such as `spring(0.5, 0)`")?;
            let method = match name {
                "zoh" => Discretization::ZeroOrderHold,
                "impulse" => Discretization::ImpulseInvariant,
                "matched" => Discretization::Matched,
                _ => Discretization::Bilinear,
            };
            match sub_spec(&args[0], name)? {
                SmoothSpec::Iir { system, .. } => Ok(SmoothSpec::Iir { system, method }),
                other => Err(SignalError::Invalid(format!(
                    "`{name}` discretises an IIR system (spring, msd, lowpass), not `{other}`"
                ))),
            }
        }
        "series" => {
            arity(name, args, 1, usize::MAX, "one or more systems")?;
            Ok(SmoothSpec::Series(
                args.iter()
                    .map(|a| sub_spec(a, name))
                    .collect::<Result<_, _>>()?,
            ))
        }
        "parallel" => {
            if args.is_empty() || !args.len().is_multiple_of(2) {
                return Err(SignalError::Invalid(
                    "`parallel` takes pairs of a weight and a system: parallel(0.5, spring(0.4, 0), 0.5, fir(linear, 0.2))"
                        .into(),
                ));
            }
            let parts = args
                .chunks(2)
                .enumerate()
                .map(|(i, c)| Ok((num(name, args, 2 * i, "weight")?, sub_spec(&c[1], name)?)))
                .collect::<Result<Vec<_>, SignalError>>()?;
            check_weights(parts.iter().map(|p| p.0))?;
            Ok(SmoothSpec::Parallel(parts))
        }
        _ => Err(SignalError::Unknown {
            kind: "system",
            name: name.to_string(),
            expected: "none, simple, spline, fir, arc, spring, msd, lowpass, zoh, impulse, tustin, matched, series, parallel",
        }),
    }
}

impl fmt::Display for CallArg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CallArg::Num(v) => write!(f, "{v}"),
            CallArg::Call(name, args) if args.is_empty() => write!(f, "{name}"),
            CallArg::Call(name, args) => {
                write!(f, "{name}(")?;
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{a}")?;
                }
                write!(f, ")")
            }
        }
    }
}

impl fmt::Display for Easing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Easing::Linear => write!(f, "linear"),
            Easing::CubicBezier([a, b, c, d]) => write!(f, "cubic({a}, {b}, {c}, {d})"),
            Easing::BSpline(k) => write!(f, "bspline({k})"),
            Easing::Poles { n, tau } => write!(f, "poles({n}, {tau})"),
            Easing::Steps(n) => write!(f, "steps({n})"),
        }
    }
}

/// `x` rounded to twelve significant digits.
fn significant(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

impl fmt::Display for SmoothSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SmoothSpec::Identity => write!(f, "none"),
            SmoothSpec::Simple(e) => write!(f, "simple({}, {})", e.easing(), e.duration()),
            SmoothSpec::Spline(d) => write!(f, "spline({d})"),
            SmoothSpec::Fir(e) => write!(f, "fir({}, {})", e.easing(), e.duration()),
            SmoothSpec::Arc(a) => write!(
                f,
                "arc({}, {})",
                a.aspect(),
                super::fir::Response::<[f64; 2]>::duration(a)
            ),
            SmoothSpec::Iir { system, method } => {
                let inner = match system {
                    IirSystem::Spring(s) if s.mass() == 1.0 => {
                        // Duration and bounce are recovered from stiffness and damping,
                        // which leaves float noise (0.2 prints as 0.19999999999999996);
                        // twelve significant digits give back what the user wrote.
                        format!(
                            "spring({}, {})",
                            significant(s.duration()),
                            significant(s.bounce())
                        )
                    }
                    IirSystem::Spring(s) => {
                        format!("msd({}, {}, {})", s.mass(), s.stiffness(), s.damping())
                    }
                    IirSystem::Lowpass { n, tau } => format!("lowpass({n}, {tau})"),
                };
                match method {
                    Discretization::ZeroOrderHold => write!(f, "{inner}"),
                    Discretization::ImpulseInvariant => write!(f, "impulse({inner})"),
                    Discretization::Bilinear => write!(f, "tustin({inner})"),
                    Discretization::Matched => write!(f, "matched({inner})"),
                }
            }
            SmoothSpec::Series(p) => {
                write!(f, "series(")?;
                for (i, s) in p.iter().enumerate() {
                    write!(f, "{}{s}", if i > 0 { ", " } else { "" })?;
                }
                write!(f, ")")
            }
            SmoothSpec::Parallel(p) => {
                write!(f, "parallel(")?;
                for (i, (w, s)) in p.iter().enumerate() {
                    write!(f, "{}{w}, {s}", if i > 0 { ", " } else { "" })?;
                }
                write!(f, ")")
            }
        }
    }
}

/// A recursive-descent parser for `name(arg, …)` with numbers, units and nested calls.
struct Parser<'a> {
    src: &'a str,
    pos: usize,
    /// Calls open around the current position.
    depth: usize,
}

/// The deepest calls may nest in a system description (`cascade(cascade(…))`): deeper
/// text is refused with a position instead of overflowing the stack.
pub const MAX_SYSTEM_NESTING: usize = 64;

impl Parser<'_> {
    fn error_at(&self, byte: usize, message: &str) -> SignalError {
        SignalError::Syntax {
            column: self.src[..byte.min(self.src.len())].chars().count() + 1,
            message: message.into(),
        }
    }

    fn peek(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn skip_ws(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.pos += self.peek().map_or(0, char::len_utf8);
        }
    }

    fn arg(&mut self) -> Result<CallArg, SignalError> {
        self.skip_ws();
        match self.peek() {
            Some(c) if c.is_ascii_digit() || c == '-' || c == '+' || c == '.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == '_' => self.call(),
            Some(c) => Err(self.error_at(
                self.pos,
                &format!("expected a number or a name, found `{c}`"),
            )),
            None => Err(self.error_at(self.pos, "expected a number or a name, found the end")),
        }
    }

    fn number(&mut self) -> Result<CallArg, SignalError> {
        let start = self.pos;
        let bytes = self.src.as_bytes();
        let mut end = self.pos;
        if end < bytes.len() && (bytes[end] == b'-' || bytes[end] == b'+') {
            end += 1;
        }
        while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
            end += 1;
        }
        if end < bytes.len() && (bytes[end] == b'e' || bytes[end] == b'E') {
            let mut e = end + 1;
            if e < bytes.len() && (bytes[e] == b'-' || bytes[e] == b'+') {
                e += 1;
            }
            if e < bytes.len() && bytes[e].is_ascii_digit() {
                end = e;
                while end < bytes.len() && bytes[end].is_ascii_digit() {
                    end += 1;
                }
            }
        }
        let value: f64 = self.src[start..end].parse().map_err(|_| {
            self.error_at(
                start,
                &format!("`{}` is not a number", &self.src[start..end]),
            )
        })?;
        self.pos = end;
        let rest = &self.src[self.pos..];
        let scale = if rest.starts_with("ms") {
            self.pos += 2;
            1e-3
        } else if rest.starts_with('s')
            && !rest[1..].starts_with(|c: char| c.is_ascii_alphanumeric())
        {
            self.pos += 1;
            1.0
        } else if rest.starts_with('%') {
            self.pos += 1;
            1e-2
        } else {
            1.0
        };
        Ok(CallArg::Num(value * scale))
    }

    fn call(&mut self) -> Result<CallArg, SignalError> {
        let start = self.pos;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            self.pos += 1;
        }
        let name = self.src[start..self.pos].to_string();
        self.skip_ws();
        let mut args = Vec::new();
        if self.peek() == Some('(') {
            if self.depth >= MAX_SYSTEM_NESTING {
                return Err(self.error_at(
                    start,
                    &format!(
                        "the system description nests calls more than {MAX_SYSTEM_NESTING} deep"
                    ),
                ));
            }
            self.pos += 1;
            self.skip_ws();
            if self.peek() == Some(')') {
                self.pos += 1;
                return Ok(CallArg::Call(name, args));
            }
            loop {
                self.depth += 1;
                let arg = self.arg();
                self.depth -= 1;
                args.push(arg?);
                self.skip_ws();
                match self.peek() {
                    Some(',') => self.pos += 1,
                    Some(')') => {
                        self.pos += 1;
                        break;
                    }
                    _ => {
                        return Err(self.error_at(
                            self.pos,
                            &format!("expected `,` or `)` in the arguments of `{name}`"),
                        ));
                    }
                }
            }
        }
        Ok(CallArg::Call(name, args))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_is_refused_off_a_plane_position() {
        let arc = SmoothSpec::parse("arc(0.6, 0.5)").unwrap();
        assert!(arc.build::<[f64; 2]>(60.0).is_ok());
        for err in [
            arc.build::<f64>(60.0).err(),
            arc.build::<[f64; 4]>(60.0).err(),
        ] {
            let msg = err.expect("arc off a 2-D channel is an error").to_string();
            assert!(msg.contains("2-D path"), "{msg}");
        }
    }

    #[test]
    fn spellings_parse_and_print_back() {
        for text in [
            "none",
            "spring(0.5, 0.2)",
            "fir(bspline(3), 0.3)",
            // Named easings print as the cubic they stand for.
            "simple(cubic(0.42, 0, 0.58, 1), 0.4)",
            "spline(0.25)",
            "tustin(msd(2, 170, 20))",
            "matched(lowpass(4, 0.05))",
            "series(lowpass(2, 0.05), spring(0.6, 0))",
            "parallel(0.25, fir(linear, 0.2), 0.75, spring(0.5, 0))",
            "arc(0.6, 0.8)",
        ] {
            let spec = SmoothSpec::parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            // Printing gives back the text as written (a printer that dropped or reordered
            // a parameter would reach a different fixed point), and that text parses to the
            // same spec.
            assert_eq!(spec.to_string(), text);
            assert_eq!(
                SmoothSpec::parse(&spec.to_string()).unwrap(),
                spec,
                "{text}"
            );
        }
        assert_eq!(
            SmoothSpec::parse("simple(ease-in-out, 0.4)").unwrap(),
            SmoothSpec::parse("simple(cubic(0.42, 0, 0.58, 1), 0.4)").unwrap()
        );
        assert_eq!(
            SmoothSpec::parse("spline(300ms)").unwrap(),
            SmoothSpec::Spline(0.3)
        );
        assert_eq!(
            SmoothSpec::parse(" spline( 0.3s ) ").unwrap(),
            SmoothSpec::Spline(0.3)
        );
    }

    #[test]
    fn bad_spellings_explain_themselves() {
        let cases = [
            ("spring(0.5, 1.5)", "bounce"),
            ("spring(0, 0)", "duration"),
            ("msd(-1, 100, 10)", "mass"),
            ("fir(3, 0.2)", "easing"),
            ("fir(bspline(3))", "takes an easing and a duration"),
            ("wobble(1)", "unknown system `wobble`"),
            ("parallel(0.5, spring(0.5, 0), 0.7, none)", "sum to"),
            ("zoh(fir(linear, 0.2))", "IIR"),
            ("spring(0.5, 0", "expected `,` or `)`"),
            ("spring(0.5, 0) x", "unexpected text"),
            ("lowpass(2.5, 0.1)", "poles"),
        ];
        crate::testing::assert_refused(&cases, SmoothSpec::parse);
        let spec = SmoothSpec::parse("arc(0.5, 1)").unwrap();
        assert!(spec.build::<f64>(60.0).is_err());
        assert!(spec.build::<[f64; 2]>(60.0).is_ok());
        assert!(smooth_samples(&SmoothSpec::Identity, &[0.0, f64::NAN], 60.0).is_err());
    }

    #[test]
    fn settle_time_of_a_fir_is_its_duration() {
        let spec = SmoothSpec::parse("fir(bspline(3), 0.5)").unwrap();
        let t = spec.settle_time(1e-3).unwrap();
        assert!(t > 0.4 && t <= 0.5 + 1.0 / 240.0, "{t}");
        assert!(
            SmoothSpec::parse("lowpass(1, 1000)")
                .unwrap()
                .settle_time(1e-3)
                .is_err()
        );
    }
}
