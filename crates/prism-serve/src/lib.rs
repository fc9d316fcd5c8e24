//! prism's live viewer: `prism serve` starts a local web server whose one page shows a
//! render refining frame by frame, and steers it. The camera (orbit, pan, zoom) and the
//! settings (integrator, accelerator, sampler, depth, shadow method, view, resolution) come
//! back over one WebSocket; any change restarts the accumulation.
//!
//! The pieces, in the order they depend on each other: [`limits`] and `assets` (the page,
//! embedded in the binary) ← [`protocol`] (the messages), [`steer`] (camera motion),
//! [`controls`] (the settings a page may change) and [`source`] (where frames come from:
//! [`source::Frames`], the engine's progressive accumulation) ← `picture` (a frame's pixels for the page, and the
//! PNG a page saves) ← `engine` (the render thread) ← `socket` (one browser tab) ←
//! `server` (the HTTP routes and the [`Server`] handle). docs/viewer.md has the protocol.

mod assets;
pub mod controls;
mod engine;
pub mod limits;
mod picture;
pub mod protocol;
mod server;
mod socket;
pub mod source;
pub mod steer;

pub use server::{ServeError, Server, ServerConfig};
