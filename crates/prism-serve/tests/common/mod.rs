//! What the viewer's suites share: a server on a free port of the loopback, a blocking
//! WebSocket client that reads the viewer's messages, and plain HTTP requests written by
//! hand (so that a path reaches the server exactly as written, never normalised).

#![allow(dead_code)]

use prism_serve::protocol::{split_binary, FrameHeader};
use prism_serve::{Server, ServerConfig};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::{Ipv4Addr, TcpStream};
use std::time::{Duration, Instant};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// Generous: the suites share two cores with the rest of the test run.
pub(crate) const PATIENCE: Duration = Duration::from_secs(60);

/// The built-in Whitted scene served at `width` × `height` on an ephemeral port.
pub(crate) fn server(width: u32, height: u32) -> Server {
    server_with_threads(width, height, 0)
}

/// The same with `threads` render threads (0: every core).
pub(crate) fn server_with_threads(width: u32, height: u32, threads: usize) -> Server {
    let scene = prism::scene::builtin::find("whitted").expect("the built-in scene");
    let options = prism::RenderOptions {
        width,
        height,
        samples: 1,
        sampler: prism::sampling::SamplerKind::Jittered,
        threads,
        ..scene.options.clone()
    };
    let config = ServerConfig {
        bind: Ipv4Addr::LOCALHOST.into(),
        port: 0,
    };
    Server::start(scene, "builtin:whitted", options, &config).expect("the server starts")
}

/// A status code and body of one HTTP/1.1 request, the request target sent as written.
pub(crate) fn http(server: &Server, method: &str, target: &str) -> (u16, String) {
    let mut stream = TcpStream::connect(server.addr()).unwrap();
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    write!(
        stream,
        "{method} {target} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
        server.addr()
    )
    .unwrap();
    let mut bytes = Vec::new();
    let _ = stream.read_to_end(&mut bytes);
    let text = String::from_utf8_lossy(&bytes).to_string();
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    (status, text)
}

/// A page's WebSocket, read one message at a time.
pub(crate) struct Client {
    pub(crate) ws: WebSocket<MaybeTlsStream<TcpStream>>,
}

/// One message from the server.
pub(crate) enum Received {
    Text(Value),
    Frame(FrameHeader, Vec<u8>),
    Binary(Value, Vec<u8>),
    Closed,
}

impl Client {
    pub(crate) fn connect(server: &Server) -> Client {
        let (ws, _) = tungstenite::connect(format!("ws://{}/ws", server.addr())).expect("connects");
        if let MaybeTlsStream::Plain(s) = ws.get_ref() {
            s.set_read_timeout(Some(PATIENCE)).unwrap();
        }
        Client { ws }
    }

    pub(crate) fn send(&mut self, text: &str) {
        self.ws.send(Message::Text(text.into())).expect("sends");
    }

    pub(crate) fn receive(&mut self) -> Received {
        loop {
            match self.ws.read() {
                Ok(Message::Text(t)) => return Received::Text(serde_json::from_str(&t).unwrap()),
                Ok(Message::Binary(b)) => {
                    let (header, payload) = split_binary(&b).expect("a header");
                    let value: Value = serde_json::from_str(header).unwrap();
                    if value["kind"] == "frame" {
                        let h: FrameHeader = serde_json::from_value(value).unwrap();
                        return Received::Frame(h, payload.to_vec());
                    }
                    return Received::Binary(value, payload.to_vec());
                }
                Ok(Message::Close(_)) | Err(_) => return Received::Closed,
                Ok(_) => continue,
            }
        }
    }

    /// The next text message of type `kind`, skipping everything else.
    pub(crate) fn text(&mut self, kind: &str) -> Value {
        let deadline = Instant::now() + PATIENCE;
        while Instant::now() < deadline {
            match self.receive() {
                Received::Text(v) if v["type"] == kind => return v,
                Received::Closed => panic!("closed while waiting for {kind}"),
                _ => {}
            }
        }
        panic!("no {kind} message in time");
    }

    /// The next frame for which `accept` holds, skipping everything else.
    pub(crate) fn frame_where(
        &mut self,
        accept: impl Fn(&FrameHeader) -> bool,
    ) -> (FrameHeader, Vec<u8>) {
        let deadline = Instant::now() + PATIENCE;
        while Instant::now() < deadline {
            match self.receive() {
                Received::Frame(h, p) if accept(&h) => return (h, p),
                Received::Closed => panic!("closed while waiting for a frame"),
                _ => {}
            }
        }
        panic!("no such frame in time");
    }

    pub(crate) fn frame(&mut self) -> (FrameHeader, Vec<u8>) {
        self.frame_where(|_| true)
    }
}

/// Mean absolute difference of two RGBA images, per channel byte.
pub(crate) fn difference(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).abs())
        .sum::<f64>()
        / a.len() as f64
}
