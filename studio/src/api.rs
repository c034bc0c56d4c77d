//! The HTTP routes: the page, lottie-web, and the JSON API (see `docs/studio.md`). Bad
//! input is answered 4xx, never a panic.

use std::sync::Arc;

use gmotion::canvas::OutputSize;
use serde_json::json;

use crate::gate::Gate;
use crate::http::{Request, Response};
use crate::live::{Built, Live, MAX_MERGE_LINES, MergeError, Resolution, SaveError};

/// What every request thread shares.
#[derive(Debug)]
pub(crate) struct Ctx {
    pub live: Arc<Live>,
    pub port: u16,
    pub token: String,
    /// What frames, the Lottie document, rules and edits take a pass from.
    pub work: Gate,
    /// What whole exports (downloads, SMIL) take a pass from, one at a time: a GIF of a
    /// long animation takes seconds, and frames and edits do not queue behind it.
    pub exports: Gate,
}

/// The page: one HTML file with its JS and CSS inline.
const PAGE: &str = include_str!("../assets/studio.html");

/// An answer: status, content type, bytes, and a download name.
struct Reply {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
    download: Option<&'static str>,
    /// The methods a route allows, sent with a 405.
    allow: Option<&'static str>,
}

impl Reply {
    fn ok(kind: &'static str, body: impl Into<Vec<u8>>) -> Reply {
        Reply {
            status: 200,
            kind,
            body: body.into(),
            download: None,
            allow: None,
        }
    }

    fn json(v: &serde_json::Value) -> Reply {
        Reply::ok("application/json", v.to_string())
    }

    fn error(status: u16, message: &str) -> Reply {
        Reply {
            status,
            kind: "application/json",
            body: json!({ "error": message }).to_string().into_bytes(),
            download: None,
            allow: None,
        }
    }

    /// A 405 naming the methods `allow`ed.
    fn not_allowed(allow: &'static str) -> Reply {
        Reply {
            allow: Some(allow),
            ..Reply::error(405, "method not allowed")
        }
    }
}

/// The value of query parameter `name` in `query` (no percent-decoding: the API's values
/// are numbers and hex).
fn param<'a>(query: &'a str, name: &str) -> Option<&'a str> {
    query
        .split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == name)
        .map(|(_, v)| v)
}

/// Compares in time that depends on the lengths only, not on where the first difference
/// is (the token's length is no secret: 32 hex digits); `black_box` keeps the optimiser
/// from turning the fold back into an early exit.
fn same(a: &str, b: &str) -> bool {
    let diff = a
        .bytes()
        .zip(b.bytes())
        .fold(0u8, |d, (x, y)| d | std::hint::black_box(x ^ y));
    a.len() == b.len() && std::hint::black_box(diff) == 0
}

/// Answers one request.
pub(crate) fn handle(ctx: &Ctx, request: &Request) -> Response {
    let reply = route(ctx, request);
    let mut headers = vec![
        ("Content-Type", reply.kind.to_string()),
        ("Cache-Control", "no-store".to_string()),
        ("X-Content-Type-Options", "nosniff".to_string()),
        // The page may talk to its own server only.
        (
            "Content-Security-Policy",
            "default-src 'self'; script-src 'self' 'unsafe-inline' 'unsafe-eval'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; connect-src 'self'"
                .to_string(),
        ),
    ];
    if let Some(methods) = reply.allow {
        headers.push(("Allow", methods.to_string()));
    }
    if let Some(name) = reply.download {
        headers.push((
            "Content-Disposition",
            format!("attachment; filename=\"{name}\""),
        ));
    }
    Response {
        status: reply.status,
        headers,
        body: reply.body,
    }
}

fn route(ctx: &Ctx, request: &Request) -> Reply {
    let host_ok = request.header("Host").is_some_and(|h| {
        h == format!("127.0.0.1:{}", ctx.port) || h == format!("localhost:{}", ctx.port)
    });
    if !host_ok {
        return Reply::error(
            403,
            "forbidden: the Host must be 127.0.0.1:PORT or localhost:PORT",
        );
    }
    let url = request.target.as_str();
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    let method = request.method.as_str();
    match (method, path) {
        ("GET", "/") => return Reply::ok("text/html; charset=utf-8", PAGE),
        ("GET", "/lottie.min.js") => {
            return Reply::ok(
                "text/javascript; charset=utf-8",
                gmotion_pipeline::html::LOTTIE_JS,
            );
        }
        (_, "/" | "/lottie.min.js") => return Reply::not_allowed("GET"),
        _ => {}
    }
    if !path.starts_with("/api/") {
        return Reply::error(404, "not found");
    }
    let token = param(query, "token").or_else(|| request.header("X-Gmotion-Token"));
    if !token.is_some_and(|t| same(t, &ctx.token)) {
        return Reply::error(403, "forbidden: a valid token is needed");
    }
    let live = &ctx.live;
    let route = &path["/api".len()..];
    // Renders, exports and rebuilds wait for a pass; polling never does.
    let _pass = lane(ctx, method, route).map(Gate::enter);
    match (method, route) {
        ("GET", "/state") => {
            let now = live.snapshot();
            let (shapes, timelines) = live.shapes_and_timelines(&now.good);
            let scene = &now.good.rendered.anim.scene;
            Reply::json(&json!({
                "version": now.version,
                "duration": now.good.rendered.anim.duration,
                "fps": now.good.rendered.anim.fps,
                "width": scene.width,
                "height": scene.height,
                "shapes": shapes,
                "timelines": timelines,
                "diagnostics": now.diagnostics,
                "grammar": now.text,
                "unsaved": now.unsaved,
                "conflict": now.conflict,
            }))
        }
        ("GET", "/status") => {
            let now = live.snapshot();
            Reply::json(&json!({
                "version": now.version,
                "diagnostics": now.diagnostics,
                "grammar": now.text,
                "unsaved": now.unsaved,
                "conflict": now.conflict,
            }))
        }
        ("GET", "/layers") => {
            let good = live.good();
            Reply::json(&json!({
                "version": live.version(),
                "layers": crate::layers::layers_json(
                    &good.rendered.anim.scene,
                    good.rendered.source.as_deref(),
                ),
            }))
        }
        ("GET", "/grammar") => Reply::ok("text/plain; charset=utf-8", live.text()),
        ("PUT", "/grammar") => {
            // The server refuses bodies over `http::MAX_BODY` (4 MiB) before this.
            let text = match String::from_utf8(request.body.clone()) {
                Ok(text) => text,
                Err(e) => return Reply::error(400, &not_utf8(e.utf8_error(), &request.body)),
            };
            let (version, diagnostics) = live.set_text(text);
            Reply::json(&json!({
                "version": version,
                "diagnostics": diagnostics.iter().map(crate::live::diagnostic_json).collect::<Vec<_>>(),
            }))
        }
        ("POST", "/save") => match live.save() {
            Ok(p) => {
                Reply::json(&json!({"saved": p.display().to_string(), "version": live.version()}))
            }
            Err(SaveError::Changed) => Reply::error(
                409,
                "the grammar file changed on disk since it was read: keep mine or take theirs first",
            ),
            Err(SaveError::Io(e)) => Reply::error(500, &format!("cannot save: {e}")),
        },
        ("POST", "/resolve") => {
            let how = match param(query, "take") {
                Some("mine") => Resolution::Mine,
                Some("theirs") => Resolution::Theirs,
                Some("merge") => {
                    return match live.merge() {
                        Ok(()) => {
                            Reply::json(&json!({"version": live.version(), "grammar": live.text()}))
                        }
                        Err(MergeError::NoConflict) => {
                            Reply::error(409, "there is no conflict to resolve")
                        }
                        Err(MergeError::TooLarge) => Reply::error(
                            422,
                            &format!(
                                "a text is longer than {MAX_MERGE_LINES} lines, too long to \
                                 merge: keep mine or take theirs"
                            ),
                        ),
                        Err(MergeError::Overlap(n)) => Reply::error(
                            409,
                            &format!(
                                "both texts changed the same lines ({n} {}): keep mine or \
                                 take theirs",
                                if n == 1 { "place" } else { "places" }
                            ),
                        ),
                    };
                }
                _ => return Reply::error(400, "take must be mine, theirs or merge"),
            };
            if !live.resolve(how) {
                return Reply::error(409, "there is no conflict to resolve");
            }
            Reply::json(&json!({"version": live.version(), "grammar": live.text()}))
        }
        ("POST", "/retime") => {
            let body: serde_json::Value = match serde_json::from_slice(&request.body) {
                Ok(v) => v,
                Err(e) => return Reply::error(400, &format!("the body must be JSON: {e}")),
            };
            let index = |k: &str| body[k].as_u64().and_then(|v| usize::try_from(v).ok());
            let (Some(shape), Some(boundary), Some(time)) = (
                index("shape"),
                index("boundary"),
                body["time"].as_f64().filter(|t| t.is_finite()),
            ) else {
                return Reply::error(
                    400,
                    "the body is {\"shape\": INDEX, \"boundary\": INDEX, \"time\": SECONDS}",
                );
            };
            match live.retime(shape, boundary, time) {
                Ok((done, version, diagnostics)) => Reply::json(&json!({
                    "version": version,
                    "grammar": done.text,
                    "line": done.line,
                    "fractions": done.fractions,
                    "diagnostics": diagnostics.iter().map(crate::live::diagnostic_json).collect::<Vec<_>>(),
                })),
                Err(e) => Reply::error(422, &e),
            }
        }
        ("POST", "/offset") => {
            let body: serde_json::Value = match serde_json::from_slice(&request.body) {
                Ok(v) => v,
                Err(e) => return Reply::error(400, &format!("the body must be JSON: {e}")),
            };
            let index = |k: &str| body[k].as_u64().and_then(|v| usize::try_from(v).ok());
            let number = |k: &str| body[k].as_f64().filter(|t| t.is_finite());
            let (Some(shape), Some(slice), Some(from), Some(time)) = (
                index("shape"),
                index("slice"),
                number("from"),
                number("time"),
            ) else {
                return Reply::error(
                    400,
                    "the body is {\"shape\": INDEX, \"slice\": INDEX, \"from\": SECONDS, \"time\": SECONDS}",
                );
            };
            match live.move_offset((shape, slice, from, time)) {
                Ok((done, version)) => Reply::json(&json!({
                    "version": version,
                    "grammar": done.text,
                    "line": done.line,
                    "offset": done.offset,
                    "diagnostics": [],
                })),
                Err(e) => Reply::error(422, &e),
            }
        }
        ("POST", "/value") => {
            let body: serde_json::Value = match serde_json::from_slice(&request.body) {
                Ok(v) => v,
                Err(e) => return Reply::error(400, &format!("the body must be JSON: {e}")),
            };
            let line = body["line"].as_u64().and_then(|v| u32::try_from(v).ok());
            let arg = body.get("arg").map_or(Some(crate::value::Arg::Value), |a| {
                a.as_str().and_then(crate::value::Arg::named)
            });
            let (Some(line), Some(arg), Some(value)) = (line, arg, body["value"].as_str()) else {
                return Reply::error(
                    400,
                    "the body is {\"line\": LINE, \"arg\": \"value\" or \"ease\", \"value\": TEXT}",
                );
            };
            match live.set_value((line, arg, value)) {
                Ok((done, version)) => Reply::json(&json!({
                    "version": version,
                    "grammar": done.text,
                    "line": done.line,
                    "value": done.value,
                    "diagnostics": [],
                })),
                Err(e) => Reply::error(422, &e),
            }
        }
        ("GET", "/rules") => {
            let shape = param(query, "shape").and_then(|v| v.parse::<usize>().ok());
            let t = param(query, "t")
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|t| t.is_finite());
            let (Some(shape), Some(t)) = (shape, t) else {
                return Reply::error(400, "shape must be an index and t a number of seconds");
            };
            match live.rules_at(shape, t) {
                Ok(rules) => Reply::json(&json!({"version": live.version(), "rules": rules})),
                Err(e) => Reply::error(422, &e),
            }
        }
        ("GET", "/boxes") => {
            let built = live.good();
            let t = match param(query, "t").map(str::parse::<f64>) {
                None => 0.0,
                Some(Ok(t)) if t.is_finite() => t.clamp(0.0, built.rendered.anim.duration),
                Some(_) => return Reply::error(400, "t must be a number of seconds"),
            };
            Reply::json(
                &json!({"version": live.version(), "t": t, "boxes": Live::boxes_at(&built, t)}),
            )
        }
        ("GET", "/lottie") => match live.lottie() {
            Ok(body) => Reply::ok("application/json", body),
            Err(e) => Reply::error(422, &e),
        },
        ("GET", "/smil") => export(live, &live.good(), "svg", 0.0, None),
        ("GET", "/frame.png") => {
            let t = match param(query, "t").map(str::parse::<f64>) {
                None => 0.0,
                Some(Ok(t)) if t.is_finite() => t,
                Some(_) => return Reply::error(400, "t must be a number of seconds"),
            };
            let built = match param(query, "seed").map(str::parse::<u64>) {
                None => live.good(),
                Some(Ok(s)) => match live.with_seed(s) {
                    Ok(b) => b,
                    Err(e) => return Reply::error(422, &e),
                },
                Some(Err(_)) => return Reply::error(400, "seed must be a whole number"),
            };
            let t = t.clamp(0.0, built.rendered.anim.duration);
            // `w`: the width the page shows it at, so a thumbnail of a large scene is not
            // decoded at full size on the page's main thread.
            let size = match param(query, "w").map(str::parse::<u32>) {
                None => built.size,
                Some(Ok(w)) if (1..=8192).contains(&w) => OutputSize {
                    width: Some(w),
                    height: None,
                },
                Some(_) => return Reply::error(400, "w must be a width in pixels, 1 to 8192"),
            };
            match live.export_sized(&built, "png", t, size) {
                Ok(body) => Reply::ok("image/png", body),
                Err(e) => Reply::error(422, &e),
            }
        }
        ("GET", "/export/lottie") => {
            export(live, &live.good(), "json", 0.0, Some("animation.json"))
        }
        ("GET", "/export/dotlottie") => {
            export(live, &live.good(), "lottie", 0.0, Some("animation.lottie"))
        }
        ("GET", "/export/smil") => export(live, &live.good(), "svg", 0.0, Some("animation.svg")),
        ("GET", "/export/gif") => export(live, &live.good(), "gif", 0.0, Some("animation.gif")),
        ("GET", "/export/html") => export(live, &live.good(), "html", 0.0, Some("preview.html")),
        (_, "/grammar") => Reply::not_allowed("GET, PUT"),
        (_, "/save" | "/resolve" | "/retime" | "/offset" | "/value") => Reply::not_allowed("POST"),
        (
            _,
            "/state" | "/status" | "/layers" | "/rules" | "/boxes" | "/lottie" | "/smil"
            | "/frame.png" | "/export/lottie" | "/export/dotlottie" | "/export/smil"
            | "/export/gif" | "/export/html",
        ) => Reply::not_allowed("GET"),
        _ => Reply::error(404, "no such API route"),
    }
}

/// Where a body that should be UTF-8 text stops being it, as line and column (of
/// characters), and the byte found there.
fn not_utf8(e: std::str::Utf8Error, body: &[u8]) -> String {
    let good = &body[..e.valid_up_to()];
    let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let col = String::from_utf8_lossy(&good[start..]).chars().count() + 1;
    format!(
        "the grammar is not UTF-8 text: line {line}, column {col} holds the byte {:#04x}",
        body[e.valid_up_to()]
    )
}

/// The gate `route` (under `/api`) asked with `method` waits at: whole exports at
/// `exports`, frames, the Lottie document, rules and rebuilds at `work`, the rest (which
/// answer from the last build at once) at none.
fn lane<'a>(ctx: &'a Ctx, method: &str, route: &str) -> Option<&'a Gate> {
    match (method, route) {
        ("GET", "/smil") => Some(&ctx.exports),
        ("GET", r) if r.starts_with("/export/") => Some(&ctx.exports),
        ("GET", "/lottie" | "/frame.png" | "/rules")
        | ("PUT", "/grammar")
        | ("POST", "/resolve" | "/retime" | "/offset" | "/value") => Some(&ctx.work),
        _ => None,
    }
}

/// `built` written as `ext`, answered inline or as a download.
fn export(
    live: &Live,
    built: &Built,
    ext: &str,
    time: f64,
    download: Option<&'static str>,
) -> Reply {
    let bytes = live.export(built, ext, time);
    match bytes {
        Ok(body) => Reply {
            status: 200,
            kind: match ext {
                "json" => "application/json",
                "lottie" => "application/zip",
                "svg" => "image/svg+xml",
                "png" => "image/png",
                "gif" => "image/gif",
                _ => "text/html; charset=utf-8",
            },
            body,
            download,
            allow: None,
        },
        Err(e) => Reply::error(422, &e),
    }
}

#[cfg(test)]
mod tests {
    use super::PAGE;

    /// The page highlights the directives by name; its list is the grammar's.
    #[test]
    fn the_page_highlights_the_grammars_directives() {
        let start = PAGE
            .find("const DIRECTIVES = [")
            .expect("the page lists the directives");
        let list = &PAGE[start + "const DIRECTIVES = [".len()..];
        let list = &list[..list.find(']').expect("the list ends")];
        let page: Vec<&str> = list
            .split(',')
            .map(|name| name.trim().trim_matches('"'))
            .collect();
        let grammar: Vec<&str> = gmotion::grammar::DIRECTIVES
            .iter()
            .map(|d| d.name)
            .collect();
        assert_eq!(page, grammar);
    }
}
