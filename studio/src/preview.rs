//! The self-contained HTML preview: lottie-web, the Lottie and the SMIL in one file that
//! plays with the network off (`gmotion animate … -o preview.html`, `gmotion demo`).

use std::path::Path;

use gmotion::{Animation, Warning};
use gmotion_output::{LottieSource, Options, OutputError};

/// lottie-web's player (5.13.0, MIT, vendored from npm; licence in
/// `assets/LICENSE-lottie-web.md`).
pub const LOTTIE_JS: &str = include_str!("../assets/lottie.min.js");

/// Text safe inside a `<script>` element: no `</` that could end it early.
fn in_script(text: &str) -> String {
    text.replace("</", "<\\/")
}

/// One HTML file showing the animation twice, side by side: lottie-web playing `lottie`
/// (Lottie JSON) and the browser playing `smil` (an animated SVG). Everything is inline.
pub fn preview_html(lottie: &str, smil: &str, title: &str) -> String {
    let smil = smil
        .trim_start()
        .strip_prefix("<?xml")
        .and_then(|s| s.split_once("?>").map(|(_, rest)| rest))
        .unwrap_or(smil);
    let title = title
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
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
<div class="pane"><h2>Lottie (lottie-web)</h2><div id="lottie"></div></div>
<div class="pane"><h2>Animated SVG (SMIL)</h2><div id="smil">{smil}</div></div>
</div>
<script>{player}</script>
<script>
const data = {data};
lottie.loadAnimation({{ container: document.getElementById('lottie'), renderer: 'svg', loop: true, autoplay: true, animationData: data }});
</script>
</body></html>
"#,
        player = in_script(LOTTIE_JS),
        data = in_script(lottie),
    )
}

/// Whether `path` names an HTML preview (`.html` or `.htm`).
pub fn is_preview(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"))
}

/// The self-contained preview of `anim` ([`preview_html`]), with what the Lottie and SMIL
/// exporters could not show exactly; `path` is named in errors and gives the title.
pub fn preview_document(
    anim: &Animation,
    source: Option<&LottieSource>,
    path: &Path,
    opts: &Options,
) -> Result<(String, Vec<Warning>), OutputError> {
    let (lottie, mut warnings) = gmotion_output::lottie_text(anim, source, path, opts)?;
    let (smil, more) = gmotion_output::smil_text(anim, source, path, opts)?;
    warnings.extend(more);
    let title = path
        .file_stem()
        .map_or("gmotion".into(), |s| s.to_string_lossy());
    Ok((
        preview_html(&lottie, &smil, &format!("gmotion: {title}")),
        warnings,
    ))
}

/// Writes [`preview_document`] to `path`, whole or not at all ([`gmotion::atomic`]).
pub fn write_preview(
    anim: &Animation,
    source: Option<&LottieSource>,
    path: &Path,
    opts: &Options,
) -> Result<Vec<Warning>, OutputError> {
    let (html, warnings) = preview_document(anim, source, path, opts)?;
    gmotion::atomic::write_bytes(path, html.as_bytes()).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(warnings)
}
