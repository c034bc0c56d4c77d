//! A number as a Lottie document written by gmotion spells it: rounded where it is made,
//! integral values without a fraction, so output is compact and identical from run to run.

use serde::{Serialize, Serializer};

/// A number as written: rounded by its constructor, integral values without `.0`.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Default)]
pub struct N(pub f64);

impl N {
    /// A coordinate, angle, percentage or frame time: three decimals.
    pub fn coord(x: f64) -> N {
        N(round_to(x, 1e3))
    }

    /// A colour component, opacity fraction, gradient offset or easing handle: five decimals.
    pub fn fine(x: f64) -> N {
        N(round_to(x, 1e5))
    }
}

fn round_to(x: f64, scale: f64) -> f64 {
    let r = (x * scale).round() / scale;
    // Avoid writing `-0`.
    if r == 0.0 { 0.0 } else { r }
}

impl Serialize for N {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let x = self.0;
        if x.fract() == 0.0 && x.abs() < 1e15 {
            s.serialize_i64(x as i64)
        } else if x.is_finite() {
            s.serialize_f64(x)
        } else {
            // Non-finite values never reach the model (callers check), but JSON has no
            // spelling for them, so write a neutral number rather than invalid JSON.
            s.serialize_i64(0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact() {
        let v = serde_json::to_string(&vec![
            N::coord(1.0),
            N::coord(2.50004),
            N::coord(-0.0001),
            N::fine(1.0 / 3.0),
        ])
        .unwrap();
        assert_eq!(v, "[1,2.5,0,0.33333]");
    }
}
