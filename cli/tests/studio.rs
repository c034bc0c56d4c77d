//! `gmotion studio`'s JSON API (issue 16, docs/studio.md), over a plain HTTP/1.1 client: the
//! token and the `Host` check, the state, live edits that keep the last good animation,
//! the grammar file followed on disk, and save.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::support::root;

/// The studio process, killed when the test ends, passed or not.
pub(crate) struct Studio {
    child: Child,
    pub(crate) port: u16,
    pub(crate) token: String,
    dir: PathBuf,
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A response: status and body.
struct Reply {
    status: u16,
    body: Vec<u8>,
}

impl Reply {
    fn json(&self) -> Value {
        serde_json::from_slice(&self.body).expect("a JSON body")
    }
}

impl Studio {
    /// A fresh folder holding a copy of the toy example.
    fn folder(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("gmotion-studio-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for f in ["toy.gm", "toy.svg"] {
            std::fs::copy(root().join("grammars").join(f), dir.join(f)).unwrap();
        }
        dir
    }

    /// Starts the studio on a copy of the toy example.
    pub(crate) fn start(name: &str) -> Studio {
        let dir = Studio::folder(name);
        let scene = dir.join("toy.svg");
        Studio::start_on(dir, &scene)
    }

    /// Starts the studio on `scene` and the toy grammar in `dir` (removed at the end).
    fn start_on(dir: PathBuf, scene: &std::path::Path) -> Studio {
        let args = [scene.as_os_str(), dir.join("toy.gm").as_os_str()].map(|a| a.to_owned());
        Studio::start_with(dir, &args)
    }

    /// Starts `gmotion studio --no-open --port 0 ARGS` in `dir` (removed at the end).
    fn start_with(dir: PathBuf, args: &[std::ffi::OsString]) -> Studio {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .args(["studio", "--no-open", "--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let mut studio = Studio {
            child,
            port: 0,
            token: String::new(),
            dir,
        };
        let rest = line
            .trim_end()
            .strip_prefix("studio: http://127.0.0.1:")
            .unwrap_or_else(|| panic!("unexpected first line {line:?}"));
        let (port, token) = rest.split_once("/?token=").unwrap();
        studio.port = port.parse().unwrap();
        studio.token = token.to_string();
        assert_eq!(token.len(), 32, "a 16-byte token in hex");
        studio
    }

    /// One request; `token` goes in the header when given.
    fn raw(&self, method: &str, path: &str, host: &str, token: Option<&str>, body: &str) -> Reply {
        let mut s = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        let mut req = format!(
            "{method} {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\nContent-Length: {}\r\n",
            body.len()
        );
        if let Some(t) = token {
            req.push_str(&format!("X-Gmotion-Token: {t}\r\n"));
        }
        req.push_str("\r\n");
        req.push_str(body);
        s.write_all(req.as_bytes()).unwrap();
        let mut bytes = Vec::new();
        s.read_to_end(&mut bytes).unwrap();
        let split = bytes
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("a header");
        let head = String::from_utf8_lossy(&bytes[..split]).into_owned();
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        let mut body = bytes[split + 4..].to_vec();
        if head
            .to_ascii_lowercase()
            .contains("transfer-encoding: chunked")
        {
            body = unchunk(&body);
        }
        Reply { status, body }
    }

    fn call(&self, method: &str, path: &str, body: &str) -> Reply {
        let host = format!("127.0.0.1:{}", self.port);
        self.raw(method, path, &host, Some(&self.token.clone()), body)
    }

    /// Saves the grammar through the API and asserts that `gmotion check` accepts the file:
    /// what the studio's edits wrote is a grammar the command line takes.
    fn save_and_check(&self) {
        self.call("POST", "/api/save", "");
        let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .arg("check")
            .arg(self.dir.join("toy.gm"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }

    fn state(&self) -> Value {
        let r = self.call("GET", "/api/state", "");
        assert_eq!(r.status, 200);
        r.json()
    }
}

/// A chunked body's bytes.
fn unchunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let eol = b.windows(2).position(|w| w == b"\r\n").unwrap();
        let len = usize::from_str_radix(String::from_utf8_lossy(&b[..eol]).trim(), 16).unwrap();
        if len == 0 {
            return out;
        }
        out.extend_from_slice(&b[eol + 2..eol + 2 + len]);
        b = &b[eol + 4 + len..];
    }
}

#[test]
fn refuses_without_token_or_with_a_foreign_host() {
    let s = Studio::start("refuse");
    let host = format!("127.0.0.1:{}", s.port);
    assert_eq!(s.raw("GET", "/api/state", &host, None, "").status, 403);
    assert_eq!(
        s.raw("GET", "/api/state", &host, Some("0123"), "").status,
        403
    );
    let evil = format!("evil.example:{}", s.port);
    assert_eq!(
        s.raw("GET", "/api/state", &evil, Some(&s.token), "").status,
        403
    );
    let query = format!("/api/state?token={}", s.token);
    assert_eq!(s.raw("GET", &query, &host, None, "").status, 200);
    let local = format!("localhost:{}", s.port);
    assert_eq!(s.raw("GET", &query, &local, None, "").status, 200);
    // Bad input is a 4xx, not a crash.
    assert_eq!(s.call("GET", "/api/frame.png?t=abc", "").status, 400);
    assert_eq!(s.call("GET", "/api/nothing", "").status, 404);
    assert_eq!(s.call("POST", "/api/state", "").status, 405);
    assert_eq!(s.call("GET", "/", "").status, 200);
}

#[test]
fn editing_the_import_directives_imports_the_scene_again() {
    // A tagged group of two paths: one unit under `units auto`, two under `units paths`;
    // their tags come from `class` under `tag_from class`, and from their layer's id
    // under `tag_from layer`.
    let dir = Studio::folder("reimport");
    let scene = dir.join("pair.svg");
    std::fs::write(
        &scene,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100"><g id="pair" class="duo"><rect class="left" width="40" height="40"/><rect class="right" x="50" width="40" height="40"/></g></svg>"#,
    )
    .unwrap();
    std::fs::write(dir.join("toy.gm"), "duration 1s\n").unwrap();
    let s = Studio::start_on(dir, &scene);
    let tags = |st: &Value| -> Vec<String> {
        st["shapes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x["tag"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(tags(&s.state()), ["duo"]);
    let put = |text: &str| {
        let r = s.call("PUT", "/api/grammar", text).json();
        assert_eq!(r["diagnostics"], serde_json::json!([]), "{text}: {r}");
    };
    put("duration 1s\nunits paths\ntag_from class\n");
    assert_eq!(tags(&s.state()), ["left", "right"]);
    put("duration 1s\nunits paths\ntag_from layer\n");
    assert_eq!(tags(&s.state()), ["pair", "pair"]);
    // A rule on the new tags runs on the scene imported under them.
    put(
        "duration 1s\nunits paths\ntag_from class\nanimate(opacity, local, 0, 0) : [all, left] -> [gone]\n",
    );
    let lottie: Value = serde_json::from_slice(&s.call("GET", "/api/lottie", "").body).unwrap();
    // The moving `left`, the still `right`, and their group as the null they hang from.
    let layers = lottie["layers"].as_array().unwrap();
    let pair = layers.iter().find(|l| l["nm"] == "pair").expect("a null");
    let mut children: Vec<&str> = layers
        .iter()
        .filter(|l| l["parent"] == pair["ind"])
        .map(|l| l["nm"].as_str().unwrap())
        .collect();
    children.sort();
    assert_eq!(
        (layers.len(), children),
        (3, vec!["left", "right"]),
        "{lottie}"
    );
    put("duration 1s\n");
    assert_eq!(tags(&s.state()), ["duo"]);
}

#[test]
fn state_edits_file_and_save() {
    let s = Studio::start("edit");
    let st = s.state();
    let shapes = st["shapes"].as_array().unwrap();
    let timelines = st["timelines"].as_array().unwrap();
    assert!(!shapes.is_empty());
    assert_eq!(shapes.len(), timelines.len());
    assert!(shapes[0]["bbox"].as_array().unwrap().len() == 4);
    let square = shapes.iter().position(|x| x["tag"] == "s").unwrap();
    let slices = timelines[square].as_array().unwrap();
    assert!(slices.iter().any(|x| x["inverted"] == true), "{slices:?}");
    let v1 = st["version"].as_u64().unwrap();
    let lottie1 = s.call("GET", "/api/lottie", "").body;
    let png = s.call("GET", "/api/frame.png?t=1&seed=3", "");
    assert_eq!(png.status, 200);
    assert!(png.body.starts_with(b"\x89PNG"));

    // A broken grammar: located diagnostic, same version and animation.
    let r = s
        .call(
            "PUT",
            "/api/grammar",
            "duration 2s\ntimesplit(0.5 : [all, s]\n",
        )
        .json();
    assert_eq!(r["version"].as_u64(), Some(v1));
    let d = &r["diagnostics"][0];
    assert_eq!(d["line"], 2, "{r}");
    assert!(d["column"].as_u64().unwrap() > 0);
    assert_eq!(s.call("GET", "/api/lottie", "").body, lottie1);
    let status = s.call("GET", "/api/status", "").json();
    assert_eq!(status["version"].as_u64(), Some(v1));
    assert_eq!(status["diagnostics"][0]["line"], 2);
    assert!(
        status["grammar"]
            .as_str()
            .unwrap()
            .starts_with("duration 2s")
    );

    // A good one: new version, new Lottie.
    let good = std::fs::read_to_string(s.dir.join("toy.gm"))
        .unwrap()
        .replace("translate(260, 0)", "translate(100, 50)");
    let r = s.call("PUT", "/api/grammar", &good).json();
    let v2 = r["version"].as_u64().unwrap();
    assert!(v2 > v1 && r["diagnostics"].as_array().unwrap().is_empty());
    assert_ne!(s.call("GET", "/api/lottie", "").body, lottie1);

    // Save writes the live text.
    let saved = s.call("POST", "/api/save", "");
    assert_eq!(saved.status, 200);
    assert_eq!(std::fs::read_to_string(s.dir.join("toy.gm")).unwrap(), good);

    // An edit on disk bumps the version.
    std::fs::write(
        s.dir.join("toy.gm"),
        good.replace("duration 6s", "duration 3.5s"),
    )
    .unwrap();
    let start = Instant::now();
    loop {
        let st = s.state();
        if st["version"].as_u64().unwrap() > v2 {
            assert_eq!(st["duration"], 3.5);
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(10), "no reload");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn animate_writes_a_self_contained_preview() {
    let dir = std::env::temp_dir().join(format!("gmotion-preview-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("toy.html");
    let status = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .arg("animate")
        .arg(root().join("grammars/toy.gm"))
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.contains("lottie.loadAnimation") && html.contains("<animate"));
    // The timeline's data: the square's slice and its inverted twin (tag index k written
    // as -1 - k).
    let timeline: serde_json::Value = html
        .lines()
        .find_map(|l| l.strip_prefix("const timeline = "))
        .and_then(|l| serde_json::from_str(l.trim_end_matches(';')).ok())
        .expect("the page's timeline data");
    let tran = timeline["tags"]
        .as_array()
        .unwrap()
        .iter()
        .position(|t| t == "tran")
        .expect("the tag tran") as i64;
    let codes: Vec<i64> = timeline["rows"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| {
            r.as_array().unwrap()[1..]
                .chunks(3)
                .map(|s| s[2].as_i64().unwrap())
        })
        .collect();
    assert!(
        codes.contains(&tran) && codes.contains(&(-1 - tran)),
        "{codes:?}"
    );
    assert!(!html.contains("<script src") && !html.contains("https://"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn variations_writes_a_sheet_or_a_folder() {
    let dir = std::env::temp_dir().join(format!("gmotion-variations-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let run = |out: &std::path::Path| {
        let status = Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .args([
                "variations",
                "--count",
                "4",
                "--seed-start",
                "7",
                "--width",
                "60",
            ])
            .arg(root().join("grammars/toy.gm"))
            .arg("-o")
            .arg(out)
            .status()
            .unwrap();
        assert!(status.success());
    };
    let sheet = dir.join("sheet.png");
    run(&sheet);
    let png = std::fs::read(&sheet).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    // Two columns of 60-pixel frames and their gaps.
    let width = u32::from_be_bytes(png[16..20].try_into().unwrap());
    assert!((120..140).contains(&width), "{width}");
    let folder = dir.join("seeds");
    run(&folder);
    for s in 7..11 {
        assert!(folder.join(format!("seed_{s}.png")).is_file());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_shapes_json_lists_what_the_studio_lists() {
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .args(["check", "--shapes", "--json"])
        .arg(root().join("grammars/toy.svg"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let listed: Value = serde_json::from_slice(&out.stdout).unwrap();
    let s = Studio::start("shapes");
    assert_eq!(listed, s.state()["shapes"]);
}

#[test]
fn a_lottie_scene_works_too() {
    let dir = Studio::folder("lottie");
    let scene = dir.join("toy.json");
    let converted = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .arg("convert")
        .arg(dir.join("toy.svg"))
        .arg("-o")
        .arg(&scene)
        .status()
        .unwrap();
    assert!(converted.success());
    std::fs::write(
        dir.join("toy.gm"),
        "duration 2s\ntimesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n\
         animate(affine, world, 0, translate(50, 0)) : [a, all] -> [m]\n",
    )
    .unwrap();
    let s = Studio::start_on(dir, &scene);
    let st = s.state();
    assert_eq!(st["diagnostics"].as_array().map(Vec::len), Some(0), "{st}");
    assert_eq!(st["timelines"][0][1]["inverted"], true);
    let png = s.call("GET", "/api/frame.png?t=0.5", "");
    assert!(png.status == 200 && png.body.starts_with(b"\x89PNG"));
    let lottie = s.call("GET", "/api/lottie", "").json();
    assert!(lottie["layers"].as_array().is_some_and(|l| !l.is_empty()));
}

#[test]
fn layers_give_the_scenes_groups_by_name() {
    let dir = Studio::folder("layers");
    let scene = dir.join("face.svg");
    std::fs::write(
        &scene,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
          <g id="face"><g id="eyes"><circle cx="30" cy="30" r="5"/><circle cx="70" cy="30" r="5"/></g>
          <rect x="30" y="60" width="40" height="5"/></g><rect x="0" y="90" width="100" height="10"/></svg>"#,
    )
    .unwrap();
    std::fs::write(dir.join("toy.gm"), "duration 1s\n").unwrap();
    let s = Studio::start_on(dir, &scene);
    let r = s.call("GET", "/api/layers", "");
    assert_eq!(r.status, 200);
    let body = r.json();
    assert_eq!(body["version"], s.state()["version"]);
    let rows: Vec<(Value, Value, Value)> = body["layers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e["name"].clone(), e["depth"].clone(), e["shapes"].clone()))
        .collect();
    assert_eq!(
        rows,
        vec![
            (json!("face"), json!(0), json!([0, 1, 2])),
            (json!("eyes"), json!(1), json!([0, 1])),
            (json!(null), json!(2), json!(null)),
            (json!(null), json!(2), json!(null)),
            (json!(null), json!(1), json!(null)),
            (json!(null), json!(0), json!(null)),
        ],
        "{body}"
    );
    // The route needs the token like every other.
    let refused = s.raw(
        "GET",
        "/api/layers",
        &format!("127.0.0.1:{}", s.port),
        None,
        "",
    );
    assert_eq!(refused.status, 403);
}

/// Polls `/api/status` until `done` holds (10 s at most).
fn wait_status(s: &Studio, what: &str, done: impl Fn(&Value) -> bool) -> Value {
    let start = Instant::now();
    loop {
        let st = s.call("GET", "/api/status", "").json();
        if done(&st) {
            return st;
        }
        assert!(start.elapsed() < Duration::from_secs(10), "{what}: {st}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn a_missing_grammar_is_created_empty_at_start() {
    let dir = Studio::folder("new");
    std::fs::remove_file(dir.join("toy.gm")).unwrap();
    let scene = dir.join("toy.svg");
    let s = Studio::start_on(dir, &scene);
    assert_eq!(
        std::fs::read_to_string(s.dir.join("toy.gm")).unwrap(),
        "",
        "the paper starts from a possibly empty grammar"
    );
    let st = s.state();
    assert_eq!(st["diagnostics"], serde_json::json!([]), "{st}");
    assert_eq!(st["shapes"].as_array().unwrap().len(), 6);
}

#[test]
fn an_outside_edit_under_unsaved_edits_is_a_conflict_never_dropped() {
    let s = Studio::start("conflict");
    let path = s.dir.join("toy.gm");
    let disk = std::fs::read_to_string(&path).unwrap();
    let mine = disk.replace("translate(260, 0)", "translate(100, 0)");
    let theirs = disk.replace("duration 6s", "duration 4s");
    s.call("PUT", "/api/grammar", &mine);
    assert_eq!(s.call("GET", "/api/status", "").json()["unsaved"], true);

    // Changed on disk before the watcher has looked: Save refuses and shows the conflict.
    std::fs::write(&path, &theirs).unwrap();
    let r = s.call("POST", "/api/save", "");
    assert_eq!(r.status, 409, "{}", String::from_utf8_lossy(&r.body));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), theirs);
    let st = wait_status(&s, "a conflict", |st| st["conflict"].is_string());
    assert_eq!(st["conflict"], theirs.as_str());
    assert_eq!(st["grammar"], mine.as_str(), "my text stays");
    // The watcher's turn does not drop it either.
    std::thread::sleep(Duration::from_millis(700));
    let st = s.call("GET", "/api/status", "").json();
    assert_eq!(
        (st["grammar"].as_str(), st["conflict"].as_str()),
        (Some(mine.as_str()), Some(theirs.as_str()))
    );
    assert_eq!(s.call("POST", "/api/save", "").status, 409);

    // Keep mine: Save may now write over theirs.
    assert_eq!(s.call("POST", "/api/resolve?take=nobody", "").status, 400);
    let r = s.call("POST", "/api/resolve?take=mine", "").json();
    assert_eq!(r["grammar"], mine.as_str());
    assert_eq!(s.call("POST", "/api/resolve?take=mine", "").status, 409);
    assert_eq!(s.call("POST", "/api/save", "").status, 200);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), mine);

    // Take theirs: the page's text becomes the file's, and the animation follows.
    let other = mine.replace("duration 6s", "duration 3s");
    s.call("PUT", "/api/grammar", &mine.replace("fps 30", "fps 24"));
    std::fs::write(&path, &other).unwrap();
    wait_status(&s, "a second conflict", |st| {
        st["conflict"] == other.as_str()
    });
    let r = s.call("POST", "/api/resolve?take=theirs", "").json();
    assert_eq!(r["grammar"], other.as_str());
    let st = s.state();
    assert_eq!(
        (st["duration"].as_f64(), st["unsaved"].as_bool()),
        (Some(3.0), Some(false))
    );

    // With no unsaved edits, an outside edit is simply taken.
    let again = other.replace("duration 3s", "duration 2s");
    std::fs::write(&path, &again).unwrap();
    let st = wait_status(&s, "the outside edit", |st| st["grammar"] == again.as_str());
    assert!(st["conflict"].is_null(), "{st}");
}

#[test]
fn a_conflict_merges_both_sides_changes_or_stays_pending() {
    let s = Studio::start("merge");
    let path = s.dir.join("toy.gm");
    let disk = std::fs::read_to_string(&path).unwrap();
    assert_eq!(s.call("POST", "/api/resolve?take=merge", "").status, 409);

    // The page moved the square, the file's other editor changed the duration: both kept.
    let mine = disk.replace("translate(260, 0)", "translate(100, 0)");
    let theirs = disk.replace("duration 6s", "duration 4s");
    s.call("PUT", "/api/grammar", &mine);
    std::fs::write(&path, &theirs).unwrap();
    wait_status(&s, "a conflict", |st| st["conflict"].is_string());
    let r = s.call("POST", "/api/resolve?take=merge", "");
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let both = disk
        .replace("translate(260, 0)", "translate(100, 0)")
        .replace("duration 6s", "duration 4s");
    assert_eq!(r.json()["grammar"], both.as_str());
    let st = s.state();
    assert_eq!(
        (st["duration"].as_f64(), st["unsaved"].as_bool()),
        (Some(4.0), Some(true)),
        "the merge is built, and unsaved"
    );
    // The file's text counts as read: Save writes the merge over it.
    assert_eq!(s.call("POST", "/api/save", "").status, 200);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), both);

    // Both changed the same line: nothing changes, no markers, the conflict stays open.
    let mine = both.replace("duration 4s", "duration 5s");
    let theirs = both.replace("duration 4s", "duration 3s");
    s.call("PUT", "/api/grammar", &mine);
    std::fs::write(&path, &theirs).unwrap();
    wait_status(&s, "a second conflict", |st| {
        st["conflict"] == theirs.as_str()
    });
    let r = s.call("POST", "/api/resolve?take=merge", "");
    assert_eq!(r.status, 409);
    let message = r.json()["error"].as_str().unwrap().to_owned();
    assert!(message.contains("same lines (1 place)"), "{message}");
    let st = s.call("GET", "/api/status", "").json();
    assert_eq!(
        (st["grammar"].as_str(), st["conflict"].as_str()),
        (Some(mine.as_str()), Some(theirs.as_str()))
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), theirs);
}

#[test]
fn the_scene_saved_again_shows_and_a_broken_one_keeps_the_last_animation() {
    let s = Studio::start("rescene");
    let scene = s.dir.join("toy.svg");
    let art = std::fs::read_to_string(&scene).unwrap();
    let square_x = |st: &Value| st["shapes"][1]["centroid"][0].as_f64().unwrap();
    let before = s.state();
    assert_eq!(square_x(&before), 100.0);
    let version = before["version"].as_u64().unwrap();

    // The art saved again in its design tool: the square now starts 40 to the right.
    std::fs::write(
        &scene,
        art.replace(r#"x="60" y="120""#, r#"x="100" y="120""#),
    )
    .unwrap();
    let st = wait_status(&s, "the scene imported again", |st| {
        st["version"].as_u64() > Some(version)
    });
    assert!(st["diagnostics"].as_array().unwrap().is_empty(), "{st}");
    assert_eq!(square_x(&s.state()), 140.0);
    let version = st["version"].as_u64().unwrap();

    // Broken, then deleted: said at 1:1, the last animation served all along.
    for (what, broken) in [("broken", Some("<svg><rect")), ("deleted", None)] {
        match broken {
            Some(text) => std::fs::write(&scene, text).unwrap(),
            None => std::fs::remove_file(&scene).unwrap(),
        }
        let st = wait_status(&s, what, |st| {
            st["diagnostics"].as_array().is_some_and(|d| !d.is_empty())
        });
        let message = st["diagnostics"][0]["message"].as_str().unwrap();
        assert!(
            message.starts_with("the scene file changed and could not be imported"),
            "{what}: {message}"
        );
        assert_eq!(st["version"].as_u64(), Some(version), "{what}");
        assert_eq!(s.call("GET", "/api/lottie", "").status, 200, "{what}");
        assert_eq!(square_x(&s.state()), 140.0, "{what}");
    }

    // Back: imported again, the diagnostic gone.
    std::fs::write(&scene, &art).unwrap();
    let st = wait_status(&s, "the scene back", |st| {
        st["version"].as_u64() > Some(version)
    });
    assert!(st["diagnostics"].as_array().unwrap().is_empty(), "{st}");
    assert_eq!(square_x(&s.state()), 100.0);
}

#[test]
fn a_pasted_binary_or_huge_grammar_is_answered_clearly() {
    let s = Studio::start("paste");
    let toy = std::fs::read_to_string(s.dir.join("toy.gm")).unwrap();
    // Invalid UTF-8 on line 3: refused, saying where, the text as it was.
    let body = b"duration 6s\nfps 30\nseed \xff\xfe\n".to_vec();
    let mut c = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
    write!(
        c,
        "PUT /api/grammar HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Gmotion-Token: {}\r\n\
         Connection: close\r\nContent-Length: {}\r\n\r\n",
        s.port,
        s.token,
        body.len()
    )
    .unwrap();
    c.write_all(&body).unwrap();
    let mut answer = String::new();
    c.read_to_string(&mut answer).unwrap();
    assert!(answer.starts_with("HTTP/1.1 400"), "{answer}");
    assert!(
        answer.contains("not UTF-8 text: line 3, column 6 holds the byte 0xff"),
        "{answer}"
    );
    assert_eq!(s.call("GET", "/api/grammar", "").body, toy.as_bytes());

    // A 4 MiB paste (the toy and a long comment) builds; one byte more is refused, 413.
    let limit = 4 << 20;
    let mut big = toy.clone();
    big.push('#');
    big.push_str(&"x".repeat(limit - big.len() - 1));
    big.push('\n');
    assert_eq!(big.len(), limit);
    let r = s.call("PUT", "/api/grammar", &big);
    assert_eq!(r.status, 200);
    assert!(r.json()["diagnostics"].as_array().unwrap().is_empty());
    assert_eq!(s.call("GET", "/api/grammar", "").body.len(), limit);
    // Refused from its header, before the body is sent (the server does not read it).
    let mut c = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
    write!(
        c,
        "PUT /api/grammar HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Gmotion-Token: {}\r\n\
         Content-Length: {}\r\n\r\n",
        s.port,
        s.token,
        limit + 1
    )
    .unwrap();
    let mut answer = String::new();
    c.read_to_string(&mut answer).unwrap();
    assert!(answer.starts_with("HTTP/1.1 413"), "{answer}");
    assert_eq!(s.call("GET", "/api/grammar", "").body.len(), limit);
}

#[test]
fn boxes_follow_the_frame_shown() {
    let s = Studio::start("boxes");
    let st = s.state();
    let square = st["shapes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|x| x["tag"] == "s")
        .unwrap();
    let at = |t: f64| -> Vec<f64> {
        let r = s.call("GET", &format!("/api/boxes?t={t}"), "").json();
        r["boxes"][square]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    // The square slides 260 to the right over the first half (6 s), and back.
    assert_eq!(at(0.0), vec![60.0, 120.0, 80.0, 80.0]);
    let mid = at(3.0);
    assert!((mid[0] - 320.0).abs() < 1e-6 && mid[1] == 120.0, "{mid:?}");
    assert_eq!(s.call("GET", "/api/boxes?t=x", "").status, 400);
}

#[test]
fn many_keep_alive_connections_are_all_answered() {
    // Browsers keep a handful of connections open; a new one must not queue behind them.
    let s = Studio::start("connections");
    let request = format!(
        "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Gmotion-Token: {}\r\n\r\n",
        s.port, s.token
    );
    let mut open: Vec<TcpStream> = (0..12)
        .map(|_| TcpStream::connect(("127.0.0.1", s.port)).unwrap())
        .collect();
    for round in 0..3 {
        for c in &mut open {
            c.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
            c.write_all(request.as_bytes()).unwrap();
        }
        for (i, c) in open.iter_mut().enumerate() {
            let mut head = Vec::new();
            let mut byte = [0u8; 1];
            while !head.ends_with(b"\r\n\r\n") {
                c.read_exact(&mut byte)
                    .unwrap_or_else(|e| panic!("connection {i}, round {round}: {e}"));
                head.push(byte[0]);
            }
            let head = String::from_utf8(head).unwrap();
            assert!(head.starts_with("HTTP/1.1 200"), "{head}");
            let length: usize = head
                .lines()
                .find_map(|l| l.strip_prefix("Content-Length: "))
                .unwrap()
                .parse()
                .unwrap();
            let mut body = vec![0; length];
            c.read_exact(&mut body).unwrap();
        }
    }
}

/// Issue 46: 200 clients holding connections open (half sending nothing, half stalled in
/// the middle of their headers) leave the page served, each answer within a second; a
/// client trickling its headers a byte at a time is answered 408 and cut off once the
/// request has taken 10 s, instead of holding its connection for ever.
#[test]
fn slow_and_stalled_clients_do_not_lock_the_page_out() {
    let s = Studio::start("slow-clients");
    let mut held: Vec<TcpStream> = (0..200)
        .map(|_| TcpStream::connect(("127.0.0.1", s.port)).unwrap())
        .collect();
    for c in held.iter_mut().step_by(2) {
        c.write_all(b"GET /api/status HTTP/1.1\r\nHost: 127.0")
            .unwrap();
    }
    let request = format!(
        "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nX-Gmotion-Token: {}\r\nConnection: close\r\n\r\n",
        s.port, s.token
    );
    for _ in 0..5 {
        let started = std::time::Instant::now();
        let mut c = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
        c.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        c.write_all(request.as_bytes()).unwrap();
        let mut answer = String::new();
        c.read_to_string(&mut answer).unwrap();
        assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
        assert!(
            started.elapsed() < Duration::from_secs(1),
            "answered in {:?} beside 200 held connections",
            started.elapsed()
        );
    }
    // A byte every half second: each restarts a plain idle timeout, not the request's.
    let mut trickle = TcpStream::connect(("127.0.0.1", s.port)).unwrap();
    trickle
        .set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let started = std::time::Instant::now();
    let mut answer = Vec::new();
    for b in b"GET /api/status HTTP/1.1\r\nX-Long-Header: "
        .iter()
        .cycle()
    {
        if trickle.write_all(&[*b]).is_err() {
            break;
        }
        let mut buf = [0u8; 512];
        match trickle.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => answer.extend_from_slice(&buf[..n]),
            Err(_) => {}
        }
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "still connected after 20 s"
        );
        std::thread::sleep(Duration::from_millis(400));
    }
    let answer = String::from_utf8_lossy(&answer);
    assert!(answer.starts_with("HTTP/1.1 408"), "{answer}");
    assert!(
        started.elapsed() >= Duration::from_secs(9),
        "{:?}",
        started.elapsed()
    );
    drop(held);
}

#[test]
fn retime_rewrites_the_timesplit_fractions_keeping_their_sum() {
    let s = Studio::start("retime");
    let st = s.state();
    let shapes = st["shapes"].as_array().unwrap();
    let find = |tag: &str| shapes.iter().position(|x| x["tag"] == tag).unwrap();
    let (square, circle) = (find("s"), find("c"));
    let boundary = |st: &Value, shape: usize, k: usize| {
        st["timelines"][shape][k + 1]["start"].as_f64().unwrap()
    };
    assert_eq!(boundary(&st, square, 0), 3.0);
    let retime = |shape: usize, k: usize, time: f64| {
        s.call(
            "POST",
            "/api/retime",
            &format!(r#"{{"shape": {shape}, "boundary": {k}, "time": {time}}}"#),
        )
    };
    // The square's turn (half of 6 s) moved to 2.4 s: the first split becomes 0.4, 0.6.
    let r = retime(square, 0, 2.4).json();
    assert_eq!(r["diagnostics"], serde_json::json!([]), "{r}");
    assert_eq!(r["fractions"], serde_json::json!(["0.4", "0.6"]), "{r}");
    let text = r["grammar"].as_str().unwrap();
    assert!(
        text.contains("timesplit(0.4, 0.6)                                    : [all, (s, c)]"),
        "{text}"
    );
    let st = s.state();
    assert!((boundary(&st, square, 0) - 2.4).abs() < 1e-9);
    // The circles' first cut (0.4 of the first 2.4 s = 0.96 s) moved to 1.2 s: the second
    // split becomes 0.5, 0.5, its sum kept at 1.
    assert!(
        (boundary(&st, circle, 0) - 0.96).abs() < 1e-9,
        "{}",
        st["timelines"][circle]
    );
    let r = retime(circle, 0, 1.2).json();
    assert_eq!(r["fractions"], serde_json::json!(["0.5", "0.5"]), "{r}");
    assert!((boundary(&s.state(), circle, 0) - 1.2).abs() < 1e-9);
    // Past the end it clamps, never to a zero slice; here the staggered circles would no
    // longer fit their slices, so the edit is refused and the text left as it was.
    let before = s.call("GET", "/api/grammar", "").body;
    let r = retime(square, 0, 99.0);
    assert_eq!(r.status, 422);
    assert!(
        String::from_utf8_lossy(&r.body).contains("offset"),
        "{}",
        String::from_utf8_lossy(&r.body)
    );
    assert_eq!(s.call("GET", "/api/grammar", "").body, before);
    // Bad input is a 4xx.
    assert_eq!(retime(square, 7, 1.0).status, 422);
    assert_eq!(s.call("POST", "/api/retime", "{}").status, 400);
    assert_eq!(s.call("POST", "/api/retime", "nonsense").status, 400);
    // What the API wrote, `gmotion check` accepts.
    s.save_and_check();
}

#[test]
fn a_port_in_use_is_named_on_the_terminal() {
    let held = std::net::TcpListener::bind(("127.0.0.1", 0)).unwrap();
    let port = held.local_addr().unwrap().port();
    let dir = Studio::folder("port");
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .args(["studio", "--no-open", "--port", &port.to_string()])
        .arg(dir.join("toy.svg"))
        .arg(dir.join("toy.gm"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains(&format!("cannot listen on 127.0.0.1:{port}")),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn frames_are_drawn_at_the_width_asked() {
    let s = Studio::start("width");
    let png = s.call("GET", "/api/frame.png?t=1&seed=4&w=130", "");
    assert_eq!(png.status, 200);
    let width = u32::from_be_bytes(png.body[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(png.body[20..24].try_into().unwrap());
    // The toy scene is 520 × 320: a quarter of it.
    assert_eq!((width, height), (130, 80));
    for bad in ["0", "9000", "wide"] {
        assert_eq!(
            s.call("GET", &format!("/api/frame.png?w={bad}"), "").status,
            400,
            "{bad}"
        );
    }
}

#[test]
fn moving_a_change_rewrites_its_offset_as_a_whole() {
    let s = Studio::start("offset");
    let st = s.state();
    let shapes = st["shapes"].as_array().unwrap();
    let find = |tag: &str, id: u64| {
        shapes
            .iter()
            .position(|x| x["tag"] == tag && x["id"] == id)
            .unwrap()
    };
    let (c0, c1, square) = (find("c", 0), find("c", 1), find("s", 0));
    // The circles' spin starts 0.15 s apart: c#1's at 1.2 + 0.15 s on its second slice.
    let start = |st: &Value, shape: usize, slice: usize| {
        st["timelines"][shape][slice]["changes"][0][0]
            .as_f64()
            .unwrap()
    };
    assert!(
        (start(&st, c1, 1) - 1.35).abs() < 1e-9,
        "{}",
        st["timelines"][c1]
    );
    let offset = |shape: usize, slice: usize, from: f64, time: f64| {
        s.call(
            "POST",
            "/api/offset",
            &format!(r#"{{"shape": {shape}, "slice": {slice}, "from": {from}, "time": {time}}}"#),
        )
    };
    // Another shape's drag scales the stagger …
    let r = offset(c1, 1, 1.35, 1.5).json();
    assert_eq!(r["offset"], "0.3 * id", "{r}");
    let st = s.state();
    assert!((start(&st, c1, 1) - 1.5).abs() < 1e-9);
    // … the first shape's moves where it begins.
    let r = offset(c0, 1, 1.2, 1.3).json();
    assert_eq!(r["offset"], "0.1 + 0.3 * id", "{r}");
    let st = s.state();
    assert!((start(&st, c0, 1) - 1.3).abs() < 1e-9 && (start(&st, c1, 1) - 1.6).abs() < 1e-9);
    // A plain number becomes the new delay.
    let r = offset(square, 0, 0.0, 0.5).json();
    assert_eq!(r["offset"], "0.5", "{r}");
    assert!(
        r["grammar"]
            .as_str()
            .unwrap()
            .contains("animate(affine, world, 0.5, translate(260, 0)")
    );
    // No change starts there, a malformed body, a time breaking the grammar: refused.
    assert_eq!(offset(square, 0, 2.0, 1.0).status, 422);
    assert_eq!(s.call("POST", "/api/offset", "{}").status, 400);
    let before = s.call("GET", "/api/grammar", "").body;
    let far = offset(c1, 1, 1.6, 2.99);
    assert_eq!(far.status, 422, "{}", String::from_utf8_lossy(&far.body));
    assert_eq!(s.call("GET", "/api/grammar", "").body, before);
    s.save_and_check();
}

#[test]
fn a_rule_value_is_set_in_place_or_refused() {
    let s = Studio::start("value");
    let st = s.state();
    let shapes = st["shapes"].as_array().unwrap();
    let find = |tag: &str| shapes.iter().position(|x| x["tag"] == tag).unwrap();
    let (square, circle) = (find("s"), find("c"));
    // Which rules change a shape in the slice under the playhead, and how far along.
    let rules = |shape: usize, t: f64| {
        s.call("GET", &format!("/api/rules?shape={shape}&t={t}"), "")
            .json()["rules"]
            .clone()
    };
    let moving = rules(square, 1.5);
    assert_eq!(moving.as_array().unwrap().len(), 1, "{moving}");
    let m = &moving[0];
    assert_eq!(
        (&m["type"], &m["value"], &m["ease"]),
        (
            &json!("affine"),
            &json!("translate(260, 0)"),
            &json!("ease-in-out")
        )
    );
    // Half-way through an ease-in-out change, half-way along.
    assert!((m["progress"].as_f64().unwrap() - 0.5).abs() < 1e-9, "{m}");
    let line = m["line"].as_u64().unwrap();
    // The circles: shrinking on their first slice, then the spin on the next one.
    assert_eq!(rules(circle, 1.0)[0]["value"], "scale(0.5)");
    let spin = rules(circle, 2.9);
    assert_eq!(spin[0]["value"], "rotate(90) scale(1.6)", "{spin}");
    assert_eq!(spin[0]["ease"], Value::Null);
    let spin_line = spin[0]["line"].as_u64().unwrap();
    assert_eq!(s.call("GET", "/api/rules?shape=x&t=1", "").status, 400);

    let box_at =
        |t: f64| s.call("GET", &format!("/api/boxes?t={t}"), "").json()["boxes"][square].clone();
    assert_eq!(box_at(1.5), json!([190.0, 120.0, 80.0, 80.0]));
    let set = |line: u64, arg: &str, value: &str| {
        s.call(
            "POST",
            "/api/value",
            &json!({"line": line, "arg": arg, "value": value}).to_string(),
        )
    };
    // The value is rewritten in place, and the frame at 1.5 s moves by half the change.
    let r = set(line, "value", "translate(300, 20)").json();
    assert_eq!(r["value"], "translate(300, 20)", "{r}");
    let text = r["grammar"].as_str().unwrap();
    assert!(text.contains("animate(affine, world, 0, translate(300, 20), ease=ease-in-out) :"));
    assert_eq!(box_at(1.5), json!([210.0, 130.0, 80.0, 80.0]));
    // An easing replaced, and one added to a rule that had none.
    let r = set(line, "ease", "cubic(0.1, 0.2, 0.3, 1)").json();
    assert!(
        r["grammar"]
            .as_str()
            .unwrap()
            .contains("ease=cubic(0.1, 0.2, 0.3, 1)) :")
    );
    let r = set(spin_line, "ease", "ease-out").json();
    assert!(
        r["grammar"]
            .as_str()
            .unwrap()
            .contains("rotate(90) scale(1.6), ease=ease-out) :"),
        "{r}"
    );
    // Refused, the text unchanged: a value that is not one value, an unknown easing, a
    // line without an animate rule; a malformed body.
    let before = s.call("GET", "/api/grammar", "").body;
    for (l, arg, value) in [
        (line, "value", "translate(1,"),
        (line, "value", "translate(1, 0)) : [a, s] -> [x]"),
        (line, "value", "translate(1, 0), 2"),
        (line, "ease", "bogus"),
        (1, "value", "1"),
    ] {
        let r = set(l, arg, value);
        assert_eq!(
            r.status,
            422,
            "{value}: {}",
            String::from_utf8_lossy(&r.body)
        );
    }
    assert_eq!(s.call("GET", "/api/grammar", "").body, before);
    assert_eq!(set(line, "speed", "1").status, 400);
    assert_eq!(s.call("POST", "/api/value", "{}").status, 400);
    s.save_and_check();
}

/// `studio --learn ANIMATION NEW.gm` starts from a designer's own animation (issue 45, item
/// 5): the grammar and its still scene are learned, written and opened, the grammar the
/// studio shows is the file's, and it runs with no error; an existing grammar with text in
/// it, or a scene given besides, is refused and nothing is written.
#[test]
fn learn_opens_an_animation_as_a_grammar() {
    let dir = Studio::folder("learn");
    let exported = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .arg("animate")
        .arg(dir.join("toy.gm"))
        .arg("-o")
        .arg(dir.join("moving.json"))
        .output()
        .unwrap();
    assert!(exported.status.success());
    let refused = |args: &[&str], what: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .args(["studio", "--no-open", "--port", "0", "--learn"])
            .args(args.iter().map(|a| dir.join(a)))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(what),
            "{args:?}: {err}"
        );
    };
    // toy.gm holds the hand-written grammar: never replaced.
    let hand = std::fs::read_to_string(dir.join("toy.gm")).unwrap();
    refused(&["moving.json", "toy.gm"], "exists and is not empty");
    assert_eq!(std::fs::read_to_string(dir.join("toy.gm")).unwrap(), hand);
    refused(
        &["moving.json", "toy.svg", "new.gm"],
        "give only the grammar",
    );
    assert!(!dir.join("new.gm").exists() && !dir.join("new.json").exists());

    let args = ["--learn", "moving.json", "new.gm"].map(|a| {
        if a.starts_with("--") {
            a.into()
        } else {
            dir.join(a).into_os_string()
        }
    });
    let s = Studio::start_with(dir.clone(), &args);
    let learned = std::fs::read_to_string(dir.join("new.gm")).unwrap();
    assert!(dir.join("new.json").exists(), "the still scene is written");
    assert!(
        learned.contains("scene \"new.json\"") && learned.contains("0.15 * id"),
        "{learned}"
    );
    let st = s.state();
    assert_eq!(st["grammar"], learned.as_str());
    assert_eq!(st["diagnostics"].as_array().map(Vec::len), Some(0), "{st}");
    // The toy's square and four circles, and its background, as units of the still scene.
    assert_eq!(st["shapes"].as_array().unwrap().len(), 6, "{st}");
}
