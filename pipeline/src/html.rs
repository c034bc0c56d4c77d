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

/// Every shape's final slices as the page's timeline reads them: JSON
/// `{"duration": seconds (the animation's length in whole frames), "tags": [slice tag…], "rows": [[label, t0, dur, tag, …], …]}`,
/// one row per shape in scene order, each slice four numbers (start and length in seconds,
/// the index of its tag, negative-and-minus-one for an inverted slice: `-1 - index`).
/// Compact on purpose: at the intersections scale (8217 shapes) it is what the page must
/// carry for every shape, and the page draws only the rows in view.
pub fn timeline_json(anim: &Animation, x: &Expansion) -> String {
    let mut out = format!(
        r#"{{"duration":{},"tags":{},"rows":["#,
        // The span the Lottie and the SVG beside it play: the duration rounded to whole
        // frames.
        short(anim.length()),
        serde_json::Value::from(x.slice_tags.clone())
    );
    for (i, (slices, shape)) in x.timelines.iter().zip(&anim.scene.shapes).enumerate() {
        if i > 0 {
            out.push(',');
        }
        let label = format!("{}#{}", shape.tag, shape.id);
        let _ = write!(out, "[{}", serde_json::Value::from(label));
        for sl in slices {
            let tag = i64::from(sl.tag);
            let tag = if sl.inverted { -1 - tag } else { tag };
            let _ = write!(out, ",{},{},{tag}", short(sl.t0), short(sl.dur));
        }
        out.push(']');
    }
    out.push_str("]}");
    out
}

/// A time in seconds with at most five decimals (10 µs: far below a pixel of the timeline).
fn short(t: f64) -> String {
    let r = (t * 1e5).round() / 1e5;
    if r == 0.0 {
        "0".to_string()
    } else {
        r.to_string()
    }
}

/// One HTML file showing the animation twice, side by side: lottie-web playing `lottie`
/// (Lottie JSON) and the browser playing `smil` (an animated SVG), with the timeline of
/// every shape's slices ([`timeline_json`]) under them when given: a scrolling list that
/// draws only the rows in view, with a playhead that follows lottie-web. The Lottie player
/// loops when `looping` (the grammar's `loop`), else stops on the last frame. Everything
/// is inline.
pub fn preview_html(
    lottie: &str,
    smil: &str,
    timeline: Option<&str>,
    title: &str,
    looping: bool,
) -> String {
    let smil = smil
        .trim_start()
        .strip_prefix("<?xml")
        .and_then(|s| s.split_once("?>").map(|(_, rest)| rest))
        .unwrap_or(smil);
    let title = escape(title);
    let timeline = timeline.unwrap_or("null");
    format!(
        r#"<!doctype html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font: 14px system-ui, sans-serif; margin: 1em; background: #f4f4f4; }}
.panes {{ display: flex; gap: 1em; flex-wrap: wrap; }}
.pane {{ background: #fff; padding: .5em; border: 1px solid #ccc; }}
.pane > div {{ width: 480px; max-width: 90vw; }}
.pane svg {{ width: 100%; height: auto; }}
#timeline {{ position: relative; width: 800px; max-width: 95vw; max-height: 420px; overflow-y: auto; font: 9px sans-serif; }}
#timeline .row {{ position: absolute; left: 0; right: 0; height: 14px; }}
#timeline .label {{ position: absolute; left: 2px; width: 76px; top: 2px; overflow: hidden; white-space: nowrap; }}
#timeline .slice {{ position: absolute; top: 1px; height: 12px; color: #fff; overflow: hidden; white-space: nowrap; box-sizing: border-box; padding-left: 2px; }}
#timeline .inv {{ background-image: repeating-linear-gradient(45deg, rgba(255,255,255,.45) 0 3px, transparent 3px 6px); }}
#playhead {{ position: absolute; top: 0; width: 2px; background: #e03131; pointer-events: none; z-index: 1; }}
</style></head>
<body>
<h1>{title}</h1>
<div class="panes">
<div class="pane"><h2>Lottie (lottie-web)</h2><div id="lottie"></div><p id="markers"></p></div>
<div class="pane"><h2>Animated SVG (SMIL)</h2><div id="smil">{smil}</div></div>
</div>
<div class="pane" id="timeline-pane" hidden><h2>Timeline <small id="timeline-count"></small></h2><div id="timeline" role="list" aria-label="Timeline: every shape's slices"></div></div>
<script>{player}</script>
<script>
const data = {data};
const anim = lottie.loadAnimation({{ container: document.getElementById('lottie'), renderer: 'svg', loop: {looping}, autoplay: true, animationData: data }});
// The timeline: one row per shape, built only for the rows in view (and a few around), so
// that a scene of thousands of shapes scrolls as lightly as one of ten.
const timeline = {timeline};
if (timeline) {{
  const ROW = 14, LABEL = 80, WIDTH = 720, SPARE = 10;
  const pane = document.getElementById('timeline-pane');
  const view = document.getElementById('timeline');
  pane.hidden = false;
  document.getElementById('timeline-count').textContent = `(${{timeline.rows.length}} shapes)`;
  const inner = document.createElement('div');
  inner.style.height = `${{timeline.rows.length * ROW}}px`;
  inner.style.position = 'relative';
  view.appendChild(inner);
  const head = document.createElement('div');
  head.id = 'playhead';
  head.style.height = `${{timeline.rows.length * ROW}}px`;
  inner.appendChild(head);
  const hue = (tag) => [...tag].reduce((h, c) => (h * 31 + c.charCodeAt(0)) % 360, 0);
  const d = Math.max(timeline.duration, 1e-9);
  const built = new Map();
  const build = (i) => {{
    const r = timeline.rows[i];
    const row = document.createElement('div');
    row.className = 'row';
    row.setAttribute('role', 'listitem');
    row.style.top = `${{i * ROW}}px`;
    const label = document.createElement('span');
    label.className = 'label';
    label.textContent = r[0];
    row.appendChild(label);
    for (let k = 1; k + 2 < r.length; k += 3) {{
      const [t0, dur, code] = [r[k], r[k + 1], r[k + 2]];
      const inverted = code < 0;
      const tag = timeline.tags[inverted ? -1 - code : code] ?? '?';
      const name = inverted ? `inv_${{tag}}` : tag;
      const bar = document.createElement('div');
      bar.className = inverted ? 'slice inv' : 'slice';
      bar.style.left = `${{LABEL + WIDTH * t0 / d}}px`;
      bar.style.width = `${{Math.max(0.5, WIDTH * dur / d)}}px`;
      bar.style.backgroundColor = `hsl(${{hue(tag)}},55%,45%)`;
      bar.title = `${{name}} ${{t0.toFixed(3)}}–${{(t0 + dur).toFixed(3)}} s`;
      bar.textContent = name;
      row.appendChild(bar);
    }}
    return row;
  }};
  const show = () => {{
    const first = Math.max(0, Math.floor(view.scrollTop / ROW) - SPARE);
    const last = Math.min(timeline.rows.length, Math.ceil((view.scrollTop + view.clientHeight) / ROW) + SPARE);
    for (const [i, row] of built) if (i < first || i >= last) {{ row.remove(); built.delete(i); }}
    for (let i = first; i < last; i += 1) if (!built.has(i)) {{ const row = build(i); built.set(i, row); inner.appendChild(row); }}
  }};
  view.addEventListener('scroll', show, {{ passive: true }});
  show();
  const follow = () => {{
    const t = anim.totalFrames > 0 ? anim.currentFrame / anim.frameRate : 0;
    head.style.left = `${{LABEL + WIDTH * Math.min(t / d, 1)}}px`;
    requestAnimationFrame(follow);
  }};
  follow();
}}
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
        timeline = in_script(timeline),
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
                .map(|x| timeline_json(anim, x))
                .as_deref(),
            &format!("gmotion: {title}"),
            anim.looping,
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
