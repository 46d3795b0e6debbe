//! A scene built in code: `Scene()` and its `add_*` calls gather TOML
//! objects (the format of scenes/README.md) and meshes, and `commit()`
//! hands them to `Scene::from_toml`, so every value is checked and every
//! message worded as for a scene file; the keys it names are the objects'
//! (`objects[i]`, in the order they were added) and `meshes[i]`.

use std::path::Path;

use sturmray::geometry::Mesh;
use sturmray::scene::Scene;
use toml::{Table, Value};

use crate::errors::value_error;

/// What messages call a scene built in code; relative files in its TOML
/// (textures, OBJ meshes) are read from the working directory.
const NAME: &str = "<sturmray.Scene>";

#[derive(Default)]
pub struct Builder {
    /// The TOML given to `Scene(toml=...)`: materials, camera, lights, render settings.
    base: Table,
    objects: Vec<Value>,
    constants: Table,
    meshes: Vec<(Mesh, Option<String>)>,
}

fn triple(v: [f64; 3]) -> Value {
    Value::Array(v.iter().map(|&x| Value::Float(x)).collect())
}

/// `clip = { min, max }`.
pub fn clip_table(clip: ([f64; 3], [f64; 3])) -> Value {
    let mut t = Table::new();
    t.insert("min".into(), triple(clip.0));
    t.insert("max".into(), triple(clip.1));
    Value::Table(t)
}

impl Builder {
    pub fn new(toml: Option<&str>) -> pyo3::PyResult<Builder> {
        let base: Table = match toml {
            Some(text) => text
                .parse()
                .map_err(|e| value_error(format!("{NAME}: toml: {e}")))?,
            None => Table::new(),
        };
        Ok(Builder {
            base,
            ..Builder::default()
        })
    }

    /// Adds an analytic object of `kind` with its parameters, placed by
    /// `translate` and `rotate` (degrees about x, then y, then z); returns its
    /// index among the objects.
    pub fn shape(
        &mut self,
        kind: &str,
        params: Vec<(&str, Value)>,
        translate: [f64; 3],
        rotate: [f64; 3],
        material: Option<String>,
    ) -> usize {
        let mut t = Table::new();
        t.insert("type".into(), Value::String(kind.into()));
        for (key, value) in params {
            t.insert(key.into(), value);
        }
        let mut transform = Table::new();
        transform.insert("translate".into(), triple(translate));
        transform.insert("rotate".into(), triple(rotate));
        t.insert("transform".into(), Value::Table(transform));
        if let Some(m) = material {
            t.insert("material".into(), Value::String(m));
        }
        self.objects.push(Value::Table(t));
        self.objects.len() - 1
    }

    /// Names usable in algebraic expressions; a name given twice must keep its value.
    pub fn constants(&mut self, constants: Vec<(String, f64)>) -> pyo3::PyResult<()> {
        for (name, value) in constants {
            match self.constants.get(&name) {
                Some(Value::Float(old)) if *old != value => {
                    return Err(value_error(format!(
                        "constants.{name}: already {old}, cannot become {value}"
                    )));
                }
                _ => {
                    self.constants.insert(name, Value::Float(value));
                }
            }
        }
        Ok(())
    }

    /// Adds a mesh; returns its index among the meshes (its `geom_id`).
    pub fn mesh(&mut self, mesh: Mesh, material: Option<String>) -> usize {
        self.meshes.push((mesh, material));
        self.meshes.len() - 1
    }

    /// The scene, read as the library reads a scene file (the meshes moved, not copied).
    pub fn build(self) -> sturmray::error::Result<Scene> {
        let mut file = self.base;
        let mut objects = match file.remove("objects") {
            Some(Value::Array(given)) => given,
            _ => Vec::new(),
        };
        objects.extend(self.objects);
        if !objects.is_empty() {
            file.insert("objects".into(), Value::Array(objects));
        }
        if !self.constants.is_empty() {
            let mut constants = match file.remove("constants") {
                Some(Value::Table(given)) => given,
                _ => Table::new(),
            };
            constants.extend(self.constants);
            file.insert("constants".into(), Value::Table(constants));
        }
        let text = toml::to_string(&file).map_err(|e| {
            sturmray::error::Error::Internal(format!("the built scene as TOML: {e}"))
        })?;
        Scene::from_toml(Path::new(NAME), &text, self.meshes)
    }
}
