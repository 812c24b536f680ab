//! The connection layer against clients that would starve it, over real TCP: a request head
//! or body that does not arrive, a kept-alive connection left idle, a stream whose client
//! stops reading, more connections than the cap, and HTTP/1.1 without `Host`. Each is cut
//! off within its limit and the server goes on serving. (Shutdown and running out of file
//! descriptors are tested on the binary, in `server/tests/`.)

use nhlab_server::{Config, serve};
use nhlab_tests::TestServer;
use serde_json::{Value, json};
use std::time::{Duration, Instant};
use tokio::net::{TcpSocket, TcpStream};

fn options(header_timeout: f64, write_timeout: f64, max_connections: usize) -> serve::Options {
    serve::Options {
        header_timeout: Duration::from_secs_f64(header_timeout),
        write_timeout: Duration::from_secs_f64(write_timeout),
        max_connections,
    }
}

/// Writes all of `data` (tokio's `io-util` is not among the workspace's features).
async fn write_all(stream: &TcpStream, mut data: &[u8]) -> std::io::Result<()> {
    while !data.is_empty() {
        stream.writable().await?;
        match stream.try_write(data) {
            Ok(n) => data = &data[n..],
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Reads what has arrived (0 at the end).
async fn read(stream: &TcpStream, buffer: &mut [u8]) -> std::io::Result<usize> {
    loop {
        stream.readable().await?;
        match stream.try_read(buffer) {
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
            result => return result,
        }
    }
}

async fn connect(server: &TestServer) -> TcpStream {
    TcpStream::connect(server.url.trim_start_matches("http://")).await.unwrap()
}

/// Reads until the server closes the connection (failing after `limit`): what it sent and
/// when it closed.
async fn until_closed(stream: &mut TcpStream, limit: Duration) -> (String, Duration) {
    let start = Instant::now();
    let mut received = Vec::new();
    let read = tokio::time::timeout(limit, async {
        let mut buffer = [0; 4096];
        loop {
            match read(stream, &mut buffer).await {
                Ok(0) | Err(_) => break,
                Ok(n) => received.extend_from_slice(&buffer[..n]),
            }
        }
    });
    read.await.unwrap_or_else(|_| panic!("still open after {limit:?}"));
    (String::from_utf8_lossy(&received).into_owned(), start.elapsed())
}

/// The status and JSON body of a whole response in `text` (sent with `Content-Length`).
fn parse(text: &str) -> (u16, Value) {
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or_else(|| panic!("{text}"));
    let status = head.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap();
    (status, serde_json::from_str(body).unwrap_or(Value::Null))
}

#[tokio::test]
async fn a_request_head_must_arrive_within_the_header_timeout() {
    let server = TestServer::with_options(Config::default(), options(0.5, 30.0, 64)).await;
    let start = Instant::now();
    // Nothing sent at all.
    let mut silent = connect(&server).await;
    // Part of a head, then nothing.
    let mut half = connect(&server).await;
    write_all(&half, b"GET /health HTTP/1.1\r\nHost: nhlab\r\nAcc").await.unwrap();
    // A head sent a byte every 100 ms: slow enough to miss the deadline though never idle.
    let trickle = connect(&server).await;
    let head = b"GET /health HTTP/1.1\r\nHost: nhlab\r\nAccept: application/json\r\n\r\n";
    let trickling = tokio::spawn(async move {
        for byte in head {
            if write_all(&trickle, &[*byte]).await.is_err() {
                break;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        trickle
    });
    for (name, stream) in [("silent", &mut silent), ("half", &mut half)] {
        let (text, _) = until_closed(stream, Duration::from_secs(5)).await;
        let took = start.elapsed();
        eprintln!("{name}: closed {took:?} after it opened");
        assert!(took >= Duration::from_millis(300), "{name}: {took:?}");
        assert!(!text.contains("200 OK"), "{name}: {text}");
    }
    let mut trickle = trickling.await.unwrap();
    let (text, _) = until_closed(&mut trickle, Duration::from_secs(5)).await;
    assert!(!text.contains("200 OK"), "trickle: {text}");
    assert_eq!(server.health().await["status"], "ok");
}

#[tokio::test]
async fn an_idle_keep_alive_connection_is_closed_after_the_header_timeout() {
    let server = TestServer::with_options(Config::default(), options(0.5, 30.0, 64)).await;
    let mut stream = connect(&server).await;
    for _ in 0..2 {
        write_all(&stream, b"GET /health HTTP/1.1\r\nHost: nhlab\r\n\r\n").await.unwrap();
        let mut buffer = [0; 4096];
        let n = read(&stream, &mut buffer).await.unwrap();
        assert!(buffer[..n].starts_with(b"HTTP/1.1 200"));
        // Kept alive: shorter pauses than the timeout do not close it.
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
    let (text, took) = until_closed(&mut stream, Duration::from_secs(5)).await;
    eprintln!("idle connection closed after {took:?} more");
    assert!(text.is_empty(), "{text}");
}

#[tokio::test]
async fn a_body_that_does_not_arrive_in_time_gets_408() {
    let config = Config { body_timeout: Duration::from_millis(500), ..Config::default() };
    let server = TestServer::with_options(config, options(10.0, 30.0, 64)).await;
    let mut stream = connect(&server).await;
    let start = Instant::now();
    let head = b"POST /simulate HTTP/1.1\r\nHost: nhlab\r\nContent-Type: application/json\r\n\
                 Content-Length: 100\r\n\r\n{\"system\": \"kni";
    write_all(&stream, head).await.unwrap();
    let (text, _) = until_closed(&mut stream, Duration::from_secs(5)).await;
    let took = start.elapsed();
    eprintln!("408 after {took:?}");
    let (status, body) = parse(&text);
    assert_eq!(status, 408, "{text}");
    assert_eq!(body["path"], Value::Null);
    assert!(body["error"].as_str().unwrap().contains("body_timeout"), "{body}");
    assert!(took >= Duration::from_millis(450), "{took:?}");
    // A body that does arrive is read as ever.
    let (status, body) =
        server.post_json("/simulate", &json!({"system": "knife_edge", "points": 10})).await;
    assert_eq!(status, 200, "{body}");
}

#[tokio::test]
async fn http_1_1_without_host_gets_400_naming_the_header() {
    let server = TestServer::start().await;
    let exchange = |request: &'static str| {
        let server = &server;
        async move {
            let mut stream = connect(server).await;
            write_all(&stream, request.as_bytes()).await.unwrap();
            let (text, _) = until_closed(&mut stream, Duration::from_secs(5)).await;
            (parse(&text), text)
        }
    };
    let ((status, body), text) =
        exchange("GET /health HTTP/1.1\r\nConnection: close\r\n\r\n").await;
    assert_eq!(status, 400, "{text}");
    assert!(text.contains("content-type: application/json"), "{text}");
    assert_eq!(body["path"], Value::Null);
    assert!(body["error"].as_str().unwrap().contains("Host"), "{body}");
    // A POST without Host is refused before its body is read.
    let ((status, _), text) = exchange(
        "POST /simulate HTTP/1.1\r\nContent-Type: application/json\r\nContent-Length: 2\r\n\
         Connection: close\r\n\r\n{}",
    )
    .await;
    assert_eq!(status, 400, "{text}");
    // An absolute-form target names the host; HTTP/1.0 needs no Host.
    for request in [
        "GET http://nhlab/health HTTP/1.1\r\nConnection: close\r\n\r\n",
        "GET /health HTTP/1.0\r\n\r\n",
        "GET /health HTTP/1.1\r\nHost: nhlab\r\nConnection: close\r\n\r\n",
    ] {
        let ((status, body), text) = exchange(request).await;
        assert_eq!((status, &body["status"]), (200, &json!("ok")), "{request}: {text}");
    }
}

#[tokio::test]
async fn a_stream_whose_client_stops_reading_is_closed_and_frees_its_slot() {
    let write_timeout = 1.0;
    let config =
        Config { max_simulations: 1, report_every: Duration::from_millis(5), ..Config::default() };
    let server = TestServer::with_options(config, options(10.0, write_timeout, 64)).await;
    // A client with a small receive window that never reads.
    let socket = TcpSocket::new_v4().unwrap();
    socket.set_recv_buffer_size(4096).unwrap();
    let address = server.url.trim_start_matches("http://").parse().unwrap();
    let mut stream = socket.connect(address).await.unwrap();
    // Many points, within the answer budget: frequent `points` events fill the buffers.
    let body = json!({"system": "cvt_pendulum", "preset": "rotating", "t_end": 1e6,
                      "points": 20_000})
    .to_string();
    let request = format!(
        "POST /simulate HTTP/1.1\r\nHost: nhlab\r\nAccept: text/event-stream\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    write_all(&stream, request.as_bytes()).await.unwrap();

    let start = Instant::now();
    while server.health().await["simulations"] != 1 {
        assert!(start.elapsed() < Duration::from_secs(5), "the stream did not start");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let started = Instant::now();
    let limit = Duration::from_secs_f64(write_timeout + 10.0);
    loop {
        let h = server.health().await;
        if h["simulations"] == 0 && h["active_runs"] == 0 {
            break;
        }
        assert!(started.elapsed() < limit, "still busy {limit:?} after the stream began: {h}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let freed = started.elapsed();
    eprintln!("slot free {freed:?} after the stream began (write timeout {write_timeout} s)");
    // Not much before: the write timeout counts from when the buffers are full, which is
    // after the stream began (seen here a little late on a busy machine).
    assert!(freed >= Duration::from_secs_f64(write_timeout * 0.5), "{freed:?}");
    // The server closed the connection; the client still holds it open.
    let (text, _) = until_closed(&mut stream, Duration::from_secs(10)).await;
    assert!(text.starts_with("HTTP/1.1 200"));
    assert!(!text.contains("event: done"), "the stream should not have finished");
}

#[tokio::test]
async fn beyond_the_connection_cap_new_clients_wait_their_turn() {
    let server = TestServer::with_options(Config::default(), options(1.0, 30.0, 8)).await;
    let mut idle = Vec::new();
    for _ in 0..20 {
        idle.push(connect(&server).await);
    }
    let start = Instant::now();
    let client = reqwest::Client::builder().timeout(Duration::from_secs(20)).build().unwrap();
    let response = client.get(server.at("/health")).send().await.expect("answered in turn");
    let waited = start.elapsed();
    eprintln!("/health answered after {waited:?} behind 20 idle connections (cap 8)");
    assert_eq!(response.status(), 200);
    // The idle ones went first, 8 at a time, each closed by the header timeout.
    assert!(waited >= Duration::from_millis(900), "{waited:?}");
    for mut stream in idle {
        let (text, _) = until_closed(&mut stream, Duration::from_secs(10)).await;
        assert!(text.is_empty(), "{text}");
    }
    assert_eq!(server.health().await["status"], "ok");
}

#[tokio::test]
async fn requests_hyper_cannot_read_get_a_json_error_too() {
    let server = TestServer::start().await;
    let long_target = format!("GET /{} HTTP/1.1\r\nHost: nhlab\r\n\r\n", "a".repeat(70_000));
    let headers: String = (0..200).map(|i| format!("X-A{i}: {}\r\n", "b".repeat(1000))).collect();
    let big_head = format!("GET / HTTP/1.1\r\nHost: nhlab\r\n{headers}\r\n");
    for (request, status, words) in [
        ("GARBAGE\r\n\r\n".to_owned(), 400, "malformed"),
        ("GET / HTTP/1.1\r\nHost: nhlab\r\nBad Header\r\n\r\n".to_owned(), 400, "malformed"),
        (long_target, 414, "too long"),
        (big_head, 431, "too large"),
    ] {
        let mut stream = connect(&server).await;
        // The server may answer and close before it has read all of a huge head.
        let _ = write_all(&stream, request.as_bytes()).await;
        let (text, _) = until_closed(&mut stream, Duration::from_secs(5)).await;
        let (got, body) = parse(&text);
        assert_eq!(got, status, "{text}");
        assert!(text.contains("content-type: application/json"), "{text}");
        assert!(body["error"].as_str().unwrap_or_default().contains(words), "{body}");
        assert_eq!(body["path"], Value::Null);
    }
}
