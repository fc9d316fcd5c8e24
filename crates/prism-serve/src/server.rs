//! The HTTP side: the routes (the embedded page, its script and style sheet, the WebSocket;
//! a 404 for every other path, so no request path ever reaches the file system), the
//! same-origin check on the WebSocket, and the [`Server`] handle that starts the render
//! thread and the network thread and stops them.

use crate::assets;
use crate::engine::{self, Link};
use crate::limits::MAX_TRANSPORT_BYTES;
use crate::socket;
use axum::extract::ws::WebSocketUpgrade;
use axum::extract::State;
use axum::http::{header, HeaderMap, HeaderValue, Method, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use prism::{RenderOptions, Scene};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpListener};
use std::sync::atomic::Ordering;
use std::thread::JoinHandle;

/// Where the server listens.
#[derive(Clone, Debug)]
pub struct ServerConfig {
    /// The address to bind; 127.0.0.1 by default, so only this machine can connect.
    pub bind: IpAddr,
    /// The port; 0 lets the system choose a free one (see [`Server::url`]).
    pub port: u16,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 8000,
        }
    }
}

/// Why the server could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The address could not be bound (in use, not this machine's, no permission).
    // The system's words are in the message, so the field is no `source`: a chain printer
    // (anyhow's `{:#}`) would print them a second time.
    #[error("cannot listen on {addr}: {cause} (--port 0 takes any free port)")]
    Bind {
        /// The address asked for.
        addr: SocketAddr,
        /// What the system said.
        cause: std::io::Error,
    },
    /// A thread or the network runtime could not be started.
    #[error("cannot start the viewer: {0}")]
    Start(#[from] std::io::Error),
    /// The scene's options cannot render.
    #[error("invalid option: {0}")]
    Options(String),
}

/// A running viewer: the network thread serving pages and the render thread.
pub struct Server {
    addr: SocketAddr,
    link: Link,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    network: Option<JoinHandle<()>>,
    render: Option<JoinHandle<()>>,
}

impl Server {
    /// Binds `config`'s address and starts serving `scene` (named `name` on the page),
    /// rendered with `options`. Returns once the socket is bound: pages can connect.
    pub fn start(
        scene: Scene,
        name: &str,
        options: RenderOptions,
        config: &ServerConfig,
    ) -> Result<Server, ServeError> {
        options.validate().map_err(ServeError::Options)?;
        let addr = SocketAddr::new(config.bind, config.port);
        let listener = TcpListener::bind(addr).map_err(|cause| ServeError::Bind { addr, cause })?;
        listener.set_nonblocking(true)?;
        let addr = listener.local_addr()?;
        let (link, render) = engine::start(scene, name, options)?;
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()?;
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let app = router(link.clone(), addr.ip().is_loopback());
        let network = std::thread::Builder::new()
            .name("prism-serve network".into())
            .spawn(move || {
                runtime.block_on(async move {
                    let listener = match tokio::net::TcpListener::from_std(listener) {
                        Ok(l) => l,
                        Err(e) => {
                            eprintln!("prism serve: cannot listen: {e}");
                            return;
                        }
                    };
                    let served = axum::serve(listener, app).with_graceful_shutdown(async {
                        let _ = stopped.await;
                    });
                    if let Err(e) = served.await {
                        eprintln!("prism serve: the server stopped: {e}");
                    }
                });
            })?;
        Ok(Server {
            addr,
            link,
            stop: Some(stop),
            network: Some(network),
            render: Some(render),
        })
    }

    /// The address the server listens on (with the port the system chose for port 0).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The page's address, to open in a browser.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Frames rendered and published since the start: stops growing while no page is
    /// connected.
    pub fn frames_rendered(&self) -> u64 {
        self.link.shared.frames.load(Ordering::SeqCst)
    }

    /// Blocks until the server stops (it runs until the process ends).
    pub fn wait(mut self) {
        if let Some(network) = self.network.take() {
            let _ = network.join();
        }
    }

    /// Stops serving: open connections are closed, the render thread ends.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        self.link.shared.cancel.store(true, Ordering::SeqCst);
        if let Some(network) = self.network.take() {
            let _ = network.join();
        }
        // The last command sender goes with the link (after the network thread's copies),
        // which ends the render thread's wait.
        let Server { link, render, .. } = self;
        let (commands, _) = std::sync::mpsc::channel();
        drop(std::mem::replace(&mut link.commands, commands));
        if let Some(render) = render.take() {
            let _ = render.join();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// The routes; `loopback` says the server listens on a loopback address only, where
/// requests must name this machine (`check_host`).
fn router(link: Link, loopback: bool) -> Router {
    Router::new()
        .route("/ws", get(websocket))
        .fallback(asset)
        .layer(axum::middleware::from_fn_with_state(loopback, check_host))
        .with_state(link)
}

/// On a loopback address, refuses a request whose Host is not this machine's name: a
/// site whose name an attacker made resolve to 127.0.0.1 (DNS rebinding) would otherwise
/// be same-origin with the viewer in the user's browser.
async fn check_host(
    State(loopback): State<bool>,
    request: axum::extract::Request,
    next: axum::middleware::Next,
) -> Response {
    if loopback && !local_host(request.headers()) {
        return (
            StatusCode::FORBIDDEN,
            "the viewer answers only requests for localhost or a loopback address\n",
        )
            .into_response();
    }
    next.run(request).await
}

/// A Host header naming `localhost`, an IPv4 loopback address or `[::1]`, with any port.
fn local_host(headers: &HeaderMap) -> bool {
    let Some(host) = headers.get(header::HOST).and_then(|h| h.to_str().ok()) else {
        return false;
    };
    let name = match host.strip_prefix('[') {
        Some(v6) => v6.split(']').next().unwrap_or(""),
        None => host.split(':').next().unwrap_or(""),
    };
    name.eq_ignore_ascii_case("localhost")
        || name.parse::<IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

/// The embedded file at exactly the request's path, or 404. The path is compared as
/// received (still percent-encoded), never decoded, joined or looked up on disk.
async fn asset(method: Method, uri: Uri) -> Response {
    let found =
        assets::find(uri.path()).filter(|_| method == Method::GET || method == Method::HEAD);
    match found {
        Some(asset) => (
            [
                (
                    header::CONTENT_TYPE,
                    HeaderValue::from_static(asset.content_type),
                ),
                (header::CACHE_CONTROL, HeaderValue::from_static("no-cache")),
                (
                    header::X_CONTENT_TYPE_OPTIONS,
                    HeaderValue::from_static("nosniff"),
                ),
                (
                    header::CONTENT_SECURITY_POLICY,
                    HeaderValue::from_static(
                        "default-src 'self'; connect-src 'self'; img-src 'self' blob: data:; \
                         frame-ancestors 'none'",
                    ),
                ),
            ],
            asset.body,
        )
            .into_response(),
        None => (
            StatusCode::NOT_FOUND,
            "not found: the viewer serves only its page, /\n",
        )
            .into_response(),
    }
}

/// The WebSocket, for pages of this server only: a browser sends the page's origin, and a
/// page of another site (which could otherwise steer the render from the user's browser)
/// is refused. Clients that are not browsers send no origin.
async fn websocket(
    State(link): State<Link>,
    headers: HeaderMap,
    upgrade: WebSocketUpgrade,
) -> Response {
    if !same_origin(&headers) {
        return (
            StatusCode::FORBIDDEN,
            "the viewer's WebSocket takes only its own page\n",
        )
            .into_response();
    }
    upgrade
        .max_message_size(MAX_TRANSPORT_BYTES)
        .max_frame_size(MAX_TRANSPORT_BYTES)
        .on_upgrade(move |socket| socket::run(socket, link))
}

/// No Origin header, or one whose host and port are the Host header's.
fn same_origin(headers: &HeaderMap) -> bool {
    let Some(origin) = headers.get(header::ORIGIN) else {
        return true;
    };
    let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
    let origin = origin
        .to_str()
        .ok()
        .and_then(|o| o.split_once("://"))
        .map(|(_, rest)| rest);
    matches!((origin, host), (Some(o), Some(h)) if o.eq_ignore_ascii_case(h))
}
