//! The exceptions prism raises in Python. `PrismError` is the root, so one `except` catches
//! everything prism refuses; the messages are prism's own, with file:line:col for a scene
//! file's mistakes. Arguments of the wrong value raise `ValueError`, as Python expects.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _prism,
    PrismError,
    PyException,
    "Something prism could not do; the message says what and where."
);
create_exception!(
    _prism,
    SceneError,
    PrismError,
    "A scene that cannot be loaded or rendered: the message names the file, line and column."
);
create_exception!(
    _prism,
    RenderError,
    PrismError,
    "A render that could not start or finish (memory, threads, the camera)."
);
create_exception!(
    _prism,
    ImageError,
    PrismError,
    "An image that cannot be written, read or compared."
);

/// Adds the exception classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("PrismError", py.get_type::<PrismError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("RenderError", py.get_type::<RenderError>())?;
    m.add("ImageError", py.get_type::<ImageError>())?;
    Ok(())
}

/// A bad argument: `ValueError` with `message`.
pub(crate) fn bad_argument(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// A scene error: the loader's message as it is (file:line:col: what).
pub(crate) fn scene_error(e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(e.to_string())
}

/// An image that could not be written, read or compared.
pub(crate) fn image_error(e: impl std::fmt::Display) -> PyErr {
    ImageError::new_err(e.to_string())
}

/// A render refused or failed by the engine. Options it refuses are the caller's
/// arguments, so they are a `ValueError`; the camera belongs to the scene. The engine's
/// advice names command-line flags (`--integrator whitted`); Python is told the keyword
/// (`integrator="whitted"`).
pub(crate) fn render_error(e: prism::render::RenderError) -> PyErr {
    use prism::render::RenderError as E;
    match e {
        E::Options(message) => bad_argument(keywords(&format!("invalid options: {message}"))),
        E::Camera(e) => SceneError::new_err(keywords(&format!("the scene's camera: {e}"))),
        other => RenderError::new_err(keywords(&other.to_string())),
    }
}

/// `message` with each `--flag VALUE` of a render setting written as the keyword
/// `Scene.render` takes, `key="VALUE"` (a flag without a value as its key alone). Other
/// text, and flags that are no setting's, stay as they are.
pub(crate) fn keywords(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        let flag_len = after
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .unwrap_or(after.len());
        let flag = &after[..flag_len];
        let setting = prism::options::SETTINGS
            .iter()
            .find(|s| !flag.is_empty() && s.flag == Some(flag));
        let Some(setting) = setting else {
            out.push_str("--");
            rest = after;
            continue;
        };
        let tail = &after[flag_len..];
        let value = tail.strip_prefix(' ').map(|v| {
            let end = v
                .find(|c: char| !(c.is_ascii_alphanumeric() || "_:=,.".contains(c)))
                .unwrap_or(v.len());
            // A sentence's full stop or comma is not part of the value.
            v[..end].trim_end_matches(['.', ','])
        });
        match value {
            Some(v) if !v.is_empty() => {
                out.push_str(&format!("{}=\"{v}\"", setting.key));
                rest = &tail[1 + v.len()..];
            }
            _ => {
                out.push_str(setting.key);
                rest = tail;
            }
        }
    }
    out.push_str(rest);
    out
}
