//! The HTTP front on the view's address: a WebSocket upgrade is passed byte
//! for byte to the Foxglove SDK's server (which serves WebSocket only, on an
//! ephemeral loopback port); any other GET serves the page's files, embedded
//! in the binary so that the page works offline.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// The longest request head read before the request is refused.
const MAX_HEAD: usize = 16 * 1024;

/// The page's files: (path, content type, bytes).
const PAGE: [(&str, &str, &[u8]); 4] = [
    ("/", "text/html; charset=utf-8", include_bytes!("../page/index.html")),
    (
        "/app.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../page/app.js"),
    ),
    (
        "/mcap.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../page/mcap.js"),
    ),
    (
        "/style.css",
        "text/css; charset=utf-8",
        include_bytes!("../page/style.css"),
    ),
];

/// The path a replayed recording is served at.
pub(crate) const RECORDING_PATH: &str = "/recording.mcap";

/// What the front passes on or serves.
#[derive(Debug)]
pub(crate) struct Front {
    /// The SDK's WebSocket server.
    pub upstream: SocketAddr,
    /// A recording served at [`RECORDING_PATH`], if any.
    pub recording: Option<PathBuf>,
}

/// Accepts connections on `listener` forever (until the runtime stops).
pub(crate) async fn serve(listener: TcpListener, front: Arc<Front>) {
    loop {
        let Ok((socket, _)) = listener.accept().await else {
            continue;
        };
        let front = front.clone();
        tokio::spawn(async move {
            // A client that goes away mid-request is no error of the view's.
            let _ = connection(socket, &front).await;
        });
    }
}

async fn connection(mut socket: TcpStream, front: &Front) -> std::io::Result<()> {
    let mut head = Vec::with_capacity(1024);
    let end = loop {
        if socket.read_buf(&mut head).await? == 0 {
            return Ok(());
        }
        if let Some(i) = head.windows(4).position(|w| w == b"\r\n\r\n") {
            break i;
        }
        if head.len() > MAX_HEAD {
            return respond(
                &mut socket,
                "431 Request Header Fields Too Large",
                "text/plain",
                b"",
                true,
            )
            .await;
        }
    };
    let text = String::from_utf8_lossy(&head[..end]);
    let mut lines = text.split("\r\n");
    let mut request = lines.next().unwrap_or("").split_whitespace();
    let (method, target) = (request.next().unwrap_or(""), request.next().unwrap_or(""));
    let upgrade = lines.any(|line| {
        line.split_once(':').is_some_and(|(name, value)| {
            name.trim().eq_ignore_ascii_case("upgrade") && value.trim().eq_ignore_ascii_case("websocket")
        })
    });
    if upgrade {
        let mut upstream = TcpStream::connect(front.upstream).await?;
        upstream.write_all(&head).await?;
        tokio::io::copy_bidirectional(&mut socket, &mut upstream).await?;
        return Ok(());
    }
    let body_wanted = match method {
        "GET" => true,
        "HEAD" => false,
        _ => return respond(&mut socket, "405 Method Not Allowed", "text/plain", b"", true).await,
    };
    let path = target.split(['?', '#']).next().unwrap_or("/");
    let path = if path == "/index.html" { "/" } else { path };
    if let Some((_, kind, bytes)) = PAGE.iter().find(|(p, _, _)| *p == path) {
        return respond(&mut socket, "200 OK", kind, bytes, body_wanted).await;
    }
    if path == RECORDING_PATH
        && let Some(file) = &front.recording
    {
        let file = file.clone();
        let bytes = tokio::task::spawn_blocking(move || std::fs::read(file))
            .await
            .map_err(std::io::Error::other)?;
        return match bytes {
            Ok(bytes) => respond(&mut socket, "200 OK", "application/octet-stream", &bytes, body_wanted).await,
            Err(_) => {
                respond(
                    &mut socket,
                    "404 Not Found",
                    "text/plain",
                    b"recording unreadable\n",
                    body_wanted,
                )
                .await
            }
        };
    }
    respond(&mut socket, "404 Not Found", "text/plain", b"not found\n", body_wanted).await
}

async fn respond(
    socket: &mut TcpStream,
    status: &str,
    kind: &str,
    body: &[u8],
    with_body: bool,
) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    );
    socket.write_all(head.as_bytes()).await?;
    if with_body {
        socket.write_all(body).await?;
    }
    socket.shutdown().await
}
