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
    // At a tolerance the octagonal length of rlottie and ThorVG stays within (1.4 px off
    // lottie-web on this arch), the cubic is one interval.
    let json = to_lottie(
        &a,
        &LottieOptions {
            tolerance: 3.0,
            ..Default::default()
        },
    )
    .unwrap()
    .0;
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
    // Two segments, the heading's halvings and the frames where rlottie's and ThorVG's
    // octagonal length strays (33 keys): fewer than the 61 frames a bake has.
    let n = found[0].len();
    assert!((3..=40).contains(&n), "{n} position keyframes");
}

/// Where rlottie and ThorVG, which measure a Bézier's length with the octagonal norm
/// `max + 3/8·min`, put a point at `frac` of a key interval's length, against where the
/// arc length does: the largest distance apart (canvas units).
fn octagonal_gap(p0: [f64; 2], to: [f64; 2], ti: [f64; 2], p3: [f64; 2]) -> f64 {
    let pts = [
        p0,
        [p0[0] + to[0], p0[1] + to[1]],
        [p3[0] + ti[0], p3[1] + ti[1]],
        p3,
    ];
    let at = |t: f64| {
        let u = 1.0 - t;
        let w = [u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t];
        let x = (0..4).map(|i| w[i] * pts[i][0]).sum::<f64>();
        let y = (0..4).map(|i| w[i] * pts[i][1]).sum::<f64>();
        (x, y)
    };
    const K: usize = 2000;
    let (mut e, mut o) = (vec![0.0; K + 1], vec![0.0; K + 1]);
    let mut prev = at(0.0);
    for j in 1..=K {
        let p = at(j as f64 / K as f64);
        let (dx, dy) = ((p.0 - prev.0).abs(), (p.1 - prev.1).abs());
        e[j] = e[j - 1] + dx.hypot(dy);
        o[j] = o[j - 1] + dx.max(dy) + 0.375 * dx.min(dy);
        prev = p;
    }
    if e[K] == 0.0 {
        return 0.0;
    }
    (0..=K)
        .map(|j| (o[j] / o[K] - e[j] / e[K]).abs())
        .fold(0.0, f64::max)
        * e[K]
}

#[test]
fn no_frame_falls_where_rlottie_and_thorvg_measure_the_arc_otherwise() {
    // The conformance matrix's gm-0035 path (0.8 px apart on its arch before) and the
    // one-cubic arch (1.4 px), eased, at the default tolerance (0.25).
    for g in [
        "duration 1.5s\nfps 24\nanimate(follow, local, 0, \"M 0 0 C 30 -60 90 -60 120 0 S 150 40 170 20\", ease=ease) : [all, arrow] -> [m]\n",
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\", ease=ease-in) : [all, arrow] -> [m]\n",
    ] {
        let a = anim(g);
        let json = export(&a);
        let found = spatial_positions(&json);
        assert_eq!(found.len(), 1, "{json}");
        let keys = &found[0];
        let v = |k: &Value, f: &str| {
            let a = k[f].as_array().unwrap();
            [a[0].as_f64().unwrap(), a[1].as_f64().unwrap()]
        };
        let frames = (a.duration * a.fps).round() as usize;
        assert!(
            keys.len() <= frames + 2,
            "{} keys for {frames} frames",
            keys.len()
        );
        for w in keys.windows(2) {
            let (t0, t1) = (w[0]["t"].as_f64().unwrap(), w[1]["t"].as_f64().unwrap());
            let gap = octagonal_gap(v(&w[0], "s"), v(&w[0], "to"), v(&w[0], "ti"), v(&w[1], "s"));
            let frame_inside = (t0.floor() as i64 + 1..=t1.ceil() as i64 - 1)
                .next()
                .is_some();
            assert!(
                gap <= 0.125 + 1e-3 || !frame_inside,
                "interval {t0}..{t1}: {gap:.3} px apart with a frame inside\n{g}"
            );
        }
    }
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
            // The conformance matrix's gm-0035: rlottie and ThorVG measured its arch 0.8 px
            // apart from lottie-web before its intervals were keyed at frames.
            "follow-arch-twin",
            "duration 1.5s\nfps 24\ntimesplit(0.5, 0.5) : [all, box] -> [inv_a, a]\nanimate(follow, local, 0.25 * d, \"M 0 0 C 30 -60 90 -60 120 0 S 150 40 170 20\", ease=ease) : [a, box] -> [m]\n",
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
