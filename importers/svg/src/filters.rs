//! SVG filters as scene effects.
//!
//! A filter is a little program of primitives, and the same two effects are written many
//! ways: a blur is one `feGaussianBlur`; a drop shadow is one `feDropShadow` (CSS
//! `drop-shadow()`), or Figma's flood, hard-alpha matrix, offset, blur, composite, tint
//! matrix and two blends, or Illustrator's and Inkscape's blur of `SourceAlpha`, offset,
//! flood, composite and merge. [`recognise`] runs the program on symbolic values (the
//! graphic with effects so far, a silhouette with its offset, blur and colour, a flood) and
//! answers the [`Effect`]s it amounts to, which every output can carry. Anything it cannot
//! follow is rasterised by [`bake`] instead.

use std::sync::Arc;

use gmotion::color::Color;
use gmotion::scene::{Effect, Filter, ImageFormat, ImageNode};
use kurbo::{Affine, Rect, Vec2};

use crate::convert::affine;
use usvg::filter::{self as uf, ColorInterpolation, Input, Kind};

/// What a primitive's result is.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    /// The source graphic with these effects applied.
    Drawn(Vec<Effect>),
    /// A silhouette of the graphic.
    Shadow(Shadow),
    /// One colour everywhere (nothing when its alpha is 0).
    Flood(Color),
}

/// The silhouette of the graphic drawn with `of`, moved, blurred (`variance` is the squared
/// standard deviation, which adds up over successive blurs) and coloured.
#[derive(Clone, Debug, PartialEq)]
struct Shadow {
    of: Vec<Effect>,
    offset: Vec2,
    variance: Vec2,
    color: Color,
}

impl Shadow {
    fn of(effects: &[Effect]) -> Shadow {
        Shadow {
            of: effects.to_vec(),
            offset: Vec2::ZERO,
            variance: Vec2::ZERO,
            color: Color::BLACK,
        }
    }

    /// Whether this is the plain silhouette of `effects` (as `SourceAlpha` is):
    /// compositing a shadow `out` of it only removes what the graphic drawn on top covers
    /// anyway.
    fn is_silhouette_of(&self, effects: &[Effect]) -> bool {
        self.of == effects && self.offset == Vec2::ZERO && self.variance == Vec2::ZERO
    }

    fn effect(self) -> Effect {
        Effect::DropShadow {
            offset: self.offset,
            std_dev: Vec2::new(self.variance.x.sqrt(), self.variance.y.sqrt()),
            color: self.color,
        }
    }
}

/// The effects of `filters` (applied in order, as usvg lists a CSS filter chain), or
/// `None` when they do something no effect expresses. A filter that does nothing answers
/// an empty effect list.
pub fn recognise(filters: &[Arc<uf::Filter>]) -> Option<Filter> {
    let mut effects = Vec::new();
    let mut region: Option<Rect> = None;
    let mut linear_rgb = false;
    for f in filters {
        let mut results: Vec<(&str, Value)> = Vec::new();
        for p in f.primitives() {
            let input = |i: &Input| -> Option<Value> {
                match i {
                    Input::SourceGraphic => Some(Value::Drawn(effects.clone())),
                    Input::SourceAlpha => Some(Value::Shadow(Shadow::of(&effects))),
                    Input::Reference(name) => results
                        .iter()
                        .rev()
                        .find(|(r, _)| r == name)
                        .map(|(_, v)| v.clone()),
                }
            };
            let linear = p.color_interpolation() == ColorInterpolation::LinearRGB;
            let value = match p.kind() {
                Kind::GaussianBlur(b) => {
                    let s = Vec2::new(b.std_dev_x().get().into(), b.std_dev_y().get().into());
                    match input(b.input())? {
                        Value::Drawn(e) => {
                            linear_rgb |= linear && s != Vec2::ZERO;
                            Value::Drawn(with(e, (s != Vec2::ZERO).then_some(Effect::Blur(s))))
                        }
                        Value::Shadow(sh) => Value::Shadow(Shadow {
                            variance: sh.variance + Vec2::new(s.x * s.x, s.y * s.y),
                            ..sh
                        }),
                        flood @ Value::Flood(_) => flood,
                    }
                }
                Kind::Offset(o) => {
                    let d = Vec2::new(o.dx().into(), o.dy().into());
                    match input(o.input())? {
                        Value::Shadow(sh) => Value::Shadow(Shadow {
                            offset: sh.offset + d,
                            ..sh
                        }),
                        drawn @ Value::Drawn(_) if d == Vec2::ZERO => drawn,
                        Value::Drawn(_) => return None,
                        flood @ Value::Flood(_) => flood,
                    }
                }
                Kind::DropShadow(s) => {
                    let Value::Drawn(e) = input(s.input())? else {
                        return None;
                    };
                    let c = s.color();
                    let shadow = Effect::DropShadow {
                        offset: Vec2::new(s.dx().into(), s.dy().into()),
                        std_dev: Vec2::new(s.std_dev_x().get().into(), s.std_dev_y().get().into()),
                        color: Color {
                            a: s.opacity().get(),
                            ..Color::rgb8(c.red, c.green, c.blue)
                        },
                    };
                    Value::Drawn(with(e, Some(shadow)))
                }
                Kind::Flood(f) => {
                    let c = f.color();
                    Value::Flood(Color {
                        a: f.opacity().get(),
                        ..Color::rgb8(c.red, c.green, c.blue)
                    })
                }
                Kind::ColorMatrix(m) => match (m.kind(), input(m.input())?) {
                    (uf::ColorMatrixKind::Matrix(m), v) => tint(m, v, linear)?,
                    _ => return None,
                },
                Kind::Composite(c) => {
                    let (a, b) = (input(c.input1())?, input(c.input2())?);
                    match c.operator() {
                        uf::CompositeOperator::Over => merge(vec![b, a])?,
                        uf::CompositeOperator::In => clip_in(a, b)?,
                        uf::CompositeOperator::Out => match (a, b) {
                            (Value::Shadow(s), Value::Shadow(p)) if p.is_silhouette_of(&s.of) => {
                                Value::Shadow(s)
                            }
                            _ => return None,
                        },
                        _ => return None,
                    }
                }
                Kind::Blend(b) if b.mode() == usvg::BlendMode::Normal => {
                    merge(vec![input(b.input2())?, input(b.input1())?])?
                }
                Kind::Merge(m) => merge(m.inputs().iter().map(input).collect::<Option<_>>()?)?,
                _ => return None,
            };
            results.push((p.result(), value));
        }
        match results.pop() {
            Some((_, Value::Drawn(e))) => effects = e,
            _ => return None,
        }
        let r = f.rect();
        let r = Rect::new(
            r.left().into(),
            r.top().into(),
            r.right().into(),
            r.bottom().into(),
        );
        region = Some(region.map_or(r, |u| u.union(r)));
    }
    Some(Filter {
        id: filters
            .first()
            .map(|f| f.id().to_string())
            .unwrap_or_default(),
        region: region?,
        effects,
        linear_rgb,
    })
}

/// Elements whose `style` gives a CSS filter with a function inside a function
/// (`drop-shadow(… rgba(0, 0, 0, 0.5))`): usvg's style parser drops the whole
/// declaration, so the element would lose its filter without a word.
pub fn unread_css_filters<'a, 'i>(
    doc: &'a usvg::roxmltree::Document<'i>,
) -> Vec<usvg::roxmltree::Node<'a, 'i>> {
    doc.descendants()
        .filter(|e| {
            e.attribute("style").is_some_and(|style| {
                style.split(';').any(|decl| {
                    decl.split_once(':').is_some_and(|(name, value)| {
                        name.trim() == "filter" && value.matches('(').count() > 1
                    })
                })
            })
        })
        .collect()
}

fn with(mut effects: Vec<Effect>, e: Option<Effect>) -> Vec<Effect> {
    effects.extend(e);
    effects
}

/// A colour matrix applied to `v`: on a silhouette or a flood, one that sets a constant
/// colour and scales alpha (Figma's shadow tint, and its `127×` "hard alpha").
fn tint(m: &[f32], v: Value, linear: bool) -> Option<Value> {
    let m: Vec<f64> = m.iter().map(|&x| f64::from(x)).collect();
    // Rows R, G, B must not read the input (their constant column is the colour) and row
    // A must read only alpha.
    let constant_rgb = (0..3).all(|row| m[row * 5..row * 5 + 4].iter().all(|&x| x == 0.0));
    let alpha_only = m[15..18].iter().all(|&x| x == 0.0) && m[19] == 0.0;
    if !constant_rgb || !alpha_only {
        return None;
    }
    let channel = |x: f64| {
        let x = x.clamp(0.0, 1.0);
        // In linear RGB (SVG's default for filters) the matrix's constants are linear
        // light; scene colours are sRGB.
        (if linear { linear_to_srgb(x) } else { x }) as f32
    };
    let rgb = [channel(m[4]), channel(m[9]), channel(m[14])];
    let recolour = |c: Color| Color {
        r: rgb[0],
        g: rgb[1],
        b: rgb[2],
        a: (f64::from(c.a) * m[18]).clamp(0.0, 1.0) as f32,
    };
    Some(match v {
        Value::Shadow(s) => Value::Shadow(Shadow {
            color: recolour(s.color),
            ..s
        }),
        Value::Flood(c) => Value::Flood(recolour(c)),
        Value::Drawn(_) => return None,
    })
}

fn linear_to_srgb(x: f64) -> f64 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// `a` where `b` is (`feComposite operator="in"`): a flood inside a silhouette colours it.
fn clip_in(a: Value, b: Value) -> Option<Value> {
    match (a, b) {
        (Value::Flood(c), Value::Shadow(s)) => Some(Value::Shadow(Shadow {
            color: Color {
                a: c.a * s.color.a,
                ..c
            },
            ..s
        })),
        (Value::Shadow(s), Value::Flood(c)) => Some(Value::Shadow(Shadow {
            color: Color {
                a: s.color.a * c.a,
                ..s.color
            },
            ..s
        })),
        _ => None,
    }
}

/// Layers drawn one over the other, bottom first: a shadow under the graphic it is the
/// shadow of is a drop shadow; transparent floods draw nothing.
fn merge(layers: Vec<Value>) -> Option<Value> {
    let mut layers: Vec<Value> = layers
        .into_iter()
        .filter(|v| !matches!(v, Value::Flood(c) if c.a == 0.0))
        .collect();
    match layers.len() {
        1 => layers.pop(),
        2 => match (layers.remove(0), layers.remove(0)) {
            (Value::Shadow(s), Value::Drawn(e)) if s.of == e => {
                Some(Value::Drawn(with(e, Some(s.effect()))))
            }
            _ => None,
        },
        _ => None,
    }
}

/// The largest side, in pixels, of a rasterised filter.
const MAX_BAKED_SIDE: f64 = 4096.0;

/// The most pixels drawn, by default, for filters drawn as images in one import (32
/// million, 128 MB; [`crate::Policy::max_baked_pixels`]): a file of thousands of filtered
/// elements is drawn in bounded time; past this, filters are left out with a warning.
pub const MAX_BAKED_PIXELS: u64 = 32_000_000;

/// Why a filter was not drawn as an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unbaked {
    /// The group draws nothing, or reaches coordinates the rasteriser cannot take.
    Nothing,
    /// It would take more pixels than were left of [`crate::Policy::max_baked_pixels`].
    OverBudget,
}

/// Draws `g` (its filters included) with resvg into an image at twice the output's
/// resolution, capped at [`MAX_BAKED_SIDE`] pixels a side and at `budget` pixels. Answers
/// the image and where it goes in the coordinates `g`'s parent draws in (`parent_abs`
/// maps them to the canvas), or `None` when the group draws nothing, reaches coordinates
/// the rasteriser cannot take ([`Unbaked::Nothing`]), or would need more pixels than
/// `budget` ([`Unbaked::OverBudget`]). A group holding a raster image of more than
/// `max_image_pixels` pixels is not drawn (resvg would decode it whole).
pub fn bake(
    g: &usvg::Group,
    parent_abs: usvg::Transform,
    budget: f64,
    max_image_pixels: u64,
) -> Result<(ImageNode, Affine), Unbaked> {
    let node = usvg::Node::Group(Box::new(g.clone()));
    let bbox = node.abs_layer_bounding_box().ok_or(Unbaked::Nothing)?;
    let (w, h) = (f64::from(bbox.width()), f64::from(bbox.height()));
    let abs = affine(parent_abs);
    let own_scale = (abs.determinant().abs().sqrt() * 2.0).max(1e-9);
    let scale = own_scale.min(MAX_BAKED_SIDE / w.max(h));
    let (pw, ph) = ((w * scale).ceil(), (h * scale).ceil());
    if pw * ph > budget {
        return Err(Unbaked::OverBudget);
    }
    if !(scale.is_finite()
        && pw >= 1.0
        && ph >= 1.0
        && drawable(g, scale, bbox)
        && images_within(g, max_image_pixels))
    {
        return Err(Unbaked::Nothing);
    }
    let mut pixmap = resvg::tiny_skia::Pixmap::new(pw as u32, ph as u32).ok_or(Unbaked::Nothing)?;
    // resvg draws the node from its own transform down and shifts by the bounding box's
    // corner: put the parent's transform back in between.
    let (bx, by) = (bbox.x(), bbox.y());
    let ts = usvg::Transform::from_scale(scale as f32, scale as f32)
        .pre_translate(-bx, -by)
        .pre_concat(parent_abs)
        .pre_translate(bx, by);
    resvg::render_node(&node, ts, &mut pixmap.as_mut()).ok_or(Unbaked::Nothing)?;
    let data = pixmap.encode_png().map_err(|_| Unbaked::Nothing)?;
    let image = ImageNode {
        id: String::new(),
        data: Arc::from(data),
        format: ImageFormat::Png,
        width: pw,
        height: ph,
        smooth: true,
        unit: None,
    };
    let place = abs.inverse()
        * Affine::translate((f64::from(bx), f64::from(by)))
        * Affine::scale(1.0 / scale);
    Ok((image, place))
}

/// Whether every path under `g` (clip paths and masks included), drawn at `scale` from
/// the corner of `bbox`, stays within what tiny-skia draws without panicking.
/// Whether every raster image in `g`, its clip paths, masks, patterns and filters
/// included, declares at most `limit` pixels.
fn images_within(g: &usvg::Group, limit: u64) -> bool {
    g.children().iter().all(|n| {
        let own = match n {
            usvg::Node::Group(h) => images_within(h, limit),
            usvg::Node::Image(i) => match i.kind() {
                usvg::ImageKind::PNG(d)
                | usvg::ImageKind::JPEG(d)
                | usvg::ImageKind::GIF(d)
                | usvg::ImageKind::WEBP(d) => gmotion::scene::image_pixel_size(d)
                    .is_none_or(|(w, h)| w.saturating_mul(h) <= limit),
                usvg::ImageKind::SVG(tree) => images_within(tree.root(), limit),
            },
            usvg::Node::Path(_) | usvg::Node::Text(_) => true,
        };
        let mut inner = true;
        n.subroots(|s| inner &= images_within(s, limit));
        own && inner
    })
}

fn drawable(g: &usvg::Group, scale: f64, bbox: usvg::NonZeroRect) -> bool {
    const LIMIT: f64 = 1e8;
    let ok = |r: usvg::Rect| {
        [
            f64::from(r.left() - bbox.x()),
            f64::from(r.right() - bbox.x()),
            f64::from(r.top() - bbox.y()),
            f64::from(r.bottom() - bbox.y()),
        ]
        .iter()
        .all(|v| (v * scale).abs() < LIMIT)
    };
    let group_ok = |h: &usvg::Group| {
        h.clip_path()
            .is_none_or(|c| drawable(c.root(), scale, bbox))
            && h.mask().is_none_or(|m| drawable(m.root(), scale, bbox))
    };
    group_ok(g)
        && g.children().iter().all(|n| match n {
            usvg::Node::Group(h) => drawable(h, scale, bbox),
            usvg::Node::Path(p) => ok(p.abs_stroke_bounding_box()),
            usvg::Node::Image(i) => ok(i.abs_bounding_box()),
            usvg::Node::Text(t) => ok(t.abs_stroke_bounding_box()),
        })
}
