//! Properties as the exporter writes them into a document of its own: the shared
//! [`model::Prop`] and [`model::Keyframe`] holding [`Value`]s, with frames and easing
//! handles as [`N`]s (rounded where they are made), serialised in the key order players
//! need (`{"a":0,"k":value}`, `{"t","s","h"}` or `{"t","s","o","i"}`).

use serde::ser::{SerializeMap, SerializeSeq};
use serde::{Serialize, Serializer};

use crate::model::{self, Bezier};
use crate::number::N;

/// A property value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number (written bare when static, as `[x]` in keyframes).
    Scalar(N),
    /// A vector: point, scale, colour or flat gradient list.
    Vec(Vec<N>),
    /// A Bézier outline (written as `[bezier]` in keyframes); boxed, since every
    /// property holds a value and most are a number or a pair.
    Bezier(Box<Bezier>),
}

impl Value {
    /// A number or vector rounded as a coordinate ([`N::coord`]); an outline as it is
    /// (transforms, the values rounded this way, hold none).
    fn rounded(mut self) -> Value {
        match &mut self {
            Value::Scalar(x) => *x = N::coord(x.0),
            Value::Vec(xs) => xs.iter_mut().for_each(|x| *x = N::coord(x.0)),
            Value::Bezier(_) => {}
        }
        self
    }

    fn write_keyframe_value<S: SerializeMap>(&self, m: &mut S) -> Result<(), S::Error> {
        match self {
            Value::Scalar(x) => m.serialize_entry("s", &[x]),
            Value::Vec(v) => m.serialize_entry("s", v),
            Value::Bezier(b) => m.serialize_entry("s", std::slice::from_ref(&**b)),
        }
    }
}

impl Serialize for Value {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::Scalar(x) => x.serialize(s),
            Value::Vec(v) => v.serialize(s),
            Value::Bezier(b) => b.serialize(s),
        }
    }
}

/// An easing handle as written: one time and one value fraction.
pub type Ease = model::Ease<N>;

/// How a written keyframe eases to the next: its out handle (`o`) and the next keyframe's
/// in handle (`i`).
pub type Easing = [Ease; 2];

/// Linear interpolation.
pub const LINEAR: Easing = [
    Ease {
        x: N(0.0),
        y: N(0.0),
    },
    Ease {
        x: N(1.0),
        y: N(1.0),
    },
];

/// The easing of CSS `cubic-bezier(x1, y1, x2, y2)` control points.
pub fn from_css([x1, y1, x2, y2]: [f64; 4]) -> Easing {
    [
        Ease {
            x: N::fine(x1.clamp(0.0, 1.0)),
            y: N::fine(y1),
        },
        Ease {
            x: N::fine(x2.clamp(0.0, 1.0)),
            y: N::fine(y2),
        },
    ]
}

/// A keyframe as written: the value at frame `t` and how it moves on to the next keyframe.
pub type Keyframe = model::Keyframe<Value, N, N>;

impl Keyframe {
    /// `s` at frame `t`, eased to the next keyframe by `ease` (`None` on the last one and
    /// on holds), or held until it.
    pub fn written(t: N, s: Value, ease: Option<Easing>, hold: bool) -> Keyframe {
        Keyframe {
            t,
            s: Some(s),
            e: None,
            o: ease.map(|[o, _]| o),
            i: ease.map(|[_, i]| i),
            hold,
            to: None,
            ti: None,
        }
    }

    /// The value (a written keyframe always has one).
    pub fn value(&self) -> &Value {
        self.s.as_ref().expect("written keyframes hold their value")
    }

    /// How it eases to the next keyframe (`None` on the last one and on holds).
    pub fn easing(&self) -> Option<Easing> {
        Some([self.o?, self.i?])
    }

    /// Sets how it eases to the next keyframe.
    pub fn set_easing(&mut self, ease: Option<Easing>) {
        self.o = ease.map(|[o, _]| o);
        self.i = ease.map(|[_, i]| i);
    }
}

impl Serialize for Keyframe {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("t", &self.t)?;
        self.value().write_keyframe_value(&mut m)?;
        if self.hold {
            m.serialize_entry("h", &1)?;
        } else if let Some([o, i]) = self.easing() {
            m.serialize_entry("o", &o)?;
            m.serialize_entry("i", &i)?;
        }
        // Spatial tangents (a position moving along a curve), rounded as coordinates.
        let coords = |v: &[f64]| v.iter().map(|x| N::coord(*x)).collect::<Vec<_>>();
        if let Some(to) = &self.to {
            m.serialize_entry("to", &coords(to))?;
        }
        if let Some(ti) = &self.ti {
            m.serialize_entry("ti", &coords(ti))?;
        }
        m.end()
    }
}

/// An animatable property as written: `{"a":0,"k":value}` or `{"a":1,"k":[keyframes]}`,
/// at least two keyframes. (No split position, `{"s":true,"x":…,"y":…}`: lottie-web
/// draws nothing when a shape group's transform holds one, and every animated transform
/// the exporter writes is a shape group's.)
pub type Prop = model::Prop<Value, N, N>;

impl From<N> for Prop {
    /// A fixed number.
    fn from(x: N) -> Prop {
        Prop::scalar(x)
    }
}

impl Prop {
    /// Every value rounded as a coordinate; keys that then all hold one value become a
    /// fixed value.
    pub fn rounded(self) -> Prop {
        match self {
            Prop::Static(v) => Prop::Static(v.rounded()),
            Prop::Animated(mut keys) => {
                for k in &mut keys {
                    k.s = k.s.take().map(Value::rounded);
                }
                Prop::keyed(keys)
            }
        }
    }

    /// A fixed value.
    pub fn fixed(v: Value) -> Prop {
        Prop::Static(v)
    }

    /// A fixed number.
    pub fn scalar(x: N) -> Prop {
        Prop::Static(Value::Scalar(x))
    }

    /// A fixed vector.
    pub fn vec(v: Vec<N>) -> Prop {
        Prop::Static(Value::Vec(v))
    }

    /// Keyframes, collapsed to a fixed value when every keyframe holds the same value.
    pub fn keyed(keys: Vec<Keyframe>) -> Prop {
        match keys.first() {
            None => Prop::scalar(N(0.0)),
            Some(first) if keys.iter().all(|k| k.s == first.s) => {
                Prop::Static(first.value().clone())
            }
            Some(_) => Prop::Animated(keys),
        }
    }
}

impl Serialize for Prop {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(2))?;
        match self {
            Prop::Static(v) => {
                m.serialize_entry("a", &0)?;
                m.serialize_entry("k", v)?;
            }
            Prop::Animated(keys) => {
                m.serialize_entry("a", &1)?;
                m.serialize_entry("k", &KeyList(keys))?;
            }
        }
        m.end()
    }
}

struct KeyList<'a>(&'a [Keyframe]);

impl Serialize for KeyList<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for k in self.0 {
            seq.serialize_element(k)?;
        }
        seq.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_keyframes_are_arrays() {
        let k = |t, ease| Keyframe::written(N(t), Value::Scalar(N(5.0)), ease, false);
        let j = serde_json::to_string(&Prop::Animated(vec![k(0.0, Some(LINEAR)), k(10.0, None)]))
            .unwrap();
        assert_eq!(
            j,
            r#"{"a":1,"k":[{"t":0,"s":[5],"o":{"x":0,"y":0},"i":{"x":1,"y":1}},{"t":10,"s":[5]}]}"#
        );
    }
}
