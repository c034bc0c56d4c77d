//! Timelines → keyframed tracks. Walks each shape's slices in time order, keeping the state
//! the shape is in at every slice boundary, so each motion knows its pivot (the centroid
//! where it began) and each attribute change knows the value it starts from.

use std::sync::Arc;

use kurbo::{Affine, Point};

use crate::motion::{AttrSeg, Lookup, MotionKind, MotionSeg, Timing, Tint, Track};
use crate::scene::Shape;

use super::expand::{AnimInst, AnimSpec, Slice};

/// A shape's state at a slice boundary.
#[derive(Clone, Copy, Debug)]
struct State {
    transform: Affine,
    fill: Tint,
    stroke: Tint,
    opacity: f64,
    width: f64,
}

const REST: State = State {
    transform: Affine::IDENTITY,
    fill: Tint::NONE,
    stroke: Tint::NONE,
    opacity: 1.0,
    width: 1.0,
};

/// A map searched linearly: a shape has a handful of motions and changes, for which this
/// beats hashing (and allocates only when the first entry arrives).
struct VecMap<K, V>(Vec<(K, V)>);

impl<K: PartialEq, V> VecMap<K, V> {
    fn new() -> Self {
        VecMap(Vec::new())
    }

    fn get(&self, k: &K) -> Option<&V> {
        self.0.iter().find(|(x, _)| x == k).map(|(_, v)| v)
    }

    fn contains_key(&self, k: &K) -> bool {
        self.get(k).is_some()
    }

    fn get_or_insert_with(&mut self, k: K, f: impl FnOnce() -> V) -> &mut V {
        let i = match self.0.iter().position(|(x, _)| *x == k) {
            Some(i) => i,
            None => {
                self.0.push((k, f()));
                self.0.len() - 1
            }
        };
        &mut self.0[i].1
    }

    fn insert(&mut self, k: K, v: V) {
        match self.0.iter_mut().find(|(x, _)| *x == k) {
            Some(e) => e.1 = v,
            None => self.0.push((k, v)),
        }
    }
}

fn timing(a: &AnimInst) -> Timing {
    Timing {
        start: a.start,
        end: a.end,
        delay: a.delay,
        ease: a.ease.clone(),
        reversed: a.reversed,
    }
}

/// Compiles one shape's timeline into its track.
pub fn track(shape: &Shape, slices: &[Slice]) -> Track {
    let mut track = Track::default();
    // Reserve each channel's segments up front: one per (slice, change) of that kind.
    let mut counts = [0usize; 5];
    for a in slices.iter().flat_map(|s| s.anims.iter()) {
        counts[match a.spec {
            AnimSpec::Motion { .. } => 0,
            AnimSpec::Fill(_) => 1,
            AnimSpec::Border(_) => 2,
            AnimSpec::Opacity(_) => 3,
            AnimSpec::StrokeWidth(_) => 4,
        }] += 1;
    }
    track.motions.reserve_exact(counts[0]);
    track.fill.reserve_exact(counts[1]);
    track.stroke.reserve_exact(counts[2]);
    track.opacity.reserve_exact(counts[3]);
    track.stroke_width.reserve_exact(counts[4]);
    // The composition order of the current slice's changes (buffer reused across slices).
    let mut ordered: Vec<&Arc<AnimInst>> = Vec::new();
    let mut state = REST;
    // States at slice starts, to find where a split motion began.
    let mut history: Vec<(f64, State)> = Vec::with_capacity(slices.len());
    // Pivots and lookups already resolved for a motion instance (shared by its pieces).
    let mut resolved: VecMap<*const AnimInst, MotionKind> = VecMap::new();
    // The latest forward motion set at each expansion step: an inverted twin (same step)
    // reuses its pivot and grid cells, so it undoes exactly that motion.
    let mut forward_at_step: VecMap<usize, MotionKind> = VecMap::new();
    // Values a forward attribute change started from, by (step, channel), for its inv_ twin.
    let mut before: VecMap<(usize, u8), State> = VecMap::new();

    for slice in slices {
        history.push((slice.t0, state));
        if slice.anims.is_empty() {
            continue;
        }
        let (t0, t1) = (slice.t0, slice.t0 + slice.dur);
        let at_start = |tau: f64| {
            history
                .iter()
                .rev()
                .find(|(t, _)| (*t - tau).abs() <= 1e-9)
                .map(|(_, s)| *s)
                .unwrap_or(state)
        };
        let window_start = state.transform;
        let mut motions_here = 0;
        outermost_first(&slice.anims, &mut ordered);
        if slice.inverted {
            for a in &ordered {
                if a.reversed
                    && let Some(k) = forward_at_step.get(&a.step)
                {
                    resolved.get_or_insert_with(Arc::as_ptr(a), || k.clone());
                }
            }
            resolve_reversed(shape, &ordered, &at_start, &mut resolved);
            // An inverted slice undoes its twin: the twin's innermost change is undone
            // first, so the order of composition flips.
            ordered.reverse();
        }
        for &a in &ordered {
            let begun = at_start(a.start);
            let tm = timing(a);
            match &a.spec {
                AnimSpec::Motion {
                    grid,
                    world,
                    pivot_offset,
                    lookup,
                    interp,
                } => {
                    let kind = resolved
                        .get_or_insert_with(Arc::as_ptr(a), || {
                            let centroid = begun.transform * shape.centroid;
                            if *lookup == Lookup::Vertex {
                                let pivot =
                                    if *world { Point::ORIGIN } else { centroid } + *pivot_offset;
                                return MotionKind::Vertex {
                                    grid: grid.clone(),
                                    pivot: Some(pivot),
                                };
                            }
                            let blend = grid.lookup(centroid, *lookup);
                            let pivot =
                                if *world { Point::ORIGIN } else { centroid } + *pivot_offset;
                            MotionKind::Rigid {
                                pivot,
                                blend,
                                interp: *interp,
                            }
                        })
                        .clone();
                    if !a.reversed {
                        forward_at_step.insert(a.step, kind.clone());
                    }
                    track.motions.push(MotionSeg {
                        t0,
                        t1,
                        timing: tm,
                        kind,
                        start: window_start,
                    });
                    motions_here += 1;
                }
                AnimSpec::Fill(c) => {
                    let (from, to) =
                        tint_change(a, 0, begun.fill, Tint::full(*c), &mut before, begun, |s| {
                            s.fill
                        });
                    track.fill.push(AttrSeg {
                        t0,
                        t1,
                        timing: tm,
                        from,
                        to,
                    });
                }
                AnimSpec::Border(c) => {
                    let (from, to) = tint_change(
                        a,
                        1,
                        begun.stroke,
                        Tint::full(*c),
                        &mut before,
                        begun,
                        |s| s.stroke,
                    );
                    track.stroke.push(AttrSeg {
                        t0,
                        t1,
                        timing: tm,
                        from,
                        to,
                    });
                }
                AnimSpec::Opacity(x) => {
                    let (from, to) =
                        tint_change(a, 2, begun.opacity, *x, &mut before, begun, |s| s.opacity);
                    track.opacity.push(AttrSeg {
                        t0,
                        t1,
                        timing: tm,
                        from,
                        to,
                    });
                }
                AnimSpec::StrokeWidth(w) => {
                    let target = if shape.stroke_width > 0.0 {
                        w / shape.stroke_width
                    } else {
                        1.0
                    };
                    let (from, to) =
                        tint_change(a, 3, begun.width, target, &mut before, begun, |s| s.width);
                    track.stroke_width.push(AttrSeg {
                        t0,
                        t1,
                        timing: tm,
                        from,
                        to,
                    });
                }
            }
        }
        // The state at the slice end, read back from what was just emitted.
        if motions_here > 0 {
            let n = track.motions.len();
            let group = &track.motions[n - motions_here..];
            state.transform = group
                .iter()
                .fold(Affine::IDENTITY, |acc, s| acc * s.relative_at(t1))
                * window_start;
        }
        if let Some(s) = track.fill.last().filter(|s| s.t0 == t0) {
            state.fill = s.value_at(t1);
        }
        if let Some(s) = track.stroke.last().filter(|s| s.t0 == t0) {
            state.stroke = s.value_at(t1);
        }
        if let Some(s) = track.opacity.last().filter(|s| s.t0 == t0) {
            state.opacity = s.value_at(t1);
        }
        if let Some(s) = track.stroke_width.last().filter(|s| s.t0 == t0) {
            state.width = s.value_at(t1);
        }
    }
    track
}

/// The order in which the motions of one slice compose, outermost first. World motions
/// wrap local ones, so a shape that moves across the canvas while spinning spins about its
/// own (moving) centre and a world rotation turns the whole path it travels; within each
/// kind, the rule applied later is outer. Attribute changes do not compose and keep their
/// order.
fn outermost_first<'a>(anims: &'a [Arc<AnimInst>], out: &mut Vec<&'a Arc<AnimInst>>) {
    let world = |a: &&Arc<AnimInst>| matches!(&a.spec, AnimSpec::Motion { world: true, .. });
    let local = |a: &&Arc<AnimInst>| matches!(&a.spec, AnimSpec::Motion { world: false, .. });
    out.clear();
    out.extend(anims.iter().rev().filter(world));
    out.extend(anims.iter().rev().filter(local));
    out.extend(
        anims
            .iter()
            .filter(|a| !matches!(&a.spec, AnimSpec::Motion { .. })),
    );
}

/// Resolves the reversed rigid motions of an inverted slice that has no forward twin before
/// it (e.g. `[inv_a, a]`), together. Their forward twins would
/// have pivoted about the centroid `c` the shape had when the twin slice began, composing
/// into `F` with `F(c)` = the centroid now. `F(c)` is affine in `c`, so `c` is found by
/// inverting that affine map; the grid is then read at `c`, as the twin read it.
fn resolve_reversed(
    shape: &Shape,
    forward: &[&Arc<AnimInst>],
    at_start: &dyn Fn(f64) -> State,
    resolved: &mut VecMap<*const AnimInst, MotionKind>,
) {
    let pending: Vec<&Arc<AnimInst>> = forward
        .iter()
        .copied()
        .filter(|a| a.reversed && !resolved.contains_key(&Arc::as_ptr(a)))
        .filter(|a| matches!(&a.spec, AnimSpec::Motion { lookup, .. } if *lookup != Lookup::Vertex))
        .collect();
    let Some(first) = pending.first() else {
        return;
    };
    let now = at_start(first.start).transform * shape.centroid;
    let blends_at = |cell: Point| -> Vec<crate::motion::Blend> {
        pending
            .iter()
            .filter_map(|a| match &a.spec {
                AnimSpec::Motion { grid, lookup, .. } => Some(grid.lookup(cell, *lookup)),
                _ => None,
            })
            .collect()
    };
    // F = F₁∘…∘Fₙ (F₁ outermost), local ones about `c`, applied to `x`.
    let apply = |blends: &[crate::motion::Blend], c: Point, x: Point| -> Point {
        pending.iter().zip(blends).rev().fold(x, |x, (a, blend)| {
            let (world, off) = match &a.spec {
                AnimSpec::Motion {
                    world,
                    pivot_offset,
                    ..
                } => (*world, *pivot_offset),
                _ => (true, kurbo::Vec2::ZERO),
            };
            let pivot = if world { Point::ORIGIN } else { c } + off;
            crate::motion::grid::blend_at(blend, pivot, 1.0) * x
        })
    };
    // Φ(c) = F_c(c) is affine in c for fixed grid cells: invert it at the centroid now.
    let solve = |cell: Point| -> Point {
        let blends = blends_at(cell);
        let phi = |c: Point| apply(&blends, c, c);
        let o = phi(Point::ORIGIN);
        let ex = phi(Point::new(1.0, 0.0)) - o;
        let ey = phi(Point::new(0.0, 1.0)) - o;
        let m = Affine::new([ex.x, ex.y, ey.x, ey.y, o.x, o.y]);
        if m.determinant().abs() < 1e-12 {
            now
        } else {
            m.inverse() * now
        }
    };
    // Read the grid where the shape is now, solve, then read it where the twin began.
    let c = solve(solve(now));
    for a in pending {
        if let AnimSpec::Motion {
            grid,
            world,
            pivot_offset,
            lookup,
            interp,
        } = &a.spec
        {
            let blend = grid.lookup(c, *lookup);
            let pivot = if *world { Point::ORIGIN } else { c } + *pivot_offset;
            resolved.insert(
                Arc::as_ptr(a),
                MotionKind::Rigid {
                    pivot,
                    blend,
                    interp: *interp,
                },
            );
        }
    }
}

/// The endpoints of an attribute change. Forward: from the value where the change began to
/// the target. Reversed: from that value back to what the forward twin (same step) started
/// from — the shape's original value when there is no twin before it — so `[a, b, inv_a]`
/// closes the loop for colours, opacity and width just as for motion.
fn tint_change<T: Copy>(
    a: &AnimInst,
    channel: u8,
    begun: T,
    target: T,
    before: &mut VecMap<(usize, u8), State>,
    begun_state: State,
    get: impl Fn(&State) -> T,
) -> (T, T) {
    if a.reversed {
        let back = before
            .get(&(a.step, channel))
            .map(&get)
            .unwrap_or_else(|| get(&REST));
        (back, begun)
    } else {
        before.get_or_insert_with((a.step, channel), || begun_state);
        (begun, target)
    }
}
