//! Scenes: the in-memory form, loaded from a TOML file, a bare OBJ or a
//! POV-Ray scene (.pov), at the scene's own image size or one a command asks for.

mod camera;
mod emitters;
mod file;
mod fog;
mod hash;
mod instance;
mod interaction;
mod locate;
mod obj;
mod ply;
mod pov;
mod size;
mod solids;
mod textures;

use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use camera::{
    Camera, CameraFrame, CameraKey, CameraProblem, ImagePlane, Optics, Projection, ThinLens,
};
pub use fog::{Fog, GroundFog, along as fog_along, through as fog_through};
pub use instance::{Instance, Prototype};
pub use interaction::Interaction;
use obj::MAX_COORDINATE;
pub use obj::{ObjFile, load_obj};

pub use size::SizeRequest;
use textures::Textures;

use crate::error::{Error, Result};
use crate::geometry::{Mesh, Shape};
use crate::lights::{Environment, Light, LightPicker};
use crate::math::{Bounds, INVALID_ID, Vec3};
use crate::sampling::{Filter, SamplerKind};
use crate::shading::Material;
use crate::shading::srgb_to_linear;

/// Which light transport the render computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum Integrator {
    /// Local shading, shadow rays, specular reflection and refraction.
    #[default]
    Whitted,
    /// Global illumination: paths with next-event estimation and Russian roulette.
    Path,
}

/// Adaptive supersampling: after its base samples a pixel takes further rounds
/// of as many while the standard error of its mean luminance is above
/// `threshold` times the mean, up to `max_spp` samples.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Adaptive {
    pub max_spp: u32,
    pub threshold: f32,
}

/// Per-render settings.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RenderSettings {
    pub spp: u32,
    /// How many specular bounces the ray tree follows, at most [`MAX_DEPTH`].
    pub max_depth: u32,
    pub seed: u64,
    /// A branch of the ray tree whose weight falls below this ends (adaptive depth).
    pub min_weight: f32,
    /// The reconstruction filter, applied by filter importance sampling: each
    /// sample counts only for its own pixel.
    pub filter: Filter,
    /// Where each sample's uniform numbers come from.
    pub sampler: SamplerKind,
    pub integrator: Integrator,
    /// Adaptive supersampling, when asked for.
    pub adaptive: Option<Adaptive>,
    pub photons: PhotonSettings,
    /// How the integrator's radiance becomes linear light (POV-Ray's
    /// `assumed_gamma`); linear everywhere else, and then not hashed, so
    /// those scenes' hashes are what they were.
    #[serde(skip_serializing_if = "WorkingGamma::is_linear")]
    pub working_gamma: WorkingGamma,
}

/// The space a scene's colours, and so the radiance computed from them,
/// are in. POV-Ray 3.7 lights a scene in its working gamma space and only
/// decodes the result to light for the output file: with `assumed_gamma
/// 2.2`, a colour of 0.5 lit by a light of 1 shows as 0.5 in the file,
/// not as 0.5 sRGB-encoded. A sample's radiance is decoded the same way
/// before it reaches the film (per sample: with one sample a pixel, as
/// POV-Ray renders without anti-aliasing, the pixel is POV-Ray's).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub enum WorkingGamma {
    /// Colours are linear (`assumed_gamma 1`, and every other scene kind).
    #[default]
    Linear,
    /// `assumed_gamma G`: a value v is the light v^G.
    Power(f32),
    /// The value is the output file's, sRGB-encoded: POV-Ray 3.7's
    /// "gamma correction off" for a scene older than 3.7 that sets no
    /// `assumed_gamma` (its file gamma is then the display's, sRGB), and
    /// `assumed_gamma srgb`.
    Srgb,
}

impl WorkingGamma {
    pub fn is_linear(&self) -> bool {
        *self == WorkingGamma::Linear
    }

    /// The linear light of radiance `v` in this space.
    pub fn to_linear(self, v: Vec3) -> Vec3 {
        // max: a power of a negative is NaN; radiance is never below 0
        // but for rounding.
        let each = |f: fn(f32, f32) -> f32, g: f32| {
            Vec3::new(f(v.x.max(0.0), g), f(v.y.max(0.0), g), f(v.z.max(0.0), g))
        };
        match self {
            WorkingGamma::Linear => v,
            WorkingGamma::Power(g) => each(f32::powf, g),
            WorkingGamma::Srgb => each(|c, _| srgb_to_linear(c), 0.0),
        }
    }
}

/// The largest value of a colour (albedo, emission, light intensity or
/// irradiance), in TOML and MTL alike: a product of two stays within f32.
pub const MAX_COLOUR: f32 = 1e18;

/// The largest `render.max_depth`. The Whitted ray tree recurses once per
/// bounce, so the limit keeps its stack within a worker thread's (POV-Ray's
/// `max_trace_level` has the same ceiling); no scene needs more, since each
/// bounce's weight is at most 1 and `min_weight` ends a branch far sooner.
pub const MAX_DEPTH: u32 = 256;

/// The photon pass for caustics (light → specular → diffuse transport).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PhotonSettings {
    /// Photons emitted from the lights; 0 turns the pass off.
    pub count: u32,
    /// The gather radius; `None` derives it from the stored photons
    /// (`render::photon::Radius`), never from the scene's size.
    pub radius: Option<f32>,
}

impl PhotonSettings {
    /// The most photons a pass may emit: 100 million, 500 times the default
    /// and more than any caustic needs; a larger count is a typo.
    pub const MAX_COUNT: u32 = 100_000_000;

    /// The photon pass's peak memory per emitted photon, at worst (every photon
    /// stored): the traced chunks, their concatenation and the grid's copy (48
    /// bytes each), plus the grid's keys, order and bucket starts.
    pub const BYTES_PER_PHOTON: u64 = 176;

    /// Whether `count` photons are allowed and fit in this machine's memory;
    /// the reason when not.
    pub fn check_count(count: u32) -> std::result::Result<(), String> {
        if count > Self::MAX_COUNT {
            return Err(format!(
                "expected at most {} photons, found {count}",
                Self::MAX_COUNT
            ));
        }
        let bytes = u64::from(count) * Self::BYTES_PER_PHOTON;
        match file::physical_memory() {
            Some(memory) if bytes > memory => Err(format!(
                "{count} photons need up to {:.1} GiB, more than this machine's {:.1} GiB",
                bytes as f64 / GIB,
                memory as f64 / GIB
            )),
            _ => Ok(()),
        }
    }
}

const GIB: f64 = (1u64 << 30) as f64;

impl Default for PhotonSettings {
    fn default() -> Self {
        PhotonSettings {
            count: 200_000,
            radius: None,
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            spp: 4,
            max_depth: 5,
            seed: 0,
            min_weight: 1e-3,
            filter: Filter::default(),
            sampler: SamplerKind::default(),
            integrator: Integrator::default(),
            adaptive: None,
            photons: PhotonSettings::default(),
            working_gamma: WorkingGamma::Linear,
        }
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    /// The file stem: renders default to `out/<name>.exr`.
    pub name: String,
    pub camera: Camera,
    pub render: RenderSettings,
    pub background: Vec3,
    /// The environment light (`[environment]`): when present, what rays that
    /// leave the scene see, in place of `background`.
    pub environment: Option<Arc<Environment>>,
    /// POV-Ray's fogs, on every ray's way through the air.
    pub fogs: Vec<Fog>,
    pub materials: Vec<Material>,
    /// Geometry i of the scene is mesh i: its `geom_id` in hits.
    pub meshes: Vec<Mesh>,
    /// Analytic shapes: together one more geometry, `geom_id` = the number of
    /// meshes, and `prim_id` the shape's index here.
    pub shapes: Vec<Shape>,
    /// Geometry declared once (`[prototypes.NAME]`), in name order.
    pub prototypes: Vec<Prototype>,
    /// Placements of the prototypes: a hit on instance i has `inst_id` i.
    pub instances: Vec<Instance>,
    /// Point and directional lights first, then the area lights (the emissive
    /// geometry, in geometry order).
    pub lights: Vec<Light>,
    /// Which lights a shading point samples, and which light a hit found.
    pub light_picker: LightPicker,
    /// Problems that do not stop a render (degenerate triangles), for the CLI
    /// to print once: the library itself prints nothing.
    pub warnings: Vec<String>,
    /// Every file the scene was read from (scene file, OBJs, MTLs), so no
    /// output of a command can be written over one of them.
    pub sources: Vec<PathBuf>,
    /// For a scene read from another renderer's language (POV-Ray's), what
    /// was read and what was skipped, for `sturmray info`.
    pub import: Option<Import>,
}

/// What a scene in POV-Ray's language was read as: how many of each kind
/// of statement (objects by keyword, lights, includes), and which keywords
/// outside the subset were skipped (each with a warning).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Import {
    pub read: std::collections::BTreeMap<String, usize>,
    pub skipped: std::collections::BTreeMap<String, usize>,
}

/// What a command asks of the loader beyond the file itself.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// The image size asked for on the command line (`--width`, `--height`), replacing the scene's.
    pub size: Option<(u32, u32)>,
    /// Extra folders `#include` searches in a .pov scene (`--pov-include DIR`), before POV-Ray's installed includes.
    pub pov_include: Vec<PathBuf>,
}

/// The kinds of scene file, told by the extension (in any case).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SceneKind {
    Toml,
    Obj,
    Ply,
    Pov,
}

impl SceneKind {
    fn of(path: &Path) -> Result<SceneKind> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        [
            ("toml", SceneKind::Toml),
            ("obj", SceneKind::Obj),
            ("ply", SceneKind::Ply),
            ("pov", SceneKind::Pov),
        ]
        .into_iter()
        .find_map(|(name, kind)| ext.eq_ignore_ascii_case(name).then_some(kind))
        .ok_or_else(|| {
            Error::Input(format!(
                "{}: expected a scene file ending in .toml, .obj, .ply or .pov",
                path.display()
            ))
        })
    }
}

impl Scene {
    /// Loads a `.toml` scene, a bare `.obj` or `.ply` file or a `.pov` scene.
    pub fn load(path: &Path) -> Result<Scene> {
        Scene::load_with(path, &LoadOptions::default())
    }

    /// A scene from TOML text (the format of a .toml scene file), for scenes
    /// built in code: `path` is the name messages give it and the folder its
    /// relative files are read from. `meshes` join after the text's objects,
    /// each with the name of one of the text's materials or none (the default
    /// grey).
    pub fn from_toml(
        path: &Path,
        text: &str,
        meshes: Vec<(Mesh, Option<String>)>,
    ) -> Result<Scene> {
        file::from_text(path, text, meshes)
    }

    /// Loads a scene as [`Scene::load`], with what a command asks beyond the
    /// file. `options.size` is checked first, as a scene file's size is, but
    /// with errors naming the flags: a .pov scene is read at that size (its
    /// `image_width` and `image_height`), and a TOML or OBJ scene's camera
    /// takes it once loaded, keeping its vertical field of view.
    pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Scene> {
        let kind = SceneKind::of(path)?;
        if let Some(size) = options.size {
            SizeRequest::both(size).check(size)?;
        }
        let mut scene = match kind {
            SceneKind::Toml => file::load(path)?,
            SceneKind::Obj | SceneKind::Ply => Scene::from_mesh_file(path)?,
            SceneKind::Pov => pov::load(path, options)?,
        };
        // A .pov scene's camera (an image plane, perhaps) was made for this
        // size already; setting it again changes nothing there.
        if let Some(size) = options.size {
            (scene.camera.width, scene.camera.height) = size;
        }
        Ok(scene)
    }

    /// A scene named after the file at `path`, with nothing in it yet: the
    /// loaders fill it.
    fn empty(path: &Path, render: RenderSettings, background: Vec3) -> Scene {
        Scene {
            name: scene_name(path),
            camera: Camera::default(),
            render,
            background,
            environment: None,
            fogs: Vec::new(),
            materials: Vec::new(),
            meshes: Vec::new(),
            shapes: Vec::new(),
            prototypes: Vec::new(),
            instances: Vec::new(),
            lights: Vec::new(),
            light_picker: LightPicker::default(),
            warnings: Vec::new(),
            sources: vec![path.to_owned()],
            import: None,
        }
    }

    /// A bare OBJ or PLY as a scene: a camera framing its bounds, a point
    /// light near the camera, grey diffuse for faces without a material.
    fn from_mesh_file(path: &Path) -> Result<Scene> {
        let mut scene = Scene::empty(path, RenderSettings::default(), Vec3::splat(0.05));
        scene.add_obj(
            path,
            load_mesh(path)?,
            None,
            |_| None,
            &mut Textures::default(),
        );
        let bounds = scene.bounds();
        if bounds.is_empty() {
            return Err(Error::Mesh {
                path: path.to_owned(),
                line: 0,
                message: "the file has no faces".into(),
            });
        }
        scene.camera = Camera::framing(bounds, 640, 480);
        scene.camera.check().map_err(|p| Error::Mesh {
            path: path.to_owned(),
            line: 0,
            message: format!("the camera that frames this model: {}", p.message),
        })?;
        scene.lights.push(headlight(&scene.camera));
        scene.gather_emitters();
        Ok(scene)
    }

    /// Appends the meshes of the OBJ at `path`. `forced` replaces all its
    /// materials when given; otherwise `named` gives the scene file's
    /// material of a name, which replaces the OBJ's own of that name. A
    /// missing library and a name nothing defines are a warning each (file
    /// and line), and such faces get the default grey.
    pub(crate) fn add_obj(
        &mut self,
        path: &Path,
        obj: ObjFile,
        forced: Option<u32>,
        named: impl Fn(&str) -> Option<u32>,
        textures: &mut Textures,
    ) {
        self.warnings.extend(obj.unread);
        if obj.degenerate > 0 {
            self.warnings.push(format!(
                "{}: {} degenerate triangle{} (zero area) skipped: never hit, but kept so \
                 triangle numbers do not shift",
                path.display(),
                obj.degenerate,
                if obj.degenerate == 1 { "" } else { "s" }
            ));
        }
        for source in obj.sources {
            if !self.sources.contains(&source) {
                self.sources.push(source);
            }
        }
        let at = |line: usize| format!("{}:{line}", path.display());
        if forced.is_none() {
            for (line, file) in &obj.missing_libraries {
                self.warnings.push(format!(
                    "{}: material library {} not found; its materials render as the default \
                     grey diffuse",
                    at(*line),
                    file.display()
                ));
            }
            for (library, line, keyword) in &obj.unread_maps {
                self.warnings.push(format!(
                    "{}:{line}: `{keyword}` is not read yet: the material's own value is used",
                    library.display()
                ));
            }
        }
        // Every material a library defines is added, used or not, in file
        // order, so the scene hash of files that loaded before is unchanged.
        let mut index = Vec::with_capacity(obj.materials.len());
        for m in obj.materials {
            let own = match (named(&m.name), m.defined) {
                (Some(replaced), _) => replaced,
                (None, Some(mut defined)) => {
                    for map in &m.maps {
                        let asked_by = format!("{}:{}", map.library.display(), map.line);
                        if !map.slot.matters_for(defined.kind) {
                            self.warnings.push(format!(
                                "{asked_by}: material `{}` is {}, which has no parameter \
                                 this map scales: the map is left out",
                                m.name,
                                defined.kind.name()
                            ));
                            continue;
                        }
                        let texture = textures.texture(
                            &map.file,
                            map.slot.srgb(),
                            &map.placement,
                            &asked_by,
                            &mut self.warnings,
                        );
                        obj::set_map(
                            &mut defined,
                            map.slot,
                            texture,
                            map.placement.bump,
                            map.factor,
                        );
                    }
                    self.materials.push(defined);
                    self.materials.len() as u32 - 1
                }
                (None, None) if forced.is_some() => INVALID_ID,
                (None, None) => {
                    self.warnings.push(format!(
                        "{}: material `{}` is not defined in any material library loaded so \
                         far; its faces render as the default grey diffuse",
                        at(m.line),
                        m.name
                    ));
                    self.default_material()
                }
            };
            index.push(forced.unwrap_or(own));
        }
        let mut default = forced;
        for mut mesh in obj.meshes {
            for m in &mut mesh.materials {
                *m = match index.get(*m as usize) {
                    Some(&own) => own,
                    None => *default.get_or_insert_with(|| self.default_material()),
                };
            }
            self.meshes.push(mesh);
        }
    }

    /// The index of the grey default material, added on first use.
    pub(crate) fn default_material(&mut self) -> u32 {
        let grey = Material::default_grey();
        match self.materials.iter().position(|m| *m == grey) {
            Some(i) => i as u32,
            None => {
                self.materials.push(grey);
                self.materials.len() as u32 - 1
            }
        }
    }

    /// The emissive material of area light `index`'s geometry.
    pub(crate) fn light_material(&mut self, index: usize, radiance: Vec3) -> u32 {
        let mut m = Material::diffuse(&format!("light {index}"), Vec3::ZERO);
        m.kind = crate::shading::MaterialKind::Emissive;
        m.emission = radiance;
        self.materials.push(m);
        self.materials.len() as u32 - 1
    }

    pub fn bounds(&self) -> Bounds {
        let meshes = self.meshes.iter().map(Mesh::bounds);
        let shapes = self.shapes.iter().map(Shape::bounds);
        let instances = self
            .instances
            .iter()
            .map(|i| i.bounds_to_world(self.prototypes[i.prototype as usize].bounds()));
        meshes
            .chain(shapes)
            .chain(instances)
            .fold(Bounds::EMPTY, Bounds::union)
    }

    /// The geometry id of the analytic shapes (one Embree geometry holds them all).
    pub fn shapes_geom_id(&self) -> u32 {
        self.meshes.len() as u32
    }

    /// The triangles of the scene's own meshes, each prototype's counted once.
    pub fn triangle_count(&self) -> usize {
        let own: usize = self.meshes.iter().map(|m| m.triangles.len()).sum();
        own + self
            .prototypes
            .iter()
            .map(Prototype::triangle_count)
            .sum::<usize>()
    }

    /// The triangles the scene shows: each instance counts its prototype's.
    pub fn instanced_triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.prototypes[i.prototype as usize].triangle_count())
            .sum()
    }
}

/// Reads a mesh file: PLY by its extension (in any case), OBJ otherwise.
pub fn load_mesh(path: &Path) -> Result<ObjFile> {
    let ply = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    if ply {
        ply::load_ply(path)
    } else {
        load_obj(path)
    }
}

/// Why geometry with these world bounds cannot be traced, if it cannot: a
/// coordinate beyond [`MAX_COORDINATE`] (see there for the reason).
fn bounds_problem(bounds: Bounds) -> Option<String> {
    let largest = bounds.min.abs().max(bounds.max.abs()).max_element();
    let beyond = largest.is_nan() || f64::from(largest) > MAX_COORDINATE;
    (!bounds.is_empty() && beyond).then(|| {
        format!(
            "in world space this reaches a coordinate of {largest:e}, beyond the limit of \
             {MAX_COORDINATE:e}"
        )
    })
}

fn scene_name(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
}

/// A point light just above the camera, bright enough that a white surface at
/// the look-at point receives an irradiance of about 3.
fn headlight(camera: &Camera) -> Light {
    let distance = camera.eye.distance(camera.look_at);
    let position = camera.eye + 0.2 * distance * camera.up.normalize();
    let d = position.distance(camera.look_at);
    Light::Point {
        position,
        intensity: Vec3::splat(3.0 * d * d),
    }
}

#[cfg(test)]
mod tests;
