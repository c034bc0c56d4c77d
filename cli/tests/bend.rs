//! `lookup=vertex` bends outlines (issue 42): a rectangle under a 12×1 `path` grid waves
//! along the curve instead of tilting as a quad, in every Lottie player and in Chromium's
//! SMIL as in gmotion's own frames, with a handful of path keyframes (not a bake).

use serde_json::Value;

use crate::support::pictures::{Judge, animate_and_play};
use crate::support::players::Player;

/// The players' bar (tests/conformance: 0.5 % of the pixels).
const MAX_OFF: f64 = 0.005;

const ART: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="240">
<rect data-tag="paper" width="400" height="240" fill="#fafaf7"/>
<rect data-tag="band" x="20" y="40" width="360" height="24" fill="#2e86ab"/>
<path data-tag="leaf" d="M 60 170 C 120 130 220 130 300 170 C 220 210 120 210 60 170 Z" fill="#e4572e"/>
</svg>"##;

/// Every animated path (`sh` with keyframes) of the document: (keyframes, vertices).
fn path_keys(json: &str) -> Vec<(usize, usize)> {
    fn walk(v: &Value, out: &mut Vec<(usize, usize)>) {
        match v {
            Value::Object(m) => {
                if m.get("ty") == Some(&Value::from("sh"))
                    && let Some(Value::Array(keys)) = m.get("ks").and_then(|k| k.get("k"))
                {
                    let v = keys[0]["s"][0]["v"].as_array().map_or(0, Vec::len);
                    out.push((keys.len(), v));
                }
                m.values().for_each(|x| walk(x, out));
            }
            Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(&serde_json::from_str(json).unwrap(), &mut out);
    out
}

/// The middle row of the band's pixels in column `x` of `frame` (800 px wide: twice the
/// canvas), from its blue.
fn band_middle(frame: &gmotion_export_raster::Pixmap, x: u32) -> f64 {
    let rows: Vec<u32> = (0..frame.height())
        .filter(|&y| {
            let p = frame.pixel(x, y).unwrap();
            p.blue() > 150 && p.red() < 100
        })
        .collect();
    assert!(!rows.is_empty(), "no band in column {x}");
    f64::from(rows[0] + rows[rows.len() - 1]) / 2.0
}

#[test]
fn a_band_under_a_path_grid_waves_in_every_player() {
    let d = crate::support::case_dir("bend", "band");
    std::fs::write(d.join("art.svg"), ART).unwrap();
    std::fs::write(
        d.join("art.gm"),
        "duration 2s\nfps 30\nloop false\n\
         animate(path, world, 0, \"M 0 120 C 100 20 300 220 400 120\", grid=12x1, lookup=vertex, ease=ease-in-out) : [all, band] -> [bent]\n\
         animate(path, world, 0, \"M 40 60 L 200 220 L 360 60\", grid=6x6, lookup=vertex) : [all, leaf] -> [pulled]\n",
    )
    .unwrap();
    let mut judge = Judge::new(MAX_OFF);
    let frames = [0.0, 15.0, 30.0, 45.0, 59.0];
    let ours = animate_and_play(
        "bend-band",
        &d,
        800,
        30.0,
        &frames,
        &Player::ALL,
        &mut judge,
    );
    judge.assert_all_close(&d);

    // At rest the band is straight; at the end its middle follows the curve's wave: a crest
    // on the left, a trough on the right, which no straight band (the quad it was) draws.
    let mids = |f: &gmotion_export_raster::Pixmap, xs: [u32; 3]| xs.map(|x| band_middle(f, x));
    let rest = mids(&ours[0], [60, 400, 740]);
    assert!((rest[0] - rest[2]).abs() < 1.0, "{rest:?}");
    let [l, m, r] = mids(&ours[4], [40, 160, 280]);
    assert!(m < l.min(r) - 15.0, "no crest: {l} {m} {r}");
    let [l, m, r] = mids(&ours[4], [460, 640, 760]);
    assert!(m > l.max(r) + 15.0, "no trough: {l} {m} {r}");

    // Native and small: one keyframed path per shape, far fewer keyframes than the 61
    // frames a bake writes, and the outlines cut a few dozen times, not per pixel.
    let json = std::fs::read_to_string(d.join("anim.json")).unwrap();
    let keys = path_keys(&json);
    assert_eq!(keys.len(), 2, "{keys:?}");
    for (k, v) in keys {
        assert!(k <= 16, "{k} path keyframes");
        assert!((8..=160).contains(&v), "{v} vertices");
    }
}
