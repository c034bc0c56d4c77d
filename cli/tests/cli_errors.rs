//! Bad input, table-driven, through the real binary: every case exits with status 1 (not a
//! panic's 101), says what and where, and leaves no output file behind.
//!
//! Hostile input (issue 18) too: every case must finish within a time bound (a FIFO must
//! not block, a bomb must not expand), and every file the case starts with must be there
//! afterwards, byte for byte (no input or pre-existing output is ever overwritten).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::support::run_bounded;

const SCENE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect data-tag="s" x="10" y="10" width="20" height="20" fill="red"/>
  <circle data-tag="c" cx="60" cy="40" r="10" fill="blue"/>
</svg>
"#;

const GOOD: &str = "duration 1s\nanimate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n";

const STROKED: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect data-tag="s" x="10" y="10" width="20" height="20" fill="red" stroke="black" stroke-width="2"/>
  <circle data-tag="c" cx="60" cy="40" r="10" fill="blue"/>
</svg>
"#;

const TARGETS: &str = r#"{"fps": 30, "duration": 1, "targets": [{"time": 0, "tag": "s", "id": 0, "attr": "dx", "value": 0}, {"time": 0.5, "tag": "s", "id": 0, "attr": "dx", "value": 20}]}"#;

/// A 2 s Lottie composition of one square.
const LOTTIE: &str = r#"{"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 100, "h": 100, "layers": [{"ddd": 0, "ty": 4, "nm": "sq", "ind": 1, "ip": 0, "op": 60, "st": 0, "ks": {}, "shapes": [{"ty": "rc", "d": 1, "p": {"a": 0, "k": [50, 50]}, "s": {"a": 0, "k": [20, 20]}, "r": {"a": 0, "k": 0}}, {"ty": "fl", "c": {"a": 0, "k": [1, 0, 0, 1]}, "o": {"a": 0, "k": 100}}]}]}"#;

/// The command line most cases run: animate the case's scene and grammar to a PNG.
/// One 800 px square `s`: large enough that a runaway split has room to run away.
const LARGE_SQUARE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="800" height="800"><rect data-tag="s" width="800" height="800"/></svg>"#;

const ANIMATE_PNG: &str = "animate {d}/scene.svg {d}/g.gm -o {d}/out.png";

/// One run of the binary and what must follow from it.
struct Case {
    name: &'static str,
    /// Files to create: (name, contents); `scene.svg` and `g.gm` unless told otherwise.
    files: Vec<(&'static str, Vec<u8>)>,
    /// The arguments, separated by single spaces; `{d}` is replaced by the case directory.
    args: String,
    /// Substrings the error must contain.
    expect: Vec<&'static str>,
    /// Output that must not exist afterwards (relative to the case directory).
    output: &'static str,
    /// Something to set up in the directory first (FIFOs, links, folders); the names it
    /// makes are not strays.
    setup: fn(&Path) -> Vec<&'static str>,
    /// The exit status expected: 1 for errors (2, clap's usage error, counts too), 0 for
    /// inputs that succeed with a warning.
    code: i32,
}

impl Case {
    /// A case running `args` on the default scene and grammar.
    fn new(name: &'static str, args: &str, expect: &[&'static str], output: &'static str) -> Case {
        Case {
            name,
            files: vec![("scene.svg", SCENE.into()), ("g.gm", GOOD.into())],
            args: args.to_string(),
            expect: expect.to_vec(),
            output,
            setup: |_| Vec::new(),
            code: 1,
        }
    }

    /// Replaces (or adds) the file `name`.
    fn file(mut self, name: &'static str, bytes: impl Into<Vec<u8>>) -> Case {
        self.files.retain(|f| f.0 != name);
        self.files.push((name, bytes.into()));
        self
    }

    /// Replaces all starting files.
    fn files(mut self, files: Vec<(&'static str, Vec<u8>)>) -> Case {
        self.files = files;
        self
    }

    fn setup(mut self, setup: fn(&Path) -> Vec<&'static str>) -> Case {
        self.setup = setup;
        self
    }

    /// The case succeeds (with a warning that `expect` names).
    fn succeeds(mut self) -> Case {
        self.code = 0;
        self
    }
}

/// A grammar that fails: animated to a Lottie and a PNG, neither may be left behind.
fn case(name: &'static str, grammar: &str, expect: &[&'static str]) -> Case {
    Case::new(
        name,
        "animate {d}/scene.svg {d}/g.gm -o {d}/out.json -o {d}/out.png",
        expect,
        "out.png",
    )
    .file("g.gm", grammar)
}

/// A scene that fails when animated to a PNG.
fn scene_case(name: &'static str, svg: &[u8], expect: &[&'static str]) -> Case {
    Case::new(name, ANIMATE_PNG, expect, "out.png").file("scene.svg", svg)
}

/// An 800 px scene of one polygon of `vertices` vertices on a circle.
fn round_polygon(vertices: usize) -> String {
    let points: Vec<String> = (0..vertices)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / vertices as f64;
            format!(
                "{:.3},{:.3}",
                400.0 + 390.0 * a.cos(),
                400.0 + 390.0 * a.sin()
            )
        })
        .collect();
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"800\"><polygon data-tag=\"s\" points=\"{}\"/></svg>",
        points.join(" ")
    )
}

/// A scene whose rect (on line 2) sits inside `groups` nested groups, `<svg>` counted as
/// depth 0.
fn nested_groups(groups: usize) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">\n{}<rect data-tag=\"s\" width=\"9\" height=\"9\"/>{}\n</svg>\n",
        "<g>".repeat(groups),
        "</g>".repeat(groups)
    )
}

/// A scene whose one `<text>` (on line 2) holds `spans` `<tspan>`s of `chars` characters.
fn text_svg(spans: usize, chars: usize) -> String {
    let span = format!(
        "<tspan fill=\"blue\">{}</tspan>",
        &"ab c".repeat(chars / 4 + 1)[..chars]
    );
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">\n<text x=\"10\" y=\"20\" font-size=\"12\">{}</text>\n<rect data-tag=\"s\" width=\"10\" height=\"10\"/>\n</svg>",
        span.repeat(spans)
    )
}

fn fifo(dir: &Path, name: &'static str) -> Vec<&'static str> {
    let status = Command::new("mkfifo").arg(dir.join(name)).status().unwrap();
    assert!(status.success(), "mkfifo");
    vec![name]
}

/// `svg` with an `<image>` of `href`, and a picture beside it that it may reference.
fn image_svg(href: &str) -> Vec<u8> {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect data-tag="s" x="10" y="10" width="20" height="20" fill="red"/>
  <image id="pic" href="{href}" width="10" height="10"/>
</svg>
"#
    )
    .into_bytes()
}

/// A PNG of a few dozen bytes whose header declares `width` × `height` pixels (valid
/// checksums, so a decoder believes it and allocates them all).
fn png_bomb(width: u32, height: u32) -> Vec<u8> {
    fn crc(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    fn chunk(out: &mut Vec<u8>, kind: &[u8], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let body: Vec<u8> = kind.iter().chain(data).copied().collect();
        out.extend(&body);
        out.extend(crc(&body).to_be_bytes());
    }
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend(width.to_be_bytes());
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([8, 6, 0, 0, 0]);
    chunk(&mut png, b"IHDR", &ihdr);
    // An empty zlib stream: the pixels never come.
    chunk(
        &mut png,
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    );
    chunk(&mut png, b"IEND", &[]);
    png
}

/// `png` as a `data:` URL.
fn png_url(png: &[u8]) -> String {
    use base64::Engine as _;
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    )
}

/// A Lottie composition showing one image layer of `png`, embedded.
fn lottie_with_image(png: &[u8]) -> Vec<u8> {
    format!(
        r#"{{"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 100, "h": 100, "assets": [{{"id": "image_0", "w": 50, "h": 50, "u": "", "p": "{}", "e": 1}}], "layers": [{{"ddd": 0, "ty": 2, "nm": "pic", "refId": "image_0", "ind": 1, "ip": 0, "op": 60, "st": 0, "ks": {{}}}}, {{"ddd": 0, "ty": 4, "nm": "sq", "ind": 2, "ip": 0, "op": 60, "st": 0, "ks": {{}}, "shapes": [{{"ty": "rc", "d": 1, "p": {{"a": 0, "k": [50, 50]}}, "s": {{"a": 0, "k": [20, 20]}}, "r": {{"a": 0, "k": 0}}}}, {{"ty": "fl", "c": {{"a": 0, "k": [1, 0, 0, 1]}}, "o": {{"a": 0, "k": 100}}}}]}}]}}"#,
        png_url(png)
    )
    .into_bytes()
}

/// A Lottie shape layer of `depth` groups, each repeating the one inside `copies` times.
fn nested_repeaters(depth: usize, copies: usize) -> Vec<u8> {
    let repeater = format!(
        r#"{{"ty": "rp", "c": {{"a": 0, "k": {copies}}}, "o": {{"a": 0, "k": 0}}, "m": 1, "tr": {{"ty": "tr", "p": {{"a": 0, "k": [1, 0]}}, "r": {{"a": 0, "k": 1}}}}}}"#
    );
    let mut items = r#"{"ty": "rc", "d": 1, "p": {"a": 0, "k": [0, 0]}, "s": {"a": 0, "k": [5, 5]}, "r": {"a": 0, "k": 0}}, {"ty": "fl", "c": {"a": 0, "k": [1, 0, 0, 1]}, "o": {"a": 0, "k": 100}}"#.to_string();
    for _ in 0..depth {
        items = format!(r#"{{"ty": "gr", "it": [{items}, {repeater}]}}"#);
    }
    format!(
        r#"{{"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 100, "h": 100, "layers": [{{"ddd": 0, "ty": 4, "nm": "burst", "ind": 1, "ip": 0, "op": 60, "st": 0, "ks": {{}}, "shapes": [{items}]}}]}}"#
    )
    .into_bytes()
}

/// A Lottie file of `layers` shape layers, each an outline of `vertices` vertices with
/// zig-zags of `ridges` ridges a segment.
fn zigzag_bomb(layers: usize, vertices: usize, ridges: f64) -> Vec<u8> {
    let v: Vec<String> = (0..vertices)
        .map(|k| {
            let a = k as f64 / vertices as f64 * std::f64::consts::TAU;
            format!(
                "[{:.3}, {:.3}]",
                50.0 + 40.0 * a.cos(),
                50.0 + 40.0 * a.sin()
            )
        })
        .collect();
    let zero = vec!["[0, 0]"; vertices].join(", ");
    let shape = format!(
        r#"{{"ty": "sh", "ks": {{"a": 0, "k": {{"c": true, "v": [{}], "i": [{zero}], "o": [{zero}]}}}}}}"#,
        v.join(", ")
    );
    let layer = |i: usize| {
        format!(
            r#"{{"ddd": 0, "ty": 4, "nm": "spiky {i}", "ind": {i}, "ip": 0, "op": 60, "st": 0, "ks": {{}}, "shapes": [{shape}, {{"ty": "zz", "s": {{"a": 0, "k": 3}}, "r": {{"a": 0, "k": {ridges}}}, "pt": {{"a": 0, "k": 1}}}}, {{"ty": "fl", "c": {{"a": 0, "k": [1, 0, 0, 1]}}, "o": {{"a": 0, "k": 100}}}}]}}"#
        )
    };
    let layers: Vec<String> = (1..=layers).map(layer).collect();
    format!(
        r#"{{"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 100, "h": 100, "layers": [{}]}}"#,
        layers.join(", ")
    )
    .into_bytes()
}

/// A Lottie file whose image layer links the picture `u` + `p` (`e: 0`).
fn lottie_linking(u: &str, p: &str) -> Vec<u8> {
    String::from_utf8(lottie_with_image(b""))
        .unwrap()
        .replacen(r#""u": """#, &format!(r#""u": "{u}""#), 1)
        .replacen(
            &format!(r#""p": "{}", "e": 1"#, png_url(b"")),
            &format!(r#""p": "{p}", "e": 0"#),
            1,
        )
        .into_bytes()
}

/// `levels` groups, each holding ten `<use>`s of the one before: 10^levels rects from a
/// document of a few kilobytes.
fn use_bomb(levels: usize) -> Vec<u8> {
    let mut s = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100" height="100"><defs><rect id="l0" width="1" height="1" fill="red"/>"#,
    );
    for i in 1..=levels {
        s.push_str(&format!("<g id=\"l{i}\">"));
        for k in 0..10 {
            s.push_str(&format!("<use xlink:href=\"#l{}\" x=\"{k}\"/>", i - 1));
        }
        s.push_str("</g>");
    }
    s.push_str(&format!("</defs><use xlink:href=\"#l{levels}\"/></svg>"));
    s.into_bytes()
}

/// A quadratic entity expansion: a 2 kB entity referenced 1000 times (2 MB of text).
fn entity_bomb() -> Vec<u8> {
    let value = "x".repeat(2000);
    let refs = "&big;".repeat(1000);
    format!(
        r#"<?xml version="1.0"?>
<!DOCTYPE svg [
  <!ENTITY big "{value}">
]>
<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect data-tag="s" width="20" height="20"/>
  <text>{refs}</text>
</svg>
"#
    )
    .into_bytes()
}

/// 200 000 CSS rules in a `<style>` on line 2 (a minute of style resolution unbounded).
fn css_bomb() -> Vec<u8> {
    let rules: String = (0..200_000).map(|i| format!(".c{i}{{fill:red}}")).collect();
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"80\">\n<style>{rules}</style>\n<rect class=\"c1\" width=\"10\" height=\"10\"/></svg>\n"
    )
    .into_bytes()
}

/// A gzip stream of `n` bytes of spaces after an SVG opening (a `.svgz` bomb when large).
fn svgz(n: usize) -> Vec<u8> {
    use std::io::Write;
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    enc.write_all(b"<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'><rect width='5' height='5'/>")
        .unwrap();
    let chunk = vec![b' '; 1 << 16];
    let mut left = n;
    while left > 0 {
        let k = left.min(chunk.len());
        enc.write_all(&chunk[..k]).unwrap();
        left -= k;
    }
    enc.write_all(b"</svg>").unwrap();
    enc.finish().unwrap()
}

/// `cascade(` 10 000 times (an argument may hold 128 kB): a stack overflow before the
/// parser bounded its depth.
/// 2000 large squares, each with a filter that is drawn as an image.
fn many_baked_filters() -> Vec<u8> {
    let mut s = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="1000"><filter id="m"><feMorphology radius="2"/></filter>"#,
    );
    for i in 0..2000 {
        s.push_str(&format!(
            "\n<rect x=\"{}\" y=\"{}\" width=\"900\" height=\"900\" filter=\"url(#m)\"/>",
            i % 10,
            i / 10
        ));
    }
    s.push_str("</svg>");
    s.into_bytes()
}

fn deep_system() -> String {
    "cascade(".repeat(10_000)
}

/// The hostile cases (issue 18), then the plain bad-input ones: a table, one case a line
/// (a builder call after it for what differs from the default scene and grammar).
#[rustfmt::skip]
fn all_cases() -> Vec<Case> {
    let transitions = "transitions {d}/scene.svg {d}/t.json -o {d}/out.json";
    let mut v = vec![
        // 1. Numbers that would crash the renderer: refused with the frame and the shape.
        // The renderer's refusal knows the shape, not the file: the import names the element.
        Case::new("stroke-width 1e10 in the scene", "convert {d}/scene.svg -o {d}/out.png", &["scene.svg: warning: <rect> (line 2): its stroke, 1.000e10 wide,", "out.png", "shape s:0", "±1e8 px"], "out.png")
            .file("scene.svg", STROKED.replace("stroke-width=\"2\"", "stroke-width=\"1e10\"")),
        Case::new("animated stroke-width 1e10", "animate {d}/scene.svg {d}/g.gm -o {d}/out.gif", &["out.gif", "frame 1 ", "shape s:0", "±1e8 px"], "out.gif")
            .file("scene.svg", STROKED)
            .file("g.gm", "duration 1s\nanimate(stroke-width, local, 0, 1e10) : [all, s] -> [m]\n"),
        Case::new("scale(1e10) on a stroked shape", &format!("{ANIMATE_PNG} --time 0.5"), &["out.png", "frame 15 ", "shape s:0", "stroke width, scale or coordinate"], "out.png")
            .file("scene.svg", STROKED)
            .file("g.gm", "duration 1s\nanimate(affine, local, 0, scale(1e10)) : [all, s] -> [m]\n"),
        // 2. Never destructive.
        Case::new("output is the scene", "animate {d}/scene.svg {d}/g.gm -o {d}/scene.svg", &["scene.svg", "refusing to write over an input"], "scene.svg"),
        Case::new("output is the grammar, second of two", "animate {d}/scene.svg {d}/g.gm -o {d}/out.json -o {d}/g.gm", &["g.gm", "refusing to write over an input"], "out.json"),
        Case::new("convert onto itself", "convert {d}/scene.svg -o {d}/scene.svg", &["scene.svg", "refusing to write over an input"], "scene.svg"),
        Case::new("output is the tag map", "animate {d}/scene.svg {d}/g.gm --tags {d}/m.tags -o {d}/m.tags", &["m.tags", "refusing to write over an input"], "m.tags")
            .file("m.tags", "rect -> box\n"),
        Case::new("convert onto its tag map", "convert {d}/scene.svg --tags {d}/m.tags -o {d}/m.tags", &["m.tags", "refusing to write over an input"], "m.tags")
            .file("m.tags", "rect -> box\n"),
        Case::new("check --graph onto the grammar", "check {d}/g.gm --graph {d}/g.gm", &["g.gm", "refusing to write over an input"], "g.gm"),
        Case::new("transitions onto its targets", "transitions {d}/scene.svg {d}/t.json -o {d}/t.json", &["t.json", "refusing to write over an input"], "t.json")
            .files(vec![("scene.svg", SCENE.into()), ("t.json", TARGETS.into())]),
        Case::new("output is a device (through a link)", "convert {d}/scene.svg -o {d}/dev.png", &["dev.png", "a device"], "none").setup(|d| {
            std::os::unix::fs::symlink("/dev/null", d.join("dev.png")).unwrap();
            vec!["dev.png"]
        }),
        Case::new("output is write-protected", "animate {d}/scene.svg {d}/g.gm -o {d}/out.json -o {d}/kept.png", &["kept.png", "write-protected"], "out.json")
            .file("kept.png", "a picture someone keeps")
            .setup(|d| {
                use std::os::unix::fs::PermissionsExt;
                std::fs::set_permissions(d.join("kept.png"), std::fs::Permissions::from_mode(0o444)).unwrap();
                Vec::new()
            }),
        Case::new("output is /dev/full", "convert {d}/scene.svg -o /dev/full", &["/dev/full", "a device"], "none"),
        Case::new(
            "second output fails: the first is not written, the old one kept",
            "animate {d}/scene.svg {d}/g.gm -o {d}/out.json -o {d}/new.svg -o {d}/out.gif",
            &["out.gif", "shape s:0"],
            "new.svg",
        )
        .file("scene.svg", STROKED)
        .file("g.gm", "duration 1s\nanimate(stroke-width, local, 0, 1e10) : [all, s] -> [m]\n")
        .file("out.json", "precious"),
        // 3. File-access policy: refused references are warnings naming the element.
        Case::new(
            "image with an absolute path",
            "convert {d}/scene.svg -o {d}/out.json",
            &["<image id=\"pic\"> (line 3)", "/etc/hostname", "outside the SVG's folder", "--allow-path"],
            "none",
        )
        .file("scene.svg", image_svg("/etc/hostname"))
        .succeeds(),
        Case::new("image escaping with ..", "convert {d}/scene.svg -o {d}/out.json", &["<image id=\"pic\">", "outside the SVG's folder"], "none")
            .file("scene.svg", image_svg("../../../../../../etc/hostname"))
            .succeeds(),
        Case::new("image on /dev/zero", "convert {d}/scene.svg -o {d}/out.json --allow-path /dev", &["<image id=\"pic\">", "/dev/zero", "a device"], "none")
            .file("scene.svg", image_svg("/dev/zero"))
            .succeeds(),
        Case::new("image on a FIFO beside the scene", "convert {d}/scene.svg -o {d}/out.json", &["<image id=\"pic\">", "pipe.png", "a FIFO"], "none")
            .file("scene.svg", image_svg("pipe.png"))
            .setup(|d| fifo(d, "pipe.png"))
            .succeeds(),
        // Filters: every pixel drawn for filters drawn as images counts, and no number
        // in a blur or a shadow reaches the rasteriser unbounded.
        Case::new("thousands of filters drawn as images", "convert {d}/scene.svg -o {d}/out.json", &["filter ignored", "limit of 32000000 pixels", "--limit filter-pixels=N"], "none")
            .file("scene.svg", many_baked_filters())
            .succeeds(),
        Case::new("blur and shadow of 1e9 and 1e30", "convert {d}/scene.svg -o {d}/out.json -o {d}/out.png", &["rlottie"], "out.png")
            .file("scene.svg", r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100"><filter id="f"><feGaussianBlur stdDeviation="1e9"/></filter><filter id="g" x="-1e9" y="-1e9" width="3e9" height="3e9" filterUnits="userSpaceOnUse"><feDropShadow dx="1e30" dy="1e30" stdDeviation="1e20"/></filter><circle cx="50" cy="50" r="20" filter="url(#f)"/><circle cx="50" cy="50" r="10" filter="url(#g)"/></svg>"#)
            .succeeds(),
        // Raster images: a header may declare more pixels than any decoder can allocate
        // (found by the `lottie` fuzz target: 48 × 603 979 904 aborted on allocation).
        Case::new("PNG declaring 100000 x 100000 px in an SVG", "convert {d}/scene.svg -o {d}/out.png -o {d}/out.json", &["scene.svg", "image data not read", "100000 × 100000 pixels", "--limit image-pixels=N"], "out.png")
            .file("scene.svg", image_svg(&png_url(&png_bomb(100_000, 100_000))))
            .succeeds(),
        Case::new("PNG declaring 48 x 603979904 px in a Lottie", "convert {d}/anim.json -o {d}/out.png --time 1", &["anim.json", "$.layers[0]", "48 × 603979904 pixels", "--limit image-pixels=N"], "out.png")
            .files(vec![("anim.json", lottie_with_image(&png_bomb(48, 603_979_904)))])
            .succeeds(),
        // Repeaters in repeaters multiply what they copy: bounded in all.
        Case::new("Lottie repeaters nested four deep, 1000 copies each", "convert {d}/anim.json -o {d}/out.png", &["anim.json", "repeater copies past 50000 repeated items in all are left out"], "out.png")
            .files(vec![("anim.json", nested_repeaters(4, 1000))])
            .succeeds(),
        // A reference time the grammar gives is blamed on its line; the command line's on the file.
        Case::new("reference_time outside the Lottie composition", "animate {d}/anim.json {d}/g.gm -o {d}/out.json", &["g.gm:1:16", "^^^", "anim.json", "the reference time 99s lies outside the composition (0 to 2s)"], "out.json")
            .files(vec![
                ("anim.json", LOTTIE.as_bytes().to_vec()),
                ("g.gm", b"reference_time 99s\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [m]\n".to_vec()),
            ]),
        Case::new("--reference-time outside the Lottie composition", "animate {d}/anim.json {d}/g.gm -o {d}/out.json --reference-time 50", &["anim.json", "the reference time 50s lies outside the composition (0 to 2s)"], "out.json")
            .files(vec![
                ("anim.json", LOTTIE.as_bytes().to_vec()),
                ("g.gm", b"animate(affine, local, 0, rotate(90)) : [all, all] -> [m]\n".to_vec()),
            ]),
        // A Lottie played to SVG draws every frame, as a GIF does: the frames limit holds.
        Case::new("Lottie of 1e8 frames played to SVG", "convert {d}/anim.json -o {d}/out.svg", &["anim.json", "1e8 frames", "--limit frames=N"], "out.svg")
            .files(vec![("anim.json", LOTTIE.replace(r#""op": 60, "w""#, r#""op": 100000000, "w""#).into_bytes())]),
        // Zig-zags multiply an outline's points by their ridge count: bounded in all.
        Case::new("Lottie zig-zags of a billion ridges on outlines of 5000 vertices", "convert {d}/anim.json -o {d}/out.png", &["anim.json", "$.layers[2].shapes", "zig-zags past 2000000 added points in all are drawn with fewer ridges"], "out.png")
            .files(vec![("anim.json", zigzag_bomb(3, 5000, 1e9))])
            .succeeds(),
        // Colour changes copy the precompositions a unit draws: one used many times over at
        // many levels (the lottie fuzz target's find) is copied within a bound.
        Case::new("Lottie precomposition used many times at many levels, recoloured", "animate {d}/anim.json {d}/g.gm -o {d}/out.json", &["out.json", "feudar_Précomp:0", "more than 20000 layers of precompositions to copy with colour changes"], "out.json")
            .files(vec![
                ("anim.json", include_bytes!("../../fuzz/regressions/lottie/precomp-used-many-times-at-many-levels-recoloured.json").to_vec()),
                ("g.gm", b"fps 10\nanimate(fill, local, 0, #3366ff) : [all, all] -> [blue]\n".to_vec()),
            ])
            .succeeds(),
        // A Lottie file's linked images fall under the same policy as an SVG's.
        Case::new("Lottie image linked by an absolute path", "convert {d}/anim.json -o {d}/out.png", &["anim.json", "$.layers[0]", "/etc/hostname", "outside the Lottie file's folder", "--allow-path"], "out.png")
            .files(vec![("anim.json", lottie_linking("/etc/", "hostname"))])
            .succeeds(),
        Case::new("Lottie image linked through ..", "convert {d}/anim.json -o {d}/out.png", &["$.layers[0]", "../../../../../../etc/hostname", "outside the Lottie file's folder"], "out.png")
            .files(vec![("anim.json", lottie_linking("../../../../../../etc/", "hostname"))])
            .succeeds(),
        Case::new("Lottie image linked on /dev/zero", "convert {d}/anim.json -o {d}/out.png --allow-path /dev", &["$.layers[0]", "/dev/zero", "a device"], "out.png")
            .files(vec![("anim.json", lottie_linking("/dev/", "zero"))])
            .succeeds(),
        Case::new("Lottie image linked on a FIFO", "convert {d}/anim.json -o {d}/out.png", &["$.layers[0]", "images/pipe.png", "a FIFO"], "out.png")
            .files(vec![("anim.json", lottie_linking("images/", "pipe.png"))])
            .setup(|d| {
                std::fs::create_dir_all(d.join("images")).unwrap();
                fifo(d, "images/pipe.png");
                vec!["images"]
            })
            .succeeds(),
        Case::new("Lottie image linking a PNG declaring 100000 x 100000 px", "convert {d}/anim.json -o {d}/out.png", &["$.layers[0]", "100000 × 100000 pixels", "--limit image-pixels=N"], "out.png")
            .files(vec![("anim.json", lottie_linking("", "bomb.png")), ("bomb.png", png_bomb(100_000, 100_000))])
            .succeeds(),
        Case::new("Lottie image linking a file that is no picture", "convert {d}/anim.json -o {d}/out.png", &["$.layers[0]", "`notes.png` is not a PNG, JPEG, GIF or WebP image"], "out.png")
            .files(vec![("anim.json", lottie_linking("", "notes.png")), ("notes.png", b"just text".to_vec())])
            .succeeds(),
        // Found by the `svg` fuzz target: usvg follows a ring of gradient references for
        // ever when it is entered from outside the ring.
        Case::new("gradient href ring entered from outside", "convert {d}/scene.svg -o {d}/out.png", &["<linearGradient id=\"b\"> (line 1)", "closes a cycle of references (a → b → a)"], "out.png")
            .file("scene.svg", r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100" height="100"><linearGradient id="a" xlink:href="#b"/><linearGradient id="b" xlink:href="#a"/><linearGradient id="c" xlink:href="#a"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient><rect width="100" height="100" fill="url(#c)"/></svg>"##)
            .succeeds(),
        // Found by the `svg` fuzz target: an entity of two elements used twice gave the
        // importer overlapping edits of the text it hands usvg (a panic).
        Case::new("entity of two elements used twice", "convert {d}/scene.svg -o {d}/out.png", &[], "out.png")
            .file("scene.svg", "<!DOCTYPE svg [<!ENTITY pair \"<rect id='r' width='20' height='20'/><rect id='r' x='40' width='20' height='20'/>\">]><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\"><g id=\"a\">&pair;</g><g id=\"b\" transform=\"translate(0 50)\">&pair;</g></svg>")
            .succeeds(),
        // Found by the `svg` fuzz target: usvg panics placing an image so thin that its
        // fitted side rounds to nothing.
        Case::new("PNG declaring 1207959553 x 1 px in an SVG", "convert {d}/scene.svg -o {d}/out.png", &["image data not read", "1207959553 × 1 pixels"], "out.png")
            .file("scene.svg", image_svg(&png_url(&png_bomb(1_207_959_553, 1))))
            .succeeds(),
        Case::new("PNG declaring 67000000 x 1 px in an SVG", "convert {d}/scene.svg -o {d}/out.png", &["image data not read", "67000000 × 1 pixels, proportions no renderer places"], "out.png")
            .file("scene.svg", image_svg(&png_url(&png_bomb(67_000_000, 1))))
            .succeeds(),
        Case::new("PNG declaring 67000000 x 1 px in a Lottie", "convert {d}/anim.json -o {d}/out.png --time 1", &["anim.json", "$.layers[0]", "67000000 × 1 pixels", "proportions no renderer places"], "out.png")
            .files(vec![("anim.json", lottie_with_image(&png_bomb(67_000_000, 1)))])
            .succeeds(),
        Case::new("image-pixels raised past the rendered image's", "convert {d}/scene.svg -o {d}/out.png --limit image-pixels=1e12", &["out.png", "declares 100000x100000 px", "--limit pixels=N"], "out.png")
            .file("scene.svg", image_svg(&png_url(&png_bomb(100_000, 100_000)))),
        // Inputs are regular files: a FIFO is an error at once, not a hang.
        Case::new("scene is a FIFO", "animate {d}/pipe.svg {d}/g.gm -o {d}/out.png", &["pipe.svg", "a FIFO", "regular files"], "out.png").setup(|d| fifo(d, "pipe.svg")),
        Case::new("grammar is a FIFO", "animate {d}/scene.svg {d}/pipe.gm -o {d}/out.png", &["pipe.gm", "a FIFO"], "out.png").setup(|d| fifo(d, "pipe.gm")),
        Case::new("targets is a FIFO", "transitions {d}/scene.svg {d}/pipe.json -o {d}/out.json", &["pipe.json", "a FIFO"], "out.json").setup(|d| fifo(d, "pipe.json")),
        Case::new("output through a link to the scene", "convert {d}/scene.svg -o {d}/link.svg", &["link.svg", "refusing to write over an input"], "none").setup(|d| {
            std::os::unix::fs::symlink(d.join("scene.svg"), d.join("link.svg")).unwrap();
            vec!["link.svg"]
        }),
        Case::new("output is a directory", "convert {d}/scene.svg -o {d}/dir.png", &["dir.png", "a directory"], "none").setup(|d| {
            std::fs::create_dir(d.join("dir.png")).unwrap();
            vec!["dir.png"]
        }),
        // 4. Limits: each names itself and how to raise it.
        // The flag is blamed, not a line of the grammar: the file holds no such rate.
        Case::new("--fps 1e9", "animate {d}/scene.svg {d}/g.gm -o {d}/out.gif --fps 1e9", &["--fps 1e9 with the duration 1s (", "g.gm:1:1) make 1e9 frames", "--limit frames=N"], "out.gif"),
        Case::new("--fps 1e9, no duration", "animate {d}/scene.svg {d}/g.gm -o {d}/out.gif --fps 1e9", &["--fps 1e9 with the default duration 5s make 5e9 frames", "--limit frames=N"], "out.gif")
            .file("g.gm", "animate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n"),
        case("duration 1e308", "duration 1e308s\nanimate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n", &["g.gm:1:1: error: duration", "frames", "--limit frames=N"]),
        case("fps 1e9 in the grammar", "duration 1s\nfps 1e9\nanimate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n", &["g.gm:2:1: error: duration 1s at 1e9 fps", "--limit frames=N"]),
        Case::new("frames limit lowered", "animate {d}/scene.svg {d}/g.gm -o {d}/out.json --limit frames=5", &["30 frames", "limit of 5"], "out.json"),
        Case::new("--width 16384 gif", "animate {d}/scene.svg {d}/g.gm -o {d}/out.gif --width 16384", &["out.gif", "--limit animation-pixels=N"], "out.gif"),
        Case::new("pixels limit", "convert {d}/scene.svg -o {d}/out.png --width 10000", &["out.png", "--limit pixels=N"], "out.png"),
        Case::new(
            "--max-steps u64::MAX",
            "animate {d}/scene.svg {d}/g.gm -o {d}/out.json --max-steps 18446744073709551615",
            &["--max-steps", "--limit steps=N"],
            "out.json",
        ),
        case(
            "max_steps directive past the limit",
            "duration 1s\nmax_steps 1000000000\nanimate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n",
            &["g.gm:2:1: error: max_steps", "--limit steps=N"],
        ),
        Case::new("unknown limit", "convert {d}/scene.svg -o {d}/out.png --limit wombats=3", &["unknown limit `wombats`", "frames"], "out.png"),
        Case::new("input-bytes limit", "convert {d}/scene.svg -o {d}/out.png --limit input-bytes=100", &["scene.svg", "limit of 100 bytes", "input-bytes"], "out.png"),
        // The picture's size comes from the file: the import says where, the renderer refuses.
        scene_case("canvas of 1e9 px", br#"<svg xmlns="http://www.w3.org/2000/svg" width="1e9" height="100"><rect data-tag="s" width="10" height="10"/></svg>"#, &["scene.svg: warning: <svg> (line 1): its canvas, 1000000000 × 100 px, has 100000000000 pixels", "--limit pixels=N"]),
        scene_case("200 000 CSS rules", &css_bomb(), &["scene.svg", "2:1:", "hold 200000 CSS rules", "more than the limit of 10000", "css-rules"]),
        Case::new("path-segments limit", "convert {d}/scene.svg -o {d}/out.png --limit path-segments=1000", &["scene.svg", "3:3:", "segments (commands of `d`, points of `points`), more than the limit of 1000", "--limit path-segments=N"], "out.png")
            .file("scene.svg", format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">\n  <path d=\"M0 0{}\"/>\n  <path d=\"M0 0{}\"/>\n</svg>", " L1 1".repeat(600), " 2 2".repeat(600))),
        // usvg refuses elements nested past 1 024 with its million-elements error; the
        // message blamed a million elements the file does not hold and named no place.
        scene_case("100 000 nested groups", nested_groups(100_000).as_bytes(), &["scene.svg: 2:3073:", "elements nest more than 1024 deep here (`<g>`)"]),
        // The deepest nesting usvg follows still converts.
        Case::new("groups nested 1 024 deep", "convert {d}/scene.svg -o {d}/out.png", &["wrote"], "out.png").file("scene.svg", nested_groups(1023)).succeeds(),
        scene_case("<use> of <use> seven levels deep (10^7 rects)", &use_bomb(7), &["scene.svg", "of them `<use>`, which usvg counts again", "usvg's element limit of 1 000 000 elements"]),
        // A million and one plain rects, within the default `xml-nodes`: usvg's own element
        // limit, named as such with what the document holds (the message used to blame
        // `<use>` references the file does not have).
        Case::new(
            "a million and one rects",
            "convert {d}/scene.svg -o {d}/out.png",
            &["scene.svg: cannot convert the SVG: the document has 1 000 002 elements: past usvg's element limit of 1 000 000 elements, a fixed limit which no `--limit` raises"],
            "out.png",
        )
        .file("scene.svg", format!(r#"<svg xmlns="http://www.w3.org/2000/svg" width="9" height="9">{}</svg>"#, "<rect width=\"1\" height=\"1\"/>".repeat(1_000_001))),
        Case::new("perturb(1, 1e-300): a lattice without end", "animate {d}/scene.svg {d}/g.gm -o {d}/out.png", &["g.gm", "2:1", "scale 1e-300 is too small for a shape this size"], "out.png")
            .file("g.gm", "duration 1s\nperturb(1, 1e-300) : s -> [p]\n")
            .succeeds(),
        Case::new("streamlineSplit around a centre at 1e300", "animate {d}/scene.svg {d}/g.gm -o {d}/out.png", &[], "out.png")
            .file("g.gm", "duration 1s\nstreamlineSplit(circular, 1, center=(1e300, 0)) : s -> [r]\n")
            .succeeds(),
        case("timesplit with 100 000 fractions (the parser was quadratic in arguments: 22 s)", &format!("duration 1s\ntimesplit({}) : [all, s] -> [a]\n", vec!["0.00001"; 100_000].join(",")), &["g.gm:2:1", "100000 fractions but 1 output tags"]),
        // Found by the `svg` fuzz target: svgtypes cuts an arc into curves by its radius and
        // takes them from the front of a vector, quadratic in their number (hours).
        scene_case("arc reaching 1e37 px", b"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">\n<path d=\"M10 10 A100 150 0 0 0 1e37 5 Z\"/>\n</svg>", &["scene.svg", "2:1:", "an arc of radius 5.000e36 is too large to draw"]),
        // Found by the `svg` fuzz target: usvg lays a text out in time that grows with its
        // spans times its characters (4 000 spans: 42 s).
        scene_case("text of 4 000 spans", text_svg(4000, 2).as_bytes(), &["scene.svg", "2:1:", "4000 elements inside it", "--limit text-spans=N"]),
        scene_case("text of 30 000 characters", text_svg(1, 30_000).as_bytes(), &["scene.svg", "2:1:", "30000 characters", "--limit text-chars=N"]),
        // i_overlay's union of 300 rotated glyphs crossing one another took 44 s in the
        // measure; they are summed as drawn now.
        Case::new("text along a path folded on itself", "convert {d}/scene.svg -o {d}/out.json", &[], "out.json")
            .file("scene.svg", include_bytes!("../../fuzz/regressions/svg/text-on-a-path-of-4000-segments-folded-on-itself.svg").to_vec())
            .succeeds(),
        Case::new("text-chars limit raised", "animate {d}/scene.svg {d}/g.gm -o {d}/out.png --limit text-chars=20000", &[], "out.png")
            .file("scene.svg", text_svg(1, 12_000))
            .succeeds(),
        Case::new("xml-nodes limit", "convert {d}/scene.svg -o {d}/out.png --limit xml-nodes=3", &["scene.svg", "limit of 3 XML nodes", "xml-nodes"], "out.png"),
        scene_case("entity expansion", &entity_bomb(), &["scene.svg", "7:", "XML entities", "xml-entity-bytes"]),
        Case::new("svgz bomb", "convert {d}/scene.svgz -o {d}/out.png", &["scene.svgz", "decompresses to more than the limit", "svgz-bytes"], "out.png")
            .files(vec![("scene.svgz", svgz(80 << 20)), ("g.gm", GOOD.into())]),
        Case::new("--system nested 100000 deep", &format!("{transitions} --system {}", deep_system()), &["--system", "more than 64 deep"], "out.json")
            .files(vec![("scene.svg", SCENE.into()), ("t.json", TARGETS.into())]),
        Case::new("targets' system nested 100000 deep", transitions, &["t.json", "more than 64 deep"], "out.json").files(vec![
            ("scene.svg", SCENE.into()),
            ("t.json", TARGETS.replacen("{", &format!("{{\"system\": \"{}\", ", "cascade(".repeat(100_000)), 1).into_bytes()),
        ]),
        Case::new("targets at 1e308 s", "transitions {d}/scene.svg {d}/t.json -o {d}/out.json", &["t.json", "targets up to 1e308s at 30 fps", "--limit frames=N"], "out.json")
            .files(vec![("scene.svg", SCENE.into()), ("t.json", TARGETS.replace("\"time\": 0.5", "\"time\": 1e308").into_bytes())]),
        // 5. Line endings and encodings.
        case("lone CR line endings", "# a comment\rduration 1s\rwiggle(3) : [all, s] -> [m]\r", &["g.gm:3:1", "wiggle"]),
        case("CRLF line endings", "# a comment\r\nduration 1s\r\nwiggle(3) : [all, s] -> [m]\r\n", &["g.gm:3:1", "wiggle"]),
        case("BOM then an error", "\u{feff}duration 1s\nwiggle(3) : [all, s] -> [m]\n", &["g.gm:2:1", "wiggle"]),
        Case::new("grammar in UTF-16", ANIMATE_PNG, &["g.gm:1:1", "UTF-16"], "out.png").file("g.gm", vec![0xff, 0xfe, b'd', 0, b'u', 0]),
        Case::new("invalid UTF-8 on line 3", ANIMATE_PNG, &["g.gm:3:4", "not UTF-8"], "out.png").file("g.gm", b"duration 1s\n# ok\n# b\xffad\n".to_vec()),
        scene_case("scene in Windows-1252, line 2", b"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\">\n<text>caf\xe9</text><rect id=\"s\" width=\"5\" height=\"5\"/></svg>", &["scene.svg", "2:10:", "not UTF-8", "0xe9"]),
        scene_case("scene in UTF-16", &[0xfe, 0xff, 0, b'<'], &["scene.svg", "1:1:", "UTF-16"]),
    ];
    v.extend(cases());
    v
}

#[rustfmt::skip]
fn cases() -> Vec<Case> {
    vec![
        scene_case("malformed svg", b"<svg xmlns='http://www.w3.org/2000/svg'>\n  <rect width='10'\n</svg>", &["scene.svg", "3:"]),
        scene_case("empty svg file", b"", &["scene.svg"]),
        scene_case("not an svg", b"hello, I am text", &["scene.svg"]),
        scene_case("svg without shapes", b"<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'/>", &["scene.svg: error:", "no visible shapes"]),
        scene_case("zero-size svg", b"<svg xmlns='http://www.w3.org/2000/svg' width='0' height='10'><rect width='5' height='5'/></svg>", &["scene.svg"]),
        case("syntax error", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] [m]\n", &["g.gm:2:", "^", "->"]),
        case("unknown operator", "duration 1s\nwiggle(3) : [all, s] -> [m]\n", &["g.gm:2:1", "unknown", "wiggle"]),
        case("misspelt operator", "duration 1s\nanimat(affine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:1", "did you mean `animate`?"]),
        case("misspelt animation type", "duration 1s\nanimate(afine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:9", "did you mean `affine`?"]),
        case("misspelt reference", "duration 1s\nanimate(affine, wrold, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:17", "did you mean `world`?"]),
        case("camel-case easing", "duration 1s\nanimate(affine, world, 0, translate(1, 0), ease=easeInOut) : [all, s] -> [m]\n", &["g.gm:2:", "did you mean `ease-in-out`?"]),
        case("misspelt spatial operator", "outlin(3) : s -> [a]\n", &["g.gm:1:1", "did you mean `outline`?"]),
        case("pattern naming no shape", "duration 1s\nanimate(affine, world, 0, scale(2)) : [all, btn-*] -> [m]\n", &["g.gm:2:", "matches the pattern `btn-*`"]),
        case("pattern as a slice tag", "duration 1s\ntimesplit(0.5, 0.5) : [a*, s] -> [b, c]\n", &["g.gm:2:24", "is a pattern here"]),
        case("excluding an unknown tag", "duration 1s\nanimate(affine, world, 0, scale(2)) : [all, all - bgg] -> [m]\n", &["g.gm:2:", "unknown shape tag `bgg`"]),
        case("let bound twice", "let q = 1\nlet q = 2\nanimate(affine, world, 0, scale(q)) : [all, s] -> [m]\n", &["g.gm:2:5", "bound twice", "line 1"]),
        case("let renaming a variable", "let cx = 1\nanimate(affine, world, 0, scale(2)) : [all, s] -> [m]\n", &["g.gm:1:5", "a variable every shape has"]),
        case("let growing without bound", &(1..20).fold("let a0 = id\n".to_string(), |g, i| g + &format!("let a{i} = a{} + a{}\n", i - 1, i - 1)), &["g.gm:", "too large"]),
        case("keyframe variable without keyframes", "duration 1s\nanimate(affine, world, 0, translate(10 * u, 0)) : [all, s] -> [m]\n", &["g.gm:2:", "grid=1x1x5"]),
        case("too many keyframes in time", "duration 1s\ngrid 2x2x65\nanimate(affine, world, 0, scale(2)) : [all, s] -> [m]\n", &["g.gm:2:", "NxMxP"]),
        Case::new("a font file that does not exist", "--font-file {d}/none.ttf convert {d}/scene.svg -o {d}/out.png", &["none.ttf", "no such font file"], "out.png"),
        Case::new("standard output without a format", "animate {d}/scene.svg {d}/g.gm -o -", &["--format"], "none"),
        Case::new("a batch into two outputs", "convert {d}/scene.svg {d}/g2.svg -o {d}/a -o {d}/b", &["one -o DIR/"], "a").file("g2.svg", SCENE),
        Case::new("an example that is not bundled", "demo --example nope -o {d}/demo", &["no bundled example `nope`", "toy"], "demo"),
        case("unknown shape tag", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [all, square] -> [m]\n", &["g.gm:2:", "square"]),
        case("unknown slice tag", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [a1l, s] -> [m]\n", &["g.gm:2:", "a1l"]),
        case("fractions do not sum to 1", "duration 1s\ntimesplit(0.5, 0.6) : [all, s] -> [a, b]\n", &["g.gm:2:", "sum to 1"]),
        case("zero fraction", "duration 1s\ntimesplit(0, 1) : [all, s] -> [a, b]\n", &["g.gm:2:", "greater than zero"]),
        case("zero duration", "duration 0s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:1:", "duration"]),
        case("negative duration", "duration -2s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:1:", "duration"]),
        case("nan value", "duration 1s\nanimate(affine, world, 0, translate(sqrt(-1), 0)) : [all, s] -> [m]\n", &["g.gm:2:37", "square root"]),
        case("infinite value", "duration 1s\nanimate(affine, world, 0, translate(1 / 0, 0)) : [all, s] -> [m]\n", &["g.gm:2:"]),
        case("overflowing literal", "duration 1s\nanimate(affine, world, 0, translate(1e999, 0)) : [all, s] -> [m]\n", &["g.gm:2:"]),
        case(
            "never terminates",
            "duration 1s\nmax_steps 40\ntimesplit(0.5, 0.5) : [all, s] -> [x, z]\nanimate(opacity, local, 0, 0.5) : [x, s] -> [y]\nanimate(opacity, local, 0, 1) : [y, s] -> [x]\n",
            &["did not terminate within 40", "line 4", "line 5"],
        ),
        case(
            "splits its own output forever",
            "duration 1s\ntimesplit(0.5, 0.5) : [all, s] -> [x, x]\ntimesplit(0.5, 0.5) : [x, s] -> [x, x]\n",
            &["g.gm:3:1", "slices (at most 10000)", "line 3"],
        ),
        case(
            "a microscopic zig-zag split",
            "duration 1s\nregularSplit(\"M0 0 L0.001 0.001 L0.002 0 L0.003 0.001 L0.004 0\", 12) : s -> [p]\n",
            &["g.gm: warning: 2:1:", "repeats 204003 times", "more than 1000000"],
        )
        // Copies of a 0.004-unit period across an 800 px square asked for 6 GB and a minute.
        .file("scene.svg", LARGE_SQUARE)
        .succeeds(),
        case(
            "a flood of errors",
            &(0..50_000).map(|i| format!("zzzzzzzzzz @@ {i} !!\n")).collect::<String>(),
            &["g.gm:1:1", "g.gm:100:1", "49900 more errors not shown", "50000 errors in"],
        ),
        case(
            "a spatial rule feeding itself",
            "duration 1s\nregularSplit(line, 2) : s -> [s]\n",
            &["pieces in", "`regularSplit` at 2:1", "--limit pieces=N"],
        )
        // A large square: its halves stay splittable for long enough that the work, not the
        // steps, is what runs away (over a minute before the limit on the pieces made).
        .file("scene.svg", LARGE_SQUARE),
        // Outlines of outlines of a 20 000-vertex polygon: few pieces, each costly to cut, so
        // neither the pieces nor the steps bound it (over a minute before); time does.
        Case::new(
            "a spatial rule feeding itself on costly shapes",
            "animate {d}/scene.svg {d}/g.gm -o {d}/out.json --limit spatial-seconds=1",
            &["g.gm: error: spatial expansion ran past the limit of 1 s", "`outline` at 2:1", "--limit spatial-seconds=N"],
            "out.json",
        )
        .file("g.gm", "duration 1s\noutline(5) : s -> [s, s]\n")
        .file("scene.svg", round_polygon(20_000)),
        case(
            "bad value before a cycle",
            "duration 1s\nanimate(opacity, local, 0, 2) : [all, s] -> [x]\nanimate(opacity, local, 0, 0.5) : [x, s] -> [x]\n",
            &["g.gm:2:", "[0, 1]"],
        ),
        case("negative offset", "duration 1s\nanimate(affine, world, -1, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:", "negative"]),
        case("opacity out of range", "duration 1s\nanimate(opacity, local, 0, 3) : [all, s] -> [m]\n", &["g.gm:2:", "[0, 1]"]),
        case("bad colour", "duration 1s\nanimate(fill, local, 0, 12) : [all, s] -> [m]\n", &["g.gm:2:", "colour"]),
        case("bad path data", "duration 1s\nanimate(path, world, 0, \"M 0 0 Q\") : [all, s] -> [m]\n", &["g.gm:2:", "path"]),
        case("wrong argument count", "duration 1s\nanimate(affine, world, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:", "4 arguments"]),
        case("split outputs mismatch", "duration 1s\ntimesplit(0.5, 0.5) : [all, s] -> [a, b, c]\n", &["g.gm:2:", "output"]),
        case("unknown directive", "durration 1s\n", &["g.gm:1:1", "durration"]),
        case("unknown easing", "duration 1s\nanimate(affine, world, 0, translate(1, 0), ease=wobbly) : [all, s] -> [m]\n", &["g.gm:2:", "wobbly"]),
        case("unknown animation type", "duration 1s\nanimate(spin, world, 0, 1) : [all, s] -> [m]\n", &["g.gm:2:", "animation type"]),
        Case::new("grammar not utf-8", ANIMATE_PNG, &["g.gm", "UTF-8"], "out.png").file("g.gm", vec![b'd', 0xff, 0xfe, b'\n']),
        Case::new("missing grammar", "animate {d}/scene.svg {d}/nope.gm -o {d}/out.png", &["nope.gm"], "out.png"),
        Case::new("missing scene", "animate {d}/nope.svg {d}/g.gm -o {d}/out.png", &["nope.svg"], "out.png"),
        Case::new("scene is a directory", "animate {d} {d}/g.gm -o {d}/out.png", &["{d}"], "out.png"),
        Case::new("unwritable output", "animate {d}/scene.svg {d}/g.gm -o {d}/no/such/dir/out.png", &["out.png", "does not exist"], "no"),
        Case::new("unknown output format", "animate {d}/scene.svg {d}/g.gm -o {d}/out.xyz", &["out.xyz", ".xyz"], "out.xyz"),
        Case::new("zero width", &format!("{ANIMATE_PNG} --width 0"), &["width"], "out.png"),
        Case::new("time outside animation", &format!("{ANIMATE_PNG} --time 7"), &["--time"], "out.png"),
        Case::new("zero fps", "animate {d}/scene.svg {d}/g.gm -o {d}/out.gif --fps 0", &["fps"], "out.gif"),
        Case::new("bad tolerance", "animate {d}/scene.svg {d}/g.gm -o {d}/out.json --tolerance 0", &["tolerance"], "out.json"),
        Case::new("convert missing file", "convert {d}/nope.svg -o {d}/out.png", &["nope.svg"], "out.png"),
        Case::new("convert to a frames directory", "convert {d}/scene.svg -o {d}/frames", &["still"], "frames"),
        Case::new("check missing grammar", "check {d}/nope.gm", &["nope.gm"], "nope.gm"),
        Case::new("convert --time on a still SVG", "convert {d}/scene.svg -o {d}/out.png --time 1", &["scene.svg", "--time picks a frame of a Lottie input"], "out.png"),
        Case::new("Lottie --time past the end", "convert {d}/anim.json -o {d}/out.png --time 9", &["--time", "0..2s"], "out.png").file("anim.json", LOTTIE),
        Case::new("Lottie reference time past the end", "check --shapes {d}/anim.json --reference-time 5", &["anim.json", "reference time 5s lies outside the composition"], "none").file("anim.json", LOTTIE),
    ]
}

fn case_dir(i: usize) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-cli-errors-{}-{i}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// How long any case may take: rejected input is rejected quickly (most take
/// milliseconds; the bound is generous for a loaded machine, not a target).
const TIME_BOUND: Duration = Duration::from_secs(20);

#[test]
fn bad_input_is_reported_cleanly() {
    let all = all_cases();
    assert!(all.len() >= 85);
    let mut failures = Vec::new();
    for (i, c) in all.iter().enumerate() {
        let dir = case_dir(i);
        for (name, bytes) in &c.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let made = (c.setup)(&dir);
        let d = dir.display().to_string();
        let args: Vec<String> = c.args.split(' ').map(|a| a.replace("{d}", &d)).collect();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_gmotion"));
        cmd.args(&args);
        let (code, stderr, elapsed) = run_bounded(&mut cmd, TIME_BOUND);
        let mut problems = Vec::new();
        if elapsed > TIME_BOUND {
            problems.push(format!("took {elapsed:?}, more than {TIME_BOUND:?}"));
        }
        let ok_code = if c.code == 1 {
            code == Some(1) || code == Some(2)
        } else {
            code == Some(c.code)
        };
        if !ok_code {
            problems.push(format!(
                "exit status {code:?}, expected {} (1 = error, 2 = usage; anything else is a crash)",
                c.code
            ));
        }
        for (name, bytes) in &c.files {
            if std::fs::read(dir.join(name)).ok().as_deref() != Some(bytes.as_slice()) {
                problems.push(format!("{name} was changed or removed"));
            }
        }
        for e in &c.expect {
            let e = e.replace("{d}", &d);
            if !stderr.contains(&e) {
                problems.push(format!("message lacks `{e}`"));
            }
        }
        if stderr.contains("panicked") {
            problems.push("panicked".into());
        }
        let leftover = Path::new(&dir).join(c.output);
        let mut expected_files: Vec<_> = c.files.iter().map(|f| f.0).collect();
        expected_files.extend(made);
        if c.code == 0 {
            // Succeeding cases write their output; only strays count.
            expected_files.push(c.output);
            expected_files.push("out.json");
        }
        if leftover.exists() && !expected_files.contains(&c.output) {
            problems.push(format!("left {} behind", leftover.display()));
        }
        let stray: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !expected_files.contains(&n.as_str()))
            .collect();
        if !stray.is_empty() {
            problems.push(format!("stray files {stray:?}"));
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{}: {}\n--- stderr ---\n{stderr}",
                c.name,
                problems.join("; ")
            ));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        all.len(),
        failures.join("\n\n")
    );
}

/// An output whose name takes the whole 255 bytes a file name may have is written: its
/// temporary sibling's name is cut to fit instead of failing as too long.
#[test]
fn an_output_name_of_255_bytes_is_written() {
    let dir = case_dir(9_000);
    std::fs::write(dir.join("scene.svg"), SCENE).unwrap();
    std::fs::write(dir.join("g.gm"), GOOD).unwrap();
    let name = format!("{}.json", "é".repeat(125));
    assert_eq!(name.len(), 255);
    let out = dir.join(&name);
    let (code, stderr, _) = run_bounded(
        Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .arg("animate")
            .arg(dir.join("scene.svg"))
            .arg(dir.join("g.gm"))
            .arg("-o")
            .arg(&out),
        TIME_BOUND,
    );
    assert_eq!(code, Some(0), "{stderr}");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.contains(&name), "{names:?}");
    assert_eq!(names.len(), 3, "a temporary file was left: {names:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
