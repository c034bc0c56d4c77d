//! Motion along a path (`animate(follow, …)`): the shape's centroid travels a curve by arc
//! length, optionally turning with the curve's tangent (After Effects' motion path with
//! auto-orient, CSS `offset-path` with `offset-rotate: auto`).
//!
//! A [`Route`] is the curve measured once: its segments (the moves between subpaths are
//! jumps, not travelled), each segment's arc length and the heading along it unwrapped, so
//! a loop turns by a whole turn rather than jumping back by 360°. A [`Follow`] is the
//! route placed for one shape: `F(p)` moves the centroid from where the motion began to the
//! route's point at the arc-length fraction `p`, turning about the centroid by the heading
//! gained since the route's start, so the shape starts as drawn and `F(0)` is the identity
//! (what a motion window needs to telescope and an inverted twin to undo it).

use kurbo::{
    Affine, BezPath, CubicBez, ParamCurve, ParamCurveArclen, ParamCurveDeriv, PathSeg, Point, Vec2,
};

/// How closely arc lengths are measured, in canvas units.
const ARCLEN_ACCURACY: f64 = 1e-7;

/// A path measured for travelling along it by arc length.
#[derive(Clone, Debug)]
pub struct Route {
    /// The travelled segments in order (subpaths one after the other).
    segs: Vec<PathSeg>,
    /// Arc length at the start of each segment, and the total at the end.
    starts: Vec<f64>,
    /// The unwrapped heading (radians) at the start of each segment, and at the end of the
    /// last: tangent directions read between these are taken on the branch nearest them.
    headings: Vec<f64>,
}

impl Route {
    /// The route along `path`, or `None` when it has no length to travel.
    pub fn new(path: &BezPath) -> Option<Route> {
        let segs: Vec<PathSeg> = path
            .segments()
            .filter(|s| s.arclen(ARCLEN_ACCURACY) > 1e-9)
            .collect();
        if segs.is_empty() {
            return None;
        }
        let mut starts = Vec::with_capacity(segs.len() + 1);
        let mut total = 0.0;
        for s in &segs {
            starts.push(total);
            total += s.arclen(ARCLEN_ACCURACY);
        }
        starts.push(total);
        // Unwrap the heading along each segment finely enough that no turn between two
        // samples exceeds half a turn (a cubic turns at most by 2π between its ends).
        let mut headings = Vec::with_capacity(segs.len() + 1);
        let mut last: Option<f64> = None;
        for s in &segs {
            for k in 0..=32 {
                let a = unwrap(raw_heading(s, k as f64 / 32.0), last);
                if k == 0 {
                    headings.push(a);
                }
                last = Some(a);
            }
        }
        headings.push(last.unwrap_or(0.0));
        Some(Route {
            segs,
            starts,
            headings,
        })
    }

    /// The total arc length.
    pub fn length(&self) -> f64 {
        self.starts[self.segs.len()]
    }

    /// The travelled segments, in order.
    pub fn segments(&self) -> &[PathSeg] {
        &self.segs
    }

    /// The arc-length fraction (0 to 1) at which each segment starts, and 1 at the end.
    pub fn fractions(&self) -> impl Iterator<Item = f64> + '_ {
        let total = self.length();
        self.starts.iter().map(move |s| s / total)
    }

    /// The route's first point.
    pub fn start(&self) -> Point {
        self.segs[0].start()
    }

    /// The segment (index into [`Route::segments`]) and its parameter at arc-length
    /// fraction `u`, clamped to the route; a segment's end is the next one's start.
    pub fn locate(&self, u: f64) -> (usize, f64) {
        let s = u.clamp(0.0, 1.0) * self.length();
        let i = self
            .starts
            .partition_point(|&x| x <= s)
            .saturating_sub(1)
            .min(self.segs.len() - 1);
        let seg = &self.segs[i];
        let len = self.starts[i + 1] - self.starts[i];
        let within = (s - self.starts[i]).clamp(0.0, len);
        let t = if within >= len {
            1.0
        } else {
            seg.inv_arclen(within, ARCLEN_ACCURACY)
        };
        (i, t)
    }

    /// The point at arc-length fraction `u`. Beyond the ends (an easing that overshoots)
    /// the route goes on along its end tangents.
    pub fn point_at(&self, u: f64) -> Point {
        if u < 0.0 {
            let d = direction(&self.segs[0], 0.0);
            return self.start() + d * (u * self.length());
        }
        if u > 1.0 {
            let last = &self.segs[self.segs.len() - 1];
            return last.end() + direction(last, 1.0) * ((u - 1.0) * self.length());
        }
        let (i, t) = self.locate(u);
        self.segs[i].eval(t)
    }

    /// The heading (radians, unwrapped: continuous along the route) at fraction `u`;
    /// held at the ends beyond them.
    pub fn heading_at(&self, u: f64) -> f64 {
        let (i, t) = self.locate(u);
        let seg = &self.segs[i];
        // The branch nearest the heading interpolated between the segment's sampled ones.
        let mut near = self.headings[i];
        for k in 1..=32 {
            let tk = k as f64 / 32.0;
            if tk > t {
                break;
            }
            near = unwrap(raw_heading(seg, tk), Some(near));
        }
        unwrap(raw_heading(seg, t), Some(near))
    }
}

/// The unit tangent of `seg` at `t`, looking a little inside where the derivative vanishes
/// (a control point on its end point).
fn direction(seg: &PathSeg, t: f64) -> Vec2 {
    let d = derivative(seg, t);
    if d.hypot() > 1e-9 {
        return d.normalize();
    }
    for eps in [1e-4, 1e-2, 0.1] {
        let tt = if t < 0.5 { t + eps } else { t - eps };
        let d = derivative(seg, tt);
        if d.hypot() > 1e-9 {
            return d.normalize();
        }
    }
    (seg.end() - seg.start()).normalize()
}

fn derivative(seg: &PathSeg, t: f64) -> Vec2 {
    match seg {
        PathSeg::Line(l) => l.p1 - l.p0,
        PathSeg::Quad(q) => q.deriv().eval(t).to_vec2(),
        PathSeg::Cubic(c) => c.deriv().eval(t).to_vec2(),
    }
}

fn raw_heading(seg: &PathSeg, t: f64) -> f64 {
    let d = direction(seg, t);
    d.y.atan2(d.x)
}

/// `a` moved by whole turns to lie within half a turn of `near`.
fn unwrap(a: f64, near: Option<f64>) -> f64 {
    let Some(n) = near else { return a };
    let tau = std::f64::consts::TAU;
    a + ((n - a) / tau).round() * tau
}

/// A route placed for one shape: what a follow motion does at each progress.
#[derive(Clone, Debug)]
pub struct Follow {
    /// The route, in canvas coordinates (before [`Follow::frame`]).
    pub route: std::sync::Arc<Route>,
    /// The centroid where the motion began: the shape turns about it.
    pub pivot: Point,
    /// How far the centroid is put from where it was as soon as the motion moves: zero when
    /// the route starts at the centroid (`local`), the way to the route's start (`world`).
    pub lead: Vec2,
    /// Whether the shape turns with the route's tangent.
    pub orient: bool,
    /// Carries the motion onto the canvas: `frame·F(p)·frame⁻¹` (the motions outer to it
    /// that moved since it began; the identity for most).
    pub frame: Affine,
}

impl Follow {
    /// The motion for a shape whose centroid is `pivot` when it begins: along `route` as
    /// written (`world`, the centroid put on its start as soon as it moves) or with the
    /// route's start on the centroid (`local`).
    pub fn new(route: std::sync::Arc<Route>, pivot: Point, world: bool, orient: bool) -> Follow {
        let lead = if world {
            route.start() - pivot
        } else {
            Vec2::ZERO
        };
        Follow {
            route,
            pivot,
            lead,
            orient,
            frame: Affine::IDENTITY,
        }
    }

    /// Where the centroid is at progress `p`, relative to where it began (before
    /// [`Follow::frame`]).
    pub fn offset_at(&self, p: f64) -> Vec2 {
        if p == 0.0 {
            return Vec2::ZERO;
        }
        self.route.point_at(p) - self.route.start() + self.lead
    }

    /// The turn (radians) at progress `p`: the heading gained since the route's start, or
    /// none without `orient`.
    pub fn turn_at(&self, p: f64) -> f64 {
        if !self.orient || p == 0.0 {
            return 0.0;
        }
        self.route.heading_at(p) - self.route.heading_at(0.0)
    }

    /// `F(p)`: the shape turned about its centroid by [`Follow::turn_at`], then moved by
    /// [`Follow::offset_at`].
    pub fn at(&self, p: f64) -> Affine {
        let c = self.pivot.to_vec2();
        let m = Affine::translate(self.offset_at(p) + c)
            * Affine::rotate(self.turn_at(p))
            * Affine::translate(-c);
        if self.frame == Affine::IDENTITY {
            m
        } else {
            self.frame * m * self.frame.inverse()
        }
    }

    /// The same motion carried by `g` (see [`Follow::frame`]).
    pub fn carried(&self, g: Affine) -> Follow {
        Follow {
            frame: g * self.frame,
            ..self.clone()
        }
    }
}

/// The single cubic a segment is, as a cubic (lines and quadratics raised exactly).
pub fn as_cubic(seg: &PathSeg) -> CubicBez {
    match seg {
        PathSeg::Line(l) => CubicBez::new(
            l.p0,
            l.p0.lerp(l.p1, 1.0 / 3.0),
            l.p0.lerp(l.p1, 2.0 / 3.0),
            l.p1,
        ),
        PathSeg::Quad(q) => q.raise(),
        PathSeg::Cubic(c) => *c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn route(d: &str) -> Route {
        Route::new(&BezPath::from_svg(d).unwrap()).unwrap()
    }

    #[test]
    fn travels_by_arc_length() {
        // Two lines of lengths 30 and 10: a quarter of the way is 10 along the first.
        let r = route("M0 0 H30 V10");
        assert!((r.length() - 40.0).abs() < 1e-9);
        assert!((r.point_at(0.25) - Point::new(10.0, 0.0)).hypot() < 1e-6);
        assert!((r.point_at(0.875) - Point::new(30.0, 5.0)).hypot() < 1e-6);
        assert!((r.heading_at(0.9) - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
    }

    #[test]
    fn a_circle_turns_a_whole_turn() {
        let c = kurbo::Circle::new((50.0, 50.0), 20.0);
        let path = kurbo::Shape::to_path(&c, 1e-3);
        let r = Route::new(&path).unwrap();
        let turn = r.heading_at(1.0) - r.heading_at(0.0);
        assert!((turn.abs() - std::f64::consts::TAU).abs() < 1e-3, "{turn}");
    }

    #[test]
    fn starts_as_drawn_and_lands_on_the_route() {
        let r = Arc::new(route("M100 100 C150 0 250 200 300 100"));
        let f = Follow::new(r.clone(), Point::new(10.0, 20.0), false, true);
        assert_eq!(f.at(0.0), Affine::IDENTITY);
        let end = f.at(1.0) * Point::new(10.0, 20.0);
        assert!((end - Point::new(210.0, 20.0)).hypot() < 1e-6);
        let w = Follow::new(r, Point::new(10.0, 20.0), true, false);
        assert!((w.at(0.5) * Point::new(10.0, 20.0) - w.route.point_at(0.5)).hypot() < 1e-9);
    }
}
