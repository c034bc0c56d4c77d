//! Trim paths: a unit whose strokes are drawn on or off by a Lottie trim (`tm`) is learned
//! as `animate(trim, …)` changes of its start, end and shift, read from the trim's own
//! properties at every frame, while its motion is sampled on the document with the trims
//! taken out (the player cuts the outline, so the trimmed drawing has no points that
//! keep their place from frame to frame).

use std::fmt::Write as _;

use gmotion::signals::Easing;
use gmotion_lottie::eval;
use gmotion_lottie::model::{Layer, ShapeItem, ShapeKind};
use gmotion_pipeline::LottieSource;
use kurbo::{ParamCurveArclen, PathSeg};

use crate::fit::Clock;

/// The grammar's rest state of a trim: the whole stroke, `(0, 1, 0)`.
const REST: Value = [0.0, 1.0, 0.0];

/// Trim values closer than this (a fraction of the length) hold.
const HOLD: f64 = 1e-6;

/// A trim value: start and end (fractions of the length, start first) and shift (turns).
pub type Value = [f64; 3];

/// One unit's trim, as sampled.
#[derive(Clone, Debug)]
pub struct UnitTrim {
    /// Its value at every frame.
    pub values: Vec<Value>,
    /// Why the language cannot say it, when it cannot (the unit keeps its drawing as the
    /// player draws it, reported).
    pub problem: Option<String>,
}

impl UnitTrim {
    /// Whether the trim changes over the frames.
    pub fn changes(&self) -> bool {
        self.values.windows(2).any(|w| off(&w[0], &w[1]) > HOLD)
    }
}

/// The trims of every unit of `src` (`None` for a unit without one), and the document
/// with the trims that can be learned taken out, to sample the motion on (`None` when
/// there is none).
pub fn find(src: &LottieSource) -> (Vec<Option<UnitTrim>>, Option<LottieSource>) {
    let doc = &src.document;
    let frames = ((doc.op - doc.ip).ceil().max(1.0)) as usize;
    let mut untrimmed = src.clone();
    let mut any = false;
    let out = src
        .units
        .iter()
        .map(|unit| {
            let &li = unit.layers.first()?;
            let layer = doc.layers.get(li)?;
            let items: Vec<&ShapeItem> = match unit.part {
                Some(p) => layer.shapes.get(p).into_iter().collect(),
                None => layer.shapes.iter().collect(),
            };
            let mut trims = Vec::new();
            let mut fills_cut = false;
            for item in items {
                collect(item, &mut trims, &mut fills_cut);
            }
            let first = trims.first()?;
            let values: Vec<Value> = (0..frames)
                .map(|f| value_at(first, layer, doc.ip + f as f64))
                .collect();
            let mut problem = None;
            if fills_cut {
                problem = Some("its trim paths cut a fill, and the language's trim draws strokes only".to_string());
            } else if trims.iter().any(|t| matches!(t.kind, ShapeKind::Trim { individually: true, .. })) {
                problem = Some("its trim paths trim its outlines as one run (`m` 2), and the language trims each on its own".to_string());
            } else if trims.iter().skip(1).any(|t| {
                (0..frames).any(|f| off(&value_at(t, layer, doc.ip + f as f64), &values[f]) > HOLD)
            }) {
                problem = Some("it has several trim paths that differ".to_string());
            }
            if problem.is_none() {
                any = true;
                if let Some(l) = untrimmed.document.layers.get_mut(li) {
                    match unit.part {
                        Some(p) => l.shapes.get_mut(p).into_iter().for_each(untrim),
                        None => l.shapes.iter_mut().for_each(untrim),
                    }
                }
            }
            Some(UnitTrim { values, problem })
        })
        .collect();
    (out, any.then_some(untrimmed))
}

/// The trim items under `item`, and whether a fill shares a group with one (the trim
/// cuts every outline of its group, filled ones too).
fn collect<'a>(item: &'a ShapeItem, trims: &mut Vec<&'a ShapeItem>, fills_cut: &mut bool) {
    if item.hidden {
        return;
    }
    if let ShapeKind::Group(items) = &item.kind {
        let trimmed = items
            .iter()
            .any(|i| !i.hidden && matches!(i.kind, ShapeKind::Trim { .. }));
        if trimmed && items.iter().any(has_fill) {
            *fills_cut = true;
        }
        for i in items {
            collect(i, trims, fills_cut);
        }
    } else if matches!(item.kind, ShapeKind::Trim { .. }) {
        trims.push(item);
    }
}

/// Whether `item` paints a fill (a trim above it would cut the filled outline too).
fn has_fill(item: &ShapeItem) -> bool {
    match &item.kind {
        ShapeKind::Fill { .. } => !item.hidden,
        ShapeKind::Gradient(g) => !item.hidden && !g.stroke,
        ShapeKind::Group(items) => !item.hidden && items.iter().any(has_fill),
        _ => false,
    }
}

/// Takes the trims under `item` out: a trim without properties keeps the whole outline.
fn untrim(item: &mut ShapeItem) {
    match &mut item.kind {
        ShapeKind::Group(items) => items.iter_mut().for_each(untrim),
        ShapeKind::Trim { s, e, o, .. } => {
            (*s, *e, *o) = (None, None, None);
        }
        _ => {}
    }
}

/// A trim item's value at composition frame `frame`, in the language's terms: start and
/// end clamped to 0 … 1, start first (Lottie swaps them when drawing), the offset in turns.
fn value_at(item: &ShapeItem, layer: &Layer, frame: f64) -> Value {
    let ShapeKind::Trim { s, e, o, .. } = &item.kind else {
        return REST;
    };
    let stretch = if layer.sr.abs() > 1e-9 { layer.sr } else { 1.0 };
    let t = (frame - layer.st) / stretch;
    let a = (eval::scalar(s.as_ref(), t, 0.0) / 100.0).clamp(0.0, 1.0);
    let b = (eval::scalar(e.as_ref(), t, 100.0) / 100.0).clamp(0.0, 1.0);
    let shift = eval::scalar(o.as_ref(), t, 0.0) / 360.0;
    [a.min(b), a.max(b), shift]
}

/// The largest difference of two trim values.
fn off(a: &Value, b: &Value) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `a` towards `b` by `p`.
fn lerp(a: &Value, b: &Value, p: f64) -> Value {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * p)
}

/// One piece of a learned trim: a slice and the change it plays, if any.
#[derive(Clone, Debug)]
pub struct Piece {
    /// Start, in seconds.
    pub t0: f64,
    /// End, in seconds.
    pub t1: f64,
    /// The change: its delay, easing and end value; `None` holds. On the first slice of a
    /// unit whose stroke starts trimmed, the change is played backwards (an inverted slice,
    /// from the value to the whole stroke).
    pub change: Option<(f64, Easing, Value)>,
    /// Whether the slice is inverted.
    pub inverted: bool,
}

/// A unit's learned trim.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// Its slices, covering the whole animation.
    pub pieces: Vec<Piece>,
    /// The largest error of the learned trim, as a fraction of the stroke's length.
    pub max_off: f64,
}

/// The learned trim's value at `t`.
pub fn model_at(pieces: &[Piece], t: f64) -> Value {
    let mut value = REST;
    for p in pieces {
        let Some((delay, ease, target)) = &p.change else {
            if t < p.t1 {
                return value;
            }
            continue;
        };
        if p.inverted {
            // Played backwards: from the target at the slice start to the state before
            // it at `t1 − delay`.
            let end = p.t1 - delay;
            if t < p.t1 {
                let u = if end > p.t0 {
                    ((end - t) / (end - p.t0)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                return lerp(&value, target, ease.apply(u));
            }
            continue;
        }
        let start = p.t0 + delay;
        if t < p.t1 {
            let u = if p.t1 > start {
                ((t - start) / (p.t1 - start)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            return lerp(&value, target, ease.apply(u));
        }
        value = *target;
    }
    value
}

/// Fits `trim` as slices of holds and changes with easings of the language, within `tol`
/// (a fraction of the length); `None` when the first slice cannot be said (the stroke
/// starts trimmed and does not first return to the whole stroke as one eased change).
pub fn fit(trim: &UnitTrim, clock: Clock, tol: f64) -> Option<Fitted> {
    let v = &trim.values;
    let n = v.len();
    let time = |f: usize| f as f64 / clock.fps;
    let eases = crate::fit::easings();
    let mut pieces = Vec::new();
    let mut state = REST;
    let mut at = 0.0;
    let mut f = 0;
    if n > 0 && off(&v[0], &REST) > tol {
        // The still draws the whole stroke: the first slice plays a change to frame 0's
        // value backwards, back to the whole stroke by the first frame that shows it.
        let e = (1..n).find(|&g| off(&v[g], &REST) <= HOLD)?;
        let ease = eases.iter().find(|ease| {
            (0..=e).all(|g| {
                let u = 1.0 - g as f64 / e as f64;
                off(&lerp(&REST, &v[0], ease.apply(u)), &v[g]) <= tol
            })
        })?;
        pieces.push(Piece {
            t0: 0.0,
            t1: time(e),
            change: Some((0.0, ease.clone(), v[0])),
            inverted: true,
        });
        at = time(e);
        f = e;
    }
    while f + 1 < n {
        if off(&v[f + 1], &v[f]) <= HOLD && off(&v[f], &state) <= tol {
            f += 1;
            continue;
        }
        let mut b = f + 1;
        while b + 1 < n && off(&v[b + 1], &v[b]) > HOLD {
            b += 1;
        }
        let mut a = f;
        while a < b {
            // A change from frame `a` to `end` (seconds) reaching `target`, eased by `ease`,
            // when it stays within the tolerance over frames `a ..= e`.
            let fits = |e: usize, end: f64, target: &Value, ease: &Easing| {
                (a..=e).all(|g| {
                    let u = (time(g) - time(a)) / (end - time(a));
                    off(&lerp(&state, target, ease.apply(u)), &v[g]) <= tol
                })
            };
            let found = (a + 1..=b).rev().find_map(|e| {
                eases.iter().find_map(|ease| {
                    // A change still running at the last frame ends with the animation:
                    // its end value is what the last frame's progress points to (a trim
                    // drawn off by the end reaches (1, 1) there, not at the last frame).
                    if e + 1 == n && clock.duration > time(e) + 1e-9 {
                        let p = ease.apply((time(e) - time(a)) / (clock.duration - time(a)));
                        let target: Value = std::array::from_fn(|i| {
                            let x = state[i] + (v[e][i] - state[i]) / p.max(1e-9);
                            (x * 1e4).round() / 1e4
                        });
                        let inside = target[0] >= 0.0 && target[1] <= 1.0 && target[0] <= target[1];
                        if p > 1e-6 && inside && fits(e, clock.duration, &target, ease) {
                            return Some((e, clock.duration, ease.clone(), target));
                        }
                    }
                    fits(e, time(e), &v[e], ease).then(|| (e, time(e), ease.clone(), v[e]))
                })
            });
            let (e, end, ease, target) =
                found.unwrap_or((a + 1, time(a + 1), Easing::Linear, v[a + 1]));
            pieces.push(Piece {
                t0: at,
                t1: end,
                change: Some((time(a) - at, ease, target)),
                inverted: false,
            });
            state = target;
            at = end;
            a = e;
        }
        f = b;
    }
    if clock.duration - at > 1e-6 || pieces.is_empty() {
        pieces.push(Piece {
            t0: at,
            t1: clock.duration,
            change: None,
            inverted: false,
        });
    } else if let Some(last) = pieces.last_mut() {
        last.t1 = clock.duration;
    }
    let max_off = (0..n)
        .map(|g| off(&model_at(&pieces, time(g)), &v[g]))
        .fold(0.0, f64::max);
    Some(Fitted { pieces, max_off })
}

/// The length of the longest stroked outline of `node`, on the canvas: what a trim
/// fraction's error is measured against, in pixels.
pub fn stroke_length(node: &gmotion::scene::Node, m: kurbo::Affine) -> f64 {
    use gmotion::scene::Node;
    match node {
        Node::Path(p) if p.stroke.is_some() => (m * p.path.clone())
            .segments()
            .map(|s: PathSeg| s.arclen(1e-3))
            .sum(),
        Node::Path(_) | Node::Image(_) => 0.0,
        Node::Group(g) => g
            .children
            .iter()
            .map(|c| stroke_length(c, m * g.transform))
            .fold(0.0, f64::max),
    }
}

/// Writes the trim rules of one unit (shape tag `tag`) into `out`; returns how many.
pub fn write(out: &mut String, tag: &str, fitted: &Fitted, clock: Clock) -> usize {
    let fractions: Vec<f64> = fitted
        .pieces
        .iter()
        .map(|p| (p.t1 - p.t0) / clock.duration)
        .collect();
    let mut rules = 0;
    let whole = fitted.pieces.len() == 1;
    if !whole {
        let names: Vec<String> = (0..fitted.pieces.len()).map(|k| format!("q{k}")).collect();
        let _ = writeln!(
            out,
            "timesplit({}) : [all, {tag}] -> [{}]",
            crate::rules::tidy(&fractions).join(", "),
            names.join(", ")
        );
        rules += 1;
    }
    for (k, p) in fitted.pieces.iter().enumerate() {
        let Some((delay, ease, [s, e, shift])) = &p.change else {
            continue;
        };
        let slice = if whole {
            "all".to_string()
        } else {
            format!("q{k}")
        };
        let value = if crate::rules::num(*shift, 4) == "0" {
            format!(
                "({}, {})",
                crate::rules::num(*s, 4),
                crate::rules::num(*e, 4)
            )
        } else {
            format!(
                "({}, {}, {})",
                crate::rules::num(*s, 4),
                crate::rules::num(*e, 4),
                crate::rules::num(*shift, 4)
            )
        };
        let ease = crate::rules::ease_text(ease).map_or(String::new(), |e| format!(", ease={e}"));
        let inv = if p.inverted { "inv_" } else { "" };
        let _ = writeln!(
            out,
            "animate(trim, local, {}, {value}{ease}) : [{slice}, {tag}] -> [{inv}trimmed{k}]",
            crate::rules::num(*delay, 6)
        );
        rules += 1;
    }
    out.push('\n');
    rules
}
