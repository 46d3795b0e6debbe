//! `sturmray.Scene` and `sturmray.roots`.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sturmray::accel::{Accel, Backend, check_rays};
use sturmray::geometry::Mesh;
use sturmray::math::{Hit, Ray, Vec3};
use sturmray::poly::query::Query;
use sturmray::render::order::CoherentOrder;
use sturmray::render::{
    AllHits, RenderOptions, all_hits_batch, occluded_batch, thread_pool, trace_batch,
};
use sturmray::scene::{Integrator, LoadOptions, Scene};

use crate::arrays::{rays, rows3};
use crate::builder::{Builder, clip_table};
use crate::errors::{to_py, value_error};

/// Rays traced between two looks at Ctrl-C: a few milliseconds of work.
const BATCH: usize = 1 << 16;

/// How often a render, running on its own threads, looks at Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

fn backend(name: &str) -> PyResult<Backend> {
    match name {
        "rust-bvh" => Ok(Backend::FASTEST_RUST),
        _ => Backend::ALL
            .into_iter()
            .find(|b| b.name() == name)
            .ok_or_else(|| {
                value_error(format!(
                    "backend: expected embree, obvhs, bvh or rust-bvh, found {name:?}"
                ))
            }),
    }
}

/// A scene and its BVH: loaded from a file, or built in code and committed.
#[pyclass(name = "Scene", module = "sturmray")]
pub struct PyScene {
    /// Objects added in code, until `commit`.
    builder: Option<Builder>,
    /// The scene and its BVH, once loaded or committed.
    committed: Option<(Scene, Accel)>,
    backend: Backend,
    threads: Option<usize>,
}

impl PyScene {
    fn builder(&mut self) -> PyResult<&mut Builder> {
        self.builder.as_mut().ok_or_else(|| {
            value_error("the scene is committed (or loaded): build a new Scene to add objects")
        })
    }

    fn committed(&self) -> PyResult<&(Scene, Accel)> {
        self.committed
            .as_ref()
            .ok_or_else(|| value_error("the scene is not committed: call commit() first"))
    }

    /// One result per ray from `trace`, which is handed the rays in their
    /// coherent order (`render::order`), in batches (`in_batches`); the
    /// results come back in the caller's order.
    fn per_ray<T: Copy + Send + Sync>(
        &self,
        py: Python<'_>,
        rays: &[Ray],
        empty: T,
        trace: impl Fn(&Accel, &[Ray], &mut [T]) -> sturmray::error::Result<()> + Sync,
    ) -> PyResult<Vec<T>> {
        let pool = thread_pool(self.threads).map_err(to_py)?;
        let (order, sorted_rays) = py.detach(|| {
            pool.install(|| {
                let order = CoherentOrder::new(rays);
                let sorted = order.gather(rays);
                (order, sorted)
            })
        });
        let mut sorted = vec![empty; rays.len()];
        self.in_batches(py, &sorted_rays, |accel, range| {
            trace(accel, &sorted_rays[range.clone()], &mut sorted[range])
        })?;
        let mut results = vec![empty; rays.len()];
        order.scatter(&sorted, &mut results);
        Ok(results)
    }

    /// Runs `trace` over the rays in batches with the GIL released, on one
    /// rayon pool, looking at Ctrl-C between batches.
    fn in_batches(
        &self,
        py: Python<'_>,
        rays: &[Ray],
        mut trace: impl FnMut(&Accel, Range<usize>) -> sturmray::error::Result<()> + Send,
    ) -> PyResult<()> {
        let (_, accel) = self.committed()?;
        check_rays(rays).map_err(to_py)?;
        let pool = thread_pool(self.threads).map_err(to_py)?;
        for start in (0..rays.len()).step_by(BATCH) {
            let range = start..(start + BATCH).min(rays.len());
            py.detach(|| pool.install(|| trace(accel, range)))
                .map_err(to_py)?;
            py.check_signals()?;
        }
        Ok(())
    }
}

/// The columns of hits as numpy arrays: t, geom_id, prim_id, inst_id, u, v,
/// ng (N, 3).
fn hit_columns<'py>(py: Python<'py>, hits: &[Hit]) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let column = |f: fn(&Hit) -> f32| hits.iter().map(f).collect::<Vec<f32>>();
    let ids = |f: fn(&Hit) -> u32| hits.iter().map(f).collect::<Vec<u32>>();
    dict.set_item("t", PyArray1::from_vec(py, column(|h| h.t)))?;
    dict.set_item("geom_id", PyArray1::from_vec(py, ids(|h| h.geom_id)))?;
    dict.set_item("prim_id", PyArray1::from_vec(py, ids(|h| h.prim_id)))?;
    dict.set_item("inst_id", PyArray1::from_vec(py, ids(|h| h.inst_id)))?;
    dict.set_item("u", PyArray1::from_vec(py, column(|h| h.u)))?;
    dict.set_item("v", PyArray1::from_vec(py, column(|h| h.v)))?;
    let ng: Vec<f32> = hits.iter().flat_map(|h| h.ng.to_array()).collect();
    dict.set_item("ng", PyArray1::from_vec(py, ng).reshape([hits.len(), 3])?)?;
    Ok(dict)
}

#[pymethods]
impl PyScene {
    /// An empty scene to build in code: `add_mesh`, `add_sphere`, ... then
    /// `commit()`. `toml` gives what objects do not: materials (by name in
    /// `material=`), camera, lights, render settings, in the format of a
    /// .toml scene file. `backend` is "embree" (default), "obvhs", "bvh" or
    /// "rust-bvh"; `threads` bounds the build and trace threads.
    #[new]
    #[pyo3(signature = (toml=None, backend="embree", threads=None))]
    fn new(toml: Option<&str>, backend: &str, threads: Option<usize>) -> PyResult<PyScene> {
        Ok(PyScene {
            builder: Some(Builder::new(toml)?),
            committed: None,
            backend: self::backend(backend)?,
            threads,
        })
    }

    /// Loads a scene file as the CLI does: TOML, OBJ, PLY or POV-Ray .pov; its
    /// BVH is built at once. `width`/`height` replace the image size.
    #[staticmethod]
    #[pyo3(signature = (path, width=None, height=None, backend="embree", threads=None, pov_include=Vec::new()))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        width: Option<u32>,
        height: Option<u32>,
        backend: &str,
        threads: Option<usize>,
        pov_include: Vec<PathBuf>,
    ) -> PyResult<PyScene> {
        let backend = self::backend(backend)?;
        let options = LoadOptions {
            size: width.zip(height),
            pov_include,
        };
        if width.is_some() != height.is_some() {
            return Err(value_error("width and height: give both or neither"));
        }
        let committed = py
            .detach(|| {
                let scene = Scene::load_with(&path, &options)?;
                let accel = Accel::build(&scene, backend, threads)?;
                Ok((scene, accel))
            })
            .map_err(to_py)?;
        Ok(PyScene {
            builder: None,
            committed: Some(committed),
            backend,
            threads,
        })
    }

    /// Adds a triangle mesh: (V, 3) float vertices and (F, 3) integer
    /// faces (read as float32 and uint32). Returns its geom_id.
    #[pyo3(signature = (vertices, faces, material=None))]
    fn add_mesh(
        &mut self,
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        material: Option<String>,
    ) -> PyResult<usize> {
        let v = rows3::<f32>(py, vertices, "float32", "vertices")?;
        let min = py
            .import("numpy")?
            .call_method1("min", (faces,))
            .and_then(|m| m.extract::<i64>())
            .unwrap_or(0);
        if min < 0 {
            return Err(value_error(format!(
                "faces: expected vertex indices >= 0, found {min}"
            )));
        }
        let f = rows3::<u32>(py, faces, "uint32", "faces")?;
        let positions = v
            .as_slice()?
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        let triangles = f
            .as_slice()?
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let mesh = Mesh {
            name: format!("mesh {}", f.shape()[0]),
            positions,
            triangles,
            ..Mesh::default()
        };
        Ok(self.builder()?.mesh(mesh, material))
    }

    /// Adds an analytic sphere; returns its index among the shapes (prim_id).
    #[pyo3(signature = (radius, center=[0.0; 3], material=None))]
    fn add_sphere(
        &mut self,
        radius: f64,
        center: [f64; 3],
        material: Option<String>,
    ) -> PyResult<usize> {
        let params = vec![("radius", toml::Value::Float(radius))];
        Ok(self
            .builder()?
            .shape("sphere", params, center, [0.0; 3], material))
    }

    /// Adds an analytic torus about the z axis (R = major, r = minor),
    /// rotated by `rotate` (degrees about x, y, z) and moved to `center`.
    #[pyo3(signature = (major, minor, center=[0.0; 3], rotate=[0.0; 3], material=None))]
    fn add_torus(
        &mut self,
        major: f64,
        minor: f64,
        center: [f64; 3],
        rotate: [f64; 3],
        material: Option<String>,
    ) -> PyResult<usize> {
        let params = vec![
            ("major", toml::Value::Float(major)),
            ("minor", toml::Value::Float(minor)),
        ];
        Ok(self
            .builder()?
            .shape("torus", params, center, rotate, material))
    }

    /// Adds the quadric xᵀA x + b·x + c = 0 inside the box `clip` = (min, max).
    #[pyo3(signature = (a, b, c, clip, material=None))]
    fn add_quadric(
        &mut self,
        a: [[f64; 3]; 3],
        b: [f64; 3],
        c: f64,
        clip: ([f64; 3], [f64; 3]),
        material: Option<String>,
    ) -> PyResult<usize> {
        let rows = a
            .iter()
            .map(|r| toml::Value::Array(r.iter().map(|&x| toml::Value::Float(x)).collect()))
            .collect();
        let params = vec![
            ("a", toml::Value::Array(rows)),
            ("b", toml::Value::Array(b.map(toml::Value::Float).into())),
            ("c", toml::Value::Float(c)),
            ("clip", clip_table(clip)),
        ];
        Ok(self
            .builder()?
            .shape("quadric", params, [0.0; 3], [0.0; 3], material))
    }

    /// Adds the algebraic surface `expr` = 0 (in x, y, z and `constants`)
    /// inside the box `clip` = (min, max).
    #[pyo3(signature = (expr, clip, constants=None, material=None))]
    fn add_algebraic(
        &mut self,
        expr: String,
        clip: ([f64; 3], [f64; 3]),
        constants: Option<Vec<(String, f64)>>,
        material: Option<String>,
    ) -> PyResult<usize> {
        let builder = self.builder()?;
        builder.constants(constants.unwrap_or_default())?;
        let params = vec![
            ("expr", toml::Value::String(expr)),
            ("clip", clip_table(clip)),
        ];
        Ok(builder.shape("algebraic", params, [0.0; 3], [0.0; 3], material))
    }

    /// Checks the scene as a scene file is checked and builds its BVH.
    fn commit(&mut self, py: Python<'_>) -> PyResult<()> {
        let builder = self
            .builder
            .take()
            .ok_or_else(|| value_error("already committed"))?;
        let (backend, threads) = (self.backend, self.threads);
        let committed = py
            .detach(|| {
                let scene = builder.build()?;
                let accel = Accel::build(&scene, backend, threads)?;
                Ok((scene, accel))
            })
            .map_err(to_py)?;
        self.committed = Some(committed);
        Ok(())
    }

    /// The nearest hit of each ray in [tnear, tfar): a dict of arrays `t`
    /// (inf on a miss), `geom_id`, `prim_id` (INVALID_ID on a miss),
    /// `inst_id` (the instance's index, INVALID_ID off instances), `u`, `v`,
    /// `ng` (N, 3), as `sturmray trace` writes them.
    #[pyo3(signature = (origins, directions, tnear=None, tfar=None))]
    fn intersect<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: Option<&Bound<'py, PyAny>>,
        tfar: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rays = ray_args(py, origins, directions, tnear, tfar)?;
        let hits = self.per_ray(py, &rays, Hit::MISS, trace_batch)?;
        hit_columns(py, &hits)
    }

    /// Whether anything blocks each ray in [tnear, tfar): a bool array.
    #[pyo3(signature = (origins, directions, tnear=None, tfar=None))]
    fn occluded<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: Option<&Bound<'py, PyAny>>,
        tfar: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let rays = ray_args(py, origins, directions, tnear, tfar)?;
        let blocked = self.per_ray(py, &rays, false, occluded_batch)?;
        Ok(PyArray1::from_vec(py, blocked))
    }

    /// Every hit of each ray in [tnear, tfar), nearest first (the nearest
    /// `max_hits` if given): the columns of `intersect`, flat, plus
    /// `offsets` (N + 1 int64): ray i's hits are rows offsets[i]:offsets[i+1].
    /// Two triangles hit at the same t (a shared edge) are both there.
    #[pyo3(signature = (origins, directions, tnear=None, tfar=None, max_hits=None))]
    fn intersect_all<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tnear: Option<&Bound<'py, PyAny>>,
        tfar: Option<&Bound<'py, PyAny>>,
        max_hits: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rays = ray_args(py, origins, directions, tnear, tfar)?;
        let mut all = AllHits::default();
        self.in_batches(py, &rays, |accel, range| {
            all_hits_batch(accel, &rays[range], max_hits, &mut all)
        })?;
        let dict = hit_columns(py, &all.hits)?;
        let offsets: Vec<i64> = all.offsets.iter().map(|&o| o as i64).collect();
        dict.set_item("offsets", PyArray1::from_vec(py, offsets))?;
        Ok(dict)
    }

    /// Renders the scene's camera view: an (H, W, 3) float32 array of
    /// linear radiance. `spp` and `integrator` ("whitted" or "path")
    /// replace the scene's. With `aovs=True`, returns (image, aovs), aovs a
    /// dict of `depth` (H, W), `normal` and `albedo` (H, W, 3).
    /// Ctrl-C stops the render (KeyboardInterrupt).
    #[pyo3(signature = (spp=None, integrator=None, aovs=false))]
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        spp: Option<u32>,
        integrator: Option<&str>,
        aovs: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let threads = self.threads;
        let (scene, accel) = self
            .committed
            .as_mut()
            .ok_or_else(|| value_error("the scene is not committed: call commit() first"))?;
        if spp == Some(0) {
            return Err(value_error("spp: expected at least 1, found 0"));
        }
        let chosen = match integrator {
            None => scene.render.integrator,
            Some("whitted") => Integrator::Whitted,
            Some("path") => Integrator::Path,
            Some(other) => {
                return Err(value_error(format!(
                    "integrator: expected \"whitted\" or \"path\", found {other:?}"
                )));
            }
        };
        let kept = std::mem::replace(&mut scene.render.integrator, chosen);
        let interrupt = Arc::new(AtomicBool::new(false));
        let options = RenderOptions {
            threads,
            spp,
            interrupt: Some(interrupt.clone()),
            ..RenderOptions::default()
        };
        let (scene, accel) = (&*scene, &*accel);
        let mut stopped = None;
        let result = std::thread::scope(|s| {
            let render = s.spawn(|| sturmray::render::render(scene, accel, &options));
            while !render.is_finished() {
                py.detach(|| std::thread::sleep(SIGNAL_POLL));
                if let Err(e) = py.check_signals() {
                    interrupt.store(true, Ordering::Relaxed);
                    stopped.get_or_insert(e);
                }
            }
            py.detach(|| render.join())
        });
        if let Some((scene, _)) = self.committed.as_mut() {
            scene.render.integrator = kept;
        }
        if let Some(e) = stopped {
            return Err(e);
        }
        let output = result
            .map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("the render panicked"))?
            .map_err(to_py)?;
        let (w, h) = (output.film.width, output.film.height);
        let layers = output.film.layers();
        let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
        let image = PyArray1::from_vec(py, flat(&layers.beauty)).reshape([h, w, 3])?;
        if !aovs {
            return Ok(image.into_any());
        }
        let dict = PyDict::new(py);
        dict.set_item(
            "depth",
            PyArray1::from_vec(py, layers.depth).reshape([h, w])?,
        )?;
        dict.set_item(
            "normal",
            PyArray1::from_vec(py, flat(&layers.normal)).reshape([h, w, 3])?,
        )?;
        dict.set_item(
            "albedo",
            PyArray1::from_vec(py, flat(&layers.albedo)).reshape([h, w, 3])?,
        )?;
        Ok((image, dict).into_pyobject(py)?.into_any())
    }

    /// The image size (width, height) of the scene's camera.
    #[getter]
    fn size(&self) -> PyResult<(u32, u32)> {
        let (scene, _) = self.committed()?;
        Ok((scene.camera.width, scene.camera.height))
    }

    /// The geom_id of the analytic shapes (after the meshes): their prim_id
    /// is their index in the order they were added or read.
    #[getter]
    fn shapes_geom_id(&self) -> PyResult<u32> {
        Ok(self.committed()?.0.shapes_geom_id())
    }

    /// The backend and its version, as `sturmray info` prints it.
    #[getter]
    fn backend(&self) -> PyResult<String> {
        Ok(self.committed()?.1.describe())
    }

    /// Warnings the scene raised while loading (the CLI prints them).
    #[getter]
    fn warnings(&self) -> PyResult<Vec<String>> {
        Ok(self.committed()?.0.warnings.clone())
    }
}

fn ray_args<'py>(
    py: Python<'py>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    tnear: Option<&Bound<'py, PyAny>>,
    tfar: Option<&Bound<'py, PyAny>>,
) -> PyResult<Vec<Ray>> {
    let zero = 0.0f32.into_pyobject(py)?.into_any();
    let inf = f32::INFINITY.into_pyobject(py)?.into_any();
    rays(
        py,
        origins,
        directions,
        tnear.unwrap_or(&zero),
        tfar.unwrap_or(&inf),
    )
}

/// The roots of the polynomial with `coeffs` (lowest degree first) in
/// (a, b] = `interval`: the answer of the CLI's `roots` for the same
/// query, as a dict of `roots`, `count`, `multiplicity`, `bound` and
/// `found_by`. `method` is a root finder's name ("sturm-newton", ...,
/// or "exact"); None takes the renderer's.
#[pyfunction]
#[pyo3(signature = (coeffs, interval=None, method=None, tolerance=None))]
pub fn roots<'py>(
    py: Python<'py>,
    coeffs: Vec<f64>,
    interval: Option<[f64; 2]>,
    method: Option<String>,
    tolerance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let query = Query {
        coeffs,
        interval,
        method,
        tolerance,
    };
    let answer = py.detach(|| query.answer()).map_err(value_error)?;
    let c = &answer.certificate;
    let dict = PyDict::new(py);
    dict.set_item("roots", c.values())?;
    dict.set_item("count", c.roots.len())?;
    dict.set_item(
        "multiplicity",
        c.roots.iter().map(|r| r.multiplicity).collect::<Vec<u32>>(),
    )?;
    dict.set_item(
        "bound",
        c.roots.iter().map(|r| r.bound).collect::<Vec<f64>>(),
    )?;
    dict.set_item("found_by", answer.found_by)?;
    Ok(dict)
}
