//! [`ErrorBodies`]: gives the HTTP layer's own error responses the API's JSON error body.
//!
//! When a request cannot even be parsed (a malformed head: 400, a target too long: 414, a
//! head too large: 431), hyper answers by itself, before any handler runs, with an empty
//! body and `connection: close`. Every other error of the API is `{"error", "path"}`, so
//! these are rewritten on their way to the socket: a response head that hyper wrote alone
//! (an error status, `content-length: 0`, `connection: close`, nothing after it) gets a
//! JSON body saying what was wrong. The handlers' own responses always carry a body, so they
//! never match.

use std::io;
use std::pin::Pin;
use std::task::{Context, Poll, ready};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

/// A socket whose writes pass through, but for the HTTP layer's bodiless error responses.
pub(super) struct ErrorBodies<T> {
    inner: T,
    /// A rewritten response still to be written (reported to hyper as written already).
    pending: Vec<u8>,
    sent: usize,
}

impl<T> ErrorBodies<T> {
    pub(super) fn new(inner: T) -> Self {
        Self { inner, pending: Vec::new(), sent: 0 }
    }
}

/// The JSON error body for hyper's bodiless error head `head`, if it is one.
fn with_body(head: &[u8]) -> Option<Vec<u8>> {
    // Most writes are bodies: a look at the first bytes sets them aside.
    if !head.starts_with(b"HTTP/1.") || head.len() > 1024 {
        return None;
    }
    let text = std::str::from_utf8(head).ok()?;
    let status_line = text.strip_prefix("HTTP/1.1 ").or_else(|| text.strip_prefix("HTTP/1.0 "))?;
    let (code, reason) = status_line.split_once("\r\n")?.0.split_once(' ')?;
    let lower = text.to_ascii_lowercase();
    let bodiless = text.ends_with("\r\n\r\n")
        && text.matches("\r\n\r\n").count() == 1
        && lower.contains("\r\ncontent-length: 0\r\n")
        && lower.contains("\r\nconnection: close\r\n");
    if !(bodiless && (code.starts_with('4') || code.starts_with('5'))) {
        return None;
    }
    let why = match code {
        "400" => "the request is not valid HTTP/1.1: its request line or a header is malformed",
        "414" => "the request target (the URL) is too long",
        "431" => "the request head (its headers) is too large",
        _ => "the request could not be read as HTTP/1.1",
    };
    let body = serde_json::json!({"error": format!("{reason}: {why}"), "path": null}).to_string();
    let at = lower.find("\r\ncontent-length: 0\r\n")?;
    let rest = &text[at + "\r\ncontent-length: 0\r\n".len()..];
    Some(
        format!(
            "{}\r\ncontent-type: application/json\r\nx-content-type-options: nosniff\r\n\
             content-length: {}\r\n{rest}{body}",
            &text[..at],
            body.len()
        )
        .into_bytes(),
    )
}

impl<T: AsyncWrite + Unpin> ErrorBodies<T> {
    /// Writes what is pending; ready once nothing is.
    fn drain(&mut self, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        while self.sent < self.pending.len() {
            let n = ready!(Pin::new(&mut self.inner).poll_write(cx, &self.pending[self.sent..]))?;
            if n == 0 {
                return Poll::Ready(Err(io::ErrorKind::WriteZero.into()));
            }
            self.sent += n;
        }
        self.pending.clear();
        self.sent = 0;
        Poll::Ready(Ok(()))
    }
}

impl<T: AsyncRead + Unpin> AsyncRead for ErrorBodies<T> {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_read(cx, buf)
    }
}

impl<T: AsyncWrite + Unpin> AsyncWrite for ErrorBodies<T> {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        ready!(self.drain(cx))?;
        if let Some(rewritten) = with_body(buf) {
            self.pending = rewritten;
            // Whatever does not go out now goes out on the next write, flush or shutdown.
            let _ = self.drain(cx)?;
            return Poll::Ready(Ok(buf.len()));
        }
        Pin::new(&mut self.inner).poll_write(cx, buf)
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let mut non_empty = bufs.iter().filter(|b| !b.is_empty());
        if let (Some(only), None) = (non_empty.next(), non_empty.next()) {
            return self.poll_write(cx, only);
        }
        ready!(self.drain(cx))?;
        Pin::new(&mut self.inner).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        ready!(self.drain(cx))?;
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        ready!(self.drain(cx))?;
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::with_body;

    #[test]
    fn only_bodiless_error_heads_get_a_body() {
        let hyper_431 = b"HTTP/1.1 431 Request Header Fields Too Large\r\nconnection: close\r\n\
                          content-length: 0\r\ndate: Thu, 26 Nov 2026 04:25:20 GMT\r\n\r\n";
        let out = String::from_utf8(with_body(hyper_431).expect("rewritten")).expect("UTF-8");
        let (head, body) = out.split_once("\r\n\r\n").expect("a head and a body");
        assert!(head.contains("content-type: application/json"), "{head}");
        assert!(head.contains(&format!("content-length: {}", body.len())), "{head}");
        let json: serde_json::Value = serde_json::from_str(body).expect("JSON");
        assert!(json["error"].as_str().unwrap_or_default().contains("too large"), "{json}");
        assert!(json["path"].is_null());
        // The app's own responses pass untouched.
        let ok = b"HTTP/1.1 200 OK\r\ncontent-length: 0\r\nconnection: close\r\n\r\n";
        let with_a_body = b"HTTP/1.1 400 Bad Request\r\nconnection: close\r\n\
                            content-length: 12\r\n\r\n{\"error\":1}";
        let keep_alive = b"HTTP/1.1 404 Not Found\r\ncontent-length: 0\r\n\r\n";
        for buf in [&ok[..], &with_a_body[..], &keep_alive[..], b"{\"error\": 1}"] {
            assert!(with_body(buf).is_none(), "{}", String::from_utf8_lossy(buf));
        }
    }
}
