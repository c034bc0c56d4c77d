//! Fast evaluation of a whole animation, frame after frame.
//!
//! [`Track::transform_at`] finds the window holding `t`, then recomputes the progress at the
//! window start and inverts `F(p₀)` for every segment on every call. A [`Sampler`] does that
//! work once: it groups every track's segments into windows laid out flat in shape order
//! (so a frame walks memory forward; large animations in parts of consecutive shapes,
//! compiled in parallel), stores each window's start and settled end
//! transforms, and each segment's `F(p₀)⁻¹`. Per shape and frame what remains is a scan of
//! a few start times and, inside a moving window, one `F(p)` per segment.
//!
//! Evaluation is bound by memory traffic more than by arithmetic, so the data a frame
//! reads is split by how often it is read: start times apart (scanned for every shape),
//! settled values apart (read by most shapes most of the time), and the full segment
//! records (read only while something moves) kept small.
//!
//! The arithmetic is the same as [`Track::transform_at`]'s, step for step, so both give
//! identical results; tests compare them on every example grammar.

use std::collections::HashMap;

use kurbo::{Affine, Point};
use rayon::prelude::*;

use super::{
    Animation, AttrSeg, Blendable, Component, Interp, MotionKind, MotionSeg, ShapeState, Timing,
    Tint, Track, Trim, attr_at, component::product_at, grid,
};
use crate::signals::Easing;

mod playhead;
pub use playhead::Playhead;

/// [`Clock::ease`] of a linear timing, which needs no easing call.
const LINEAR: u32 = u32::MAX;
/// [`Seg::inv0`] when `F(p₀)` is the identity.
const NO_INVERSE: u32 = u32::MAX;
/// [`Seg::comps`]' count marking a segment evaluated through its [`MotionSeg`].
const SLOW: u32 = u32::MAX;

/// How a [`Timing`]'s progress follows time: its span resolved and its easing moved out
/// of line. All that evaluating a running change needs.
#[derive(Clone, Copy)]
pub(super) struct Pace {
    start: f64,
    delay: f64,
    /// `max(end − start − delay, 0)`, as [`Timing::progress`] computes it.
    span: f64,
    /// Index into [`Part::eases`], or [`LINEAR`].
    ease: u32,
    reversed: bool,
}

impl Pace {
    /// [`Timing::progress`], step for step.
    #[inline(always)]
    pub(super) fn progress(&self, t: f64, eases: &[Easing]) -> f64 {
        let local = if self.reversed {
            t - self.start
        } else {
            t - self.start - self.delay
        };
        let u = if self.span <= 0.0 {
            if local >= 0.0 { 1.0 } else { 0.0 }
        } else {
            (local / self.span).clamp(0.0, 1.0)
        };
        let u = if self.reversed { 1.0 - u } else { u };
        if self.ease == LINEAR {
            // What `Easing::Linear.apply` returns for `u` in [0, 1] or NaN.
            if u.is_nan() { 0.0 } else { u }
        } else {
            eases[self.ease as usize].apply(u)
        }
    }
}

/// A [`Pace`] with the interval in which its progress can move.
#[derive(Clone, Copy)]
pub(super) struct Clock {
    pub(super) pace: Pace,
    /// The progress cannot change before this time…
    still_before: f64,
    /// …nor from this time on (see [`Clock::new`]).
    still_after: f64,
}

impl Clock {
    fn new(t: &Timing, eases: &mut Vec<Easing>) -> Clock {
        let ease = if t.ease == Easing::Linear {
            LINEAR
        } else if let Some(i) = eases.iter().take(64).position(|e| *e == t.ease) {
            // Grammars use a handful of easings: keeping each once keeps the list short
            // (searching only its start bounds the cost when easings vary per shape).
            i as u32
        } else {
            eases.push(t.ease.clone());
            eases.len() as u32 - 1
        };
        // The progress moves only inside `active()`. Rounding in `progress` may shift that
        // interval's ends by an ulp, so the still ranges stop well short of them.
        let (a0, a1) = t.active();
        let margin = |a: f64| 1e-9 * (1.0 + a.abs());
        Clock {
            pace: Pace {
                start: t.start,
                delay: t.delay,
                span: (t.end - t.start - t.delay).max(0.0),
                ease,
                reversed: t.reversed,
            },
            still_before: a0 - margin(a0),
            still_after: a1 + margin(a1),
        }
    }

    /// Whether the progress may be moving at `t`, and the next time that can change.
    #[inline(always)]
    pub(super) fn moving_until(&self, t: f64) -> (bool, f64) {
        if t < self.still_before {
            (false, self.still_before)
        } else if t < self.still_after {
            (true, self.still_after)
        } else {
            (false, f64::INFINITY)
        }
    }

    #[inline(always)]
    fn progress(&self, t: f64, eases: &[Easing]) -> f64 {
        self.pace.progress(t, eases)
    }
}

/// One moving segment with its start progress and inverse resolved.
struct Seg {
    t0: f64,
    t1: f64,
    clock: Clock,
    /// Progress at the window start.
    p0: f64,
    /// Centre of the product (the origin for world motions).
    pivot: Point,
    /// First component in [`Sampler::comps`], or an index into [`Sampler::slow`].
    first: u32,
    /// Number of components, or [`SLOW`] for segments evaluated through their
    /// [`MotionSeg`] (blends of grid cells, Alexa interpolation).
    count: u32,
    /// `F(p₀)⁻¹` in [`Sampler::inverses`], or [`NO_INVERSE`] when `p₀ = 0`.
    inv0: u32,
    /// The slot remembering this segment's shared lookup's last product, or [`NO_SLOT`].
    slot: u32,
}

/// [`Seg::slot`] of a segment whose product is not remembered.
const NO_SLOT: u32 = u32::MAX;

/// The last product of each shared component list, by slot: `(progress bits, product)`.
///
/// A rule applied to many shapes gives all of them one grid lookup (a shared
/// [`super::Blend`] when the grid is constant), and shapes whose slices line up reach the
/// same progress at every instant. Evaluating the shapes of a frame one after the other, the product (with its sines and tangents) is then
/// computed once per frame instead of once per shape. A slot is reused only for the very
/// same progress bits, and the product is a pure function of the list and the progress, so
/// the result is bit for bit what computing it gives.
type Products = [(u64, Affine)];

/// Progress bits no progress has (a NaN payload), marking an empty slot.
const EMPTY_SLOT: u64 = u64::MAX;

/// Where one shape's data starts in each flat array.
#[derive(Clone, Copy, Default)]
struct Offsets {
    windows: u32,
    fill: u32,
    stroke: u32,
    opacity: u32,
    width: u32,
}

/// The last of a shape's entries `starts[lo..hi]` (sorted start times) that has started at
/// `t`, by a scan from the first.
#[inline(always)]
fn current(starts: &[f64], lo: u32, hi: u32, t: f64) -> Option<usize> {
    let (lo, hi) = (lo as usize, hi as usize);
    let k = starts[lo..hi].iter().take_while(|&&t0| t0 <= t).count();
    (k > 0).then(|| lo + k - 1)
}

/// [`current`] for a [`Playhead`]: `cursor` (the index just past the last started entry)
/// only moves forward, and `quiet` is lowered to the next entry's start.
#[inline(always)]
fn advance(
    starts: &[f64],
    cursor: &mut u32,
    lo: u32,
    hi: u32,
    t: f64,
    quiet: &mut f64,
) -> Option<usize> {
    let (lo, hi) = (lo as usize, hi as usize);
    let mut c = *cursor as usize;
    while c < hi && starts[c] <= t {
        c += 1;
    }
    *cursor = c as u32;
    if c < hi {
        *quiet = quiet.min(starts[c]);
    }
    (c > lo).then(|| c - 1)
}

/// [`product_at`], written out for the one- and two-component lists nearly every motion
/// has, so it is inlined and the product does not come back through memory (reading it
/// there in other pairs of entries than were written stalls the loads). Same operations
/// in the same order, so the same bits.
#[inline(always)]
fn product(comps: &[Component], p: f64) -> Affine {
    match comps {
        [c] => c.at(p),
        [c0, c1] => c0.at(p) * c1.at(p),
        _ => product_at(comps, p),
    }
}

/// [`product`], through `slot` of `products` when it has one (see [`Products`]).
#[inline(always)]
fn remembered(comps: &[Component], p: f64, slot: u32, products: &mut Products) -> Affine {
    // `NO_SLOT` is past any slot, and an empty `products` has none.
    match products.get_mut(slot as usize) {
        Some(slot) => {
            if slot.0 != p.to_bits() {
                *slot = (p.to_bits(), product(comps, p));
            }
            slot.1
        }
        None => product(comps, p),
    }
}

/// One attribute channel of every shape, flat in shape order.
struct ChangeList<T> {
    /// Segment start times.
    t0: Vec<f64>,
    /// Segment end and the value held from then on: what most frames read.
    settled: Vec<(f64, T)>,
    /// Timing and endpoints, read only while the segment runs.
    moving: Vec<(Clock, T, T)>,
}

impl<T: Blendable> ChangeList<T> {
    fn with_capacity(n: usize) -> ChangeList<T> {
        ChangeList {
            t0: Vec::with_capacity(n),
            settled: Vec::with_capacity(n),
            moving: Vec::with_capacity(n),
        }
    }

    fn len(&self) -> u32 {
        self.t0.len() as u32
    }

    fn extend(&mut self, segs: &[AttrSeg<T>], eases: &mut Vec<Easing>) {
        for s in segs {
            self.t0.push(s.t0);
            self.settled.push((s.t1, s.value_at(s.t1)));
            self.moving
                .push((Clock::new(&s.timing, eases), s.from, s.to));
        }
    }

    /// One shape's value at `t`; its segments are `lo..hi`. Same result as `attr_at` on
    /// the track's own list.
    #[inline(always)]
    fn at(&self, lo: u32, hi: u32, t: f64, default: T, eases: &[Easing]) -> T {
        let Some(i) = current(&self.t0, lo, hi, t) else {
            return default;
        };
        let (t1, end) = self.settled[i];
        if t >= t1 {
            return end;
        }
        let (clock, from, to) = &self.moving[i];
        from.blend(*to, clock.progress(t.clamp(self.t0[i], t1), eases))
    }

    /// What a [`Playhead`] needs of one shape's channel at `t`: the value while it holds
    /// still, or the entry that is running. `cursor` counts the shape's entries that have
    /// started (as an index into the flat arrays) and only moves forward.
    #[inline(always)]
    fn mode(
        &self,
        cursor: &mut u32,
        lo: u32,
        hi: u32,
        t: f64,
        default: T,
        eases: &[Easing],
    ) -> Mode<T> {
        let mut next = f64::INFINITY;
        let Some(i) = advance(&self.t0, cursor, lo, hi, t, &mut next) else {
            return Mode::Still(default, next);
        };
        let (t1, end) = self.settled[i];
        if t >= t1 {
            return Mode::Still(end, next);
        }
        let (clock, from, to) = &self.moving[i];
        let (moving, change) = clock.moving_until(t);
        let until = next.min(t1).min(change);
        if moving {
            Mode::Moving(i, until)
        } else {
            Mode::Still(
                from.blend(*to, clock.progress(t.clamp(self.t0[i], t1), eases)),
                until,
            )
        }
    }
}

/// A channel of one shape as a [`Playhead`] sees it at some `t`.
enum Mode<T> {
    /// The value, held from `t` up to (not including) the time given.
    Still(T, f64),
    /// The running entry (index into the flat arrays), which may move from `t` up to the
    /// time given.
    Moving(usize, f64),
}

/// Shapes per [`Part`]. Parts are compiled in parallel; a thousand shapes amortise the
/// hand-over to a thread, and 8k-shape scenes still give every core several parts.
const PART: usize = 1024;

/// Every track of an animation compiled for repeated sampling. Borrows the animation.
///
/// The shapes are cut into parts of a thousand-odd consecutive shapes, compiled in
/// parallel and each laid out flat; evaluation walks them in order, so a frame still reads
/// memory forward.
pub struct Sampler<'a> {
    parts: Vec<Part<'a>>,
    /// Number of shapes.
    len: usize,
    /// Number of product slots (see [`Products`]) over all parts.
    slots: usize,
}

/// Only the size: the compiled parts are large and have no readable form.
impl std::fmt::Debug for Sampler<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sampler")
            .field("shapes", &self.len)
            .finish_non_exhaustive()
    }
}

/// The compiled tracks of consecutive shapes.
struct Part<'a> {
    /// Per shape where its data starts, plus one entry for the end.
    offsets: Vec<Offsets>,
    /// Window start times, scanned for every shape and frame.
    t0s: Vec<f64>,
    /// Per window: from this time on its value no longer changes, and that value.
    settled: Vec<(f64, Affine)>,
    /// Per window: the accumulated transform before it and its range in `segs`.
    windows: Vec<(Affine, (u32, u32))>,
    segs: Vec<Seg>,
    comps: Vec<super::Component>,
    /// Segments whose `F(p)` is not a single product.
    slow: Vec<&'a MotionSeg>,
    inverses: Vec<Affine>,
    /// Easings other than linear, each once.
    eases: Vec<Easing>,
    /// The shared component lists met, by the slot number this part gave them (their
    /// address); [`Sampler::new`] renumbers the slots over all parts.
    shared: Vec<usize>,
    fill: ChangeList<Tint>,
    stroke: ChangeList<Tint>,
    opacity: ChangeList<f64>,
    width: ChangeList<f64>,
    /// The shapes whose strokes are trimmed (part index, changes): few, so looked up as
    /// the track does rather than compiled.
    trims: Vec<(u32, &'a [AttrSeg<Trim>])>,
}

impl<'a> Sampler<'a> {
    /// Compiles every track of `anim` (in parallel for large animations; the result does
    /// not depend on the number of threads).
    pub fn new(anim: &'a Animation) -> Sampler<'a> {
        let tracks = &anim.tracks[..];
        let mut parts: Vec<Part<'a>> = if tracks.len() <= PART {
            tracks.chunks(PART).map(Part::new).collect()
        } else {
            tracks.par_chunks(PART).map(Part::new).collect()
        };
        // Number the shared lists over all parts, in shape order.
        let mut ids: HashMap<usize, u32> = HashMap::new();
        let renumber: Vec<Vec<u32>> = parts
            .iter()
            .map(|p| {
                p.shared
                    .iter()
                    .map(|&list| {
                        let next = ids.len() as u32;
                        *ids.entry(list).or_insert(next)
                    })
                    .collect()
            })
            .collect();
        // The first part numbered its lists from 0 in this same order, so its slots
        // already are the global ones (and a small animation, one part, needs no threads).
        if parts.len() > 1 {
            parts[1..]
                .par_iter_mut()
                .zip(&renumber[1..])
                .for_each(|(part, ids)| {
                    for s in part.segs.iter_mut().filter(|s| s.slot != NO_SLOT) {
                        s.slot = ids[s.slot as usize];
                    }
                });
        }
        Sampler {
            parts,
            len: tracks.len(),
            slots: ids.len(),
        }
    }

    /// Number of shapes.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the animation has no shapes.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Shape `i`'s rigid transform at `t` (equal to `tracks[i].transform_at(t)`).
    pub fn transform_at(&self, i: usize, t: f64) -> Affine {
        let (p, j) = (&self.parts[i / PART], i % PART);
        p.transform(p.offsets[j].windows, p.offsets[j + 1].windows, t)
    }

    /// A playhead for evaluating frames in time order.
    pub fn playhead(&self) -> Playhead<'_, 'a> {
        Playhead::new(self)
    }

    /// Shape `i`'s state at `t` (equal to `tracks[i].state_at(t)`).
    #[inline]
    pub fn state_at(&self, i: usize, t: f64) -> ShapeState {
        self.parts[i / PART].state_at(i % PART, t)
    }

    /// Every shape's state at `t`, written into `out` (cleared first).
    pub fn evaluate_into(&self, t: f64, out: &mut Vec<ShapeState>) {
        out.clear();
        for p in &self.parts {
            out.extend((0..p.len()).map(|i| p.state_at(i, t)));
        }
    }

    /// Every shape's state at `t`.
    pub fn evaluate(&self, t: f64) -> Vec<ShapeState> {
        let mut out = Vec::with_capacity(self.len());
        self.evaluate_into(t, &mut out);
        out
    }
}

impl<'a> Part<'a> {
    /// Compiles consecutive tracks.
    fn new(tracks: &'a [Track]) -> Part<'a> {
        let total: usize = tracks.iter().map(|t| t.motions.len()).sum();
        let count = |f: fn(&Track) -> usize| tracks.iter().map(f).sum::<usize>();
        let mut s = Part {
            offsets: Vec::with_capacity(tracks.len() + 1),
            t0s: Vec::with_capacity(total),
            settled: Vec::with_capacity(total),
            windows: Vec::with_capacity(total),
            segs: Vec::with_capacity(total),
            comps: Vec::with_capacity(total * 2),
            slow: Vec::new(),
            // At most one inverse per segment; pages never written are never faulted in.
            inverses: Vec::with_capacity(total),
            eases: Vec::new(),
            shared: Vec::new(),
            fill: ChangeList::with_capacity(count(|t| t.fill.len())),
            stroke: ChangeList::with_capacity(count(|t| t.stroke.len())),
            opacity: ChangeList::with_capacity(count(|t| t.opacity.len())),
            width: ChangeList::with_capacity(count(|t| t.stroke_width.len())),
            trims: tracks
                .iter()
                .enumerate()
                .filter(|(_, t)| !t.trim.is_empty())
                .map(|(i, t)| (i as u32, &t.trim[..]))
                .collect(),
        };
        let mut slots = HashMap::new();
        for track in tracks {
            s.offsets.push(s.here());
            s.add_track(track, &mut slots);
            s.fill.extend(&track.fill, &mut s.eases);
            s.stroke.extend(&track.stroke, &mut s.eases);
            s.opacity.extend(&track.opacity, &mut s.eases);
            s.width.extend(&track.stroke_width, &mut s.eases);
        }
        s.offsets.push(s.here());
        s
    }

    /// Number of shapes.
    fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Each shape's cursors before anything has started.
    fn cursors(&self) -> impl Iterator<Item = [u32; 5]> + '_ {
        self.offsets[..self.len()]
            .iter()
            .map(|o| [o.windows, o.fill, o.stroke, o.opacity, o.width])
    }

    fn here(&self) -> Offsets {
        Offsets {
            windows: self.t0s.len() as u32,
            fill: self.fill.len(),
            stroke: self.stroke.len(),
            opacity: self.opacity.len(),
            width: self.width.len(),
        }
    }

    /// Adds one track; `slots` maps shared component lists (by address) to their slot.
    fn add_track(&mut self, track: &'a Track, slots: &mut HashMap<usize, u32>) {
        let m = &track.motions;
        let mut i = 0;
        while i < m.len() {
            let t0 = m[i].t0;
            let j = i + m[i..].iter().take_while(|s| s.t0 == t0).count();
            let first_seg = self.segs.len() as u32;
            for seg in &m[i..j] {
                let (pivot, first, count, slot) = match &seg.kind {
                    // Vertex motions act through `Track::deform` and add the identity here.
                    MotionKind::Vertex { .. } => continue,
                    MotionKind::Rigid {
                        pivot,
                        blend,
                        interp: Interp::Linear,
                    } if blend.len() == 1 => {
                        let list = &blend[0].1;
                        let lo = self.comps.len() as u32;
                        self.comps.extend_from_slice(list);
                        // Only products with trigonometry are worth remembering, and only
                        // lists other segments share can be met again.
                        let trig = list
                            .iter()
                            .any(|c| matches!(c, Component::Rotate(_) | Component::Skew(..)));
                        // The blend is what lookups share (the list inside it is held once).
                        let slot = if trig && std::sync::Arc::strong_count(blend) > 1 {
                            let shared = &mut self.shared;
                            *slots.entry(blend.as_ptr() as usize).or_insert_with(|| {
                                shared.push(blend.as_ptr() as usize);
                                shared.len() as u32 - 1
                            })
                        } else {
                            NO_SLOT
                        };
                        (*pivot, lo, self.comps.len() as u32 - lo, slot)
                    }
                    MotionKind::Rigid { .. } | MotionKind::Follow(_) => {
                        self.slow.push(seg);
                        (Point::ORIGIN, self.slow.len() as u32 - 1, SLOW, NO_SLOT)
                    }
                };
                let p0 = seg.timing.progress(seg.t0);
                let inv0 = if p0 == 0.0 {
                    NO_INVERSE
                } else {
                    self.inverses.push(seg.full_at(p0).inverse());
                    self.inverses.len() as u32 - 1
                };
                let clock = Clock::new(&seg.timing, &mut self.eases);
                self.segs.push(Seg {
                    t0: seg.t0,
                    t1: seg.t1,
                    clock,
                    p0,
                    pivot,
                    first,
                    count,
                    inv0,
                    slot,
                });
            }
            let segs = (first_seg, self.segs.len() as u32);
            let start = m[i].start;
            let last_t1 = m[j - 1].t1;
            // Past its window the value is the next window's start, as in `transform_at`;
            // the last window settles once all of its segments have ended.
            let settled = match m.get(j) {
                Some(next) => (last_t1, next.start),
                None => {
                    let t = m[i..j].iter().map(|s| s.t1).fold(last_t1, f64::max);
                    (t, self.fold(segs, start, t, &mut []))
                }
            };
            self.t0s.push(t0);
            self.settled.push(settled);
            self.windows.push((start, segs));
            i = j;
        }
    }

    /// `R₁(t)·…·Rₙ(t)·start` over a window's segments. `products` remembers shared
    /// products (see [`Products`]); it may be empty.
    #[inline]
    fn fold(&self, (a, b): (u32, u32), start: Affine, t: f64, products: &mut Products) -> Affine {
        let segs = &self.segs[a as usize..b as usize];
        // Most windows hold one segment: no accumulator, one product with `start`.
        if let [s] = segs {
            return match self.relative(s, t, products) {
                Some(r) => r * start,
                None => start,
            };
        }
        // Starts empty rather than at the identity, as the single case does.
        let mut acc: Option<Affine> = None;
        for s in segs {
            if let Some(r) = self.relative(s, t, products) {
                acc = Some(match acc {
                    None => r,
                    Some(m) => m * r,
                });
            }
        }
        match acc {
            None => start,
            Some(m) => m * start,
        }
    }

    /// One segment's `R(t) = F(p)·F(p₀)⁻¹`, or `None` while it is still at `p₀` (the
    /// identity).
    #[inline(always)]
    fn relative(&self, s: &Seg, t: f64, products: &mut Products) -> Option<Affine> {
        let p = s.clock.progress(t.clamp(s.t0, s.t1), &self.eases);
        if p == s.p0 {
            return None;
        }
        let f = if s.count == SLOW {
            self.slow[s.first as usize].full_at(p)
        } else {
            let lo = s.first as usize;
            let comps = &self.comps[lo..lo + s.count as usize];
            grid::about(s.pivot, remembered(comps, p, s.slot, products))
        };
        Some(match s.inv0 {
            NO_INVERSE => f,
            k => f * self.inverses[k as usize],
        })
    }

    #[inline(always)]
    fn transform(&self, lo: u32, hi: u32, t: f64) -> Affine {
        let Some(w) = current(&self.t0s, lo, hi, t) else {
            return Affine::IDENTITY;
        };
        let (settle, end) = self.settled[w];
        if t >= settle {
            return end;
        }
        let (start, segs) = self.windows[w];
        self.fold(segs, start, t, &mut [])
    }

    /// [`ChangeList::mode`] for the transform.
    #[inline(always)]
    fn transform_mode(
        &self,
        products: &mut Products,
        cursor: &mut u32,
        lo: u32,
        hi: u32,
        t: f64,
    ) -> Mode<Affine> {
        let mut next = f64::INFINITY;
        let Some(w) = advance(&self.t0s, cursor, lo, hi, t, &mut next) else {
            return Mode::Still(Affine::IDENTITY, next);
        };
        let (settle, end) = self.settled[w];
        if t >= settle {
            return Mode::Still(end, next);
        }
        let mut until = next.min(settle);
        let (start, (a, b)) = self.windows[w];
        let mut moving = false;
        for seg in &self.segs[a as usize..b as usize] {
            let (m, change) = seg.clock.moving_until(t);
            moving |= m;
            until = until.min(change);
        }
        if moving {
            Mode::Moving(w, until)
        } else {
            Mode::Still(self.fold((a, b), start, t, products), until)
        }
    }

    /// The part's shape `i`'s state at `t`.
    #[inline]
    fn state_at(&self, i: usize, t: f64) -> ShapeState {
        let (a, b) = (self.offsets[i], self.offsets[i + 1]);
        let e = &self.eases[..];
        ShapeState {
            transform: self.transform(a.windows, b.windows, t),
            fill: self.fill.at(a.fill, b.fill, t, Tint::NONE, e),
            stroke: self.stroke.at(a.stroke, b.stroke, t, Tint::NONE, e),
            opacity: self.opacity.at(a.opacity, b.opacity, t, 1.0, e),
            stroke_width: self.width.at(a.width, b.width, t, 1.0, e),
            trim: self.trim_at(i, t),
        }
    }

    /// The part's shape `i`'s trim at `t`.
    #[inline]
    fn trim_at(&self, i: usize, t: f64) -> Trim {
        match self.trims.iter().find(|(k, _)| *k as usize == i) {
            Some((_, segs)) => attr_at(segs, t, Trim::REST),
            None => Trim::REST,
        }
    }
}
