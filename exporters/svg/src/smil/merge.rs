//! Merging a unit's nested groups and their `animateTransform`s where the product stays
//! the same at every instant.
//!
//! [`super::transform::plan`] writes a group per segment: a static `transform` and the
//! segment's animations, `B₁·A₁(t)·B₂·A₂(t)·…`. Two things make that shorter exactly:
//!
//! - a group's static transform that commutes with every animation of the group outside
//!   it (a uniform scale or a rotation with rotations and even scales, a scale with scales,
//!   a translation with translations) moves out past them, and the two groups become one
//!   group with both lists of animations: `B₁·B₂·A₁(t)·A₂(t)`;
//! - two animations of one type in a group, with only animations that commute with them in
//!   between, whose keys lie in disjoint spans of time, become one: while one moves the
//!   other holds, so the merged keys are each one's keys added to (rotations,
//!   translations) or multiplied by (scales) the other's held value, with their timing and
//!   splines unchanged (a spline is a fraction of the change between two keys).
//!
//! On the gallery's intersections example a shape scaled and turned by seven slices about
//! its centre ends up under one group with one `rotate` and one `scale`.

use kurbo::Affine;

use super::transform::{Kind, Nested, TransformAnim};
use gmotion::keyframe::Key;
use gmotion::tolerance::Tolerance;

/// The groups, outermost first, and the innermost group's transform, merged where exact.
pub fn merge(mut layers: Vec<Nested>, mut inner: Affine) -> (Vec<Nested>, Affine) {
    let mut i = 0;
    while i + 1 < layers.len() {
        // An `animateMotion` keeps its group to itself: browsers apply it after the
        // group's `animateTransform`s whatever the document order.
        let alone = moves_along_path(&layers[i]) || moves_along_path(&layers[i + 1]);
        if !alone
            && layers[i]
                .anims
                .iter()
                .all(|a| commutes_with(layers[i + 1].base, a))
        {
            let next = layers.remove(i + 1);
            layers[i].base *= next.base;
            layers[i].anims.extend(next.anims);
        } else {
            i += 1;
        }
    }
    if let Some(last) = layers.last_mut()
        && last.anims.iter().all(|a| commutes_with(inner, a))
    {
        last.base *= inner;
        inner = Affine::IDENTITY;
    }
    for layer in &mut layers {
        merge_anims(&mut layer.anims);
    }
    (layers, inner)
}

/// Whether the group holds an `animateMotion`.
fn moves_along_path(layer: &Nested) -> bool {
    layer
        .anims
        .iter()
        .any(|a| matches!(a.kind, Kind::Motion { .. }))
}

/// Merges animations of one type within a group, each into an earlier one it can reach by
/// commuting past those between them.
fn merge_anims(anims: &mut Vec<TransformAnim>) {
    let mut j = 1;
    while j < anims.len() {
        let into = (0..j).rev().find(|&i| {
            mergeable(&anims[i], &anims[j])
                && anims[i + 1..j].iter().all(|b| anims_commute(b, &anims[j]))
        });
        match into {
            Some(i) => {
                let b = anims.remove(j);
                let a = std::mem::take(&mut anims[i].keys);
                anims[i].keys = join(a, b.keys, b.kind);
            }
            None => j += 1,
        }
    }
}

/// Whether `a` and `b` are one type, both continuous or both discrete, with keys in
/// disjoint spans of time, and a type whose values compose by adding or multiplying.
fn mergeable(a: &TransformAnim, b: &TransformAnim) -> bool {
    if a.keys.is_empty() || b.keys.is_empty() {
        return false;
    }
    let span = |x: &TransformAnim| (x.keys[0].t, x.keys[x.keys.len() - 1].t);
    let ((a0, a1), (b0, b1)) = (span(a), span(b));
    a.kind == b.kind
        && a.discrete == b.discrete
        && matches!(a.kind, Kind::Translate | Kind::Rotate | Kind::Scale)
        && (a1 <= b0 || b1 <= a0)
}

/// The keys of two animations of type `kind` with disjoint spans, as one: the earlier's
/// keys composed with the later's first value, then the later's composed with the
/// earlier's last.
fn join(a: Vec<Key<[f64; 2]>>, b: Vec<Key<[f64; 2]>>, kind: Kind) -> Vec<Key<[f64; 2]>> {
    let (first, then) = if a[a.len() - 1].t <= b[0].t {
        (a, b)
    } else {
        (b, a)
    };
    let op = |x: [f64; 2], y: [f64; 2]| match kind {
        Kind::Scale => [x[0] * y[0], x[1] * y[1]],
        _ => [x[0] + y[0], x[1] + y[1]],
    };
    let (held_first, held_then) = (first[first.len() - 1].v, then[0].v);
    let mut keys: Vec<Key<[f64; 2]>> = first
        .into_iter()
        .map(|k| Key {
            v: op(k.v, held_then),
            ..k
        })
        .collect();
    let boundary = keys[keys.len() - 1].t;
    keys.extend(then.into_iter().enumerate().filter_map(|(n, k)| {
        let v = op(held_first, k.v);
        match n {
            // Where the earlier ends as the later starts, the value is already there.
            0 if k.t == boundary => None,
            // A hold from the earlier's end: the same value at both ends.
            0 => Some(Key::linear(k.t, v)),
            _ => Some(Key { v, ..k }),
        }
    }));
    keys
}

/// Whether every value of a scale is even.
fn even(a: &TransformAnim) -> bool {
    a.keys
        .iter()
        .all(|k| Tolerance::OfFirst(1e-12).same(k.v[0], k.v[1]))
}

/// Whether `x·y = y·x` at every instant for two animations.
fn anims_commute(x: &TransformAnim, y: &TransformAnim) -> bool {
    use Kind::*;
    match (x.kind, y.kind) {
        (Rotate, Rotate) | (Scale, Scale) | (Translate, Translate) => true,
        (Rotate, Scale) => even(y),
        (Scale, Rotate) => even(x),
        _ => false,
    }
}

/// Whether the static `m` commutes with `a` at every instant.
fn commutes_with(m: Affine, a: &TransformAnim) -> bool {
    let [p, q, r, s, e, f] = m.as_coeffs();
    let close = |x: f64, y: f64| Tolerance::Scaled(1e-12).same(x, y);
    let linear = close(e, 0.0) && close(f, 0.0);
    let diagonal = close(q, 0.0) && close(r, 0.0);
    let identity_part = diagonal && close(p, 1.0) && close(s, 1.0);
    match a.kind {
        _ if linear && identity_part => true,
        Kind::Translate => identity_part,
        Kind::Rotate => linear && close(p, s) && close(q, -r),
        Kind::Scale => linear && (diagonal || even(a)),
        Kind::SkewX | Kind::SkewY | Kind::Motion { .. } => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::keyframe::Ease;
    use kurbo::Point;

    /// Keys `from` at `t0` to `to` at `t1` along a spline, held before and after.
    fn anim(kind: Kind, t0: f64, t1: f64, from: [f64; 2], to: [f64; 2]) -> TransformAnim {
        TransformAnim {
            kind,
            keys: vec![
                Key::linear(t0, from),
                Key {
                    t: t1,
                    v: to,
                    ease: Ease::Bezier([0.42, 0.0, 0.58, 1.0]),
                },
            ],
            discrete: false,
            path: None,
        }
    }

    /// The animation's matrix at `t` as a browser computes it: first or last key outside
    /// them, the arriving key's spline between them.
    fn at(a: &TransformAnim, t: f64) -> Affine {
        let k = &a.keys;
        let v = if t <= k[0].t {
            k[0].v
        } else if t >= k[k.len() - 1].t {
            k[k.len() - 1].v
        } else {
            let i = k.iter().rposition(|x| x.t <= t).unwrap();
            let (x, y) = (&k[i], &k[i + 1]);
            let u = (t - x.t) / (y.t - x.t);
            let u = match y.ease {
                Ease::Linear => u,
                Ease::Bezier(c) => gmotion::signals::easing::Easing::CubicBezier(c).apply(u),
                Ease::Hold => 0.0,
            };
            [
                x.v[0] + (y.v[0] - x.v[0]) * u,
                x.v[1] + (y.v[1] - x.v[1]) * u,
            ]
        };
        match a.kind {
            Kind::Translate => Affine::translate((v[0], v[1])),
            Kind::Rotate => Affine::rotate(v[0].to_radians()),
            Kind::Scale => Affine::scale_non_uniform(v[0], v[1]),
            Kind::SkewX => Affine::skew(v[0].to_radians().tan(), 0.0),
            Kind::SkewY => Affine::skew(0.0, v[0].to_radians().tan()),
            Kind::Motion { .. } => unreachable!("these tests merge no motion along a path"),
        }
    }

    fn matrix(layers: &[Nested], inner: Affine, t: f64) -> Affine {
        layers.iter().fold(Affine::IDENTITY, |m, l| {
            l.anims.iter().fold(m * l.base, |m, a| m * at(a, t))
        }) * inner
    }

    fn assert_same(before: &(Vec<Nested>, Affine), after: &(Vec<Nested>, Affine)) {
        let corners = [(80.0, 40.0), (120.0, 40.0), (80.0, 70.0), (120.0, 70.0)].map(Point::from);
        for n in 0..=800 {
            let t = f64::from(n) / 100.0;
            let (m, k) = (matrix(&before.0, before.1, t), matrix(&after.0, after.1, t));
            for p in corners {
                let d = (m * p - k * p).hypot();
                assert!(d < 1e-6, "at {t} s {p:?} moved {d}");
            }
        }
    }

    #[test]
    fn slices_about_one_centre_become_one_group() {
        // What `plan` writes for three slices about (100, 55): scale, turn, scale, each
        // group undoing where the slice before it started.
        let c = Affine::translate((100.0, 55.0));
        let layers = vec![
            Nested {
                base: c,
                anims: vec![anim(Kind::Scale, 5.0, 7.0, [1.0, 1.0], [0.5, 0.5])],
            },
            Nested {
                base: Affine::IDENTITY,
                anims: vec![anim(Kind::Rotate, 2.0, 4.0, [0.0, 0.0], [90.0, 0.0])],
            },
            Nested {
                base: Affine::scale(1.25),
                anims: vec![anim(Kind::Scale, 0.0, 2.0, [0.8, 0.8], [1.6, 1.6])],
            },
        ];
        let before = (layers.clone(), c.inverse());
        let after = merge(layers, c.inverse());
        assert_same(&before, &after);
        assert_eq!(after.0.len(), 1);
        assert_eq!(after.0[0].anims.len(), 2, "{:#?}", after.0[0].anims);
    }

    #[test]
    fn what_does_not_commute_stays_apart() {
        // An uneven scale outside a turn, a translation outside a scale: both skew or move
        // differently when swapped.
        let layers = vec![
            Nested {
                base: Affine::translate((100.0, 55.0)),
                anims: vec![anim(Kind::Scale, 5.0, 7.0, [1.0, 1.0], [2.0, 0.5])],
            },
            Nested {
                base: Affine::rotate(0.3),
                anims: vec![
                    anim(Kind::Rotate, 2.0, 4.0, [0.0, 0.0], [90.0, 0.0]),
                    anim(Kind::Translate, 0.0, 1.0, [0.0, 0.0], [10.0, 5.0]),
                    anim(Kind::Scale, 1.0, 2.0, [1.0, 1.0], [1.5, 1.5]),
                    anim(Kind::Translate, 3.0, 5.0, [0.0, 0.0], [-4.0, 2.0]),
                ],
            },
        ];
        let before = (layers.clone(), Affine::translate((-100.0, -55.0)));
        let after = merge(layers, before.1);
        assert_same(&before, &after);
        assert_eq!(after.0.len(), 2);
        assert_eq!(after.0[1].anims.len(), 4);
    }

    #[test]
    fn merging_keeps_every_instant_of_random_groups() {
        let mut rng = gmotion::tangle::noise::Rng::new(0x9e37_79b9_7f4a_7c15);
        let mut next = move || rng.next_f64();
        let (mut groups, mut anims) = ((0, 0), (0, 0));
        for _ in 0..300 {
            let mut layers = Vec::new();
            for _ in 0..1 + (next() * 5.0) as usize {
                let base = match (next() * 4.0) as usize {
                    0 => Affine::IDENTITY,
                    1 => Affine::scale(0.5 + next()),
                    2 => Affine::rotate(next()) * Affine::scale(1.2),
                    _ => Affine::translate((next() * 9.0, 3.0)),
                };
                let mut list = Vec::new();
                for _ in 0..1 + (next() * 3.0) as usize {
                    let t0 = (next() * 6.0 * 4.0).round() / 4.0;
                    let t1 = t0 + 0.25 + (next() * 2.0 * 4.0).round() / 4.0;
                    let k = 0.5 + next();
                    let uneven = if next() < 0.3 { 1.4 } else { 1.0 };
                    list.push(match (next() * 3.0) as usize {
                        0 => anim(Kind::Rotate, t0, t1, [0.0, 0.0], [next() * 180.0, 0.0]),
                        1 => anim(Kind::Scale, t0, t1, [1.0, 1.0], [k * uneven, k]),
                        _ => anim(Kind::Translate, t0, t1, [0.0, 0.0], [k * 9.0, -4.0]),
                    });
                }
                layers.push(Nested { base, anims: list });
            }
            let before = (layers.clone(), Affine::translate((-50.0, 0.0)));
            let after = merge(layers, before.1);
            assert_same(&before, &after);
            let count = |l: &[Nested]| l.iter().map(|l| l.anims.len()).sum::<usize>();
            groups = (groups.0 + before.0.len(), groups.1 + after.0.len());
            anims = (anims.0 + count(&before.0), anims.1 + count(&after.0));
        }
        // The rules do merge (they are not all refusing).
        assert!(groups.1 * 4 < groups.0 * 3, "{groups:?}");
        assert!(anims.1 < anims.0, "{anims:?}");
    }
}
