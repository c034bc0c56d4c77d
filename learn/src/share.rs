//! Shared rule sets: the units whose slices say the same kinds of change (the same pieces,
//! components, pivots and paint) share one rule set, each number of it (a slice boundary,
//! an offset, a translation, an angle, a scale, a pivot, an opacity or a colour) written
//! as a linear expression of the shape's variables (`id`, `k`, `cx`, `cy`, the distance
//! from the canvas centre), fitted by least squares over the units, the simplest that
//! fits first. A set is kept only when every unit it covers, played with the values the
//! expressions give it, stays within the tolerance.

use gmotion::motion::Component;
use gmotion::signals::Easing;
use kurbo::{Affine, Point, Vec2};

use crate::Options;
use crate::fit::{self, Change, Clock, Fitted, Move, Pivot, Slice};
use crate::sample::UnitSamples;

/// A variable of the shape a shared number may be an expression of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Var {
    /// `id`: the shape's id within its tag.
    Id,
    /// `k`: its index, in paint order, among the shapes the rule takes.
    K,
    /// `cx`: its centroid's x.
    Cx,
    /// `cy`: its centroid's y.
    Cy,
    /// Its centroid's distance from the canvas centre.
    Dist,
}

impl Var {
    /// The variable as a grammar writes it.
    fn text(self) -> &'static str {
        match self {
            Var::Id => "id",
            Var::K => "k",
            Var::Cx => "cx",
            Var::Cy => "cy",
            Var::Dist => "sqrt((cx - W / 2) ^ 2 + (cy - H / 2) ^ 2)",
        }
    }
}

/// The models tried for each number, simplest first: a constant, a line in one variable
/// (the counters before the geometry: a stagger in `id` reads best), a plane in `cx, cy`.
const MODELS: &[&[Var]] = &[
    &[],
    &[Var::Id],
    &[Var::K],
    &[Var::Cx],
    &[Var::Cy],
    &[Var::Dist],
    &[Var::Cx, Var::Cy],
];

/// A unit's variables, as the engine evaluates them on the still scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vars {
    /// `id`.
    pub id: f64,
    /// `k`.
    pub k: f64,
    /// `cx`.
    pub cx: f64,
    /// `cy`.
    pub cy: f64,
    /// The distance of (`cx`, `cy`) from the canvas centre.
    pub dist: f64,
}

impl Vars {
    /// The value of `v`.
    fn get(&self, v: Var) -> f64 {
        match v {
            Var::Id => self.id,
            Var::K => self.k,
            Var::Cx => self.cx,
            Var::Cy => self.cy,
            Var::Dist => self.dist,
        }
    }
}

/// `c + Σ b·var`: a number of a rule, the same for every unit or varying with its shape.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// The constant.
    pub c: f64,
    /// The variables and their coefficients.
    pub terms: Vec<(Var, f64)>,
}

impl Expr {
    /// The constant `c`.
    pub fn constant(c: f64) -> Expr {
        Expr {
            c,
            terms: Vec::new(),
        }
    }

    /// Its value for a unit.
    pub fn eval(&self, vars: &Vars) -> f64 {
        self.c
            + self
                .terms
                .iter()
                .map(|(v, b)| b * vars.get(*v))
                .sum::<f64>()
    }

    /// Whether it is the same for every unit.
    pub fn is_constant(&self) -> bool {
        self.terms.iter().all(|(_, b)| *b == 0.0)
    }

    /// `self + s · other`.
    pub fn plus(&self, s: f64, other: &Expr) -> Expr {
        let mut out = self.clone();
        out.c += s * other.c;
        for (v, b) in &other.terms {
            match out.terms.iter_mut().find(|(w, _)| w == v) {
                Some((_, a)) => *a += s * b,
                None => out.terms.push((*v, s * b)),
            }
        }
        out.terms.retain(|(_, b)| *b != 0.0);
        out
    }

    /// `s · self`.
    pub fn times(&self, s: f64) -> Expr {
        Expr::constant(0.0).plus(s, self)
    }

    /// Rounded as written with `digits` decimals for the constant, a coefficient with as
    /// few as keep its term within half of the constant's last digit over the units'
    /// range of its variable (`range`).
    pub fn rounded(&self, digits: usize, range: &dyn Fn(Var) -> f64) -> Expr {
        let eps = 0.5 * 10f64.powi(-(digits as i32));
        let mut out = Expr::constant(parse(&crate::rules::num(self.c, digits)));
        for (v, b) in &self.terms {
            let m = range(*v).max(1.0);
            let b = (0..=12)
                .map(|d| parse(&crate::rules::num(*b, d)))
                .find(|r| (r - b).abs() * m <= eps)
                .unwrap_or(*b);
            if b != 0.0 {
                out.terms.push((*v, b));
            }
        }
        out
    }

    /// Rounded to the fewest decimals that keep its value within `eps` wherever its
    /// variables stay within `range`.
    pub fn rounded_within(&self, eps: f64, range: &dyn Fn(Var) -> f64) -> Expr {
        let share = eps / (self.terms.len() + 1) as f64;
        let short = |x: f64, m: f64| {
            (0..=12)
                .map(|d| parse(&crate::rules::num(x, d)))
                .find(|r| (r - x).abs() * m <= share)
                .unwrap_or(x)
        };
        Expr {
            c: short(self.c, 1.0),
            terms: self
                .terms
                .iter()
                .map(|(v, b)| (*v, short(*b, range(*v).max(1.0))))
                .filter(|(_, b)| *b != 0.0)
                .collect(),
        }
    }

    /// As the grammar writes it (coefficients as they are: round first).
    pub fn text(&self, digits: usize) -> String {
        let mut out = String::new();
        let c = crate::rules::num(self.c, digits);
        if c != "0" || self.terms.is_empty() {
            out.push_str(&c);
        }
        for (v, b) in &self.terms {
            let mag = crate::rules::num(b.abs(), 12);
            let term = if mag == "1" {
                v.text().to_string()
            } else {
                format!("{mag} * {}", v.text())
            };
            match (out.is_empty(), *b < 0.0) {
                (true, false) => out.push_str(&term),
                (true, true) => {
                    out.push('-');
                    out.push_str(&term);
                }
                (false, neg) => {
                    out.push_str(if neg { " - " } else { " + " });
                    out.push_str(&term);
                }
            }
        }
        out
    }
}

/// A written number read back (it always parses: [`crate::rules::num`] writes it).
fn parse(t: &str) -> f64 {
    t.parse().unwrap_or(0.0)
}

/// What a number of a rule measures: how finely it is fitted and written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A time in seconds: an offset.
    Time,
    /// A slice's end, in seconds (written as fractions of the duration).
    End,
    /// A length in pixels (a translation, a pivot, a matrix's translation).
    Px,
    /// An angle in degrees (a rotation, a skew).
    Angle,
    /// A factor (a scale, a matrix's linear part).
    Factor,
    /// An opacity, 0 … 1.
    Paint,
    /// A colour channel, 0 … 255 (as `rgb(…)` writes it).
    Colour,
}

impl Kind {
    /// Decimals written.
    pub fn digits(self) -> usize {
        match self {
            Kind::Time | Kind::End | Kind::Factor => 6,
            Kind::Px | Kind::Angle | Kind::Paint => 4,
            Kind::Colour => 2,
        }
    }

    /// The largest misfit of a model over the units that still counts as fitting it (a
    /// simpler model within it wins over a closer, more complex one).
    fn slack(self, clock: Clock, opts: &Options) -> f64 {
        match self {
            Kind::Time | Kind::End => 0.25 / clock.fps,
            Kind::Px => opts.tolerance * 0.25,
            Kind::Angle => 0.01,
            Kind::Factor => 1e-4,
            Kind::Paint => opts.opacity_tolerance * 0.25,
            Kind::Colour => opts.opacity_tolerance * 0.25 * 255.0,
        }
    }
}

/// The numbers of `slices`, in order, with their kinds: per level-1 slice its end and
/// offset, then per slice its inner slices' ends and offsets, then every move's values
/// (components in order, a world pivot's point; paint's opacity and colour).
pub fn numbers(slices: &[Slice]) -> Vec<(f64, Kind)> {
    let mut v = Vec::new();
    let delay = |s: &Slice| s.play.as_ref().map_or(0.0, |m| m.delay);
    for s in slices {
        v.push((s.t1, Kind::End));
        v.push((delay(s), Kind::Time));
    }
    for s in slices {
        for i in &s.inner {
            v.push((i.t1, Kind::End));
            v.push((delay(i), Kind::Time));
        }
    }
    for m in moves(slices) {
        match &m.change {
            Change::Affine(comps, pivot) => {
                for c in comps {
                    match *c {
                        Component::Translate(t) => {
                            v.extend([(t.x, Kind::Px), (t.y, Kind::Px)]);
                        }
                        Component::Rotate(a) => v.push((a, Kind::Angle)),
                        Component::Scale(k) => v.extend([(k.x, Kind::Factor), (k.y, Kind::Factor)]),
                        Component::Skew(x, y) => v.extend([(x, Kind::Angle), (y, Kind::Angle)]),
                        Component::Matrix(m) => {
                            let c = m.as_coeffs();
                            v.extend(c[..4].iter().map(|x| (*x, Kind::Factor)));
                            v.extend(c[4..].iter().map(|x| (*x, Kind::Px)));
                        }
                    }
                }
                if let Pivot::World(p) = pivot {
                    v.extend([(p.x, Kind::Px), (p.y, Kind::Px)]);
                }
            }
            Change::Paint(p) => {
                if let Some(o) = p.opacity {
                    v.push((o, Kind::Paint));
                }
                if let Some(c) = p.fill {
                    v.extend(c.iter().map(|x| (x * 255.0, Kind::Colour)));
                }
            }
        }
    }
    v
}

/// Every move of `slices` in the order [`numbers`] lists their values.
fn moves(slices: &[Slice]) -> impl Iterator<Item = &Move> {
    slices.iter().filter_map(|s| s.play.as_ref()).chain(
        slices
            .iter()
            .flat_map(|s| &s.inner)
            .filter_map(|i| i.play.as_ref()),
    )
}

/// [`moves`], to change them.
fn moves_mut(slices: &mut [Slice]) -> Vec<&mut Move> {
    let mut level1 = Vec::new();
    let mut inner = Vec::new();
    for s in slices.iter_mut() {
        let Slice {
            play, inner: ins, ..
        } = s;
        level1.extend(play.as_mut());
        inner.extend(ins.iter_mut().filter_map(|i| i.play.as_mut()));
    }
    level1.extend(inner);
    level1
}

/// `template` with the numbers `nums` (the layout of [`numbers`]).
pub fn with_numbers(template: &[Slice], nums: &[f64]) -> Vec<Slice> {
    let mut out = template.to_vec();
    let mut it = nums.iter().copied();
    let mut next = || it.next().unwrap_or(0.0);
    let mut t0 = 0.0;
    for s in out.iter_mut() {
        s.t0 = t0;
        s.t1 = next();
        let d = next();
        if let Some(m) = &mut s.play {
            m.delay = d;
        }
        t0 = s.t1;
    }
    for s in out.iter_mut() {
        let mut t0 = s.t0;
        for i in s.inner.iter_mut() {
            i.t0 = t0;
            i.t1 = next();
            let d = next();
            if let Some(m) = &mut i.play {
                m.delay = d;
            }
            t0 = i.t1;
        }
    }
    for m in moves_mut(&mut out) {
        match &mut m.change {
            Change::Affine(comps, pivot) => {
                for c in comps.iter_mut() {
                    *c = match c {
                        Component::Translate(_) => Component::Translate(Vec2::new(next(), next())),
                        Component::Rotate(_) => Component::Rotate(next()),
                        Component::Scale(_) => Component::Scale(Vec2::new(next(), next())),
                        Component::Skew(..) => Component::Skew(next(), next()),
                        Component::Matrix(_) => {
                            Component::Matrix(Affine::new(std::array::from_fn(|_| next())))
                        }
                    };
                }
                if let Pivot::World(p) = pivot {
                    *p = Point::new(next(), next());
                }
            }
            Change::Paint(p) => {
                if let Some(o) = &mut p.opacity {
                    *o = next();
                }
                if let Some(c) = &mut p.fill {
                    *c = std::array::from_fn(|_| next() / 255.0);
                }
            }
        }
    }
    out
}

/// Whether two units' slices say the same kinds of change (the numbers aside): the same
/// slices, twins, pivots' kinds, components' kinds and paint channels.
pub fn same_kinds(a: &[Slice], b: &[Slice]) -> bool {
    fn play_kinds(x: &Option<Move>, y: &Option<Move>) -> bool {
        match (x, y) {
            (None, None) => true,
            (Some(p), Some(q)) => match (&p.change, &q.change) {
                (Change::Affine(c, pv), Change::Affine(d, qv)) => {
                    matches!(
                        (pv, qv),
                        (Pivot::Local, Pivot::Local) | (Pivot::World(_), Pivot::World(_))
                    ) && c.len() == d.len()
                        && c.iter()
                            .zip(d)
                            .all(|(u, v)| std::mem::discriminant(u) == std::mem::discriminant(v))
                }
                (Change::Paint(u), Change::Paint(v)) => {
                    u.opacity.is_some() == v.opacity.is_some()
                        && u.fill.is_some() == v.fill.is_some()
                }
                _ => false,
            },
            _ => false,
        }
    }
    a.len() == b.len()
        && a.iter().zip(b).all(|(s, t)| {
            s.twin_of == t.twin_of
                && play_kinds(&s.play, &t.play)
                && s.inner.len() == t.inner.len()
                && s.inner
                    .iter()
                    .zip(&t.inner)
                    .all(|(i, j)| play_kinds(&i.play, &j.play))
        })
}

/// Least squares `y ≈ c + Σ b_j·x_j` over the units; `None` when the variables do not
/// tell the units apart (a singular system).
fn least_squares(vars: &[Vars], model: &[Var], ys: &[f64]) -> Option<Expr> {
    let n = model.len() + 1;
    let row = |u: &Vars| {
        let mut r = vec![1.0];
        r.extend(model.iter().map(|v| u.get(*v)));
        r
    };
    // Centred on the means, so that `cx` in the hundreds does not swamp the constant.
    let mean: Vec<f64> = (0..n)
        .map(|j| vars.iter().map(|u| row(u)[j]).sum::<f64>() / vars.len() as f64)
        .collect();
    let my = ys.iter().sum::<f64>() / ys.len() as f64;
    if model.is_empty() {
        return Some(Expr::constant(my));
    }
    let m = model.len();
    let mut a = vec![vec![0.0; m + 1]; m];
    for (u, y) in vars.iter().zip(ys) {
        let r = row(u);
        for i in 0..m {
            for j in 0..m {
                a[i][j] += (r[i + 1] - mean[i + 1]) * (r[j + 1] - mean[j + 1]);
            }
            a[i][m] += (r[i + 1] - mean[i + 1]) * (y - my);
        }
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..m {
        let p = (col..m).max_by(|x, y| a[*x][col].abs().total_cmp(&a[*y][col].abs()))?;
        a.swap(col, p);
        let scale = (0..m)
            .map(|j| a[j][j].abs())
            .fold(0.0, f64::max)
            .max(1e-300);
        if a[col][col].abs() <= 1e-9 * scale {
            return None;
        }
        let pivot = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot[col];
                for (x, p) in row.iter_mut().zip(&pivot).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    let b: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    let c = my - (0..m).map(|i| b[i] * mean[i + 1]).sum::<f64>();
    Some(Expr {
        c,
        terms: model.iter().copied().zip(b).collect(),
    })
}

/// The simplest model of `ys` over the units within `slack` (else the closest), and the
/// closest (a simpler one on a tie).
fn fit_expr(vars: &[Vars], ys: &[f64], slack: f64) -> (Expr, Expr) {
    let mut simplest = None;
    let mut best: Option<(f64, Expr)> = None;
    for model in MODELS {
        let Some(e) = least_squares(vars, model, ys) else {
            continue;
        };
        let worst = vars
            .iter()
            .zip(ys)
            .map(|(u, y)| (e.eval(u) - y).abs())
            .fold(0.0, f64::max);
        if worst <= slack && simplest.is_none() {
            simplest = Some(e.clone());
        }
        if best.as_ref().is_none_or(|(w, _)| worst < *w - 1e-9) {
            best = Some((worst, e));
        }
    }
    let closest = best.map_or(Expr::constant(ys[0]), |(_, e)| e);
    (simplest.unwrap_or_else(|| closest.clone()), closest)
}

/// One rule set shared by several units: the slices of the first, to be played with the
/// numbers its expressions give each unit.
#[derive(Clone, Debug)]
pub struct Shared {
    /// The slices whose kinds of change every unit shares (numbers: the first unit's).
    pub template: Vec<Slice>,
    /// Every number of the set (the layout of [`numbers`]) as an expression.
    pub exprs: Vec<(Expr, Kind)>,
    /// Each unit's largest pixel and opacity errors as the set plays it, in the order of
    /// the units shared.
    pub errors: Vec<(f64, f64)>,
    /// The largest magnitude of each variable over the units (`id`, `k`, `cx`, `cy`,
    /// distance), what a coefficient's rounding is weighed by.
    pub range: [f64; 5],
}

impl Shared {
    /// The largest magnitude of `v` over the units.
    pub fn range(&self, v: Var) -> f64 {
        self.range[v as usize]
    }
}

/// Tries to share one rule set among `units`, whose variables are `vars`: the same kinds
/// of change, every number an expression of the variables. `None` unless every unit stays
/// within the tolerance (or its own plain fit's error, when that was larger).
pub fn share(
    units: &[usize],
    vars: &[Vars],
    samples: &[UnitSamples],
    fitted: &[Fitted],
    clock: Clock,
    opts: &Options,
) -> Option<Shared> {
    let first = &fitted[units[0]].slices;
    if first.is_empty() || !units.iter().all(|&u| same_kinds(first, &fitted[u].slices)) {
        return None;
    }
    // Each move's easing: the one most units have (the first unit's on a tie).
    let mut template = first.clone();
    let eases: Vec<Vec<Easing>> = units
        .iter()
        .map(|&u| moves(&fitted[u].slices).map(|m| m.ease.clone()).collect())
        .collect();
    for (slot, m) in moves_mut(&mut template).into_iter().enumerate() {
        let mut count: Vec<(&Easing, usize)> = Vec::new();
        for e in eases.iter().filter_map(|e| e.get(slot)) {
            match count.iter_mut().find(|(x, _)| *x == e) {
                Some((_, c)) => *c += 1,
                None => count.push((e, 1)),
            }
        }
        if let Some((e, _)) = count.iter().rev().max_by_key(|(_, c)| *c) {
            m.ease = (*e).clone();
        }
    }
    let all: Vec<Vec<(f64, Kind)>> = units.iter().map(|&u| numbers(&fitted[u].slices)).collect();
    let range = |v: Var| vars.iter().map(|u| u.get(v).abs()).fold(0.0, f64::max);
    let mut fits = Vec::with_capacity(all[0].len());
    for j in 0..all[0].len() {
        let kind = all[0][j].1;
        let ys: Vec<f64> = all.iter().map(|n| n[j].0).collect();
        let slack = kind.slack(clock, opts);
        let (e, closest) = fit_expr(vars, &ys, slack);
        fits.push((e, kind, slack, ys, closest));
    }
    // Written as a person would (`0.12 * id`, not `0.00119 + 0.1193452 * id`, the units'
    // own numbers being cut at eighths of a frame): each varying number with the fewest
    // decimals that stay as close to the units' numbers as the fit, or within half its
    // slack; when that does not play within the tolerance, the closest expression to the
    // digits it is written with.
    let short: Vec<(Expr, Kind)> = fits
        .iter()
        .map(|(e, k, slack, ys, _)| {
            // A constant is written to its digits: the ends of the timeline stay put.
            if e.terms.is_empty() {
                (e.rounded(k.digits(), &range), *k)
            } else if *k == Kind::End {
                // Short as the fraction of the duration `timesplit` writes.
                let d = clock.duration;
                let fr: Vec<f64> = ys.iter().map(|y| y / d).collect();
                let f = shortest_fit(&e.times(1.0 / d), vars, &fr, slack / 2.0 / d, &range);
                (f.times(d), *k)
            } else {
                (shortest_fit(e, vars, ys, slack / 2.0, &range), *k)
            }
        })
        .collect();
    let fine: Vec<(Expr, Kind)> = fits
        .iter()
        .map(|(_, k, _, _, closest)| (closest.rounded(k.digits(), &range), *k))
        .collect();
    let plays = |exprs: &[(Expr, Kind)]| -> Option<Vec<(f64, f64)>> {
        units
            .iter()
            .zip(vars)
            .map(|(&u, v)| plays_within(u, v, exprs, &template, samples, fitted, clock, opts))
            .collect()
    };
    let (exprs, errors) = if let Some(e) = plays(&short) {
        (short, e)
    } else if let Some(e) = (fine != short).then(|| plays(&fine)).flatten() {
        (fine, e)
    } else {
        return None;
    };
    Some(Shared {
        errors,
        template,
        exprs,
        range: [Var::Id, Var::K, Var::Cx, Var::Cy, Var::Dist].map(range),
    })
}

/// `e` with the fewest decimals (a coefficient with as many more as its variable's range
/// has digits) whose largest distance from the units' numbers `ys` is at most `e`'s own,
/// or `slack`.
fn shortest_fit(
    e: &Expr,
    vars: &[Vars],
    ys: &[f64],
    slack: f64,
    range: &dyn Fn(Var) -> f64,
) -> Expr {
    let off = |x: &Expr| {
        vars.iter()
            .zip(ys)
            .map(|(v, y)| (x.eval(v) - y).abs())
            .fold(0.0, f64::max)
    };
    let bound = off(e).max(slack);
    for d in 0..=12usize {
        let r = |x: f64, extra: usize| parse(&crate::rules::num(x, d + extra));
        let cand = Expr {
            c: r(e.c, 0),
            terms: e
                .terms
                .iter()
                .map(|(v, b)| (*v, r(*b, range(*v).max(1.0).log10().ceil() as usize)))
                .filter(|(_, b)| *b != 0.0)
                .collect(),
        };
        if off(&cand) <= bound {
            return cand;
        }
    }
    e.clone()
}

/// Whether unit `u` (variables `v`), played with the numbers `exprs` give it on
/// `template`, stays within the tolerance (or its own plain fit's error, when that was
/// larger), every slice keeping a length, opacities and colours in range: its largest
/// pixel and opacity errors if so.
#[allow(clippy::too_many_arguments)]
fn plays_within(
    u: usize,
    v: &Vars,
    exprs: &[(Expr, Kind)],
    template: &[Slice],
    samples: &[UnitSamples],
    fitted: &[Fitted],
    clock: Clock,
    opts: &Options,
) -> Option<(f64, f64)> {
    let nums: Vec<f64> = exprs.iter().map(|(e, _)| e.eval(v)).collect();
    let slices = with_numbers(template, &nums);
    // Opacities and colours must stay in their ranges (`animate` refuses others).
    let in_range = |(x, k): (&f64, &(Expr, Kind))| match k.1 {
        Kind::Paint => (0.0..=1.0).contains(x),
        Kind::Colour => (0.0..=255.0).contains(x),
        _ => true,
    };
    if !nums.iter().zip(exprs).all(in_range) {
        return None;
    }
    // Every slice must keep a length and its offset must fit in it.
    if slices
        .iter()
        .chain(slices.iter().flat_map(|s| &s.inner))
        .any(|s| {
            s.t1 - s.t0 <= 1e-9
                || s.play
                    .as_ref()
                    .is_some_and(|m| m.delay < -1e-9 || m.delay >= s.t1 - s.t0)
        })
    {
        return None;
    }
    let pts = fit::points_of(&samples[u]);
    let (px, op) = fit::errors(&samples[u], &pts, clock, &slices);
    let own = &fitted[u];
    // A unit its own rules already leave off may be off by a hundredth of the tolerance
    // more: the shared numbers are written rounded, its own ones were checked exact.
    let bound = |tol: f64, own: f64| {
        if own > tol { own + 0.01 * tol } else { tol }
    };
    (px <= bound(opts.tolerance, own.max_px) + 1e-9
        && op <= bound(opts.opacity_tolerance, own.max_opacity) + 1e-9)
        .then_some((px, op))
}
