//! [`Connection`]: one accepted TCP connection served to its end: its socket wrapped with the
//! write timeout and watched for pending writes ([`Tracked`]), the HTTP layer's own error
//! responses given a JSON body ([`ErrorBodies`]), its requests checked for
//! `Host` and counted while in flight ([`Activity`]), and its shutdown, which closes it as
//! soon as it has nothing left to deliver.

use super::error_bodies::ErrorBodies;
use crate::error::AppError;
use axum::Router;
use axum::body::Body;
use axum::http::{Request, Version, header};
use axum::response::IntoResponse;
use hyper::body::{Frame, Incoming, SizeHint};
use hyper::server::conn::http1;
use hyper::service::Service as _;
use hyper_util::rt::TokioIo;
use hyper_util::server::graceful::Watcher;
use hyper_util::service::TowerToHyperService;
use std::convert::Infallible;
use std::io;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::TcpStream;
use tokio::sync::{OwnedSemaphorePermit, watch};
use tokio_io_timeout::TimeoutStream;

/// How often a connection that had a request in flight at shutdown checks whether it has
/// delivered everything (hyper closes it itself once the response is written; this catches
/// a connection left with nothing to say but a client that said nothing more either).
const SHUTDOWN_POLL: Duration = Duration::from_millis(50);

/// What one connection needs to be served.
pub(super) struct Connection {
    pub(super) http: http1::Builder,
    pub(super) app: Router,
    pub(super) write_timeout: Duration,
    pub(super) watcher: Watcher,
    pub(super) stop: watch::Receiver<bool>,
    /// The connection's place under the cap, given back when it closes.
    pub(super) permit: OwnedSemaphorePermit,
}

impl Connection {
    /// Serves the connection until it closes, the client goes away, a timeout closes it, or
    /// shutdown finds it with nothing left to deliver.
    pub(super) async fn run(self, stream: TcpStream, peer: SocketAddr) {
        let Self { http, app, write_timeout, watcher, mut stop, permit: _open } = self;
        let activity = Arc::new(Activity::default());
        let mut timed = TimeoutStream::new(stream);
        timed.set_write_timeout(Some(write_timeout));
        let tracked = Tracked { inner: Box::pin(timed), activity: activity.clone() };
        let io = TokioIo::new(ErrorBodies::new(tracked));
        // The app behind the `Host` check, each request counted in flight until its
        // response body is dropped (delivered, or abandoned with the connection).
        let app = TowerToHyperService::new(app);
        let counted = activity.clone();
        let service = hyper::service::service_fn(move |request: Request<Incoming>| {
            let in_flight = InFlight::enter(&counted);
            let checked = missing_host(&request).map(|()| app.call(request));
            async move {
                let response = match checked {
                    Ok(call) => call.await?,
                    Err(error) => error.into_response(),
                };
                Ok::<_, Infallible>(response.map(|body| Counted { body, _in_flight: in_flight }))
            }
        });
        let connection = watcher.watch(http.serve_connection(io, service));
        tokio::pin!(connection);
        tokio::select! {
            result = connection.as_mut() => return ended(result, peer),
            _ = stop.wait_for(|&stop| stop) => {}
        }
        // Shutting down: the watcher has asked hyper to close the connection after the
        // response in flight (and hyper closes an idle one at once). A connection with no
        // request in flight and no write pending has nothing left to deliver: a client that
        // sent part of a request head, or nothing, does not hold up the exit.
        loop {
            if activity.is_quiet() {
                tracing::debug!(%peer, "closing a connection with no request in flight");
                break;
            }
            tokio::select! {
                result = connection.as_mut() => return ended(result, peer),
                () = tokio::time::sleep(SHUTDOWN_POLL) => {}
            }
        }
    }
}

fn ended(result: Result<(), hyper::Error>, peer: SocketAddr) {
    if let Err(e) = result {
        // Timeouts, resets and malformed requests: the client's doing, not worth a warning.
        tracing::debug!(%peer, "connection closed: {e}");
    }
}

/// RFC 9112 §3.2: an HTTP/1.1 request must name its host, in `Host` or in an absolute-form
/// target. (HTTP/1.0 had no such rule.)
fn missing_host(request: &Request<Incoming>) -> Result<(), AppError> {
    let named = request.version() != Version::HTTP_11
        || request.headers().contains_key(header::HOST)
        || request.uri().authority().is_some();
    if named {
        Ok(())
    } else {
        Err(AppError::bad_request("an HTTP/1.1 request must have a Host header (RFC 9112 §3.2)"))
    }
}

/// What a connection is doing, as far as shutdown needs to know.
#[derive(Debug, Default)]
struct Activity {
    /// Requests handed to the app whose response body is not yet dropped.
    in_flight: AtomicUsize,
    /// Whether the last write or flush on the socket is waiting for the client to read.
    write_pending: AtomicBool,
}

impl Activity {
    /// No request in flight and nothing waiting to be written.
    fn is_quiet(&self) -> bool {
        self.in_flight.load(Ordering::SeqCst) == 0 && !self.write_pending.load(Ordering::SeqCst)
    }
}

/// Counts one request in flight until dropped.
struct InFlight(Arc<Activity>);

impl InFlight {
    fn enter(activity: &Arc<Activity>) -> Self {
        activity.in_flight.fetch_add(1, Ordering::SeqCst);
        Self(activity.clone())
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        self.0.in_flight.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A response body that counts its request in flight as long as it lives.
struct Counted {
    body: Body,
    _in_flight: InFlight,
}

impl hyper::body::Body for Counted {
    type Data = <Body as hyper::body::Body>::Data;
    type Error = <Body as hyper::body::Body>::Error;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Self::Data>, Self::Error>>> {
        Pin::new(&mut self.body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

/// The socket with its write timeout, noting whether a write is pending.
struct Tracked {
    inner: Pin<Box<TimeoutStream<TcpStream>>>,
    activity: Arc<Activity>,
}

impl Tracked {
    fn note<T>(&self, poll: Poll<T>) -> Poll<T> {
        self.activity.write_pending.store(poll.is_pending(), Ordering::SeqCst);
        poll
    }
}

impl AsyncRead for Tracked {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        self.inner.as_mut().poll_read(cx, buf)
    }
}

impl AsyncWrite for Tracked {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let poll = self.inner.as_mut().poll_write(cx, buf);
        self.note(poll)
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let poll = self.inner.as_mut().poll_write_vectored(cx, bufs);
        self.note(poll)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let poll = self.inner.as_mut().poll_flush(cx);
        self.note(poll)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        self.inner.as_mut().poll_shutdown(cx)
    }
}
