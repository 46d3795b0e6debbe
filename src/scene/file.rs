//! The TOML scene format (see scenes/README.md). Every table denies unknown
//! keys, so a typo is an error that names the line and suggests the key meant.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::{Camera, RenderSettings, Scene, headlight, load_obj, locate, scene_name, suggest};
use crate::error::{Error, Result};
use crate::lights::Light;
use crate::math::{Mat4, Vec3};
use crate::shading::{Material, MaterialKind};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    background: Option<[f32; 3]>,
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
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "lowercase")]
enum KindFile {
    Diffuse,
    Plastic,
    Mirror,
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
    ior: Option<f32>,
    radiance: Option<[f32; 3]>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
enum ObjectFile {
    Mesh(MeshFile),
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
struct TransformFile {
    translate: Option<[f32; 3]>,
    /// Degrees about x, then y, then z.
    rotate: Option<[f32; 3]>,
    scale: Option<ScaleFile>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ScaleFile {
    Uniform(f32),
    Axes([f32; 3]),
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
enum LightFile {
    Point(PointFile),
    Directional(DirectionalFile),
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

    fn finite(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        if v.iter().all(|x| x.is_finite() && x.abs() < 1e18) {
            Ok(Vec3::from(v))
        } else {
            Err(self.error(key, format!("expected finite numbers, found {v:?}")))
        }
    }

    fn colour(&self, key: &str, v: [f32; 3]) -> Result<Vec3> {
        let c = self.finite(key, v)?;
        if c.min_element() < 0.0 {
            return Err(self.error(key, format!("expected values >= 0, found {v:?}")));
        }
        Ok(c)
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
        if eye == look_at {
            return Err(self.error("camera.look_at", "must differ from camera.eye"));
        }
        if (look_at - eye).normalize().cross(up.normalize()).length() < 1e-4 {
            return Err(self.error("camera.up", "must not be parallel to the view direction"));
        }
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
        Ok(Camera {
            eye,
            look_at,
            up,
            fov: c.fov,
            width: c.width,
            height: c.height,
        })
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
            ior,
            emission: colour("radiance", m.radiance, 0.0)?,
        })
    }

    fn transform(&self, index: usize, t: &TransformFile) -> Result<Mat4> {
        let key = |field: &str| format!("objects[{index}].transform.{field}");
        let translate = self.finite(&key("translate"), t.translate.unwrap_or([0.0; 3]))?;
        let rotate = self.finite(&key("rotate"), t.rotate.unwrap_or([0.0; 3]))?;
        let scale = match t.scale {
            None => Vec3::ONE,
            Some(ScaleFile::Uniform(s)) => Vec3::splat(s),
            Some(ScaleFile::Axes(s)) => Vec3::from(s),
        };
        if !scale.is_finite() || scale.abs().min_element() < 1e-12 {
            return Err(self.error(
                &key("scale"),
                format!("expected finite, nonzero factors, found {scale}"),
            ));
        }
        let r = rotate * (std::f32::consts::PI / 180.0);
        let rotation =
            Mat4::from_rotation_z(r.z) * Mat4::from_rotation_y(r.y) * Mat4::from_rotation_x(r.x);
        Ok(Mat4::from_translation(translate) * rotation * Mat4::from_scale(scale))
    }
}

pub(super) fn load(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
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
    };
    if render.spp == 0 {
        return Err(check.error("render.spp", "expected at least 1 sample per pixel"));
    }
    let mut scene = Scene {
        name: scene_name(path),
        camera: Camera::default(),
        render,
        background: check.colour("background", file.background.unwrap_or([0.0; 3]))?,
        materials: Vec::new(),
        meshes: Vec::new(),
        lights: Vec::new(),
    };
    for (name, m) in &file.materials {
        scene.materials.push(check.material(name, m)?);
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    for (index, object) in file.objects.iter().enumerate() {
        let ObjectFile::Mesh(mesh) = object;
        let material =
            match &mesh.material {
                None => None,
                Some(name) => Some(file.materials.keys().position(|k| k == name).ok_or_else(
                    || {
                        let hint =
                            suggest::closest(name, file.materials.keys().map(String::as_str))
                                .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
                        check.error(
                            &format!("objects[{index}].material"),
                            format!("no material named `{name}` in [materials]{hint}"),
                        )
                    },
                )? as u32),
            };
        let transform = check.transform(index, &mesh.transform)?;
        let first = scene.meshes.len();
        scene.add_obj(load_obj(&dir.join(&mesh.file))?, material);
        for m in &mut scene.meshes[first..] {
            m.transform(&transform);
        }
    }
    for (index, light) in file.lights.iter().enumerate() {
        let key = |field: &str| format!("lights[{index}].{field}");
        scene.lights.push(match light {
            LightFile::Point(p) => Light::Point {
                position: check.finite(&key("position"), p.position)?,
                intensity: check.colour(&key("intensity"), p.intensity)?,
            },
            LightFile::Directional(d) => Light::Directional {
                direction: check.direction(&key("direction"), d.direction)?,
                irradiance: check.colour(&key("irradiance"), d.irradiance)?,
            },
        });
    }
    scene.camera = match &file.camera {
        Some(c) => check.camera(c)?,
        None => {
            let bounds = scene.bounds();
            if bounds.is_empty() {
                return Err(check.error("camera", "missing, and there is no geometry to frame"));
            }
            let camera = Camera::framing(bounds, 640, 480);
            if file.lights.is_empty() {
                scene.lights.push(headlight(&camera));
            }
            camera
        }
    };
    Ok(scene)
}
