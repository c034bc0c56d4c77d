//! gmotion studio: a local web editor for a grammar on a scene (issue 16, after gMotion
//! §4.3–4.4). The binary serves one HTML page (inline JS and CSS) and a JSON API the page
//! itself uses, so scripts and tests can drive the studio too; the API is documented in
//! `docs/studio.md`.
//!
//! The server is the crate's own small HTTP/1.1 server over `std::net` (`http`): a
//! thread per connection, no async runtime and no dependency, which keeps the build cheap
//! on a two-core machine; the studio serves one local user. Everything the page needs is embedded in
//! the binary (lottie-web is vendored from npm with its MIT licence in `assets/`): the page
//! makes no request outside its own server.
//!
//! Security: the server binds 127.0.0.1 only; every `/api/*` request needs the random
//! token of the session (query `token=` or header `X-Gmotion-Token`) and a `Host` header of
//! `127.0.0.1:PORT` or `localhost:PORT` (a page on another site that rebinds its DNS name to
//! 127.0.0.1 sends its own name as `Host`); anything else is answered 403. Malformed
//! requests are refused by the server with their 4xx or 5xx before any route runs
//! (`http`), and renders, exports and rebuilds take turns (`gate`) so that polling never
//! waits behind them.
#![forbid(unsafe_code)]

mod api;
mod gate;
mod http;
mod layers;
mod live;
mod offset;
mod retime;
mod value;

use std::io;
use std::net::TcpListener;
use std::path::PathBuf;
use std::sync::Arc;
use std::thread;

use gmotion::engine::RunOptions;
use gmotion_pipeline::{Imported, Rescene};

pub use live::{Live, MAX_MERGE_LINES, MergeError, Resolution, SaveError, shapes_json};

/// What a studio session edits.
#[derive(Debug)]
pub struct Config {
    /// The grammar file: read at start, watched, written by save.
    pub grammar_path: PathBuf,
    /// The scene the grammar runs on (with the Lottie document it came from), as imported
    /// under the grammar at start.
    pub imported: Imported,
    /// Imports the scene again when an edit changes the directives that decide the import
    /// (`scene`, `tag_from`, `units`, `unit_depth`, `tags`); without it the scene stays.
    pub rescene: Option<Rescene>,
    /// Overrides of the grammar's header (`--seed`, `--fps`, `--max-steps`).
    pub run: RunOptions,
    /// The port to bind on 127.0.0.1; 0 picks any free port.
    pub port: u16,
}

/// A bound studio server, not yet serving.
pub struct Studio {
    listener: TcpListener,
    /// The live state, the port and the token the routes check.
    ctx: Arc<api::Ctx>,
}

impl std::fmt::Debug for Studio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Studio")
            .field("port", &self.ctx.port)
            .finish()
    }
}

impl Studio {
    /// Loads the grammar (a broken one is kept with its diagnostics, and the studio starts
    /// with the scene still) and binds 127.0.0.1:`config.port`.
    pub fn bind(config: Config) -> io::Result<Studio> {
        let token = random_token()?;
        let listener = TcpListener::bind(("127.0.0.1", config.port)).map_err(|e| {
            io::Error::new(
                e.kind(),
                format!("cannot listen on 127.0.0.1:{}: {e}", config.port),
            )
        })?;
        let port = listener.local_addr()?.port();
        let live = Arc::new(Live::new(config)?);
        let ctx = api::Ctx {
            live,
            port,
            token,
            work: gate::Gate::cores_less_one(),
            exports: gate::Gate::new(1),
        };
        Ok(Studio {
            listener,
            ctx: Arc::new(ctx),
        })
    }

    /// The port bound.
    pub fn port(&self) -> u16 {
        self.ctx.port
    }

    /// The page's address, token included.
    pub fn url(&self) -> String {
        format!(
            "http://127.0.0.1:{}/?token={}",
            self.ctx.port, self.ctx.token
        )
    }

    /// The bytes the server would send back for `input` arriving on one connection: each
    /// request in it parsed and answered in order as [`Studio::serve`] answers them (the
    /// same limits, refusals and routes, edits included), without a socket. For the fuzz
    /// target, and for embedders that carry requests some other way.
    pub fn answer(&self, input: &[u8]) -> Vec<u8> {
        http::answer(input, &|request: &http::Request| {
            api::handle(&self.ctx, request)
        })
    }

    /// Serves until the process ends: a thread per connection and a thread that polls
    /// the grammar file.
    pub fn serve(self) -> io::Result<()> {
        let live = Arc::clone(&self.ctx.live);
        thread::Builder::new()
            .name("studio-watch".into())
            .spawn(move || live.watch())?;
        let ctx = self.ctx;
        http::serve(
            self.listener,
            Arc::new(move |request: &http::Request| api::handle(&ctx, request)),
        )
    }
}

/// Opens `url` in the desktop's browser (`xdg-open`, `open` on macOS); errors are ignored,
/// the address is printed anyway.
pub fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else {
        "xdg-open"
    };
    let _ = std::process::Command::new(opener)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
}

/// 16 random bytes from the system, in hex.
fn random_token() -> io::Result<String> {
    let mut bytes = [0u8; 16];
    io::Read::read_exact(&mut std::fs::File::open("/dev/urandom")?, &mut bytes)?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}
