//! The messages between the page and the server. The page sends JSON text messages
//! ([`ClientMessage`]); the server sends JSON text ([`ServerMessage`]) and binary messages:
//! a 4-byte little-endian length, a JSON header of that length ([`FrameHeader`] or
//! [`SaveHeader`]), then the payload (RGBA pixels, or a PNG file). docs/viewer.md shows
//! each message.

use crate::controls::Control;
use crate::limits::MAX_MESSAGE_BYTES;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A message from a page. Unknown fields and unknown types are refused, so a typo in a
/// client is an error message, not a silently ignored change.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMessage {
    /// Camera motion (see `steer::Motion`); missing parts are zero.
    Move {
        /// Degrees to the right and upwards around the look-at point.
        #[serde(default)]
        orbit: [f32; 2],
        /// View heights to the right and upwards.
        #[serde(default)]
        pan: [f32; 2],
        /// Doublings of closeness.
        #[serde(default)]
        zoom: f32,
    },
    /// A whole camera.
    Camera {
        /// Eye point.
        eye: [f32; 3],
        /// Look-at point.
        look_at: [f32; 3],
        /// Up vector.
        up: [f32; 3],
        /// Field of view in degrees (perspective cameras).
        fov: f32,
    },
    /// Back to the scene's own camera.
    ResetCamera,
    /// A new value for one control (see `controls`).
    Set {
        /// The control's name.
        control: String,
        /// Its new value, as text.
        value: String,
    },
    /// Send this page the current image as a PNG file.
    Save,
}

/// Reads a page's text message, refusing one above [`MAX_MESSAGE_BYTES`] before parsing it.
pub fn parse(text: &str) -> Result<ClientMessage, String> {
    if text.len() > MAX_MESSAGE_BYTES {
        return Err(format!(
            "message of {} bytes refused: the viewer reads at most {MAX_MESSAGE_BYTES}",
            text.len()
        ));
    }
    serde_json::from_str(text).map_err(|e| format!("not a viewer message: {e}"))
}

/// A camera as the page is told it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraInfo {
    /// Eye point.
    pub eye: [f32; 3],
    /// Look-at point.
    pub look_at: [f32; 3],
    /// Up vector.
    pub up: [f32; 3],
    /// Field of view in degrees.
    pub fov: f32,
}

/// The limits, as the page is told them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitsInfo {
    /// Largest text message read.
    pub message_bytes: usize,
    /// Largest side of the image.
    pub side: u32,
    /// Most pixels.
    pub pixels: u32,
    /// Samples per pixel at which the accumulation stops.
    pub samples: u32,
}

/// A JSON text message to a page.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMessage {
    /// Sent once on connecting: the scene, the controls to build and the limits.
    Hello {
        /// The scene's name.
        scene: String,
        /// The controls, in order.
        controls: Vec<Control>,
        /// What the server accepts.
        limits: LimitsInfo,
    },
    /// The current settings and camera, sent to every page when any of them changes.
    State {
        /// Each control's current value.
        values: BTreeMap<String, String>,
        /// The current camera.
        camera: CameraInfo,
        /// Counts the changes; frames carry the generation they show.
        generation: u64,
    },
    /// A message was refused; the connection goes on.
    Error {
        /// Why, in words.
        message: String,
    },
}

impl ServerMessage {
    /// The message as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("server messages always serialize")
    }
}

/// The header of a binary frame message; the payload is width × height RGBA bytes, shown
/// scaled to `display`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameHeader {
    /// Always "frame".
    pub kind: String,
    /// Pixels per row of the payload.
    pub width: u32,
    /// Rows of the payload.
    pub height: u32,
    /// The image's size on the page: the payload's, or larger for a preview.
    pub display: [u32; 2],
    /// A preview: the first frame after a change, rendered at a fraction of the resolution
    /// (when full frames are slow) and not part of the accumulation.
    pub preview: bool,
    /// Samples per pixel accumulated in the image (0 for a preview).
    pub spp: u32,
    /// The settings' generation the frame shows (see `ServerMessage::State`).
    pub generation: u64,
    /// Wall-clock time of the last frame's render, in milliseconds.
    pub frame_ms: f64,
    /// Rays traced per second by the last frame.
    pub rays_per_s: f64,
    /// What the picture shows.
    pub view: String,
    /// True once the accumulation has reached its limit and rendering has stopped.
    pub converged: bool,
}

/// The header of a saved image; the payload is a PNG file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SaveHeader {
    /// Always "png".
    pub kind: String,
    /// A file name to offer for the download.
    pub name: String,
}

/// A binary message: the header's length, the header, the payload.
pub fn binary(header: &impl Serialize, payload: &[u8]) -> Vec<u8> {
    let json = serde_json::to_vec(header).expect("headers always serialize");
    let mut out = Vec::with_capacity(4 + json.len() + payload.len());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(payload);
    out
}

/// Splits a binary message into its JSON header and payload (for clients and tests).
pub fn split_binary(message: &[u8]) -> Option<(&str, &[u8])> {
    let len = u32::from_le_bytes(message.get(..4)?.try_into().ok()?) as usize;
    let header = std::str::from_utf8(message.get(4..4 + len)?).ok()?;
    Some((header, &message[4 + len..]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_parse_and_strangers_are_refused() {
        assert_eq!(
            parse(r#"{"type":"move","orbit":[1,2]}"#),
            Ok(ClientMessage::Move {
                orbit: [1.0, 2.0],
                pan: [0.0, 0.0],
                zoom: 0.0
            })
        );
        assert_eq!(parse(r#"{"type":"save"}"#), Ok(ClientMessage::Save));
        for bad in [
            "",
            "{",
            "null",
            "[]",
            r#"{"type":"move","orbit":[1,2],"speed":3}"#,
            r#"{"type":"launch"}"#,
            r#"{"orbit":[1,2]}"#,
            r#"{"type":"move","zoom":1e400}"#,
            r#"{"type":"move","zoom":NaN}"#,
            r#"{"type":"set","control":"depth","value":3}"#,
        ] {
            assert!(parse(bad).is_err(), "{bad}");
        }
        let long = format!(
            r#"{{"type":"set","control":"accel","value":"{}"}}"#,
            "a".repeat(MAX_MESSAGE_BYTES)
        );
        assert!(parse(&long).unwrap_err().contains("refused"));
    }

    #[test]
    fn binary_messages_split_back() {
        let header = SaveHeader {
            kind: "png".into(),
            name: "a.png".into(),
        };
        let m = binary(&header, &[1, 2, 3]);
        let (h, p) = split_binary(&m).unwrap();
        assert_eq!(serde_json::from_str::<SaveHeader>(h).unwrap(), header);
        assert_eq!(p, &[1, 2, 3]);
        assert!(split_binary(&[9, 0, 0, 0, b'{']).is_none());
    }
}
