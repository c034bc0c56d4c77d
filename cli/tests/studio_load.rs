//! Issue 46: `gmotion studio` under load and under attack, against the real process.
//!
//! - Load: 50 clients on keep-alive connections for a minute (`GMOTION_STUDIO_LOAD_SECS`
//!   shortens it), each polling `/api/status`, reading `/api/state`, `/api/lottie` and a
//!   frame, and editing the grammar with `PUT /api/grammar`, beside one client exporting
//!   GIFs the whole time. Every answer is checked (status, JSON, PNG and GIF signatures,
//!   the edit in the next state, and every version answered paired with the text that
//!   version was made from); none may fail. The latency of `/api/status` is printed
//!   (`--nocapture`) as p50, p99 and max, and bounded: polling never waits behind the
//!   renders and exports, which take turns through the server's gate.
//! - Slow clients: 200 connections trickling their headers a byte at a time while a
//!   normal client is answered in under a second, again and again.
//! - Malformed requests: each answered with the status HTTP names for it, promptly, and
//!   the server still serving afterwards.

use std::collections::HashMap;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::studio::Studio;

/// The clients editing and polling at once.
const CLIENTS: usize = 50;

/// How long the load runs: a minute, or `GMOTION_STUDIO_LOAD_SECS` seconds.
fn load_time() -> Duration {
    let secs = std::env::var("GMOTION_STUDIO_LOAD_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    Duration::from_secs(secs)
}

/// An answer: status, head and body.
struct Answer {
    status: u16,
    head: String,
    body: Vec<u8>,
}

impl Answer {
    fn json(&self) -> Result<Value, String> {
        serde_json::from_slice(&self.body).map_err(|e| format!("not JSON ({e})"))
    }

    /// The answer if its status is `status`, else what came instead.
    fn expect(self, status: u16, what: &str) -> Result<Answer, String> {
        if self.status == status {
            return Ok(self);
        }
        let body = String::from_utf8_lossy(&self.body[..self.body.len().min(200)]).into_owned();
        Err(format!(
            "{what}: {} instead of {status}: {body}",
            self.status
        ))
    }
}

/// A client on one keep-alive connection, opened again only if the server closes it.
struct Client {
    port: u16,
    token: String,
    conn: Option<BufReader<TcpStream>>,
}

impl Client {
    fn new(s: &Studio) -> Client {
        Client {
            port: s.port,
            token: s.token.clone(),
            conn: None,
        }
    }

    fn send(&mut self, method: &str, path: &str, body: &[u8]) -> Result<Answer, String> {
        let port = self.port;
        let conn = match &mut self.conn {
            Some(c) => c,
            None => {
                let c = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
                c.set_read_timeout(Some(Duration::from_secs(120)))
                    .map_err(|e| e.to_string())?;
                self.conn.insert(BufReader::new(c))
            }
        };
        let mut request = format!(
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Gmotion-Token: {}\r\nContent-Length: {}\r\n\r\n",
            self.token,
            body.len()
        )
        .into_bytes();
        request.extend_from_slice(body);
        let answer = exchange(conn, &request).map_err(|e| format!("{method} {path}: {e}"));
        if answer
            .as_ref()
            .map_or(true, |a| a.head.contains("Connection: close"))
        {
            self.conn = None;
        }
        answer
    }
}

/// Writes `request` on `conn` and reads one answer (by its `Content-Length`).
fn exchange(conn: &mut BufReader<TcpStream>, request: &[u8]) -> Result<Answer, String> {
    conn.get_mut()
        .write_all(request)
        .map_err(|e| format!("write: {e}"))?;
    let mut head = String::new();
    loop {
        let mut line = String::new();
        let n = conn
            .read_line(&mut line)
            .map_err(|e| format!("read: {e}"))?;
        if n == 0 {
            return Err(format!("the connection closed after {head:?}"));
        }
        if line == "\r\n" {
            break;
        }
        head.push_str(&line);
    }
    let status = head
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("no status in {head:?}"))?;
    let length: usize = head
        .lines()
        .find_map(|l| l.strip_prefix("Content-Length: "))
        .and_then(|l| l.parse().ok())
        .ok_or_else(|| format!("no length in {head:?}"))?;
    let mut body = vec![0; length];
    conn.read_exact(&mut body)
        .map_err(|e| format!("body: {e}"))?;
    Ok(Answer { status, head, body })
}

fn hash(text: &str) -> u64 {
    let mut h = DefaultHasher::new();
    text.hash(&mut h);
    h.finish()
}

/// What the clients saw, for the checks made once they are done.
#[derive(Default)]
struct Seen {
    /// Each version an edit was answered with, and the hash of that edit's text.
    edits: HashMap<u64, u64>,
    /// Each version `/api/status` or `/api/state` answered, with the hash of its text.
    versions: Vec<(u64, u64)>,
    /// Every `/api/status` latency.
    latencies: Vec<Duration>,
    failures: Vec<String>,
}

/// The toy grammar with client `client`'s edit `round`: the square's slide, a new length
/// each time, and a comment naming the edit (so no two edits are the same text).
fn edited(base: &str, client: usize, round: usize) -> String {
    let x = 100 + (client * 7 + round * 13) % 100;
    let text = base.replace("translate(260, 0)", &format!("translate({x}, 0)"));
    assert_ne!(text, base, "the toy grammar slides its square by 260");
    format!("{text}# load: client {client}, edit {round}\n")
}

/// `/api/status` checked, its latency and what it answered kept: the version.
fn poll_status(c: &mut Client, seen: &Mutex<Seen>) -> Result<u64, String> {
    let started = Instant::now();
    let status = c.send("GET", "/api/status", b"")?;
    let took = started.elapsed();
    let status = status.expect(200, "status")?.json()?;
    let (Some(version), Some(text)) = (status["version"].as_u64(), status["grammar"].as_str())
    else {
        return Err(format!("status without version or grammar: {status}"));
    };
    let mut seen = seen.lock().unwrap();
    seen.latencies.push(took);
    seen.versions.push((version, hash(text)));
    Ok(version)
}

/// One round of client `client`: poll, read, render, edit, and read the edit back.
fn round(
    c: &mut Client,
    (client, round): (usize, usize),
    base: &str,
    seen: &Mutex<Seen>,
) -> Result<(), String> {
    let version = poll_status(c, seen)?;
    let state = c
        .send("GET", "/api/state", b"")?
        .expect(200, "state")?
        .json()?;
    let shapes = state["shapes"].as_array().map_or(0, Vec::len);
    if shapes != 6 {
        return Err(format!(
            "the toy scene has 6 shapes (a background, a square, 4 circles), the state lists {shapes}"
        ));
    }
    if state["version"].as_u64() < Some(version) {
        return Err(format!("the state's version went back from {version}"));
    }
    let lottie = c
        .send("GET", "/api/lottie", b"")?
        .expect(200, "lottie")?
        .json()?;
    if lottie["layers"].as_array().is_none_or(Vec::is_empty) {
        return Err("a Lottie document without layers".into());
    }
    let t = (round % 8) as f64 * 0.75;
    let frame = c
        .send("GET", &format!("/api/frame.png?t={t}&w=48"), b"")?
        .expect(200, "frame")?;
    if !frame.body.starts_with(b"\x89PNG\r\n\x1a\n") {
        return Err("a frame that is not a PNG".into());
    }
    let mine = edited(base, client, round);
    let put = c
        .send("PUT", "/api/grammar", mine.as_bytes())?
        .expect(200, "edit")?
        .json()?;
    let Some(done) = put["version"].as_u64() else {
        return Err(format!("an edit answered without a version: {put}"));
    };
    if put["diagnostics"].as_array().is_none_or(|d| !d.is_empty()) {
        return Err(format!("a valid edit answered with diagnostics: {put}"));
    }
    if let Some(other) = seen.lock().unwrap().edits.insert(done, hash(&mine))
        && other != hash(&mine)
    {
        return Err(format!("two edits answered with version {done}"));
    }
    let after = c
        .send("GET", "/api/state", b"")?
        .expect(200, "state")?
        .json()?;
    let (Some(now), Some(text)) = (after["version"].as_u64(), after["grammar"].as_str()) else {
        return Err(format!("a state without version or grammar: {after}"));
    };
    seen.lock().unwrap().versions.push((now, hash(text)));
    // Another client's edit may have landed since; otherwise the text is this edit's.
    if now < done || (now == done && text != mine) {
        return Err(format!(
            "the edit answered as version {done} is not in the next state (version {now})"
        ));
    }
    Ok(())
}

/// The `q` quantile of sorted `d`.
fn quantile(d: &[Duration], q: f64) -> Duration {
    d[((d.len() - 1) as f64 * q).round() as usize]
}

#[test]
fn fifty_clients_edit_and_poll_while_exports_run() {
    let s = Studio::start("load");
    let base = std::fs::read_to_string(crate::support::root().join("grammars/toy.gm")).unwrap();
    let seen = Mutex::new(Seen::default());
    seen.lock().unwrap().edits.insert(1, hash(&base));
    let (rounds, gifs) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let end = Instant::now() + load_time();
    std::thread::scope(|scope| {
        for client in 0..CLIENTS {
            let (s, base, seen, rounds) = (&s, &base, &seen, &rounds);
            // The page polls on a connection of its own, as a browser's fetches spread
            // over several, every 50 ms here (the page: every second).
            scope.spawn(move || {
                let mut c = Client::new(s);
                while Instant::now() < end {
                    if let Err(e) = poll_status(&mut c, seen) {
                        seen.lock()
                            .unwrap()
                            .failures
                            .push(format!("poller {client}: {e}"));
                        c.conn = None;
                    }
                    std::thread::sleep(Duration::from_millis(50));
                }
            });
            scope.spawn(move || {
                let mut c = Client::new(s);
                let mut n = 0;
                while Instant::now() < end {
                    if let Err(e) = round(&mut c, (client, n), base, seen) {
                        seen.lock()
                            .unwrap()
                            .failures
                            .push(format!("client {client}: {e}"));
                        c.conn = None;
                    }
                    n += 1;
                }
                rounds.fetch_add(n, Ordering::SeqCst);
            });
        }
        // The heaviest request, all the while: a GIF of every frame.
        let (s, seen, gifs) = (&s, &seen, &gifs);
        scope.spawn(move || {
            let mut c = Client::new(s);
            while Instant::now() < end {
                let gif = c
                    .send("GET", "/api/export/gif", b"")
                    .and_then(|a| a.expect(200, "gif"));
                match gif {
                    Ok(a) if a.body.starts_with(b"GIF89a") => {
                        gifs.fetch_add(1, Ordering::SeqCst);
                    }
                    Ok(_) => seen
                        .lock()
                        .unwrap()
                        .failures
                        .push("a GIF that is not one".into()),
                    Err(e) => seen.lock().unwrap().failures.push(e),
                }
            }
        });
    });
    let mut seen = seen.into_inner().unwrap();
    let (rounds, gifs) = (rounds.into_inner(), gifs.into_inner());
    // Every version answered came with the text it was made from (read under one lock).
    for (version, text) in &seen.versions {
        match seen.edits.get(version) {
            Some(h) if h == text => {}
            Some(_) => seen.failures.push(format!(
                "version {version} answered with another version's text"
            )),
            None => seen
                .failures
                .push(format!("version {version} answered, no edit made it")),
        }
    }
    seen.latencies.sort();
    let l = &seen.latencies;
    let ms = |d: Duration| d.as_secs_f64() * 1000.0;
    let (p50, p99, max) = (quantile(l, 0.5), quantile(l, 0.99), l[l.len() - 1]);
    println!(
        "studio load: {CLIENTS} clients for {:?}: {rounds} rounds and {} polls ({} requests, \
         {} failed), {gifs} GIF exports beside them; /api/status p50 {:.1} ms, p99 {:.1} ms, \
         max {:.1} ms",
        load_time(),
        l.len() - rounds,
        rounds * 5 + l.len() + gifs,
        seen.failures.len(),
        ms(p50),
        ms(p99),
        ms(max),
    );
    assert!(
        seen.failures.is_empty(),
        "{} failures, the first: {:#?}",
        seen.failures.len(),
        &seen.failures[..seen.failures.len().min(5)]
    );
    assert!(rounds >= CLIENTS, "{rounds} rounds in all");
    assert!(gifs > 0, "no GIF finished");
    // Polling waits for no render, export or rebuild: a lock or a queue shared with them
    // would put whole renders into these (a GIF export, 1.4 s here, is running most of the
    // minute). Measured: 8 ms p99 on a 2-core host at load 20 (36 ms with no gate); the
    // bounds leave room for a busy CI machine.
    assert!(p99 < Duration::from_millis(500), "p99 {p99:?}");
    assert!(max < Duration::from_secs(3), "max {max:?}");
}

/// `/api/status` on a fresh connection: the answer, and how long it took.
fn poll(s: &Studio) -> (Result<Answer, String>, Duration) {
    let started = Instant::now();
    let mut c = Client::new(s);
    (c.send("GET", "/api/status", b""), started.elapsed())
}

#[test]
fn two_hundred_trickling_clients_leave_the_page_served() {
    let s = Studio::start("trickle");
    let mut slow: Vec<TcpStream> = (0..200)
        .map(|_| TcpStream::connect(("127.0.0.1", s.port)).unwrap())
        .collect();
    let stop = Arc::new(AtomicBool::new(false));
    // One byte on each connection every 100 ms: each request is still arriving.
    let trickler = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let head = b"GET /api/status HTTP/1.1\r\nX-Trickle: ";
            let mut at = 0;
            while !stop.load(Ordering::SeqCst) {
                let byte = head.get(at).copied().unwrap_or(b'a');
                for c in &mut slow {
                    c.write_all(&[byte]).unwrap();
                }
                at += 1;
                std::thread::sleep(Duration::from_millis(100));
            }
            slow
        })
    };
    std::thread::sleep(Duration::from_millis(500));
    for i in 0..10 {
        let (answer, took) = poll(&s);
        let answer = answer.and_then(|a| a.expect(200, "status")).unwrap();
        assert!(answer.json().unwrap()["version"].is_u64());
        assert!(
            took < Duration::from_secs(1),
            "poll {i} answered in {took:?} beside 200 trickling clients"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    stop.store(true, Ordering::SeqCst);
    let slow = trickler.join().unwrap();
    assert_eq!(slow.len(), 200);
}

/// The first answer to `request`, sent on a fresh connection that the server must then
/// close: its status and head. Nothing is sent after `request` (an HTTP/0.9 request waits
/// for its answer), so an answer that comes only at the request timeout (10 s) is missed.
fn refusal(port: u16, request: &[u8]) -> (u16, String) {
    let mut c = TcpStream::connect(("127.0.0.1", port)).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    c.write_all(request).unwrap();
    let mut bytes = Vec::new();
    c.read_to_end(&mut bytes)
        .unwrap_or_else(|e| panic!("{:?}: no answer ({e})", String::from_utf8_lossy(request)));
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{:?}: answered {text:?}", String::from_utf8_lossy(request)));
    (status, text)
}

#[test]
fn malformed_requests_are_refused_with_their_status() {
    let s = Studio::start("malformed");
    let (port, token) = (s.port, s.token.clone());
    let host = format!("Host: 127.0.0.1:{port}\r\n");
    let auth = format!("{host}X-Gmotion-Token: {token}\r\n");
    let get = |target: &str| format!("GET {target} HTTP/1.1\r\n{auth}Connection: close\r\n\r\n");
    let with = |headers: &str| {
        format!("PUT /api/grammar HTTP/1.1\r\n{auth}{headers}Connection: close\r\n\r\n")
    };
    let cases: Vec<(&str, Vec<u8>, u16)> = vec![
        ("no request line", b"GARBAGE\r\n\r\n".to_vec(), 400),
        ("two spaces", get("/api/status").replacen(' ', "  ", 1).into(), 400),
        ("HTTP/0.9, answered at once", b"GET /\r\n".to_vec(), 400),
        ("HTTP/2.0", get("/").replace("HTTP/1.1", "HTTP/2.0").into(), 505),
        ("not HTTP", get("/").replace("HTTP/1.1", "FTP/1.1").into(), 400),
        (
            "no Host",
            format!("GET /api/status?token={token} HTTP/1.1\r\n\r\n").into(),
            400,
        ),
        (
            "two Hosts",
            format!("GET /api/status?token={token} HTTP/1.1\r\n{host}{host}\r\n").into(),
            400,
        ),
        (
            "a 70 KiB header",
            format!("GET / HTTP/1.1\r\n{host}X-Big: {}\r\n\r\n", "a".repeat(70 << 10)).into(),
            431,
        ),
        (
            "Content-Length past 64 bits",
            with("Content-Length: 99999999999999999999999\r\n").into(),
            413,
        ),
        ("negative Content-Length", with("Content-Length: -1\r\n").into(), 400),
        ("signed Content-Length", with("Content-Length: +1\r\n").into(), 400),
        (
            "Content-Lengths that disagree",
            with("Content-Length: 5\r\nContent-Length: 6\r\n").into(),
            400,
        ),
        ("a chunked body", with("Transfer-Encoding: chunked\r\n").into(), 411),
        ("a gzip body", with("Transfer-Encoding: gzip\r\n").into(), 501),
        (
            "both lengths",
            with("Transfer-Encoding: chunked\r\nContent-Length: 3\r\n").into(),
            400,
        ),
        // Refused before the body is read: none is sent.
        ("a body past 4 MiB", with("Content-Length: 5000000\r\n").into(), 413),
        ("dot segments", get("/api/../api/status").into(), 404),
        ("encoded dot segments", get("/api/%2e%2e/status").into(), 404),
        ("out of the root", get("/%2e%2e/%2e%2e/etc/passwd").into(), 404),
        ("a double slash", get("//api/status").into(), 404),
        ("an encoded NUL", get("/api/status%00").into(), 404),
        ("a raw NUL", get("/api/status\0").into(), 400),
        ("an unknown method", get("/api/status").replace("GET", "BREW").into(), 501),
        ("DELETE, not served", get("/api/state").replace("GET", "DELETE").into(), 501),
        ("PUT on a GET route", get("/api/status").replace("GET", "PUT").into(), 405),
        ("POST on the page", get("/").replace("GET", "POST").into(), 405),
        (
            "a wrong token",
            get("/api/status").replace(&token, &"0".repeat(32)).into(),
            403,
        ),
        (
            "absolute form",
            format!(
                "GET http://127.0.0.1:{port}/api/status HTTP/1.1\r\n{auth}Connection: close\r\n\r\n"
            )
            .into(),
            200,
        ),
        (
            "absolute form, another host",
            format!(
                "GET http://evil.example:{port}/api/status HTTP/1.1\r\n{auth}Connection: close\r\n\r\n"
            )
            .into(),
            403,
        ),
        ("asterisk form", get("*").into(), 400),
        (
            "a header without a colon",
            get("/").replace("Connection: close", "Connection close").into(),
            400,
        ),
        (
            "a space before the colon",
            get("/").replace("Connection: close", "Connection : close").into(),
            400,
        ),
        (
            "a folded header",
            get("/").replace("Connection: close", "X-A: b\r\n  c\r\nConnection: close").into(),
            400,
        ),
        ("non-UTF-8 in a header", {
            let mut b = get("/").replace("Connection: close", "X-A: \u{1}").into_bytes();
            let at = b.iter().position(|&x| x == 1).unwrap();
            b[at] = 0xff;
            b
        }, 400),
        ("non-UTF-8 in the target", {
            let mut b = get("/api/status\u{1}").into_bytes();
            let at = b.iter().position(|&x| x == 1).unwrap();
            b[at] = 0xc3;
            b
        }, 400),
    ];
    let mut wrong = Vec::new();
    for (what, request, expected) in &cases {
        let (status, answer) = refusal(port, request);
        if status != *expected {
            wrong.push(format!(
                "{what}: {status} instead of {expected}: {answer:?}"
            ));
        }
        if *expected == 405 && !answer.contains("\r\nAllow: ") {
            wrong.push(format!("{what}: a 405 without Allow: {answer:?}"));
        }
        let (after, took) = poll(&s);
        if after.and_then(|a| a.expect(200, "status")).is_err() || took > Duration::from_secs(1) {
            wrong.push(format!("{what}: the next poll failed or took {took:?}"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}
