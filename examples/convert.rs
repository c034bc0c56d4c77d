//! A still SVG to Lottie, no grammar: what `gmotion convert in.svg -o out.json` does. Run
//! with `cargo run --example convert [IN.svg]` (default `grammars/cube.svg`); it writes
//! `target/examples-out/convert.json` and a PNG of gmotion's own render beside it.

use std::path::{Path, PathBuf};

use gmotion_import_svg::{ImportOptions, load};
use gmotion_output::{Options, write_still};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = std::env::args()
        .nth(1)
        .map_or_else(|| root.join("grammars/cube.svg"), PathBuf::from);
    let imported = load(&input, &ImportOptions::default())?;
    for w in &imported.warnings {
        eprintln!("{}: warning: {w}", input.display());
    }
    let out = root.join("target/examples-out");
    std::fs::create_dir_all(&out)?;
    for name in ["convert.json", "convert.png"] {
        let path = out.join(name);
        for w in write_still(&imported.scene, &path, &Options::default())? {
            eprintln!("{}: warning: {w}", path.display());
        }
        println!("wrote {}", path.display());
    }
    Ok(())
}
