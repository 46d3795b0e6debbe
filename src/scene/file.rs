//! The TOML scene format (see scenes/README.md). Every table denies unknown
//! keys, so a typo is an error that names the line and suggests the key meant.

use std::collections::BTreeMap;

use glam::{DAffine3, DMat4, DVec3};
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::obj::MAX_COORDINATE;
use super::shapes::{self, ShapeFile, ShapeKind};
use super::{
    Adaptive, Camera, CameraKey, Integrator, MAX_COLOUR, MAX_DEPTH, PhotonSettings, RenderSettings,
    Scene, headlight, load_obj, locate,
};
use crate::error::{Error, Result};
use crate::geometry::{Box3, Shape};
use crate::lights::Light;
use crate::math::{Bounds, Vec3};
use crate::poly::solve::{Method, Solver};
use crate::shading::{Material, MaterialKind};
use crate::suggest;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    background: Option<[f32; 3]>,
    /// Names usable in `expr` of algebraic objects.
    #[serde(default)]
    constants: BTreeMap<String, f64>,
    camera: Option<CameraFile>,
    #[serde(default)]
    render: RenderFile,
    #[serde(default)]
    materials: BTreeMap<String, MaterialFile>,
    #[serde(default)]
    objects: Vec<ObjectFile>,
    #[serde(default)]
    lights: Vec<LightFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    eye: [f32; 3],
    look_at: [f32; 3],
    #[serde(default = "y_up")]
    up: [f32; 3],
    fov: f32,
    width: u32,
    height: u32,
    /// A camera path: where the camera is at some frames (`render --frame K`).
    #[serde(default)]
    keys: Vec<CameraKeyFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraKeyFile {
    frame: u32,
    eye: [f32; 3],
    look_at: [f32; 3],
}

fn y_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RenderFile {
    spp: Option<u32>,
    max_depth: Option<u32>,
    seed: Option<u64>,
    min_weight: Option<f32>,
    /// "box", "tent", "gaussian" or "mitchell".
    filter: Option<String>,
    integrator: Option<IntegratorFile>,
    /// The root finder for analytic surfaces, by its stable name.
    method: Option<String>,
    tolerance: Option<f64>,
    adaptive: Option<AdaptiveFile>,
    photons: Option<PhotonsFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AdaptiveFile {
    max_spp: u32,
    threshold: f32,
}

/// `photons = { count, radius }`: the caustic photon pass.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PhotonsFile {
    count: Option<u32>,
    radius: Option<f32>,
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum IntegratorFile {
    Whitted,
    Path,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "lowercase")]
enum KindFile {
    Diffuse,
    Plastic,
    Mirror,
    Metal,
    Dielectric,
    Emissive,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    #[serde(rename = "type")]
    kind: KindFile,
    albedo: Option<[f32; 3]>,
    specular: Option<[f32; 3]>,
    shininess: Option<f32>,
    roughness: Option<f32>,
    ior: Option<f32>,
    radiance: Option<[f32; 3]>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum ObjectFile {
    Mesh(MeshFile),
    Sphere(ShapeFile),
    Quadric(ShapeFile),
    Ellipsoid(ShapeFile),
    Cylinder(ShapeFile),
    Cone(ShapeFile),
    Hyperboloid1(ShapeFile),
    Hyperboloid2(ShapeFile),
    Paraboloid(ShapeFile),
    HyperbolicParaboloid(ShapeFile),
    Torus(ShapeFile),
    Algebraic(ShapeFile),
}

impl ObjectFile {
    fn shape(&self) -> Option<(ShapeKind, &ShapeFile)> {
        use ObjectFile::*;
        Some(match self {
            Mesh(_) => return None,
            Sphere(f) => (ShapeKind::Sphere, f),
            Quadric(f) => (ShapeKind::Quadric, f),
            Ellipsoid(f) => (ShapeKind::Ellipsoid, f),
            Cylinder(f) => (ShapeKind::Cylinder, f),
            Cone(f) => (ShapeKind::Cone, f),
            Hyperboloid1(f) => (ShapeKind::Hyperboloid1, f),
            Hyperboloid2(f) => (ShapeKind::Hyperboloid2, f),
            Paraboloid(f) => (ShapeKind::Paraboloid, f),
            HyperbolicParaboloid(f) => (ShapeKind::HyperbolicParaboloid, f),
            Torus(f) => (ShapeKind::Torus, f),
            Algebraic(f) => (ShapeKind::Algebraic, f),
        })
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    file: PathBuf,
    material: Option<String>,
    #[serde(default)]
    transform: TransformFile,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct TransformFile {
    translate: Option<[f64; 3]>,
    /// Degrees about x, then y, then z.
    rotate: Option<[f64; 3]>,
    scale: Option<ScaleFile>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ScaleFile {
    Uniform(f64),
    Axes([f64; 3]),
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
enum LightFile {
    Point(PointFile),
    Directional(DirectionalFile),
    Sphere(SphereLightFile),
    Quad(QuadLightFile),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereLightFile {
    center: [f32; 3],
    radius: f32,
    radiance: [f32; 3],
}

/// A parallelogram corner + s·edge1 + t·edge2, emitting towards edge1 × edge2.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct QuadLightFile {
    corner: [f32; 3],
    edge1: [f32; 3],
    edge2: [f32; 3],
    radiance: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PointFile {
    position: [f32; 3],
    intensity: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionalFile {
    direction: [f32; 3],
    irradiance: [f32; 3],
}

/// What a render holds per pixel: the film's f64 sums (`film::Pixel`, 88
/// bytes) and the f32 layers written out (beauty, depth, normal, albedo: 40).
pub(super) const FILM_BYTES_PER_PIXEL: u64 = 128;

/// The machine's memory in bytes, where the system says (Linux), so an image
/// whose film cannot be allocated is refused at load instead of aborting the
/// render. None elsewhere: then only the limit on each side applies.
pub(super) fn physical_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Reports the problems of one scene file, each named by its line and key.
struct Check<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Check<'_> {
    fn error(&self, key: &str, message: impl std::fmt::Display) -> Error {
        let line = locate::line_of(self.text, key).map_or(String::new(), |l| format!("line {l}, "));
        Error::Scene {
            path: self.path.to_owned(),
            message: format!("{line}{key}: {message}"),
        }
    }

    /// A position or vector within [`MAX_COORDINATE`].
    fn finite(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        self.finite64(key, v.map(f64::from)).map(|v| v.as_vec3())
    }

    fn finite64(&self, key: &str, v: [f64; 3]) -> Result<DVec3> {
        if v.iter().all(|x| x.abs() <= MAX_COORDINATE) {
            Ok(DVec3::from(v))
        } else {
            Err(self.error(
                key,
                format!("expected finite numbers of size at most {MAX_COORDINATE:e}, found {v:?}"),
            ))
        }
    }

    /// World-space geometry within [`MAX_COORDINATE`]: a transform can scale
    /// coordinates that are each within it far beyond it.
    fn bounds(&self, key: &str, bounds: Bounds) -> Result<()> {
        super::bounds_problem(bounds).map_or(Ok(()), |message| Err(self.error(key, message)))
    }

    fn colour(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        if !v.iter().all(|x| (0.0..=MAX_COLOUR).contains(x)) {
            return Err(self.error(
                key,
                format!("expected values >= 0 and at most {MAX_COLOUR:e}, found {v:?}"),
            ));
        }
        Ok(Vec3::from(v))
    }

    fn direction(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        let d = self.finite(key, v)?;
        if d.length_squared() == 0.0 {
            return Err(self.error(key, "a direction cannot be zero"));
        }
        Ok(d)
    }

    fn camera(&self, c: &CameraFile) -> Result<Camera> {
        let eye = self.finite("camera.eye", c.eye)?;
        let look_at = self.finite("camera.look_at", c.look_at)?;
        let up = self.direction("camera.up", c.up)?;
        if !(c.fov > 0.0 && c.fov < 180.0) {
            return Err(self.error(
                "camera.fov",
                format!("expected degrees in (0, 180), found {}", c.fov),
            ));
        }
        const MAX_SIDE: u32 = 1 << 16;
        for (key, side) in [("camera.width", c.width), ("camera.height", c.height)] {
            if side == 0 || side > MAX_SIDE {
                return Err(self.error(
                    key,
                    format!("expected 1 to {MAX_SIDE} pixels, found {side}"),
                ));
            }
        }
        let bytes = u64::from(c.width) * u64::from(c.height) * FILM_BYTES_PER_PIXEL;
        if let Some(memory) = physical_memory()
            && bytes > memory
        {
            const GIB: f64 = (1u64 << 30) as f64;
            return Err(self.error(
                "camera",
                format!(
                    "a {}x{} image needs {:.1} GiB for its film ({FILM_BYTES_PER_PIXEL} bytes \
                     per pixel), more than this machine's {:.1} GiB of memory",
                    c.width,
                    c.height,
                    bytes as f64 / GIB,
                    memory as f64 / GIB
                ),
            ));
        }
        let mut keys = Vec::with_capacity(c.keys.len());
        for (i, k) in c.keys.iter().enumerate() {
            let key = |field: &str| format!("camera.keys[{i}].{field}");
            let (eye, look_at) = (
                self.finite(&key("eye"), k.eye)?,
                self.finite(&key("look_at"), k.look_at)?,
            );
            if keys
                .last()
                .is_some_and(|last: &CameraKey| last.frame >= k.frame)
            {
                return Err(self.error(
                    &key("frame"),
                    format!("frames must increase, found {} after a later one", k.frame),
                ));
            }
            keys.push(CameraKey {
                frame: k.frame,
                eye,
                look_at,
            });
        }
        let camera = Camera {
            keys,
            eye,
            look_at,
            up,
            fov: c.fov,
            width: c.width,
            height: c.height,
        };
        camera.check().map_err(|p| self.error(&p.key, p.message))?;
        Ok(camera)
    }

    fn material(&self, name: &str, m: &MaterialFile) -> Result<Material> {
        let key = |field: &str| format!("materials.{name}.{field}");
        let colour = |field: &str, v: Option<[f32; 3]>, default: f32| match v {
            Some(v) => self.colour(&key(field), v),
            None => Ok(Vec3::splat(default)),
        };
        let kind = match m.kind {
            KindFile::Diffuse => MaterialKind::Diffuse,
            KindFile::Plastic => MaterialKind::Plastic,
            KindFile::Mirror => MaterialKind::Mirror,
            KindFile::Metal => MaterialKind::Metal,
            KindFile::Dielectric => MaterialKind::Dielectric,
            KindFile::Emissive => MaterialKind::Emissive,
        };
        let ior = m.ior.unwrap_or(1.5);
        if !(ior > 0.0 && ior.is_finite()) {
            return Err(self.error(&key("ior"), format!("expected a number > 0, found {ior}")));
        }
        let shininess = m.shininess.unwrap_or(50.0);
        if !(shininess >= 0.0 && shininess.is_finite()) {
            return Err(self.error(
                &key("shininess"),
                format!("expected a number >= 0, found {shininess}"),
            ));
        }
        let roughness = m.roughness.unwrap_or(0.3);
        if !(0.0..=1.0).contains(&roughness) {
            return Err(self.error(
                &key("roughness"),
                format!("expected a number from 0 to 1, found {roughness}"),
            ));
        }
        let specular_default = if kind == MaterialKind::Plastic {
            0.04
        } else {
            0.0
        };
        Ok(Material {
            name: name.to_owned(),
            kind,
            albedo: colour("albedo", m.albedo, 0.7)?,
            specular: colour("specular", m.specular, specular_default)?,
            shininess,
            roughness,
            ior,
            emission: colour("radiance", m.radiance, 0.0)?,
        })
    }

    fn transform(&self, index: usize, t: &TransformFile) -> Result<DAffine3> {
        let key = |field: &str| format!("objects[{index}].transform.{field}");
        let vector =
            |field: &str, v: Option<[f64; 3]>| self.finite64(&key(field), v.unwrap_or([0.0; 3]));
        let translate = vector("translate", t.translate)?;
        let rotate = vector("rotate", t.rotate)?;
        let scale = match t.scale {
            None => DVec3::ONE,
            Some(ScaleFile::Uniform(s)) => DVec3::splat(s),
            Some(ScaleFile::Axes(s)) => DVec3::from(s),
        };
        if !scale.is_finite()
            || scale.abs().min_element() < 1e-12
            || scale.abs().max_element() > 1e12
        {
            return Err(self.error(
                &key("scale"),
                format!("expected finite factors between 1e-12 and 1e12 in size, found {scale}"),
            ));
        }
        let r = rotate * (std::f64::consts::PI / 180.0);
        let rotation =
            DMat4::from_rotation_z(r.z) * DMat4::from_rotation_y(r.y) * DMat4::from_rotation_x(r.x);
        Ok(DAffine3::from_mat4(
            DMat4::from_translation(translate) * rotation * DMat4::from_scale(scale),
        ))
    }

    fn material_index(
        &self,
        index: usize,
        name: &Option<String>,
        materials: &BTreeMap<String, MaterialFile>,
    ) -> Result<Option<u32>> {
        let Some(name) = name else {
            return Ok(None);
        };
        match materials.keys().position(|k| k == name) {
            Some(i) => Ok(Some(i as u32)),
            None => {
                let hint = suggest::closest(name, materials.keys().map(String::as_str))
                    .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
                Err(self.error(
                    &format!("objects[{index}].material"),
                    format!("no material named `{name}` in [materials]{hint}"),
                ))
            }
        }
    }

    fn solver(&self, render: &RenderFile) -> Result<Solver> {
        let mut solver = Solver::default();
        if let Some(name) = &render.method {
            solver.method = name
                .parse::<Method>()
                .map_err(|e| self.error("render.method", e))?;
        }
        if let Some(tolerance) = render.tolerance {
            if !(tolerance > 0.0 && tolerance < 1.0) {
                return Err(self.error(
                    "render.tolerance",
                    format!("expected a number in (0, 1), found {tolerance}"),
                ));
            }
            solver.tolerance = tolerance;
        }
        Ok(solver)
    }
}

pub(super) fn load(path: &Path) -> Result<Scene> {
    let text = crate::io::input::read_text(path)?;
    let file: SceneFile = toml::from_str(&text).map_err(|e| Error::Scene {
        path: path.to_owned(),
        message: suggest::with_suggestion(&e.to_string()),
    })?;
    let check = Check { path, text: &text };
    let defaults = RenderSettings::default();
    let render = RenderSettings {
        spp: file.render.spp.unwrap_or(defaults.spp),
        max_depth: file.render.max_depth.unwrap_or(defaults.max_depth),
        seed: file.render.seed.unwrap_or(defaults.seed),
        min_weight: file.render.min_weight.unwrap_or(defaults.min_weight),
        filter: match &file.render.filter {
            Some(name) => name.parse().map_err(|e| check.error("render.filter", e))?,
            None => defaults.filter,
        },
        integrator: match file.render.integrator {
            Some(IntegratorFile::Whitted) | None => Integrator::Whitted,
            Some(IntegratorFile::Path) => Integrator::Path,
        },
        adaptive: file.render.adaptive.as_ref().map(|a| Adaptive {
            max_spp: a.max_spp,
            threshold: a.threshold,
        }),
        photons: match &file.render.photons {
            Some(p) => PhotonSettings {
                count: p.count.unwrap_or(defaults.photons.count),
                radius: p.radius.or(defaults.photons.radius),
            },
            None => defaults.photons,
        },
    };
    if let Some(a) = &render.adaptive {
        // Disagreement needs two samples to measure, and a round to grow by.
        if render.spp < 2 || a.max_spp < render.spp {
            return Err(check.error(
                "render.adaptive.max_spp",
                format!(
                    "adaptive sampling takes rounds of spp ({}) samples, which must be at least 2, \
                     up to max_spp ({}), which must be at least spp",
                    render.spp, a.max_spp
                ),
            ));
        }
        if !(a.threshold > 0.0 && a.threshold.is_finite()) {
            return Err(check.error(
                "render.adaptive.threshold",
                format!("expected a number > 0, found {}", a.threshold),
            ));
        }
    }
    if let Some(radius) = render.photons.radius
        && !(radius > 0.0 && radius.is_finite())
    {
        return Err(check.error(
            "render.photons.radius",
            format!("expected a number > 0, found {radius}"),
        ));
    }
    if !(render.min_weight >= 0.0 && render.min_weight < 1.0) {
        return Err(check.error(
            "render.min_weight",
            format!("expected a number in [0, 1), found {}", render.min_weight),
        ));
    }
    if render.spp == 0 {
        return Err(check.error("render.spp", "expected at least 1 sample per pixel"));
    }
    if render.max_depth > MAX_DEPTH {
        return Err(check.error(
            "render.max_depth",
            format!(
                "expected at most {MAX_DEPTH} bounces (the ray tree's stack limit), found {}",
                render.max_depth
            ),
        ));
    }
    PhotonSettings::check_count(render.photons.count)
        .map_err(|e| check.error("render.photons.count", e))?;
    let background = check.colour("background", file.background.unwrap_or([0.0; 3]))?;
    let mut scene = Scene::empty(path, render, background);
    for (name, m) in &file.materials {
        scene.materials.push(check.material(name, m)?);
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let constants: Vec<(&str, f64)> = file
        .constants
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .collect();
    let solver = check.solver(&file.render)?;
    for (index, object) in file.objects.iter().enumerate() {
        if let Some((kind, shape)) = object.shape() {
            let material = match check.material_index(index, &shape.material, &file.materials)? {
                Some(m) => m,
                None => scene.default_material(),
            };
            let key = format!("objects[{index}]");
            let (surface, default_clip) =
                shapes::surface(kind, shape, &constants).map_err(|(field, message)| {
                    let key = if field.is_empty() {
                        key.clone()
                    } else {
                        format!("{key}.{field}")
                    };
                    check.error(&key, message)
                })?;
            let clip = match &shape.clip {
                Some(c) => Some(Box3 {
                    min: check.finite64(&format!("{key}.clip.min"), c.min)?,
                    max: check.finite64(&format!("{key}.clip.max"), c.max)?,
                }),
                None => None,
            };
            let to_world = check.transform(index, &shape.transform)?;
            let shape = Shape::new(surface, to_world, clip.or(default_clip), material, solver)
                .map_err(|e| check.error(&key, e))?;
            check.bounds(&key, shape.bounds())?;
            scene.shapes.push(shape);
            continue;
        }
        let ObjectFile::Mesh(mesh) = object else {
            unreachable!("every other type is a shape")
        };
        let material = check.material_index(index, &mesh.material, &file.materials)?;
        let transform = check.transform(index, &mesh.transform)?;
        let first = scene.meshes.len();
        let obj_path = dir.join(&mesh.file);
        // A file that cannot be read is named with the line that asks for it.
        let obj = load_obj(&obj_path).map_err(|e| match e {
            Error::Io { .. } => check.error(&format!("objects[{index}].file"), e),
            other => other,
        })?;
        scene.add_obj(&obj_path, obj, material);
        let matrix = DMat4::from(transform).as_mat4();
        for m in &mut scene.meshes[first..] {
            m.transform(&matrix);
            check.bounds(&format!("objects[{index}]"), m.bounds())?;
        }
    }
    for (index, light) in file.lights.iter().enumerate() {
        let key = |field: &str| format!("lights[{index}].{field}");
        match light {
            LightFile::Point(p) => scene.lights.push(Light::Point {
                position: check.finite(&key("position"), p.position)?,
                intensity: check.colour(&key("intensity"), p.intensity)?,
            }),
            LightFile::Directional(d) => scene.lights.push(Light::Directional {
                direction: check.direction(&key("direction"), d.direction)?,
                irradiance: check.colour(&key("irradiance"), d.irradiance)?,
            }),
            // Area lights are emissive geometry: camera and bounce rays see them, they
            // cast shadows, and `gather_emitters` makes them sampled lights.
            LightFile::Sphere(l) => {
                let center = check.finite(&key("center"), l.center)?;
                let radiance = check.colour(&key("radiance"), l.radiance)?;
                if !(l.radius > 0.0 && f64::from(l.radius) <= MAX_COORDINATE) {
                    return Err(check.error(
                        &key("radius"),
                        format!(
                            "expected a number > 0 and at most {MAX_COORDINATE:e}, found {}",
                            l.radius
                        ),
                    ));
                }
                let material = scene.light_material(index, radiance);
                let place = DAffine3::from_translation(center.as_dvec3());
                let surface = crate::geometry::Surface::Sphere {
                    radius: f64::from(l.radius),
                };
                let shape = Shape::new(surface, place, None, material, solver)
                    .map_err(|e| check.error(&key("radius"), e))?;
                check.bounds(&key("radius"), shape.bounds())?;
                scene.shapes.push(shape);
            }
            LightFile::Quad(l) => {
                let corner = check.finite(&key("corner"), l.corner)?;
                let edge1 = check.finite(&key("edge1"), l.edge1)?;
                let edge2 = check.finite(&key("edge2"), l.edge2)?;
                let radiance = check.colour(&key("radiance"), l.radiance)?;
                if edge1.cross(edge2).length() <= 0.0 {
                    return Err(check.error(
                        &key("edge1"),
                        "the quad has zero area: its edges are parallel or zero",
                    ));
                }
                // Counter-clockwise seen from the side edge1 × edge2 points to, which
                // is the side it emits on.
                let material = scene.light_material(index, radiance);
                scene.meshes.push(crate::geometry::Mesh {
                    name: format!("light {index}"),
                    positions: vec![
                        corner,
                        corner + edge1,
                        corner + edge1 + edge2,
                        corner + edge2,
                    ],
                    triangles: vec![[0, 1, 2], [0, 2, 3]],
                    materials: vec![material; 2],
                });
                check.bounds(&key("corner"), scene.bounds())?;
            }
        }
    }
    scene.camera = match &file.camera {
        Some(c) => check.camera(c)?,
        None => {
            let bounds = scene.bounds();
            if bounds.is_empty() {
                return Err(check.error("camera", "missing, and there is no geometry to frame"));
            }
            let camera = Camera::framing(bounds, 640, 480);
            camera
                .check()
                .map_err(|p| check.error("camera", p.message))?;
            if file.lights.is_empty() {
                scene.lights.push(headlight(&camera));
            }
            camera
        }
    };
    scene.gather_emitters();
    Ok(scene)
}
