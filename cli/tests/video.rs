//! Video (`-o anim.mp4|webm|mov`) through ffmpeg: the file holds the grammar's frames, at
//! its rate and for its duration, as ffprobe reads them; decoded, they are gmotion's own
//! PNG frames (over the background) at PSNR ≥ 35 dB; transparency is kept where asked and
//! the format has it; a missing or failing ffmpeg leaves no file behind.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("video", name)
}

/// A scene with no backdrop (most of each frame clear) at 24 fps for 1.5 s (36 frames): a
/// square that turns and circles that move and fade, so every frame differs.
fn grammar(dir: &Path) -> PathBuf {
    let svg = dir.join("clear.svg");
    std::fs::write(
        &svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="520" height="320">
<rect data-tag="s" x="60" y="120" width="80" height="80" fill="#e4572e"/>
<circle data-tag="c" cx="220" cy="160" r="26" fill="#17bebb"/>
<circle data-tag="c" cx="290" cy="160" r="26" fill="#2e4057" stroke="#ffc914" stroke-width="6"/>
</svg>"##,
    )
    .unwrap();
    let gm = dir.join("clip.gm");
    std::fs::write(
        &gm,
        format!(
            "scene {}\nduration 1.5s\nfps 24\n\
             animate(affine, local, 0, rotate(90)) : [all, s] -> [turned]\n\
             animate(affine, world, 0, translate(120, 30)) : [all, c] -> [moved]\n\
             animate(opacity, local, 0, 0.4) : [moved, c] -> [faded]\n",
            svg.display()
        ),
    )
    .unwrap();
    gm
}

fn run_ok(cmd: &mut Command) {
    let out = cmd.output().expect("run gmotion");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// ffprobe's `key=value` answers for the first video stream and the container.
fn probe(file: &Path) -> std::collections::HashMap<String, String> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries"])
        .arg("stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames:stream_tags=alpha_mode:format=duration")
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(file)
        .output()
        .expect("run ffprobe");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_once('='))
        .map(|(k, v)| (k.trim_start_matches("TAG:").to_string(), v.to_string()))
        .collect()
}

/// An RGBA picture.
struct Picture {
    width: usize,
    height: usize,
    rgba: Vec<u8>,
}

fn read_png(path: &Path) -> Picture {
    let mut decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
    ));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let channels = info.color_type.samples();
    let rgba = match channels {
        4 => buf,
        3 => buf
            .chunks(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
        n => panic!("{}: {n} channels", path.display()),
    };
    Picture {
        width: info.width as usize,
        height: info.height as usize,
        rgba,
    }
}

/// Decodes `video` into PNG frames `dir/PREFIX_00001.png` on (ffmpeg numbers from 1);
/// `codec` picks a decoder (libvpx-vp9 reads a WebM's alpha, the built-in one drops it).
fn decode(video: &Path, dir: &Path, prefix: &str, codec: Option<&str>) {
    let mut cmd = Command::new("ffmpeg");
    cmd.args(["-v", "error", "-y"]);
    if let Some(c) = codec {
        cmd.args(["-c:v", c]);
    }
    let out = cmd
        .arg("-i")
        .arg(video)
        .args(["-pix_fmt", "rgba"])
        .arg(dir.join(format!("{prefix}_%05d.png")))
        .output()
        .expect("run ffmpeg");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// PSNR (dB) of the decoded frame against gmotion's frame drawn over `bg`, over the
/// gmotion frame's area (padding aside).
fn psnr_over(decoded: &Picture, ours: &Picture, bg: [u8; 3]) -> f64 {
    let mut sum = 0.0;
    for y in 0..ours.height {
        for x in 0..ours.width {
            let o = &ours.rgba[(y * ours.width + x) * 4..][..4];
            let d = &decoded.rgba[(y * decoded.width + x) * 4..][..4];
            let a = f64::from(o[3]) / 255.0;
            for c in 0..3 {
                let want = f64::from(o[c]) * a + f64::from(bg[c]) * (1.0 - a);
                sum += (want - f64::from(d[c])).powi(2);
            }
        }
    }
    let mse = sum / (ours.width * ours.height * 3) as f64;
    10.0 * (255.0f64 * 255.0 / mse.max(1e-12)).log10()
}

#[test]
fn video_holds_the_grammars_frames_at_its_rate_and_draws_them() {
    let dir = out_dir("frames");
    let gm = grammar(&dir);
    let (mp4, webm, mov, frames) = (
        dir.join("c.mp4"),
        dir.join("c.webm"),
        dir.join("c.mov"),
        dir.join("frames"),
    );
    let _ = std::fs::remove_dir_all(&frames);
    run_ok(
        bin()
            .arg("animate")
            .arg(&gm)
            .args(["-o"])
            .arg(&mp4)
            .arg("-o")
            .arg(&webm)
            .arg("-o")
            .arg(&mov)
            .arg("-o")
            .arg(&frames),
    );
    for (video, codec, prefix) in [
        (&mp4, "h264", "m"),
        (&webm, "vp9", "w"),
        (&mov, "prores", "q"),
    ] {
        let p = probe(video);
        assert_eq!(p["codec_name"], codec, "{p:?}");
        assert_eq!(p["nb_read_frames"], "36", "{p:?}");
        assert_eq!(p["r_frame_rate"], "24/1", "{p:?}");
        let duration: f64 = p["duration"].parse().unwrap();
        assert!((duration - 1.5).abs() < 0.5 / 24.0, "{p:?}");
        // The scene is 520 × 320, even: no padding.
        assert_eq!((p["width"].as_str(), p["height"].as_str()), ("520", "320"));
        decode(video, &dir, prefix, None);
        for i in 0..36 {
            let ours = read_png(&frames.join(format!("frame_{i:05}.png")));
            let decoded = read_png(&dir.join(format!("{prefix}_{:05}.png", i + 1)));
            let psnr = psnr_over(&decoded, &ours, [255; 3]);
            assert!(psnr >= 35.0, "{}: frame {i}: {psnr:.1} dB", video.display());
        }
    }
    assert_eq!(probe(&mp4)["pix_fmt"], "yuv420p");
}

#[test]
fn transparency_is_kept_in_webm_and_mov_and_refused_in_mp4() {
    let dir = out_dir("alpha");
    let gm = grammar(&dir);
    let (webm, mov, frames) = (dir.join("a.webm"), dir.join("a.mov"), dir.join("frames"));
    let _ = std::fs::remove_dir_all(&frames);
    run_ok(
        bin()
            .arg("animate")
            .arg(&gm)
            .arg("--transparent")
            .arg("-o")
            .arg(&webm)
            .arg("-o")
            .arg(&mov)
            .arg("-o")
            .arg(&frames),
    );
    assert_eq!(probe(&webm)["alpha_mode"], "1");
    assert!(probe(&mov)["pix_fmt"].starts_with("yuva444p"));
    decode(&webm, &dir, "w", Some("libvpx-vp9"));
    decode(&mov, &dir, "q", None);
    for prefix in ["w", "q"] {
        for i in [0, 17, 35] {
            let ours = read_png(&frames.join(format!("frame_{i:05}.png")));
            let decoded = read_png(&dir.join(format!("{prefix}_{:05}.png", i + 1)));
            // The alpha channel is the frame's: most of the picture is clear, the shapes
            // opaque but for the fading circles.
            let off = ours
                .rgba
                .chunks(4)
                .zip(decoded.rgba.chunks(4))
                .filter(|(o, d)| o[3].abs_diff(d[3]) > 24)
                .count();
            assert!(
                off * 200 < ours.width * ours.height,
                "{prefix} frame {i}: {off} pixels with another alpha"
            );
            assert!(ours.rgba.chunks(4).any(|p| p[3] == 0));
        }
    }
    let mp4 = dir.join("a.mp4");
    let out = bin()
        .arg("animate")
        .arg(&gm)
        .arg("--transparent")
        .arg("-o")
        .arg(&mp4)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("MP4 (H.264) has no transparency"),
        "{err}"
    );
    assert!(!mp4.exists());
}

#[test]
fn an_odd_size_is_padded_on_the_background() {
    let dir = out_dir("odd");
    let gm = grammar(&dir);
    let mp4 = dir.join("odd.mp4");
    run_ok(
        bin()
            .arg("animate")
            .arg(&gm)
            .args(["--width", "101", "--background", "#c00000"])
            .arg("-o")
            .arg(&mp4),
    );
    // 520 × 320 at width 101 is 101 × 62: one column more for 4:2:0.
    let p = probe(&mp4);
    assert_eq!((p["width"].as_str(), p["height"].as_str()), ("102", "62"));
    decode(&mp4, &dir, "o", None);
    let first = read_png(&dir.join("o_00001.png"));
    // The padding column and the clear picture beside it (no shape reaches the right
    // edge) are the background.
    for y in 0..62 {
        let px = &first.rgba[(y * first.width + 101) * 4..][..3];
        assert!(
            px[0] > 160 && px[1] < 60 && px[2] < 60,
            "row {y}: padding {px:?}"
        );
    }
}

#[test]
fn without_ffmpeg_or_when_it_fails_nothing_is_written() {
    let dir = out_dir("errors");
    let gm = grammar(&dir);
    let out = dir.join("x.mp4");
    let res = bin()
        .arg("animate")
        .arg(&gm)
        .arg("-o")
        .arg(&out)
        .env("PATH", "/nonexistent")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(
        !res.status.success()
            && err.contains("writing video needs ffmpeg, which is not on the PATH"),
        "{err}"
    );
    assert!(!out.exists());
    // An ffmpeg that reads a few frames, then fails: its message is quoted, and neither
    // the output nor a temporary file is left.
    let fake = dir.join("fake-ffmpeg.sh");
    std::fs::write(
        &fake,
        "#!/bin/sh\nhead -c 2000000 >/dev/null\necho 'Conversion failed: no space left' >&2\nexit 1\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let json = dir.join("x.json");
    let res = bin()
        .arg("animate")
        .arg(&gm)
        .arg("-o")
        .arg(&json)
        .arg("-o")
        .arg(&out)
        .env("GMOTION_FFMPEG", &fake)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(
        !res.status.success() && err.contains("Conversion failed: no space left"),
        "{err}"
    );
    assert!(
        !out.exists() && !json.exists(),
        "outputs land together or not at all"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}
