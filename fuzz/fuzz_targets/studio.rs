//! The studio's HTTP server without its socket: any bytes, as one connection's input, read
//! by its request parser and answered by its routes (`Studio::answer`), edits included, on
//! a fresh studio each time (a small scene and grammar in a temporary folder). In the
//! input, `TOKEN` stands for the session's token and `HOST` for `127.0.0.1:PORT`, so that
//! the fuzzer reaches the API behind the token and `Host` checks. Every answer must be an
//! HTTP/1.1 status line with a status the studio documents.
//!
//! Inputs asking for a GIF are left out: a valid grammar may ask for thousands of frames,
//! which the limits allow and which take seconds by design, not by a bug.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use gmotion::engine::RunOptions;
use gmotion_import_svg::ImportOptions;
use gmotion_pipeline::Imported;
use gmotion_studio::{Config, Studio};
use libfuzzer_sys::fuzz_target;

/// Three shapes of two tags.
const SCENE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="60">
<rect data-tag="s" x="10" y="10" width="30" height="30" fill="#e4572e"/>
<circle data-tag="c" cx="70" cy="25" r="12" fill="#17bebb"/>
<circle data-tag="c" cx="100" cy="25" r="12" fill="#17bebb"/>
</svg>"##;

/// A short grammar on it (few frames, so that exports stay quick).
const GRAMMAR: &str = "duration 1s\nfps 6\n\
timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]\n\
animate(affine, world, 0, translate(40, 0), ease=ease-in-out) : [a, s] -> [tran]\n\
animate(affine, local, 0.1 * id, rotate(90)) : [a, c] -> [spin]\n";

/// The statuses the studio answers with (docs/studio.md).
const STATUSES: [u16; 15] = [
    200, 400, 403, 404, 405, 408, 409, 411, 413, 422, 431, 500, 501, 503, 505,
];

/// The folder the studio's grammar file lives in.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("gmotion-fuzz-studio-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        dir
    })
}

fuzz_target!(|data: &[u8]| {
    if data.windows(3).any(|w| w.eq_ignore_ascii_case(b"gif")) {
        return;
    }
    let grammar_path = folder().join("studio.gm");
    std::fs::write(&grammar_path, GRAMMAR).expect("the grammar is written");
    let scene = gmotion_import_svg::parse(SCENE, "scene.svg", &ImportOptions::default())
        .expect("the fixed scene imports")
        .scene;
    let studio = Studio::bind(Config {
        grammar_path,
        imported: Imported {
            scene,
            source: None,
            package: None,
        },
        rescene: None,
        run: RunOptions::default(),
        port: 0,
    })
    .expect("the studio binds");
    let url = studio.url();
    let token = url.rsplit_once("token=").expect("a token in the address").1;
    let host = format!("127.0.0.1:{}", studio.port());
    let input = replace(&replace(data, b"TOKEN", token.as_bytes()), b"HOST", host.as_bytes());
    let out = studio.answer(&input);
    if out.is_empty() {
        return;
    }
    let status = out
        .strip_prefix(b"HTTP/1.1 ")
        .and_then(|rest| std::str::from_utf8(rest.get(..3)?).ok()?.parse::<u16>().ok())
        .unwrap_or_else(|| panic!("not a status line: {:?}", String::from_utf8_lossy(&out)));
    assert!(STATUSES.contains(&status), "status {status}");
});

/// `data` with every `from` replaced by `to`.
fn replace(data: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len());
    let mut i = 0;
    while i < data.len() {
        if data[i..].starts_with(from) {
            out.extend_from_slice(to);
            i += from.len();
        } else {
            out.push(data[i]);
            i += 1;
        }
    }
    out
}
