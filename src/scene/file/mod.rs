//! The TOML scene format (see scenes/README.md): loading a `Scene` from a
//! file, one function per section. The schema is read by serde (`schema`),
//! each value checked (`check`), and analytic objects built by their type
//! (`shapes`).

mod check;
mod environment;
mod schema;
mod shapes;
mod tree;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;

use glam::{Affine3A, DAffine3, DMat4, DVec3};

use super::solids::{linear, rotation};
use check::Check;
pub(super) use check::physical_memory;
use schema::{
    CameraFile, FovAxisFile, InstanceFile, IntegratorFile, LightFile, MaterialFile, MeshFile,
    MetallicFile, Object, Param, ProjectionFile, PrototypeFile, RenderFile, SamplerFile, ScaleFile,
    SceneFile, ShapeFile, ShapeKind, SpecularFile, TransformFile,
};
use shapes::{Body, Built};
use tree::Parent;

use super::obj::{MAX_COORDINATE, MapSlot, set_map};
use super::textures::{Placement, Textures};
use super::{
    Adaptive, Camera, CameraKey, Instance, Integrator, Optics, PhotonSettings, Projection,
    Prototype, RenderSettings, Scene, ThinLens, headlight, load_mesh,
};
use crate::error::{Error, Result};
use crate::geometry::{Box3, Csg, Mesh, Shape, Surface};
use crate::lights::Light;
use crate::math::Vec3;
use crate::poly::solve::{Method, Solver};
use crate::sampling::SamplerKind;
use crate::shading::{Checker, Finish, Material, MaterialKind};
use crate::suggest;

pub(super) fn load(path: &Path) -> Result<Scene> {
    let text = crate::io::input::read_text(path)?;
    from_text(path, &text, Vec::new())
}

/// A scene from TOML text that `path` names in messages (and whose folder
/// relative files are read from), with `meshes` made in code after its
/// objects: each with the name of one of its materials, or none for the
/// default. See `Scene::from_toml`.
pub(super) fn from_text(
    path: &Path,
    text: &str,
    meshes: Vec<(Mesh, Option<String>)>,
) -> Result<Scene> {
    let file: SceneFile = toml::from_str(text).map_err(|e| Error::Scene {
        path: path.to_owned(),
        message: suggest::with_suggestion(&e.to_string()),
    })?;
    let check = Check { path, text };
    let render = render(&check, &file.render)?;
    check.render(&render)?;
    let background = check.colour("background", file.background.unwrap_or([0.0; 3]))?;
    let mut scene = Scene::empty(path, render, background);
    let dir = path.parent().unwrap_or(Path::new("."));
    if let Some(env) = &file.environment {
        if file.background.is_some() {
            let message = "an [environment] is the background: give one or the other";
            return Err(check.error("background", message));
        }
        let env = environment::environment(&check, dir, env, &mut scene.sources)?;
        scene.environment = Some(env);
    }
    let mut textures = Textures::default();
    for (name, m) in &file.materials {
        let mut material = material(&check, name, m)?;
        // Read as an MTL map is: its colour space by the slot, once per scene.
        for (field, slot, file) in textured(m) {
            let key = format!("materials.{name}.{field}");
            let asked_by = format!("{}: {}.texture", path.display(), check.place(&key));
            let placement = Placement::default();
            let texture = textures.texture(
                &dir.join(file),
                slot.srgb(),
                &placement,
                &asked_by,
                &mut scene.warnings,
            );
            set_map(&mut material, slot, texture, placement.bump, 1.0);
        }
        scene.materials.push(material);
    }
    let solver = solver(&check, &file.render)?;
    let objects = Objects {
        check: &check,
        dir,
        textures: RefCell::new(textures),
        constants: file
            .constants
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect(),
        materials: &file.materials,
        solver,
    };
    for (name, prototype) in &file.prototypes {
        objects.prototype(&mut scene, name, prototype)?;
    }
    for (index, object) in file.objects.iter().enumerate() {
        let key = format!("objects[{index}]");
        match object.view() {
            Object::Shape(kind, shape) => objects.shape(&mut scene, &key, kind, shape)?,
            Object::Mesh(mesh) => objects.mesh(&mut scene, &key, mesh)?,
            Object::Instance(instance) => {
                objects.instance(&mut scene, &key, &file.prototypes, instance)?
            }
        }
    }
    for (index, (mut mesh, material)) in meshes.into_iter().enumerate() {
        let key = format!("meshes[{index}]");
        let material = match objects.material(&key, &material)? {
            Some(m) => m,
            None => scene.default_material(),
        };
        let vertices = mesh.positions.len();
        if let Some(bad) = mesh
            .triangles
            .iter()
            .flatten()
            .find(|&&i| i as usize >= vertices)
        {
            let message = format!("vertex index {bad} out of range: {vertices} vertices");
            return Err(check.error(&key, message));
        }
        mesh.materials = vec![material; mesh.triangles.len()];
        check.bounds(&key, mesh.bounds())?;
        scene.meshes.push(mesh);
    }
    let unused: Vec<String> = (scene.prototypes.iter().enumerate())
        .filter(|&(i, _)| !scene.instances.iter().any(|x| x.prototype as usize == i))
        .map(|(_, p)| {
            format!(
                "{}: prototype `{}` is declared but no object instances it",
                path.display(),
                p.name
            )
        })
        .collect();
    scene.warnings.extend(unused);
    for (index, entry) in file.lights.iter().enumerate() {
        light(&check, &mut scene, index, entry, solver)?;
    }
    scene.camera = match &file.camera {
        Some(c) => camera(&check, c)?,
        None => {
            let bounds = scene.bounds();
            if bounds.is_empty() {
                return Err(check.error("camera", "missing, and there is no geometry to frame"));
            }
            let camera = Camera::framing(bounds, 640, 480);
            camera
                .check()
                .map_err(|p| check.error("camera", p.message))?;
            if file.lights.is_empty() && scene.environment.is_none() {
                scene.lights.push(headlight(&camera));
            }
            camera
        }
    };
    scene.gather_emitters();
    Ok(scene)
}

/// `[render]`, with the defaults for what it leaves out.
fn render(check: &Check, file: &RenderFile) -> Result<RenderSettings> {
    let defaults = RenderSettings::default();
    Ok(RenderSettings {
        spp: file.spp.unwrap_or(defaults.spp),
        max_depth: file.max_depth.unwrap_or(defaults.max_depth),
        seed: file.seed.unwrap_or(defaults.seed),
        min_weight: file.min_weight.unwrap_or(defaults.min_weight),
        filter: match &file.filter {
            Some(name) => name.parse().map_err(|e| check.error("render.filter", e))?,
            None => defaults.filter,
        },
        sampler: match file.sampler {
            Some(SamplerFile::Sobol) => SamplerKind::Sobol,
            Some(SamplerFile::Independent) => SamplerKind::Independent,
            None => defaults.sampler,
        },
        integrator: match file.integrator {
            Some(IntegratorFile::Whitted) | None => Integrator::Whitted,
            Some(IntegratorFile::Path) => Integrator::Path,
        },
        adaptive: file.adaptive.as_ref().map(|a| Adaptive {
            max_spp: a.max_spp,
            threshold: a.threshold,
        }),
        photons: match &file.photons {
            Some(p) => PhotonSettings {
                count: p.count.unwrap_or(defaults.photons.count),
                radius: p.radius.or(defaults.photons.radius),
            },
            None => defaults.photons,
        },
        working_gamma: defaults.working_gamma,
    })
}

/// The root finder of `[render]` (`method`, `tolerance`) for analytic shapes.
fn solver(check: &Check, render: &RenderFile) -> Result<Solver> {
    let mut solver = Solver::default();
    if let Some(name) = &render.method {
        solver.method = name
            .parse::<Method>()
            .map_err(|e| check.error("render.method", e))?;
    }
    if let Some(tolerance) = render.tolerance {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            return Err(check.error(
                "render.tolerance",
                format!("expected a number in (0, 1), found {tolerance}"),
            ));
        }
        solver.tolerance = tolerance;
    }
    Ok(solver)
}

/// The camera's projection and lens, with its field of view: an
/// orthographic camera has none (it is kept at 90° to pass the range check,
/// and unused), and a `fov` or `fov_axis` given to one is an error, as is a
/// lens setting without the other.
fn optics(check: &Check, c: &CameraFile) -> Result<(f32, Optics)> {
    let projection = match (c.kind, c.fov, c.view_width) {
        (ProjectionFile::Perspective, Some(_), Some(_)) => {
            return Err(check.error(
                "camera.view_width",
                "a perspective camera takes fov, not view_width (set type = \"orthographic\")",
            ));
        }
        (ProjectionFile::Perspective, None, _) => {
            return Err(check.error(
                "camera",
                "missing fov: a perspective camera needs its field of view in degrees",
            ));
        }
        (ProjectionFile::Perspective, Some(_), None) if c.fov_axis == FovAxisFile::X => {
            Projection::PerspectiveX
        }
        (ProjectionFile::Perspective, Some(_), None) => Projection::Perspective,
        (ProjectionFile::Orthographic, Some(_), _) => {
            return Err(check.error(
                "camera.fov",
                "an orthographic camera has no field of view: give view_width instead",
            ));
        }
        (ProjectionFile::Orthographic, None, None) => {
            return Err(check.error(
                "camera",
                "missing view_width: an orthographic camera needs the width it sees",
            ));
        }
        (ProjectionFile::Orthographic, None, Some(view_width)) => {
            if c.fov_axis != FovAxisFile::Y {
                return Err(check.error(
                    "camera.fov_axis",
                    "an orthographic camera has no field of view: view_width is its width",
                ));
            }
            Projection::Orthographic { view_width }
        }
    };
    let lens = match (c.aperture, c.focus_distance) {
        (None, None) => None,
        (Some(aperture), Some(focus_distance)) => Some(ThinLens {
            aperture,
            focus_distance,
        }),
        (Some(_), None) => {
            return Err(check.error(
                "camera.aperture",
                "a lens needs focus_distance too: the distance along the view that is sharp",
            ));
        }
        (None, Some(_)) => {
            return Err(check.error(
                "camera.focus_distance",
                "a lens needs aperture too: the lens radius (0 for a pinhole)",
            ));
        }
    };
    Ok((c.fov.unwrap_or(90.0), Optics { projection, lens }))
}

/// `[camera]`, with its path of keys.
fn camera(check: &Check, c: &CameraFile) -> Result<Camera> {
    let eye = check.finite("camera.eye", c.eye)?;
    let look_at = check.finite("camera.look_at", c.look_at)?;
    let up = check.direction("camera.up", c.up)?;
    let (fov, optics) = optics(check, c)?;
    check.image(fov, c.width, c.height)?;
    let mut keys = Vec::with_capacity(c.keys.len());
    for (i, k) in c.keys.iter().enumerate() {
        let key = |field: &str| format!("camera.keys[{i}].{field}");
        let (eye, look_at) = (
            check.finite(&key("eye"), k.eye)?,
            check.finite(&key("look_at"), k.look_at)?,
        );
        if keys
            .last()
            .is_some_and(|last: &CameraKey| last.frame >= k.frame)
        {
            return Err(check.error(
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
        fov,
        width: c.width,
        height: c.height,
        plane: None,
        optics,
    };
    camera.check().map_err(|p| check.error(&p.key, p.message))?;
    Ok(camera)
}

/// One `[materials.NAME]` table.
fn material(check: &Check, name: &str, m: &MaterialFile) -> Result<Material> {
    let key = |field: &str| format!("materials.{name}.{field}");
    let colour = |field: &str, v: Option<[f32; 3]>, default: f32| match v {
        Some(v) => check.colour(&key(field), v),
        None => Ok(Vec3::splat(default)),
    };
    let kind = m.kind;
    // A texture where the type has no parameter it drives: MTL's rule
    // (which warns, as exported files carry such maps); here the file was
    // written by hand, so it is a mistake.
    if let Some((field, slot, _)) = textured(m).find(|(_, slot, _)| !slot.matters_for(kind)) {
        let kinds = MaterialKind::ALL
            .into_iter()
            .filter(|&k| slot.matters_for(k));
        let names: Vec<String> = kinds.map(|k| format!("\"{}\"", k.name())).collect();
        return Err(check.error(
            &key(field),
            format!(
                "a texture drives the {field} of a material of type {} only, not \"{}\"",
                names.join(" or "),
                kind.name()
            ),
        ));
    }
    let classic = kind == MaterialKind::Classic;
    // A classic material's interior is POV-Ray's: ior 1 (no bending) unless given.
    let ior = m.ior.unwrap_or(if classic { 1.0 } else { 1.5 });
    check.positive(&key("ior"), ior)?;
    let shininess = m.shininess.unwrap_or(50.0);
    if !(shininess >= 0.0 && shininess.is_finite()) {
        return Err(check.error(
            &key("shininess"),
            format!("expected a number >= 0, found {shininess}"),
        ));
    }
    // A parameter given as a texture takes the constant 1 (the map alone
    // sets it), as an MTL map without its constant does.
    let roughness = match m.roughness {
        Some(Param::Value(r)) => r,
        Some(Param::Table(_)) => 1.0,
        None if classic => 0.05,
        None => 0.3,
    };
    // A classic highlight's exponent is 1/roughness: 0 has none.
    let low = if classic { "above 0" } else { "from 0" };
    if !(0.0..=1.0).contains(&roughness) || (classic && roughness == 0.0) {
        return Err(check.error(
            &key("roughness"),
            format!("expected a number {low} to 1, found {roughness}"),
        ));
    }
    let specular_default = if kind == MaterialKind::Plastic {
        0.04
    } else {
        0.0
    };
    let (specular, finish) = if classic {
        (Vec3::ZERO, finish(check, name, m, roughness)?)
    } else {
        let specular = match m.specular {
            Some(Param::Value(SpecularFile::Colour(v))) => Some(v),
            Some(Param::Table(_)) => Some([1.0; 3]),
            Some(Param::Value(SpecularFile::Amount(_))) => {
                return Err(check.error(
                    &key("specular"),
                    "expected a colour [r, g, b] (a single amount is the classic type's)",
                ));
            }
            None => None,
        };
        if kind == MaterialKind::Metal && matches!(m.metallic, Some(Param::Value(_))) {
            return Err(check.error(
                &key("metallic"),
                "a metal is metal throughout: its metalness takes only a map, \
                 { texture = \"file.png\" } (a number is the classic type's)",
            ));
        }
        classic_keys_refused(check, name, m)?;
        (
            colour("specular", specular, specular_default)?,
            Finish::default(),
        )
    };
    let (albedo, checker) = match &m.albedo {
        Some(Param::Value(v)) => (colour("albedo", Some(*v), 0.7)?, None),
        Some(Param::Table(t)) => match (&t.checker, &t.texture, t.scale) {
            (Some(colours), None, scale) => (
                Vec3::splat(0.7),
                Some(checker(check, name, colours, scale)?),
            ),
            (None, Some(_), None) => (Vec3::splat(0.7), None),
            _ => {
                return Err(check.error(
                    &key("albedo"),
                    format!(
                        "expected {}",
                        <schema::AlbedoTable as schema::Described>::WHAT
                    ),
                ));
            }
        },
        None => (Vec3::splat(0.7), None),
    };
    let emission = match &m.radiance {
        Some(Param::Value(v)) => colour("radiance", Some(*v), 0.0)?,
        Some(Param::Table(_)) => Vec3::ONE,
        None => Vec3::ZERO,
    };
    Ok(Material {
        name: name.to_owned(),
        kind,
        albedo,
        checker,
        mapped: None,
        specular,
        shininess,
        roughness,
        ior,
        emission,
        finish,
        // Read by `load`, which keeps the scene's textures.
        albedo_map: None,
        maps: Default::default(),
    })
}

/// Material `index` as an analytic object placed by `to_world` shows it: a
/// checker in the object's own space (issue 16: "in object space for
/// analytic shapes"), so it moves, turns and scales with the object, as
/// POV-Ray's pigment does. A copy of the material with the checker placed,
/// shared by objects placed alike; the material itself where it has no
/// checker or the object is not moved.
fn placed(scene: &mut Scene, index: u32, to_world: DAffine3) -> u32 {
    let material = &scene.materials[index as usize];
    let Some(checker) = material.checker.filter(|_| to_world != DAffine3::IDENTITY) else {
        return index;
    };
    let placed = Material {
        checker: Some(Checker {
            to_pattern: checker.to_pattern * to_world.inverse(),
            ..checker
        }),
        ..material.clone()
    };
    match scene.materials.iter().position(|m| *m == placed) {
        Some(i) => i as u32,
        None => {
            scene.materials.push(placed);
            scene.materials.len() as u32 - 1
        }
    }
}

/// The parameters of a material given as images: each one's key, the MTL
/// map it stands for, and the file (relative to the scene file).
fn textured(m: &MaterialFile) -> impl Iterator<Item = (&'static str, MapSlot, &str)> {
    fn file<T>(p: &Option<Param<T>>) -> Option<&str> {
        match p {
            Some(Param::Table(t)) => Some(&t.texture),
            _ => None,
        }
    }
    let albedo = match &m.albedo {
        Some(Param::Table(t)) => t.texture.as_deref(),
        _ => None,
    };
    [
        ("albedo", MapSlot::Albedo, albedo),
        ("specular", MapSlot::Specular, file(&m.specular)),
        ("roughness", MapSlot::Roughness, file(&m.roughness)),
        ("metallic", MapSlot::Metallic, file(&m.metallic)),
        ("radiance", MapSlot::Emission, file(&m.radiance)),
    ]
    .into_iter()
    .filter_map(|(field, slot, file)| Some((field, slot, file?)))
}

/// `albedo = { checker = [A, B], scale = s }`: both colours checked, the
/// scale > 0 and finite.
fn checker(
    check: &Check,
    name: &str,
    colours: &[[f32; 3]; 2],
    scale: Option<f64>,
) -> Result<Checker> {
    let key = |field: &str| format!("materials.{name}.albedo.{field}");
    let colours = [
        check.colour(&key("checker"), colours[0])?,
        check.colour(&key("checker"), colours[1])?,
    ];
    let scale = scale.unwrap_or(1.0);
    check.positive(&key("scale"), scale)?;
    // A subnormal scale is > 0 but its inverse, the pattern's transform, is not finite.
    if !scale.recip().is_finite() {
        return Err(check.error(
            &key("scale"),
            format!("expected a number > 0 whose inverse is finite, found {scale:e}"),
        ));
    }
    Ok(Checker {
        colours,
        to_pattern: DAffine3::from_scale(DVec3::splat(scale.recip())),
    })
}

/// A classic material's finish: POV-Ray's keys and defaults, each fraction in
/// [0, 1] and `phong_size` > 0.
fn finish(check: &Check, name: &str, m: &MaterialFile, roughness: f32) -> Result<Finish> {
    let key = |field: &str| format!("materials.{name}.{field}");
    let defaults = Finish::default();
    let fraction = |field: &str, v: Option<f32>, default: f32| match v {
        Some(v) => check.fraction(&key(field), v),
        None => Ok(default),
    };
    for (field, given) in [
        ("shininess", m.shininess.is_some()),
        ("radiance", m.radiance.is_some()),
    ] {
        if given {
            return Err(check.error(
                &key(field),
                "a classic material has no such key (roughness and phong_size set its highlights)",
            ));
        }
    }
    // A texture is refused before: a classic material has none.
    let specular = match m.specular {
        Some(Param::Value(SpecularFile::Amount(v))) => check.fraction(&key("specular"), v)?,
        Some(Param::Value(SpecularFile::Colour(_))) => {
            return Err(check.error(
                &key("specular"),
                "expected the Blinn highlight's amount, a number from 0 to 1, not a colour",
            ));
        }
        Some(Param::Table(_)) | None => defaults.specular,
    };
    let phong_size = m.phong_size.unwrap_or(defaults.phong_size);
    check.positive(&key("phong_size"), phong_size)?;
    let brilliance = m.brilliance.unwrap_or(defaults.brilliance);
    check.positive(&key("brilliance"), brilliance)?;
    let reflection = fraction("reflection", m.reflection, defaults.reflection)?;
    let fresnel = m.fresnel.unwrap_or(defaults.fresnel);
    let metallic = match m.metallic {
        Some(Param::Value(MetallicFile::On(on))) => f32::from(u8::from(on)),
        Some(Param::Value(MetallicFile::Amount(v))) => check.fraction(&key("metallic"), v)?,
        Some(Param::Table(_)) | None => defaults.metallic,
    };
    Ok(Finish {
        diffuse: fraction("diffuse", m.diffuse, defaults.diffuse)?,
        ambient: fraction("ambient", m.ambient, defaults.ambient)?,
        specular,
        roughness,
        phong: fraction("phong", m.phong, defaults.phong)?,
        phong_size,
        reflection,
        // Fresnel's own grazing limit is all the light; without it, a
        // constant fraction unless a grazing one is given.
        reflection_max: fraction(
            "reflection_max",
            m.reflection_max,
            if fresnel { 1.0 } else { reflection },
        )?,
        fresnel,
        metallic,
        transmit: fraction("transmit", m.transmit, defaults.transmit)?,
        filter: defaults.filter,
        brilliance,
        fade: defaults.fade,
    })
}

/// The finish keys on a material of another type: an error naming the first.
fn classic_keys_refused(check: &Check, name: &str, m: &MaterialFile) -> Result<()> {
    let given = [
        ("diffuse", m.diffuse.is_some()),
        ("ambient", m.ambient.is_some()),
        ("phong", m.phong.is_some()),
        ("phong_size", m.phong_size.is_some()),
        ("brilliance", m.brilliance.is_some()),
        ("reflection", m.reflection.is_some()),
        ("reflection_max", m.reflection_max.is_some()),
        ("fresnel", m.fresnel.is_some()),
        // A metal's metalness map is its own (checked with the textures).
        ("metallic", matches!(m.metallic, Some(Param::Value(_)))),
        ("transmit", m.transmit.is_some()),
    ];
    match given.iter().find(|(_, g)| *g) {
        Some((field, _)) => Err(check.error(
            &format!("materials.{name}.{field}"),
            "only a material of type \"classic\" takes this key",
        )),
        None => Ok(()),
    }
}

/// Why an emissive prototype or instance material is refused: the lights
/// are gathered from the scene's own geometry, and sampling every copy of an
/// instanced emitter as a light would undo what instancing saves.
const EMISSIVE_INSTANCE: &str = "emissive geometry cannot be instanced (the lights are not \
     gathered from instances): place it as an object of its own";

/// What every `[[objects]]` entry is built with.
struct Objects<'a> {
    check: &'a Check<'a>,
    /// The scene file's folder, which OBJ paths are relative to.
    dir: &'a Path,
    /// The scene's images, shared by every object's materials.
    textures: RefCell<Textures>,
    constants: Vec<(&'a str, f64)>,
    materials: &'a BTreeMap<String, MaterialFile>,
    solver: Solver,
}

impl Objects<'_> {
    /// An analytic object of type `kind`: one entry of the scene's shapes,
    /// a CSG tree for the types that are more than one surface.
    fn shape(&self, scene: &mut Scene, key: &str, kind: ShapeKind, file: &ShapeFile) -> Result<()> {
        let check = self.check;
        let material = match self.material(key, &file.material)? {
            Some(m) => m,
            None => scene.default_material(),
        };
        if file.inverse.is_some() {
            return Err(check.error(
                &format!("{key}.inverse"),
                "`inverse` applies only to an object inside a csg",
            ));
        }
        let built = self.built(key, kind, file)?;
        let to_world = self.transform(key, &file.transform)?;
        // The object's own space, where its checker lies.
        let object = to_world;
        let clip = self.clip(key, file)?;
        let (surface, to_world, clip) = match built {
            Built::Surface {
                surface,
                clip: default,
                frame,
                body: Body::Open | Body::Solid,
            } => (surface, to_world * frame, clip.or(default)),
            Built::Plane { normal, distance } => match clip {
                Some(clip) => (linear(normal, distance), to_world, Some(clip)),
                None => {
                    return Err(check.error(
                        key,
                        "a plane is infinite: give it a `clip` box, or cut it in a csg",
                    ));
                }
            },
            built => {
                let mut leaves = Vec::new();
                let parent = Parent {
                    to_world: DAffine3::IDENTITY,
                    material,
                    depth: 0,
                };
                let root = self.node(key, file, built, &parent, &mut leaves)?;
                // A part's own material follows the whole object too.
                for leaf in &mut leaves {
                    leaf.material = placed(scene, leaf.material, object);
                }
                let tree = Csg::new(root, leaves).map_err(|e| check.error(key, e))?;
                (Surface::Csg(Box::new(tree)), DAffine3::IDENTITY, None)
            }
        };
        // A tree's parts carry their own (placed above).
        let material = match surface {
            Surface::Csg(_) => material,
            _ => placed(scene, material, object),
        };
        let shape = Shape::new(surface, to_world, clip, material, self.solver)
            .map_err(|e| check.error(key, e))?;
        check.bounds(key, shape.bounds())?;
        scene.shapes.push(shape);
        Ok(())
    }

    /// The object's parts by its type, errors named at `key`.
    fn built(&self, key: &str, kind: ShapeKind, file: &ShapeFile) -> Result<Built> {
        shapes::build(kind, file, &self.constants).map_err(|(field, message)| {
            let key = if field.is_empty() {
                key.to_owned()
            } else {
                format!("{key}.{field}")
            };
            self.check.error(&key, message)
        })
    }

    /// The object's own `clip` box, if it gives one.
    fn clip(&self, key: &str, file: &ShapeFile) -> Result<Option<Box3>> {
        let Some(c) = &file.clip else {
            return Ok(None);
        };
        Ok(Some(Box3 {
            min: self.check.finite64(&format!("{key}.clip.min"), c.min)?,
            max: self.check.finite64(&format!("{key}.clip.max"), c.max)?,
        }))
    }

    /// A `type = "mesh"` object: the meshes of an OBJ or PLY file, placed.
    fn mesh(&self, scene: &mut Scene, key: &str, mesh: &MeshFile) -> Result<()> {
        let check = self.check;
        let material = self.material(key, &mesh.material)?;
        let transform = self.transform(key, &mesh.transform)?;
        let first = scene.meshes.len();
        let obj_path = self.dir.join(&mesh.file);
        // A file that cannot be read is named with the line that asks for it.
        let obj = load_mesh(&obj_path).map_err(|e| match e {
            Error::Io { .. } => check.error(&format!("{key}.file"), e),
            other => other,
        })?;
        // A scene material of a name the OBJ uses replaces the OBJ's own.
        let named = |name: &str| {
            self.materials
                .keys()
                .position(|k| k == name)
                .map(|i| i as u32)
        };
        let textures = &mut self.textures.borrow_mut();
        scene.add_obj(&obj_path, obj, material, named, textures);
        let matrix = DMat4::from(transform).as_mat4();
        for m in &mut scene.meshes[first..] {
            m.transform(&matrix);
            check.bounds(key, m.bounds())?;
        }
        Ok(())
    }

    /// `[prototypes.NAME]`: its objects loaded as the scene's own are, in
    /// the prototype's space, then moved out of the scene into the prototype.
    fn prototype(&self, scene: &mut Scene, name: &str, file: &PrototypeFile) -> Result<()> {
        let check = self.check;
        let (first_mesh, first_shape) = (scene.meshes.len(), scene.shapes.len());
        for (index, object) in file.objects.iter().enumerate() {
            let key = format!("prototypes.{name}.objects[{index}]");
            match object.view() {
                Object::Shape(kind, shape) => self.shape(scene, &key, kind, shape)?,
                Object::Mesh(mesh) => self.mesh(scene, &key, mesh)?,
                Object::Instance(_) => {
                    return Err(check.error(
                        &key,
                        "an instance cannot be part of a prototype: instancing is one level \
                         deep, so put the geometry itself in this prototype",
                    ));
                }
            }
        }
        let prototype = Prototype::new(
            name.to_owned(),
            scene.meshes.split_off(first_mesh),
            scene.shapes.split_off(first_shape),
        );
        let key = format!("prototypes.{name}");
        if prototype.meshes.is_empty() && prototype.shapes.is_empty() {
            return Err(check.error(
                &format!("{key}.objects"),
                "a prototype needs at least one object, e.g. [[prototypes.NAME.objects]]",
            ));
        }
        let materials = prototype.meshes.iter().flat_map(|m| m.materials.clone());
        let mut materials = materials.chain(prototype.shapes.iter().flat_map(Shape::materials));
        if materials.any(|m| scene.materials[m as usize].emits()) {
            return Err(check.error(&key, EMISSIVE_INSTANCE));
        }
        scene.prototypes.push(prototype);
        Ok(())
    }

    /// A `type = "instance"` object: the prototype it names, placed.
    fn instance(
        &self,
        scene: &mut Scene,
        key: &str,
        prototypes: &BTreeMap<String, PrototypeFile>,
        file: &InstanceFile,
    ) -> Result<()> {
        let check = self.check;
        let Some(prototype) = prototypes.keys().position(|k| *k == file.prototype) else {
            let hint = suggest::closest(&file.prototype, prototypes.keys().map(String::as_str))
                .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
            return Err(check.error(
                &format!("{key}.prototype"),
                format!(
                    "no prototype named `{}` in [prototypes]{hint}",
                    file.prototype
                ),
            ));
        };
        let material = self.material(key, &file.material)?;
        if material.is_some_and(|m| scene.materials[m as usize].emits()) {
            return Err(check.error(&format!("{key}.material"), EMISSIVE_INSTANCE));
        }
        let placement = self.transform(key, &file.transform)?;
        let to_world = Affine3A::from_mat4(DMat4::from(placement).as_mat4());
        let mut instance = Instance::new(prototype as u32, to_world, material);
        // The checker of an analytic shape moves with the instance: what its
        // shapes show is placed once more, by the instance's transform. An
        // instance's own material is placed by that alone (its checker in
        // the prototype's space).
        let shown = match material {
            Some(m) => vec![m],
            None => scene.prototypes[prototype]
                .shapes
                .iter()
                .flat_map(Shape::materials)
                .collect(),
        };
        for m in shown {
            let moved = placed(scene, m, placement);
            if moved != m && !instance.shape_materials.iter().any(|&(from, _)| from == m) {
                instance.shape_materials.push((m, moved));
            }
        }
        let bounds = scene.prototypes[prototype].bounds();
        check.bounds(key, instance.bounds_to_world(bounds))?;
        scene.instances.push(instance);
        Ok(())
    }

    /// The transform of the object at `key`.
    fn transform(&self, key: &str, t: &TransformFile) -> Result<DAffine3> {
        let key = |field: &str| format!("{key}.transform.{field}");
        let vector = |field: &str, v: Option<[f64; 3]>| {
            self.check.finite64(&key(field), v.unwrap_or([0.0; 3]))
        };
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
            return Err(self.check.error(
                &key("scale"),
                format!("expected finite factors between 1e-12 and 1e12 in size, found {scale}"),
            ));
        }
        let r = rotate * (std::f64::consts::PI / 180.0);
        Ok(DAffine3::from_translation(translate) * rotation(r) * DAffine3::from_scale(scale))
    }

    /// The index of the material an object names, if it names one.
    fn material(&self, key: &str, name: &Option<String>) -> Result<Option<u32>> {
        let Some(name) = name else {
            return Ok(None);
        };
        match self.materials.keys().position(|k| k == name) {
            Some(i) => Ok(Some(i as u32)),
            None => {
                let hint = suggest::closest(name, self.materials.keys().map(String::as_str))
                    .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
                Err(self.check.error(
                    &format!("{key}.material"),
                    format!("no material named `{name}` in [materials]{hint}"),
                ))
            }
        }
    }
}

/// One `[[lights]]` entry. Area lights are emissive geometry: camera and
/// bounce rays see them, they cast shadows, and `gather_emitters` makes them
/// sampled lights.
fn light(
    check: &Check,
    scene: &mut Scene,
    index: usize,
    light: &LightFile,
    solver: Solver,
) -> Result<()> {
    let key = |field: &str| format!("lights[{index}].{field}");
    match light {
        LightFile::Point(p) => scene.lights.push(Light::Point {
            position: check.finite(&key("position"), p.position)?,
            intensity: check.colour(&key("intensity"), p.intensity)?,
        }),
        LightFile::Spot(l) => {
            if !(l.cone_angle > 0.0 && l.cone_angle <= 180.0) {
                return Err(check.error(
                    &key("cone_angle"),
                    format!("expected degrees in (0, 180], found {}", l.cone_angle),
                ));
            }
            if !(l.falloff >= 0.0 && l.falloff <= l.cone_angle) {
                return Err(check.error(
                    &key("falloff"),
                    format!(
                        "expected degrees from 0 to cone_angle ({}), found {}",
                        l.cone_angle, l.falloff
                    ),
                ));
            }
            scene.lights.push(Light::Spot {
                position: check.finite(&key("position"), l.position)?,
                direction: check.direction(&key("direction"), l.direction)?.normalize(),
                intensity: check.colour(&key("intensity"), l.intensity)?,
                cos_end: l.cone_angle.to_radians().cos(),
                cos_start: (l.cone_angle - l.falloff).to_radians().cos(),
            });
        }
        LightFile::Directional(d) => scene.lights.push(Light::Directional {
            direction: check.direction(&key("direction"), d.direction)?,
            irradiance: check.colour(&key("irradiance"), d.irradiance)?,
        }),
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
            let surface = Surface::Sphere {
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
            scene.meshes.push(Mesh {
                name: format!("light {index}"),
                positions: vec![
                    corner,
                    corner + edge1,
                    corner + edge1 + edge2,
                    corner + edge2,
                ],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                materials: vec![material; 2],
                ..Mesh::default()
            });
            check.bounds(&key("corner"), scene.bounds())?;
        }
    }
    Ok(())
}
