//! Embedding gmotion: an SVG and a grammar in, Lottie and animated SVG (SMIL) out, all in
//! memory. Run with `cargo run --example embed`; it writes `target/examples-out/embed.*`.

use gmotion::engine::{RunOptions, run};
use gmotion_export_lottie::{LottieOptions, to_lottie};
use gmotion_export_svg::smil::{SmilOptions, to_smil};
use gmotion_import_svg::{ImportOptions, parse};

const SCENE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">
  <rect class="box" x="20" y="30" width="40" height="40" fill="#e4572e"/>
  <circle class="dot" cx="150" cy="50" r="20" fill="#29335c"/>
</svg>"##;

// Two slices per shape; `inv_a` plays `a` backwards, so the box slides out and back and the
// dot turns a quarter and back, and the loop closes.
const GRAMMAR: &str = "
duration 2s
timesplit(0.5, 0.5)                              : [all, all] -> [a, inv_a]
animate(affine, world, 0, translate(100, 0), ease=ease-in-out) : [a, box] -> [slide]
animate(affine, local, 0, rotate(90))            : [a, dot]   -> [turn]
";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = parse(SCENE, "scene.svg", &ImportOptions::default())?.scene;
    let grammar = gmotion::grammar::parse(GRAMMAR)?;
    let (animation, stats) = run(scene, &grammar, &RunOptions::default())?;
    let (lottie, warnings) = to_lottie(&animation, &LottieOptions::default())?;
    let (smil, more) = to_smil(&animation, &SmilOptions::default())?;
    for w in warnings.iter().chain(&more) {
        eprintln!("warning: {w}");
    }

    let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/examples-out");
    std::fs::create_dir_all(&out)?;
    gmotion::atomic::write_bytes(&out.join("embed.json"), lottie.as_bytes())?;
    gmotion::atomic::write_bytes(&out.join("embed.svg"), smil.as_bytes())?;
    println!(
        "{} shapes, {} slices in {} steps: wrote {}/embed.json (Lottie) and embed.svg (SMIL)",
        animation.scene.shapes.len(),
        stats.slices,
        stats.steps,
        out.display()
    );
    Ok(())
}
