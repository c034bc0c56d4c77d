//! Strokes that change: a unit whose stroke colour or width changes is learned as
//! `animate(border, …)` and `animate(stroke-width, …)` changes nested in the leaves of its
//! slices, as its morphs are ([`crate::outline`]): a split keeps the motion and paint
//! running. The still draws frame 0's stroke, where the changes start.

use std::fmt::Write as _;

use gmotion::signals::Easing;

use crate::fit::Clock;

/// A stroke as the grammar changes it: red, green, blue (0 … 1) and width.
pub type Value = [f64; 4];

/// Changes smaller than this hold.
const HOLD: f64 = 1e-4;

/// One stroke piece of a leaf: its span and the change it plays, if any.
#[derive(Clone, Debug)]
pub struct Piece {
    /// Start, in seconds.
    pub t0: f64,
    /// End, in seconds.
    pub t1: f64,
    /// The delay, easing and end value; `None` holds.
    pub change: Option<(f64, Easing, Value)>,
}

/// A unit's learned stroke.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// Per leaf of its slices ([`crate::outline::leaves`]), its pieces.
    pub leaves: Vec<Vec<Piece>>,
    /// Frame 0's stroke: what the still draws.
    pub first: Value,
    /// The largest colour channel error over the frames (0 … 1).
    pub max_colour: f64,
    /// The largest width error over the frames.
    pub max_width: f64,
}

/// The stroke values of every frame, when the unit has a solid stroke at every frame
/// whose opacity holds (the language changes no stroke opacity), else `None`.
pub fn values(samples: &[Option<[f32; 5]>]) -> Option<Vec<Value>> {
    let first = samples.first().copied().flatten()?;
    samples
        .iter()
        .map(|s| {
            let s = (*s)?;
            ((s[3] - first[3]).abs() <= 1e-4).then_some([
                f64::from(s[0]),
                f64::from(s[1]),
                f64::from(s[2]),
                f64::from(s[4]),
            ])
        })
        .collect()
}

/// Whether two values differ by more than the tolerances (a colour channel by `colour`,
/// the width by `width`).
fn apart(a: &Value, b: &Value, colour: f64, width: f64) -> bool {
    (0..3).any(|i| (a[i] - b[i]).abs() > colour) || (a[3] - b[3]).abs() > width
}

/// `a` towards `b` by `p`.
fn lerp(a: &Value, b: &Value, p: f64) -> Value {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * p)
}

/// Fits the stroke `v` (one value per frame) as changes inside each of `leaves`, within
/// `colour` (a channel) and `width`; `None` when it never changes.
pub fn fit(
    v: &[Value],
    leaves: &[(f64, f64)],
    clock: Clock,
    colour: f64,
    width: f64,
) -> Option<Fitted> {
    let n = v.len();
    if n == 0 || v.iter().all(|x| !apart(x, &v[0], HOLD, HOLD)) {
        return None;
    }
    let time = |f: usize| f as f64 / clock.fps;
    let eases = crate::fit::easings();
    let mut state = v[0];
    let mut out = Vec::with_capacity(leaves.len());
    for &(t0, t1) in leaves {
        let lo = ((t0 * clock.fps) - 1e-6).ceil().max(0.0) as usize;
        let hi = (((t1 * clock.fps) + 1e-6).floor() as usize).min(n - 1);
        let mut pieces = Vec::new();
        let mut at = t0;
        let mut f = lo;
        while f < hi {
            if !apart(&v[f + 1], &v[f], HOLD, HOLD) && !apart(&v[f], &state, colour, width) {
                f += 1;
                continue;
            }
            let mut b = f + 1;
            while b < hi && apart(&v[b + 1], &v[b], HOLD, HOLD) {
                b += 1;
            }
            let mut a = f;
            while a < b {
                // A change from frame `a` to `end` (seconds) reaching `to`, when every
                // frame up to `e` stays within the tolerances.
                let fits = |e: usize, end: f64, to: &Value, ease: &Easing| {
                    (a + 1..=e).all(|g| {
                        let u = (time(g) - time(a)) / (end - time(a));
                        !apart(&lerp(&state, to, ease.apply(u)), &v[g], colour, width)
                    })
                };
                let found = (a + 1..=b).rev().find_map(|e| {
                    eases.iter().find_map(|ease| {
                        // A change still running at the last frame (and leaf) ends with
                        // the leaf: its end value is where the last frame's progress
                        // points.
                        if e + 1 == n && t1 > time(e) + 1e-9 {
                            let p = ease.apply((time(e) - time(a)) / (t1 - time(a)));
                            let to: Value = std::array::from_fn(|i| {
                                let x = state[i] + (v[e][i] - state[i]) / p.max(1e-9);
                                (x * 1e4).round() / 1e4
                            });
                            let inside =
                                to[..3].iter().all(|c| (0.0..=1.0).contains(c)) && to[3] >= 0.0;
                            if p > 1e-6 && inside && fits(e, t1, &to, ease) {
                                return Some((e, t1, ease.clone(), to));
                            }
                        }
                        fits(e, time(e), &v[e], ease).then(|| (e, time(e), ease.clone(), v[e]))
                    })
                });
                let (e, end, ease, to) =
                    found.unwrap_or((a + 1, time(a + 1), Easing::Linear, v[a + 1]));
                pieces.push(Piece {
                    t0: at,
                    t1: end,
                    change: Some((time(a) - at, ease, to)),
                });
                state = to;
                at = end;
                a = e;
            }
            f = b;
        }
        if !pieces.is_empty() && t1 - at > 1e-9 {
            pieces.push(Piece {
                t0: at,
                t1,
                change: None,
            });
        }
        if let Some(last) = pieces.last_mut() {
            last.t1 = t1;
        }
        out.push(pieces);
    }
    // The error as played, every frame.
    let all: Vec<&Piece> = out.iter().flatten().collect();
    let (mut max_colour, mut max_width) = (0.0f64, 0.0f64);
    let mut from = v[0];
    let mut k = 0;
    for (g, want) in v.iter().enumerate() {
        let t = time(g);
        while k < all.len() && t > all[k].t1 + 1e-9 {
            if let Some((_, _, to)) = &all[k].change {
                from = *to;
            }
            k += 1;
        }
        let now = match all.get(k).and_then(|p| p.change.as_ref().map(|c| (p, c))) {
            Some((p, (delay, ease, to))) => {
                let s = p.t0 + delay;
                let u = if p.t1 > s {
                    ((t - s) / (p.t1 - s)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                lerp(&from, to, ease.apply(u))
            }
            None => from,
        };
        for i in 0..3 {
            max_colour = max_colour.max((now[i] - want[i]).abs());
        }
        max_width = max_width.max((now[3] - want[3]).abs());
    }
    Some(Fitted {
        leaves: out,
        first: v[0],
        max_colour,
        max_width,
    })
}

/// Writes the stroke rules of leaf `leaf` (its slice tag `slice`, the unit's shape tag
/// `tag`) into `out`; returns how many.
pub fn write(out: &mut String, slice: &str, tag: &str, leaf: usize, pieces: &[Piece]) -> usize {
    let num = crate::rules::num;
    let Some((first, last)) = pieces.first().zip(pieces.last()) else {
        return 0;
    };
    let d = last.t1 - first.t0;
    let mut rules = 0;
    let whole = pieces.len() == 1;
    if !whole {
        let fractions: Vec<f64> = pieces.iter().map(|p| (p.t1 - p.t0) / d).collect();
        let names: Vec<String> = (0..pieces.len()).map(|k| format!("s{leaf}_{k}")).collect();
        let _ = writeln!(
            out,
            "timesplit({}) : [{slice}, {tag}] -> [{}]",
            crate::rules::tidy(&fractions).join(", "),
            names.join(", ")
        );
        rules += 1;
    }
    let mut before: Option<&Value> = None;
    for (k, p) in pieces.iter().enumerate() {
        let Some((delay, ease, to)) = &p.change else {
            continue;
        };
        let mut name = if whole {
            slice.to_string()
        } else {
            format!("s{leaf}_{k}")
        };
        let ease = crate::rules::ease_text(ease).map_or(String::new(), |e| format!(", ease={e}"));
        let delay = num(*delay, 6);
        // Only what changes is written: a colour that holds keeps its value, as does a
        // width (the first piece writes both, not knowing the state it starts from).
        let colour = before.is_none_or(|b| apart(b, &[to[0], to[1], to[2], b[3]], HOLD, HOLD));
        let width = before.is_none_or(|b| (b[3] - to[3]).abs() > HOLD);
        if colour {
            let _ = writeln!(
                out,
                "animate(border, local, {delay}, rgb({}, {}, {}){ease}) : [{name}, {tag}] -> [b{leaf}_{k}]",
                num(to[0] * 255.0, 2),
                num(to[1] * 255.0, 2),
                num(to[2] * 255.0, 2)
            );
            name = format!("b{leaf}_{k}");
            rules += 1;
        }
        if width {
            let _ = writeln!(
                out,
                "animate(stroke-width, local, {delay}, {}{ease}) : [{name}, {tag}] -> [w{leaf}_{k}]",
                num(to[3], 4)
            );
            rules += 1;
        }
        before = Some(to);
    }
    rules
}

/// Paints every solid stroke under `node` with `v`'s colour and width (the still's stroke,
/// where the changes start).
pub fn restroke(node: &mut gmotion::scene::Node, v: &Value) {
    use gmotion::scene::{Node, Paint};
    match node {
        Node::Path(p) => {
            if let Some(s) = p.stroke.as_mut()
                && let Paint::Solid(c) = &mut s.paint
            {
                (c.r, c.g, c.b) = (v[0] as f32, v[1] as f32, v[2] as f32);
                s.width = v[3];
            }
        }
        Node::Group(g) => g.children.iter_mut().for_each(|c| restroke(c, v)),
        Node::Image(_) => {}
    }
}
