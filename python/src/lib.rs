//! `prism._prism`: the native half of prism's Python package (python/prism). It wraps the
//! engine and its libraries as they are: scenes from prism-io's loaders or the built-ins,
//! renders through `prism::render::render_region` with the GIL released, images written
//! and compared by prism-io and prism-lab, the acceleration benchmark of prism-lab. NumPy
//! stays on the Python side: pixels cross as bytes of little-endian f32, which the
//! package views as an (H, W, 3) array, so this crate needs no NumPy binding.
//!
//! Every error reaches Python as an exception (`errors.rs`); no panic crosses the border
//! (PyO3 turns a stray one into `PanicException`, and the code below returns errors
//! instead of unwrapping anything that input can break).

mod bench;
mod errors;
mod image;
mod overrides;
mod render;
mod scene;
mod settings;

use pyo3::prelude::*;

/// The module Python imports as `prism._prism`.
#[pymodule]
fn _prism(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtin, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtins, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_files, m)?)?;
    m.add_function(wrap_pyfunction!(image::write, m)?)?;
    m.add_function(wrap_pyfunction!(image::read, m)?)?;
    m.add_function(wrap_pyfunction!(image::compare, m)?)?;
    m.add_function(wrap_pyfunction!(bench::bench, m)?)?;
    m.add_function(wrap_pyfunction!(settings::settings, m)?)?;
    m.add_function(wrap_pyfunction!(settings::integer_ranges, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
