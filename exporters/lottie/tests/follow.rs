//! `animate(follow, …)` exported natively: position keyframes with spatial tangents, one
//! per segment of the path (not a bake), and every player drawing them like the model.

use gmotion::motion::Animation;
use gmotion_export_lottie::{LottieOptions, to_lottie};
use serde_json::Value;

#[cfg(feature = "players")]
use crate::support::players::{Player, assert_plays_like_model, frames_to_check};

const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="240">
<rect data-tag="paper" width="400" height="240" fill="#fafaf7"/>
<path data-tag="arrow" d="M 22 172 L 58 180 L 22 188 Z" fill="#e4572e"/>
<rect data-tag="box" x="150" y="150" width="30" height="20" fill="#2e86ab" stroke="#1b1b1b" stroke-width="2"/>
</svg>"##;

fn anim(grammar: &str) -> Animation {
    crate::support::run_grammar(crate::support::scene_of(SVG), grammar)
}

/// Every animated position of the document that moves along curves (has spatial tangents).
fn spatial_positions(json: &str) -> Vec<Vec<Value>> {
    fn walk(v: &Value, out: &mut Vec<Vec<Value>>) {
        match v {
            Value::Object(m) => {
                if let Some(Value::Object(p)) = m.get("p")
                    && p.get("a") == Some(&Value::from(1))
                    && let Some(Value::Array(keys)) = p.get("k")
                    && keys.iter().any(|k| k.get("to").is_some())
                {
                    out.push(keys.clone());
                }
                m.values().for_each(|x| walk(x, out));
            }
            Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
            _ => {}
        }
    }
    let doc: Value = serde_json::from_str(json).unwrap();
    let mut out = Vec::new();
    walk(&doc, &mut out);
    out
}

fn export(a: &Animation) -> String {
    to_lottie(a, &LottieOptions::default()).unwrap().0
}

#[test]
fn one_cubic_writes_two_keyframes_and_its_tangents() {
    let a = anim(
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\") : [all, arrow] -> [m]\n",
    );
    let json = export(&a);
    let found = spatial_positions(&json);
    assert_eq!(found.len(), 1, "{json}");
    let keys = &found[0];
    assert_eq!(keys.len(), 2, "one cubic, linear: two keyframes");
    let num = |v: &Value| v.as_f64().unwrap();
    // The cubic's handles, relative to its ends.
    assert_eq!(
        keys[0]["to"]
            .as_array()
            .unwrap()
            .iter()
            .map(num)
            .collect::<Vec<_>>(),
        [80.0, -160.0]
    );
    assert_eq!(
        keys[0]["ti"]
            .as_array()
            .unwrap()
            .iter()
            .map(num)
            .collect::<Vec<_>>(),
        [-80.0, -160.0]
    );
    assert_eq!(num(&keys[1]["t"]), 60.0);
}

#[test]
fn an_eased_turning_follow_is_keyed_not_baked() {
    let a = anim(
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180 S 400 300 200 200\", orient=auto, ease=ease-in-out) : [all, arrow] -> [m]\n",
    );
    let json = export(&a);
    let found = spatial_positions(&json);
    assert_eq!(found.len(), 1);
    // Two segments and the heading's halvings: far fewer than the 61 frames a bake has.
    let n = found[0].len();
    assert!((3..=20).contains(&n), "{n} position keyframes");
}

#[cfg(feature = "players")]
#[test]
fn follows_play_in_every_player() {
    let cases = [
        (
            "follow-linear",
            "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\") : [all, arrow] -> [m]\n",
        ),
        (
            "follow-orient-twin",
            "duration 3s\ntimesplit(0.5, 0.5) : [all, arrow] -> [a, inv_a]\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180 S 400 300 200 200\", orient=auto, ease=ease-in-out) : [a, arrow] -> [m]\n",
        ),
        (
            "follow-world-spin",
            "duration 2s\nloop false\nanimate(follow, world, 0.3, \"M 165 160 Q 250 20 340 160 T 100 100\", ease=ease-out) : [all, box] -> [m]\nanimate(affine, local, 0, rotate(180)) : [m, box] -> [n]\n",
        ),
        (
            "follow-split",
            "duration 2s\nloop false\nanimate(follow, local, 0, \"M 0 0 C 100 -150 200 150 300 0\", orient=auto, ease=ease-in) : [all, arrow] -> [m]\ntimesplit(0.35, 0.65) : [m, arrow] -> [p, q]\nanimate(affine, local, 0, scale(0.6)) : [q, arrow] -> [r]\n",
        ),
    ];
    for (name, g) in cases {
        let a = anim(g);
        let json = export(&a);
        let width = (2.0 * a.scene.width).round() as u32;
        assert_plays_like_model(name, &a, &json, &frames_to_check(&a), width, &Player::ALL);
    }
}
