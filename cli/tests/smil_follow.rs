//! `animate(follow, …)` in SMIL: written natively as an `animateMotion` along the path
//! (its `keyPoints` the arc-length fractions, the rule's easing its `keySplines`,
//! `rotate="auto"` for `orient=auto`), sampled only where SMIL cannot say it, and played
//! by Chromium as gmotion draws it.

use gmotion::motion::Animation;
use gmotion_export_svg::smil::{SmilOptions, smil_document};

/// An arrow and a box on a paper, as the Lottie follow tests draw them.
const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="240">
<rect data-tag="paper" width="400" height="240" fill="#fafaf7"/>
<path data-tag="arrow" d="M 22 172 L 58 180 L 22 188 Z" fill="#e4572e"/>
<rect data-tag="box" x="150" y="150" width="30" height="20" fill="#2e86ab" stroke="#1b1b1b" stroke-width="2"/>
</svg>"##;

fn anim(grammar: &str) -> Animation {
    crate::support::run_grammar(crate::support::scene_of(SVG), grammar)
}

fn smil(a: &Animation) -> String {
    smil_document(a, &SmilOptions::default())
        .unwrap()
        .svg
        .into_string()
}

/// The follows Chromium plays: a linear cubic; a turning, eased two-curve path in a slice
/// with its inverted twin; a `world` path of quadratics starting on the box's centroid (so
/// not a jump) with a rotation nested in it; a turning path cut by a later slice with a scale nested in the second part;
/// a turning polyline with a linear easing.
const PLAYED: [(&str, &str); 5] = [
    (
        "cubic",
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\") : [all, arrow] -> [m]\n",
    ),
    (
        "orient_twin",
        "duration 3s\ntimesplit(0.5, 0.5) : [all, arrow] -> [a, inv_a]\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180 S 400 300 200 200\", orient=auto, ease=ease-in-out) : [a, arrow] -> [m]\n",
    ),
    (
        "world_rotated",
        "duration 2s\nloop false\nanimate(follow, world, 0.3, \"M 165 160 Q 250 20 340 160 T 100 100\", ease=ease-out) : [all, box] -> [m]\nanimate(affine, local, 0, rotate(180)) : [m, box] -> [n]\n",
    ),
    (
        "orient_cut",
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 0 0 C 100 -150 200 150 300 0\", orient=auto, ease=ease-in) : [all, arrow] -> [m]\ntimesplit(0.35, 0.65) : [m, arrow] -> [p, q]\nanimate(affine, local, 0, scale(0.6)) : [q, arrow] -> [r]\n",
    ),
    (
        "orient_polyline",
        "duration 2s\nloop false\nanimate(follow, local, 0, \"M 40 200 L 180 60 L 330 120\", orient=auto) : [all, arrow] -> [m]\n",
    ),
];

#[test]
fn a_linear_follow_along_one_cubic_is_one_animate_motion() {
    let a = anim(PLAYED[0].1);
    let svg = smil(&a);
    assert_eq!(svg.matches("<animateMotion").count(), 1, "{svg}");
    assert!(!svg.contains("<animateTransform"), "sampled: {svg}");
    assert!(
        svg.contains("path=\"M640 2880 C1920 320 4480 320 5760 2880\""),
        "{svg}"
    );
    assert!(svg.contains("keyPoints=\"0;1\""), "{svg}");
    assert!(svg.contains("calcMode=\"linear\""), "{svg}");
    assert!(!svg.contains("rotate=\"auto\""), "{svg}");
}

#[test]
fn orient_auto_turns_with_the_path_and_eases_by_splines() {
    let a = anim(PLAYED[1].1);
    let svg = smil(&a);
    // The motion and its inverted twin, both along the path.
    assert_eq!(svg.matches("<animateMotion").count(), 2, "{svg}");
    assert!(!svg.contains("<animateTransform"), "{svg}");
    assert_eq!(svg.matches("rotate=\"auto\"").count(), 2, "{svg}");
    // Each holds its end through the other's half: the motion, then the twin back.
    assert!(svg.contains("keyPoints=\"0;1;1\""), "{svg}");
    assert!(svg.contains("keyPoints=\"1;1;0\""), "{svg}");
    assert!(svg.contains("calcMode=\"spline\""), "{svg}");
}

#[test]
fn what_smil_cannot_say_is_sampled() {
    for grammar in [
        // An easing that is no cubic Bézier.
        "duration 2s\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\", ease=bspline(3)) : [all, arrow] -> [m]\n",
        // Overshooting the path's end.
        "duration 2s\nanimate(follow, local, 0, \"M 40 180 C 120 20 280 20 360 180\", ease=cubic(0.3, -0.3, 0.7, 1.3)) : [all, arrow] -> [m]\n",
        // A world path away from the centroid: the jump onto it.
        "duration 2s\nanimate(follow, world, 0, \"M 40 100 H 300\") : [all, arrow] -> [m]\n",
        // Two subpaths.
        "duration 2s\nanimate(follow, local, 0, \"M 0 0 H 100 M 100 50 H 200\") : [all, arrow] -> [m]\n",
    ] {
        let svg = smil(&anim(grammar));
        assert!(!svg.contains("<animateMotion"), "{grammar}\n{svg}");
        assert!(svg.contains("<animateTransform"), "{grammar}\n{svg}");
    }
}

#[cfg(feature = "players")]
#[test]
fn chromium_plays_the_smil_follows_as_the_model() {
    use crate::support::players::{chromium, frames_to_check};
    use gmotion_export_raster::{compare, render};
    use gmotion_export_svg::frame::frame_svg;

    for (name, grammar) in PLAYED {
        let a = anim(grammar);
        let d = crate::support::tmp_dir().join("smil_follow").join(name);
        std::fs::create_dir_all(&d).unwrap();
        let file = d.join("out.svg");
        std::fs::write(&file, smil(&a)).unwrap();
        let times: Vec<f64> = frames_to_check(&a).iter().map(|f| f / a.fps).collect();
        let shots = chromium(&file, 400, &times);
        let mut bad = Vec::new();
        for (&t, got) in times.iter().zip(&shots) {
            let model = render(&frame_svg(&a, t), 400).unwrap();
            let off = compare(&model, got, 32);
            // Far stricter than the conformance bar (0.5 %): the path written 16 times
            // larger keeps Chromium's arc length (measured to about half a unit) within
            // 0.03 px here; at its own size the box of `world_rotated` was 0.5 px off.
            if off >= 0.001 {
                bad.push(format!("t = {t:.3}: {:.3}% off", off * 100.0));
            }
        }
        assert!(
            bad.is_empty(),
            "{name} ({}):\n{}",
            d.display(),
            bad.join("\n")
        );
    }
}
