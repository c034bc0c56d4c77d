//! Trim paths: the visible part of a shape's strokes, `START…END` of each subpath's length
//! moved along it by `SHIFT` turns (After Effects' and Lottie's trim paths, `tm`).
//!
//! A [`Trim`] is a plain value that blends linearly, one more attribute channel of a
//! [`super::Track`]. Strokes only: the fill of the shape stays whole. Each subpath is
//! trimmed on its own (Lottie's "trim multiple shapes: simultaneously"), by arc length.
//! When the shifted window passes the end of a subpath it wraps to its start: the visible
//! part is then two pieces, each drawn with its own caps (as Lottie players and a dash
//! pattern draw it).

use kurbo::{BezPath, ParamCurve, ParamCurveArclen, PathEl, PathSeg};

use super::Blendable;
use crate::keyframe::Same;
use crate::tolerance::KEY;

/// Arc lengths are measured to this accuracy, relative to a subpath's length.
const ARCLEN_ACCURACY: f64 = 1e-6;

/// The visible part of a stroke: fractions `start ≤ end` of each subpath's length, moved by
/// `shift` turns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trim {
    /// Start of the visible part, a fraction of the length in `0..=1`.
    pub start: f64,
    /// End of the visible part, in `start..=1`.
    pub end: f64,
    /// How far the visible part is moved along the path, in turns (any number).
    pub shift: f64,
}

impl Trim {
    /// The whole stroke, unmoved: `(0, 1, 0)`.
    pub const REST: Trim = Trim {
        start: 0.0,
        end: 1.0,
        shift: 0.0,
    };

    /// True when the whole stroke shows (a shift of a whole stroke changes nothing).
    pub fn is_whole(&self) -> bool {
        self.end - self.start >= 1.0
    }

    /// True when nothing of the stroke shows.
    pub fn is_empty(&self) -> bool {
        self.end - self.start <= 0.0
    }

    /// The visible intervals of a subpath, as fractions of its length in `[0, 1]`, in order
    /// along it: one, or two when the shifted window wraps past the end.
    pub fn intervals(&self) -> Vec<(f64, f64)> {
        if self.is_empty() {
            return Vec::new();
        }
        if self.is_whole() {
            return vec![(0.0, 1.0)];
        }
        let a = (self.start + self.shift).rem_euclid(1.0);
        let b = a + (self.end - self.start);
        if b <= 1.0 {
            vec![(a, b)]
        } else {
            vec![(0.0, b - 1.0), (a, 1.0)]
        }
    }

    /// The visible part of `path`'s stroke: each subpath cut to [`Trim::intervals`] of its
    /// own length, every piece an open subpath.
    pub fn apply(&self, path: &BezPath) -> BezPath {
        let mut out = BezPath::new();
        if self.is_whole() {
            return path.clone();
        }
        let intervals = self.intervals();
        if intervals.is_empty() {
            return out;
        }
        for sub in subpaths(path) {
            let lengths: Vec<f64> = sub.iter().map(|s| s.arclen(ARCLEN_ACCURACY)).collect();
            let total: f64 = lengths.iter().sum();
            if total <= 0.0 {
                continue;
            }
            for &(a, b) in &intervals {
                piece(&sub, &lengths, a * total, b * total, &mut out);
            }
        }
        out
    }
}

impl Blendable for Trim {
    fn blend(self, o: Trim, t: f64) -> Trim {
        Trim {
            start: self.start.blend(o.start, t),
            end: self.end.blend(o.end, t),
            shift: self.shift.blend(o.shift, t),
        }
    }
}

impl Same for Trim {
    fn same(&self, o: &Trim) -> bool {
        KEY.same(self.start, o.start) && KEY.same(self.end, o.end) && KEY.same(self.shift, o.shift)
    }
}

/// The segments of each subpath of `path` (a closed one ends with its closing line, unless
/// that line has no length).
fn subpaths(path: &BezPath) -> Vec<Vec<PathSeg>> {
    let mut out: Vec<Vec<PathSeg>> = Vec::new();
    let mut current: Vec<PathSeg> = Vec::new();
    let mut start = kurbo::Point::ORIGIN;
    let mut last = start;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                }
                start = p;
                last = p;
            }
            PathEl::LineTo(p) => {
                current.push(PathSeg::Line(kurbo::Line::new(last, p)));
                last = p;
            }
            PathEl::QuadTo(c, p) => {
                current.push(PathSeg::Quad(kurbo::QuadBez::new(last, c, p)));
                last = p;
            }
            PathEl::CurveTo(c1, c2, p) => {
                current.push(PathSeg::Cubic(kurbo::CubicBez::new(last, c1, c2, p)));
                last = p;
            }
            PathEl::ClosePath => {
                if last != start {
                    current.push(PathSeg::Line(kurbo::Line::new(last, start)));
                }
                last = start;
                if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// Appends the part of the subpath `segs` (segment lengths `lengths`) between arc lengths
/// `from` and `to` as an open subpath.
fn piece(segs: &[PathSeg], lengths: &[f64], from: f64, to: f64, out: &mut BezPath) {
    if to <= from {
        return;
    }
    let mut at = 0.0;
    let mut started = false;
    for (seg, &len) in segs.iter().zip(lengths) {
        let (s0, s1) = (at, at + len);
        at = s1;
        if s1 < from || s0 > to || len <= 0.0 {
            continue;
        }
        let param = |s: f64| {
            if s <= s0 {
                0.0
            } else if s >= s1 {
                1.0
            } else {
                seg.inv_arclen(s - s0, ARCLEN_ACCURACY * len)
            }
        };
        let (u0, u1) = (param(from), param(to));
        if u1 <= u0 {
            continue;
        }
        let part = seg.subsegment(u0..u1);
        if !started {
            out.move_to(part.start());
            started = true;
        }
        match part {
            PathSeg::Line(l) => out.line_to(l.p1),
            PathSeg::Quad(q) => out.quad_to(q.p1, q.p2),
            PathSeg::Cubic(c) => out.curve_to(c.p1, c.p2, c.p3),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shifted_window_wraps_into_two_pieces() {
        let t = Trim {
            start: 0.25,
            end: 0.5,
            shift: 0.625,
        };
        let iv = t.intervals();
        assert_eq!(iv.len(), 2);
        assert!((iv[0].0, iv[1].1) == (0.0, 1.0));
        assert!((iv[0].1 - 0.125).abs() < 1e-12 && (iv[1].0 - 0.875).abs() < 1e-12);
        assert!(
            Trim {
                end: 0.25,
                ..Trim::REST
            }
            .intervals()
                == [(0.0, 0.25)]
        );
        assert!(
            Trim {
                start: 0.5,
                end: 0.5,
                shift: 0.0
            }
            .intervals()
            .is_empty()
        );
    }

    #[test]
    fn trimmed_length_is_the_fraction_of_each_subpath() {
        let p = BezPath::from_svg("M0 0 L100 0 M0 10 L0 50 L30 50 Z").unwrap();
        let t = Trim {
            start: 0.1,
            end: 0.6,
            shift: 0.0,
        };
        let cut = t.apply(&p);
        let subs = subpaths(&cut);
        assert_eq!(subs.len(), 2);
        let len = |s: &[PathSeg]| s.iter().map(|x| x.arclen(1e-9)).sum::<f64>();
        assert!((len(&subs[0]) - 50.0).abs() < 1e-6);
        // The triangle is 40 + 30 + 50 = 120 long.
        assert!((len(&subs[1]) - 60.0).abs() < 1e-6);
        assert!(Trim::REST.apply(&p) == p);
    }
}
