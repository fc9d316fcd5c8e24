//! What a client may ask for. A WebSocket message past these limits is answered with an
//! error message and the connection goes on; a resolution past them is refused the same
//! way. The transport limit is larger: a message above it cannot even be read whole, so
//! the WebSocket library closes that one connection (with close code 1009, "message too
//! big"), and the server and every other tab go on.

/// The largest text message the viewer reads; its real messages are under 300 bytes.
pub const MAX_MESSAGE_BYTES: usize = 16 * 1024;

/// The largest message or WebSocket frame the transport accepts before closing the
/// connection.
pub const MAX_TRANSPORT_BYTES: usize = 1024 * 1024;

/// The widest and tallest image a page may ask for.
pub const MAX_SIDE: u32 = 3840;

/// The most pixels a page may ask for: 2560 × 1440, 14 MiB per RGBA frame sent to every tab.
pub const MAX_PIXELS: u32 = 2560 * 1440;

/// The narrowest and lowest image.
pub const MIN_SIDE: u32 = 16;

/// The deepest ray tree the depth control allows (the engine allows 256; beyond a few
/// dozen bounces a Whitted image no longer changes, and a frame only gets slower).
pub const MAX_DEPTH: u32 = 64;

/// Samples per pixel at which the accumulation stops: the image has converged far past
/// 8-bit precision and the cores go back to everyone else.
pub const MAX_SAMPLES: u32 = 4096;

/// The largest camera coordinate accepted, in world units: far beyond any scene, small
/// enough that differences of coordinates stay finite in f32.
pub const MAX_COORDINATE: f32 = 1.0e7;

/// The most pages connected at once; one more is refused (503) until one closes. Each holds
/// up to a frame in its socket's buffers.
pub const MAX_CLIENTS: usize = 32;

/// Seconds a page may take to accept one message before the server drops it: a page that
/// stopped reading would otherwise keep the render running for nobody.
pub const SEND_TIMEOUT_SECONDS: u64 = 30;
