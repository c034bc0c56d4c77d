//! Timelines → keyframed tracks. Walks each shape's slices in time order, keeping the state
//! the shape is in at every slice boundary, so each motion knows its pivot (the centroid
//! where it began) and each attribute change knows the value it starts from.
//!
//! Motions are *layers*. Within one window (a slice and the motions it plays) they compose
//! outermost first: world motions wrap local ones, the rule applied later is outer. A motion
//! that keeps running through several windows (its slice was split) keeps its own frame: the
//! frame is carried by the motions outer to it, so a local spin inherited by the pieces of a
//! travelling slice keeps spinning about the moving centre, whatever the pieces add.
//!
//! Inverted slices (gMotion sec. 3.2: start and end values swapped):
//! - an inverted slice with a forward twin before it (same step, e.g. `[a, inv_a]`) plays the
//!   twin's motion backwards in the twin's own layer and frame, so it undoes exactly that
//!   motion — and nothing the pieces inherited;
//! - an inverted slice with no twin before it (`[inv_a, a]`) is *pre-applied*: the shape
//!   starts in the twin's end state (an entrance), innermost, as if the art had been drawn
//!   that way, and the slice plays back to the drawn state. Several such slices stack, the
//!   earliest outermost, so `[inv_c, inv_b, b, c]` is `[b, c, inv_c, inv_b]` turned by half.
//!   Colour, opacity and stroke width do the same: the change runs from its target back to
//!   the value underneath, and a channel whose first change is such a slice holds the target
//!   from time 0. A pre-applied per-vertex motion stays in the art's frame: it deforms the
//!   drawn points themselves, innermost ([`crate::motion::Track::deform`]).

use std::cell::Cell;
use std::sync::Arc;

use kurbo::{Affine, BezPath, Point, Vec2};

use crate::motion::{
    AttrSeg, Channel, Component, Interp, Lookup, MorphSeg, MotionKind, MotionSeg, Timing, Tint,
    Track, Trim,
};
use crate::scene::Shape;

use super::expand::{AnimInst, AnimSpec, Slice};
use super::morph::MorphSpec;

/// A shape's state at a slice boundary.
#[derive(Clone, Copy, Debug)]
struct State {
    transform: Affine,
    fill: Tint,
    stroke: Tint,
    opacity: f64,
    width: f64,
    trim: Trim,
}

const REST: State = State {
    transform: Affine::IDENTITY,
    fill: Tint::NONE,
    stroke: Tint::NONE,
    opacity: 1.0,
    width: 1.0,
    trim: Trim::REST,
};

/// A map searched linearly: a shape has a handful of motions and changes, for which this
/// beats hashing (and allocates only when the first entry arrives).
struct VecMap<K, V>(Vec<(K, V)>);

impl<K, V> Default for VecMap<K, V> {
    fn default() -> Self {
        VecMap(Vec::new())
    }
}

impl<K: PartialEq, V> VecMap<K, V> {
    fn clear(&mut self) {
        self.0.clear();
    }

    fn get(&self, k: &K) -> Option<&V> {
        self.0.iter().find(|(x, _)| x == k).map(|(_, v)| v)
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

/// What an animation instance is to the timeline it plays on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// A forward change.
    Forward,
    /// A reversed change whose forward twin (same step) played before it.
    Paired,
    /// A reversed change with no twin before it: pre-applied, played back to the drawn state.
    First,
}

/// The channel an animation changes (`None` for a morph, which changes the outline: see
/// [`Morphs`]).
fn channel(spec: &AnimSpec) -> Option<Channel> {
    match spec {
        AnimSpec::Motion { .. } | AnimSpec::Follow { .. } => Some(Channel::Transform),
        AnimSpec::Fill(_) => Some(Channel::Fill),
        AnimSpec::Border(_) => Some(Channel::Stroke),
        AnimSpec::Opacity(_) => Some(Channel::Opacity),
        AnimSpec::StrokeWidth(_) => Some(Channel::StrokeWidth),
        AnimSpec::Trim(_) => Some(Channel::Trim),
        AnimSpec::Morph(_) => None,
    }
}

/// Where a layer is in its life.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// A pre-applied inverted slice that has not played yet.
    Pending,
    /// Playing (it has a segment in the current window).
    Running,
    /// A forward motion that has played; its inverted twin may still come.
    Awaiting,
    /// Nothing more to do.
    Done,
}

/// What composition order and twin bookkeeping read of an animation instance (copied, so a
/// layer holds no reference count).
#[derive(Clone, Copy, Debug)]
struct Span {
    /// Identifies the instance (shared by the pieces of a split slice).
    id: *const AnimInst,
    world: bool,
    start: f64,
    end: f64,
    step: usize,
    reversed: bool,
}

impl Span {
    fn of(a: &Arc<AnimInst>) -> Span {
        Span {
            id: Arc::as_ptr(a),
            // A follow carries the shape as a world motion does: it wraps the local
            // motions it plays with, so a local spin turns about the travelling centre.
            world: matches!(
                a.spec,
                AnimSpec::Motion { world: true, .. } | AnimSpec::Follow { .. }
            ),
            start: a.start,
            end: a.end,
            step: a.step,
            reversed: a.reversed,
        }
    }
}

/// One motion on one shape: its transform in its own frame, and the frame.
struct Layer {
    inst: Span,
    /// The motion resolved where it began (canvas at its start, or the layer frame of a
    /// pre-applied inverted slice).
    kind: MotionKind,
    /// Carries `kind` onto the canvas: what the motions outer to it did since.
    frame: Affine,
    /// `kind` carried by `frame`, computed when a segment reads it after the frame changed
    /// (a layer is carried after every slice it plays or waits in, but read only on the
    /// slices it plays: most carried frames are never read). `None` while the frame is the
    /// identity (most layers: the copy would only cost).
    canvas: Option<MotionKind>,
    /// Whether `canvas` is out of date with `frame`.
    stale: bool,
    phase: Phase,
    /// A pre-applied per-vertex motion: it deforms the drawn art itself (innermost, see
    /// [`crate::motion::Track::deform`]), so it stays in the art's frame and is never carried.
    art: bool,
}

impl Layer {
    fn new(inst: Span, kind: MotionKind, frame: Affine, phase: Phase) -> Layer {
        let art = phase == Phase::Pending && matches!(kind, MotionKind::Vertex { .. });
        let frame = if art { Affine::IDENTITY } else { frame };
        Layer {
            inst,
            kind,
            frame,
            canvas: None,
            stale: frame != Affine::IDENTITY,
            phase,
            art,
        }
    }

    fn carry(&mut self, by: Affine) {
        if by == Affine::IDENTITY || self.art {
            return;
        }
        self.frame = by * self.frame;
        self.stale = true;
    }

    /// The motion on the canvas.
    fn canvas(&mut self) -> &MotionKind {
        if self.stale {
            self.canvas = Some(carried(&self.kind, self.frame));
            self.stale = false;
        }
        self.canvas.as_ref().unwrap_or(&self.kind)
    }
}

/// The working buffers of [`track`], kept per thread and reused from shape to shape:
/// compiling a shape needs nine small vectors, and allocating and freeing them for every
/// shape was a large share of its cost. Empty between shapes (nothing is kept alive).
#[derive(Default)]
struct Scratch {
    /// The shape's motion layers, one per motion instance (found by [`Span::id`]).
    layers: Vec<Layer>,
    /// States at slice starts, to find where an attribute change began.
    history: Vec<(f64, State)>,
    /// The latest forward motion layer set at each expansion step: its inverted twin
    /// continues it.
    forward_at_step: VecMap<usize, usize>,
    /// Values a forward attribute change started from, by (step, channel), for its inv_ twin.
    before: VecMap<(usize, Channel), State>,
    /// The composition order of the current slice's changes (indices into its list).
    ordered: Vec<usize>,
    /// The layer index of each segment of the current window.
    window: Vec<usize>,
    /// The relative transform of each segment of the current window.
    rels: Vec<Affine>,
    /// [`Roles::firsts`].
    firsts: Vec<*const AnimInst>,
    /// [`Roles::new`]'s steps of the forward changes seen so far.
    forward_steps: Vec<usize>,
}

impl Scratch {
    fn clear(&mut self) {
        self.layers.clear();
        self.history.clear();
        self.forward_at_step.clear();
        self.before.clear();
        self.ordered.clear();
        self.window.clear();
        self.rels.clear();
        self.firsts.clear();
        self.forward_steps.clear();
    }
}

thread_local! {
    /// One per thread compiling shapes (the rayon workers, or the caller for small scenes).
    static SCRATCH: Cell<Scratch> = Cell::default();
}

/// Compiles one shape's timeline into its track.
pub fn track(shape: &Shape, slices: &[Slice]) -> Track {
    SCRATCH.with(|cell| {
        let mut scratch = cell.take();
        let track = compile(shape, slices, &mut scratch);
        scratch.clear();
        cell.set(scratch);
        track
    })
}

fn compile(shape: &Shape, slices: &[Slice], scratch: &mut Scratch) -> Track {
    let Scratch {
        layers,
        history,
        forward_at_step,
        before,
        ordered,
        window,
        rels,
        firsts,
        forward_steps,
    } = scratch;
    let mut track = Track::default();
    // Reserve each channel's segments up front: one per (slice, change) of that kind.
    let mut counts = [0usize; Channel::COUNT];
    for a in slices.iter().flat_map(|s| s.anims.iter()) {
        if let Some(ch) = channel(&a.spec) {
            counts[ch as usize] += 1;
        }
    }
    track
        .motions
        .reserve_exact(counts[Channel::Transform as usize]);
    track.fill.reserve_exact(counts[Channel::Fill as usize]);
    track.stroke.reserve_exact(counts[Channel::Stroke as usize]);
    track
        .opacity
        .reserve_exact(counts[Channel::Opacity as usize]);
    track
        .stroke_width
        .reserve_exact(counts[Channel::StrokeWidth as usize]);
    track.trim.reserve_exact(counts[Channel::Trim as usize]);

    let roles = Roles::new(shape, slices, firsts, forward_steps);
    let mut state = REST;
    // The pre-applied inverted slices, earliest outermost: the shape starts in their end
    // states (each resolved about the centroid the later ones leave it at).
    let mut first_frame = Affine::IDENTITY;
    {
        // The motions of one slice all pivot where that slice begins, as a forward slice's
        // motions do; slices further on lie further in.
        let mut below = Affine::IDENTITY;
        let mut kinds = Vec::with_capacity(roles.first_motions.len());
        for group in roles.first_motions.chunk_by(|x, y| x.1 == y.1).rev() {
            let centroid = below * shape.centroid;
            let mut product = Affine::IDENTITY;
            for (a, _) in group.iter().rev() {
                let kind = resolve(a, centroid);
                product = full(a, &kind) * product;
                kinds.push(kind);
            }
            below = product * below;
        }
        for ((a, _), kind) in roles.first_motions.iter().zip(kinds.into_iter().rev()) {
            let f = full(a, &kind);
            layers.push(Layer::new(Span::of(a), kind, first_frame, Phase::Pending));
            first_frame *= f;
        }
        state.transform = first_frame;
    }
    // Per channel: the value under a run of pre-applied changes, while one is open.
    let mut run_base: [Option<State>; Channel::COUNT] = [None; Channel::COUNT];
    let mut morphs = Morphs::default();

    for (i, slice) in slices.iter().enumerate() {
        history.push((slice.t0, state));
        let (t0, t1) = (slice.t0, slice.t0 + slice.dur);
        // A pre-applied start needs a window from time 0 to hold it.
        if i == 0 && state.transform != Affine::IDENTITY && !has_motion(slice) {
            track
                .motions
                .push(MotionSeg::linear(t0, t1, &[], state.transform));
        }
        if slice.anims.is_empty() {
            continue;
        }
        // The state where a change set at `tau` began: the current one for a change set on
        // this slice; else, slice starts ascending, the last one at `tau` is found by
        // bisection (a change inherited from a long slice began many slices back).
        let at_start = |tau: f64| {
            if (t0 - tau).abs() <= 1e-9 {
                return state;
            }
            let n = history.partition_point(|(t, _)| *t <= tau + 1e-9);
            n.checked_sub(1)
                .map(|i| history[i])
                .filter(|(t, _)| (*t - tau).abs() <= 1e-9)
                .map_or(state, |(_, s)| s)
        };
        let window_start = state.transform;
        outermost_first(&slice.anims, &roles, ordered);
        window.clear();
        for &k in ordered.iter() {
            let a = &slice.anims[k];
            let tm = a.timing();
            let role = roles.of(a);
            match &a.spec {
                AnimSpec::Motion { .. } | AnimSpec::Follow { .. } => {
                    let id = Arc::as_ptr(a);
                    let li = match layers.iter().position(|l| l.inst.id == id) {
                        Some(li) => li,
                        None => {
                            let layer = match (role, forward_at_step.get(&a.step)) {
                                (Role::Paired, Some(&twin)) => {
                                    let t = &mut layers[twin];
                                    t.phase = Phase::Done;
                                    Layer::new(Span::of(a), t.kind.clone(), t.frame, Phase::Running)
                                }
                                _ => {
                                    let kind = resolve(a, window_start * shape.centroid);
                                    Layer::new(Span::of(a), kind, Affine::IDENTITY, Phase::Running)
                                }
                            };
                            let li = layers.len();
                            layers.push(layer);
                            if role == Role::Forward {
                                if let Some(&old) = forward_at_step.get(&a.step) {
                                    layers[old].phase = Phase::Done;
                                }
                                forward_at_step.insert(a.step, li);
                            }
                            li
                        }
                    };
                    layers[li].phase = Phase::Running;
                    track.motions.push(MotionSeg {
                        t0,
                        t1,
                        timing: tm,
                        kind: layers[li].canvas().clone(),
                        start: window_start,
                    });
                    window.push(li);
                }
                AnimSpec::Morph(spec) => morphs.push(&mut track, a, spec, role, (t0, t1)),
                spec => {
                    let begun = at_start(a.start);
                    let Some(ch) = channel(spec) else {
                        continue;
                    };
                    let get = |s: &State| match ch {
                        Channel::Fill => Value::Tint(s.fill),
                        Channel::Stroke => Value::Tint(s.stroke),
                        Channel::Opacity => Value::Num(s.opacity),
                        Channel::StrokeWidth | Channel::Transform => Value::Num(s.width),
                        Channel::Trim => Value::Trim(s.trim),
                    };
                    let target = target_of(shape, spec);
                    // Value at progress 0 and 1 (a reversed change starts at 1).
                    let (from, to) = match role {
                        Role::Forward => {
                            run_base[ch as usize] = None;
                            before.get_or_insert_with((a.step, ch), || begun);
                            (get(&begun), target)
                        }
                        Role::Paired => {
                            run_base[ch as usize] = None;
                            let back = before.get(&(a.step, ch)).map_or(get(&REST), &get);
                            (back, get(&begun))
                        }
                        Role::First => {
                            // Back to what lies underneath: the next pre-applied change of
                            // this channel, or the value under the whole run.
                            let base = *run_base[ch as usize].get_or_insert(begun);
                            let under = roles.under(a).unwrap_or_else(|| get(&base));
                            (under, target)
                        }
                    };
                    push_attr(&mut track, ch, t0, t1, tm, from, to, role == Role::First);
                }
            }
        }
        // The state at the slice end, read back from what was just emitted.
        if !window.is_empty() {
            let n = track.motions.len();
            let group = &track.motions[n - window.len()..];
            rels.clear();
            rels.extend(group.iter().map(|s| s.relative_at(t1)));
            let mut outer = Affine::IDENTITY;
            for (k, &li) in window.iter().enumerate() {
                layers[li].carry(outer);
                outer *= rels[k];
            }
            state.transform = outer * window_start;
            // Layers not playing here: pre-applied ones lie under everything; a forward
            // motion awaiting its twin is carried by the motions that wrap it and span it,
            // which began no later than it did (none, when every motion here began later).
            let earliest = window
                .iter()
                .map(|&li| layers[li].inst.start)
                .fold(f64::INFINITY, f64::min);
            for li in 0..layers.len() {
                match layers[li].phase {
                    Phase::Pending => layers[li].carry(outer),
                    Phase::Awaiting if earliest <= layers[li].inst.start + 1e-9 => {
                        let by = wrapping(layers, li, window, rels);
                        layers[li].carry(by);
                    }
                    _ => {}
                }
            }
            for &li in window.iter() {
                let l = &mut layers[li];
                if l.inst.end <= t1 + 1e-9 {
                    l.phase = if l.inst.reversed || forward_at_step.get(&l.inst.step) != Some(&li) {
                        Phase::Done
                    } else {
                        Phase::Awaiting
                    };
                }
            }
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
        if let Some(s) = track.trim.last().filter(|s| s.t0 == t0) {
            state.trim = s.value_at(t1);
        }
    }
    track
}

fn has_motion(slice: &Slice) -> bool {
    slice
        .anims
        .iter()
        .any(|a| matches!(a.spec, AnimSpec::Motion { .. } | AnimSpec::Follow { .. }))
}

/// The outline channel while a shape's timeline compiles: morphs replace the outline, as
/// attributes replace their values (a chained morph starts from where the last one ended,
/// an inverted twin plays its twin's outlines backwards, a pre-applied one holds its
/// target from time 0). Every morph of the track has one structure (each path the same
/// subpaths of the same segment counts): a morph matched after others cuts theirs again
/// ([`crate::morph::Refine`]), which leaves their in-betweens as they were.
#[derive(Default)]
struct Morphs {
    /// The outlines now (each path in its own coordinates, of the track's structure) and
    /// their centroid on the canvas; `None` while the paths are as drawn.
    current: Option<(Arc<[BezPath]>, Point)>,
    /// Each morph's pair of matched outlines, by instance (the pieces of a split slice
    /// share it).
    pairs: VecMap<*const AnimInst, MorphPair>,
    /// The latest forward morph set at each expansion step: its inverted twin plays it back.
    at_step: VecMap<usize, *const AnimInst>,
}

#[derive(Clone)]
struct MorphPair {
    from: Arc<[BezPath]>,
    to: Arc<[BezPath]>,
    /// The centroids of `from` and `to` on the canvas.
    centroids: (Point, Point),
}

impl Morphs {
    fn push(
        &mut self,
        track: &mut Track,
        a: &Arc<AnimInst>,
        spec: &MorphSpec,
        role: Role,
        (t0, t1): (f64, f64),
    ) {
        let id = Arc::as_ptr(a);
        let twin = match role {
            Role::Paired => self
                .at_step
                .get(&a.step)
                .and_then(|k| self.pairs.get(k))
                .cloned(),
            _ => None,
        };
        let pair = match (self.pairs.get(&id), twin) {
            (Some(p), _) => p.clone(),
            // Back from where the paths are to where the twin began: the same structure.
            (None, Some(twin)) => match &self.current {
                Some((now, c)) => MorphPair {
                    from: twin.from,
                    to: now.clone(),
                    centroids: (twin.centroids.0, *c),
                },
                None => twin,
            },
            (None, None) => self.matched(track, spec),
        };
        if self.pairs.get(&id).is_none() {
            self.pairs.insert(id, pair.clone());
            if role == Role::Forward {
                self.at_step.insert(a.step, id);
            }
        }
        if role == Role::First && track.morphs.is_empty() && t0 > 0.0 {
            track.morphs.push(MorphSeg {
                t0: 0.0,
                t1: t0,
                timing: Timing::linear(0.0, t0),
                from: pair.to.clone(),
                to: pair.to.clone(),
            });
        }
        track.morphs.push(MorphSeg {
            t0,
            t1,
            timing: a.timing(),
            from: pair.from.clone(),
            to: pair.to.clone(),
        });
        // Once the morph has played out, the next one starts from where it left the paths:
        // its target after a forward morph, where it began after one played backwards.
        if a.end <= t1 + 1e-9 {
            self.current = Some(match role {
                Role::Forward => (pair.to, pair.centroids.1),
                _ => (pair.from, pair.centroids.0),
            });
        }
    }

    /// A new morph matched from the current outlines to `spec`'s target; the outlines
    /// already in the track are cut again to the structure it leaves.
    fn matched(&mut self, track: &mut Track, spec: &MorphSpec) -> MorphPair {
        let (current, centroid): (Vec<BezPath>, Point) = match &self.current {
            Some((paths, c)) => (paths.to_vec(), *c),
            None => (
                spec.art.iter().map(|(_, p)| p.clone()).collect(),
                spec.centroid,
            ),
        };
        let placed = super::morph::placed(spec, centroid);
        let placed_centroid = super::morph::centroid_of(spec, &placed);
        let mut from = Vec::with_capacity(placed.len());
        let mut to = Vec::with_capacity(placed.len());
        for (leaf, (cur, target)) in current.iter().zip(&placed).enumerate() {
            if self.current.is_none() {
                let (a, b) = crate::morph::correspond(cur, target);
                from.push(a);
                to.push(b);
                continue;
            }
            let (a, b, refine) = crate::morph::correspond_from(cur, target);
            from.push(a);
            to.push(b);
            self.refine(track, leaf, &refine);
        }
        MorphPair {
            from: from.into(),
            to: to.into(),
            centroids: (centroid, placed_centroid),
        }
    }

    /// Cuts path `leaf` of every outline kept so far to a chain's new structure.
    fn refine(&mut self, track: &mut Track, leaf: usize, refine: &crate::morph::Refine) {
        let cut = |paths: &Arc<[BezPath]>| -> Arc<[BezPath]> {
            let mut v = paths.to_vec();
            if let Some(p) = v.get_mut(leaf) {
                *p = refine.apply(p);
            }
            v.into()
        };
        // Outlines shared by several segments are cut once and shared again.
        let mut done: Vec<(*const [BezPath], Arc<[BezPath]>)> = Vec::new();
        let mut once = |paths: &mut Arc<[BezPath]>| {
            let key = Arc::as_ptr(paths);
            let new = match done.iter().find(|(k, _)| std::ptr::addr_eq(*k, key)) {
                Some((_, n)) => n.clone(),
                None => {
                    let n = cut(paths);
                    done.push((key, n.clone()));
                    n
                }
            };
            *paths = new;
        };
        for seg in &mut track.morphs {
            once(&mut seg.from);
            once(&mut seg.to);
        }
        for (_, pair) in &mut self.pairs.0 {
            once(&mut pair.from);
            once(&mut pair.to);
        }
        if let Some((now, _)) = &mut self.current {
            once(now);
        }
    }
}

/// The product, outermost first, of the window's segments that wrap the awaiting motion
/// `li` (outer to it by the composition order) and span its whole slice (the slice it was
/// split from set them): what its inverted twin must be carried by to undo exactly it.
fn wrapping(layers: &[Layer], li: usize, window: &[usize], rels: &[Affine]) -> Affine {
    let a = &layers[li].inst;
    let mut by = Affine::IDENTITY;
    for (k, &lj) in window.iter().enumerate() {
        let m = &layers[lj].inst;
        let outer = wraps(m, a) == std::cmp::Ordering::Greater;
        if outer && m.start <= a.start + 1e-9 && m.end >= a.end - 1e-9 {
            by *= rels[k];
        }
    }
    by
}

/// An attribute value of either kind.
#[derive(Clone, Copy, Debug)]
enum Value {
    Tint(Tint),
    Num(f64),
    Trim(Trim),
}

/// Pushes an attribute change onto its channel; a pre-applied change that opens its channel
/// first holds its start value from time 0.
#[allow(clippy::too_many_arguments)]
fn push_attr(
    track: &mut Track,
    ch: Channel,
    t0: f64,
    t1: f64,
    timing: Timing,
    from: Value,
    to: Value,
    pre_applied: bool,
) {
    fn push<T: Copy>(
        segs: &mut Vec<AttrSeg<T>>,
        t0: f64,
        t1: f64,
        timing: Timing,
        from: T,
        to: T,
        pre: bool,
    ) {
        if pre && segs.is_empty() && t0 > 0.0 {
            segs.push(AttrSeg::linear(0.0, t0, to, to));
        }
        segs.push(AttrSeg {
            t0,
            t1,
            timing,
            from,
            to,
        });
    }
    match (ch, from, to) {
        (Channel::Fill, Value::Tint(f), Value::Tint(t)) => {
            push(&mut track.fill, t0, t1, timing, f, t, pre_applied)
        }
        (Channel::Stroke, Value::Tint(f), Value::Tint(t)) => {
            push(&mut track.stroke, t0, t1, timing, f, t, pre_applied)
        }
        (Channel::Opacity, Value::Num(f), Value::Num(t)) => {
            push(&mut track.opacity, t0, t1, timing, f, t, pre_applied)
        }
        (Channel::StrokeWidth, Value::Num(f), Value::Num(t)) => {
            push(&mut track.stroke_width, t0, t1, timing, f, t, pre_applied)
        }
        (Channel::Trim, Value::Trim(f), Value::Trim(t)) => {
            push(&mut track.trim, t0, t1, timing, f, t, pre_applied)
        }
        // A channel's values are all of its kind, and motions are not attributes.
        _ => {}
    }
}

/// Every reversed animation of a timeline classified once, in time order. A forward one is
/// always [`Role::Forward`] and a reversed one [`Role::Paired`] unless listed as
/// pre-applied, so only the pre-applied ones are stored: most timelines have none (the
/// usual `[a, b, inv_a]` pairs every reversed one), and then nothing here allocates.
struct Roles<'a> {
    /// The reversed animations classified [`Role::First`]; every other reversed one is
    /// [`Role::Paired`].
    firsts: &'a [*const AnimInst],
    /// Pre-applied inverted motions, earliest first (ties in composition order), with the
    /// index of the slice they begin on.
    first_motions: Vec<(&'a Arc<AnimInst>, usize)>,
    /// For a pre-applied attribute change: the target of the next change of its channel
    /// when that one is pre-applied too (what it plays back to).
    under: VecMap<*const AnimInst, Value>,
}

impl<'a> Roles<'a> {
    /// Classifies the reversed animations of `slices`, the pre-applied ones into `firsts`
    /// (`forward_steps` is a buffer), which the result then reads.
    fn new(
        shape: &Shape,
        slices: &'a [Slice],
        firsts: &'a mut Vec<*const AnimInst>,
        forward_steps: &mut Vec<usize>,
    ) -> Roles<'a> {
        if !slices.iter().any(|s| s.anims.iter().any(|a| a.reversed)) {
            return Roles {
                firsts,
                first_motions: Vec::new(),
                under: VecMap::default(),
            };
        }
        // Steps of the forward changes seen so far: a reversed change is paired when its
        // step is among them.
        let mut first_motions = Vec::new();
        let mut firsts_here: Vec<&'a Arc<AnimInst>> = Vec::new();
        let mut first_attrs = false;
        for (si, slice) in slices.iter().enumerate() {
            // Inverted slices that come first compose innermost, in the order the slice
            // composes its motions (outermost first, see `outermost_first`).
            firsts_here.clear();
            for a in slice.anims.iter() {
                if !a.reversed {
                    if !forward_steps.contains(&a.step) {
                        forward_steps.push(a.step);
                    }
                    continue;
                }
                // A change split over several slices is seen once per piece; only its first
                // piece classifies it (a paired one stays paired: the steps only grow).
                let id = Arc::as_ptr(a);
                if forward_steps.contains(&a.step) || firsts.contains(&id) {
                    continue;
                }
                firsts.push(id);
                match channel(&a.spec) {
                    Some(Channel::Transform) => firsts_here.push(a),
                    Some(_) => first_attrs = true,
                    None => {}
                }
            }
            firsts_here.sort_by(|a, b| wraps(&Span::of(b), &Span::of(a)));
            first_motions.extend(firsts_here.iter().map(|&a| (a, si)));
        }
        let mut roles = Roles {
            firsts,
            first_motions,
            under: VecMap::default(),
        };
        if first_attrs {
            roles.under = roles.under_of(shape, slices);
        }
        roles
    }

    /// For each pre-applied attribute change followed (in its channel, each change counted
    /// once) by another pre-applied one: that one's target.
    fn under_of(&self, shape: &Shape, slices: &[Slice]) -> VecMap<*const AnimInst, Value> {
        let mut channels: [Vec<(&Arc<AnimInst>, Role)>; Channel::COUNT] = Default::default();
        for a in slices.iter().flat_map(|s| s.anims.iter()) {
            let Some(ch) = channel(&a.spec).filter(|&c| c != Channel::Transform) else {
                continue;
            };
            let list = &mut channels[ch as usize];
            if list.iter().any(|(b, _)| Arc::ptr_eq(a, b)) {
                continue;
            }
            list.push((a, self.of(a)));
        }
        let mut under = VecMap::default();
        for list in &channels {
            for w in list.windows(2) {
                if w[0].1 == Role::First && w[1].1 == Role::First {
                    under.insert(Arc::as_ptr(w[0].0), target_of(shape, &w[1].0.spec));
                }
            }
        }
        under
    }

    fn of(&self, a: &Arc<AnimInst>) -> Role {
        if !a.reversed {
            Role::Forward
        } else if self.firsts.contains(&Arc::as_ptr(a)) {
            Role::First
        } else {
            Role::Paired
        }
    }

    fn under(&self, a: &Arc<AnimInst>) -> Option<Value> {
        self.under.get(&Arc::as_ptr(a)).copied()
    }
}

/// The value an attribute change goes to.
fn target_of(shape: &Shape, spec: &AnimSpec) -> Value {
    match spec {
        AnimSpec::Fill(c) | AnimSpec::Border(c) => Value::Tint(Tint::full(*c)),
        AnimSpec::Opacity(x) => Value::Num(*x),
        AnimSpec::Trim(x) => Value::Trim(*x),
        AnimSpec::StrokeWidth(w) if shape.stroke_width > 0.0 => Value::Num(w / shape.stroke_width),
        _ => Value::Num(1.0),
    }
}

/// A motion resolved about a centroid: its pivot (the centroid for local motions, the origin
/// for world ones, plus the offset of a transform written about a point) and the grid cells
/// it reads there.
fn resolve(a: &AnimInst, centroid: Point) -> MotionKind {
    if let AnimSpec::Follow {
        route,
        world,
        orient,
    } = &a.spec
    {
        let f = crate::motion::follow::Follow::new(route.clone(), centroid, *world, *orient);
        return MotionKind::Follow(Arc::new(f));
    }
    let AnimSpec::Motion {
        grid,
        world,
        pivot_offset,
        lookup,
        interp,
    } = &a.spec
    else {
        return MotionKind::Rigid {
            pivot: Point::ORIGIN,
            blend: Arc::from([]),
            interp: Interp::Linear,
        };
    };
    let pivot = if *world { Point::ORIGIN } else { centroid } + *pivot_offset;
    if *lookup == Lookup::Vertex {
        return MotionKind::Vertex {
            grid: grid.clone(),
            pivot: Some(pivot),
        };
    }
    MotionKind::Rigid {
        pivot,
        blend: grid.lookup(centroid, *lookup),
        interp: *interp,
    }
}

/// The transform a pre-applied inverted motion starts at: the progress its reversed timing
/// has at the slice start (the twin's end, `ease(1)`).
fn full(a: &AnimInst, kind: &MotionKind) -> Affine {
    kind.at(a.timing().progress(a.start))
}

/// `kind` carried by `g`: `g·F(p)·g⁻¹` at every progress. The pivot moves by `g`; the
/// components are conjugated by `g`'s linear part, exactly for translations, matrices and
/// scales (all linear in progress), for rotations under similarities and for anything under
/// a uniform scale. A rotation or skew carried by a shear is matched at its ends and
/// interpolated entry by entry between them (Alexa interpolation stays exact throughout).
fn carried(kind: &MotionKind, g: Affine) -> MotionKind {
    if g == Affine::IDENTITY {
        return kind.clone();
    }
    match kind {
        MotionKind::Rigid {
            pivot,
            blend,
            interp,
        } => {
            let [a, b, c, d, _, _] = g.as_coeffs();
            let linear = Affine::new([a, b, c, d, 0.0, 0.0]);
            let tol = 1e-12 * (a.abs() + b.abs() + c.abs() + d.abs());
            let blend = if (a - 1.0).abs() <= tol
                && b.abs() <= tol
                && c.abs() <= tol
                && (d - 1.0).abs() <= tol
            {
                blend.clone()
            } else {
                blend
                    .iter()
                    .map(|(w, cs)| {
                        let cs: Arc<[Component]> =
                            cs.iter().map(|x| conjugate(*x, linear, tol)).collect();
                        (*w, cs)
                    })
                    .collect()
            };
            MotionKind::Rigid {
                pivot: g * *pivot,
                blend,
                interp: *interp,
            }
        }
        // The pivot stays in the grid's own frame, which the grid carries.
        MotionKind::Vertex { grid, pivot } => MotionKind::Vertex {
            grid: Arc::new(grid.framed(g)),
            pivot: *pivot,
        },
        MotionKind::Follow(f) => MotionKind::Follow(Arc::new(f.carried(g))),
    }
}

/// `l·c·l⁻¹` for a linear map `l`, as a component.
fn conjugate(c: Component, l: Affine, tol: f64) -> Component {
    let [a, b, cc, d, _, _] = l.as_coeffs();
    let similar = (a - d).abs() <= tol && (b + cc).abs() <= tol;
    let mirror = (a + d).abs() <= tol && (b - cc).abs() <= tol;
    let uniform = similar && b.abs() <= tol && cc.abs() <= tol;
    let matrix = |m: Affine| Component::Matrix(l * m * l.inverse());
    match c {
        Component::Translate(v) => {
            Component::Translate(Vec2::new(a * v.x + cc * v.y, b * v.x + d * v.y))
        }
        Component::Rotate(deg) if similar => Component::Rotate(deg),
        Component::Rotate(deg) if mirror => Component::Rotate(-deg),
        Component::Scale(k) if k.x == k.y && (similar || mirror) => c,
        Component::Skew(..) if uniform => c,
        Component::Matrix(m) => matrix(m),
        other => matrix(other.at(1.0)),
    }
}

/// The order in which the motions of one slice compose, outermost first (see [`wraps`]).
/// World motions wrap local ones, so a shape that moves across the canvas while spinning
/// spins about its own (moving) centre and a world rotation turns the whole path it
/// travels. An inverted twin takes its twin's place (same
/// rule), so it undoes the twin in place; pre-applied inverted slices lie innermost.
/// Attribute changes do not compose and keep their order.
fn outermost_first(anims: &[Arc<AnimInst>], roles: &Roles, out: &mut Vec<usize>) {
    let is_motion = |k: &usize| {
        matches!(
            anims[*k].spec,
            AnimSpec::Motion { .. } | AnimSpec::Follow { .. }
        )
    };
    out.clear();
    out.extend((0..anims.len()).filter(is_motion));
    out.sort_by(|&x, &y| wraps(&Span::of(&anims[y]), &Span::of(&anims[x])));
    let motions = out.len();
    out.extend((0..anims.len()).filter(|k| !is_motion(k)));
    // Stable: pre-applied motions move to the end of the motions, in their order.
    out[..motions].sort_by_key(|&k| roles.of(&anims[k]) == Role::First);
}

/// How motion `a` composes against `b` when both play: `Greater` when `a` is outer. World
/// wraps local; then a motion inherited from a longer slice wraps what its pieces add (so
/// it keeps running undisturbed through them); then, on one slice, the later rule wraps.
fn wraps(a: &Span, b: &Span) -> std::cmp::Ordering {
    a.world
        .cmp(&b.world)
        .then((a.end - a.start).total_cmp(&(b.end - b.start)))
        .then(a.step.cmp(&b.step))
}
