//! Outlines that change: a unit drawn by one path whose outline changes over the frames
//! (a morph, keyed path data) is learned as `animate(morph, world, …, "PATH")` changes to
//! its outline at the end of each piece, nested in the slices of its motion and paint (a
//! split keeps their changes running). Each piece is checked as the engine plays it: both
//! outlines brought to one structure ([`gmotion::morph::correspond`]), their control
//! points moved in straight lines, compared with the drawn outline at equal fractions of
//! the length.

use std::fmt::Write as _;

use gmotion::morph::correspond;
use gmotion::signals::Easing;
use kurbo::{BezPath, ParamCurve, ParamCurveArclen, PathEl, PathSeg, Point};

use crate::fit::{Clock, Slice};
use crate::sample::Outline;

/// Points compared per subpath, at equal fractions of its length.
const SAMPLES: usize = 32;

/// Two outlines whose points differ by less than this (pixels) hold.
const HOLD_PX: f64 = 1e-3;

/// One morph piece: a slice of a leaf and the change it plays, if any.
#[derive(Clone, Debug)]
pub struct Piece {
    /// Start, in seconds.
    pub t0: f64,
    /// End, in seconds.
    pub t1: f64,
    /// The delay, easing and target outline (on the canvas, where the still draws the
    /// unit); `None` holds.
    pub change: Option<(f64, Easing, BezPath)>,
}

/// A unit's learned outline: the morph pieces of each leaf of its slices.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// Per leaf (in the order of [`leaves`]), its pieces.
    pub leaves: Vec<Vec<Piece>>,
    /// The largest distance, over the frames, between the learned outline and the drawn
    /// one (before the unit's motion), in pixels.
    pub max_px: f64,
}

/// The leaves of a unit's slices, in the order the grammar writes them: each slice's paint
/// slices, or the slice itself when its paint holds; the whole animation when it has none.
pub fn leaves(slices: &[Slice], clock: Clock) -> Vec<(f64, f64)> {
    if slices.is_empty() {
        return vec![(0.0, clock.duration)];
    }
    slices
        .iter()
        .flat_map(|s| {
            if s.inner.is_empty() {
                vec![(s.t0, s.t1)]
            } else {
                s.inner.iter().map(|i| (i.t0, i.t1)).collect()
            }
        })
        .collect()
}

/// Points at equal fractions of each subpath's length.
fn samples(path: &BezPath) -> Vec<Point> {
    let mut out = Vec::new();
    let mut sub: Vec<PathSeg> = Vec::new();
    let flush = |sub: &mut Vec<PathSeg>, out: &mut Vec<Point>| {
        if sub.is_empty() {
            return;
        }
        let lens: Vec<f64> = sub.iter().map(|s| s.arclen(1e-4)).collect();
        let total: f64 = lens.iter().sum();
        for k in 0..SAMPLES {
            let mut want = total * k as f64 / SAMPLES as f64;
            let mut i = 0;
            while i + 1 < sub.len() && want > lens[i] {
                want -= lens[i];
                i += 1;
            }
            let t = if lens[i] > 0.0 {
                sub[i].inv_arclen(want.min(lens[i]), 1e-4)
            } else {
                0.0
            };
            out.push(sub[i].eval(t));
        }
        sub.clear();
    };
    for seg in path.segments() {
        // `segments` runs over subpaths without saying where one ends: a segment that does
        // not start where the last one ended starts a new subpath.
        if let Some(prev) = sub.last()
            && (prev.end() - seg.start()).hypot() > 1e-9
        {
            flush(&mut sub, &mut out);
        }
        sub.push(seg);
    }
    flush(&mut sub, &mut out);
    if out.is_empty() {
        // A path of points only: its points.
        out.extend(path.elements().iter().filter_map(|e| match e {
            PathEl::MoveTo(p) => Some(*p),
            _ => None,
        }));
    }
    out
}

/// The largest distance between two outlines' points at equal fractions of the length.
fn distance(a: &[Point], b: &[Point]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).hypot())
        .fold(0.0, f64::max)
}

/// The in-between of `a` and `b` (of one structure) at `p`, as the morph draws it.
fn between(a: &BezPath, b: &BezPath, p: f64) -> BezPath {
    let lerp = |x: Point, y: Point| x.lerp(y, p);
    BezPath::from_vec(
        a.elements()
            .iter()
            .zip(b.elements())
            .map(|(x, y)| match (*x, *y) {
                (PathEl::MoveTo(u), PathEl::MoveTo(v)) => PathEl::MoveTo(lerp(u, v)),
                (PathEl::LineTo(u), PathEl::LineTo(v)) => PathEl::LineTo(lerp(u, v)),
                (PathEl::QuadTo(u1, u), PathEl::QuadTo(v1, v)) => {
                    PathEl::QuadTo(lerp(u1, v1), lerp(u, v))
                }
                (PathEl::CurveTo(u1, u2, u), PathEl::CurveTo(v1, v2, v)) => {
                    PathEl::CurveTo(lerp(u1, v1), lerp(u2, v2), lerp(u, v))
                }
                _ => *x,
            })
            .collect(),
    )
}

/// Fits the outline of `o` as morph pieces inside each of `leaves`, within `tol` pixels;
/// the still draws frame 0's outline. `None` when the outline never changes.
pub fn fit(o: &Outline, leaves: &[(f64, f64)], clock: Clock, tol: f64) -> Option<Fitted> {
    let n = o.frames.len();
    if n == 0 {
        return None;
    }
    let placed: Vec<BezPath> = o.frames.iter().map(|p| o.world * p.clone()).collect();
    let drawn: Vec<Vec<Point>> = placed.iter().map(samples).collect();
    let time = |f: usize| f as f64 / clock.fps;
    let eases = crate::fit::easings();
    let mut state = placed[0].clone();
    let mut state_pts = drawn[0].clone();
    let mut out = Vec::with_capacity(leaves.len());
    let mut max_px = 0.0f64;
    for &(t0, t1) in leaves {
        let lo = ((t0 * clock.fps) - 1e-6).ceil().max(0.0) as usize;
        let hi = (((t1 * clock.fps) + 1e-6).floor() as usize).min(n - 1);
        let mut pieces = Vec::new();
        let mut at = t0;
        let mut f = lo;
        while f < hi {
            if distance(&drawn[f + 1], &drawn[f]) <= HOLD_PX
                && distance(&drawn[f], &state_pts) <= tol
            {
                f += 1;
                continue;
            }
            let mut b = f + 1;
            while b < hi && distance(&drawn[b + 1], &drawn[b]) > HOLD_PX {
                b += 1;
            }
            let mut a = f;
            while a < b {
                // The piece grows a frame at a time while one easing keeps every frame of
                // it within the tolerance (a one-frame piece is exact at both ends).
                let try_end = |e: usize| -> Option<Easing> {
                    let (from, to) = correspond(&state, &placed[e]);
                    eases
                        .iter()
                        .find(|ease| {
                            (a + 1..e).all(|g| {
                                let u = (time(g) - time(a)) / (time(e) - time(a));
                                let now = samples(&between(&from, &to, ease.apply(u)));
                                distance(&now, &drawn[g]) <= tol
                            })
                        })
                        .cloned()
                };
                let mut best = (a + 1, try_end(a + 1).unwrap_or(Easing::Linear));
                for e in a + 2..=b {
                    match try_end(e) {
                        Some(ease) => best = (e, ease),
                        None => break,
                    }
                }
                let (e, ease) = best;
                pieces.push(Piece {
                    t0: at,
                    t1: time(e),
                    change: Some((time(a) - at, ease, placed[e].clone())),
                });
                state = placed[e].clone();
                state_pts = drawn[e].clone();
                at = time(e);
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
    // The error as played: every frame against the pieces' in-betweens.
    let mut from = placed[0].clone();
    let all: Vec<&Piece> = out.iter().flatten().collect();
    let mut k = 0;
    for (g, pts) in drawn.iter().enumerate() {
        let t = time(g);
        while k < all.len() && t > all[k].t1 + 1e-9 {
            if let Some((_, _, target)) = &all[k].change {
                from = target.clone();
            }
            k += 1;
        }
        let now = match all.get(k).and_then(|p| p.change.as_ref().map(|c| (p, c))) {
            Some((p, (delay, ease, target))) => {
                let s = p.t0 + delay;
                let u = if p.t1 > s {
                    ((t - s) / (p.t1 - s)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                let (a, b) = correspond(&from, target);
                samples(&between(&a, &b, ease.apply(u)))
            }
            None => samples(&from),
        };
        max_px = max_px.max(distance(&now, pts));
    }
    Some(Fitted {
        leaves: out,
        max_px,
    })
}

/// SVG path data of `p`, in canvas units to the thousandth.
fn path_data(p: &BezPath) -> String {
    let n = |x: f64| crate::rules::num(x, 3);
    let pt = |q: Point| format!("{} {}", n(q.x), n(q.y));
    p.elements()
        .iter()
        .map(|e| match *e {
            PathEl::MoveTo(q) => format!("M {}", pt(q)),
            PathEl::LineTo(q) => format!("L {}", pt(q)),
            PathEl::QuadTo(a, q) => format!("Q {} {}", pt(a), pt(q)),
            PathEl::CurveTo(a, b, q) => format!("C {} {} {}", pt(a), pt(b), pt(q)),
            PathEl::ClosePath => "Z".to_string(),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes the morph rules of leaf `leaf` (its slice tag `slice`, the unit's shape tag
/// `tag`) into `out`; returns how many.
pub fn write(out: &mut String, slice: &str, tag: &str, leaf: usize, pieces: &[Piece]) -> usize {
    let Some((first, last)) = pieces.first().zip(pieces.last()) else {
        return 0;
    };
    let d = last.t1 - first.t0;
    let mut rules = 0;
    let whole = pieces.len() == 1;
    if !whole {
        let fractions: Vec<f64> = pieces.iter().map(|p| (p.t1 - p.t0) / d).collect();
        let names: Vec<String> = (0..pieces.len()).map(|k| format!("r{leaf}_{k}")).collect();
        let _ = writeln!(
            out,
            "timesplit({}) : [{slice}, {tag}] -> [{}]",
            crate::rules::tidy(&fractions).join(", "),
            names.join(", ")
        );
        rules += 1;
    }
    for (k, p) in pieces.iter().enumerate() {
        let Some((delay, ease, target)) = &p.change else {
            continue;
        };
        let name = if whole {
            slice.to_string()
        } else {
            format!("r{leaf}_{k}")
        };
        let ease = crate::rules::ease_text(ease).map_or(String::new(), |e| format!(", ease={e}"));
        let _ = writeln!(
            out,
            "animate(morph, world, {}, \"{}\"{ease}) : [{name}, {tag}] -> [g{leaf}_{k}]",
            crate::rules::num(*delay, 6),
            path_data(target)
        );
        rules += 1;
    }
    rules
}

/// Sets the one path under `node` to `path` (a one-path unit's outline in the still).
pub fn set_path(node: &mut gmotion::scene::Node, path: &BezPath) {
    use gmotion::scene::Node;
    match node {
        Node::Path(p) => p.path = path.clone(),
        Node::Group(g) => g.children.iter_mut().for_each(|c| set_path(c, path)),
        Node::Image(_) => {}
    }
}
