//! `cargo xtask COMMAND`: regenerates files committed to the repository.
//!
//! - `transitions [DIR]`: the transitions examples (`histogram`, `permutation`,
//!   `revisions`: an SVG scene and a `.targets.json` each) into DIR (default `grammars/`);
//! - `gallery [DIR]`: the gMotion gallery's scenes and the intersections grammars into DIR
//!   (default `grammars/`);
//! - `plots [DIR]`: the signal plots of the README into DIR (default `docs/img/`).
#![forbid(unsafe_code)]

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = |default: &str| {
        args.get(1)
            .map_or_else(|| root.join(default), PathBuf::from)
    };
    let written: Result<Vec<PathBuf>, String> = match args.first().map(String::as_str) {
        Some("transitions") => xtask::examples()
            .map_err(|e| e.to_string())
            .and_then(|exs| {
                let out = dir("grammars");
                let mut files = Vec::new();
                for ex in exs {
                    let (svg, json) = ex
                        .write(&out)
                        .map_err(|e| format!("{}: {e}", out.display()))?;
                    files.extend([svg, json]);
                }
                Ok(files)
            }),
        Some("gallery") => {
            let out = dir("grammars");
            xtask::gallery::files()
                .into_iter()
                .map(|f| {
                    let path = out.join(&f.name);
                    gmotion::atomic::write_bytes(&path, f.text.as_bytes())
                        .map(|()| path)
                        .map_err(|e| format!("{}: {e}", out.join(&f.name).display()))
                })
                .collect()
        }
        Some("plots") => xtask::plot::transition_plots(&dir("docs/img")).map_err(|e| e.to_string()),
        _ => Err("usage: cargo xtask transitions|gallery|plots [DIR]".to_string()),
    };
    match written {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}
