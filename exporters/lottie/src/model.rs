//! The subset of the Lottie JSON format gmotion writes, as serde structures.
//!
//! Field names follow the format (two-letter keys); the official schema
//! (`lottie_specs/data/lottie.schema.json`) is what the conformance run validates against.
//! Numbers are rounded where they are made ([`N::coord`], [`N::fine`]) and written without
//! a fraction when integral, so output is compact and identical from run to run; the
//! number, the Bézier outline and the properties and keyframes ([`gmotion_lottie::written`])
//! are `gmotion-lottie`'s, shared with the importer.

use gmotion::engine::markers::Marker;
use serde::Serialize;

use std::io::{self, Write};

use gmotion_lottie::model::LayerParts;
pub use gmotion_lottie::model::{Bezier, Dash, LayerKind};
pub use gmotion_lottie::number::N;
pub use gmotion_lottie::written::{Easing, Keyframe, LINEAR, Prop, Value, from_css};

/// The top-level animation.
#[derive(Clone, Debug)]
pub struct Animation {
    /// Format version the file targets (Bodymovin numbering, read by every player).
    pub v: &'static str,
    /// Frame rate.
    pub fr: N,
    /// First frame.
    pub ip: N,
    /// Frame after the last one.
    pub op: N,
    /// Width in pixels.
    pub w: u32,
    /// Height in pixels.
    pub h: u32,
    /// Name.
    pub nm: String,
    /// Named spans (not written when empty).
    pub markers: Vec<MarkerOut>,
    /// Precompositions referenced by precomp layers (not written when empty).
    pub assets: Vec<Asset>,
    /// Layers, topmost first.
    pub layers: Vec<Layer>,
}

impl Animation {
    /// Writes the document as JSON to `out`, its layers a run of [`LAYERS_PER_WRITE`] at a
    /// time ([`write_layers`]), each run freed before the next is written. The whole text
    /// is never held: for 999 000 shapes it was 856 MB.
    pub fn write_to(mut self, out: &mut dyn Write) -> io::Result<()> {
        let mut layers = std::mem::take(&mut self.layers).into_iter();
        self.write_with(out, |out| {
            let mut written = 0;
            loop {
                let run: Vec<Layer> = layers.by_ref().take(LAYERS_PER_WRITE).collect();
                if run.is_empty() {
                    return Ok(());
                }
                written = write_layers(out, written, run)?;
            }
        })
    }

    /// Writes the document as JSON to `out` with the layers `layers` writes (with
    /// [`write_layers`]) in place of its own, which are left out: how a large scene's
    /// layers are written as they are built ([`crate::layers::Builder::write_root`]).
    pub(crate) fn write_with(
        &self,
        out: &mut dyn Write,
        layers: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> io::Result<()> {
        out.write_all(&self.head())?;
        layers(out)?;
        out.write_all(b"]}")
    }

    /// The document's text up to its first layer.
    fn head(&self) -> Vec<u8> {
        let mut head = Vec::new();
        head.extend_from_slice(b"{\"v\":");
        json(&mut head, &self.v);
        for (key, n) in [("fr", self.fr), ("ip", self.ip), ("op", self.op)] {
            field(&mut head, key, &n);
        }
        field(&mut head, "w", &self.w);
        field(&mut head, "h", &self.h);
        field(&mut head, "nm", &self.nm);
        if !self.markers.is_empty() {
            field(&mut head, "markers", &self.markers);
        }
        if !self.assets.is_empty() {
            head.extend_from_slice(b",\"assets\":[");
            for (k, a) in self.assets.iter().enumerate() {
                if k > 0 {
                    head.push(b',');
                }
                a.write_json(&mut head);
            }
            head.push(b']');
        }
        head.extend_from_slice(b",\"layers\":[");
        head
    }
}

/// How many layers [`Animation::write_to`] writes at a time: enough to keep every thread
/// busy and make few system calls, few enough that a run's text stays a few megabytes.
const LAYERS_PER_WRITE: usize = 4096;

/// Writes `run`, the layers of the document's list after the `written` already written,
/// to `out`: each layer in parallel to its own buffer and dropped there (at the
/// intersections scale, 8214 layers, one thread writing into one doubling string, then
/// freeing the model, was a fifth of the export), then handed to `out` and freed. Returns
/// the layers written so far.
pub(crate) fn write_layers(
    mut out: &mut dyn Write,
    written: usize,
    run: Vec<Layer>,
) -> io::Result<usize> {
    use rayon::prelude::*;
    let n = run.len();
    let pieces: Vec<[Vec<u8>; 2]> = run
        .into_par_iter()
        .enumerate()
        .map(|(k, l)| layer_pieces((written + k, l)))
        .collect();
    gmotion::atomic::write_pieces(
        &mut out,
        pieces
            .iter()
            .flatten()
            .filter(|p| !p.is_empty())
            .map(Vec::as_slice),
    )?;
    Ok(written + n)
}

/// The `k`th layer's text (a comma before all but the first), in two pieces: its head,
/// and its sealed tail, which is most of its text and is passed on rather than copied
/// after the few fields before it (empty when the layer was not sealed).
fn layer_pieces((k, mut l): (usize, Layer)) -> [Vec<u8>; 2] {
    let tail = l.written.sealed.take();
    let head = exact(|out| {
        if k > 0 {
            out.push(b',');
        }
        write_head(&l, out);
        if tail.is_none() {
            write_tail(&l, out);
        }
    });
    [head, tail.map_or_else(Vec::new, Vec::from)]
}

/// A marker as Lottie writes it: a named span in frames, its name in `cm` (what lottie-web's
/// `goToAndPlay(name, true)` and dotlottie-web's `setMarker(name)` look up).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MarkerOut {
    /// The start frame.
    pub tm: N,
    /// The name.
    pub cm: String,
    /// The length in frames.
    pub dr: N,
}

impl MarkerOut {
    /// `m` in the frames of a composition starting at frame `ip`, `fps` frames a second.
    pub fn of(m: &Marker, ip: f64, fps: f64) -> MarkerOut {
        MarkerOut {
            tm: N::coord(ip + m.start * fps),
            cm: m.name.clone(),
            dr: N::coord((m.end - m.start) * fps),
        }
    }
}

/// What `write` writes, in a vector of exactly its size. It writes into this thread's
/// reused buffer, then copies out once: a fresh vector per layer grew by doubling, each
/// step a reallocation and a copy of fresh memory (a tenth of a large export's time was
/// `realloc`).
fn exact(write: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    thread_local! {
        static SCRATCH: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    SCRATCH.with_borrow_mut(|out| {
        out.clear();
        write(out);
        let exact = out.to_vec();
        // One huge layer should not keep its size in every thread for the process's life.
        if out.capacity() > SCRATCH_KEPT {
            *out = Vec::new();
        }
        exact
    })
}

/// The most a thread's [`exact`] buffer keeps between layers, in bytes.
const SCRATCH_KEPT: usize = 1 << 20;

/// Appends `v` as JSON (serde_json's spelling, which the model's types define).
fn json<T: Serialize + ?Sized>(out: &mut Vec<u8>, v: &T) {
    serde_json::to_writer(out, v).expect("the Lottie model serialises to JSON");
}

/// Appends `,"key":v`.
fn field<T: Serialize + ?Sized>(out: &mut Vec<u8>, key: &str, v: &T) {
    out.extend_from_slice(b",\"");
    out.extend_from_slice(key.as_bytes());
    out.extend_from_slice(b"\":");
    json(out, v);
}

/// An asset: a precomposition, or an embedded image.
#[derive(Clone, Debug)]
pub struct Asset {
    /// Asset id (referenced by `refId`).
    pub id: String,
    /// Layers, topmost first (a precomposition's; empty for an image).
    pub layers: Vec<Layer>,
    /// The picture, for an image asset.
    pub image: Option<ImageAsset>,
}

/// An image asset's picture, embedded (`e: 1`) so the document stands alone.
#[derive(Clone, Debug)]
pub struct ImageAsset {
    /// Width in pixels: an image layer draws the picture this wide.
    pub w: u32,
    /// Height in pixels.
    pub h: u32,
    /// The picture as a `data:` URL.
    pub p: String,
}

impl Asset {
    fn write_json(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(b"{\"id\":");
        json(out, &self.id);
        if let Some(img) = &self.image {
            field(out, "w", &img.w);
            field(out, "h", &img.h);
            field(out, "u", "");
            field(out, "p", &img.p);
            field(out, "e", &1);
            out.push(b'}');
            return;
        }
        out.extend_from_slice(b",\"layers\":[");
        for (k, l) in self.layers.iter().enumerate() {
            if k > 0 {
                out.push(b',');
            }
            l.write_json(out);
        }
        out.extend_from_slice(b"]}");
    }
}

/// A layer as the exporter writes it: `gmotion-lottie`'s, holding the exporter's numbers,
/// properties, shapes, masks and effects ([`Export`]).
pub type Layer = gmotion_lottie::model::Layer<Export>;

/// How the exporter holds a [`Layer`]: indices and sizes as whole numbers, times as
/// written numbers, its own shapes (`None`: not a shape layer), masks and effects.
#[derive(Clone, Copy, Debug)]
pub struct Export;

impl LayerParts for Export {
    type Ind = u32;
    type Index = u32;
    type Time = N;
    type Size = u32;
    type Prop = Prop;
    type Position = Prop;
    type Shapes = Option<Vec<Shape>>;
    type Mask = Mask;
    type Effect = LayerEffect;
    type Written = Written;
}

/// What only a written layer holds.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Whether `masksProperties` is set (lottie-web reads this flag).
    pub has_mask: Option<bool>,
    /// The JSON of the fields from `masksProperties` on, when written early by
    /// [`WriteLayer::seal`]; those fields are then empty and no longer read.
    pub sealed: Option<Box<[u8]>>,
    /// The opacity slot this layer's unit carries (see [`crate::slots`]): its id, and
    /// whether it sits on the layer's first group's transform rather than the layer's.
    pub slot: Option<(String, bool)>,
}

/// Making and writing a [`Layer`] (a trait, the layer being `gmotion-lottie`'s).
pub trait WriteLayer {
    /// A layer of type `kind` visible from `ip` to `op`, untransformed.
    fn new(kind: LayerKind, nm: String, ind: u32, ip: f64, op: f64) -> Self;

    /// Writes the fields from `masksProperties` on (the masks, transform and shapes: all
    /// but the few that numbering and parenting change later) and frees them. Built in
    /// parallel and sealed on the thread that built it, a layer's shape tree is freed while
    /// that thread's memory is warm, instead of living on until the whole document is
    /// written: at the intersections scale that tree was ~200 MB of fresh pages.
    fn seal(&mut self);

    /// Writes the layer as a JSON object, keys in the format's usual order, absent
    /// options left out.
    fn write_json(&self, out: &mut Vec<u8>);
}

impl WriteLayer for Layer {
    fn new(kind: LayerKind, nm: String, ind: u32, ip: f64, op: f64) -> Layer {
        Layer {
            kind,
            nm,
            ind,
            parent: None,
            ip: N::coord(ip),
            op: N::coord(op),
            st: N(0.0),
            ks: layer_identity(),
            shapes: None,
            ref_id: None,
            w: None,
            h: None,
            td: false,
            tt: None,
            tp: None,
            masks: Vec::new(),
            effects: Vec::new(),
            written: Written::default(),
            // Read from documents only.
            at: Default::default(),
            sr: 1.0,
            solid_color: None,
            sw: None,
            sh: None,
            tm: None,
            hidden: false,
            text: None,
        }
    }

    fn seal(&mut self) {
        if self.written.sealed.is_some() {
            return;
        }
        let tail = exact(|out| write_tail(self, out)).into_boxed_slice();
        self.masks = Vec::new();
        self.ks = Transform::empty();
        self.effects = Vec::new();
        self.shapes = None;
        self.written.sealed = Some(tail);
    }

    fn write_json(&self, out: &mut Vec<u8>) {
        write_head(self, out);
        match &self.written.sealed {
            Some(tail) => out.extend_from_slice(tail),
            None => write_tail(self, out),
        }
    }
}

/// A layer's fields before `masksProperties`, from the opening brace.
fn write_head(l: &Layer, out: &mut Vec<u8>) {
    // rlottie ignores a layer's rotation unless `ddd` precedes the transform (measured:
    // a skewed image placed by a rotated null and a rotated image drew unrotated).
    // Image and null layers are the ones placed by a rotating `ks`.
    if matches!(l.kind, LayerKind::Image | LayerKind::Null) {
        out.extend_from_slice(b"{\"ddd\":0,\"ty\":");
    } else {
        out.extend_from_slice(b"{\"ty\":");
    }
    json(out, &l.kind);
    field(out, "nm", &l.nm);
    field(out, "ind", &l.ind);
    let number = |out: &mut Vec<u8>, key: &str, v: Option<u32>| {
        if let Some(v) = v {
            field(out, key, &v);
        }
    };
    number(out, "parent", l.parent);
    if let Some(id) = &l.ref_id {
        field(out, "refId", id);
    }
    number(out, "w", l.w);
    number(out, "h", l.h);
    if l.td {
        field(out, "td", &1);
    }
    if let Some(tt) = l.tt {
        field(out, "tt", &tt);
    }
    number(out, "tp", l.tp);
    if let Some(m) = l.written.has_mask {
        field(out, "hasMask", &m);
    }
    if let Some(slot) = &l.written.slot {
        field(out, crate::slots::MARK, slot);
    }
}

/// A layer's fields from `masksProperties` to the closing brace.
fn write_tail(l: &Layer, out: &mut Vec<u8>) {
    if !l.masks.is_empty() {
        field(out, "masksProperties", &l.masks);
    }
    field(out, "ks", &l.ks);
    if !l.effects.is_empty() {
        field(out, "ef", &l.effects);
    }
    if let Some(shapes) = &l.shapes {
        field(out, "shapes", shapes);
    }
    for (key, n) in [("ip", l.ip), ("op", l.op), ("st", l.st)] {
        field(out, key, &n);
    }
    // Blend mode: always normal.
    field(out, "bm", &0);
    out.push(b'}');
}

/// An After Effects effect on a layer (`ty` 25 drop shadow, 29 Gaussian blur): its
/// parameters in the order players read them.
#[derive(Clone, Debug, Serialize)]
pub struct LayerEffect {
    /// Effect type.
    pub ty: u8,
    /// Display name.
    pub nm: &'static str,
    /// After Effects match name.
    pub mn: &'static str,
    /// Index among the layer's effects, from 1.
    pub ix: usize,
    /// Enabled.
    pub en: u8,
    /// Number of properties.
    pub np: usize,
    /// The parameters.
    pub ef: Vec<EffectValue>,
}

/// One parameter of an effect.
#[derive(Clone, Debug, Serialize)]
pub struct EffectValue {
    /// Kind: 0 slider, 1 angle, 2 colour, 4 checkbox, 7 dropdown.
    pub ty: u8,
    /// Display name.
    pub nm: &'static str,
    /// After Effects match name.
    pub mn: String,
    /// Index within the effect, from 1.
    pub ix: usize,
    /// The value.
    pub v: Prop,
}

/// A layer mask as written (mode `a`, add): outline, opacity and expansion properties.
pub type Mask = gmotion_lottie::model::LayerMask<Prop, Prop>;

/// A transform as the exporter writes it: `T(p)·R(r)·S(s)·T(-a)` with opacity `o`, every
/// channel (the position too) a [`Prop`]; never skew (rlottie cannot draw it).
pub type Transform = gmotion_lottie::model::Transform<Prop, Prop>;

/// An identity layer transform with every channel written (some players have no defaults
/// for layer transforms).
pub fn layer_identity() -> Transform {
    Transform {
        a: Some(Prop::fixed(Value::Vec(vec![N(0.0), N(0.0)]))),
        p: Some(Prop::fixed(Value::Vec(vec![N(0.0), N(0.0)]))),
        s: Some(Prop::fixed(Value::Vec(vec![N(100.0), N(100.0)]))),
        r: Some(Prop::fixed(Value::Scalar(N(0.0)))),
        o: Some(Prop::fixed(Value::Scalar(N(100.0)))),
        ..Transform::empty()
    }
}

/// `t` with every value rounded as a coordinate ([`N::coord`]); a channel whose keys then
/// all hold one value becomes fixed. For levels computed at full precision, so that
/// composing them does not compound the rounding.
pub fn rounded(t: Transform) -> Transform {
    let round = |p: Option<Prop>| p.map(Prop::rounded);
    Transform {
        a: round(t.a),
        p: round(t.p),
        s: round(t.s),
        r: round(t.r),
        o: round(t.o),
        ..Transform::empty()
    }
}

/// A shape item.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "ty")]
pub enum Shape {
    /// A group.
    #[serde(rename = "gr")]
    Group(Group),
    /// A Bézier path.
    #[serde(rename = "sh")]
    Path(PathShape),
    /// A solid fill.
    #[serde(rename = "fl")]
    Fill(Fill),
    /// A solid stroke.
    #[serde(rename = "st")]
    Stroke(Stroke),
    /// A gradient fill (boxed, as is the gradient stroke: a shape is only as large as its
    /// largest kind, and these were several times the others; an export holds a few
    /// hundred thousand shapes).
    #[serde(rename = "gf")]
    GradientFill(Box<GradientFill>),
    /// A gradient stroke.
    #[serde(rename = "gs")]
    GradientStroke(Box<GradientStroke>),
    /// Trim paths: cuts the paths above it in its group to their visible part.
    #[serde(rename = "tm")]
    Trim(TrimPaths),
    /// The group's transform (last item of a group).
    #[serde(rename = "tr")]
    Transform(Transform),
}

/// A trim paths modifier.
#[derive(Clone, Debug, Serialize)]
pub struct TrimPaths {
    /// Start of the visible part, percent of each path's length.
    pub s: Prop,
    /// End of the visible part, percent.
    pub e: Prop,
    /// Offset along the path, degrees (360 a whole turn).
    pub o: Prop,
    /// How several paths are trimmed: 1 simultaneously (each on its own length), 2
    /// individually (one after another).
    pub m: u8,
}

/// A group of shapes.
#[derive(Clone, Debug, Serialize)]
pub struct Group {
    /// Name.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub nm: String,
    /// Items, topmost first, the transform last.
    pub it: Vec<Shape>,
}

/// A path item.
#[derive(Clone, Debug, Serialize)]
pub struct PathShape {
    /// The Bézier outline (static or keyframed).
    pub ks: Prop,
}

/// A solid fill.
#[derive(Clone, Debug, Serialize)]
pub struct Fill {
    /// Opacity in percent.
    pub o: Prop,
    /// Colour `[r, g, b]` in `0..=1`.
    pub c: Prop,
    /// Fill rule: 1 non-zero, 2 even-odd.
    pub r: u8,
    /// The colour's slot id, written as a mark [`crate::slots`] moves into `c`.
    #[serde(rename = "gmotion_sid", skip_serializing_if = "Option::is_none")]
    pub slot: Option<String>,
}

/// Caps, joins, miter limit and dashes of a solid or gradient stroke, as written.
pub type StrokeStyle = gmotion_lottie::model::StrokeStyle<Prop, N>;

/// A solid stroke.
#[derive(Clone, Debug, Serialize)]
pub struct Stroke {
    /// Opacity in percent.
    pub o: Prop,
    /// Colour.
    pub c: Prop,
    /// Width.
    pub w: Prop,
    /// Caps, joins, dashes.
    #[serde(flatten)]
    pub style: StrokeStyle,
    /// The colour's slot id, written as a mark [`crate::slots`] moves into `c`.
    #[serde(rename = "gmotion_sid", skip_serializing_if = "Option::is_none")]
    pub slot: Option<String>,
}

/// A gradient as the exporter writes it.
pub type Gradient = gmotion_lottie::model::Gradient<Prop>;

/// A gradient's stops as the exporter writes them.
pub type GradientStops = gmotion_lottie::model::GradientStops<Prop>;

/// A gradient fill.
#[derive(Clone, Debug, Serialize)]
pub struct GradientFill {
    /// Opacity in percent.
    pub o: Prop,
    /// Fill rule: 1 non-zero, 2 even-odd.
    pub r: u8,
    /// The gradient.
    #[serde(flatten)]
    pub grad: Gradient,
}

/// A gradient stroke.
#[derive(Clone, Debug, Serialize)]
pub struct GradientStroke {
    /// Opacity in percent.
    pub o: Prop,
    /// The gradient.
    #[serde(flatten)]
    pub grad: Gradient,
    /// Width.
    pub w: Prop,
    /// Caps, joins, dashes.
    #[serde(flatten)]
    pub style: StrokeStyle,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A document of `n` shape layers holding 0–3 transform shapes, some with a parent.
    fn document(n: u32) -> Animation {
        let layers = (0..n)
            .map(|i| {
                let mut l = Layer::new(LayerKind::Shape, format!("layer {i}"), i + 1, 0.0, 30.0);
                l.parent = (i % 3 == 2).then_some(1);
                l.shapes = Some(vec![Shape::Transform(Transform::empty()); i as usize % 4]);
                l
            })
            .collect();
        Animation {
            v: "5.7.0",
            fr: N(30.0),
            ip: N(0.0),
            op: N(30.0),
            w: 100,
            h: 80,
            nm: "doc".into(),
            markers: Vec::new(),
            assets: Vec::new(),
            layers,
        }
    }

    /// The document's text, as [`Animation::write_to`] writes it.
    fn text(doc: Animation) -> String {
        let mut out = Vec::new();
        doc.write_to(&mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// Sealing writes a layer's tail early and the document passes it on as a piece of
    /// its own: the text must be the same whichever layers were sealed, and valid JSON.
    #[test]
    fn sealed_layers_write_the_same_document() {
        let whole = text(document(40));
        let parsed: serde_json::Value = serde_json::from_str(&whole).unwrap();
        assert_eq!(parsed["layers"].as_array().unwrap().len(), 40);
        assert_eq!(parsed["layers"][7]["shapes"].as_array().unwrap().len(), 3);
        for every in [1, 2, 5] {
            let mut doc = document(40);
            doc.layers.iter_mut().step_by(every).for_each(Layer::seal);
            assert!(doc.layers[0].written.sealed.is_some());
            assert_eq!(text(doc), whole, "every {every}th sealed");
        }
    }

    /// Layers written over several runs make one list, in order, each once.
    #[test]
    fn runs_of_layers_join_into_one_list() {
        let n = 2 * LAYERS_PER_WRITE as u32 + 1;
        let parsed: serde_json::Value = serde_json::from_str(&text(document(n))).unwrap();
        let names: Vec<&str> = parsed["layers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["nm"].as_str().unwrap())
            .collect();
        let want: Vec<String> = (0..n).map(|i| format!("layer {i}")).collect();
        assert_eq!(names, want);
    }

    #[test]
    fn shapes_are_tagged_by_ty() {
        let s = Shape::Transform(Transform::empty());
        assert_eq!(
            serde_json::to_string(&s).unwrap(),
            r#"{"ty":"tr","o":{"a":0,"k":100}}"#
        );
    }
}
