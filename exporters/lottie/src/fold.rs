//! Folding a unit's transform levels: fewer nested groups, the same product.
//!
//! [`crate::animate`] writes a level per segment of a track, plus fixed levels that undo
//! a segment's start or correct a jump, so a shape moved by ten slices sits under ten or
//! more nested groups, each written, parsed and composed by the player every frame.
//! Adjacent levels `A·B` often compose into one level exactly, for every frame:
//!
//! - a **fixed** level next to any level: its matrix maps the neighbour's position keys
//!   linearly and adds to its rotation and multiplies its scale, which leaves every key's
//!   easing as it was (an easing is a fraction of the change between two keys);
//! - a **translation** level outside any level: the translations add;
//! - two levels that rotate and scale **about the same anchor**, whose keys lie in
//!   disjoint spans of time: while one moves the other holds, so the product's keys are
//!   one level's keys times the other's held value.
//!
//! Each rule asks what makes it exact (rotations commute with the neighbour's scale only
//! when that scale is even), and leaves the pair alone otherwise. On the gallery's
//! intersections example the 8 214 shapes go from 10 nested levels each to one.

use kurbo::{Affine, Vec2};

use crate::model::{Easing, Keyframe, N, Prop, Transform, Value};
use gmotion::tolerance::{UNIFORM, WRITTEN};

/// The levels, outermost first, with adjacent levels composed where that is exact, then
/// rounded as written ([`Transform::rounded`]).
pub fn fold(levels: Vec<Transform>) -> Vec<Transform> {
    // A level this module does not read (opacity, an animated anchor) stays where it is,
    // and its neighbours fold around it.
    let mut items: Vec<Item> = levels
        .into_iter()
        .map(|t| Level::read(&t).map_or_else(|| Item::Kept(Box::new(t)), Item::Folds))
        .collect();
    items.retain(|i| !matches!(i, Item::Folds(l) if l.is_identity()));
    // The rules in order of preference: a merge that leaves keys spanning less time leaves
    // more merges possible (a translation folded into the scale it follows first, then the
    // scales about one point, before spans are joined end to end).
    'rules: loop {
        for rule in RULES {
            if sweep(&mut items, rule) {
                continue 'rules;
            }
        }
        break;
    }
    items
        .into_iter()
        .map(|i| match i {
            Item::Folds(l) => l.write(),
            Item::Kept(t) => crate::model::rounded(*t),
        })
        .collect()
}

/// A level as this module reads it, or one it leaves as it is (boxed: a transform has a
/// slot for every channel Lottie has, most of them empty here).
enum Item {
    Folds(Level),
    Kept(Box<Transform>),
}

/// Composes an outer level and the level inside it into one, or says it cannot.
type Rule = fn(&Level, &Level) -> Option<Level>;

const RULES: [Rule; 4] = [
    Level::fixed,
    Level::translation,
    Level::same_anchor,
    Level::disjoint,
];

/// Merges every adjacent pair `rule` merges, outermost first; whether any was.
fn sweep(items: &mut Vec<Item>, rule: Rule) -> bool {
    let mut merged_any = false;
    let mut i = 0;
    while i + 1 < items.len() {
        let merged = match (&items[i], &items[i + 1]) {
            (Item::Folds(outer), Item::Folds(inner)) => rule(outer, inner),
            _ => None,
        };
        match merged {
            Some(m) => {
                let kept = (!m.is_identity()).then_some(Item::Folds(m));
                items.splice(i..i + 2, kept);
                merged_any = true;
            }
            None => i += 1,
        }
    }
    merged_any
}

/// A channel's values: fixed, or keys whose values are pairs (a number's second
/// component is 0).
#[derive(Clone, Debug)]
enum Chan {
    Fixed([f64; 2]),
    Keyed(Vec<Key>),
}

/// A keyframe of a number or a pair, held by value.
#[derive(Clone, Copy, Debug)]
struct Key {
    t: N,
    v: [f64; 2],
    ease: Option<Easing>,
    hold: bool,
}

/// Reads a number or a pair; `None` for anything else (a Bézier outline).
fn pair(v: &Value) -> Option<[f64; 2]> {
    match v {
        Value::Scalar(x) => Some([x.0, 0.0]),
        Value::Vec(xs) => match xs[..] {
            [x, y] => Some([x.0, y.0]),
            _ => None,
        },
        Value::Bezier(_) => None,
    }
}

/// A number (`scalar`) or a pair, rounded as written.
fn value(v: [f64; 2], scalar: bool) -> Value {
    match scalar {
        true => Value::Scalar(N::coord(v[0])),
        false => Value::Vec(vec![N::coord(v[0]), N::coord(v[1])]),
    }
}

impl Chan {
    fn read(p: &Option<Prop>, default: [f64; 2]) -> Option<Chan> {
        Some(match p {
            None => Chan::Fixed(default),
            Some(Prop::Static(v)) => Chan::Fixed(pair(v)?),
            Some(Prop::Animated(keys)) if keys.is_empty() => return None,
            // Keys moving along a curve (spatial tangents) are written as they are: the
            // rules here map key values, not the curves between them.
            Some(Prop::Animated(keys)) if keys.iter().any(|k| k.to.is_some()) => return None,
            Some(Prop::Animated(keys)) => Chan::Keyed(
                keys.iter()
                    .map(|k| {
                        Some(Key {
                            t: k.t,
                            v: pair(k.value())?,
                            ease: k.easing(),
                            hold: k.hold,
                        })
                    })
                    .collect::<Option<_>>()?,
            ),
        })
    }

    /// Every value the channel takes at a key (or its fixed value).
    fn values(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        let (fixed, keys) = match self {
            Chan::Fixed(v) => (Some(*v), &[][..]),
            Chan::Keyed(k) => (None, &k[..]),
        };
        fixed.into_iter().chain(keys.iter().map(|k| k.v))
    }

    /// Whether every value satisfies `f`.
    fn all(&self, f: impl Fn([f64; 2]) -> bool) -> bool {
        self.values().all(f)
    }

    fn first(&self) -> [f64; 2] {
        match self {
            Chan::Fixed(v) => *v,
            Chan::Keyed(k) => k[0].v,
        }
    }

    fn last(&self) -> [f64; 2] {
        match self {
            Chan::Fixed(v) => *v,
            Chan::Keyed(k) => k[k.len() - 1].v,
        }
    }

    /// The frames its keys span.
    fn span(&self) -> Option<(f64, f64)> {
        match self {
            Chan::Fixed(_) => None,
            Chan::Keyed(k) => Some((k.first()?.t.0, k.last()?.t.0)),
        }
    }

    /// Every value mapped by `f`; the keys' times, easings and holds stay.
    fn map(self, f: impl Fn([f64; 2]) -> [f64; 2]) -> Chan {
        match self {
            Chan::Fixed(v) => Chan::Fixed(f(v)),
            Chan::Keyed(mut keys) => {
                for k in &mut keys {
                    k.v = f(k.v);
                }
                Chan::Keyed(keys)
            }
        }
    }

    /// `op(a(t), b(t))` where `a` changes only before `b` starts changing (or either is
    /// fixed): `a`'s keys with `b` at its first value, then `b`'s with `a` at its last.
    /// `op` must be affine in each argument, so that easings carry over. `None` only when
    /// the two parts do not meet, which takes a value that is not a number.
    fn join(a: Chan, b: Chan, op: impl Fn([f64; 2], [f64; 2]) -> [f64; 2]) -> Option<Chan> {
        let (a_last, b_first) = (a.last(), b.first());
        Chan::concat(a.map(|x| op(x, b_first)), b.map(|y| op(a_last, y)))
    }

    /// `a` and then `b`, for `a` changing only before `b` starts changing; `None` unless `b`
    /// starts where `a` ends.
    fn concat(a: Chan, b: Chan) -> Option<Chan> {
        if !near(a.last(), b.first()) {
            return None;
        }
        Some(match (a, b) {
            (Chan::Fixed(_), b) => b,
            (a, Chan::Fixed(_)) => a,
            (Chan::Keyed(mut keys), Chan::Keyed(later)) => {
                let boundary = keys.last_mut().expect("keyed channels have keys");
                if boundary.t == later[0].t {
                    keys.pop();
                } else {
                    // Both sides of the gap hold the same value.
                    boundary.hold = true;
                    boundary.ease = None;
                }
                keys.extend(later);
                Chan::Keyed(keys)
            }
        })
    }

    /// The channel as a property, rounded as written; `None` when it stays at `default`.
    fn write(self, default: [f64; 2], scalar: bool) -> Option<Prop> {
        match self {
            Chan::Fixed(v) if near(v, default) => None,
            Chan::Fixed(v) => Some(Prop::fixed(value(v, scalar))),
            Chan::Keyed(keys) => Some(Prop::keyed(
                keys.into_iter()
                    .map(|k| Keyframe::written(k.t, value(k.v, scalar), k.ease, k.hold))
                    .collect(),
            )),
        }
    }
}

/// Equal within what the output writes (three decimals).
fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    WRITTEN.same_all(&a, &b)
}

/// A level `T(p)·R(r)·S(s)·T(-a)` with a fixed anchor and no opacity.
#[derive(Clone, Debug)]
struct Level {
    a: Vec2,
    p: Chan,
    /// Degrees, clockwise on screen (in the second component: 0).
    r: Chan,
    /// Percent.
    s: Chan,
}

const ZERO: [f64; 2] = [0.0, 0.0];
const FULL: [f64; 2] = [100.0, 100.0];

fn even(s: [f64; 2]) -> bool {
    UNIFORM.same(s[0], s[1])
}

fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}

impl Level {
    /// `None` for a level this module does not fold: an animated anchor, opacity, or a
    /// value that is not a number or a pair.
    fn read(t: &Transform) -> Option<Level> {
        if t.o.is_some() {
            return None;
        }
        let Chan::Fixed(a) = Chan::read(&t.a, ZERO)? else {
            return None;
        };
        Some(Level {
            a: vec2(a),
            p: Chan::read(&t.p, ZERO)?,
            r: Chan::read(&t.r, ZERO)?,
            s: Chan::read(&t.s, FULL)?,
        })
    }

    fn write(self) -> Transform {
        Transform {
            a: Chan::Fixed([self.a.x, self.a.y]).write(ZERO, false),
            p: self.p.write(ZERO, false),
            s: self.s.write(FULL, false),
            r: self.r.write(ZERO, true),
            o: None,
            ..Transform::empty()
        }
    }

    /// Whether no channel has keys.
    fn is_fixed(&self) -> bool {
        [&self.p, &self.r, &self.s]
            .iter()
            .all(|c| matches!(c, Chan::Fixed(_)))
    }

    fn is_identity(&self) -> bool {
        match (&self.p, &self.r, &self.s) {
            (Chan::Fixed(p), Chan::Fixed(r), Chan::Fixed(s)) => {
                let [p, r, s] = [*p, *r, *s];
                near(r, ZERO) && near(s, FULL) && near([p[0] - self.a.x, p[1] - self.a.y], ZERO)
            }
            _ => false,
        }
    }

    /// Only translates (by `p − a`): no rotation or scale, ever.
    fn translates(&self) -> bool {
        self.r.all(|r| near(r, ZERO)) && self.s.all(|s| near(s, FULL))
    }

    /// The frames the level's keys span, if it has any.
    fn span(&self) -> Option<(f64, f64)> {
        [&self.p, &self.r, &self.s]
            .iter()
            .filter_map(|c| c.span())
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// The fixed matrix `R(r)·S(s)` of a fixed level.
    fn linear(&self) -> Affine {
        let (r, s) = (self.r.first()[0], self.s.first());
        Affine::rotate(r.to_radians()) * Affine::scale_non_uniform(s[0] / 100.0, s[1] / 100.0)
    }

    /// A fixed level folded into its neighbour.
    fn fixed(&self, inner: &Level) -> Option<Level> {
        if self.is_fixed() {
            self.fixed_outside(inner)
        } else if inner.is_fixed() {
            self.outside_fixed(inner)
        } else {
            None
        }
    }

    /// A translation folded into the level inside it.
    fn translation(&self, inner: &Level) -> Option<Level> {
        self.translates().then(|| self.translation_outside(inner))?
    }

    /// Fixed `Q = T(q)·M·T(-b)` (`M = R(θ)·S(k)`) outside `L`:
    /// `T(q + M·(p − b))·R(θ + r)·S(k·s)·T(-a)`, when `S(k)` commutes with `R(r)`.
    fn fixed_outside(&self, inner: &Level) -> Option<Level> {
        let (q, b, theta, k) = (
            vec2(self.p.first()),
            self.a,
            self.r.first()[0],
            self.s.first(),
        );
        if !even(k) && !inner.r.all(|r| near(r, ZERO)) {
            return None;
        }
        let m = self.linear();
        Some(Level {
            a: inner.a,
            p: inner.p.clone().map(|p| {
                let v = q + linear(m, vec2(p) - b);
                [v.x, v.y]
            }),
            r: inner.r.clone().map(|r| [r[0] + theta, 0.0]),
            s: inner
                .s
                .clone()
                .map(|s| [s[0] * k[0] / 100.0, s[1] * k[1] / 100.0]),
        })
    }

    /// `L` outside fixed `Q = T(q)·M·T(-b)`: `T(p)·R(r + θ)·S(s·k)·T(-(b − M⁻¹·(q − a)))`,
    /// when `S(s)` commutes with `R(θ)` and `M` is invertible.
    fn outside_fixed(&self, fixed: &Level) -> Option<Level> {
        let (q, b, theta, k) = (
            vec2(fixed.p.first()),
            fixed.a,
            fixed.r.first()[0],
            fixed.s.first(),
        );
        let turns = !near([theta, 0.0], ZERO);
        if (turns && !self.s.all(even)) || k[0].abs() < 1e-9 || k[1].abs() < 1e-9 {
            return None;
        }
        let a = b - linear(fixed.linear().inverse(), q - self.a);
        Some(Level {
            a,
            p: self.p.clone(),
            r: self.r.clone().map(|r| [r[0] + theta, 0.0]),
            s: self
                .s
                .clone()
                .map(|s| [s[0] * k[0] / 100.0, s[1] * k[1] / 100.0]),
        })
    }

    /// Translation `T(p′ − a′)` outside `L`: `T(p′ − a′ + p)·R(r)·S(s)·T(-a)`, when the
    /// two positions' keys lie in disjoint spans.
    fn translation_outside(&self, inner: &Level) -> Option<Level> {
        let a = [self.a.x, self.a.y];
        let d = self.p.clone().map(|p| [p[0] - a[0], p[1] - a[1]]);
        let p = match ordered(&d, &inner.p)? {
            Order::FirstThen => Chan::join(d, inner.p.clone(), add)?,
            Order::SecondThen => Chan::join(inner.p.clone(), d, add)?,
        };
        Some(Level {
            a: inner.a,
            p,
            r: inner.r.clone(),
            s: inner.s.clone(),
        })
    }

    /// Two rotations and scales about one point `c` (`p = a = c` fixed in both), each
    /// channel's keys in disjoint spans: `T(c)·R(r₁ + r₂)·S(s₁·s₂)·T(-c)`, when the outer
    /// scale commutes with the inner rotation.
    fn same_anchor(&self, inner: &Level) -> Option<Level> {
        let pivots = |l: &Level| matches!(l.p, Chan::Fixed(p) if near(p, [l.a.x, l.a.y]));
        if !(pivots(self) && pivots(inner) && near([self.a.x, self.a.y], [inner.a.x, inner.a.y])) {
            return None;
        }
        if !self.s.all(even) && !inner.r.all(|r| near(r, ZERO)) {
            return None;
        }
        let in_order =
            |a: &Chan, b: &Chan, op: fn([f64; 2], [f64; 2]) -> [f64; 2]| match ordered(a, b)? {
                Order::FirstThen => Chan::join(a.clone(), b.clone(), op),
                Order::SecondThen => Chan::join(b.clone(), a.clone(), op),
            };
        Some(Level {
            a: self.a,
            p: self.p.clone(),
            r: in_order(&self.r, &inner.r, add)?,
            s: in_order(&self.s, &inner.s, |x, y| {
                [x[0] * y[0] / 100.0, x[1] * y[1] / 100.0]
            })?,
        })
    }

    /// Two levels whose keys lie in disjoint spans: while one moves, the other holds a
    /// fixed value, which folds into it ([`Self::fixed`]); the two parts are one level
    /// when they can be written about one anchor and meet where one ends and the other
    /// starts.
    fn disjoint(&self, inner: &Level) -> Option<Level> {
        let (outer_span, inner_span) = (self.span()?, inner.span()?);
        let outer_first = if outer_span.1 <= inner_span.0 {
            true
        } else if inner_span.1 <= outer_span.0 {
            false
        } else {
            return None;
        };
        // The value each holds while the other moves.
        let (outer_held, inner_held) = match outer_first {
            true => (self.held(Chan::last), inner.held(Chan::first)),
            false => (self.held(Chan::first), inner.held(Chan::last)),
        };
        let while_outer = self.outside_fixed(&inner_held)?;
        let while_inner = outer_held.fixed_outside(inner)?;
        let (while_outer, while_inner) = match while_inner.about(while_outer.a) {
            Some(i) => (while_outer, i),
            None => {
                let o = while_outer.about(while_inner.a)?;
                (o, while_inner)
            }
        };
        let (first, then) = match outer_first {
            true => (while_outer, while_inner),
            false => (while_inner, while_outer),
        };
        Some(Level {
            a: first.a,
            p: Chan::concat(first.p, then.p)?,
            r: Chan::concat(first.r, then.r)?,
            s: Chan::concat(first.s, then.s)?,
        })
    }

    /// The fixed level this one holds at its first or last keys.
    fn held(&self, at: fn(&Chan) -> [f64; 2]) -> Level {
        Level {
            a: self.a,
            p: Chan::Fixed(at(&self.p)),
            r: Chan::Fixed(at(&self.r)),
            s: Chan::Fixed(at(&self.s)),
        }
    }

    /// The same level written about anchor `a`: possible when it already is, or when it
    /// never rotates or scales differently (`T(p)·M·T(-a′) = T(p + M·(a − a′))·M·T(-a)`).
    fn about(&self, a: Vec2) -> Option<Level> {
        if near([self.a.x, self.a.y], [a.x, a.y]) {
            return Some(self.clone());
        }
        if !matches!((&self.r, &self.s), (Chan::Fixed(_), Chan::Fixed(_))) {
            return None;
        }
        let shift = linear(self.linear(), a - self.a);
        Some(Level {
            a,
            p: self.p.clone().map(|p| [p[0] + shift.x, p[1] + shift.y]),
            r: self.r.clone(),
            s: self.s.clone(),
        })
    }
}

/// Which of two channels changes first.
enum Order {
    FirstThen,
    SecondThen,
}

/// The order in which `a` and `b` change, `None` when their keys overlap in time.
fn ordered(a: &Chan, b: &Chan) -> Option<Order> {
    match (a.span(), b.span()) {
        (None, _) => Some(Order::FirstThen),
        (_, None) => Some(Order::SecondThen),
        (Some(x), Some(y)) if x.1 <= y.0 => Some(Order::FirstThen),
        (Some(x), Some(y)) if y.1 <= x.0 => Some(Order::SecondThen),
        _ => None,
    }
}

fn add(x: [f64; 2], y: [f64; 2]) -> [f64; 2] {
    [x[0] + y[0], x[1] + y[1]]
}

/// `m`'s linear part applied to `v`.
fn linear(m: Affine, v: Vec2) -> Vec2 {
    let [a, b, c, d, _, _] = m.as_coeffs();
    Vec2::new(a * v.x + c * v.y, b * v.x + d * v.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::from_css;
    use gmotion::signals::easing::Easing;
    use kurbo::Point;

    /// A property's value at `frame` as a player computes it: the first or last key
    /// outside the keys, holds, and the key's Bézier easing between them.
    fn value_at(p: &Option<Prop>, default: [f64; 2], frame: f64) -> [f64; 2] {
        let keys = match p {
            None => return default,
            Some(Prop::Static(v)) => return pair(v).unwrap(),
            Some(Prop::Animated(keys)) => keys,
        };
        let (first, last) = (&keys[0], &keys[keys.len() - 1]);
        if frame <= first.t.0 {
            return pair(first.value()).unwrap();
        }
        if frame >= last.t.0 {
            return pair(last.value()).unwrap();
        }
        let i = keys.iter().rposition(|k| k.t.0 <= frame).unwrap();
        let (a, b) = (&keys[i], &keys[i + 1]);
        let (va, vb) = (pair(a.value()).unwrap(), pair(b.value()).unwrap());
        if a.hold {
            return va;
        }
        let [o, i] = a.easing().unwrap();
        let curve = Easing::CubicBezier([o.x.0, o.y.0, i.x.0, i.y.0]);
        let u = curve.apply((frame - a.t.0) / (b.t.0 - a.t.0));
        [va[0] + (vb[0] - va[0]) * u, va[1] + (vb[1] - va[1]) * u]
    }

    fn matrix(levels: &[Transform], frame: f64) -> Affine {
        levels.iter().fold(Affine::IDENTITY, |acc, l| {
            let [a, p, s, r] = [
                value_at(&l.a, ZERO, frame),
                value_at(&l.p, ZERO, frame),
                value_at(&l.s, FULL, frame),
                value_at(&l.r, ZERO, frame),
            ];
            acc * Affine::translate((p[0], p[1]))
                * Affine::rotate(r[0].to_radians())
                * Affine::scale_non_uniform(s[0] / 100.0, s[1] / 100.0)
                * Affine::translate((-a[0], -a[1]))
        })
    }

    fn fixed(v: [f64; 2]) -> Option<Prop> {
        Some(Prop::fixed(Value::Vec(vec![N(v[0]), N(v[1])])))
    }

    /// Keys `from` at `t0`, eased by `ease`, to `to` at `t1`.
    fn keyed(t0: f64, t1: f64, from: [f64; 2], to: [f64; 2], ease: [f64; 4], scalar: bool) -> Prop {
        let v = |x: [f64; 2]| match scalar {
            true => Value::Scalar(N(x[0])),
            false => Value::Vec(vec![N(x[0]), N(x[1])]),
        };
        Prop::Animated(vec![
            Keyframe::written(N(t0), v(from), Some(from_css(ease)), false),
            Keyframe::written(N(t1), v(to), None, false),
        ])
    }

    const EASE_IN_OUT: [f64; 4] = [0.42, 0.0, 0.58, 1.0];

    /// A scale about `c` from 100% to `k`% over frames `t0`–`t1`.
    fn scale_about(c: [f64; 2], t0: f64, t1: f64, k: [f64; 2]) -> Transform {
        Transform {
            a: fixed(c),
            p: fixed(c),
            s: Some(keyed(t0, t1, FULL, k, EASE_IN_OUT, false)),
            r: None,
            o: None,
            ..Transform::empty()
        }
    }

    /// A turn about `c` by `deg` over frames `t0`–`t1`.
    fn turn_about(c: [f64; 2], t0: f64, t1: f64, deg: f64) -> Transform {
        Transform {
            a: fixed(c),
            p: fixed(c),
            s: None,
            r: Some(keyed(t0, t1, ZERO, [deg, 0.0], [0.3, 0.1, 0.7, 1.2], true)),
            o: None,
            ..Transform::empty()
        }
    }

    /// A translation written about anchor `a`: its position from `a` to `to` over frames
    /// `t0`–`t1`.
    fn shift_about(a: [f64; 2], t0: f64, t1: f64, to: [f64; 2]) -> Transform {
        Transform {
            a: fixed(a),
            p: Some(keyed(t0, t1, a, to, EASE_IN_OUT, false)),
            s: None,
            r: None,
            o: None,
            ..Transform::empty()
        }
    }

    /// A fixed level `T(p)·R(r)·S(s)·T(-a)`.
    fn still(a: [f64; 2], p: [f64; 2], r: f64, s: [f64; 2]) -> Transform {
        Transform {
            a: fixed(a),
            p: fixed(p),
            s: fixed(s),
            r: Some(Prop::scalar(N(r))),
            o: None,
            ..Transform::empty()
        }
    }

    /// Where the corners of a box around `c` go, before and after folding, at every
    /// quarter frame: the same within what rounding to three decimals moves.
    fn assert_same_motion(levels: &[Transform], folded: &[Transform], c: [f64; 2]) {
        let corners = [(-20.0, -10.0), (20.0, -10.0), (-20.0, 10.0), (20.0, 10.0)]
            .map(|(x, y)| Point::new(c[0] + x, c[1] + y));
        for q in 0..=4 * 250 {
            let f = f64::from(q) / 4.0;
            let (m, n) = (matrix(levels, f), matrix(folded, f));
            for p in corners {
                let d = (m * p - n * p).hypot();
                assert!(
                    d < 0.02,
                    "frame {f}: {p:?} at {:?} and {:?} ({d} apart)",
                    m * p,
                    n * p
                );
            }
        }
    }

    #[test]
    fn scales_about_one_point_in_turn_fold_into_one_level() {
        // What the engine writes for a shape scaled by four slices about its centre, with
        // a correction for a slice that starts from where the last one left the shape.
        let c = [888.0, 1240.0];
        // A fixed scale by `k` about `c`, written about the origin, at full precision.
        let about_c = |k: f64| {
            still(
                ZERO,
                [c[0] * (1.0 - k), c[1] * (1.0 - k)],
                0.0,
                [100.0 * k; 2],
            )
        };
        let levels = vec![
            scale_about(c, 187.2, 234.192, [50.0, 50.0]),
            about_c(0.5),
            scale_about(c, 144.0, 182.448, [142.857, 142.857]),
            turn_about(c, 96.0, 120.0, 45.0),
            about_c(1.0 / 0.85),
            scale_about(c, 5.808, 52.8, [200.0, 200.0]),
        ];
        let folded = fold(levels.clone());
        assert_eq!(folded.len(), 1, "{folded:#?}");
        assert_same_motion(&levels, &folded, c);
    }

    #[test]
    fn a_translation_folds_into_the_level_inside_it() {
        let c = [100.0, 50.0];
        let shift = shift_about([0.0, -4.0], 10.0, 30.0, [7.0, 2.0]);
        let levels = vec![shift, scale_about(c, 20.0, 60.0, [80.0, 120.0])];
        let folded = fold(levels.clone());
        assert_eq!(folded.len(), 1, "{folded:#?}");
        assert_same_motion(&levels, &folded, c);
    }

    #[test]
    fn an_uneven_scale_outside_a_turn_stays_two_levels() {
        // `S(2, 1)·R(θ)` is a skew, which one level cannot say.
        let c = [10.0, 10.0];
        let levels = vec![
            scale_about(c, 40.0, 60.0, [200.0, 100.0]),
            turn_about(c, 0.0, 20.0, 30.0),
        ];
        let folded = fold(levels.clone());
        assert_eq!(folded.len(), 2, "{folded:#?}");
        assert_same_motion(&levels, &folded, c);
        // Nor folds the same scale held fixed outside the turn.
        let levels = vec![
            still(c, c, 0.0, [200.0, 100.0]),
            turn_about(c, 0.0, 20.0, 30.0),
        ];
        assert_eq!(fold(levels.clone()).len(), 2);
    }

    #[test]
    fn folding_keeps_every_frame_of_random_stacks() {
        // Random stacks of the levels the engine writes (fixed levels, rotations and
        // scales about a few points, even and uneven, translations), keys in random spans,
        // some overlapping: whatever folds, every frame stays where it was.
        let mut rng = gmotion::tangle::noise::Rng::new(0x2545_f491_4f6c_dd1d);
        let mut next = move || rng.next_f64();
        let (mut before, mut after) = (0, 0);
        for _ in 0..400 {
            let centres = [[100.0, 80.0], [130.0, 60.0], [0.0, 0.0]];
            let mut levels = Vec::new();
            for _ in 0..2 + (next() * 6.0) as usize {
                let c = centres[(next() * 3.0) as usize];
                let t0 = (next() * 200.0).round();
                let t1 = t0 + 1.0 + (next() * 60.0).round();
                let k = 50.0 + next() * 100.0;
                let uneven = if next() < 0.3 { 1.5 } else { 1.0 };
                levels.push(match (next() * 5.0) as usize {
                    0 => still(
                        c,
                        [c[0] + next() * 20.0, c[1] - next() * 20.0],
                        (next() - 0.5) * 90.0,
                        [k * uneven, k],
                    ),
                    1 => turn_about(c, t0, t1, (next() - 0.5) * 180.0),
                    2 => scale_about(c, t0, t1, [k * uneven, k]),
                    3 => shift_about(c, t0, t1, [c[0] + 9.0, c[1] - 4.0]),
                    _ => Transform {
                        s: Some(keyed(t0, t1, FULL, [k * uneven, k], EASE_IN_OUT, false)),
                        ..turn_about(c, t0, t1, (next() - 0.5) * 90.0)
                    },
                });
            }
            let folded = fold(levels.clone());
            assert_same_motion(&levels, &folded, centres[0]);
            (before, after) = (before + levels.len(), after + folded.len());
        }
        // Most stacks fold somewhere (the rules are not all refusing).
        assert!(
            after * 3 < before * 2,
            "{before} levels folded into {after}"
        );
    }
}
