//! Frames from the library: a bundled example rendered with resvg into a GIF, an APNG and
//! one PNG, the way `gmotion animate … -o x.gif` does. Run with `cargo run --example frames
//! [NAME]` (default `toy`); it writes `target/examples-out/NAME.{gif,apng,png}`.

use std::path::Path;

use gmotion::engine::{RunOptions, run};
use gmotion_import_svg::{ImportOptions, load};
use gmotion_output::{Options, write};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let name = std::env::args().nth(1).unwrap_or_else(|| "toy".to_string());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load(
        &root.join(format!("grammars/{name}.svg")),
        &ImportOptions::default(),
    )?
    .scene;
    let source = std::fs::read_to_string(root.join(format!("grammars/{name}.gm")))?;
    let grammar = gmotion::grammar::parse(&source)?;
    let (animation, _) = run(scene, &grammar, &RunOptions::default())?;

    let out = root.join("target/examples-out");
    std::fs::create_dir_all(&out)?;
    // The format follows the file name; `time` picks the frame of a single PNG.
    let opts = Options {
        time: animation.duration / 2.0,
        ..Options::default()
    };
    for ext in ["gif", "apng", "png"] {
        let path = out.join(format!("{name}.{ext}"));
        write(&animation, &path, &opts)?;
        println!("wrote {}", path.display());
    }
    println!(
        "{} frames at {} fps",
        animation.frame_count(),
        animation.fps
    );
    Ok(())
}
