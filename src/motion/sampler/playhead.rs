//! Evaluating a whole animation at a sequence of instants, frame after frame.
//!
//! Between two frames most of a shape stands still: a channel (transform, fill, stroke,
//! opacity, width) changes only while one of its windows runs, and each shape has a
//! handful of those. A [`Playhead`] therefore keeps, per channel of every shape, the time
//! up to which the channel stays as it is, and looks the channel up again in its part only
//! then. The channels that are running are copied out of the part into dense lists (one
//! per kind of value), and a frame evaluates those lists front to back: the data a frame
//! reads is what moves, in one sequential stream, instead of a few scattered records per
//! shape in a dozen arrays.
//!
//! A copied entry evaluates with the same operations in the same order as the part's own
//! lookup, so states are bit for bit those of [`super::Sampler::evaluate`].

use kurbo::{Affine, Point};

use super::{
    Blendable, Component, EMPTY_SLOT, Mode, NO_INVERSE, PART, Pace, Part, Products, SLOW, Sampler,
    ShapeState, Tint, Trim, attr_at, remembered,
};
use crate::motion::{Channel, grid};
use crate::signals::Easing;

/// [`Playhead`] position of a channel that is not running.
const IDLE: u32 = u32::MAX;

// A shape's channels index [`Head::until`]'s entries.
const TRANSFORM: usize = Channel::Transform as usize;
const FILL: usize = Channel::Fill as usize;
const STROKE: usize = Channel::Stroke as usize;
const OPACITY: usize = Channel::Opacity as usize;
const WIDTH: usize = Channel::StrokeWidth as usize;
/// The channels a playhead follows; trims ([`Channel::Trim`], rare) are looked up every
/// frame instead.
const CHANNELS: usize = Channel::Trim as usize;

/// A running transform window, as a frame evaluates it.
// The list of these is read front to back every frame: boxing the large variant would
// scatter exactly the data the list keeps together.
#[allow(clippy::large_enum_variant)]
enum Xf {
    /// A window of one segment with at most two components (nearly all), copied whole.
    One(OneSeg),
    /// Anything else, evaluated through the part (its index in the part's windows).
    Window(u32),
}

/// Everything a one-segment window needs to give its transform at `t`: what
/// `Part::fold` reads for it, in one place.
///
/// A running entry is only evaluated inside its window (the playhead looks the channel up
/// again at the window's end), where clamping `t` to the window changes nothing; so
/// neither this nor [`Change`] keeps the window's bounds.
#[derive(Clone, Copy)]
struct OneSeg {
    pace: Pace,
    p0: f64,
    pivot: Point,
    comps: [Component; 2],
    count: u8,
    slot: u32,
    /// `F(p₀)⁻¹`, when `p₀ ≠ 0`.
    inverse: Option<Affine>,
    /// The accumulated transform before the window.
    start: Affine,
}

impl OneSeg {
    /// `Part::fold` of the window, step for step.
    #[inline(always)]
    fn at(&self, t: f64, eases: &[Easing], products: &mut Products) -> Affine {
        let p = self.pace.progress(t, eases);
        if p == self.p0 {
            return self.start;
        }
        let comps = &self.comps[..self.count as usize];
        let f = grid::about(self.pivot, remembered(comps, p, self.slot, products));
        let r = match self.inverse {
            None => f,
            Some(inv) => f * inv,
        };
        r * self.start
    }
}

/// A running attribute change, copied out of its channel.
#[derive(Clone, Copy)]
struct Change<T> {
    pace: Pace,
    from: T,
    to: T,
}

impl<T: Blendable> Change<T> {
    /// `ChangeList::at` inside the change, step for step.
    #[inline(always)]
    fn at(&self, t: f64, eases: &[Easing]) -> T {
        self.from.blend(self.to, self.pace.progress(t, eases))
    }
}

/// The running entries of one kind, dense, each with the shape it belongs to (an index
/// within the part) and its key (`shape · CHANNELS + channel`).
struct Running<R> {
    entries: Vec<(u32, R)>,
    keys: Vec<u32>,
}

impl<R> Running<R> {
    fn new() -> Running<R> {
        Running {
            entries: Vec::new(),
            keys: Vec::new(),
        }
    }

    /// Sets the entry of `key`; `at` maps keys to positions in the list.
    fn put(&mut self, at: &mut [u32], key: usize, shape: usize, entry: R) {
        match at[key] {
            IDLE => {
                at[key] = self.entries.len() as u32;
                self.entries.push((shape as u32, entry));
                self.keys.push(key as u32);
            }
            k => self.entries[k as usize] = (shape as u32, entry),
        }
    }

    /// Drops the entry of `key`, if it has one.
    fn remove(&mut self, at: &mut [u32], key: usize) {
        let k = at[key];
        if k == IDLE {
            return;
        }
        at[key] = IDLE;
        self.entries.swap_remove(k as usize);
        self.keys.swap_remove(k as usize);
        if let Some(&moved) = self.keys.get(k as usize) {
            at[moved as usize] = k;
        }
    }

    fn clear(&mut self) {
        self.entries.clear();
        self.keys.clear();
    }
}

/// One attribute channel of one shape, as [`Running::follow`] needs it.
struct Attr<'c, T> {
    channel: &'c super::ChangeList<T>,
    /// True for the second channel of its kind (stroke, stroke width).
    second: bool,
    key: usize,
    shape: usize,
}

impl<'c, T> Attr<'c, T> {
    fn new(channel: &'c super::ChangeList<T>, second: bool, key: usize, shape: usize) -> Self {
        Attr {
            channel,
            second,
            key,
            shape,
        }
    }
}

impl<T: Blendable> Running<(Change<T>, bool)> {
    /// Takes an attribute channel's new `mode`: a still value is written to `value` and
    /// the channel leaves the list, a running entry is copied into it.
    fn follow(
        &mut self,
        at: &mut [u32],
        a: Attr<'_, T>,
        mode: Mode<T>,
        value: &mut T,
        until: &mut f64,
    ) {
        match mode {
            Mode::Still(v, u) => {
                *value = v;
                *until = u;
                self.remove(at, a.key);
            }
            Mode::Moving(k, u) => {
                *until = u;
                self.put(at, a.key, a.shape, (a.channel.change(k), a.second));
            }
        }
    }
}

/// A playhead's position in one part.
struct Head {
    /// Per shape: no channel of it changes mode before this time.
    quiet: Vec<f64>,
    /// Per shape and channel: the channel stays as it is (still, or running the same
    /// entry) up to this time.
    until: Vec<[f64; CHANNELS]>,
    /// Per shape and channel: the index just past the last started entry.
    cursors: Vec<[u32; CHANNELS]>,
    /// Per key: the position of its running entry in its list, or [`IDLE`].
    at: Vec<u32>,
    transforms: Running<Xf>,
    tints: Running<(Change<Tint>, bool)>,
    numbers: Running<(Change<f64>, bool)>,
}

impl Head {
    fn new(part: &Part<'_>) -> Head {
        let n = part.len();
        // As `rewind` leaves it.
        Head {
            quiet: vec![f64::NEG_INFINITY; n],
            until: vec![[f64::NEG_INFINITY; CHANNELS]; n],
            cursors: part.cursors().collect(),
            at: vec![IDLE; n * CHANNELS],
            transforms: Running::new(),
            tints: Running::new(),
            numbers: Running::new(),
        }
    }

    /// Back to before anything has started.
    fn rewind(&mut self, part: &Part<'_>) {
        self.quiet.fill(f64::NEG_INFINITY);
        for u in &mut self.until {
            *u = [f64::NEG_INFINITY; CHANNELS];
        }
        for (c, start) in self.cursors.iter_mut().zip(part.cursors()) {
            *c = start;
        }
        self.at.fill(IDLE);
        self.transforms.clear();
        self.tints.clear();
        self.numbers.clear();
    }

    /// The part's states at `t`, written into `states`.
    fn seek(
        &mut self,
        part: &Part<'_>,
        t: f64,
        states: &mut [ShapeState],
        products: &mut Products,
    ) {
        let e = &part.eases[..];
        // Channels whose mode may have changed: looked up again, their still values
        // written, their running entries copied out.
        for (i, state) in states.iter_mut().enumerate() {
            if !due(t, self.quiet[i]) {
                continue;
            }
            let (a, b) = (part.offsets[i], part.offsets[i + 1]);
            let until = &mut self.until[i];
            let c = &mut self.cursors[i];
            let key = i * CHANNELS;
            if due(t, until[TRANSFORM]) {
                match part.transform_mode(products, &mut c[TRANSFORM], a.windows, b.windows, t) {
                    Mode::Still(v, u) => {
                        state.transform = v;
                        until[TRANSFORM] = u;
                        self.transforms.remove(&mut self.at, key);
                    }
                    Mode::Moving(w, u) => {
                        until[TRANSFORM] = u;
                        self.transforms
                            .put(&mut self.at, key, i, part.running_window(w));
                    }
                }
            }
            for (ch, channel, lo, hi) in [
                (FILL, &part.fill, a.fill, b.fill),
                (STROKE, &part.stroke, a.stroke, b.stroke),
            ] {
                if due(t, until[ch]) {
                    let mode = channel.mode(&mut c[ch], lo, hi, t, Tint::NONE, e);
                    let second = ch == STROKE;
                    let value = tint_of(state, second);
                    let attr = Attr::new(channel, second, key + ch, i);
                    self.tints
                        .follow(&mut self.at, attr, mode, value, &mut until[ch]);
                }
            }
            for (ch, channel, lo, hi) in [
                (OPACITY, &part.opacity, a.opacity, b.opacity),
                (WIDTH, &part.width, a.width, b.width),
            ] {
                if due(t, until[ch]) {
                    let mode = channel.mode(&mut c[ch], lo, hi, t, 1.0, e);
                    let second = ch == WIDTH;
                    let value = number_of(state, second);
                    let attr = Attr::new(channel, second, key + ch, i);
                    self.numbers
                        .follow(&mut self.at, attr, mode, value, &mut until[ch]);
                }
            }
            self.quiet[i] = until.iter().copied().fold(f64::INFINITY, f64::min);
        }
        // What runs, front to back.
        for (i, xf) in &self.transforms.entries {
            states[*i as usize].transform = match xf {
                Xf::One(s) => s.at(t, e, products),
                Xf::Window(w) => {
                    let (start, segs) = part.windows[*w as usize];
                    part.fold(segs, start, t, products)
                }
            };
        }
        for (i, (change, stroke)) in &self.tints.entries {
            *tint_of(&mut states[*i as usize], *stroke) = change.at(t, e);
        }
        for (i, (change, width)) in &self.numbers.entries {
            *number_of(&mut states[*i as usize], *width) = change.at(t, e);
        }
        for (i, segs) in &part.trims {
            states[*i as usize].trim = attr_at(segs, t, Trim::REST);
        }
    }
}

/// True when something held up to `until` must be looked up again at `t`: from `until`
/// on, and at a NaN instant (which the reference evaluates like any other).
#[inline(always)]
fn due(t: f64, until: f64) -> bool {
    t >= until || t.is_nan()
}

/// The fill or (`stroke`) the stroke tint of a state.
fn tint_of(state: &mut ShapeState, stroke: bool) -> &mut Tint {
    if stroke {
        &mut state.stroke
    } else {
        &mut state.fill
    }
}

/// The opacity or (`width`) the stroke width of a state.
fn number_of(state: &mut ShapeState, width: bool) -> &mut f64 {
    if width {
        &mut state.stroke_width
    } else {
        &mut state.opacity
    }
}

impl Part<'_> {
    /// Window `w`, running, as a playhead keeps it.
    fn running_window(&self, w: usize) -> Xf {
        let (start, (a, b)) = self.windows[w];
        if b == a + 1 {
            let s = &self.segs[a as usize];
            if s.count != SLOW && s.count <= 2 {
                let mut comps = [Component::Rotate(0.0); 2];
                let lo = s.first as usize;
                let n = s.count as usize;
                comps[..n].copy_from_slice(&self.comps[lo..lo + n]);
                return Xf::One(OneSeg {
                    pace: s.clock.pace,
                    p0: s.p0,
                    pivot: s.pivot,
                    comps,
                    count: n as u8,
                    slot: s.slot,
                    inverse: (s.inv0 != NO_INVERSE).then(|| self.inverses[s.inv0 as usize]),
                    start,
                });
            }
        }
        Xf::Window(w as u32)
    }
}

impl<T: Blendable> super::ChangeList<T> {
    /// Entry `k`, running, as a playhead keeps it.
    fn change(&self, k: usize) -> Change<T> {
        let (clock, from, to) = self.moving[k];
        Change {
            pace: clock.pace,
            from,
            to,
        }
    }
}

/// Evaluates every shape at a sequence of instants, fastest when they only move forward
/// (as frames do).
///
/// It keeps the last states and, per channel of every shape, where its list stands and
/// until when it stays as it is; only what runs is evaluated again (see the module
/// documentation). The states are identical to [`Sampler::evaluate`]'s at the same
/// instant, in any order of instants; going back in time restarts from the beginning.
pub struct Playhead<'s, 'a> {
    sampler: &'s Sampler<'a>,
    /// The last instant evaluated.
    last: f64,
    heads: Vec<Head>,
    states: Vec<ShapeState>,
    /// The last product of each shared component list.
    products: Vec<(u64, Affine)>,
}

/// Only where it stands: the cached channel lists have no readable form.
impl std::fmt::Debug for Playhead<'_, '_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Playhead")
            .field("last", &self.last)
            .finish_non_exhaustive()
    }
}

impl<'s, 'a> Playhead<'s, 'a> {
    pub(super) fn new(sampler: &'s Sampler<'a>) -> Playhead<'s, 'a> {
        Playhead {
            sampler,
            last: f64::NEG_INFINITY,
            heads: sampler.parts.iter().map(Head::new).collect(),
            states: vec![ShapeState::REST; sampler.len],
            products: vec![(EMPTY_SLOT, Affine::IDENTITY); sampler.slots],
        }
    }

    /// Every shape's state at `t`.
    pub fn seek(&mut self, t: f64) -> &[ShapeState] {
        let parts = &self.sampler.parts;
        // Going back (or NaN, which is then evaluated from scratch as the reference does).
        if t < self.last || t.is_nan() {
            for (head, part) in self.heads.iter_mut().zip(parts) {
                head.rewind(part);
            }
        }
        self.last = t;
        for ((head, part), states) in self
            .heads
            .iter_mut()
            .zip(parts)
            .zip(self.states.chunks_mut(PART))
        {
            head.seek(part, t, states, &mut self.products);
        }
        &self.states
    }
}
