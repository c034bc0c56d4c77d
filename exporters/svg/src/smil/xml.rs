//! Writing SMIL animation elements: number formatting, key compaction and the
//! `keyTimes`/`values`/`keySplines` attributes.

use kurbo::Affine;

use gmotion::keyframe::{Ease, Key};

/// Decimals for coordinates and angles: 1e-4 user units is far below a pixel.
pub const COORD: usize = 4;
/// Decimals for scale factors and matrix entries, which multiply coordinates.
pub const FACTOR: usize = 6;
/// Decimals for `keyTimes` (1e-6 of the duration).
const TIME: usize = 6;
/// Decimals for `keySplines`: an error of 5e-6 in a control point moves a value by at
/// most 2.5e-6 of the interval's change.
const SPLINE: usize = 5;

/// The document clock every animation shares.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    /// Simple duration in seconds.
    pub dur: f64,
    /// Repeat forever instead of freezing on the last value.
    pub looping: bool,
}

/// `x` rounded to `decimals`, without trailing zeros and without `-0`.
pub fn num(x: f64, decimals: usize) -> String {
    let mut s = String::new();
    push_num(&mut s, x, decimals);
    s
}

/// Appends [`num`]`(x, decimals)` to `out`.
pub fn push_num(out: &mut String, x: f64, decimals: usize) {
    // Formatting a float to a fixed precision is exact decimal arithmetic, and it was half
    // of a large SMIL export: round in floating point instead and print an integer,
    // wherever that is sure to give the same digits (see `num_by_integer`).
    if !num_by_integer(out, x, decimals) {
        out.push_str(&num_by_format(x, decimals));
    }
}

/// [`num`] through an integer: `x·10^decimals` rounded, appended to `out`. Its product is
/// off the exact one by at most half a unit in the last place (under 1e-7 below 1e9), so
/// its rounding is the exact one unless it lies that close to a half; then false, writing
/// nothing, as for large magnitudes.
fn num_by_integer(out: &mut String, x: f64, decimals: usize) -> bool {
    const SCALE: [f64; 7] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6];
    const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];
    let (Some(scale), Some(&unit)) = (SCALE.get(decimals), POW10.get(decimals)) else {
        return false;
    };
    let y = x * scale;
    let a = y.abs();
    // Not finite, or too large for the product's bound.
    if !a.is_finite() || a >= 1e9 {
        return false;
    }
    // The whole and fractional parts by conversions, not calls into libm's `round` and
    // `trunc` (two calls a number were a fifth of this function's time).
    let whole = a as u64;
    let frac = a - whole as f64;
    if (frac - 0.5).abs() < 1e-6 {
        return false;
    }
    // `y.round()`: never a half here, so up exactly when the fraction is over one.
    let n = whole + u64::from(frac > 0.5);
    if n == 0 {
        out.push('0');
        return true;
    }
    if y < 0.0 {
        out.push('-');
    }
    let mut digits = itoa::Buffer::new();
    out.push_str(digits.format(n / unit));
    // The fraction's digits, zero-padded to `decimals`, trailing zeros dropped.
    let (mut fraction, mut places) = (n % unit, decimals);
    if fraction != 0 {
        while fraction % 10 == 0 {
            fraction /= 10;
            places -= 1;
        }
        out.push('.');
        let text = digits.format(fraction);
        for _ in text.len()..places {
            out.push('0');
        }
        out.push_str(text);
    }
    true
}

fn num_by_format(x: f64, decimals: usize) -> String {
    let mut s = format!("{x:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" { "0".to_string() } else { s }
}

/// A static transform attribute value, `None` for the identity.
pub fn transform_value(m: Affine) -> Option<String> {
    let [a, b, c, d, e, f] = m.as_coeffs();
    let [sa, sb, sc, sd] = [a, b, c, d].map(|v| num(v, FACTOR));
    let (se, sf) = (num(e, COORD), num(f, COORD));
    if (sa.as_str(), sb.as_str(), sc.as_str(), sd.as_str()) == ("1", "0", "0", "1") {
        if se == "0" && sf == "0" {
            return None;
        }
        return Some(format!("translate({se} {sf})"));
    }
    Some(format!("matrix({sa} {sb} {sc} {sd} {se} {sf})"))
}

/// Drops keys that change nothing: the middle of three equal values, and a key repeating
/// its predecessor's time and value. The first and last key always stay.
fn compact<'k>(keys: &[Key<&'k str>]) -> Vec<Key<&'k str>> {
    let mut out: Vec<Key<&str>> = Vec::with_capacity(keys.len());
    for k in keys {
        if let Some(last) = out.last()
            && last.t == k.t
            && last.v == k.v
        {
            continue;
        }
        if out.len() >= 2 {
            let n = out.len();
            if out[n - 2].v == out[n - 1].v && out[n - 1].v == k.v {
                out.pop();
                out.push(Key::linear(k.t, k.v));
                continue;
            }
        }
        out.push(*k);
    }
    out
}

/// Key-time units per document duration (the precision `TIME` decimals write).
const TIME_UNITS: f64 = 1e6;

/// Each key's time in units of `1 / TIME_UNITS` of `dur`. A player sampling exactly at a
/// jump's time must show the value after it, as the engine does, so a jump is written at its
/// time rounded down, with the value before it one unit earlier (rounding to nearest could
/// put `1/30 s` of a 2 s document at 0.016667, after a frame sampled at 1/30 s). Discrete
/// keys are all jumps. Other keys round to nearest; the first is 0 and, unless discrete,
/// the last is the full duration.
fn key_units<V>(keys: &[Key<V>], dur: f64, discrete: bool) -> Vec<i64> {
    let frac = |t: f64| (t / dur).clamp(0.0, 1.0) * TIME_UNITS;
    // A relative slack of 1e-9 absorbs the error of `t / dur` on an exact time.
    let floor = |t: f64| (frac(t) + 1e-3).floor() as i64;
    let jump_at = |i: usize| i + 1 < keys.len() && keys[i + 1].t - keys[i].t <= 1e-12 * dur;
    let last = keys.len() - 1;
    let mut units: Vec<i64> = Vec::with_capacity(keys.len());
    for (i, k) in keys.iter().enumerate() {
        let prev = units.last().copied().unwrap_or(0);
        let u = if i == 0 {
            0
        } else if i == last && !discrete {
            TIME_UNITS as i64
        } else if discrete || (i > 0 && jump_at(i - 1)) {
            floor(k.t)
        } else if jump_at(i) {
            floor(k.t) - 1
        } else {
            frac(k.t).round() as i64
        };
        units.push(u.max(prev));
    }
    units
}

/// Appends one animation element. `head` holds the element's own attributes (name, type,
/// additive); `keys` span `[0, clock.dur]` (holds are added at either end when they don't).
/// Returns false, writing nothing, when the value never changes.
pub fn animation(
    out: &mut String,
    element: &str,
    head: &str,
    keys: &[Key<String>],
    discrete: bool,
    clock: Clock,
) -> bool {
    timed(out, element, head, "values", keys, discrete, clock)
}

/// Appends an `animateMotion` along the path its `head` names (with `rotate`), whose keys
/// are the arc-length fractions travelled (`keyPoints`), timed like [`animation`]. Its
/// `calcMode` is always written: an `animateMotion`'s default is `paced`, which would
/// ignore the key times.
pub fn motion(out: &mut String, head: &str, keys: &[Key<String>], clock: Clock) -> bool {
    timed(out, "animateMotion", head, "keyPoints", keys, false, clock)
}

/// [`animation`] with its values in the attribute named `values` (`values`, `keyPoints`).
fn timed(
    out: &mut String,
    element: &str,
    head: &str,
    values: &str,
    keys: &[Key<String>],
    discrete: bool,
    clock: Clock,
) -> bool {
    let Some(first) = keys.first() else {
        return false;
    };
    let mut full: Vec<Key<&str>> = Vec::with_capacity(keys.len() + 2);
    if first.t > 0.0 {
        full.push(Key::linear(0.0, first.v.as_str()));
    }
    full.extend(keys.iter().map(|k| Key {
        t: k.t,
        v: k.v.as_str(),
        ease: k.ease,
    }));
    let last = full[full.len() - 1];
    if last.t < clock.dur && !discrete {
        full.push(Key::linear(clock.dur, last.v));
    }
    let mut keys = compact(&full);
    if keys.iter().all(|k| k.v == keys[0].v) {
        return false;
    }
    // A jump at the start: the value before it is never shown (the engine, like every
    // window list, is right-continuous), and `0;0` leaves the player to pick a side.
    while !discrete && keys.len() > 2 && keys[1].t <= keys[0].t {
        keys.remove(0);
    }
    let units = key_units(&keys, clock.dur, discrete);
    // Written piece by piece into `out`: a large document has millions of numbers, and a
    // string for each was most of the time spent here.
    out.push('<');
    out.push_str(element);
    out.push(' ');
    out.push_str(head);
    out.push_str(" begin=\"0s\" dur=\"");
    push_num(out, clock.dur, TIME);
    out.push_str("s\" keyTimes=\"");
    for (i, &u) in units.iter().enumerate() {
        if i > 0 {
            out.push(';');
        }
        push_num(out, u as f64 / TIME_UNITS, TIME);
    }
    out.push_str("\" ");
    out.push_str(values);
    out.push_str("=\"");
    for (i, k) in keys.iter().enumerate() {
        if i > 0 {
            out.push(';');
        }
        out.push_str(k.v);
    }
    out.push('"');
    if discrete {
        out.push_str(" calcMode=\"discrete\"");
    } else if keys[1..].iter().any(|k| matches!(k.ease, Ease::Bezier(_))) {
        out.push_str(" calcMode=\"spline\" keySplines=\"");
        for (i, k) in keys[1..].iter().enumerate() {
            if i > 0 {
                out.push(';');
            }
            match k.ease {
                Ease::Linear => out.push_str("0 0 1 1"),
                Ease::Bezier(s) => {
                    for (j, v) in s.iter().enumerate() {
                        if j > 0 {
                            out.push(' ');
                        }
                        push_num(out, v.clamp(0.0, 1.0), SPLINE);
                    }
                }
                Ease::Hold => unreachable!("SMIL keys spell a hold as two keys of one value"),
            }
        }
        out.push('"');
    } else if element == "animateMotion" {
        out.push_str(" calcMode=\"linear\"");
    }
    out.push_str(if clock.looping {
        " repeatCount=\"indefinite\"/>"
    } else {
        " fill=\"freeze\"/>"
    });
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(1.0, 4), "1");
        assert_eq!(num(-0.00001, 4), "0");
        assert_eq!(num(2.50, 4), "2.5");
        assert_eq!(num(-12.345678, 4), "-12.3457");
    }

    /// The integer path prints what exact decimal formatting prints, over every magnitude
    /// a drawing has, and near the halves it leaves to it.
    #[test]
    fn numbers_by_integer_match_exact_formatting() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut checked = 0;
        for k in 0..200_000 {
            let bits = next();
            let scale = 10f64.powi((bits % 14) as i32 - 6);
            let mut x = ((bits >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
            let decimals = (next() % 7) as usize;
            if k % 4 == 0 {
                // Right at, or a hair off, a half of the last place.
                let unit = 10f64.powi(-(decimals as i32));
                x = ((x / unit).trunc() + 0.5) * unit + [0.0, 1e-12, -1e-12][k % 3];
            }
            let mut fast = String::new();
            if num_by_integer(&mut fast, x, decimals) {
                assert_eq!(fast, num_by_format(x, decimals), "{x:e} to {decimals}");
                checked += 1;
            }
        }
        assert!(checked > 120_000, "{checked}");
    }

    #[test]
    fn holds_collapse() {
        let k = |t: f64, v: &'static str| Key::linear(t, v);
        let keys = compact(&[
            k(0.0, "a"),
            k(1.0, "a"),
            k(2.0, "a"),
            k(3.0, "b"),
            k(3.0, "b"),
        ]);
        let got: Vec<(f64, &str)> = keys.iter().map(|k| (k.t, k.v)).collect();
        assert_eq!(got, vec![(0.0, "a"), (2.0, "a"), (3.0, "b")]);
    }

    #[test]
    fn constant_channels_write_nothing() {
        let mut s = String::new();
        let keys = [
            Key::linear(0.0, "1".to_string()),
            Key::linear(2.0, "1".to_string()),
        ];
        assert!(!animation(
            &mut s,
            "animate",
            "attributeName=\"opacity\"",
            &keys,
            false,
            Clock {
                dur: 2.0,
                looping: false
            }
        ));
        assert!(s.is_empty());
    }
}
