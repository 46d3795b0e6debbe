//! The serde schema of the TOML scene format (see scenes/README.md): what each
//! table may hold, as read, before any value is checked. Every table denies
//! unknown keys, so a typo is an error that names the line and suggests the
//! key meant.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::Deserialize;

use crate::shading::MaterialKind;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub background: Option<[f32; 3]>,
    pub environment: Option<EnvironmentFile>,
    /// Names usable in `expr` of algebraic objects.
    #[serde(default)]
    pub constants: BTreeMap<String, f64>,
    pub camera: Option<CameraFile>,
    #[serde(default)]
    pub render: RenderFile,
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialFile>,
    /// Geometry declared once, placed by `type = "instance"` objects.
    #[serde(default)]
    pub prototypes: BTreeMap<String, PrototypeFile>,
    #[serde(default)]
    pub objects: Vec<ObjectFile>,
    #[serde(default)]
    pub lights: Vec<LightFile>,
}

/// `[environment]`: an equirectangular map (`file`) or a constant `radiance`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvironmentFile {
    pub file: Option<PathBuf>,
    pub radiance: Option<[f32; 3]>,
    pub scale: Option<f32>,
    /// Degrees about +Y.
    pub rotation: Option<f32>,
}

/// `[prototypes.NAME]`: the objects an instance places, in their own space.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PrototypeFile {
    pub objects: Vec<ObjectFile>,
}

/// `type = "instance"`: a prototype placed by its own transform, in its own
/// material if it names one (replacing all of the prototype's).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InstanceFile {
    pub prototype: String,
    pub material: Option<String>,
    #[serde(default)]
    pub transform: TransformFile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    pub eye: [f32; 3],
    pub look_at: [f32; 3],
    #[serde(default = "y_up")]
    pub up: [f32; 3],
    /// Required by a perspective camera; an orthographic one takes `view_width`.
    pub fov: Option<f32>,
    pub width: u32,
    pub height: u32,
    /// `perspective` (the default) or `orthographic`.
    #[serde(rename = "type", default)]
    pub kind: ProjectionFile,
    /// Which side `fov` spans: `y` (the height, the default) or `x`.
    #[serde(default)]
    pub fov_axis: FovAxisFile,
    pub view_width: Option<f32>,
    /// The lens radius (0: a pinhole) and the distance in focus.
    pub aperture: Option<f32>,
    pub focus_distance: Option<f32>,
    /// A camera path: where the camera is at some frames (`render --frame K`).
    #[serde(default)]
    pub keys: Vec<CameraKeyFile>,
}

#[derive(Deserialize, Default, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
pub(super) enum ProjectionFile {
    #[default]
    Perspective,
    Orthographic,
}

#[derive(Deserialize, Default, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
pub(super) enum FovAxisFile {
    X,
    #[default]
    Y,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraKeyFile {
    pub frame: u32,
    pub eye: [f32; 3],
    pub look_at: [f32; 3],
}

fn y_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RenderFile {
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub seed: Option<u64>,
    pub min_weight: Option<f32>,
    /// "box", "tent", "gaussian" or "mitchell".
    pub filter: Option<String>,
    pub sampler: Option<SamplerFile>,
    pub integrator: Option<IntegratorFile>,
    /// The root finder for analytic surfaces, by its stable name.
    pub method: Option<String>,
    pub tolerance: Option<f64>,
    pub adaptive: Option<AdaptiveFile>,
    pub photons: Option<PhotonsFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AdaptiveFile {
    pub max_spp: u32,
    pub threshold: f32,
}

/// `photons = { count, radius }`: the caustic photon pass.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PhotonsFile {
    pub count: Option<u32>,
    pub radius: Option<f32>,
}

/// `sampler`: an unknown name is serde's "unknown variant", with a suggestion.
#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum SamplerFile {
    Sobol,
    Independent,
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum IntegratorFile {
    Whitted,
    Path,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialFile {
    #[serde(rename = "type")]
    pub kind: MaterialKind,
    pub albedo: Option<Param<[f32; 3], AlbedoTable>>,
    /// A colour (plastic's Ks), or a classic material's highlight strength.
    pub specular: Option<Param<SpecularFile>>,
    pub shininess: Option<f32>,
    pub roughness: Option<Param<f32>>,
    pub ior: Option<f32>,
    pub radiance: Option<Param<[f32; 3]>>,
    /// The classic material's finish (POV-Ray's names); other types refuse them.
    pub diffuse: Option<f32>,
    pub ambient: Option<f32>,
    pub phong: Option<f32>,
    pub phong_size: Option<f32>,
    pub brilliance: Option<f32>,
    pub reflection: Option<f32>,
    pub reflection_max: Option<f32>,
    pub fresnel: Option<bool>,
    /// A classic material's amount, or a metal's metalness map.
    pub metallic: Option<Param<MetallicFile>>,
    pub transmit: Option<f32>,
}

/// A material parameter: its plain value (a number, a colour), or a table
/// (`{ texture = "wood.png" }`, and for the albedo a checker too). Read by
/// hand rather than as an untagged enum, whose one message for every
/// mistake would hide serde's own (a misspelt key with its suggestion, a
/// colour of two values), each at its line.
pub(super) enum Param<T, M = TextureFile> {
    Value(T),
    Table(M),
}

/// What a parameter's form is called in messages.
pub(super) trait Described {
    const WHAT: &'static str;
}

impl Described for f32 {
    const WHAT: &'static str = "a number";
}

impl Described for [f32; 3] {
    const WHAT: &'static str = "a colour [r, g, b]";
}

impl Described for TextureFile {
    const WHAT: &'static str = "{ texture = \"file.png\" }";
}

impl Described for AlbedoTable {
    const WHAT: &'static str =
        "{ checker = [[r, g, b], [r, g, b]], scale = s } or { texture = \"file.png\" }";
}

impl Described for SpecularFile {
    const WHAT: &'static str = "a colour [r, g, b] or a number";
}

impl Described for MetallicFile {
    const WHAT: &'static str = "true, false or a number from 0 to 1";
}

impl<'de, T, M> Deserialize<'de> for Param<T, M>
where
    T: Deserialize<'de> + Described,
    M: Deserialize<'de> + Described,
{
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::{self, IntoDeserializer, value};
        struct Visit<T, M>(std::marker::PhantomData<(T, M)>);
        impl<'de, T, M> de::Visitor<'de> for Visit<T, M>
        where
            T: Deserialize<'de> + Described,
            M: Deserialize<'de> + Described,
        {
            type Value = Param<T, M>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "{} or {}", T::WHAT, M::WHAT)
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<Self::Value, E> {
                T::deserialize(v.into_deserializer()).map(Param::Value)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                T::deserialize(v.into_deserializer()).map(Param::Value)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                T::deserialize(v.into_deserializer()).map(Param::Value)
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                T::deserialize(v.into_deserializer()).map(Param::Value)
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                T::deserialize(value::SeqAccessDeserializer::new(seq)).map(Param::Value)
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                M::deserialize(value::MapAccessDeserializer::new(map)).map(Param::Table)
            }
        }
        d.deserialize_any(Visit(std::marker::PhantomData))
    }
}

/// `specular`: a colour for plastic, a number for a classic material's
/// Blinn highlight (which the loader tells apart by the material's type).
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged, expecting = "a colour [r, g, b] or a number")]
pub(super) enum SpecularFile {
    Colour([f32; 3]),
    Amount(f32),
}

/// `{ texture = "wood.png" }`: an image (relative to the scene file) a
/// parameter follows in a mesh's texture coordinates, as an MTL map does.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TextureFile {
    pub texture: String,
}

/// The albedo's table: POV-Ray's checker (`{ checker = [A, B], scale = s }`,
/// cubes of side s, default 1, in world space, A at the origin's cube) or
/// an image (`{ texture = "wood.png" }`); the loader takes one or the other.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AlbedoTable {
    pub checker: Option<[[f32; 3]; 2]>,
    pub scale: Option<f64>,
    pub texture: Option<String>,
}

/// `metallic = true` (all of it, as POV-Ray's bare `metallic`) or an amount.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged, expecting = "true, false or a number from 0 to 1")]
pub(super) enum MetallicFile {
    On(bool),
    Amount(f32),
}

/// Declares the analytic shape types once. From the one list come the
/// `[[objects]]` types (serde's internally tagged enum, beside `mesh`),
/// [`ShapeKind`], which `shapes::surface` matches on for each type's
/// parameters and surface, and the mapping between the two. A macro because
/// serde's other ways to share the `type` key between a fixed variant and a
/// list (`flatten`, `untagged` variants) lose `deny_unknown_fields` or its
/// "unknown field"/"unknown variant" messages, which scene files rely on.
macro_rules! objects {
    ($($(#[$doc:meta])* $shape:ident,)+) => {
        #[derive(Deserialize)]
        #[serde(tag = "type", rename_all = "snake_case")]
        pub(super) enum ObjectFile {
            Mesh(MeshFile),
            Instance(InstanceFile),
            $($shape(ShapeFile),)+
        }

        /// The analytic object types, as spelled in `[[objects]] type = "..."`.
        #[derive(Clone, Copy, Debug)]
        pub(super) enum ShapeKind {
            $($(#[$doc])* $shape,)+
        }

        impl ObjectFile {
            /// Which kind of object this is, with its parameters.
            pub fn view(&self) -> Object<'_> {
                match self {
                    ObjectFile::Mesh(mesh) => Object::Mesh(mesh),
                    ObjectFile::Instance(instance) => Object::Instance(instance),
                    $(ObjectFile::$shape(shape) => Object::Shape(ShapeKind::$shape, shape),)+
                }
            }
        }
    };
}

objects! {
    Sphere,
    /// A general quadric xᵀAx + b·x + c, which needs a clip box.
    Quadric,
    Ellipsoid,
    Cylinder,
    Cone,
    Hyperboloid1,
    Hyperboloid2,
    Paraboloid,
    HyperbolicParaboloid,
    Torus,
    /// A polynomial written as an expression, which needs a clip box.
    Algebraic,
    /// The half-space n·p < distance (POV-Ray's `plane`).
    Plane,
    /// A solid box between two corners.
    Box,
    /// A flat ring: a surface with no inside.
    Disc,
    /// A CSG operation over its `children`.
    Csg,
}

/// An object of the file, by what the loader builds from it.
pub(super) enum Object<'a> {
    Mesh(&'a MeshFile),
    Instance(&'a InstanceFile),
    Shape(ShapeKind, &'a ShapeFile),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshFile {
    pub file: PathBuf,
    pub material: Option<String>,
    #[serde(default)]
    pub transform: TransformFile,
}

/// Every parameter any analytic type takes; `shapes::surface` checks that
/// each type gets the ones it needs and no others.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShapeFile {
    pub material: Option<String>,
    #[serde(default)]
    pub transform: TransformFile,
    pub clip: Option<ClipFile>,
    pub radius: Option<f64>,
    pub radii: Option<Vec<f64>>,
    pub major: Option<f64>,
    pub minor: Option<f64>,
    pub a: Option<[[f64; 3]; 3]>,
    pub b: Option<[f64; 3]>,
    pub c: Option<f64>,
    pub expr: Option<String>,
    /// In a CSG tree: the object's inside is its outside.
    pub inverse: Option<bool>,
    /// "union", "intersection", "difference" or "merge".
    pub op: Option<String>,
    /// A CSG operation's objects, as inline tables.
    pub children: Option<Vec<ObjectFile>>,
    pub normal: Option<[f64; 3]>,
    pub distance: Option<f64>,
    pub min: Option<[f64; 3]>,
    pub max: Option<[f64; 3]>,
    pub center: Option<[f64; 3]>,
    pub hole: Option<f64>,
    pub base: Option<[f64; 3]>,
    pub cap: Option<[f64; 3]>,
    pub cap_radius: Option<f64>,
    /// Whether a cylinder or cone is closed by flat caps.
    pub caps: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ClipFile {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct TransformFile {
    pub translate: Option<[f64; 3]>,
    /// Degrees about x, then y, then z.
    pub rotate: Option<[f64; 3]>,
    pub scale: Option<ScaleFile>,
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum ScaleFile {
    Uniform(f64),
    Axes([f64; 3]),
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub(super) enum LightFile {
    Point(PointFile),
    Spot(SpotFile),
    Directional(DirectionalFile),
    Sphere(SphereLightFile),
    Quad(QuadLightFile),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereLightFile {
    pub center: [f32; 3],
    pub radius: f32,
    pub radiance: [f32; 3],
}

/// pbrt-v4's spot light: `cone_angle` (degrees from the axis) bounds the
/// light; it fades over the last `falloff` degrees of it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpotFile {
    pub position: [f32; 3],
    pub direction: [f32; 3],
    pub intensity: [f32; 3],
    pub cone_angle: f32,
    #[serde(default)]
    pub falloff: f32,
}

/// A parallelogram corner + s·edge1 + t·edge2, emitting towards edge1 × edge2.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct QuadLightFile {
    pub corner: [f32; 3],
    pub edge1: [f32; 3],
    pub edge2: [f32; 3],
    pub radiance: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PointFile {
    pub position: [f32; 3],
    pub intensity: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DirectionalFile {
    pub direction: [f32; 3],
    pub irradiance: [f32; 3],
}
