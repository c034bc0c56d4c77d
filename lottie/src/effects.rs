//! Layer effects drawn as lottie-web's svg renderer draws them: Gaussian Blur (`ty` 29) and
//! Drop Shadow (`ty` 25) become the layer group's scene filter, in the layer's coordinates.
//! lottie-web's conversions: standard deviation = 0.3 × blurriness (on both axes, or one
//! by Blur Dimensions); a shadow's standard deviation = softness / 4, its offset
//! `distance` towards `direction − 90°`, its opacity out of 255. Expression controls
//! (`ty` 5) draw nothing; any other effect is not drawn, with a warning.

use gmotion::color::Color;
use gmotion::scene::{Effect, Filter};
use kurbo::{Rect, Vec2};

use crate::model::{LayerEffect, Loc};

/// The filter of `effects` at `t`, drawing in `region` (layer coordinates), or `None` when
/// none of them draws; `warn` hears of the effects that are not drawn.
pub fn filter(
    effects: &[LayerEffect],
    t: f64,
    region: Rect,
    warn: &mut dyn FnMut(&Loc, String),
) -> Option<Filter> {
    let mut out = Vec::new();
    for e in effects.iter().filter(|e| e.enabled) {
        let scalar = |i: usize, default: f64| e.value(i, t, &[default])[0];
        match e.ty {
            29 => {
                let sigma = 0.3 * scalar(0, 0.0).max(0.0);
                let dims = scalar(1, 1.0).round();
                let s = Vec2::new(
                    if dims == 3.0 { 0.0 } else { sigma },
                    if dims == 2.0 { 0.0 } else { sigma },
                );
                if s != Vec2::ZERO {
                    out.push(Effect::Blur(s));
                }
            }
            25 => {
                if scalar(5, 0.0) != 0.0 {
                    warn(
                        &e.at,
                        "a drop shadow's Shadow Only is not drawn".to_string(),
                    );
                    continue;
                }
                let c = e.value(0, t, &[0.0, 0.0, 0.0, 1.0]);
                let ch = |k: usize| c.get(k).copied().unwrap_or(0.0).clamp(0.0, 1.0) as f32;
                let angle = (scalar(2, 135.0) - 90.0).to_radians();
                let distance = scalar(3, 5.0);
                let sigma = (scalar(4, 0.0) / 4.0).max(0.0);
                out.push(Effect::DropShadow {
                    offset: Vec2::new(distance * angle.cos(), distance * angle.sin()),
                    std_dev: Vec2::new(sigma, sigma),
                    color: Color {
                        a: (scalar(1, 127.5) / 255.0).clamp(0.0, 1.0) as f32,
                        ..Color::rgb(ch(0), ch(1), ch(2))
                    },
                });
            }
            5 => {}
            ty => {
                let name = if e.nm.is_empty() { "an effect" } else { &e.nm };
                warn(&e.at, format!("effect \"{name}\" (ty {ty}) is not drawn"));
            }
        }
    }
    (!out.is_empty()).then(|| Filter {
        id: String::new(),
        region,
        effects: out,
        // lottie-web's filters leave SVG's default colour space in place.
        linear_rgb: true,
    })
}
