//! The viewer's page, script and style sheet, compiled into the binary: the server answers
//! exactly these paths from memory, so no request ever reaches the file system.

/// One embedded file: where it is served, what it is, and its bytes.
pub(crate) struct Asset {
    pub(crate) path: &'static str,
    pub(crate) content_type: &'static str,
    pub(crate) body: &'static str,
}

/// Every path the server answers besides the WebSocket; anything else is a 404.
pub(crate) const ASSETS: [Asset; 3] = [
    Asset {
        path: "/",
        content_type: "text/html; charset=utf-8",
        body: include_str!("../assets/index.html"),
    },
    Asset {
        path: "/viewer.js",
        content_type: "text/javascript; charset=utf-8",
        body: include_str!("../assets/viewer.js"),
    },
    Asset {
        path: "/viewer.css",
        content_type: "text/css; charset=utf-8",
        body: include_str!("../assets/viewer.css"),
    },
];

/// The asset served at exactly `path`, if any.
pub(crate) fn find(path: &str) -> Option<&'static Asset> {
    ASSETS.iter().find(|a| a.path == path)
}
