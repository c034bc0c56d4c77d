//! A small HTTP/1.1 server over `std::net`: one thread per connection, keep-alive, bodies
//! by `Content-Length` only. Everything it reads is bounded (connections, head, body, the
//! time a request and an answer may take), and what HTTP/1.1 asks a server to refuse is
//! refused with the status it names (`read_request`), the connection then closed.
//!
//! Why not a crate: `tiny_http` 0.12, which the studio used, hands connections to a pool
//! that can queue a freshly accepted connection behind busy keep-alive ones (two accepts
//! in a row both see the one idle worker): the browser sends a request on that connection
//! and it is never read while the others stay open. The page's variation thumbnails
//! stayed blank that way on most loads. A thread per connection cannot starve; the
//! studio serves one local browser, which opens a handful of connections.

use std::io::{self, BufRead, BufReader, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
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

    /// Every value of header `name`, a comma-separated list split (as HTTP joins repeated
    /// headers), trimmed.
    fn values<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a str> {
        self.headers
            .iter()
            .filter(move |(k, _)| k.eq_ignore_ascii_case(name))
            .flat_map(|(_, v)| v.split(','))
            .map(str::trim)
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

/// How long to wait before accepting again when accepting failed (out of file descriptors,
/// say): the failure repeats at once while the cause lasts, and retrying without a pause
/// would spin a core.
const ACCEPT_PAUSE: Duration = Duration::from_millis(50);

/// How long writing an answer may block on a client that does not read it (a large export
/// to a stalled reader would otherwise hold its thread for ever).
const WRITE_TIME: Duration = Duration::from_secs(30);

/// How long, and how many bytes, a refused request's remaining input is read and dropped
/// before its connection closes: closing a socket with unread input resets it, and the
/// reset can reach the client before the refusal does.
const LINGER: (Duration, u64) = (Duration::from_secs(1), 1 << 20);

/// The methods the server implements; any other is answered 501.
const METHODS: [&str; 3] = ["GET", "PUT", "POST"];

/// Accepts connections on `listener` until the process ends, each served on its own
/// thread by `handler`.
pub(crate) fn serve(listener: TcpListener, handler: Arc<Handler>) -> io::Result<()> {
    let open = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else {
            thread::sleep(ACCEPT_PAUSE);
            continue;
        };
        if open.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::SeqCst);
            let _ = stream.set_write_timeout(Some(Duration::from_secs(1)));
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

/// How a conversation ended.
#[derive(Debug, PartialEq)]
enum Ended {
    /// The client closed, went idle or asked to close.
    Closed,
    /// A request was refused (answered 4xx or 5xx) and the connection must close.
    Refused,
}

/// Serves one connection's requests in order until the client closes it, asks to, goes
/// idle, or sends something unreadable (answered with its 4xx or 5xx, then closed).
fn connection(stream: TcpStream, handler: &Handler) -> io::Result<()> {
    stream.set_read_timeout(Some(IDLE))?;
    stream.set_write_timeout(Some(WRITE_TIME))?;
    let mut reader = BufReader::new(Timed {
        stream: &stream,
        deadline: None,
    });
    let ended = converse(
        &mut reader,
        |r| r.get_mut().deadline = None,
        &mut &stream,
        handler,
    )?;
    if ended == Ended::Refused {
        // The answer is out: stop sending, and drop what the client still sends for a
        // moment so that closing does not reset the connection under the answer.
        stream.shutdown(Shutdown::Write)?;
        reader.get_mut().deadline = Some(Instant::now() + LINGER.0);
        let _ = io::copy(&mut reader.take(LINGER.1), &mut io::sink());
    }
    Ok(())
}

/// Answers the requests read from `reader` in order on `out`, until the input ends, a
/// request asks to close, or one is refused; `begin` runs before each request is read (a
/// connection restarts its deadline there).
fn converse<R: BufRead>(
    reader: &mut R,
    mut begin: impl FnMut(&mut R),
    out: &mut impl Write,
    handler: &dyn Fn(&Request) -> Response,
) -> io::Result<Ended> {
    loop {
        begin(reader);
        let (request, close) = match read_request(reader) {
            Ok(Some(r)) => r,
            Ok(None) => return Ok(Ended::Closed),
            Err(Refused(status, why)) => {
                write_response(out, &Response::error(status, why), true)?;
                return Ok(Ended::Refused);
            }
        };
        let response = handler(&request);
        write_response(out, &response, close)?;
        if close {
            return Ok(Ended::Closed);
        }
    }
}

/// What the server writes back for the bytes `input` sent on one connection: every
/// request in it answered in order, as [`serve`] answers them, without a socket.
pub(crate) fn answer(mut input: &[u8], handler: &dyn Fn(&Request) -> Response) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing to memory cannot fail.
    let _ = converse(&mut input, |_| {}, &mut out, handler);
    out
}

/// A request that cannot be served: the status and why.
struct Refused(u16, &'static str);

/// A connection's stream, read under a deadline once a request has begun: before its first
/// byte a read waits up to [`IDLE`], after it the rest must come within [`REQUEST_TIME`].
struct Timed<'a> {
    stream: &'a TcpStream,
    /// When the request being read must be in, once its first byte has come.
    deadline: Option<Instant>,
}

impl Read for Timed<'_> {
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

/// The next request and whether the connection closes after it, `None` at a clean end of
/// the connection (or an idle timeout). What HTTP/1.1 (RFC 9112) asks a server to refuse is
/// refused with the status it names: a malformed request line, header or `Content-Length`
/// 400, a version other than 1.0 or 1.1 505, a method the server does not implement 501, a
/// chunked body 411 (the API's bodies are sent with their length), any other transfer coding
/// 501, a head past [`MAX_HEAD`] 431 and a body past [`MAX_BODY`] 413 (before reading it).
fn read_request<R: BufRead>(reader: &mut R) -> Result<Option<(Request, bool)>, Refused> {
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
        } else if before == 0 {
            // The request line is judged as it arrives: an HTTP/0.9 request (`GET /`, no
            // version) sends no headers and waits, and is refused now, not at the timeout.
            let text = std::str::from_utf8(line)
                .map_err(|_| Refused(400, "the request line is not text"))?;
            request_line(text.trim_end_matches(['\r', '\n']))?;
        }
    }
    let text = std::str::from_utf8(&head).map_err(|_| Refused(400, "the headers are not text"))?;
    let mut lines = text.lines();
    let (method, target, version) = request_line(lines.next().unwrap_or(""))?;
    let mut headers = Vec::new();
    for line in lines.filter(|l| !l.is_empty()) {
        headers.push(header(line)?);
    }
    let mut request = Request {
        method: method.to_string(),
        target: String::new(),
        headers,
        body: Vec::new(),
    };
    // A request sent as to a proxy names its host in the target, which then counts over
    // the `Host` header (RFC 9112 §3.2.2); the routes see the path.
    request.target = match target.strip_prefix("http://") {
        Some(rest) => {
            let (authority, path) = rest.find('/').map_or((rest, "/"), |i| rest.split_at(i));
            request
                .headers
                .retain(|(k, _)| !k.eq_ignore_ascii_case("Host"));
            request.headers.push(("Host".into(), authority.to_string()));
            path.to_string()
        }
        None if target.starts_with('/') => target.to_string(),
        None => return Err(Refused(400, "the target must be a path")),
    };
    let hosts = request
        .headers
        .iter()
        .filter(|(k, _)| k.eq_ignore_ascii_case("Host"))
        .count();
    if version == "HTTP/1.1" && hosts != 1 {
        return Err(Refused(400, "an HTTP/1.1 request has one Host header"));
    }
    if !METHODS.contains(&method) {
        return Err(Refused(501, "the methods served are GET, PUT and POST"));
    }
    let length = body_length(&request)?;
    // HTTP/1.0 closes after each answer unless asked to keep the connection.
    let asked = |what: &str| {
        request
            .header("Connection")
            .is_some_and(|c| c.split(',').any(|o| o.trim().eq_ignore_ascii_case(what)))
    };
    let close = asked("close") || (version == "HTTP/1.0" && !asked("keep-alive"));
    request.body.resize(length, 0);
    reader.read_exact(&mut request.body).map_err(|e| {
        if timed_out(&e) {
            Refused(408, "the body took too long to arrive")
        } else {
            Refused(400, "the body ended early")
        }
    })?;
    Ok(Some((request, close)))
}

/// A request line's method, target and version: `METHOD TARGET HTTP/1.1`, single spaces,
/// the method a token, the target visible ASCII (no space, control byte or byte past
/// ASCII, which percent-encoding is for).
fn request_line(line: &str) -> Result<(&str, &str, &str), Refused> {
    let mut parts = line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(Refused(400, "a request line is METHOD TARGET HTTP/1.1"));
    };
    if !is_token(method) {
        return Err(Refused(400, "the method is not a token"));
    }
    if target.is_empty() || !target.bytes().all(|b| b.is_ascii_graphic()) {
        return Err(Refused(400, "the target is not a path"));
    }
    match version {
        "HTTP/1.1" | "HTTP/1.0" => Ok((method, target, version)),
        v if v.len() == 8
            && v.starts_with("HTTP/")
            && v.as_bytes()[5].is_ascii_digit()
            && v.as_bytes()[6] == b'.'
            && v.as_bytes()[7].is_ascii_digit() =>
        {
            Err(Refused(505, "the HTTP versions served are 1.0 and 1.1"))
        }
        _ => Err(Refused(400, "a request line is METHOD TARGET HTTP/1.1")),
    }
}

/// One header line as name and value: the name a token right before its colon (no space
/// between, RFC 9112 §5.1; no line folding either), the value trimmed.
fn header(line: &str) -> Result<(String, String), Refused> {
    let Some((name, value)) = line.split_once(':') else {
        return Err(Refused(400, "a header is NAME: VALUE"));
    };
    if !is_token(name) {
        return Err(Refused(
            400,
            "a header's name is a token right before its colon",
        ));
    }
    let value = value.trim_matches([' ', '\t']);
    if value.bytes().any(|b| b.is_ascii_control() && b != b'\t') {
        return Err(Refused(400, "a header's value holds a control byte"));
    }
    Ok((name.to_string(), value.to_string()))
}

/// Whether `s` is an HTTP token (RFC 9110 §5.6.2): a method or header name.
fn is_token(s: &str) -> bool {
    !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&b))
}

/// How many body bytes follow the head: every `Content-Length` must be digits and all
/// must agree (RFC 9112 §6.3: anything else is a framing the server cannot trust);
/// transfer codings are refused.
fn body_length(request: &Request) -> Result<usize, Refused> {
    let values = |name| request.values(name);
    if let Some(coding) = values("Transfer-Encoding").last() {
        if values("Content-Length").next().is_some() {
            return Err(Refused(
                400,
                "a request has a Content-Length or a Transfer-Encoding, not both",
            ));
        }
        if coding.eq_ignore_ascii_case("chunked") {
            return Err(Refused(411, "send the body with a Content-Length"));
        }
        return Err(Refused(501, "the transfer coding is not implemented"));
    }
    let mut length = None;
    for v in values("Content-Length") {
        if v.is_empty() || !v.bytes().all(|b| b.is_ascii_digit()) {
            return Err(Refused(400, "Content-Length is not a number"));
        }
        // All digits: only too large a number fails to parse.
        let n = v
            .parse::<usize>()
            .map_err(|_| Refused(413, "the body is larger than 4 MiB"))?;
        if length.is_some_and(|l| l != n) {
            return Err(Refused(400, "the Content-Length headers disagree"));
        }
        length = Some(n);
    }
    match length.unwrap_or(0) {
        n if n <= MAX_BODY => Ok(n),
        _ => Err(Refused(413, "the body is larger than 4 MiB")),
    }
}

/// Whether a read failed by waiting too long (a socket timeout reads as either kind).
fn timed_out(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
    )
}

/// Writes `response` with its length, and `Connection: close` when the connection ends.
fn write_response(out: &mut impl Write, response: &Response, close: bool) -> io::Result<()> {
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
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "Error",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The statuses answered to `input` on one connection, and the bodies of the 200s
    /// (each the request as the handler saw it: method, target, `Host` and body).
    fn exchange(input: &[u8]) -> (Vec<u16>, Vec<String>) {
        let out = answer(input, &|r: &Request| Response {
            status: 200,
            headers: Vec::new(),
            body: format!(
                "{} {} {} {}",
                r.method,
                r.target,
                r.header("Host").unwrap_or("-"),
                String::from_utf8_lossy(&r.body)
            )
            .into_bytes(),
        });
        let mut rest = String::from_utf8(out).unwrap();
        let (mut statuses, mut bodies) = (Vec::new(), Vec::new());
        while let Some((head, tail)) = rest.split_once("\r\n\r\n") {
            let length: usize = head
                .lines()
                .find_map(|l| l.strip_prefix("Content-Length: "))
                .unwrap()
                .parse()
                .unwrap();
            statuses.push(head["HTTP/1.1 ".len()..][..3].parse().unwrap());
            if head.starts_with("HTTP/1.1 200") {
                bodies.push(tail[..length].to_string());
            }
            rest = tail[length..].to_string();
        }
        (statuses, bodies)
    }

    #[test]
    fn pipelined_requests_are_answered_in_order_until_one_is_refused() {
        let (statuses, bodies) = exchange(
            b"GET /a HTTP/1.1\r\nHost: h\r\n\r\n\
              PUT /b HTTP/1.1\r\nHost: h\r\nContent-Length: 2\r\n\r\nhi\
              GET /c HTTP/1.1\r\n\r\n\
              GET /d HTTP/1.1\r\nHost: h\r\n\r\n",
        );
        // The third has no Host: refused, and the connection ends there.
        assert_eq!(statuses, [200, 200, 400]);
        assert_eq!(bodies, ["GET /a h ", "PUT /b h hi"]);
    }

    #[test]
    fn an_absolute_target_names_the_host_and_keeps_the_path() {
        let (statuses, bodies) =
            exchange(b"GET http://127.0.0.1:9/api/status?x=1 HTTP/1.1\r\nHost: other\r\n\r\n");
        assert_eq!(statuses, [200]);
        assert_eq!(bodies, ["GET /api/status?x=1 127.0.0.1:9 "]);
    }

    #[test]
    fn equal_content_lengths_are_one_and_a_list_of_them_too() {
        let (statuses, bodies) = exchange(
            b"PUT / HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\nContent-Length: 3, 3\r\n\r\nabc",
        );
        assert_eq!(statuses, [200]);
        assert_eq!(bodies, ["PUT / h abc"]);
    }

    #[test]
    fn http_1_0_closes_after_its_answer_unless_asked_to_stay() {
        let two = b"GET /a HTTP/1.0\r\n\r\nGET /b HTTP/1.0\r\n\r\n";
        assert_eq!(exchange(two).0, [200]);
        let kept = b"GET /a HTTP/1.0\r\nConnection: keep-alive\r\n\r\nGET /b HTTP/1.0\r\n\r\n";
        assert_eq!(exchange(kept).0, [200, 200]);
    }
}
