//! Slicing and fitting: a unit's sampled motion cut at its change points into pieces, each
//! fitted as one `animate` with an easing of the language, and the motion the grammar
//! gives back evaluated as the engine composes it (so every error is measured on what
//! `animate` will play, not on the samples).

use gmotion::motion::Component;
use gmotion::signals::Easing;
use kurbo::{Affine, Point, Vec2};

use crate::sample::UnitSamples;

/// Two frames whose points move less than this (pixels) hold: keyframed holds are exact.
const HOLD_PX: f64 = 1e-3;

/// Opacity or colour changes smaller than this hold.
const HOLD_OPACITY: f64 = 1e-4;

/// Where a piece's motion turns and scales about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pivot {
    /// The unit's centroid where the slice begins (`local`).
    Local,
    /// A point of the canvas (`world`, written `translate(p) … translate(-p)`).
    World(Point),
}

/// One piece of motion: the change a slice plays after its leading hold.
#[derive(Clone, Debug)]
pub struct Move {
    /// The hold before the change, in seconds (the `animate` offset).
    pub delay: f64,
    /// The progress curve.
    pub ease: Easing,
    /// What changes.
    pub change: Change,
}

/// What a piece changes.
#[derive(Clone, Debug)]
pub enum Change {
    /// An affine motion: its components (about the pivot) and the pivot.
    Affine(Vec<Component>, Pivot),
    /// The opacity factor, the fill colour or both change to these.
    Paint(Paint),
}

/// A change of paint: the opacity factor and the fill colour (RGB, 0 … 1) it ends at,
/// each only when it changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paint {
    /// The opacity factor's end value.
    pub opacity: Option<f64>,
    /// The fill colour's end value.
    pub fill: Option<[f64; 3]>,
}

/// The paint values the model tracks: the opacity factor, then the fill's red, green and
/// blue.
pub type PaintValue = [f64; 4];

/// A slice of a unit's timeline: a span, and the piece it plays, if any.
#[derive(Clone, Debug)]
pub struct Slice {
    /// Start, in seconds.
    pub t0: f64,
    /// End, in seconds.
    pub t1: f64,
    /// Its motion; `None` holds.
    pub play: Option<Move>,
    /// The paint slices inside it (empty when opacity and fill hold through it).
    pub inner: Vec<Slice>,
    /// When it is the inverted twin of an earlier slice (`inv_…`), that slice's index: it
    /// plays that slice's change backwards, ending its offset before its own end.
    pub twin_of: Option<usize>,
}

/// A unit's learned timeline and how well it reproduces the samples.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// Its slices, covering the whole animation (empty when it never moves).
    pub slices: Vec<Slice>,
    /// The largest error in pixels of the learned motion over every frame.
    pub max_px: f64,
    /// The largest opacity or fill channel error over every frame (0 … 1).
    pub max_opacity: f64,
}

/// The timing of the samples.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    /// Frames per second.
    pub fps: f64,
    /// The animation's length in seconds.
    pub duration: f64,
}

impl Clock {
    fn time(&self, f: f64) -> f64 {
        f / self.fps
    }
}

/// The easings tried on every piece, simplest first (a tie keeps the first); trims,
/// outlines and strokes try the same.
pub(crate) fn easings() -> Vec<Easing> {
    let mut v = vec![Easing::Linear];
    for name in ["ease", "ease-in", "ease-out", "ease-in-out"] {
        if let Ok(e) = Easing::from_call(name, &[]) {
            v.push(e);
        }
    }
    // After Effects' "Easy Ease" and its one-sided forms, as Bodymovin writes them.
    for c in [
        [0.333, 0.0, 0.667, 1.0],
        [0.333, 0.0, 0.833, 0.833],
        [0.167, 0.167, 0.667, 1.0],
    ] {
        v.push(Easing::CubicBezier(c));
    }
    v
}

/// The offsets, in frames, at which a piece next to a hold may start or end between
/// frames (a stagger of 0.15 s at 30 fps starts half way between two frames).
const SUBFRAME: [f64; 8] = [0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875];

/// The change of a piece at progress `p`: `translate(P) · C(p) · translate(-P)`.
pub fn change_at(comps: &[Component], pivot: Point, p: f64) -> Affine {
    let mut m = Affine::translate(pivot.to_vec2());
    for c in comps {
        m *= c.at(p);
    }
    m * Affine::translate(-pivot.to_vec2())
}

/// Progress of a change running `[s, e]` at time `t`.
fn progress(ease: &Easing, s: f64, e: f64, t: f64) -> f64 {
    if e <= s {
        return if t >= e { 1.0 } else { 0.0 };
    }
    ease.apply((t - s) / (e - s))
}

/// The largest distance between the points carried by `a` and by `b`.
fn px(points: &[Point], a: Affine, b: Affine) -> f64 {
    points
        .iter()
        .map(|p| (a * *p - b * *p).hypot())
        .fold(0.0, f64::max)
}

/// The rotation angle of an affine's linear part, in degrees.
fn angle(m: Affine) -> f64 {
    let c = m.as_coeffs();
    c[1].atan2(c[0]).to_degrees()
}

/// `a` written as components about `pivot` whose value at progress 1 is `a`: translate,
/// rotate by `turn` degrees (the unwrapped angle), skew, scale; a raw matrix when the
/// linear part is degenerate.
fn components(a: Affine, pivot: Point, turn: f64) -> Vec<Component> {
    let [m00, m10, m01, m11, bx, by] = a.as_coeffs();
    // a·x = P + T + L(x − P), so T = b − P + L·P.
    let lin = Affine::new([m00, m10, m01, m11, 0.0, 0.0]);
    let t = Vec2::new(bx, by) - pivot.to_vec2() + (lin * pivot).to_vec2();
    let sx = m10.hypot(m00);
    let th = m10.atan2(m00);
    let (c, s) = (th.cos(), th.sin());
    let m = c * m01 + s * m11;
    let sy = -s * m01 + c * m11;
    let mut out = Vec::new();
    if t.hypot() > 1e-9 {
        out.push(Component::Translate(t));
    }
    if sx < 1e-9 || sy.abs() < 1e-9 {
        // Scaled to nothing: no angle to read; the matrix is interpolated entry by entry.
        out.push(Component::Matrix(lin));
        return out;
    }
    // Turn by the unwrapped angle, which agrees with the matrix's up to whole turns.
    let k = ((turn - th.to_degrees()) / 360.0).round();
    let rot = th.to_degrees() + 360.0 * k;
    if rot.abs() > 1e-9 {
        out.push(Component::Rotate(rot));
    }
    let skew = (m / sy).atan().to_degrees();
    if skew.abs() > 1e-6 {
        out.push(Component::Skew(skew, 0.0));
    }
    if (sx - 1.0).abs() > 1e-9 || (sy - 1.0).abs() > 1e-9 {
        out.push(Component::Scale(Vec2::new(sx, sy)));
    }
    out
}

/// Fits one unit: its affine pieces, then its paint pieces inside them.
pub fn fit(unit: &UnitSamples, clock: Clock, tol_px: f64, tol_opacity: f64) -> Fitted {
    let fitted = fit_with(unit, clock, tol_px, tol_opacity, true);
    // A twin plays its slice's rules backwards and can take no paint change of its own:
    // where paint changes during a twin or its slice, the unit is fitted without twins.
    let painted_twin = fitted.slices.iter().any(|s| {
        s.twin_of.is_some_and(|i| {
            !s.inner.is_empty() || fitted.slices.get(i).is_some_and(|f| !f.inner.is_empty())
        })
    });
    if painted_twin {
        fit_with(unit, clock, tol_px, tol_opacity, false)
    } else {
        fitted
    }
}

/// [`fit`], finding inverted twins or not (a unit whose outline changes has none: its
/// morphs are nested in its slices, which a twin would play backwards).
pub fn fit_with(
    unit: &UnitSamples,
    clock: Clock,
    tol_px: f64,
    tol_opacity: f64,
    with_twins: bool,
) -> Fitted {
    let pts = points_of(unit);
    let n = unit.motion.len();
    let eases = easings();
    let mut slices = Vec::new();
    // The modelled state where the next piece starts, and when.
    let mut state = Affine::IDENTITY;
    let mut at = 0.0;
    let mut f = 0usize;
    while f + 1 < n {
        // Skip holds: frames that do not move from the modelled state.
        if px(&pts, unit.motion[f + 1], unit.motion[f]) <= HOLD_PX {
            f += 1;
            continue;
        }
        // The run of moving frames from `f`.
        let mut b = f + 1;
        while b + 1 < n && px(&pts, unit.motion[b + 1], unit.motion[b]) > HOLD_PX {
            b += 1;
        }
        let held_before = f > 0 || at > 0.0;
        let held_after = b + 1 < n;
        // Pieces over the run, the longest that fits first.
        let mut a = f;
        let mut start_sub = held_before;
        while a < b {
            if let Some((added, end_state, end)) = with_twins
                .then(|| try_twin(unit, &pts, clock, &slices, at, a, start_sub, tol_px))
                .flatten()
            {
                slices.extend(added);
                state = end_state;
                at = end;
                start_sub = false;
                let next = ((end * clock.fps) - 1e-6).ceil().max(0.0) as usize;
                if next >= b {
                    b = b.max(next.min(n - 1));
                    break;
                }
                a = next;
                continue;
            }
            // The whole run if it fits, else the longest piece that does (a single frame
            // always fits).
            // The piece found is fitted again over every sub-frame start and end, for the
            // least error (a stagger's starts must come out exact to be shared).
            let try_fit = |e: usize, exhaustive: bool| {
                fit_piece(
                    &pts,
                    unit,
                    &eases,
                    clock,
                    state,
                    a,
                    e,
                    start_sub,
                    held_after && e == b,
                    tol_px,
                    exhaustive,
                    // A fitted cubic costs a search of its own: tried on the whole run and
                    // on the piece found, not on every length the search tries.
                    exhaustive || (e == b && a == f),
                )
            };
            let end = (a + 1..=b).rev().find(|&e| try_fit(e, false).is_some());
            let found = Some(
                match end.and_then(|e| try_fit(e, true).map(|fit| (e, fit))) {
                    Some(f) => f,
                    None => (a + 1, exact_step(unit, clock, state, a, a + 1)),
                },
            );
            let Some((e, (s_t, e_t, mv, end_state))) = found else {
                break;
            };
            slices.push(Slice {
                t0: at,
                t1: e_t,
                play: Some(Move {
                    delay: s_t - at,
                    ..mv
                }),
                inner: Vec::new(),
                twin_of: None,
            });
            state = end_state;
            at = e_t;
            a = e;
            start_sub = false;
        }
        f = b;
    }
    // A change that ends within a microsecond of the end (frame times from a rate such as
    // 29.97 land a few tens of nanoseconds short) ends at the end, instead of leaving a
    // sliver of a hold that the grammar would have to write as a fraction of 4e-8.
    if let Some(last) = slices.last_mut()
        && clock.duration - at < 1e-6
    {
        last.t1 = clock.duration;
    } else if !slices.is_empty() {
        slices.push(Slice {
            t0: at,
            t1: clock.duration,
            play: None,
            inner: Vec::new(),
            twin_of: None,
        });
    }
    fit_paint(unit, clock, tol_opacity, &eases, &mut slices);
    let (max_px, max_opacity) = errors(unit, &pts, clock, &slices);
    Fitted {
        slices,
        max_px,
        max_opacity,
    }
}

/// The slices that play an earlier slice backwards from `at` (a hold first when the
/// reversal starts later), with the state they end in and their end, when the samples
/// follow that reversal within `tol` for its whole length (up to the last frame).
#[allow(clippy::too_many_arguments)]
fn try_twin(
    unit: &UnitSamples,
    pts: &[Point],
    clock: Clock,
    slices: &[Slice],
    at: f64,
    a: usize,
    start_sub: bool,
    tol: f64,
) -> Option<(Vec<Slice>, Affine, f64)> {
    let taken: Vec<usize> = slices.iter().filter_map(|s| s.twin_of).collect();
    let n = unit.motion.len();
    let starts: Vec<f64> = if start_sub {
        SUBFRAME
            .iter()
            .map(|d| clock.time(a as f64 + d))
            .filter(|t| *t >= at - 1e-9)
            .collect()
    } else {
        vec![at]
    };
    for i in (0..slices.len()).rev() {
        let fwd = &slices[i];
        let affine = matches!(
            fwd.play,
            Some(Move {
                change: Change::Affine(..),
                ..
            })
        );
        if !affine || !fwd.inner.is_empty() || fwd.twin_of.is_some() || taken.contains(&i) {
            continue;
        }
        let d = fwd.t1 - fwd.t0;
        for &t_s in &starts {
            let end = t_s + d;
            if end > clock.duration + 1e-9 {
                continue;
            }
            let mut added = Vec::new();
            if t_s > at + 1e-9 {
                added.push(Slice {
                    t0: at,
                    t1: t_s,
                    play: None,
                    inner: Vec::new(),
                    twin_of: None,
                });
            }
            added.push(Slice {
                t0: t_s,
                t1: end,
                play: None,
                inner: Vec::new(),
                twin_of: Some(i),
            });
            let mut cand = slices.to_vec();
            cand.extend(added.iter().cloned());
            let frames = frames_in(clock, at, end.min(clock.time((n - 1) as f64)), n);
            let ok = frames.clone().all(|g| {
                let (m, _) = model_at(unit, &cand, clock.time(g as f64));
                px(pts, m, unit.motion[g]) <= tol
            });
            if ok && !frames.is_empty() {
                let (end_state, _) = model_at(unit, &cand, end);
                return Some((added, end_state, end));
            }
        }
    }
    None
}

/// A piece's fit: its start and end times, the move (delay not yet set) and the state it
/// ends in.
type PieceFit = (f64, f64, Move, Affine);

/// The best fit of frames `a ..= e` as one change from `state`, within `tol`.
#[allow(clippy::too_many_arguments)]
fn fit_piece(
    pts: &[Point],
    unit: &UnitSamples,
    eases: &[Easing],
    clock: Clock,
    state: Affine,
    a: usize,
    e: usize,
    start_sub: bool,
    end_sub: bool,
    tol: f64,
    exhaustive: bool,
    cubic: bool,
) -> Option<PieceFit> {
    let target = unit.motion[e];
    let delta = target * state.inverse();
    // The unwrapped turn over the piece.
    let mut turn = 0.0;
    let mut prev = 0.0;
    for g in a + 1..=e {
        let d = angle(unit.motion[g] * state.inverse());
        let mut step = d - prev;
        step -= 360.0 * (step / 360.0).round();
        turn += step;
        prev = d;
    }
    let centre = state * unit.centroid;
    // A pure translation reads best in the canvas's terms; anything that turns or scales,
    // about the unit's own centre first.
    let translation = {
        let c = delta.as_coeffs();
        (c[0] - 1.0).abs() + c[1].abs() + c[2].abs() + (c[3] - 1.0).abs() < 1e-9
    };
    let mut pivots = if translation {
        vec![(Pivot::World(Point::ORIGIN), Point::ORIGIN)]
    } else {
        vec![
            (Pivot::Local, centre),
            (Pivot::World(Point::ORIGIN), Point::ORIGIN),
        ]
    };
    let [m00, m10, m01, m11, bx, by] = delta.as_coeffs();
    let (i00, i01, i10, i11) = (1.0 - m00, -m01, -m10, 1.0 - m11);
    let det = i00 * i11 - i01 * i10;
    if det.abs() > 1e-6 {
        let p = Point::new((i11 * bx - i01 * by) / det, (-i10 * bx + i00 * by) / det);
        if p.x.is_finite() && p.y.is_finite() && p.to_vec2().hypot() < 1e7 {
            pivots.push((Pivot::World(p), p));
        }
    }
    let subs_s: &[f64] = if start_sub { &SUBFRAME } else { &SUBFRAME[..1] };
    let subs_e: &[f64] = if end_sub { &SUBFRAME } else { &SUBFRAME[..1] };
    // Whole frames first, then starts and ends ever further between frames: searching,
    // the first that fits is taken (each costs every pivot and easing over every frame);
    // `exhaustive`, the best of all. `cubic`: a cubic fitted to the piece is tried too.
    let mut pairs: Vec<(f64, f64)> = subs_s
        .iter()
        .flat_map(|ds| subs_e.iter().map(move |de| (*ds, *de)))
        .collect();
    pairs.sort_by(|x, y| (x.0 + x.1).total_cmp(&(y.0 + y.1)));
    let comps: Vec<Vec<Component>> = pivots
        .iter()
        .map(|(_, point)| components(delta, *point, turn))
        .collect();
    // The middle and quarter frames first: a candidate that fails mostly fails there, and
    // most candidates fail.
    let len = e - a;
    let first = [a + len / 2, a + len / 4, a + 3 * len / 4];
    let mut order: Vec<usize> = first.to_vec();
    order.extend((a..=e).filter(|g| !first.contains(g)));
    let mut best: Option<(f64, PieceFit)> = None;
    for (ds, de) in pairs {
        let s_t = clock.time(a as f64 + ds);
        let e_t = clock.time(e as f64 - de);
        if e_t <= s_t + 1e-9 {
            continue;
        }
        // Each easing's progress at each frame, shared by the pivots: solving a cubic
        // Bézier's x is most of the search's time.
        let mut memo = vec![f64::NAN; eases.len() * (len + 1)];
        for ((pivot, point), comps) in pivots.iter().zip(&comps) {
            // The named easings first; when none fits, a cubic fitted to the piece's own
            // progress (After Effects' keyframe influences are any cubic).
            // (On whole frames only: keyframes sit on frames.)
            let fitted = |found: bool| {
                (cubic && !found && ds == 0.0 && de == 0.0)
                    .then(|| {
                        fitted_cubic(pts, unit, comps, *point, state, (a, e), (s_t, e_t), clock)
                    })
                    .flatten()
            };
            let mut tried: Vec<Easing> = eases.to_vec();
            let mut k = 0;
            while k < tried.len() {
                let ease = tried[k].clone();
                k += 1;
                let mut worst = 0.0f64;
                for &g in &order {
                    let p = match memo.get_mut((k - 1) * (len + 1) + (g - a)) {
                        Some(m) if k <= eases.len() => {
                            if m.is_nan() {
                                *m = progress(&ease, s_t, e_t, clock.time(g as f64));
                            }
                            *m
                        }
                        _ => progress(&ease, s_t, e_t, clock.time(g as f64)),
                    };
                    let m = change_at(comps, *point, p) * state;
                    worst = worst.max(px(pts, m, unit.motion[g]));
                    if worst > tol {
                        break;
                    }
                }
                // A later candidate must be clearly better: float noise must not trade the
                // local pivot (which units share) for an equal world one.
                if worst <= tol && best.as_ref().is_none_or(|(w, _)| worst < *w - 1e-6) {
                    let end = change_at(comps, *point, 1.0) * state;
                    let mv = Move {
                        delay: 0.0,
                        ease: ease.clone(),
                        change: Change::Affine(comps.clone(), *pivot),
                    };
                    best = Some((worst, (s_t, e_t, mv, end)));
                }
                if k == eases.len()
                    && let Some(c) = fitted(best.is_some())
                {
                    tried.push(c);
                }
            }
        }
        if best.is_some() && !exhaustive {
            break;
        }
    }
    best.map(|(_, f)| f)
}

/// A cubic Bézier easing fitted to the progress the frames `a ..= e` show along the
/// change `comps` about `point` from `state` (each frame's progress the one whose drawing
/// is nearest), running over `s_t ..= e_t`: coordinate descent from After Effects' Easy
/// Ease on the largest progress error. `None` when the piece is too short to say.
#[allow(clippy::too_many_arguments)]
fn fitted_cubic(
    pts: &[Point],
    unit: &UnitSamples,
    comps: &[Component],
    point: Point,
    state: Affine,
    (a, e): (usize, usize),
    (s_t, e_t): (f64, f64),
    clock: Clock,
) -> Option<Easing> {
    if e < a + 3 || e_t <= s_t {
        return None;
    }
    // Each inner frame's progress, by golden-section search (the error along the change
    // has one minimum for the moves `learn` writes).
    let samples: Vec<(f64, f64)> = (a + 1..e)
        .filter_map(|g| {
            let u = (clock.time(g as f64) - s_t) / (e_t - s_t);
            if !(0.0..=1.0).contains(&u) {
                return None;
            }
            let off = |p: f64| px(pts, change_at(comps, point, p) * state, unit.motion[g]);
            let (mut lo, mut hi) = (-0.5f64, 1.5f64);
            let r = (5f64.sqrt() - 1.0) / 2.0;
            // Each step keeps one of its two probes as the next step's other one: one
            // drawing compared per step, not two.
            let (mut m1, mut m2) = (hi - r * (hi - lo), lo + r * (hi - lo));
            let (mut f1, mut f2) = (off(m1), off(m2));
            for _ in 0..40 {
                if f1 < f2 {
                    hi = m2;
                    (m2, f2) = (m1, f1);
                    m1 = hi - r * (hi - lo);
                    f1 = off(m1);
                } else {
                    lo = m1;
                    (m1, f1) = (m2, f2);
                    m2 = lo + r * (hi - lo);
                    f2 = off(m2);
                }
            }
            Some((u, (lo + hi) / 2.0))
        })
        .collect();
    if samples.len() < 2 {
        return None;
    }
    // The largest progress error, or `None` as soon as it reaches `bound`: most steps of
    // the descent are worse, and are known to be within a few samples.
    let cost = |c: &[f64; 4], bound: f64| {
        let ease = Easing::CubicBezier(*c);
        let mut worst = 0.0f64;
        for (u, p) in &samples {
            worst = worst.max((ease.apply(*u) - p).abs());
            if worst >= bound {
                return None;
            }
        }
        Some(worst)
    };
    let mut c = [0.333, 0.0, 0.667, 1.0];
    let mut now = cost(&c, f64::INFINITY).unwrap_or(f64::INFINITY);
    let mut step = 0.2;
    while step > 0.002 {
        let mut moved = false;
        for i in 0..4 {
            for dir in [-1.0, 1.0] {
                let mut t = c;
                t[i] += dir * step;
                // x in [0, 1] (a function of time), y free within reason (overshoot).
                let (lo, hi) = if i % 2 == 0 { (0.0, 1.0) } else { (-1.0, 2.0) };
                t[i] = t[i].clamp(lo, hi);
                if let Some(v) = cost(&t, now) {
                    (c, now, moved) = (t, v, true);
                }
            }
        }
        if !moved {
            step /= 2.0;
        }
    }
    let round = |x: f64| (x * 1000.0).round() / 1000.0;
    Some(Easing::CubicBezier(c.map(round)))
}

/// One frame's change, linear: exact at both frames whatever it is.
fn exact_step(unit: &UnitSamples, clock: Clock, state: Affine, a: usize, e: usize) -> PieceFit {
    let delta = unit.motion[e] * state.inverse();
    let comps = vec![Component::Matrix(delta)];
    let mv = Move {
        delay: 0.0,
        ease: Easing::Linear,
        change: Change::Affine(comps.clone(), Pivot::World(Point::ORIGIN)),
    };
    let end = change_at(&comps, Point::ORIGIN, 1.0) * state;
    (clock.time(a as f64), clock.time(e as f64), mv, end)
}

/// The frames whose times fall in `[t0, t1]`.
fn frames_in(clock: Clock, t0: f64, t1: f64, n: usize) -> std::ops::RangeInclusive<usize> {
    let a = (t0 * clock.fps - 1e-6).ceil().max(0.0) as usize;
    let b = ((t1 * clock.fps + 1e-6).floor() as usize).min(n.saturating_sub(1));
    a..=b
}

/// The opacity factor the grammar starts from: the still scene keeps the unit's opacity
/// at frame 0.
pub fn base_opacity(unit: &UnitSamples) -> f64 {
    unit.opacity.first().copied().unwrap_or(1.0)
}

/// The paint values of every frame: the opacity factor against the still's opacity, and
/// the fill colour when the unit has one colour of fill (else black, which never changes).
pub fn paint_values(unit: &UnitSamples) -> Vec<PaintValue> {
    (0..unit.opacity.len().min(unit.fill.len()))
        .map(|f| paint_value(unit, f))
        .collect()
}

/// Frame `f`'s paint value (see [`paint_values`]).
fn paint_value(unit: &UnitSamples, f: usize) -> PaintValue {
    let base = base_opacity(unit);
    let o = unit.opacity[f];
    let rgb = match (unit.one_fill, unit.fill[f]) {
        (true, Some(c)) => [f64::from(c[0]), f64::from(c[1]), f64::from(c[2])],
        _ => [0.0; 3],
    };
    // The factor can only lower the still's opacity: a unit more opaque later than at
    // frame 0 is off there, and reported.
    [
        if base > 0.0 { (o / base).min(1.0) } else { 0.0 },
        rgb[0],
        rgb[1],
        rgb[2],
    ]
}

/// The largest channel difference of two paint values.
fn paint_off(a: &PaintValue, b: &PaintValue) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `a` blended towards `b` by `p`.
fn paint_lerp(a: &PaintValue, b: &PaintValue, p: f64) -> PaintValue {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * p)
}

/// The paint value a change leads to from `from`.
fn paint_after(from: &PaintValue, change: &Paint) -> PaintValue {
    let mut v = *from;
    if let Some(o) = change.opacity {
        v[0] = o;
    }
    if let Some(c) = change.fill {
        v[1..].copy_from_slice(&c);
    }
    v
}

/// Fits the paint (opacity factor and fill) inside each slice (a whole-animation slice
/// when the unit does not move), as holds and changes with an easing of the language.
fn fit_paint(
    unit: &UnitSamples,
    clock: Clock,
    tol: f64,
    eases: &[Easing],
    slices: &mut Vec<Slice>,
) {
    let values = paint_values(unit);
    let Some(first) = values.first().copied() else {
        return;
    };
    if base_opacity(unit) <= 0.0 || values.iter().all(|v| paint_off(v, &first) <= HOLD_OPACITY) {
        return;
    }
    let n = values.len();
    if slices.is_empty() {
        slices.push(Slice {
            t0: 0.0,
            t1: clock.duration,
            play: None,
            inner: Vec::new(),
            twin_of: None,
        });
    }
    // What the model shows: the still's values at first.
    let mut value = [1.0, first[1], first[2], first[3]];
    for slice in slices.iter_mut() {
        let r = frames_in(clock, slice.t0, slice.t1, n);
        let (lo, hi) = (*r.start(), *r.end());
        let mut at = slice.t0;
        let mut inner = Vec::new();
        let mut f = lo;
        while f < hi {
            if paint_off(&values[f + 1], &values[f]) <= HOLD_OPACITY
                && paint_off(&values[f], &value) <= tol
            {
                f += 1;
                continue;
            }
            let mut b = f + 1;
            while b < hi && paint_off(&values[b + 1], &values[b]) > HOLD_OPACITY {
                b += 1;
            }
            let mut a = f;
            while a < b {
                let mut done = None;
                for e in (a + 1..=b).rev() {
                    let target = values[e];
                    let mut best: Option<(f64, Easing)> = None;
                    for ease in eases {
                        let s_t = clock.time(a as f64);
                        let e_t = clock.time(e as f64);
                        let worst = (a..=e)
                            .map(|g| {
                                let p = progress(ease, s_t, e_t, clock.time(g as f64));
                                paint_off(&paint_lerp(&value, &target, p), &values[g])
                            })
                            .fold(0.0, f64::max);
                        if worst <= tol && best.as_ref().is_none_or(|(w, _)| worst < *w - 1e-12) {
                            best = Some((worst, ease.clone()));
                        }
                    }
                    if let Some((_, ease)) = best {
                        done = Some((e, ease, target));
                        break;
                    }
                    if e == a + 1 {
                        done = Some((e, Easing::Linear, target));
                    }
                }
                let Some((e, ease, target)) = done else {
                    break;
                };
                let s_t = clock.time(a as f64).max(at);
                let e_t = clock.time(e as f64);
                let change = Paint {
                    opacity: ((target[0] - value[0]).abs() > HOLD_OPACITY).then_some(target[0]),
                    fill: (paint_off(
                        &[0.0, target[1], target[2], target[3]],
                        &[0.0, value[1], value[2], value[3]],
                    ) > HOLD_OPACITY)
                        .then_some([target[1], target[2], target[3]]),
                };
                inner.push(Slice {
                    t0: at,
                    t1: e_t,
                    play: Some(Move {
                        delay: s_t - at,
                        ease,
                        change: Change::Paint(change),
                    }),
                    inner: Vec::new(),
                    twin_of: None,
                });
                value = paint_after(&value, &change);
                at = e_t;
                a = e;
            }
            f = b;
        }
        if !inner.is_empty() {
            if at < slice.t1 - 1e-9 {
                inner.push(Slice {
                    t0: at,
                    t1: slice.t1,
                    play: None,
                    inner: Vec::new(),
                    twin_of: None,
                });
            }
            slice.inner = inner;
        }
    }
}

/// The affine motion and opacity factor the learned slices give at time `t`, composed as
/// the engine composes consecutive slices: each change applies on top of the state the
/// previous one ended in, and an inverted twin plays its slice's change backwards about
/// the same pivot.
pub fn model_at(unit: &UnitSamples, slices: &[Slice], t: f64) -> (Affine, PaintValue) {
    let mut state = Affine::IDENTITY;
    // Frame 0's value alone: this runs for every frame of every candidate checked.
    let first = if unit.opacity.is_empty() || unit.fill.is_empty() {
        [1.0, 0.0, 0.0, 0.0]
    } else {
        paint_value(unit, 0)
    };
    let mut value = [1.0, first[1], first[2], first[3]];
    // Each slice's pivot point, for its twin.
    let mut pivots: Vec<Point> = Vec::with_capacity(slices.len());
    for slice in slices {
        let mut here = state;
        let mut point = Point::ORIGIN;
        let forward = match slice.twin_of {
            Some(i) => slices.get(i).map(|s| (s, true)),
            None => Some((slice, false)),
        };
        if let Some((src, twin)) = forward
            && let Some(Move {
                delay,
                ease,
                change: Change::Affine(comps, pivot),
            }) = &src.play
        {
            point = match (twin, pivot) {
                (true, _) => pivots
                    .get(slice.twin_of.unwrap_or(0))
                    .copied()
                    .unwrap_or(Point::ORIGIN),
                (false, Pivot::Local) => state * unit.centroid,
                (false, Pivot::World(p)) => *p,
            };
            if twin {
                let back = change_at(comps, point, 1.0).inverse();
                let mirrored = src.t0 + (slice.t1 - t.clamp(slice.t0, slice.t1));
                let p = progress(ease, src.t0 + delay, src.t1, mirrored);
                here = change_at(comps, point, p) * back * state;
                state = back * state;
            } else {
                let p = progress(ease, slice.t0 + delay, slice.t1, t.min(slice.t1));
                here = change_at(comps, point, p) * state;
                state = change_at(comps, point, 1.0) * state;
            }
        }
        pivots.push(point);
        for inner in &slice.inner {
            if let Some(Move {
                delay,
                ease,
                change: Change::Paint(change),
            }) = &inner.play
            {
                if t < inner.t0 {
                    break;
                }
                let p = progress(ease, inner.t0 + delay, inner.t1, t);
                let target = paint_after(&value, change);
                if t < inner.t1 {
                    return (here, paint_lerp(&value, &target, p));
                }
                value = target;
            }
        }
        if t < slice.t1 {
            return (here, value);
        }
    }
    (state, value)
}

/// Turns the slices that retrace an earlier one into its inverted twin, where the whole
/// unit stays within `tol` pixels: `[a, …, inv_a]`, one rule playing both.
pub fn twins(unit: &UnitSamples, clock: Clock, tol: f64, fitted: &mut Fitted) {
    let pts = points_of(unit);
    let mut j = 1;
    while j < fitted.slices.len() {
        let cur = &fitted.slices[j];
        let movable = |s: &Slice| {
            s.inner.is_empty()
                && s.twin_of.is_none()
                && matches!(
                    s.play,
                    Some(Move {
                        change: Change::Affine(..),
                        ..
                    })
                )
        };
        if !movable(cur) {
            j += 1;
            continue;
        }
        let taken: Vec<usize> = fitted.slices.iter().filter_map(|s| s.twin_of).collect();
        for i in (0..j).rev() {
            let fwd = &fitted.slices[i];
            if !movable(fwd) || taken.contains(&i) {
                continue;
            }
            let d = fwd.t1 - fwd.t0;
            let mut cand = fitted.slices.clone();
            let end = cand[j].t0 + d;
            let next_hold = cand.get(j + 1).map(|n| match &n.play {
                Some(m) if n.inner.is_empty() => m.delay,
                None if n.inner.is_empty() => n.t1 - n.t0,
                _ => 0.0,
            });
            if end < cand[j].t1 - 1e-9 {
                continue;
            }
            if end > cand[j].t1 + 1e-9 {
                // The twin's trailing hold is the next slice's leading one.
                match next_hold {
                    Some(h) if h >= end - cand[j].t1 - 1e-9 => {
                        let over = end - cand[j].t1;
                        let n = &mut cand[j + 1];
                        n.t0 = end;
                        if let Some(m) = &mut n.play {
                            m.delay = (m.delay - over).max(0.0);
                        }
                        if n.t1 - n.t0 <= 1e-9 {
                            cand.remove(j + 1);
                        }
                    }
                    _ => continue,
                }
            }
            cand[j].t1 = end;
            cand[j].twin_of = Some(i);
            cand[j].play = None;
            // The twin's own frames first, stopping at the first one off: most candidates
            // fail there, and the whole unit's errors cost every frame times every slice.
            let limit = tol.max(fitted.max_px);
            let own = frames_in(clock, cand[j].t0, cand[j].t1, unit.motion.len());
            if own.into_iter().any(|g| {
                let (m, _) = model_at(unit, &cand, clock.time(g as f64));
                px(&pts, m, unit.motion[g]) > limit
            }) {
                continue;
            }
            let (px, op) = errors(unit, &pts, clock, &cand);
            if px <= tol.max(fitted.max_px) && op <= fitted.max_opacity + 1e-9 {
                fitted.slices = cand;
                fitted.max_px = px;
                fitted.max_opacity = op;
                break;
            }
        }
        j += 1;
    }
}

/// The points a unit's error is measured on.
pub fn points_of(unit: &UnitSamples) -> Vec<Point> {
    if unit.points.is_empty() {
        vec![unit.centroid]
    } else {
        unit.points.clone()
    }
}

/// The largest pixel and opacity errors of `slices` against the samples (and what moves
/// inside the unit, which no slice can explain).
pub fn errors(unit: &UnitSamples, pts: &[Point], clock: Clock, slices: &[Slice]) -> (f64, f64) {
    let base = base_opacity(unit);
    let values = paint_values(unit);
    let mut worst = (0.0f64, 0.0f64);
    for (f, m) in unit.motion.iter().enumerate() {
        let (a, v) = model_at(unit, slices, clock.time(f as f64));
        worst.0 = worst.0.max(px(pts, a, *m));
        // Opacity is compared as drawn (the factor times the still's opacity).
        let mut want = values[f];
        want[0] = unit.opacity[f];
        let got = [v[0] * base, v[1], v[2], v[3]];
        worst.1 = worst.1.max(paint_off(&got, &want));
    }
    worst.0 = worst.0.max(unit.inner_px);
    worst
}
