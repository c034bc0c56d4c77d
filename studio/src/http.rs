//! A small HTTP/1.1 server over `std::net`: one thread per connection, keep-alive, bodies
//! by `Content-Length` only.
//!
//! Why not a crate: `tiny_http` 0.12, which the studio used, hands connections to a pool
//! that can queue a freshly accepted connection behind busy keep-alive ones (two accepts
//! in a row both see the one idle worker): the browser sends a request on that connection
//! and it is never read while the others stay open. The page's variation thumbnails
//! stayed blank that way on most loads. A thread per connection cannot starve; the
//! studio serves one local browser, which opens a handful of connections.

use std::io::{self, BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread;
use std::time::{Duration, Instant};

/// The most bytes of a request body read (a pasted grammar).
pub(crate) const MAX_BODY: usize = 4 << 20;

/// The most bytes of a request line and its headers.
const MAX_HEAD: usize = 64 << 10;

/// The most connections served at once; more are answered 503 and closed. A thread each,
/// mostly asleep: enough that 200 clients holding connections open (slow or stalled) leave
/// room for the page.
const MAX_CONNECTIONS: usize = 512;

/// How long an idle keep-alive connection is kept.
const IDLE: Duration = Duration::from_secs(30);

/// How long a request may take to arrive once its first byte has: a client trickling its
/// headers or body a byte at a time would otherwise hold its connection for ever, each
/// byte restarting the idle timeout.
const REQUEST_TIME: Duration = Duration::from_secs(10);

/// A request as read: method, target (path and query), headers and body.
#[derive(Debug)]
pub(crate) struct Request {
    pub method: String,
    pub target: String,
    headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Request {
    /// The value of header `name` (case-insensitive), if sent.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }
}

/// A response: status, headers and body (sent with its `Content-Length`).
#[derive(Debug)]
pub(crate) struct Response {
    pub status: u16,
    pub headers: Vec<(&'static str, String)>,
    pub body: Vec<u8>,
}

impl Response {
    /// A JSON `{"error": message}` with `status`.
    pub fn error(status: u16, message: &str) -> Response {
        Response {
            status,
            headers: vec![("Content-Type", "application/json".into())],
            body: serde_json::json!({ "error": message })
                .to_string()
                .into_bytes(),
        }
    }
}

/// What answers requests.
pub(crate) type Handler = dyn Fn(&Request) -> Response + Send + Sync;

/// Accepts connections on `listener` until the process ends, each served on its own
/// thread by `handler`.
pub(crate) fn serve(listener: TcpListener, handler: Arc<Handler>) -> io::Result<()> {
    let open = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if open.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::SeqCst);
            let _ = write_response(
                &mut stream,
                &Response::error(503, "too many connections"),
                true,
            );
            continue;
        }
        let (handler, count) = (Arc::clone(&handler), Arc::clone(&open));
        let spawned = thread::Builder::new()
            .name("studio-http".into())
            .spawn(move || {
                let _ = connection(stream, &*handler);
                count.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            open.fetch_sub(1, Ordering::SeqCst);
        }
    }
    Ok(())
}

/// Serves one connection's requests in order until the client closes it, asks to, goes
/// idle, or sends something unreadable (answered 400 or 413, then closed).
fn connection(stream: TcpStream, handler: &Handler) -> io::Result<()> {
    stream.set_read_timeout(Some(IDLE))?;
    let mut writer = stream.try_clone()?;
    let mut reader = BufReader::new(Timed {
        stream,
        deadline: None,
    });
    loop {
        reader.get_mut().deadline = None;
        let request = match read_request(&mut reader) {
            Ok(Some(r)) => r,
            Ok(None) => return Ok(()),
            Err(Refused(status, why)) => {
                write_response(&mut writer, &Response::error(status, why), true)?;
                return Ok(());
            }
        };
        let close = request
            .header("Connection")
            .is_some_and(|c| c.eq_ignore_ascii_case("close"));
        let response = handler(&request);
        write_response(&mut writer, &response, close)?;
        if close {
            return Ok(());
        }
    }
}

/// A request that cannot be served: the status and why.
struct Refused(u16, &'static str);

/// A connection's stream, read under a deadline once a request has begun: before its first
/// byte a read waits up to [`IDLE`], after it the rest must come within [`REQUEST_TIME`].
struct Timed {
    stream: TcpStream,
    /// When the request being read must be in, once its first byte has come.
    deadline: Option<Instant>,
}

impl Read for Timed {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let wait = match self.deadline {
            None => IDLE,
            Some(deadline) => deadline
                .checked_duration_since(Instant::now())
                .filter(|left| !left.is_zero())
                .ok_or_else(|| io::Error::new(io::ErrorKind::TimedOut, "the request is late"))?,
        };
        self.stream.set_read_timeout(Some(wait))?;
        let n = self.stream.read(buf)?;
        if n > 0 && self.deadline.is_none() {
            self.deadline = Some(Instant::now() + REQUEST_TIME);
        }
        Ok(n)
    }
}

/// The next request, `None` at a clean end of the connection (or an idle timeout).
fn read_request(reader: &mut BufReader<Timed>) -> Result<Option<Request>, Refused> {
    let mut head = Vec::new();
    loop {
        let before = head.len();
        let read = reader
            .by_ref()
            .take((MAX_HEAD - head.len()) as u64)
            .read_until(b'\n', &mut head);
        let n = match read {
            Ok(n) => n,
            // Idle between requests: the connection just ends.
            Err(e) if timed_out(&e) && head.is_empty() => return Ok(None),
            Err(e) if timed_out(&e) => {
                return Err(Refused(408, "the request took too long to arrive"));
            }
            Err(_) => return Err(Refused(400, "the request could not be read")),
        };
        if n == 0 {
            if head.is_empty() {
                return Ok(None);
            }
            return Err(Refused(400, "the request ended early"));
        }
        if head.len() >= MAX_HEAD {
            return Err(Refused(431, "the request's headers are too large"));
        }
        let line = &head[before..];
        // A blank line ends the head (blank lines before the request line are skipped).
        if (line == b"\r\n" || line == b"\n") && before > 0 {
            break;
        }
        if line == b"\r\n" || line == b"\n" {
            head.clear();
        }
    }
    let text = std::str::from_utf8(&head).map_err(|_| Refused(400, "the headers are not text"))?;
    let mut lines = text.lines();
    let mut first = lines.next().unwrap_or("").split(' ');
    let (Some(method), Some(target)) = (first.next(), first.next()) else {
        return Err(Refused(400, "a request line is METHOD TARGET HTTP/1.1"));
    };
    let mut headers = Vec::new();
    for line in lines.filter(|l| !l.is_empty()) {
        let Some((k, v)) = line.split_once(':') else {
            return Err(Refused(400, "a header is NAME: VALUE"));
        };
        headers.push((k.trim().to_string(), v.trim().to_string()));
    }
    let mut request = Request {
        method: method.to_string(),
        target: target.to_string(),
        headers,
        body: Vec::new(),
    };
    if request.header("Transfer-Encoding").is_some() {
        return Err(Refused(411, "send the body with a Content-Length"));
    }
    let length = match request.header("Content-Length").map(str::parse::<usize>) {
        None => 0,
        Some(Ok(n)) if n <= MAX_BODY => n,
        Some(Ok(_)) => return Err(Refused(413, "the body is larger than 4 MiB")),
        Some(Err(_)) => return Err(Refused(400, "Content-Length is not a number")),
    };
    request.body.resize(length, 0);
    reader.read_exact(&mut request.body).map_err(|e| {
        if timed_out(&e) {
            Refused(408, "the body took too long to arrive")
        } else {
            Refused(400, "the body ended early")
        }
    })?;
    Ok(Some(request))
}

/// Whether a read failed by waiting too long (a socket timeout reads as either kind).
fn timed_out(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
    )
}

/// Writes `response` with its length, and `Connection: close` when the connection ends.
fn write_response(out: &mut TcpStream, response: &Response, close: bool) -> io::Result<()> {
    let mut head = format!(
        "HTTP/1.1 {} {}\r\nContent-Length: {}\r\n",
        response.status,
        reason(response.status),
        response.body.len()
    );
    for (k, v) in &response.headers {
        head.push_str(&format!("{k}: {v}\r\n"));
    }
    if close {
        head.push_str("Connection: close\r\n");
    }
    head.push_str("\r\n");
    let mut bytes = head.into_bytes();
    bytes.extend_from_slice(&response.body);
    out.write_all(&bytes)?;
    out.flush()
}

/// The reason phrase of the statuses the studio answers with.
fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    }
}
