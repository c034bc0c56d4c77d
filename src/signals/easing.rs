//! Easing functions: maps from linear progress `u ∈ [0,1]` to eased progress.

/// An easing curve. `apply(0) = 0` and `apply(1) = 1` for every variant.
#[derive(Clone, Debug, PartialEq)]
pub enum Easing {
    /// Identity.
    Linear,
    /// CSS `cubic-bezier(x1, y1, x2, y2)`.
    CubicBezier([f64; 4]),
}

impl Easing {
    /// Eased progress at linear progress `u` (clamped to `[0,1]`).
    pub fn apply(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        match self {
            Easing::Linear => u,
            Easing::CubicBezier(p) => cubic_bezier(*p, u),
        }
    }

    /// The CSS cubic-bezier control points, when the curve is one (exporters use them as
    /// keyframe tangents).
    pub fn as_cubic_bezier(&self) -> Option<[f64; 4]> {
        match self {
            Easing::Linear => Some([0.0, 0.0, 1.0, 1.0]),
            Easing::CubicBezier(p) => Some(*p),
        }
    }

    /// Builds an easing from its grammar spelling: a name and numeric arguments, e.g.
    /// `cubic(0.4, 0, 0.2, 1)`, `ease-in-out`, `linear`.
    pub fn from_call(name: &str, args: &[f64]) -> Result<Easing, String> {
        let none = |e: Easing| {
            if args.is_empty() {
                Ok(e)
            } else {
                Err(format!("easing `{name}` takes no arguments"))
            }
        };
        match name {
            "linear" => none(Easing::Linear),
            "ease" => none(Easing::CubicBezier([0.25, 0.1, 0.25, 1.0])),
            "ease_in" | "ease-in" => none(Easing::CubicBezier([0.42, 0.0, 1.0, 1.0])),
            "ease_out" | "ease-out" => none(Easing::CubicBezier([0.0, 0.0, 0.58, 1.0])),
            "ease_in_out" | "ease-in-out" => none(Easing::CubicBezier([0.42, 0.0, 0.58, 1.0])),
            "cubic" | "cubic_bezier" | "cubic-bezier" => {
                let [x1, y1, x2, y2] = args else {
                    return Err(format!("`{name}` takes four numbers x1, y1, x2, y2"));
                };
                if !(0.0..=1.0).contains(x1) || !(0.0..=1.0).contains(x2) {
                    return Err(format!("`{name}`: x1 and x2 must lie in [0, 1]"));
                }
                if args.iter().any(|v| !v.is_finite()) {
                    return Err(format!("`{name}`: control points must be finite"));
                }
                Ok(Easing::CubicBezier([*x1, *y1, *x2, *y2]))
            }
            _ => Err(format!("unknown easing `{name}`")),
        }
    }
}

/// Solves the CSS cubic-bezier timing function at `x` (Newton, then bisection fallback).
fn cubic_bezier([x1, y1, x2, y2]: [f64; 4], x: f64) -> f64 {
    let bez = |a: f64, b: f64, t: f64| {
        let mt = 1.0 - t;
        3.0 * mt * mt * t * a + 3.0 * mt * t * t * b + t * t * t
    };
    let dbez = |a: f64, b: f64, t: f64| {
        let mt = 1.0 - t;
        3.0 * mt * mt * a + 6.0 * mt * t * (b - a) + 3.0 * t * t * (1.0 - b)
    };
    let mut t = x;
    for _ in 0..8 {
        let err = bez(x1, x2, t) - x;
        if err.abs() < 1e-9 {
            return bez(y1, y2, t);
        }
        let d = dbez(x1, x2, t);
        if d.abs() < 1e-7 {
            break;
        }
        t = (t - err / d).clamp(0.0, 1.0);
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    t = x;
    for _ in 0..60 {
        if bez(x1, x2, t) < x {
            lo = t;
        } else {
            hi = t;
        }
        t = 0.5 * (lo + hi);
    }
    bez(y1, y2, t)
}
