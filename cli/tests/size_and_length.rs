//! Every output the same size and length (docs/formats.md, "Size and duration"): a canvas
//! of fractional size and a duration that is not a whole number of frames give a PNG, a
//! frames folder, a GIF, an APNG, a Lottie, a dotLottie, an SVG, an HTML page and a video of
//! one pixel size, each lasting the duration rounded to whole frames, the art at its own
//! scale and its motion at its own times; `--width W` scales the art by exactly W / width,
//! where Chromium draws the scene at that width.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("size_and_length", name)
}

fn run_ok(cmd: &mut Command) {
    let out = cmd.output().expect("run gmotion");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A 567.4 × 283.6 scene (a backdrop over the whole canvas, a bar that slides) and a grammar
/// of 1.05 s at 30 fps: 31.5 frames, so 32 (1.0667 s) by the rule.
fn fractional(dir: &Path) -> PathBuf {
    std::fs::write(
        dir.join("frac.svg"),
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="567.4" height="283.6" viewBox="0 0 567.4 283.6">
<rect data-tag="back" x="0" y="0" width="567.4" height="283.6" fill="#22aa66"/>
<rect data-tag="bar" x="100" y="100" width="200" height="60" fill="#dd3333"/>
</svg>"##,
    )
    .unwrap();
    let gm = dir.join("frac.gm");
    std::fs::write(
        &gm,
        "scene frac.svg\nduration 1.05s\nfps 30\nloop false\n\
         animate(affine, world, 0, translate(200, 0)) : [all, bar] -> [slid]\n",
    )
    .unwrap();
    gm
}

/// The frames, rate and length the rule gives 1.05 s at 30 fps.
const FRAMES: usize = 32;
const FPS: f64 = 30.0;
const LENGTH: f64 = FRAMES as f64 / FPS;

/// The pixel size the rule gives 567.4 × 283.6: each side rounded half up.
const SIZE: (u32, u32) = (567, 284);

fn json(bytes: &[u8]) -> Value {
    serde_json::from_slice(bytes).expect("JSON")
}

/// The root element's attribute `name` of the SVG text `svg`.
fn root_attr(svg: &str, name: &str) -> String {
    let root = &svg[..svg.find('>').unwrap()];
    let at = root.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
    root[at..at + root[at..].find('"').unwrap()].to_string()
}

/// Every `dur="…s"` of `text`, in seconds.
fn durs(text: &str) -> Vec<f64> {
    text.match_indices(" dur=\"")
        .map(|(at, m)| {
            let rest = &text[at + m.len()..];
            let v = &rest[..rest.find('"').unwrap()];
            v.strip_suffix('s').unwrap().parse().unwrap()
        })
        .collect()
}

/// The Lottie's size, in-point, out-point and rate.
fn lottie_timing(doc: &Value) -> (u64, u64, f64, f64, f64) {
    let n = |k: &str| doc[k].as_f64().unwrap();
    (
        doc["w"].as_u64().unwrap(),
        doc["h"].as_u64().unwrap(),
        n("ip"),
        n("op"),
        n("fr"),
    )
}

/// The largest keyframe time (`"t"`) anywhere in the Lottie, in frames.
fn last_key(v: &Value) -> f64 {
    match v {
        Value::Object(m) => m
            .iter()
            .map(|(k, x)| match (k.as_str(), x.as_f64()) {
                ("t", Some(t)) => t,
                _ => last_key(x),
            })
            .fold(0.0, f64::max),
        Value::Array(a) => a.iter().map(last_key).fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// The GIF's size, frame count and length in seconds (its delays are hundredths).
fn gif_timing(path: &Path) -> ((u32, u32), usize, f64) {
    let mut dec = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(path).unwrap())
        .unwrap();
    let size = (u32::from(dec.width()), u32::from(dec.height()));
    let (mut n, mut hundredths) = (0, 0u32);
    while let Some(f) = dec.read_next_frame().unwrap() {
        n += 1;
        hundredths += u32::from(f.delay);
    }
    (size, n, f64::from(hundredths) / 100.0)
}

/// The APNG's size, frame count and length in seconds.
fn apng_timing(path: &Path) -> ((u32, u32), usize, f64) {
    let mut reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()))
        .read_info()
        .unwrap();
    let size = (reader.info().width, reader.info().height);
    let frames = reader.info().animation_control().unwrap().num_frames as usize;
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let mut seconds = 0.0;
    for _ in 0..frames {
        reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control().copied().unwrap();
        let den = if fc.delay_den == 0 { 100 } else { fc.delay_den };
        seconds += f64::from(fc.delay_num) / f64::from(den);
    }
    (size, frames, seconds)
}

fn png_size(path: &Path) -> (u32, u32) {
    let p = crate::support::pictures::load(path);
    (p.width(), p.height())
}

/// The animation files of the dotLottie at `path` (`a/….json`).
fn packaged_animations(path: &Path) -> Vec<Vec<u8>> {
    use std::io::Read;
    let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut found = Vec::new();
    for i in 0..zip.len() {
        let mut f = zip.by_index(i).unwrap();
        let name = f.name().expect("a UTF-8 name").to_string();
        if name.starts_with("a/") && name.ends_with(".json") {
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes).unwrap();
            found.push(bytes);
        }
    }
    found
}

#[test]
fn a_fractional_canvas_and_duration_are_one_size_and_length_everywhere() {
    let d = out_dir("fractional");
    let gm = fractional(&d);
    let mut cmd = bin();
    cmd.current_dir(&d).arg("animate").arg(&gm);
    for o in [
        "a.png", "a.json", "a.lottie", "a.svg", "a.gif", "a.apng", "a.html", "frames/",
    ] {
        cmd.args(["-o", o]);
    }
    run_ok(&mut cmd);
    let p = |f: &str| d.join(f);

    // Size: 567 × 284 in every output, the art at its own scale (nothing fitted into a
    // rounded side): the backdrop reaches the last column whole and covers only part of the
    // last row (283.6 px of 284).
    assert_eq!(png_size(&p("a.png")), SIZE);
    let png = crate::support::pictures::load(&p("a.png"));
    let alpha = |x, y| png.pixel(x, y).unwrap().alpha();
    assert_eq!((alpha(566, 10), alpha(10, 282)), (255, 255));
    assert!(
        (60..=200).contains(&alpha(10, 283)),
        "the last row is partly covered: {}",
        alpha(10, 283)
    );
    let frames: Vec<PathBuf> = crate::support::files_with_extension(&p("frames"), "png", "");
    assert_eq!(frames.len(), FRAMES, "frames folder");
    for f in &frames {
        assert_eq!(png_size(f), SIZE, "{}", f.display());
    }
    let lottie = std::fs::read(p("a.json")).unwrap();
    let doc = json(&lottie);
    let (w, h, ip, op, fr) = lottie_timing(&doc);
    assert_eq!((w as u32, h as u32), SIZE, "Lottie w, h");
    assert_eq!((op - ip, fr), (FRAMES as f64, FPS), "Lottie op − ip and fr");
    // No stretch onto whole pixels: the layers are the scene's, with no null scaling them.
    let layers = doc["layers"].as_array().unwrap();
    assert!(layers.iter().all(|l| l["ty"] != 3), "a null in {layers:?}");
    // The dotLottie holds that Lottie, byte for byte.
    assert_eq!(
        packaged_animations(&p("a.lottie")),
        std::slice::from_ref(&lottie),
        "dotLottie animation"
    );
    let svg = std::fs::read_to_string(p("a.svg")).unwrap();
    assert_eq!(
        (root_attr(&svg, "width"), root_attr(&svg, "height")),
        (SIZE.0.to_string(), SIZE.1.to_string()),
        "SVG width, height"
    );
    assert_eq!(
        root_attr(&svg, "viewBox"),
        "0 0 567 284",
        "SVG viewBox: scale 1"
    );
    let (gif_size, gif_frames, gif_length) = gif_timing(&p("a.gif"));
    let (apng_size, apng_frames, apng_length) = apng_timing(&p("a.apng"));
    assert_eq!((gif_size, apng_size), (SIZE, SIZE), "GIF, APNG");

    // Length: 32 frames, 1.0667 s, in every output.
    assert_eq!(
        (gif_frames, apng_frames),
        (FRAMES, FRAMES),
        "GIF, APNG frames"
    );
    // GIF delays are whole hundredths adding up to the length rounded to a hundredth.
    assert!((gif_length - LENGTH).abs() <= 0.005, "GIF {gif_length} s");
    assert!((apng_length - LENGTH).abs() < 1e-4, "APNG {apng_length} s");
    assert!(((op - ip) / fr - LENGTH).abs() < 1e-9, "Lottie");
    let smil_durs = durs(&svg);
    assert!(!smil_durs.is_empty(), "the SVG animates");
    for dur in &smil_durs {
        assert!((dur - LENGTH).abs() < 1e-6, "SVG dur {dur} s, not {LENGTH}");
    }
    // The preview page's SVG loops with the Lottie, and its timeline spans the same length.
    let html = std::fs::read_to_string(p("a.html")).unwrap();
    let html_durs = durs(&html);
    assert_eq!(html_durs.len(), smil_durs.len(), "the page's SVG");
    for dur in &html_durs {
        assert!(
            (dur - LENGTH).abs() < 1e-6,
            "HTML dur {dur} s, not {LENGTH}"
        );
    }
    let span: f64 = html
        .split_once("const timeline = {\"duration\":")
        .and_then(|(_, rest)| rest.split(',').next())
        .and_then(|x| x.parse().ok())
        .expect("the page's timeline");
    assert!(
        (span - LENGTH).abs() < 1e-5,
        "timeline {span} s, not {LENGTH}"
    );

    // Only the end moved: the slide still ends at 1.05 s (frame 31.5; key time 1.05 / (32 /
    // 30) = 0.984375 of the SVG's loop).
    assert!((last_key(&doc) - 31.5).abs() < 1e-9, "{}", last_key(&doc));
    assert!(svg.contains("keyTimes=\"0;0.984375;1\""), "{svg}");
    let _ = std::fs::remove_dir_all(&d);
}

/// `--width` and `--height` pick a side; the other side is the canvas's times the scale,
/// rounded half up, and the art is scaled by exactly the given side's ratio in every
/// output: the SVG's viewBox shows the canvas part the pixels hold, where the canvas's own
/// viewBox would fit the art into the rounded side.
#[test]
fn one_side_scales_every_output_by_exactly_its_ratio() {
    let d = out_dir("one-side");
    wide_logo(&d);
    // (flag, size, the viewBox's width and height): 100.9 · 0.5 = 50.45 rows show 100
    // canvas units; 1000 · 33 / 100.9 = 327.06 columns show 327 · 100.9 / 33.
    for (flag, value, size, view_box) in [
        ("--width", "500", (500, 50), (1000.0, 100.0)),
        ("--height", "33", (327, 33), (327.0 * 100.9 / 33.0, 100.9)),
    ] {
        let mut cmd = bin();
        cmd.current_dir(&d)
            .args(["animate", "logo.svg", "logo.gm", flag, value]);
        for o in ["a.png", "a.json", "a.svg", "a.gif"] {
            cmd.args(["-o", o]);
        }
        run_ok(&mut cmd);
        let what = format!("{flag} {value}");
        assert_eq!(png_size(&d.join("a.png")), size, "{what}: PNG");
        assert_eq!(gif_timing(&d.join("a.gif")).0, size, "{what}: GIF");
        let doc = json(&std::fs::read(d.join("a.json")).unwrap());
        let (w, h, ..) = lottie_timing(&doc);
        assert_eq!((w as u32, h as u32), size, "{what}: Lottie");
        let svg = std::fs::read_to_string(d.join("a.svg")).unwrap();
        assert_eq!(
            (root_attr(&svg, "width"), root_attr(&svg, "height")),
            (size.0.to_string(), size.1.to_string()),
            "{what}: SVG"
        );
        let vb: Vec<f64> = root_attr(&svg, "viewBox")
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        assert!(
            vb[..2] == [0.0, 0.0]
                && (vb[2] - view_box.0).abs() < 1e-3
                && (vb[3] - view_box.1).abs() < 1e-3,
            "{what}: SVG viewBox {vb:?}, not {view_box:?}"
        );
        // The SVG as any viewer sizes it (resvg reads its width, height and viewBox),
        // against gmotion's PNG: the same pixels.
        let drawn = gmotion_export_raster::render_sized(&svg, Default::default()).unwrap();
        let png = crate::support::pictures::load(&d.join("a.png"));
        assert_eq!((drawn.width(), drawn.height()), size, "{what}: SVG drawn");
        let off = gmotion_export_raster::compare(&png, &drawn, 8);
        assert!(
            off < 1e-3,
            "{what}: the SVG drawn at its own size is {:.2}% off the PNG",
            off * 100.0
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A wide logo of 1000 × 100.9: a bar from x 100 to 900 and y 10 to 90, a dot that fades.
/// At `--width 500` the bar's right edge is at x 450 and its bottom at y 45; fitted into
/// the rounded height of 50 rows (scale 0.4955, centred) it would end at 448.2 and 44.6.
fn wide_logo(dir: &Path) {
    std::fs::write(
        dir.join("logo.svg"),
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="100.9" viewBox="0 0 1000 100.9">
<rect data-tag="bar" x="100" y="10" width="800" height="80" fill="#1d3557"/>
<circle data-tag="dot" cx="40" cy="50" r="20" fill="#e4572e"/>
</svg>"##,
    )
    .unwrap();
    std::fs::write(
        dir.join("logo.gm"),
        "duration 1s\nfps 10\nloop false\nanimate(opacity, local, 0, 0.5) : [all, dot] -> [faded]\n",
    )
    .unwrap();
}

/// Whether the bar's right and bottom edges are where the scale 0.5 puts them: the last
/// column and row inside it covered, the first outside clear.
#[cfg(feature = "players")]
fn edges_at_half_scale(what: &str, pic: &gmotion_export_raster::Pixmap) {
    let alpha = |x, y| pic.pixel(x, y).unwrap().alpha();
    assert_eq!((pic.width(), pic.height()), (500, 50), "{what}: size");
    assert_eq!(
        [
            alpha(448, 25),
            alpha(449, 25),
            alpha(450, 25),
            alpha(451, 25)
        ],
        [255, 255, 0, 0],
        "{what}: the right edge at x 450"
    );
    assert_eq!(
        [
            alpha(300, 43),
            alpha(300, 44),
            alpha(300, 45),
            alpha(300, 46)
        ],
        [255, 255, 0, 0],
        "{what}: the bottom edge at y 45"
    );
}

/// Where Chromium draws the scene at 500 px wide, gmotion's PNG, its SVG as a viewer sizes
/// it, and its Lottie in every Lottie player draw the bar's edges.
#[cfg(feature = "players")]
#[test]
fn width_lands_edges_where_chromium_draws_them() {
    use crate::support::players::{Player, chromium, frame_path, play};
    let d = out_dir("chromium-width");
    wide_logo(&d);
    run_ok(bin().current_dir(&d).args([
        "animate", "logo.svg", "logo.gm", "--width", "500", "-o", "a.png", "-o", "a.json", "-o",
        "a.svg",
    ]));
    // Chromium draws the scene itself at that width (the reference: a browser's drawing).
    let browser = chromium(&d.join("logo.svg"), 500, &[0.0]);
    edges_at_half_scale("Chromium, the scene", &browser[0]);
    edges_at_half_scale("PNG", &crate::support::pictures::load(&d.join("a.png")));
    let svg = std::fs::read_to_string(d.join("a.svg")).unwrap();
    let drawn = gmotion_export_raster::render_sized(&svg, Default::default()).unwrap();
    edges_at_half_scale("SVG", &drawn);
    let lottie = std::fs::read_to_string(d.join("a.json")).unwrap();
    let played = play("size-width", &lottie, &[0.0], 500, &Player::ALL);
    for p in Player::ALL {
        let pic = crate::support::pictures::load(&frame_path(&played, p, 0.0));
        edges_at_half_scale(&format!("{p:?}"), &pic);
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The Lottie and the SVG of the fractional scene, played in the real players at its 567 px,
/// draw gmotion's own frames, the last one (frame 31, before the loop) included; the MP4
/// holds the 32 frames at 30 fps for 1.0667 s (its sides padded to even, as MP4 needs).
#[cfg(feature = "players")]
#[test]
fn players_and_video_play_the_fractional_scene_to_the_same_end() {
    use crate::support::pictures::{Judge, load};
    use crate::support::players::{Player, chromium, frame_path, play};
    let d = out_dir("fractional-players");
    let gm = fractional(&d);
    run_ok(bin().current_dir(&d).arg("animate").arg(&gm).args([
        "-o", "a.json", "-o", "a.svg", "-o", "frames/", "-o", "a.mp4",
    ]));
    let frames = [0.0, 16.0, 31.0];
    let lottie = std::fs::read_to_string(d.join("a.json")).unwrap();
    let played = play("size-fractional", &lottie, &frames, SIZE.0, &Player::ALL);
    let times: Vec<f64> = frames.iter().map(|f| f / FPS).collect();
    let smil = chromium(&d.join("a.svg"), SIZE.0, &times);
    let mut judge = Judge::new(0.005);
    for (k, f) in frames.iter().enumerate() {
        let ours = load(&d.join(format!("frames/frame_{:05}.png", *f as usize)));
        for p in Player::ALL {
            judge.close(
                &format!("{p:?} frame {f}"),
                &ours,
                &load(&frame_path(&played, p, *f)),
            );
        }
        judge.close(&format!("SVG in Chromium frame {f}"), &ours, &smil[k]);
    }
    judge.assert_all_close(&played);

    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=width,height,r_frame_rate,nb_read_frames:format=duration",
        ])
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(d.join("a.mp4"))
        .output()
        .expect("run ffprobe");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let get = |k: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("{k}=")))
            .unwrap_or_else(|| panic!("{k} in {text}"))
            .to_string()
    };
    assert_eq!(get("nb_read_frames"), FRAMES.to_string(), "{text}");
    assert_eq!(get("r_frame_rate"), "30/1", "{text}");
    let duration: f64 = get("duration").parse().unwrap();
    assert!((duration - LENGTH).abs() < 1e-3, "{text}");
    // 4:2:0 needs even sides: 567 gets a column of the background, 284 stays.
    assert_eq!(
        (get("width"), get("height")),
        ("568".into(), "284".into()),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// A Lottie scene whose `op` After Effects wrote with float noise (60.0000024 at 29.97 fps)
/// is 60 frames long: a grammar that sets no duration keeps the composition as it is (no
/// cut, no warning), and the SVG lasts its 60 frames.
#[test]
fn a_lottie_length_with_float_noise_is_whole_frames() {
    let d = out_dir("lottie-noise");
    let (fr, op) = (29.970_001_220_703_1, 60.000_002_443_850_1);
    std::fs::write(
        d.join("src.json"),
        format!(
            r#"{{"v":"5.7.0","fr":{fr},"ip":0,"op":{op},"w":200,"h":100,"layers":[{{"ty":4,"nm":"box","ind":1,"ip":0,"op":{op},"st":0,"ks":{{"o":{{"a":0,"k":100}},"r":{{"a":0,"k":0}},"p":{{"a":0,"k":[100,50]}},"a":{{"a":0,"k":[0,0]}},"s":{{"a":0,"k":[100,100]}}}},"shapes":[{{"ty":"gr","nm":"g","it":[{{"ty":"rc","p":{{"a":0,"k":[0,0]}},"s":{{"a":0,"k":[80,40]}},"r":{{"a":0,"k":0}}}},{{"ty":"fl","c":{{"a":0,"k":[1,0,0,1]}},"o":{{"a":0,"k":100}}}},{{"ty":"tr","p":{{"a":0,"k":[0,0]}},"a":{{"a":0,"k":[0,0]}},"s":{{"a":0,"k":[100,100]}},"r":{{"a":0,"k":0}},"o":{{"a":0,"k":100}}}}]}}]}}]}}"#
        ),
    )
    .unwrap();
    std::fs::write(
        d.join("turn.gm"),
        "loop false\nanimate(affine, local, 0, rotate(30)) : [all, box] -> [turned]\n",
    )
    .unwrap();
    let out = bin()
        .current_dir(&d)
        .args([
            "animate", "src.json", "turn.gm", "-o", "a.json", "-o", "a.svg",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("warning"), "{err}");
    let doc = json(&std::fs::read(d.join("a.json")).unwrap());
    assert_eq!(doc["op"].as_f64(), Some(op), "the composition kept");
    let svg = std::fs::read_to_string(d.join("a.svg")).unwrap();
    assert!(!durs(&svg).is_empty(), "the SVG animates");
    for dur in durs(&svg) {
        assert!((dur - 60.0 / fr).abs() < 1e-6, "SVG dur {dur} s");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A canvas past the `pixels` limit is worth a warning only when an output is drawn at its
/// size: with `--width` (or the grammar's `width`) no image is, and the warning (which asks
/// for `--width`) would be wrong.
#[test]
fn a_huge_canvas_is_warned_of_only_when_drawn_at_its_size() {
    let dir = out_dir("huge_canvas");
    let scene = dir.join("huge.svg");
    std::fs::write(
        &scene,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100000" height="50000" viewBox="0 0 100 50"><rect data-tag="s" width="10" height="10"/></svg>"#,
    )
    .unwrap();
    let gm = dir.join("g.gm");
    let run = |args: &[&str], grammar: &str| {
        std::fs::write(&gm, grammar).unwrap();
        let out = bin().args(args).output().expect("run gmotion");
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(out.status.success(), "{args:?}: {stderr}");
        stderr.contains("more than the limit of")
    };
    let (s, g) = (scene.to_str().unwrap(), gm.to_str().unwrap());
    let png = dir.join("out.png");
    let p = png.to_str().unwrap();
    let json = dir.join("out.json");
    let j = json.to_str().unwrap();
    let move_it = "animate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n";
    assert!(run(&["convert", s, "-o", j], ""), "no output size: warned");
    assert!(!run(&["convert", s, "-o", p, "--width", "64"], ""));
    assert!(!run(&["convert", s, "-o", p, "--height", "32"], ""));
    assert!(!run(&["animate", s, g, "-o", j, "--width", "64"], move_it));
    let sized = format!("width 64\n{move_it}");
    assert!(
        !run(&["animate", s, g, "-o", p], &sized),
        "the grammar's width"
    );
    assert!(run(&["animate", s, g, "-o", j], move_it));
    assert_eq!(png_size(&png), (64, 32));
}
