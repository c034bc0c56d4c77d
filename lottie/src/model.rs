//! The parts of a Lottie document gmotion reads, as typed values taken from serde_json's
//! tree of the document.
//!
//! The model is read from a [`serde_json::Value`] rather than derived with serde: every
//! error then names its JSON location (`$.layers[3].ks.p.k[1].s`), which a derived model
//! cannot do without another crate, and whatever the model does not know (masks, effects,
//! text documents, match names, unknown keys) simply stays in the source tree, which the
//! importer keeps whole for verbatim pass-through ([`crate::Source`]). A source document
//! is never written from the model: the exporter edits the source tree itself. The types
//! the exporter also writes into documents of its own implement serde's `Serialize`, in
//! the key order players need ([`Bezier`]).

use std::fmt;

use serde::Serialize;
use serde::ser::{SerializeStruct, Serializer};
use serde_json::{Map, Value};

use crate::number::N;

use crate::text::{Fonts, TextData};

/// A JSON location in the document, written as a path from the root: `$.layers[3].ks.p`.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct Loc(String);

impl Loc {
    /// The document's root, `$`.
    pub fn root() -> Loc {
        Loc("$".to_string())
    }

    /// The member `key` of the object here.
    pub fn key(&self, key: &str) -> Loc {
        Loc(format!("{}.{key}", self.0))
    }

    /// The element `i` of the array here.
    pub fn idx(&self, i: usize) -> Loc {
        Loc(format!("{}[{i}]", self.0))
    }

    /// The path as text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Something in the document that cannot be read, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError {
    /// Where.
    pub at: Loc,
    /// What is wrong.
    pub message: String,
}

/// What reading (or drawing) the document gives, or where and why it cannot.
pub type Result<T> = std::result::Result<T, ModelError>;

pub(crate) fn error<T>(at: &Loc, message: impl Into<String>) -> Result<T> {
    Err(ModelError {
        at: at.clone(),
        message: message.into(),
    })
}

/// Numbers beyond this magnitude are refused: no real animation needs them, and products
/// of a few of them would overflow to infinity in the geometry.
pub const MAX_MAGNITUDE: f64 = 1e9;

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// A finite number of sane magnitude (booleans read as 0 and 1, as players read them).
pub(crate) fn number(v: &Value, at: &Loc) -> Result<f64> {
    let x = match v {
        Value::Number(n) => n.as_f64(),
        Value::Bool(b) => Some(f64::from(u8::from(*b))),
        other => return error(at, format!("expected a number, found {}", kind(other))),
    };
    match x {
        Some(x) if x.is_finite() && x.abs() <= MAX_MAGNITUDE => Ok(x),
        _ => error(
            at,
            format!("the number is out of range (beyond ±{MAX_MAGNITUDE})"),
        ),
    }
}

pub(crate) fn object<'a>(v: &'a Value, at: &Loc) -> Result<&'a Map<String, Value>> {
    v.as_object().map_or_else(
        || error(at, format!("expected an object, found {}", kind(v))),
        Ok,
    )
}

pub(crate) fn array<'a>(v: &'a Value, at: &Loc) -> Result<&'a [Value]> {
    v.as_array().map_or_else(
        || error(at, format!("expected an array, found {}", kind(v))),
        |a| Ok(a.as_slice()),
    )
}

pub(crate) fn opt_number(o: &Map<String, Value>, key: &str, at: &Loc) -> Result<Option<f64>> {
    match o.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => number(v, &at.key(key)).map(Some),
    }
}

fn opt_int(o: &Map<String, Value>, key: &str, at: &Loc) -> Result<Option<i64>> {
    Ok(opt_number(o, key, at)?.map(|x| x.round() as i64))
}

pub(crate) fn opt_string(o: &Map<String, Value>, key: &str, at: &Loc) -> Result<Option<String>> {
    match o.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        // Names are sometimes numbers in hand-made files; players show them as text.
        Some(Value::Number(n)) => Ok(Some(n.to_string())),
        Some(v) => error(
            &at.key(key),
            format!("expected a string, found {}", kind(v)),
        ),
    }
}

fn flag(o: &Map<String, Value>, key: &str, at: &Loc) -> Result<bool> {
    Ok(opt_number(o, key, at)?.is_some_and(|x| x != 0.0))
}

/// A value a property can take: read from JSON, interpolated between keyframes.
pub trait PropValue: Clone + fmt::Debug {
    /// Reads one value.
    fn read(v: &Value, at: &Loc) -> Result<Self>;
    /// The value a fraction `p` of the way to `other` (per component; `self` where the
    /// two do not match).
    fn lerp(&self, other: &Self, p: &[f64]) -> Self;
}

impl PropValue for Vec<f64> {
    fn read(v: &Value, at: &Loc) -> Result<Self> {
        match v {
            Value::Array(xs) => xs
                .iter()
                .enumerate()
                .map(|(i, x)| number(x, &at.idx(i)))
                .collect(),
            other => Ok(vec![number(other, at)?]),
        }
    }

    fn lerp(&self, other: &Self, p: &[f64]) -> Self {
        if other.len() != self.len() {
            return self.clone();
        }
        self.iter()
            .zip(other)
            .enumerate()
            .map(|(k, (a, b))| {
                let p = p.get(k).or(p.last()).copied().unwrap_or(0.0);
                a + (b - a) * p
            })
            .collect()
    }
}

/// A Bézier outline as Lottie writes it: vertices with in and out tangents relative to
/// them. Read from a document, and written (`{"c", "v", "i", "o"}`, each number as
/// [`N`] spells it) by the exporter, which rounds the points where it makes them.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Bezier {
    /// Whether the outline is closed (`c`; `None` when the file leaves it out, and then
    /// not written).
    pub closed: Option<bool>,
    /// Vertices.
    pub v: Vec<[f64; 2]>,
    /// In tangents, relative to their vertex.
    pub i: Vec<[f64; 2]>,
    /// Out tangents, relative to their vertex.
    pub o: Vec<[f64; 2]>,
}

impl Serialize for Bezier {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        /// Points as `[[x, y], …]`.
        struct Points<'a>(&'a [[f64; 2]]);
        impl Serialize for Points<'_> {
            fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
                s.collect_seq(self.0.iter().map(|&[x, y]| [N(x), N(y)]))
            }
        }
        let mut m = s.serialize_struct("Bezier", 4)?;
        match self.closed {
            Some(c) => m.serialize_field("c", &c)?,
            None => m.skip_field("c")?,
        }
        m.serialize_field("v", &Points(&self.v))?;
        m.serialize_field("i", &Points(&self.i))?;
        m.serialize_field("o", &Points(&self.o))?;
        m.end()
    }
}

fn points(o: &Map<String, Value>, key: &str, at: &Loc) -> Result<Vec<[f64; 2]>> {
    let Some(v) = o.get(key) else {
        return Ok(Vec::new());
    };
    let at = at.key(key);
    array(v, &at)?
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let at = at.idx(i);
            let xs = array(p, &at)?;
            match xs {
                [x, y, ..] => Ok([number(x, &at.idx(0))?, number(y, &at.idx(1))?]),
                _ => error(&at, "expected a point [x, y]"),
            }
        })
        .collect()
}

impl PropValue for Bezier {
    fn read(v: &Value, at: &Loc) -> Result<Self> {
        // Keyframe values wrap the outline in an array of one.
        if let Value::Array(xs) = v {
            return match xs.first() {
                Some(first) => Bezier::read(first, &at.idx(0)),
                None => Ok(Bezier::default()),
            };
        }
        let o = object(v, at)?;
        let closed = match o.get("c") {
            None | Some(Value::Null) => None,
            Some(Value::Bool(b)) => Some(*b),
            Some(c) => Some(number(c, &at.key("c"))? != 0.0),
        };
        Ok(Bezier {
            closed,
            v: points(o, "v", at)?,
            i: points(o, "i", at)?,
            o: points(o, "o", at)?,
        })
    }

    fn lerp(&self, other: &Self, p: &[f64]) -> Self {
        if other.v.len() != self.v.len() || other.i.len() != self.i.len() {
            return self.clone();
        }
        let p = p.first().copied().unwrap_or(0.0);
        let mix = |a: &[[f64; 2]], b: &[[f64; 2]]| {
            a.iter()
                .zip(b)
                .map(|(a, b)| [a[0] + (b[0] - a[0]) * p, a[1] + (b[1] - a[1]) * p])
                .collect()
        };
        Bezier {
            closed: self.closed,
            v: mix(&self.v, &other.v),
            i: mix(&self.i, &other.i),
            o: mix(&self.o, &other.o),
        }
    }
}

/// A keyframe's easing handle, in the unit square of (time, value) fractions: as read, one
/// `x`, `y` per component (or one for all); as the exporter writes it
/// ([`crate::written`]), one number each.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize)]
pub struct Ease<C = Vec<f64>> {
    /// Time coordinates.
    pub x: C,
    /// Value coordinates.
    pub y: C,
}

/// One keyframe. Files before Bodymovin 5.5 give each keyframe its end value `e` and end
/// with a keyframe that has only a time.
///
/// Generic over how a number is held, like [`Transform`]: as read, a frame `F` and
/// handle coordinates `C` are `f64`s (per component); in the documents the exporter
/// writes ([`crate::written::Keyframe`]), [`N`]s, with always a start value and never an
/// end value; spatial tangents only on a position moving along a path.
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe<T, F = f64, C = Vec<f64>> {
    /// Frame (in the layer's time).
    pub t: F,
    /// Start value.
    pub s: Option<T>,
    /// End value (legacy).
    pub e: Option<T>,
    /// Out handle (easing from this keyframe).
    pub o: Option<Ease<C>>,
    /// In handle (easing into the next keyframe).
    pub i: Option<Ease<C>>,
    /// Hold until the next keyframe.
    pub hold: bool,
    /// Spatial out tangent (positions).
    pub to: Option<Vec<f64>>,
    /// Spatial in tangent (positions).
    pub ti: Option<Vec<f64>>,
}

/// A property: a static value or keyframes (of the kind [`Keyframe`]'s `F` and `C` say).
#[derive(Clone, Debug, PartialEq)]
pub enum Prop<T, F = f64, C = Vec<f64>> {
    /// Not animated.
    Static(T),
    /// Keyframed.
    Animated(Vec<Keyframe<T, F, C>>),
}

/// A property with where it is and whether an expression drives it.
#[derive(Clone, Debug)]
pub struct Property<T> {
    /// The value.
    pub value: Prop<T>,
    /// Whether an expression (`x`) drives it (gmotion does not run expressions).
    pub expression: bool,
    /// Where it is.
    pub at: Loc,
}

fn ease(v: &Value, at: &Loc) -> Result<Ease> {
    let o = object(v, at)?;
    let axis = |key: &str| -> Result<Vec<f64>> {
        match o.get(key) {
            None => Ok(Vec::new()),
            Some(v) => Vec::<f64>::read(v, &at.key(key)),
        }
    };
    Ok(Ease {
        x: axis("x")?,
        y: axis("y")?,
    })
}

fn keyframe<T: PropValue>(v: &Value, at: &Loc) -> Result<Keyframe<T>> {
    let o = object(v, at)?;
    let Some(t) = opt_number(o, "t", at)? else {
        return error(at, "a keyframe needs its time `t`");
    };
    let value = |key: &str| -> Result<Option<T>> {
        match o.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => T::read(v, &at.key(key)).map(Some),
        }
    };
    let handle = |key: &str| -> Result<Option<Ease>> {
        o.get(key).map(|v| ease(v, &at.key(key))).transpose()
    };
    let tangent = |key: &str| -> Result<Option<Vec<f64>>> {
        match o.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => Vec::<f64>::read(v, &at.key(key)).map(Some),
        }
    };
    Ok(Keyframe {
        t,
        s: value("s")?,
        e: value("e")?,
        o: handle("o")?,
        i: handle("i")?,
        hold: flag(o, "h", at)?,
        to: tangent("to")?,
        ti: tangent("ti")?,
    })
}

/// Reads a property object (`{"a": 0, "k": …}`).
pub fn property<T: PropValue>(v: &Value, at: &Loc) -> Result<Property<T>> {
    let o = object(v, at)?;
    let expression = o.get("x").is_some_and(|x| !x.is_null());
    let k_at = at.key("k");
    let Some(k) = o.get("k") else {
        return error(at, "a property needs its value `k`");
    };
    // Old files leave out `a`; keyframes are told by being objects with a time.
    let keyed = match o.get("a") {
        Some(a) if !a.is_null() => number(a, &at.key("a"))? != 0.0,
        _ => false,
    } || k
        .as_array()
        .and_then(|xs| xs.first())
        .is_some_and(|f| f.get("t").is_some());
    let value = if keyed {
        let frames = array(k, &k_at)?;
        if frames.is_empty() {
            return error(&k_at, "an animated property needs at least one keyframe");
        }
        Prop::Animated(
            frames
                .iter()
                .enumerate()
                .map(|(i, f)| keyframe(f, &k_at.idx(i)))
                .collect::<Result<_>>()?,
        )
    } else {
        Prop::Static(T::read(k, &k_at)?)
    };
    Ok(Property {
        value,
        expression,
        at: at.clone(),
    })
}

pub(crate) fn opt_property<T: PropValue>(
    o: &Map<String, Value>,
    key: &str,
    at: &Loc,
) -> Result<Option<Property<T>>> {
    match o.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => property(v, &at.key(key)).map(Some),
    }
}

/// A numeric property.
pub type Num = Property<Vec<f64>>;

/// A position: one property, or (split position) one per axis.
#[derive(Clone, Debug)]
pub enum Position {
    /// `p` as one property.
    Joined(Num),
    /// `p.s`: separate `x` and `y` properties.
    Split {
        /// X.
        x: Num,
        /// Y.
        y: Num,
    },
}

/// A transform (a layer's `ks`, or a shape group's `tr`):
/// `T(p)·R(r)·Skew(sk, sa)·S(s)·T(-a)`, with opacity `o`.
///
/// Its channels are properties of type `P` and its position of type `Q`: as read from a
/// document, [`Num`]s and a [`Position`] (joined or split); in the documents the exporter
/// writes, its own property type for both (it never writes a split position: lottie-web
/// draws nothing when a shape group's transform holds one). Written as `a`, `p`, `s`, `r`,
/// `o`, then whichever of `sk`, `sa`, `rx`, `ry`, `or` are set; a missing opacity is
/// written as 100, its default here as in [`crate::eval::opacity`] (lottie-web needs it on
/// groups).
#[derive(Clone, Debug, Serialize)]
#[serde(bound(serialize = "P: Serialize + From<N> + Clone, Q: Serialize"))]
pub struct Transform<P = Num, Q = Position> {
    /// Anchor point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a: Option<P>,
    /// Position.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p: Option<Q>,
    /// Scale, in percent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub s: Option<P>,
    /// Rotation in degrees, clockwise (`rz` on 3D layers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r: Option<P>,
    /// Opacity, in percent.
    #[serde(serialize_with = "opacity_or_opaque")]
    pub o: Option<P>,
    /// Skew angle in degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sk: Option<P>,
    /// Skew axis in degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sa: Option<P>,
    /// Rotation about x in degrees (3D layers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rx: Option<P>,
    /// Rotation about y in degrees (3D layers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ry: Option<P>,
    /// Orientation `[x, y, z]` in degrees (3D layers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub or: Option<P>,
    /// The layer's `ao`: it turns to face along its motion path (a key of the layer, not
    /// of the transform: not written here).
    #[serde(skip)]
    pub auto_orient: bool,
}

/// Opacity as written: a missing one is opaque.
fn opacity_or_opaque<P: Serialize + From<N> + Clone, S: Serializer>(
    o: &Option<P>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    match o {
        Some(p) => p.serialize(s),
        None => P::from(N(100.0)).serialize(s),
    }
}

impl<P, Q> Transform<P, Q> {
    /// The identity: no channel set.
    pub fn empty() -> Transform<P, Q> {
        Transform {
            a: None,
            p: None,
            s: None,
            r: None,
            o: None,
            sk: None,
            sa: None,
            rx: None,
            ry: None,
            or: None,
            auto_orient: false,
        }
    }
}

impl<P, Q> Default for Transform<P, Q> {
    fn default() -> Transform<P, Q> {
        Transform::empty()
    }
}

impl Transform {
    /// Reads a transform object.
    pub fn read(v: &Value, at: &Loc) -> Result<Transform> {
        let o = object(v, at)?;
        let p = match o.get("p") {
            None | Some(Value::Null) => None,
            Some(p) => {
                let p_at = at.key("p");
                let po = object(p, &p_at)?;
                if po
                    .get("s")
                    .is_some_and(|s| s.as_bool() == Some(true) || s == 1)
                {
                    let axis = |k: &str| -> Result<Num> {
                        match po.get(k) {
                            Some(v) => property(v, &p_at.key(k)),
                            None => error(&p_at, format!("a split position needs `{k}`")),
                        }
                    };
                    Some(Position::Split {
                        x: axis("x")?,
                        y: axis("y")?,
                    })
                } else {
                    Some(Position::Joined(property(p, &p_at)?))
                }
            }
        };
        Ok(Transform {
            a: opt_property(o, "a", at)?,
            p,
            s: opt_property(o, "s", at)?,
            r: match opt_property(o, "r", at)? {
                Some(r) => Some(r),
                None => opt_property(o, "rz", at)?,
            },
            o: opt_property(o, "o", at)?,
            sk: opt_property(o, "sk", at)?,
            sa: opt_property(o, "sa", at)?,
            rx: opt_property(o, "rx", at)?,
            ry: opt_property(o, "ry", at)?,
            or: opt_property(o, "or", at)?,
            auto_orient: false,
        })
    }

    /// Whether an expression drives any channel.
    pub fn has_expression(&self) -> bool {
        let p = match &self.p {
            Some(Position::Joined(p)) => p.expression,
            Some(Position::Split { x, y }) => x.expression || y.expression,
            None => false,
        };
        p || [
            &self.a, &self.s, &self.r, &self.o, &self.sk, &self.sa, &self.rx, &self.ry, &self.or,
        ]
        .iter()
        .any(|c| c.as_ref().is_some_and(|c| c.expression))
    }
}

/// A dash entry of a stroke: `d` (dash), `g` (gap) or `o` (offset). Its length is a
/// property of type `P`: a [`Num`] as read from a document, the exporter's own property
/// type in the documents it writes (`{"n", "nm", "v"}`).
#[derive(Clone, Debug, Serialize)]
pub struct Dash<P = Num> {
    /// `d`, `g` or `o`.
    pub n: String,
    /// Its name: lottie-web names each entry as a property, so the names of one pattern
    /// must be unique (empty when a document leaves it out).
    pub nm: String,
    /// Its length.
    pub v: P,
}

/// What a shape item is.
#[derive(Clone, Debug)]
pub enum ShapeKind {
    /// `gr`: items, topmost first, the group's `tr` among them.
    Group(Vec<ShapeItem>),
    /// `sh`: a Bézier outline; `closed` is the legacy closed flag of the item.
    Path {
        /// The outline.
        ks: Property<Bezier>,
        /// Pre-4.4.18 files say `closed` on the item.
        closed: Option<bool>,
    },
    /// `rc`: a rectangle about its centre `p`, size `s`, corner roundness `r`.
    Rect {
        /// Centre.
        p: Option<Num>,
        /// Size.
        s: Option<Num>,
        /// Corner radius.
        r: Option<Num>,
        /// `d` 3: drawn counter-clockwise.
        reversed: bool,
    },
    /// `el`: an ellipse about its centre `p`, size `s`.
    Ellipse {
        /// Centre.
        p: Option<Num>,
        /// Size.
        s: Option<Num>,
        /// `d` 3: drawn counter-clockwise.
        reversed: bool,
    },
    /// `sr`: a star (`sy` 1) or polygon (`sy` 2).
    Star {
        /// 1 star, 2 polygon.
        sy: i64,
        /// Centre.
        p: Option<Num>,
        /// Outer radius.
        or: Option<Num>,
        /// Inner radius (stars).
        ir: Option<Num>,
        /// Rotation, degrees.
        r: Option<Num>,
        /// Number of points.
        pt: Option<Num>,
        /// `d` 3: drawn counter-clockwise.
        reversed: bool,
    },
    /// `fl`: a solid fill.
    Fill {
        /// Colour `[r, g, b(, a)]`.
        c: Option<Num>,
        /// Opacity, percent.
        o: Option<Num>,
        /// 1 non-zero, 2 even-odd.
        rule: i64,
    },
    /// `st`: a solid stroke.
    Stroke {
        /// Colour.
        c: Option<Num>,
        /// Opacity, percent.
        o: Option<Num>,
        /// Width.
        w: Option<Num>,
        /// Caps, joins and dashes.
        style: StrokeStyle,
    },
    /// `gf` / `gs`: a gradient fill or stroke.
    Gradient(Box<GradientItem>),
    /// `tm`: trim paths, which cut every outline above it (in its group and nested ones).
    Trim {
        /// Start, percent.
        s: Option<Num>,
        /// End, percent.
        e: Option<Num>,
        /// Offset, degrees.
        o: Option<Num>,
        /// `m` 2: the outlines are trimmed one after the other, as one run.
        individually: bool,
    },
    /// `rd`: round corners, which round every corner of the outlines above it.
    RoundCorners {
        /// Radius.
        r: Option<Num>,
    },
    /// `pb`: pucker and bloat, which pulls every outline's vertices towards their mean and
    /// pushes its control points away from it (or the other way).
    PuckerBloat {
        /// Amount, percent (negative puckers, positive bloats).
        a: Option<Num>,
    },
    /// `op`: offset paths, which move every outline above it along its normals.
    OffsetPath {
        /// Amount.
        a: Option<Num>,
        /// Join: 1 miter, 2 round, 3 bevel.
        lj: Option<i64>,
        /// Miter limit.
        ml: Option<Num>,
    },
    /// `zz`: zig-zags, which put ridges along every outline above it.
    ZigZag {
        /// Size of the ridges (amplitude).
        s: Option<Num>,
        /// Ridges per segment.
        r: Option<Num>,
        /// Points: 1 corners, 2 smooth.
        pt: Option<Num>,
    },
    /// `rp`: a repeater, which draws what is above it in its group `c` times, each copy
    /// transformed once more by `tr`.
    Repeater {
        /// Copies.
        c: Option<Num>,
        /// Offset, in copies.
        o: Option<Num>,
        /// `m` 1: the first copy on top; 2: at the bottom.
        above: bool,
        /// The transform between copies (anchor, position, scale, rotation).
        tr: Box<Transform>,
        /// Start opacity (the first copy's), percent.
        so: Option<Num>,
        /// End opacity (the last copy's), percent.
        eo: Option<Num>,
    },
    /// `tr`: the group's transform.
    Transform(Box<Transform>),
    /// Anything else (modifiers such as trim paths, repeaters, merge paths; unknown types):
    /// its `ty`.
    Other(String),
}

impl ShapeKind {
    /// The name of a top-level item that is a unit of its own (`--units groups`), the tag
    /// of such an item with a default name; `None` for items that draw no outline of their
    /// own (styles, modifiers, transforms).
    pub fn part_name(&self) -> Option<&'static str> {
        match self {
            ShapeKind::Group(_) => Some("group"),
            ShapeKind::Path { .. } => Some("path"),
            ShapeKind::Rect { .. } => Some("rect"),
            ShapeKind::Ellipse { .. } => Some("ellipse"),
            ShapeKind::Star { .. } => Some("star"),
            _ => None,
        }
    }
}

/// How a stroke (`st` or `gs`) draws its line: generic like [`Dash`], whose property it
/// holds, and over how a number is held (as written, the exporter's number). Written as
/// `lc`, `lj`, then `ml` and `d` when set.
#[derive(Clone, Debug, Serialize)]
#[serde(bound(serialize = "P: Serialize, F: Serialize"))]
pub struct StrokeStyle<P = Num, F = f64> {
    /// Line cap: 1 butt, 2 round, 3 square.
    pub lc: i64,
    /// Line join: 1 miter, 2 round, 3 bevel.
    pub lj: i64,
    /// Miter limit (4 when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ml: Option<F>,
    /// Dashes.
    #[serde(rename = "d", skip_serializing_if = "Vec::is_empty")]
    pub dashes: Vec<Dash<P>>,
}

impl StrokeStyle {
    fn read(o: &serde_json::Map<String, Value>, at: &Loc) -> Result<StrokeStyle> {
        let mut dashes = Vec::new();
        if let Some(d) = o.get("d") {
            let d_at = at.key("d");
            for (i, e) in array(d, &d_at)?.iter().enumerate() {
                let e_at = d_at.idx(i);
                let eo = object(e, &e_at)?;
                let n = opt_string(eo, "n", &e_at)?.unwrap_or_default();
                // Nothing gmotion draws depends on the name: read as it comes, never an
                // error.
                let nm = eo.get("nm").and_then(Value::as_str).unwrap_or_default();
                if let Some(v) = opt_property(eo, "v", &e_at)? {
                    dashes.push(Dash {
                        n,
                        nm: nm.to_string(),
                        v,
                    });
                }
            }
        }
        Ok(StrokeStyle {
            lc: opt_int(o, "lc", at)?.unwrap_or(2),
            lj: opt_int(o, "lj", at)?.unwrap_or(2),
            ml: opt_number(o, "ml", at)?,
            dashes,
        })
    }
}

/// A gradient's geometry and colours, the part gradient fills (`gf`) and strokes (`gs`)
/// share: written as `t`, `s`, `e`, then `h` and `a` when set, then `g`. Its properties
/// are of type `P` (see [`Dash`]).
#[derive(Clone, Debug, Serialize)]
pub struct Gradient<P = Num> {
    /// `t`: 1 linear, 2 radial (anything else is read as linear).
    pub t: i64,
    /// Start point (the centre of a radial gradient).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub s: Option<P>,
    /// End point (on the end circle of a radial gradient).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub e: Option<P>,
    /// Highlight length, percent of the radius (radial).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h: Option<P>,
    /// Highlight angle, degrees from the `s → e` direction (radial).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a: Option<P>,
    /// Colour (and opacity) stops.
    pub g: GradientStops<P>,
}

impl<P> Gradient<P> {
    /// Whether it is radial (`t` 2).
    pub fn radial(&self) -> bool {
        self.t == 2
    }
}

/// A gradient's stops (`g`): `p` colour stops `[offset, r, g, b]…`, then any opacity stops
/// `[offset, alpha]…`, as one flat list `k`.
#[derive(Clone, Debug, Serialize)]
pub struct GradientStops<P = Num> {
    /// How many colour stops `k` starts with.
    pub p: usize,
    /// The flat stop list.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<P>,
}

/// A gradient fill (`gf`) or stroke (`gs`) item as read: its [`Gradient`] and how it
/// paints. (The exporter writes the two kinds as items of their own.)
#[derive(Clone, Debug)]
pub struct GradientItem {
    /// Whether it is a stroke (`gs`).
    pub stroke: bool,
    /// Opacity, percent.
    pub o: Option<Num>,
    /// The gradient.
    pub gradient: Gradient,
    /// Stroke width (`gs`).
    pub w: Option<Num>,
    /// Fill rule (`gf`).
    pub rule: i64,
    /// Caps, joins and dashes (`gs`).
    pub style: StrokeStyle,
}

/// A shape item with its name, visibility and location.
#[derive(Clone, Debug)]
pub struct ShapeItem {
    /// Where it is.
    pub at: Loc,
    /// `nm`.
    pub nm: String,
    /// `hd`: hidden items draw nothing.
    pub hidden: bool,
    /// What it is.
    pub kind: ShapeKind,
}

/// Shape items. Groups nest at most about 60 deep: serde_json refuses documents nested
/// deeper than 128 levels, which bounds this recursion (and the builder's).
pub(crate) fn shape_items(v: &Value, at: &Loc) -> Result<Vec<ShapeItem>> {
    array(v, at)?
        .iter()
        .enumerate()
        .map(|(i, s)| shape_item(s, &at.idx(i)))
        .collect()
}

fn shape_item(v: &Value, at: &Loc) -> Result<ShapeItem> {
    let o = object(v, at)?;
    let ty = match o.get("ty") {
        Some(Value::String(s)) => s.as_str(),
        Some(other) => {
            return error(
                &at.key("ty"),
                format!("expected a shape type string, found {}", kind(other)),
            );
        }
        None => return error(at, "a shape item needs its type `ty`"),
    };
    let num = |key: &str| opt_property::<Vec<f64>>(o, key, at);
    // `d` is the drawing direction of a primitive (and a stroke's dashes): 3 is
    // counter-clockwise. lottie-web draws a rectangle without `d` counter-clockwise too
    // (rlottie clockwise); After Effects always writes it.
    let direction = || opt_int(o, "d", at);
    let reversed = || -> Result<bool> { Ok(direction()? == Some(3)) };
    let kind = match ty {
        "gr" => ShapeKind::Group(match o.get("it") {
            Some(it) => shape_items(it, &at.key("it"))?,
            None => Vec::new(),
        }),
        "sh" => ShapeKind::Path {
            ks: match o.get("ks") {
                Some(ks) => property(ks, &at.key("ks"))?,
                None => return error(at, "a path (`sh`) needs its outline `ks`"),
            },
            closed: match o.get("closed") {
                Some(Value::Bool(b)) => Some(*b),
                _ => None,
            },
        },
        "rc" => ShapeKind::Rect {
            p: num("p")?,
            s: num("s")?,
            r: num("r")?,
            reversed: !matches!(direction()?, Some(1 | 2)),
        },
        "el" => ShapeKind::Ellipse {
            p: num("p")?,
            s: num("s")?,
            reversed: reversed()?,
        },
        "sr" => ShapeKind::Star {
            sy: opt_int(o, "sy", at)?.unwrap_or(1),
            p: num("p")?,
            or: num("or")?,
            ir: num("ir")?,
            r: num("r")?,
            pt: num("pt")?,
            reversed: reversed()?,
        },
        "fl" => ShapeKind::Fill {
            c: num("c")?,
            o: num("o")?,
            rule: opt_int(o, "r", at)?.unwrap_or(1),
        },
        "st" => ShapeKind::Stroke {
            c: num("c")?,
            o: num("o")?,
            w: num("w")?,
            style: StrokeStyle::read(o, at)?,
        },
        "gf" | "gs" => {
            let (stops, count) = match o.get("g") {
                Some(g) => {
                    let g_at = at.key("g");
                    let go = object(g, &g_at)?;
                    let count = opt_int(go, "p", &g_at)?.unwrap_or(0).clamp(0, 1 << 16);
                    (opt_property(go, "k", &g_at)?, count as usize)
                }
                None => (None, 0),
            };
            // Read in the order the keys were always read, so that a document with
            // several faults names the same first one.
            let opacity = num("o")?;
            let t = opt_int(o, "t", at)?.unwrap_or(1);
            let gradient = Gradient {
                t,
                s: num("s")?,
                e: num("e")?,
                h: num("h")?,
                a: num("a")?,
                g: GradientStops { p: count, k: stops },
            };
            ShapeKind::Gradient(Box::new(GradientItem {
                stroke: ty == "gs",
                o: opacity,
                gradient,
                w: num("w")?,
                rule: opt_int(o, "r", at)?.unwrap_or(1),
                style: StrokeStyle::read(o, at)?,
            }))
        }
        "tm" => ShapeKind::Trim {
            s: num("s")?,
            e: num("e")?,
            o: num("o")?,
            individually: opt_int(o, "m", at)? == Some(2),
        },
        "tr" => ShapeKind::Transform(Box::new(Transform::read(v, at)?)),
        "rd" => ShapeKind::RoundCorners { r: num("r")? },
        "pb" => ShapeKind::PuckerBloat { a: num("a")? },
        "op" => ShapeKind::OffsetPath {
            a: num("a")?,
            lj: opt_int(o, "lj", at)?,
            ml: num("ml")?,
        },
        "zz" => ShapeKind::ZigZag {
            s: num("s")?,
            r: num("r")?,
            pt: num("pt")?,
        },
        "rp" => {
            let tr_at = at.key("tr");
            let (tr, so, eo) = match o.get("tr") {
                Some(tr) => {
                    let tro = object(tr, &tr_at)?;
                    (
                        Transform::read(tr, &tr_at)?,
                        opt_property(tro, "so", &tr_at)?,
                        opt_property(tro, "eo", &tr_at)?,
                    )
                }
                None => (Transform::default(), None, None),
            };
            ShapeKind::Repeater {
                c: num("c")?,
                o: num("o")?,
                above: opt_int(o, "m", at)?.unwrap_or(1) == 1,
                tr: Box::new(tr),
                so,
                eo,
            }
        }
        other => ShapeKind::Other(other.to_string()),
    };
    Ok(ShapeItem {
        at: at.clone(),
        nm: opt_string(o, "nm", at)?.unwrap_or_default(),
        hidden: o.get("hd").and_then(Value::as_bool).unwrap_or(false),
        kind,
    })
}

/// The layer types of the format; written as its number `ty` (the exporter writes
/// precompositions, images, nulls and shapes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayerKind {
    /// `ty` 0: a precomposition.
    Precomp,
    /// `ty` 1: a solid rectangle.
    Solid,
    /// `ty` 2: an image.
    Image,
    /// `ty` 3: a null (a transform others parent to; draws nothing).
    Null,
    /// `ty` 4: shapes.
    Shape,
    /// `ty` 5: text.
    Text,
    /// Anything else (audio, camera, data…): draws nothing gmotion knows.
    Other(i64),
}

impl Serialize for LayerKind {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_i64(self.ty())
    }
}

impl LayerKind {
    fn of(ty: i64) -> LayerKind {
        match ty {
            0 => LayerKind::Precomp,
            1 => LayerKind::Solid,
            2 => LayerKind::Image,
            3 => LayerKind::Null,
            4 => LayerKind::Shape,
            5 => LayerKind::Text,
            other => LayerKind::Other(other),
        }
    }

    /// Its number, `ty`.
    pub fn ty(self) -> i64 {
        match self {
            LayerKind::Precomp => 0,
            LayerKind::Solid => 1,
            LayerKind::Image => 2,
            LayerKind::Null => 3,
            LayerKind::Shape => 4,
            LayerKind::Text => 5,
            LayerKind::Other(ty) => ty,
        }
    }

    /// The kind's name, the tag of layers with a default name.
    pub fn name(self) -> &'static str {
        match self {
            LayerKind::Precomp => "precomp",
            LayerKind::Solid => "solid",
            LayerKind::Image => "image",
            LayerKind::Null => "null",
            LayerKind::Shape => "shape",
            LayerKind::Text => "text",
            LayerKind::Other(_) => "layer",
        }
    }

    /// Whether layers of this kind draw something (and so can be units).
    pub fn draws(self) -> bool {
        !matches!(self, LayerKind::Null | LayerKind::Other(_))
    }
}

/// How a [`Layer`] holds what differs between a layer read ([`Read`]) and a layer the
/// exporter writes (its own marker, with its shapes, masks and effects).
pub trait LayerParts {
    /// The layer's own index (`ind`): optional as read, always set as written.
    type Ind: Clone + fmt::Debug;
    /// Another layer's index (`parent`, `tp`).
    type Index: Clone + fmt::Debug;
    /// A time (`ip`, `op`, `st`).
    type Time: Clone + fmt::Debug;
    /// A size (`w`, `h`).
    type Size: Clone + fmt::Debug;
    /// The transform's channels ([`Transform`]'s `P`).
    type Prop: Clone + fmt::Debug;
    /// The transform's position ([`Transform`]'s `Q`).
    type Position: Clone + fmt::Debug;
    /// The shapes.
    type Shapes: Clone + fmt::Debug;
    /// A layer mask.
    type Mask: Clone + fmt::Debug;
    /// An effect.
    type Effect: Clone + fmt::Debug;
    /// What only a written layer holds (its blend mode, its text written early): nothing
    /// as read.
    type Written: Clone + fmt::Debug;
}

/// A layer as read from a document.
#[derive(Clone, Copy, Debug)]
pub struct Read;

impl LayerParts for Read {
    type Ind = Option<i64>;
    type Index = i64;
    type Time = f64;
    type Size = f64;
    type Prop = Num;
    type Position = Position;
    type Shapes = Vec<ShapeItem>;
    type Mask = LayerMask;
    type Effect = LayerEffect;
    type Written = ();
}

/// A layer: as read ([`Read`], the default) or as the exporter writes it, generic like
/// [`Transform`]. The fields after `effects` are only read: a written layer leaves them
/// empty (its `Layer::new` sets them so), as a read layer has no [`LayerParts::Written`].
#[derive(Clone, Debug)]
pub struct Layer<P: LayerParts = Read> {
    /// Its type.
    pub kind: LayerKind,
    /// Name.
    pub nm: String,
    /// Index (`ind`), which `parent` and `tp` refer to.
    pub ind: P::Ind,
    /// The parent layer's `ind`.
    pub parent: Option<P::Index>,
    /// In point (composition frames).
    pub ip: P::Time,
    /// Out point (composition frames).
    pub op: P::Time,
    /// Start time (composition frames).
    pub st: P::Time,
    /// Transform.
    pub ks: Transform<P::Prop, P::Position>,
    /// Shapes (shape layers), topmost first.
    pub shapes: P::Shapes,
    /// Asset id (precomp and image layers).
    pub ref_id: Option<String>,
    /// Width (precomp layers' clip rectangle).
    pub w: Option<P::Size>,
    /// Height.
    pub h: Option<P::Size>,
    /// `td`: this layer is the track matte of another.
    pub td: bool,
    /// `tt`: the track matte mode (1 alpha, 2 inverted alpha, 3 luma, 4 inverted luma).
    pub tt: Option<i64>,
    /// `tp`: the matte layer's `ind` (newer files; older ones use the layer above).
    pub tp: Option<P::Index>,
    /// Layer masks (`masksProperties`), in order.
    pub masks: Vec<P::Mask>,
    /// Effects (`ef`), in order.
    pub effects: Vec<P::Effect>,
    /// What only a written layer holds.
    pub written: P::Written,
    /// Where it is.
    pub at: Loc,
    /// Time stretch.
    pub sr: f64,
    /// Solid colour (`sc`, `#rrggbb`).
    pub solid_color: Option<String>,
    /// Solid width.
    pub sw: Option<f64>,
    /// Solid height.
    pub sh: Option<f64>,
    /// Time remap (precomp layers), in seconds.
    pub tm: Option<Num>,
    /// `hd`: hidden.
    pub hidden: bool,
    /// Text layers' text (`t`).
    pub text: Option<TextData>,
}

/// An After Effects effect on a layer: its type and its parameters' values by position
/// (those that are not numbers, such as layer references, are `None`).
#[derive(Clone, Debug)]
pub struct LayerEffect {
    /// Where it is.
    pub at: Loc,
    /// `ty`: 25 drop shadow, 29 Gaussian blur, 5 expression controls, ….
    pub ty: i64,
    /// Display name (`nm`).
    pub nm: String,
    /// `en`: enabled (a disabled effect draws nothing).
    pub enabled: bool,
    /// The parameters' `v`.
    pub values: Vec<Option<Num>>,
}

impl LayerEffect {
    fn read(v: &Value, at: &Loc) -> Result<LayerEffect> {
        let o = object(v, at)?;
        let values = match o.get("ef").and_then(Value::as_array) {
            Some(params) => params
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let p_at = at.key("ef").idx(i);
                    // A parameter this model cannot read is not an error: only blurs and
                    // drop shadows are drawn, and they are checked where they are.
                    p.get("v").and_then(|v| property(v, &p_at.key("v")).ok())
                })
                .collect(),
            None => Vec::new(),
        };
        Ok(LayerEffect {
            at: at.clone(),
            ty: opt_int(o, "ty", at)?.unwrap_or(-1),
            nm: opt_string(o, "nm", at)?.unwrap_or_default(),
            enabled: opt_int(o, "en", at)?.unwrap_or(1) != 0,
            values,
        })
    }

    /// Parameter `i` at `t` (`default` when absent).
    pub fn value(&self, i: usize, t: f64, default: &[f64]) -> Vec<f64> {
        crate::eval::num(self.values.get(i).and_then(Option::as_ref), t, default)
    }
}

/// A layer mask: an outline in the layer's space that adds to, subtracts from or
/// intersects with what the layer shows. Generic like [`Transform`] over how its numbers
/// (`P`) and its outline (`S`) are held (as written, the exporter's property for both);
/// written as `mode`, `pt`, `o`, `x`, `inv`.
#[derive(Clone, Debug, Serialize)]
#[serde(bound(serialize = "P: Serialize, S: Serialize"))]
pub struct LayerMask<P = Num, S = Property<Bezier>> {
    /// Where it is (read masks only).
    #[serde(skip)]
    pub at: Loc,
    /// `mode`: `a` add, `s` subtract, `i` intersect, `l` lighten, `d` darken, `f`
    /// difference, `n` none.
    pub mode: String,
    /// The outline (`pt`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pt: Option<S>,
    /// Opacity, percent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub o: Option<P>,
    /// Expansion (`x`), in pixels (lottie-web requires the property).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub x: Option<P>,
    /// `inv`: the outline's outside counts.
    #[serde(rename = "inv")]
    pub inverted: bool,
}

impl LayerMask {
    fn read(v: &Value, at: &Loc) -> Result<LayerMask> {
        let o = object(v, at)?;
        Ok(LayerMask {
            at: at.clone(),
            mode: opt_string(o, "mode", at)?.unwrap_or_else(|| "a".into()),
            pt: match o.get("pt") {
                Some(pt) => Some(property(pt, &at.key("pt"))?),
                None => None,
            },
            o: opt_property(o, "o", at)?,
            x: opt_property(o, "x", at)?,
            inverted: o.get("inv").and_then(Value::as_bool).unwrap_or(false),
        })
    }
}

/// Reads the layer `v`, which is at `at`.
pub(crate) fn read_layer(v: &Value, at: &Loc) -> Result<Layer> {
    let o = object(v, at)?;
    let ty = match opt_int(o, "ty", at)? {
        Some(ty) => ty,
        None => return error(at, "a layer needs its type `ty`"),
    };
    let kind = LayerKind::of(ty);
    let sr = opt_number(o, "sr", at)?.unwrap_or(1.0);
    if sr <= 0.0 {
        return error(&at.key("sr"), "the time stretch `sr` must be positive");
    }
    let mut ks = match o.get("ks") {
        Some(ks) => Transform::read(ks, &at.key("ks"))?,
        None => Transform::default(),
    };
    ks.auto_orient = flag(o, "ao", at)?;
    let shapes = match (kind, o.get("shapes")) {
        (LayerKind::Shape, Some(s)) => shape_items(s, &at.key("shapes"))?,
        _ => Vec::new(),
    };
    Ok(Layer {
        at: at.clone(),
        kind,
        nm: opt_string(o, "nm", at)?.unwrap_or_default(),
        ind: opt_int(o, "ind", at)?,
        parent: opt_int(o, "parent", at)?,
        ip: opt_number(o, "ip", at)?.unwrap_or(0.0),
        op: opt_number(o, "op", at)?.unwrap_or(f64::MAX),
        st: opt_number(o, "st", at)?.unwrap_or(0.0),
        sr,
        ks,
        shapes,
        ref_id: opt_string(o, "refId", at)?,
        w: opt_number(o, "w", at)?,
        h: opt_number(o, "h", at)?,
        solid_color: opt_string(o, "sc", at)?,
        sw: opt_number(o, "sw", at)?,
        sh: opt_number(o, "sh", at)?,
        tm: opt_property(o, "tm", at)?,
        td: flag(o, "td", at)?,
        tt: opt_int(o, "tt", at)?,
        tp: opt_int(o, "tp", at)?,
        hidden: o.get("hd").and_then(Value::as_bool).unwrap_or(false),
        masks: match o.get("masksProperties") {
            Some(m) => {
                let m_at = at.key("masksProperties");
                array(m, &m_at)?
                    .iter()
                    .enumerate()
                    .map(|(i, v)| LayerMask::read(v, &m_at.idx(i)))
                    .collect::<Result<_>>()?
            }
            None => Vec::new(),
        },
        text: match (kind, o.get("t")) {
            (LayerKind::Text, Some(t)) if !t.is_null() => Some(TextData::read(t, &at.key("t"))?),
            _ => None,
        },
        effects: match o.get("ef") {
            Some(ef) if !ef.is_null() => {
                let ef_at = at.key("ef");
                array(ef, &ef_at)?
                    .iter()
                    .enumerate()
                    .map(|(i, v)| LayerEffect::read(v, &ef_at.idx(i)))
                    .collect::<Result<_>>()?
            }
            _ => Vec::new(),
        },
        written: (),
    })
}

fn read_layers(v: &Value, at: &Loc) -> Result<Vec<Layer>> {
    array(v, at)?
        .iter()
        .enumerate()
        .map(|(i, l)| read_layer(l, &at.idx(i)))
        .collect()
}

/// An asset: a precomposition (with layers) or an image.
#[derive(Clone, Debug)]
pub struct Asset {
    /// Where it is.
    pub at: Loc,
    /// Its id (`refId` of the layers that use it).
    pub id: String,
    /// A precomposition's layers.
    pub layers: Option<Vec<Layer>>,
    /// Width (images).
    pub w: Option<f64>,
    /// Height (images).
    pub h: Option<f64>,
    /// The picture (images): a file name, or the image itself as a `data:` URL.
    pub p: Option<String>,
    /// The folder of a linked picture (`u`, ending in `/`), relative to the document's.
    pub u: Option<String>,
    /// The picture's bytes, once the importer has read them (embedded or linked), or why
    /// it could not.
    pub image: std::result::Result<Option<crate::build::Picture>, String>,
    /// The pixel size an embedded image declares when it is over the importer's limit
    /// (`gmotion-import-lottie`'s `ImportOptions::max_image_pixels`); such an image is not drawn.
    pub oversized: Option<(u64, u64)>,
}

/// The document's animation.
#[derive(Clone, Debug)]
pub struct Document {
    /// The Bodymovin version that wrote it (`v`).
    pub version: Option<String>,
    /// Frame rate.
    pub fr: f64,
    /// First frame.
    pub ip: f64,
    /// The frame after the last one.
    pub op: f64,
    /// Width.
    pub w: f64,
    /// Height.
    pub h: f64,
    /// The root composition's layers, topmost first.
    pub layers: Vec<Layer>,
    /// Assets.
    pub assets: Vec<Asset>,
    /// Fonts and embedded glyphs, for text layers.
    pub fonts: Fonts,
    /// Root layers split into one unit per top-level group whatever the units are: text
    /// layers cut into pieces and written as shapes ([`crate::Source::cut`]).
    pub split: Vec<usize>,
}

impl Document {
    /// Reads the model of a parsed document.
    pub fn read(v: &Value) -> Result<Document> {
        let at = Loc::root();
        let o = object(v, &at)?;
        let need = |key: &str| -> Result<f64> {
            match opt_number(o, key, &at)? {
                Some(x) => Ok(x),
                None => error(&at, format!("a Lottie animation needs `{key}`")),
            }
        };
        let fr = need("fr")?;
        let (ip, op, w, h) = (need("ip")?, need("op")?, need("w")?, need("h")?);
        if fr <= 0.0 {
            return error(&at.key("fr"), "the frame rate `fr` must be positive");
        }
        if op <= ip {
            return error(
                &at.key("op"),
                format!("the out point `op` ({op}) must come after the in point `ip` ({ip})"),
            );
        }
        if w <= 0.0 || h <= 0.0 {
            return error(&at, format!("the size {w}×{h} must be positive"));
        }
        let layers = match o.get("layers") {
            Some(l) => read_layers(l, &at.key("layers"))?,
            None => return error(&at, "a Lottie animation needs `layers`"),
        };
        let mut assets = Vec::new();
        if let Some(a) = o.get("assets") {
            let a_at = at.key("assets");
            for (i, asset) in array(a, &a_at)?.iter().enumerate() {
                let at = a_at.idx(i);
                let ao = object(asset, &at)?;
                assets.push(Asset {
                    id: opt_string(ao, "id", &at)?.unwrap_or_default(),
                    layers: match ao.get("layers") {
                        Some(l) => Some(read_layers(l, &at.key("layers"))?),
                        None => None,
                    },
                    w: opt_number(ao, "w", &at)?,
                    h: opt_number(ao, "h", &at)?,
                    p: opt_string(ao, "p", &at)?,
                    u: opt_string(ao, "u", &at)?,
                    image: Ok(None),
                    oversized: None,
                    at,
                });
            }
        }
        Ok(Document {
            version: match o.get("v") {
                Some(Value::String(s)) => Some(s.clone()),
                _ => None,
            },
            fr,
            ip,
            op,
            w,
            h,
            layers,
            assets,
            fonts: Fonts::read(o, &at)?,
            split: Vec::new(),
        })
    }

    /// Whether the file predates Bodymovin `major.minor.patch`.
    pub fn older_than(&self, version: (u32, u32, u32)) -> bool {
        let Some(v) = &self.version else {
            return false;
        };
        let mut parts = v.split('.').map(|p| p.trim().parse::<u32>().unwrap_or(0));
        let found = (
            parts.next().unwrap_or(0),
            parts.next().unwrap_or(0),
            parts.next().unwrap_or(0),
        );
        found < version
    }
}
