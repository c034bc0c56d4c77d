//! Filter effects as After Effects effects: a blur as "Gaussian Blur" (`ty` 29), a drop
//! shadow as "Drop Shadow" (`ty` 25), on the layer that draws the filtered group.
//!
//! lottie-web's svg renderer turns them back into SVG filters, in the layer's own
//! coordinates (so they scale with it) and over the layer's bounding box: a blur's region
//! is the box grown by its size on every side, a drop shadow's the box itself. The layer
//! therefore also draws the filter's region as an invisible rectangle ([`extent`]), so
//! that the box covers what the source's filter draws. Its conversions:
//! standard deviation = 0.3 × blurriness, = softness / 4; the shadow falls `distance`
//! towards `direction − 90°`; its opacity is out of 255.

use kurbo::{Affine, Rect};

use super::super::model::{
    EffectValue, Fill as LFill, Group as LGroup, LayerEffect, N, PathShape, Prop, Shape, Transform,
    Value,
};
use super::mattes::mask;
use crate::geometry::contours;
use gmotion::scene::{Effect, Filter};
use kurbo::Shape as _;

/// Which players draw the effects (said once per export that has any).
pub(super) const PLAYERS: &str = "blurs and drop shadows are Lottie effects: lottie-web's svg renderer and ThorVG draw them, rlottie and lottie-web's canvas renderer draw the layers without them";

/// The effects of `f` on a group whose content `inner` maps to the layer's coordinates.
pub(super) fn effects(f: &Filter, inner: Affine) -> Vec<LayerEffect> {
    let scale = inner.determinant().abs().sqrt();
    let mut out = Vec::new();
    for e in &f.effects {
        match *e {
            Effect::Blur(s) => {
                let s = s * scale;
                // A Lottie blur is the same both ways or along one axis only; a blur that
                // differs is two, one per axis (a Gaussian is separable).
                let close = (s.x - s.y).abs() <= 0.01 * s.x.max(s.y);
                if close {
                    out.push(blur((s.x + s.y) / 2.0, 1));
                } else {
                    for (sigma, dims) in [(s.x, 2), (s.y, 3)] {
                        if sigma > 0.0 {
                            out.push(blur(sigma, dims));
                        }
                    }
                }
            }
            Effect::DropShadow {
                offset,
                std_dev,
                color,
            } => {
                let d = inner * offset.to_point() - inner * kurbo::Point::ZERO;
                let direction = d.y.atan2(d.x).to_degrees() + 90.0;
                let softness = 4.0 * scale * (std_dev.x + std_dev.y) / 2.0;
                let rgba = [color.r, color.g, color.b, 1.0].map(|c| N::fine(c.into()));
                out.push(effect(
                    25,
                    "Drop Shadow",
                    "ADBE Drop Shadow",
                    vec![
                        (2, "Shadow Color", Prop::vec(rgba.to_vec())),
                        (0, "Opacity", scalar(f64::from(color.a) * 255.0)),
                        (1, "Direction", scalar(direction.rem_euclid(360.0))),
                        (0, "Distance", scalar(d.hypot())),
                        (0, "Softness", scalar(softness)),
                        (4, "Shadow Only", scalar(0.0)),
                    ],
                ));
            }
        }
    }
    for (i, e) in out.iter_mut().enumerate() {
        e.ix = i + 1;
    }
    out
}

fn scalar(x: f64) -> Prop {
    Prop::scalar(N::coord(x))
}

/// A Gaussian blur of standard deviation `sigma` along `dims` (1 both, 2 x, 3 y).
fn blur(sigma: f64, dims: u8) -> LayerEffect {
    effect(
        29,
        "Gaussian Blur",
        "ADBE Gaussian Blur 2",
        vec![
            (0, "Blurriness", scalar(sigma / 0.3)),
            (7, "Blur Dimensions", scalar(f64::from(dims))),
            (4, "Repeat Edge Pixels", scalar(0.0)),
        ],
    )
}

fn effect(
    ty: u8,
    nm: &'static str,
    mn: &'static str,
    values: Vec<(u8, &'static str, Prop)>,
) -> LayerEffect {
    let ef: Vec<EffectValue> = values
        .into_iter()
        .enumerate()
        .map(|(i, (ty, nm, v))| EffectValue {
            ty,
            nm,
            mn: format!("{mn}-{:04}", i + 1),
            ix: i + 1,
            v,
        })
        .collect();
    LayerEffect {
        ty,
        nm,
        mn,
        ix: 1,
        en: 1,
        np: ef.len() + 2,
        ef,
    }
}

/// An invisible rectangle over `region` (in the layer's coordinates), drawn so that the
/// layer's bounding box, which lottie-web's filter regions follow, covers it.
pub(super) fn extent(region: Rect) -> Shape {
    let outline = contours(&region.to_path(0.1))
        .into_iter()
        .next()
        .and_then(|c| mask(&c).pt)
        .unwrap_or_else(|| Prop::fixed(Value::Scalar(N(0.0))));
    Shape::Group(LGroup {
        nm: "filter region".to_string(),
        it: vec![
            Shape::Path(PathShape { ks: outline }),
            Shape::Fill(LFill {
                o: Prop::scalar(N(0.0)),
                c: Prop::vec(vec![N(0.0), N(0.0), N(0.0)]),
                r: 1,
                slot: None,
            }),
            Shape::Transform(Transform::empty()),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::color::Color;
    use kurbo::Vec2;

    #[test]
    fn blur_converts_to_blurriness_in_layer_units() {
        let f = Filter {
            id: String::new(),
            region: Rect::new(0.0, 0.0, 10.0, 10.0),
            effects: vec![Effect::Blur(Vec2::new(3.0, 3.0))],
            linear_rgb: false,
        };
        let e = effects(&f, Affine::scale(2.0));
        assert_eq!(e.len(), 1);
        // σ 3 in the group is 6 on the layer: blurriness 6 / 0.3.
        let json = serde_json::to_string(&e[0]).unwrap();
        assert!(json.contains("\"v\":{\"a\":0,\"k\":20}"), "{json}");
    }

    #[test]
    fn anisotropic_blur_is_two_blurs() {
        let f = Filter {
            id: String::new(),
            region: Rect::new(0.0, 0.0, 10.0, 10.0),
            effects: vec![
                Effect::Blur(Vec2::new(3.0, 1.0)),
                Effect::DropShadow {
                    offset: Vec2::new(0.0, 4.0),
                    std_dev: Vec2::new(1.0, 1.0),
                    color: Color::BLACK,
                },
            ],
            linear_rgb: false,
        };
        let e = effects(&f, Affine::IDENTITY);
        let kinds: Vec<u8> = e.iter().map(|e| e.ty).collect();
        assert_eq!(kinds, [29, 29, 25]);
        assert_eq!(e.iter().map(|e| e.ix).collect::<Vec<_>>(), [1, 2, 3]);
        // Straight down is AE's 180°.
        let json = serde_json::to_string(&e[2]).unwrap();
        assert!(
            json.contains(
                "\"Direction\",\"mn\":\"ADBE Drop Shadow-0003\",\"ix\":3,\"v\":{\"a\":0,\"k\":180}"
            ),
            "{json}"
        );
    }
}
