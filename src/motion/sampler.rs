//! Fast evaluation of a whole animation, frame after frame.
//!
//! [`Track::transform_at`] finds the window holding `t`, then recomputes the progress at the
//! window start and inverts `F(p₀)` for every segment on every call. A [`Sampler`] does that
//! work once: it groups every track's segments into windows laid out flat in shape order
//! (so a frame walks memory sequentially), stores each window's start and settled end
//! transforms, and each segment's `F(p₀)⁻¹`. Per shape and frame what remains is a scan of
//! a few window start times and, inside a moving window, one `F(p)` per segment.
//!
//! The arithmetic is the same as [`Track::transform_at`]'s, step for step, so both give
//! identical results; tests compare them on every example grammar.

use kurbo::{Affine, Point};

use super::{
    Animation, AttrSeg, Blendable, Component, Interp, MotionKind, MotionSeg, ShapeState, Timing,
    Tint, Track, component::product_at, grid,
};

/// How a segment computes `F(p)`.
enum Full<'a> {
    /// One product of components about a pivot, components in [`Sampler::comps`]: the
    /// common case, evaluated from data laid out in shape order.
    Product { pivot: Point, comps: (u32, u32) },
    /// Anything else (blends of grid cells, Alexa interpolation) through the segment.
    Seg(&'a MotionSeg),
}

/// One segment with its start progress and inverse resolved.
struct Seg<'a> {
    t0: f64,
    t1: f64,
    timing: Timing,
    full: Full<'a>,
    /// Progress at the window start.
    p0: f64,
    /// `F(p₀)⁻¹`, or `None` when `p₀ = 0` (then `F(p₀)` is the identity).
    inv0: Option<Affine>,
}

/// A group of segments sharing a start time.
struct Window {
    /// From this time on the window's value no longer changes.
    settle: f64,
    /// The accumulated transform before the window.
    start: Affine,
    /// The value once settled.
    end: Affine,
    /// Range into [`Sampler::segs`].
    segs: (u32, u32),
}

/// Where one shape's data starts in each flat array.
#[derive(Clone, Copy, Default)]
struct Offsets {
    windows: u32,
    fill: u32,
    stroke: u32,
    opacity: u32,
    width: u32,
}

/// Every track of an animation compiled for repeated sampling. Borrows the animation.
///
/// Everything a frame reads is copied into flat arrays in shape order, so evaluating a
/// frame walks memory forward instead of chasing a pointer per segment and channel.
pub struct Sampler<'a> {
    /// Per shape where its data starts, plus one entry for the end.
    offsets: Vec<Offsets>,
    /// Window start times, apart from the rest so the scan stays in few cache lines.
    t0s: Vec<f64>,
    windows: Vec<Window>,
    segs: Vec<Seg<'a>>,
    comps: Vec<Component>,
    fill: Vec<Attr<Tint>>,
    stroke: Vec<Attr<Tint>>,
    opacity: Vec<Attr<f64>>,
    width: Vec<Attr<f64>>,
}

/// An attribute segment with the value it holds once it has ended, which is what most
/// frames read.
#[derive(Clone)]
struct Attr<T> {
    seg: AttrSeg<T>,
    end: T,
}

fn attrs<T: Blendable>(segs: &[AttrSeg<T>]) -> impl Iterator<Item = Attr<T>> + '_ {
    segs.iter().map(|s| Attr {
        seg: s.clone(),
        end: s.value_at(s.t1),
    })
}

impl<'a> Sampler<'a> {
    /// Compiles every track of `anim`.
    pub fn new(anim: &'a Animation) -> Sampler<'a> {
        let tracks = &anim.tracks[..];
        let total: usize = tracks.iter().map(|t| t.motions.len()).sum();
        let count = |f: fn(&Track) -> usize| tracks.iter().map(f).sum::<usize>();
        let mut s = Sampler {
            offsets: Vec::with_capacity(tracks.len() + 1),
            t0s: Vec::with_capacity(total),
            windows: Vec::with_capacity(total),
            segs: Vec::with_capacity(total),
            comps: Vec::with_capacity(total * 2),
            fill: Vec::with_capacity(count(|t| t.fill.len())),
            stroke: Vec::with_capacity(count(|t| t.stroke.len())),
            opacity: Vec::with_capacity(count(|t| t.opacity.len())),
            width: Vec::with_capacity(count(|t| t.stroke_width.len())),
        };
        for track in tracks {
            s.offsets.push(s.here());
            s.add_track(track);
            s.fill.extend(attrs(&track.fill));
            s.stroke.extend(attrs(&track.stroke));
            s.opacity.extend(attrs(&track.opacity));
            s.width.extend(attrs(&track.stroke_width));
        }
        s.offsets.push(s.here());
        s
    }

    fn here(&self) -> Offsets {
        Offsets {
            windows: self.windows.len() as u32,
            fill: self.fill.len() as u32,
            stroke: self.stroke.len() as u32,
            opacity: self.opacity.len() as u32,
            width: self.width.len() as u32,
        }
    }

    fn add_track(&mut self, track: &'a Track) {
        let m = &track.motions;
        let mut i = 0;
        while i < m.len() {
            let t0 = m[i].t0;
            let j = i + m[i..].iter().take_while(|s| s.t0 == t0).count();
            let first_seg = self.segs.len() as u32;
            for seg in &m[i..j] {
                let full = match &seg.kind {
                    // Vertex motions act through `Track::deform` and add the identity here.
                    MotionKind::Vertex { .. } => continue,
                    MotionKind::Rigid {
                        pivot,
                        blend,
                        interp: Interp::Linear,
                    } if blend.len() == 1 => {
                        let lo = self.comps.len() as u32;
                        self.comps.extend_from_slice(&blend[0].1);
                        Full::Product {
                            pivot: *pivot,
                            comps: (lo, self.comps.len() as u32),
                        }
                    }
                    MotionKind::Rigid { .. } => Full::Seg(seg),
                };
                let p0 = seg.timing.progress(seg.t0);
                let inv0 = (p0 != 0.0).then(|| seg.full_at(p0).inverse());
                self.segs.push(Seg {
                    t0: seg.t0,
                    t1: seg.t1,
                    timing: seg.timing.clone(),
                    full,
                    p0,
                    inv0,
                });
            }
            let segs = (first_seg, self.segs.len() as u32);
            let start = m[i].start;
            let last_t1 = m[j - 1].t1;
            // Past its window the value is the next window's start, as in `transform_at`;
            // the last window settles once all of its segments have ended.
            let (settle, end) = match m.get(j) {
                Some(next) => (last_t1, next.start),
                None => {
                    let t = m[i..j].iter().map(|s| s.t1).fold(last_t1, f64::max);
                    (t, self.fold(segs, start, t))
                }
            };
            self.t0s.push(t0);
            self.windows.push(Window {
                settle,
                start,
                end,
                segs,
            });
            i = j;
        }
    }

    /// `R₁(t)·…·Rₙ(t)·start` over a window's segments.
    fn fold(&self, (a, b): (u32, u32), start: Affine, t: f64) -> Affine {
        // Starts empty rather than at the identity: most windows hold one moving segment,
        // which then costs no product.
        let mut acc: Option<Affine> = None;
        for s in &self.segs[a as usize..b as usize] {
            let p = s.timing.progress(t.clamp(s.t0, s.t1));
            if p == s.p0 {
                continue;
            }
            let f = match s.full {
                Full::Product {
                    pivot,
                    comps: (lo, hi),
                } => grid::about(pivot, product_at(&self.comps[lo as usize..hi as usize], p)),
                Full::Seg(seg) => seg.full_at(p),
            };
            let r = match s.inv0 {
                None => f,
                Some(inv) => f * inv,
            };
            acc = Some(match acc {
                None => r,
                Some(m) => m * r,
            });
        }
        match acc {
            None => start,
            Some(m) => m * start,
        }
    }

    /// Number of shapes.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// True when the animation has no shapes.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Shape `i`'s rigid transform at `t` (equal to `tracks[i].transform_at(t)`).
    pub fn transform_at(&self, i: usize, t: f64) -> Affine {
        let (lo, hi) = (
            self.offsets[i].windows as usize,
            self.offsets[i + 1].windows as usize,
        );
        let k = self.t0s[lo..hi].iter().take_while(|&&t0| t0 <= t).count();
        if k == 0 {
            return Affine::IDENTITY;
        }
        let w = &self.windows[lo + k - 1];
        if t >= w.settle {
            return w.end;
        }
        self.fold(w.segs, w.start, t)
    }

    /// Shape `i`'s state at `t` (equal to `tracks[i].state_at(t)`).
    pub fn state_at(&self, i: usize, t: f64) -> ShapeState {
        let (a, b) = (self.offsets[i], self.offsets[i + 1]);
        ShapeState {
            transform: self.transform_at(i, t),
            fill: channel(&self.fill, a.fill, b.fill, t, Tint::NONE),
            stroke: channel(&self.stroke, a.stroke, b.stroke, t, Tint::NONE),
            opacity: channel(&self.opacity, a.opacity, b.opacity, t, 1.0),
            stroke_width: channel(&self.width, a.width, b.width, t, 1.0),
        }
    }

    /// Every shape's state at `t`, written into `out` (cleared first).
    pub fn evaluate_into(&self, t: f64, out: &mut Vec<ShapeState>) {
        out.clear();
        out.extend((0..self.len()).map(|i| self.state_at(i, t)));
    }

    /// Every shape's state at `t`.
    pub fn evaluate(&self, t: f64) -> Vec<ShapeState> {
        let mut out = Vec::with_capacity(self.len());
        self.evaluate_into(t, &mut out);
        out
    }
}

/// One shape's attribute channel at `t`: its segments are `all[lo..hi]`. Same result as
/// [`attr_at`] on the track's own list.
#[inline]
fn channel<T: Blendable>(all: &[Attr<T>], lo: u32, hi: u32, t: f64, default: T) -> T {
    let segs = &all[lo as usize..hi as usize];
    let k = segs.iter().take_while(|a| a.seg.t0 <= t).count();
    if k == 0 {
        return default;
    }
    let a = &segs[k - 1];
    if t >= a.seg.t1 {
        a.end
    } else {
        a.seg.value_at(t)
    }
}
