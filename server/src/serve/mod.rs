//! [`serve`]: the server's connection layer, which accepts TCP connections and speaks
//! HTTP/1.1 on them (hyper's http1 connection, hyper-util's graceful shutdown) with the
//! limits that keep slow, stalled or numerous clients from starving everyone else. The app
//! ([`app`](crate::app)) sees requests only; what a connection may cost is decided here.
//!
//! - **Header timeout** ([`Options::header_timeout`], `--header-timeout`, 10 s): a client
//!   must send its whole request head within it, or its connection is closed. The same
//!   timer runs while a kept-alive connection waits for its next request (hyper starts it
//!   whenever a connection is ready to read a head), so an idle keep-alive connection is
//!   closed after the header timeout too: there is no separate idle timeout.
//! - **Body timeout** (`--body-timeout`, 10 s): the app's
//!   ([`Config::body_timeout`](crate::Config::body_timeout)); a body that does not arrive in
//!   time gets 408 from [`JsonObject`](crate::JsonObject).
//! - **Write timeout** ([`Options::write_timeout`], `--write-timeout`, 30 s): a connection
//!   whose writes make no progress for that long (the client stopped reading) is closed.
//!   Closing drops the response body; a stream's body owns its runs' cancel guard, so its
//!   runs stop and its simulation slot is freed.
//! - **Connection cap** ([`Options::max_connections`], `--max-connections`, default
//!   [`default_max_connections`]): with that many connections open the server stops
//!   accepting, and new connections wait in the kernel's listen backlog until one closes
//!   (rather than being accepted and closed at once: a waiting client is served late
//!   instead of failed, and no descriptor is spent on it).
//! - **Out of descriptors** (`EMFILE`, `ENFILE` and the like on accept): logged once per
//!   burst, then accept is retried every [`ACCEPT_BACKOFF`] instead of spinning, so the
//!   server answers again as soon as descriptors free up.
//! - **Host**: an HTTP/1.1 request without a `Host` header (and without an absolute-form
//!   target) gets 400 with the API's JSON error, as RFC 9112 §3.2 asks.
//! - **Unreadable requests**: the 400, 414 and 431 that hyper sends by itself for a request
//!   it cannot parse get the API's JSON error body too (`error_bodies.rs`).
//! - **Shutdown**: when the `shutdown` future of [`serve`] resolves the listener is closed
//!   (new connections are refused), idle keep-alive connections and connections that have
//!   not delivered a complete request head are closed at once, and each connection with a
//!   request in flight is closed as soon as its response is delivered. [`serve`] returns
//!   when the last connection is closed; the caller bounds that wait (`--shutdown-grace`).

mod connection;
mod error_bodies;

use axum::Router;
use hyper::server::conn::http1;
use hyper_util::rt::TokioTimer;
use hyper_util::server::graceful::GracefulShutdown;
use std::future::Future;
use std::io;
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::sync::{Semaphore, watch};

/// Pause before accepting again after an accept error other than a connection's own
/// (typically `EMFILE`/`ENFILE`: out of file descriptors).
pub const ACCEPT_BACKOFF: Duration = Duration::from_millis(100);

/// Descriptors kept free below the process's limit when the connection cap is derived from
/// it: for the listener, the log, and what the runtime and the blocking pool open.
pub const DESCRIPTOR_MARGIN: u64 = 64;

/// Limits of the connection layer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// Time a client has to send a whole request head, counted from when the connection is
    /// ready to read one (opened, or idle after a response); then the connection is closed.
    pub header_timeout: Duration,
    /// Longest time a write may make no progress before the connection is closed.
    pub write_timeout: Duration,
    /// Most connections open at once; beyond, new ones wait in the listen backlog.
    pub max_connections: usize,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            header_timeout: Duration::from_secs(10),
            write_timeout: Duration::from_secs(30),
            max_connections: default_max_connections(),
        }
    }
}

/// The default connection cap: 1024, or fewer when the soft limit on open files
/// (`RLIMIT_NOFILE`) minus [`DESCRIPTOR_MARGIN`] is lower (at least 1).
pub fn default_max_connections() -> usize {
    const CAP: u64 = 1024;
    let cap = open_files_limit().map_or(CAP, |n| n.saturating_sub(DESCRIPTOR_MARGIN).min(CAP));
    usize::try_from(cap.max(1)).unwrap_or(1)
}

#[cfg(unix)]
fn open_files_limit() -> Option<u64> {
    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: `limit` is a valid, writable rlimit owned by this frame; the call only writes it.
    #[allow(unsafe_code, reason = "getrlimit has no safe wrapper in libc or std")]
    let result = unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut limit) };
    if result != 0 || limit.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    #[allow(clippy::useless_conversion, reason = "rlim_t is u32 on some targets")]
    u64::try_from(limit.rlim_cur).ok()
}

#[cfg(not(unix))]
fn open_files_limit() -> Option<u64> {
    None
}

/// Serves `app` on `listener` with `options` until `shutdown` resolves, then stops
/// accepting and returns once every connection has closed (see the module's doc).
pub async fn serve(
    listener: TcpListener,
    app: Router,
    options: Options,
    shutdown: impl Future<Output = ()>,
) {
    let mut http = http1::Builder::new();
    http.timer(TokioTimer::new()).header_read_timeout(options.header_timeout);
    let open = Arc::new(Semaphore::new(options.max_connections));
    let graceful = GracefulShutdown::new();
    let (stop_tx, stop_rx) = watch::channel(false);
    let mut out_of_descriptors = false;
    let mut at_cap = false;
    tokio::pin!(shutdown);
    loop {
        if open.available_permits() == 0 && !at_cap {
            tracing::warn!(
                "{} connections open (limit max_connections): new ones wait until one closes",
                options.max_connections
            );
        }
        at_cap = open.available_permits() == 0;
        let permit = tokio::select! {
            biased;
            () = &mut shutdown => break,
            permit = open.clone().acquire_owned() => match permit {
                Ok(permit) => permit,
                Err(_) => break, // never closed
            },
        };
        let accepted = tokio::select! {
            biased;
            () = &mut shutdown => break,
            accepted = listener.accept() => accepted,
        };
        let (stream, peer) = match accepted {
            Ok(accepted) => accepted,
            Err(e) if is_connection_error(&e) => continue,
            Err(e) => {
                if !out_of_descriptors {
                    tracing::error!(
                        "cannot accept connections: {e}; retrying every {ACCEPT_BACKOFF:?}"
                    );
                    out_of_descriptors = true;
                }
                drop(permit);
                tokio::select! {
                    biased;
                    () = &mut shutdown => break,
                    () = tokio::time::sleep(ACCEPT_BACKOFF) => continue,
                }
            }
        };
        if out_of_descriptors {
            tracing::info!("accepting connections again");
            out_of_descriptors = false;
        }
        let connection = connection::Connection {
            http: http.clone(),
            app: app.clone(),
            write_timeout: options.write_timeout,
            watcher: graceful.watcher(),
            stop: stop_rx.clone(),
            permit,
        };
        tokio::spawn(connection.run(stream, peer));
    }
    drop(listener);
    let _ = stop_tx.send(true);
    let open_now = graceful.count();
    if open_now > 0 {
        tracing::info!(
            "{open_now} connections open: each closes once it has nothing left to deliver"
        );
    }
    graceful.shutdown().await;
}

/// Errors of one connection that accept reports (it was reset before we took it): nothing
/// to wait for, accept the next.
fn is_connection_error(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::ConnectionRefused
            | io::ErrorKind::ConnectionAborted
            | io::ErrorKind::ConnectionReset
    )
}
