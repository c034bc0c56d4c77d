//! The self-contained HTML page: lottie-web, the Lottie and the SMIL in one file that
//! plays with the network off (`gmotion animate … -o preview.html`, `gmotion demo`, the
//! studio's export). It sits here, over the Lottie and SMIL writers, because it joins
//! both with the run's timelines.

use std::path::Path;

use std::fmt::Write as _;

use gmotion::engine::expand::Expansion;
use gmotion::{Animation, Warning};
use gmotion_output::{Options, OutputError};

use crate::write::Rendered;

/// lottie-web's player (5.13.0, MIT, vendored from npm; licence in
/// `assets/LICENSE-lottie-web.md`).
pub const LOTTIE_JS: &str = include_str!("../assets/lottie.min.js");

/// Text safe inside a `<script>` element: no `</` that could end it early.
fn in_script(text: &str) -> String {
    text.replace("</", "<\\/")
}

/// Text safe in HTML and XML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The most shape rows a timeline picture draws.
const TIMELINE_ROWS: usize = 200;

/// A picture of every shape's final slices (one row per shape, the first 200; bars
/// coloured by slice tag and labelled with it, inverted slices hatched), with a playhead
/// that runs with the animation (SMIL, looping when the animation loops).
pub fn timeline_svg(anim: &Animation, x: &Expansion) -> String {
    const LABEL: f64 = 80.0;
    const WIDTH: f64 = 720.0;
    const ROW: f64 = 14.0;
    // The playhead loops with the Lottie and the SVG beside it: over the duration rounded
    // to whole frames.
    let d = anim.length().max(1e-9);
    let rows = x.timelines.len().min(TIMELINE_ROWS);
    let height = rows as f64 * ROW;
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{height}" font-family="sans-serif" font-size="9"><defs><pattern id="inv" width="6" height="6" patternUnits="userSpaceOnUse" patternTransform="rotate(45)"><rect width="3" height="6" fill="#fff" fill-opacity="0.45"/></pattern></defs>"##,
        LABEL + WIDTH
    );
    for (i, (slices, shape)) in x
        .timelines
        .iter()
        .zip(&anim.scene.shapes)
        .take(rows)
        .enumerate()
    {
        let y = i as f64 * ROW;
        let _ = write!(
            svg,
            r#"<text x="2" y="{}">{}#{}</text>"#,
            y + 10.0,
            escape(&shape.tag),
            shape.id
        );
        for sl in slices {
            let tag = x
                .slice_tags
                .get(sl.tag as usize)
                .map_or("?", String::as_str);
            let hue = tag.bytes().fold(0u32, |h, b| (h * 31 + u32::from(b)) % 360);
            let (bx, bw) = (LABEL + WIDTH * sl.t0 / d, (WIDTH * sl.dur / d).max(0.5));
            let name = if sl.inverted {
                format!("inv_{tag}")
            } else {
                tag.to_string()
            };
            let _ = write!(
                svg,
                r#"<g><title>{name} {:.3}–{:.3} s</title><rect x="{bx:.2}" y="{:.1}" width="{bw:.2}" height="{:.1}" fill="hsl({hue},55%,45%)"/>"#,
                sl.t0,
                sl.t0 + sl.dur,
                y + 1.0,
                ROW - 2.0
            );
            if sl.inverted {
                let _ = write!(
                    svg,
                    r#"<rect x="{bx:.2}" y="{:.1}" width="{bw:.2}" height="{:.1}" fill="url(#inv)"/>"#,
                    y + 1.0,
                    ROW - 2.0
                );
            }
            let _ = write!(
                svg,
                r##"<text x="{:.2}" y="{}" fill="#fff">{}</text></g>"##,
                bx + 2.0,
                y + 10.0,
                escape(&name)
            );
        }
    }
    let repeat = if anim.looping { "indefinite" } else { "1" };
    let _ = write!(
        svg,
        r##"<line x1="{LABEL}" x2="{LABEL}" y1="0" y2="{height}" stroke="#e03131" stroke-width="2"><animate attributeName="x1" from="{LABEL}" to="{e}" dur="{d}s" repeatCount="{repeat}" fill="freeze"/><animate attributeName="x2" from="{LABEL}" to="{e}" dur="{d}s" repeatCount="{repeat}" fill="freeze"/></line></svg>"##,
        e = LABEL + WIDTH
    );
    svg
}

/// One HTML file showing the animation twice, side by side: lottie-web playing `lottie`
/// (Lottie JSON) and the browser playing `smil` (an animated SVG), with `timeline` (an
/// SVG picture, [`timeline_svg`]) under them when given. Everything is inline.
pub fn preview_html(lottie: &str, smil: &str, timeline: Option<&str>, title: &str) -> String {
    let smil = smil
        .trim_start()
        .strip_prefix("<?xml")
        .and_then(|s| s.split_once("?>").map(|(_, rest)| rest))
        .unwrap_or(smil);
    let title = escape(title);
    let timeline = timeline.map_or(String::new(), |t| {
        format!(r#"<div class="pane"><h2>Timeline</h2>{t}</div>"#)
    });
    format!(
        r#"<!doctype html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font: 14px system-ui, sans-serif; margin: 1em; background: #f4f4f4; }}
.panes {{ display: flex; gap: 1em; flex-wrap: wrap; }}
.pane {{ background: #fff; padding: .5em; border: 1px solid #ccc; }}
.pane > div {{ width: 480px; max-width: 90vw; }}
.pane svg {{ width: 100%; height: auto; }}
</style></head>
<body>
<h1>{title}</h1>
<div class="panes">
<div class="pane"><h2>Lottie (lottie-web)</h2><div id="lottie"></div><p id="markers"></p></div>
<div class="pane"><h2>Animated SVG (SMIL)</h2><div id="smil">{smil}</div></div>
</div>
{timeline}
<script>{player}</script>
<script>
const data = {data};
const anim = lottie.loadAnimation({{ container: document.getElementById('lottie'), renderer: 'svg', loop: true, autoplay: true, animationData: data }});
// A button per marker (the grammar's `markers`, or a Lottie scene's own) loops its span.
const buttons = document.getElementById('markers');
const button = (label, play) => {{
  const b = document.createElement('button');
  b.textContent = label;
  b.onclick = play;
  buttons.appendChild(b);
}};
if ((data.markers || []).length) {{
  button('all', () => {{ anim.resetSegments(true); anim.goToAndPlay(0, true); }});
  for (const m of data.markers) button(m.cm, () => anim.playSegments([m.tm, m.tm + m.dr], true));
}}
</script>
</body></html>
"#,
        player = in_script(LOTTIE_JS),
        data = in_script(lottie),
    )
}

/// Whether `path` names an HTML page (`.html` or `.htm`).
pub fn is_page(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"))
}

/// The self-contained page of `r` ([`preview_html`]; the timeline picture when the run
/// kept its timelines), with what the Lottie and SMIL exporters could not show exactly;
/// `path` is named in errors and gives the title.
pub fn page(
    r: &Rendered,
    path: &Path,
    opts: &Options,
) -> Result<(String, Vec<Warning>), OutputError> {
    let (anim, source) = (&r.anim, r.source.as_deref());
    let (lottie, mut warnings) = gmotion_output::lottie_text(anim, source, &r.markers, path, opts)?;
    let (smil, more) = gmotion_output::smil_text(anim, source, path, opts)?;
    warnings.extend(more);
    let title = path
        .file_stem()
        .map_or("gmotion".into(), |s| s.to_string_lossy());
    Ok((
        preview_html(
            &lottie,
            &smil,
            r.timelines
                .as_ref()
                .map(|x| timeline_svg(anim, x))
                .as_deref(),
            &format!("gmotion: {title}"),
        ),
        warnings,
    ))
}

/// Writes [`page`] to `path`, whole or not at all ([`gmotion::atomic`]).
pub fn write_page(r: &Rendered, path: &Path, opts: &Options) -> crate::Result<Vec<Warning>> {
    let (html, warnings) = page(r, path, opts)?;
    gmotion::atomic::write_bytes(path, html.as_bytes()).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(warnings)
}
