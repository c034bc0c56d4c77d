//! The `smoothing` stage: every shape's channels — the six transform coefficients, both
//! tints, opacity, stroke width and trim — sampled once per frame and passed through a signal
//! system (FIR easing, spring, …; see [`crate::signals::smooth`]), so motion stays
//! continuous in velocity across slice boundaries (Reach & North, sec. 5–6).
//!
//! Filtering the matrix coefficients is a linear operation on affine maps, so the result is
//! still an affine map per frame. The smoothed samples become one window per frame that
//! interpolates linearly between consecutive frames; exporters reduce those keyframes to
//! their error bound. A looping animation is filtered over two periods and the second is
//! kept, so the loop stays seamless; otherwise the filter starts at rest on the first frame.

use kurbo::Affine;
use rayon::prelude::*;

use crate::grammar::value::Value;
use crate::motion::{AttrSeg, Component, MotionSeg, Tint, Track, Trim};
use crate::signals::smooth::{CallArg, SmoothSpec, smooth_samples};

/// Channels per shape: 6 affine coefficients, fill tint (4), stroke tint (4), opacity,
/// stroke width, trim (start, end, shift).
const N: usize = 19;

/// The system a `smoothing` directive names.
pub fn spec_from_value(v: &Value) -> Result<SmoothSpec, String> {
    fn arg(v: &Value) -> Result<CallArg, String> {
        match v {
            Value::Num(x) => Ok(CallArg::Num(*x)),
            Value::Keyword(k) => Ok(CallArg::Call(k.clone(), Vec::new())),
            Value::Call { name, args } => Ok(CallArg::Call(
                name.clone(),
                args.iter().map(arg).collect::<Result<_, _>>()?,
            )),
            other => Err(format!(
                "a smoothing system is written like `spring(0.4, 0)`; found {}",
                other.describe()
            )),
        }
    }
    match arg(v)? {
        CallArg::Call(name, args) => SmoothSpec::from_call(&name, &args).map_err(|e| e.to_string()),
        CallArg::Num(_) => Err(
            "a smoothing system is written like `spring(0.4, 0)` or `fir(bspline(3), 0.3)`".into(),
        ),
    }
}

fn pack(track: &Track, t: f64) -> [f64; N] {
    let s = track.state_at(t);
    let m = s.transform.as_coeffs();
    [
        m[0],
        m[1],
        m[2],
        m[3],
        m[4],
        m[5],
        s.fill.sum[0] as f64,
        s.fill.sum[1] as f64,
        s.fill.sum[2] as f64,
        s.fill.weight as f64,
        s.stroke.sum[0] as f64,
        s.stroke.sum[1] as f64,
        s.stroke.sum[2] as f64,
        s.stroke.weight as f64,
        s.opacity,
        s.stroke_width,
        s.trim.start,
        s.trim.end,
        s.trim.shift,
    ]
}

fn tint(v: &[f64; N], at: usize) -> Tint {
    Tint {
        sum: [v[at] as f32, v[at + 1] as f32, v[at + 2] as f32],
        weight: v[at + 3].clamp(0.0, 1.0) as f32,
    }
}

/// A smoothed trim, kept a trim: a filter that overshoots could carry its ends out of the
/// path or past each other.
fn trim(v: &[f64; N]) -> Trim {
    let start = v[16].clamp(0.0, 1.0);
    Trim {
        start,
        end: v[17].clamp(start, 1.0),
        shift: v[18],
    }
}

/// Smooths every track that changes; tracks that never change are left alone.
pub fn smooth_tracks(
    tracks: &mut [Track],
    spec: &SmoothSpec,
    duration: f64,
    fps: f64,
    looping: bool,
) -> Result<(), String> {
    let frames = crate::canvas::frames(duration, fps);
    let time = |i: usize| (i as f64 / fps).min(duration);
    // Every track's result is kept so that the error reported is the first track's,
    // whichever thread met an error first.
    let results: Vec<Result<(), String>> = tracks
        .par_iter_mut()
        .map(|track| {
            if track.is_still() {
                return Ok(());
            }
            let raw: Vec<[f64; N]> = (0..=frames).map(|i| pack(track, time(i))).collect();
            let smoothed = if looping {
                // Two periods; the second starts from the state the first ended in.
                let mut twice = raw[..frames].to_vec();
                twice.extend_from_slice(&raw);
                let out = smooth_samples(spec, &twice, fps).map_err(|e| e.to_string())?;
                out[frames..].to_vec()
            } else {
                smooth_samples(spec, &raw, fps).map_err(|e| e.to_string())?
            };
            // The outline channel is not filtered: a morph's in-between is the linear
            // blend of matched points that every player draws, which a filter would
            // turn into a bake of the outline at every frame.
            let morphs = std::mem::take(&mut track.morphs);
            *track = rebuild(&smoothed, time, !track.trim.is_empty());
            track.morphs = morphs;
            Ok(())
        })
        .collect();
    results.into_iter().collect()
}

/// The track of the smoothed samples `v`; `trims` when the track trims its strokes (else
/// the trim, filtered from a constant, comes back within float noise of the rest and is
/// left out).
fn rebuild(v: &[[f64; N]], time: impl Fn(usize) -> f64, trims: bool) -> Track {
    let mut track = Track::default();
    let affine = |x: &[f64; N]| Affine::new([x[0], x[1], x[2], x[3], x[4], x[5]]);
    // A channel reads its neutral value (identity, no tint, 1) before its first window, so a
    // run of equal samples is skipped only once a window holds the value: a state held from
    // t = 0 (a pre-applied inverted slice) gets a constant first window instead of showing
    // the drawn art until the first change.
    let rest = pack(&Track::default(), 0.0);
    for i in 0..v.len().saturating_sub(1) {
        let (t0, t1) = (time(i), time(i + 1));
        if t1 <= t0 {
            continue;
        }
        let (a, b) = (&v[i], &v[i + 1]);
        let (ma, mb) = (affine(a), affine(b));
        let hold_motion = track.motions.is_empty() && ma != affine(&rest);
        if (ma != mb || hold_motion) && ma.determinant().abs() > 1e-12 {
            // X(t) = X_a + s·(X_b − X_a): an entry-wise blend of Δ = X_b·X_a⁻¹ from the identity.
            let delta = mb * ma.inverse();
            track
                .motions
                .push(MotionSeg::linear(t0, t1, &[Component::Matrix(delta)], ma));
        }
        let (fa, fb) = (tint(a, 6), tint(b, 6));
        if fa != fb || (track.fill.is_empty() && fa != tint(&rest, 6)) {
            track.fill.push(AttrSeg::linear(t0, t1, fa, fb));
        }
        let (sa, sb) = (tint(a, 10), tint(b, 10));
        if sa != sb || (track.stroke.is_empty() && sa != tint(&rest, 10)) {
            track.stroke.push(AttrSeg::linear(t0, t1, sa, sb));
        }
        if a[14] != b[14] || (track.opacity.is_empty() && a[14] != rest[14]) {
            track.opacity.push(AttrSeg::linear(
                t0,
                t1,
                a[14].clamp(0.0, 1.0),
                b[14].clamp(0.0, 1.0),
            ));
        }
        if a[15] != b[15] || (track.stroke_width.is_empty() && a[15] != rest[15]) {
            track
                .stroke_width
                .push(AttrSeg::linear(t0, t1, a[15].max(0.0), b[15].max(0.0)));
        }
        let (ta, tb) = (trim(a), trim(b));
        if trims && (ta != tb || (track.trim.is_empty() && ta != trim(&rest))) {
            track.trim.push(AttrSeg::linear(t0, t1, ta, tb));
        }
    }
    track
}
