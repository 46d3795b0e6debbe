//! sturmray from Python: the `sturmray._sturmray` extension module that
//! `python/sturmray/__init__.py` re-exports (docs/python.md). numpy arrays
//! in and out; traces and renders run on rayon with the GIL released, in
//! batches between which Ctrl-C is checked. Scenes are loaded and built, and
//! BVHs traced, by the library's own paths (`Scene::load_with`,
//! `Scene::from_toml`, `Accel::build`, `render::trace_batch`), so the
//! module answers as the CLI does.

#![forbid(unsafe_code)]

mod arrays;
mod builder;
mod errors;
mod scene;

use pyo3::prelude::*;

/// The module: `Scene`, `roots` and the id of "no geometry".
#[pymodule]
fn _sturmray(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::roots, m)?)?;
    m.add("INVALID_ID", sturmray::math::INVALID_ID)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
