//! One page's WebSocket: it sends the page the hello, the state and every frame, and turns
//! the page's messages into checked commands for the render thread. A message that cannot
//! be used (not JSON, unknown type or field, a number out of range, a camera that cannot
//! render, a binary message, one above the size limit) is answered with an error message
//! and the connection goes on. A page that is slow to read gets the newest frame when it
//! is ready, never a queue of old ones.

use crate::controls::{self, Setting};
use crate::engine::{Command, Link};
use crate::limits::{MAX_CLIENTS, SEND_TIMEOUT_SECONDS};
use crate::protocol::{self, ClientMessage, ServerMessage};
use crate::steer::{self, Motion};
use axum::extract::ws::{Message, WebSocket};
use prism::camera::{Camera, Projection};
use prism::math::Vec3;
use std::sync::atomic::Ordering;
use std::time::Duration;
use tokio::sync::{broadcast, oneshot};

/// A page's place among the [`MAX_CLIENTS`], freed however the connection ends.
struct Place(std::sync::Arc<crate::engine::Shared>);

impl Drop for Place {
    fn drop(&mut self) {
        self.0.clients.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Tells the render thread the page has gone, however the connection ended.
struct Leave(std::sync::mpsc::Sender<Command>);

impl Drop for Leave {
    fn drop(&mut self) {
        let _ = self.0.send(Command::Leave);
    }
}

/// Sends one message, or fails when the page takes longer than
/// [`SEND_TIMEOUT_SECONDS`] to accept it.
async fn send_to(socket: &mut WebSocket, message: Message) -> Result<(), ()> {
    let limit = Duration::from_secs(SEND_TIMEOUT_SECONDS);
    match tokio::time::timeout(limit, socket.send(message)).await {
        Ok(Ok(())) => Ok(()),
        _ => Err(()),
    }
}

/// Serves one page until it closes or the connection fails.
pub(crate) async fn run(mut socket: WebSocket, link: Link) {
    let before = link.shared.clients.fetch_add(1, Ordering::SeqCst);
    let _place = Place(link.shared.clone());
    if before >= MAX_CLIENTS {
        let message = format!("too many pages: the viewer serves at most {MAX_CLIENTS} at once");
        let _ = send_to(
            &mut socket,
            Message::Text(ServerMessage::Error { message }.to_json().into()),
        )
        .await;
        let _ = socket.send(Message::Close(None)).await;
        return;
    }
    if link.commands.send(Command::Join).is_err() {
        return;
    }
    let _leave = Leave(link.commands.clone());
    let mut frames = link.frames.clone();
    let mut state = link.state.clone();
    let mut events = link.events.subscribe();
    let hello = Message::Text(link.hello.as_ref().into());
    let first_state = Message::Text(state.borrow_and_update().as_str().into());
    if send_to(&mut socket, hello).await.is_err()
        || send_to(&mut socket, first_state).await.is_err()
    {
        return;
    }
    loop {
        tokio::select! {
            incoming = socket.recv() => {
                let reply = match incoming {
                    None | Some(Err(_)) | Some(Ok(Message::Close(_))) => return,
                    Some(Ok(Message::Text(text))) => handle(text.as_str(), &link).await,
                    Some(Ok(Message::Binary(_))) => Err(
                        "binary messages are not read: send JSON text (docs/viewer.md)".to_string()
                    ),
                    // The library answers pings itself.
                    Some(Ok(Message::Ping(_) | Message::Pong(_))) => Ok(None),
                };
                let out = match reply {
                    Ok(Some(bytes)) => Message::Binary(bytes),
                    Ok(None) => continue,
                    Err(message) => Message::Text(ServerMessage::Error { message }.to_json().into()),
                };
                if send_to(&mut socket, out).await.is_err() {
                    return;
                }
            }
            changed = frames.changed() => {
                if changed.is_err() {
                    return;
                }
                let frame = frames.borrow_and_update().clone();
                if let Some(bytes) = frame {
                    if send_to(&mut socket, Message::Binary(bytes)).await.is_err() {
                        return;
                    }
                }
            }
            changed = state.changed() => {
                if changed.is_err() {
                    return;
                }
                let text = state.borrow_and_update().clone();
                if send_to(&mut socket, Message::Text(text.into())).await.is_err() {
                    return;
                }
            }
            event = events.recv() => match event {
                Ok(text) => {
                    if send_to(&mut socket, Message::Text(text.into())).await.is_err() {
                        return;
                    }
                }
                Err(broadcast::error::RecvError::Lagged(_)) => {}
                Err(broadcast::error::RecvError::Closed) => return,
            },
        }
    }
}

/// Acts on one text message: Ok(Some) is a binary reply for this page alone (a saved
/// image), Ok(None) no reply, Err an error message.
async fn handle(text: &str, link: &Link) -> Result<Option<axum::body::Bytes>, String> {
    let command = match protocol::parse(text)? {
        ClientMessage::Move { orbit, pan, zoom } => {
            let motion = Motion { orbit, pan, zoom };
            // Range checks here, so the sender hears of them; the render thread checks
            // that the moved camera renders.
            motion.check().map_err(|e| e.to_string())?;
            Command::Move(motion)
        }
        ClientMessage::Camera {
            eye,
            look_at,
            up,
            fov,
        } => {
            let camera = Camera {
                eye: Vec3::from(eye),
                look_at: Vec3::from(look_at),
                up: Vec3::from(up),
                fov_degrees: fov,
                projection: Projection::Perspective,
            };
            steer::check_camera(&camera).map_err(|e| e.to_string())?;
            Command::Camera(camera)
        }
        ClientMessage::ResetCamera => Command::ResetCamera,
        ClientMessage::Set { control, value } => Command::Set(controls::parse(&control, &value)?),
        ClientMessage::Save => {
            let (tx, rx) = oneshot::channel();
            send(link, Command::Save(tx))?;
            return rx
                .await
                .map_err(|_| "the render thread has stopped".to_string())?
                .map(Some)
                .map_err(|e| format!("cannot save the image: {e}"));
        }
    };
    // A new view shows the same samples; anything else makes the frame in flight stale.
    let restart = !matches!(command, Command::Set(Setting::View(_)));
    send(link, command)?;
    if restart {
        link.shared.cancel.store(true, Ordering::SeqCst);
    }
    Ok(None)
}

fn send(link: &Link, command: Command) -> Result<(), String> {
    link.commands
        .send(command)
        .map_err(|_| "the render thread has stopped".to_string())
}
