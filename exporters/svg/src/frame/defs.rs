//! Paint servers, clip paths and masks as `<defs>` entries: each written once per variant,
//! in the order first referenced, under an id that collides with nothing else written.

use std::collections::VecDeque;

use foldhash::{HashMap, HashSet};
use std::fmt::Write;

use kurbo::{Affine, Rect, Vec2};

use super::number::{attr_num, attr_transform, escaped, hex, num};
use super::{Ctx, Writer};
use gmotion::motion::Tint;
use gmotion::scene::{
    ClipPath, Effect, FillRule, Filter, Group, LinearGradient, Mask, MaskKind, Node, Pattern,
    RadialGradient, Spread, Stop,
};

/// One `<defs>` entry: a scene object and the variant of it a reference needs.
#[derive(Clone, Copy)]
pub(super) enum Def<'a> {
    /// A gradient with its stops tinted.
    Linear(&'a LinearGradient, Tint),
    /// A gradient with its stops tinted.
    Radial(&'a RadialGradient, Tint),
    /// A pattern with every colour of its content tinted.
    Pattern(&'a Pattern, Tint),
    /// A clip path seen from a coordinate system `extra` away from where it was defined
    /// (clip content is written flat, see [`Writer::clip_content`]).
    Clip(&'a ClipPath, Affine),
    /// A mask.
    Mask(&'a Mask),
    /// A filter drawing in a region (see [`Group::filter_region`]).
    Filter(&'a Filter, Rect),
}

#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Key {
    ptr: usize,
    kind: u8,
    variant: [u64; 6],
}

fn tint_bits(t: Tint) -> [u64; 6] {
    let [r, g, b] = t.sum.map(|v| v.to_bits() as u64);
    [r, g, b, t.weight.to_bits() as u64, 0, 0]
}

impl Def<'_> {
    fn key(&self) -> Key {
        let (ptr, kind, variant) = match *self {
            Def::Linear(g, t) => (g as *const _ as usize, 0, tint_bits(t)),
            Def::Radial(g, t) => (g as *const _ as usize, 1, tint_bits(t)),
            Def::Pattern(p, t) => (p as *const _ as usize, 2, tint_bits(t)),
            Def::Clip(c, ts) => (c as *const _ as usize, 3, ts.as_coeffs().map(f64::to_bits)),
            Def::Mask(m) => (m as *const _ as usize, 4, [0; 6]),
            Def::Filter(f, r) => {
                let [a, b, c, d] = [r.x0, r.y0, r.x1, r.y1].map(f64::to_bits);
                (f as *const _ as usize, 5, [a, b, c, d, 0, 0])
            }
        };
        Key { ptr, kind, variant }
    }

    /// The scene's own id and a fallback prefix.
    fn names(&self) -> (&str, &'static str) {
        match self {
            Def::Linear(g, _) => (&g.id, "lg"),
            Def::Radial(g, _) => (&g.id, "rg"),
            Def::Pattern(p, _) => (&p.id, "pat"),
            Def::Clip(c, _) => (&c.id, "clip"),
            Def::Mask(m) => (&m.id, "mask"),
            Def::Filter(f, _) => (&f.id, "filter"),
        }
    }

    /// Whether this is the object as defined (not a tinted or moved variant).
    fn is_original(&self) -> bool {
        match *self {
            Def::Linear(_, t) | Def::Radial(_, t) | Def::Pattern(_, t) => t == Tint::NONE,
            Def::Clip(_, ts) => ts == Affine::IDENTITY,
            Def::Mask(_) => true,
            Def::Filter(f, r) => f.region == r,
        }
    }
}

/// Readable, collision-free names for the static scene document.
pub(super) struct Names {
    /// Node ids written in the document and names handed out so far.
    taken: HashSet<String>,
    list: Vec<String>,
}

impl Names {
    pub(super) fn new(node_ids: HashSet<String>) -> Names {
        Names {
            taken: node_ids,
            list: Vec::new(),
        }
    }
}

/// The entries referenced so far and those still to write.
#[derive(Default)]
pub(super) struct Defs<'a> {
    index: HashMap<Key, usize>,
    pending: VecDeque<(usize, Def<'a>)>,
    /// `None` for frames, whose entries are simply numbered after [`Self::prefix`] (frames
    /// write no node ids).
    names: Option<Names>,
    /// What a frame's entry names start with: `d` (`d0`, `d1`, …) unless frames sharing one
    /// document need names of their own.
    prefix: String,
}

impl<'a> Defs<'a> {
    /// A frame's entries, named `{prefix}0`, `{prefix}1`, ….
    pub(super) fn numbered(prefix: &str) -> Defs<'a> {
        Defs {
            prefix: prefix.to_string(),
            ..Defs::default()
        }
    }

    pub(super) fn with_names(names: Names) -> Defs<'a> {
        Defs {
            names: Some(names),
            ..Defs::default()
        }
    }

    /// The number of `def`, queueing it for writing on first use.
    fn intern(&mut self, def: Def<'a>) -> usize {
        let key = def.key();
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        let i = self.index.len();
        self.index.insert(key, i);
        if let Some(names) = &mut self.names {
            let (own, prefix) = def.names();
            let mut name = if def.is_original() && !own.is_empty() {
                own.to_string()
            } else {
                format!("{prefix}{i}")
            };
            while names.taken.contains(&name) {
                name.push('_');
            }
            names.taken.insert(name.clone());
            names.list.push(name);
        }
        self.pending.push_back((i, def));
        i
    }

    fn write_name(&self, out: &mut String, i: usize) {
        match &self.names {
            Some(n) => escaped(out, &n.list[i]),
            None => {
                let _ = write!(out, "{}{i}", self.prefix);
            }
        }
    }
}

impl<'a> Writer<'a> {
    /// Appends ` attr="url(#…)"` for `def`.
    pub(super) fn url(&mut self, attr: &str, def: Def<'a>) {
        let i = self.defs.intern(def);
        self.out.push(' ');
        self.out.push_str(attr);
        self.out.push_str("=\"url(#");
        self.defs.write_name(&mut self.out, i);
        self.out.push_str(")\"");
    }

    /// Writes every queued entry, including those the entries themselves reference.
    pub(super) fn write_defs(&mut self) {
        while let Some((i, def)) = self.defs.pending.pop_front() {
            match def {
                Def::Linear(g, tint) => {
                    self.def_open("linearGradient", i);
                    self.out.push_str(" gradientUnits=\"userSpaceOnUse\"");
                    attr_num(&mut self.out, "x1", g.start.x);
                    attr_num(&mut self.out, "y1", g.start.y);
                    attr_num(&mut self.out, "x2", g.end.x);
                    attr_num(&mut self.out, "y2", g.end.y);
                    self.gradient_body(g.transform, g.spread, &g.stops, tint);
                    self.out.push_str("</linearGradient>\n");
                }
                Def::Radial(g, tint) => {
                    self.def_open("radialGradient", i);
                    self.out.push_str(" gradientUnits=\"userSpaceOnUse\"");
                    attr_num(&mut self.out, "cx", g.center.x);
                    attr_num(&mut self.out, "cy", g.center.y);
                    attr_num(&mut self.out, "r", g.radius);
                    attr_num(&mut self.out, "fx", g.focal.x);
                    attr_num(&mut self.out, "fy", g.focal.y);
                    if g.focal_radius != 0.0 {
                        attr_num(&mut self.out, "fr", g.focal_radius);
                    }
                    self.gradient_body(g.transform, g.spread, &g.stops, tint);
                    self.out.push_str("</radialGradient>\n");
                }
                Def::Pattern(p, tint) => {
                    self.def_open("pattern", i);
                    self.out.push_str(" patternUnits=\"userSpaceOnUse\"");
                    self.rect_attrs(p.rect);
                    attr_transform(&mut self.out, "patternTransform", p.transform);
                    self.out.push_str(">\n");
                    let ctx = Ctx {
                        fill: tint,
                        stroke: tint,
                        ..Ctx::REST
                    };
                    self.group_content(&p.root, ctx);
                    self.out.push_str("</pattern>\n");
                }
                Def::Clip(c, extra) => {
                    self.def_open("clipPath", i);
                    attr_transform(&mut self.out, "transform", extra * c.transform);
                    if let Some(inner) = &c.clip_path {
                        self.url("clip-path", Def::Clip(inner, extra));
                    }
                    self.out.push_str(">\n");
                    let root = &c.root;
                    let nested = root.clip_path.as_deref().map(|n| (n, root.transform));
                    self.clip_content(root, root.transform, nested);
                    self.out.push_str("</clipPath>\n");
                }
                Def::Mask(m) => {
                    self.def_open("mask", i);
                    self.out.push_str(" maskUnits=\"userSpaceOnUse\"");
                    self.rect_attrs(m.rect);
                    if m.kind == MaskKind::Alpha {
                        self.out.push_str(" mask-type=\"alpha\"");
                    }
                    if let Some(inner) = &m.mask {
                        self.url("mask", Def::Mask(inner));
                    }
                    self.out.push_str(">\n");
                    self.group_content(&m.root, Ctx::REST);
                    self.out.push_str("</mask>\n");
                }
                Def::Filter(f, region) => self.filter(i, f, region),
            }
        }
    }

    /// A filter of blurs and drop shadows, each primitive reading the one before.
    fn filter(&mut self, i: usize, f: &Filter, region: Rect) {
        self.def_open("filter", i);
        self.out.push_str(" filterUnits=\"userSpaceOnUse\"");
        self.rect_attrs(region);
        if !f.linear_rgb {
            self.out.push_str(" color-interpolation-filters=\"sRGB\"");
        }
        self.out.push_str(">\n");
        let std_dev = |out: &mut String, s: Vec2| {
            out.push_str(" stdDeviation=\"");
            num(out, s.x);
            out.push(' ');
            num(out, s.y);
            out.push('"');
        };
        for e in &f.effects {
            match *e {
                Effect::Blur(s) => {
                    self.out.push_str("<feGaussianBlur");
                    std_dev(&mut self.out, s);
                }
                Effect::DropShadow {
                    offset,
                    std_dev: s,
                    color,
                } => {
                    self.out.push_str("<feDropShadow");
                    attr_num(&mut self.out, "dx", offset.x);
                    attr_num(&mut self.out, "dy", offset.y);
                    std_dev(&mut self.out, s);
                    self.out.push_str(" flood-color=\"");
                    hex(&mut self.out, color);
                    self.out.push('"');
                    if color.a != 1.0 {
                        attr_num(&mut self.out, "flood-opacity", color.a.into());
                    }
                }
            }
            self.out.push_str("/>\n");
        }
        self.out.push_str("</filter>\n");
    }

    fn def_open(&mut self, element: &str, i: usize) {
        self.out.push('<');
        self.out.push_str(element);
        self.out.push_str(" id=\"");
        self.defs.write_name(&mut self.out, i);
        self.out.push('"');
    }

    fn rect_attrs(&mut self, r: kurbo::Rect) {
        attr_num(&mut self.out, "x", r.x0);
        attr_num(&mut self.out, "y", r.y0);
        attr_num(&mut self.out, "width", r.width());
        attr_num(&mut self.out, "height", r.height());
    }

    fn gradient_body(&mut self, ts: Affine, spread: Spread, stops: &[Stop], tint: Tint) {
        attr_transform(&mut self.out, "gradientTransform", ts);
        match spread {
            Spread::Pad => {}
            Spread::Reflect => self.out.push_str(" spreadMethod=\"reflect\""),
            Spread::Repeat => self.out.push_str(" spreadMethod=\"repeat\""),
        }
        self.out.push_str(">\n");
        for s in stops {
            self.out.push_str("<stop");
            attr_num(&mut self.out, "offset", s.offset as f64);
            self.out.push_str(" stop-color=\"");
            hex(&mut self.out, tint.apply(s.color));
            self.out.push('"');
            if s.color.a != 1.0 {
                attr_num(&mut self.out, "stop-opacity", s.color.a as f64);
            }
            self.out.push_str("/>\n");
        }
    }

    /// Writes the paths of clip content flat, each with its transform relative to the
    /// `clipPath` (SVG allows no groups there). `nested` is the innermost group clip path
    /// on the way, with the transform of the group that set it; the path refers to a
    /// variant of that clip moved from the group's coordinates into the path's own.
    fn clip_content(&mut self, g: &'a Group, ts: Affine, nested: Option<(&'a ClipPath, Affine)>) {
        for child in &g.children {
            match child {
                Node::Group(h) => {
                    let ts = ts * h.transform;
                    let nested = h.clip_path.as_deref().map(|c| (c, ts)).or(nested);
                    self.clip_content(h, ts, nested);
                }
                Node::Path(p) => {
                    self.out.push_str("<path");
                    attr_transform(&mut self.out, "transform", ts);
                    self.out.push_str(" d=\"");
                    self.path_data(&p.path, None);
                    self.out.push('"');
                    match &p.fill {
                        None => self.out.push_str(" fill=\"none\""),
                        Some(f) if f.rule == FillRule::EvenOdd => {
                            self.out.push_str(" clip-rule=\"evenodd\"")
                        }
                        Some(_) => {}
                    }
                    if let Some((c, at)) = nested {
                        self.url("clip-path", Def::Clip(c, super::inverse(ts) * at));
                    }
                    self.out.push_str("/>\n");
                }
                // SVG clips with shapes only; the importer puts no images in clip paths.
                Node::Image(_) => {}
            }
        }
    }
}
