//! Embree scenes: a builder that owns its geometry until `commit`, and the
//! committed scene that answers queries from any number of threads.

use std::any::Any;
use std::mem::MaybeUninit;
use std::ptr::NonNull;
use std::sync::Arc;

use super::device::Device;
use super::filter::{self, CutoutData};
use super::instance::Instances;
use super::owned::UserPtr;
use super::query::{self, Coherence, Exact, Query};
use super::sys;
use super::user::{self, UserData};
use crate::accel::cutout::Cutout;
use crate::accel::panics::PanicSlot;
use crate::accel::primitive::{UserPrimitive, padding};
use crate::error::{Error, Result};
use crate::math::{Bounds, Hit, Ray, Ray64, Vec3};

/// Rays a stream call takes (`rtcIntersect1M`): Embree sorts them into
/// packets itself, and 256 records are 20 KB on the stack.
pub const STREAM: usize = 256;

/// Embree's BVH build quality.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    Low,
    #[default]
    Medium,
    High,
}

/// Scene-wide settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneOptions {
    /// `RTC_SCENE_FLAG_ROBUST`: watertight edges, as embreex's default. On by default.
    pub robust: bool,
    pub quality: BuildQuality,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            robust: true,
            quality: BuildQuality::default(),
        }
    }
}

/// An owned `RTCScene`, released on drop.
pub(super) struct SceneHandle(pub(super) NonNull<sys::RTCSceneTy>);

impl Drop for SceneHandle {
    fn drop(&mut self) {
        // SAFETY: the handle came from rtcNewScene and is released once; the device it was
        // created on is held alive next to it (field order in the owners).
        unsafe { sys::rtcReleaseScene(self.0.as_ptr()) };
    }
}

/// An owned `RTCGeometry` that is not attached yet, released on drop.
pub(super) struct GeometryHandle(pub(super) NonNull<sys::RTCGeometryTy>);

impl Drop for GeometryHandle {
    fn drop(&mut self) {
        // SAFETY: the handle came from rtcNewGeometry; attaching took Embree's own
        // reference, so releasing ours here is balanced.
        unsafe { sys::rtcReleaseGeometry(self.0.as_ptr()) };
    }
}

/// Has Embree allocate a buffer of `items.len()` items for `geometry` (padded
/// for its 16-byte loads) and copies `items` into it; false if Embree could
/// not allocate it.
fn fill_buffer<T>(
    geometry: &mut GeometryHandle,
    kind: sys::RTCBufferType,
    format: sys::RTCFormat,
    items: impl ExactSizeIterator<Item = T>,
) -> bool {
    let len = items.len();
    // SAFETY: the geometry is new and unshared; Embree allocates `len` items of the given
    // stride, owned by the geometry, and returns null on failure.
    let raw = unsafe {
        sys::rtcSetNewGeometryBuffer(
            geometry.0.as_ptr(),
            kind,
            0,
            format,
            std::mem::size_of::<T>(),
            len,
        )
    };
    let Some(raw) = NonNull::new(raw.cast::<MaybeUninit<T>>()) else {
        return false;
    };
    // SAFETY: `raw` holds `len` items of `T`, aligned (Embree aligns buffers to 16 bytes,
    // more than the callers' 4-byte arrays need), uninitialised, hence `MaybeUninit`; the
    // geometry that owns the buffer is borrowed exclusively while the slice lives.
    let buffer = unsafe { std::slice::from_raw_parts_mut(raw.as_ptr(), len) };
    for (slot, item) in buffer.iter_mut().zip(items) {
        slot.write(item);
    }
    true
}

/// The primitives of user geometries, kept alive (and at a stable address) for
/// as long as Embree's scene may call back into them.
type UserStore = Vec<UserPtr<dyn Any + Send + Sync>>;

/// A scene being built. Not `Sync`: Embree calls on one object are not thread-safe.
pub struct SceneBuilder {
    // Fields drop in declaration order: Embree's scene is released before the
    // instanced scenes and user primitives it points into, and all before the device.
    pub(super) scene: SceneHandle,
    pub(super) instances: Instances,
    user_data: UserStore,
    pub(super) panics: Arc<PanicSlot>,
    pub(super) device: Device,
}

impl SceneBuilder {
    pub fn new(device: &Device, options: SceneOptions) -> Result<SceneBuilder> {
        // SAFETY: the device handle is valid for the call.
        let raw = unsafe { sys::rtcNewScene(device.raw()) };
        let Some(raw) = NonNull::new(raw) else {
            device.check()?;
            return Err(Error::Embree("rtcNewScene returned no scene".into()));
        };
        let scene = SceneHandle(raw);
        // Every scene lets a query carry a filter: the all-hits query's.
        let flags = super::filter::SCENE_FLAG
            | if options.robust {
                sys::RTCSceneFlags_RTC_SCENE_FLAG_ROBUST
            } else {
                sys::RTCSceneFlags_RTC_SCENE_FLAG_NONE
            };
        let quality = match options.quality {
            BuildQuality::Low => sys::RTCBuildQuality_RTC_BUILD_QUALITY_LOW,
            BuildQuality::Medium => sys::RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM,
            BuildQuality::High => sys::RTCBuildQuality_RTC_BUILD_QUALITY_HIGH,
        };
        // SAFETY: the scene is valid and not yet shared with any thread.
        unsafe { sys::rtcSetSceneFlags(raw.as_ptr(), flags) };
        // SAFETY: as above.
        unsafe { sys::rtcSetSceneBuildQuality(raw.as_ptr(), quality) };
        device.check()?;
        Ok(SceneBuilder {
            scene,
            instances: Instances::default(),
            user_data: Vec::new(),
            panics: Arc::default(),
            device: device.clone(),
        })
    }

    /// Adds a triangle mesh as geometry `geom_id`. The data are copied into
    /// buffers Embree allocates (padded for its 16-byte loads). An empty mesh
    /// attaches nothing: no ray can hit it. With a `cutout`, the geometry's
    /// intersection and occlusion filters skip the hits it cuts away
    /// (`filter::cut_out`); without, it has no filter and pays nothing.
    pub fn add_triangles(
        &mut self,
        geom_id: u32,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        cutout: Option<Cutout>,
    ) -> Result<()> {
        if triangles.is_empty() {
            return Ok(());
        }
        let count = positions.len();
        if let Some(bad) = triangles.iter().flatten().find(|&&i| i as usize >= count) {
            // Embree would read past the vertex buffer: refuse here.
            return Err(Error::Input(format!(
                "geometry {geom_id}: vertex index {bad} out of range (the mesh has {count} vertices)"
            )));
        }
        let mut geometry = self.new_geometry(sys::RTCGeometryType_RTC_GEOMETRY_TYPE_TRIANGLE)?;
        let vertices = fill_buffer(
            &mut geometry,
            sys::RTCBufferType_RTC_BUFFER_TYPE_VERTEX,
            sys::RTCFormat_RTC_FORMAT_FLOAT3,
            positions.iter().map(|p| p.to_array()),
        );
        let indices = fill_buffer(
            &mut geometry,
            sys::RTCBufferType_RTC_BUFFER_TYPE_INDEX,
            sys::RTCFormat_RTC_FORMAT_UINT3,
            triangles.iter().copied(),
        );
        if !(vertices && indices) {
            self.device.check()?;
            return Err(Error::Embree("cannot allocate geometry buffers".into()));
        }
        if let Some(cutout) = cutout {
            let data: UserPtr<dyn Any + Send + Sync> = UserPtr::new(Box::new(CutoutData {
                cutout,
                panics: Arc::clone(&self.panics),
            }));
            let user_ptr = data.as_c_void();
            // Stored before Embree sees the pointer, so it stays alive on every path.
            self.user_data.push(data);
            let g = geometry.0.as_ptr();
            // SAFETY: `g` is a new, unshared triangle geometry; the user pointer is the
            // CutoutData that `self.user_data` owns until after Embree's scene is released
            // (field order); the filters only read it through `&`.
            unsafe { sys::rtcSetGeometryUserData(g, user_ptr) };
            // SAFETY: as above; `cut_out` reads the user pointer as the CutoutData just set.
            unsafe { sys::rtcSetGeometryIntersectFilterFunction(g, Some(filter::cut_out)) };
            // SAFETY: as above.
            unsafe { sys::rtcSetGeometryOccludedFilterFunction(g, Some(filter::cut_out)) };
        }
        self.attach(geometry, geom_id)
    }

    /// Adds user primitives as geometry `geom_id`; primID i is `prims[i]`. The
    /// scene takes ownership, so the primitives outlive every callback.
    pub fn add_user<T: UserPrimitive>(&mut self, geom_id: u32, prims: Vec<T>) -> Result<()> {
        if prims.is_empty() {
            return Ok(());
        }
        let count = u32::try_from(prims.len())
            .map_err(|_| Error::Input(format!("geometry {geom_id}: too many primitives")))?;
        // A panicking `bounds` is reported as the bounds callback's would be.
        let pad = self.panics.guard(0.0, || {
            padding(prims.iter().map(T::bounds).filter(|b| !b.is_empty()))
        });
        let data: UserPtr<dyn Any + Send + Sync> = UserPtr::new(Box::new(UserData {
            pad: if pad.is_finite() { pad } else { 0.0 },
            prims: prims.into_boxed_slice(),
            panics: Arc::clone(&self.panics),
        }));
        let user_ptr = data.as_c_void();
        // Stored before Embree sees the pointer, so it stays alive on every path.
        self.user_data.push(data);
        let geometry = self.new_geometry(sys::RTCGeometryType_RTC_GEOMETRY_TYPE_USER)?;
        let g = geometry.0.as_ptr();
        // SAFETY: `g` is a new, unshared user geometry.
        unsafe { sys::rtcSetGeometryUserPrimitiveCount(g, count) };
        // SAFETY: the user pointer is the UserData<T> that `self.user_data` owns until after
        // Embree's scene is released (field order); callbacks only read it through `&`.
        unsafe { sys::rtcSetGeometryUserData(g, user_ptr) };
        // SAFETY: the callbacks are monomorphised for the T of the user data just set.
        unsafe {
            sys::rtcSetGeometryBoundsFunction(
                g,
                Some(user::bounds_callback::<T>),
                std::ptr::null_mut(),
            )
        };
        // SAFETY: as for the bounds function.
        unsafe { sys::rtcSetGeometryIntersectFunction(g, Some(user::intersect_callback::<T>)) };
        // SAFETY: as for the bounds function.
        unsafe { sys::rtcSetGeometryOccludedFunction(g, Some(user::occluded_callback::<T>)) };
        self.attach(geometry, geom_id)
    }

    /// Commits a filled geometry, visible to every ray, and attaches it as
    /// `geom_id`; Embree's scene takes its own reference, ours is dropped.
    pub(super) fn attach(&mut self, geometry: GeometryHandle, geom_id: u32) -> Result<()> {
        let g = geometry.0.as_ptr();
        // SAFETY: `g` is a valid geometry not yet attached, so not shared with any thread.
        unsafe { sys::rtcSetGeometryMask(g, u32::MAX) };
        // SAFETY: as above; its buffers and callbacks are all set.
        unsafe { sys::rtcCommitGeometry(g) };
        // SAFETY: the scene is valid and owned by `self`, which no other thread can reach.
        unsafe { sys::rtcAttachGeometryByID(self.scene.0.as_ptr(), g, geom_id) };
        drop(geometry);
        self.device.check()
    }

    /// A new geometry of `kind`, released on drop unless attached.
    pub(super) fn new_geometry(&self, kind: sys::RTCGeometryType) -> Result<GeometryHandle> {
        // SAFETY: the device is valid; a null result is checked below.
        let raw = unsafe { sys::rtcNewGeometry(self.device.raw(), kind) };
        match NonNull::new(raw) {
            Some(raw) => Ok(GeometryHandle(raw)),
            None => {
                self.device.check()?;
                Err(Error::Embree("rtcNewGeometry returned no geometry".into()))
            }
        }
    }

    /// Builds the BVH. Queries exist only on the result, so none can run on an
    /// uncommitted or half-edited scene.
    pub fn commit(self) -> Result<CommittedScene> {
        // SAFETY: the scene is valid and owned by `self`; no query can run during the build.
        unsafe { sys::rtcCommitScene(self.scene.0.as_ptr()) };
        self.device.check()?;
        let committed = CommittedScene {
            scene: self.scene,
            instances: self.instances,
            _user_data: self.user_data,
            panics: self.panics,
            device: self.device,
        };
        // A panic in a bounds callback during the build.
        committed.check()?;
        Ok(committed)
    }
}

/// A committed, immutable scene. Queries take `&self` and may run on many threads.
pub struct CommittedScene {
    // Drop order as in SceneBuilder: Embree's scene, then the instanced scenes
    // and the user primitives, then the device.
    pub(super) scene: SceneHandle,
    pub(super) instances: Instances,
    _user_data: UserStore,
    panics: Arc<PanicSlot>,
    device: Device,
}

// SAFETY: the scene is owned uniquely and never mutated after commit; Embree documents
// rtcIntersect*/rtcOccluded* on a committed scene as thread-safe; the user data, owned
// through `UserPtr` like a Box, are `Send + Sync`.
unsafe impl Send for CommittedScene {}
// SAFETY: as for Send; `&CommittedScene` only permits those queries and bounds reads.
unsafe impl Sync for CommittedScene {}

impl CommittedScene {
    /// Embree's scene, for the queries of sibling modules (`filter`).
    pub(super) fn raw(&self) -> sys::RTCScene {
        self.scene.0.as_ptr()
    }

    /// The nearest hit in (tnear, tfar), or `Hit::MISS`.
    pub fn intersect(&self, ray: &Ray) -> Hit {
        let mut record = query::rayhit_record(ray);
        self.intersect_record(&mut record, Coherence::Incoherent, Exact::None);
        self.instances.to_world(query::hit_from_record(&record))
    }

    /// The nearest hit of `exact`'s rounding (over [0, inf)), with the user
    /// primitives solving for `exact` itself (see `Ray64`).
    pub fn intersect_exact(&self, exact: &Ray64) -> Hit {
        let mut record = query::rayhit_record(&exact.rounded());
        self.intersect_record(&mut record, Coherence::Incoherent, Exact::One(exact));
        self.instances.to_world(query::hit_from_record(&record))
    }

    /// Whether anything blocks the ray in (tnear, tfar).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let mut record = query::ray_record(ray);
        #[cfg(embree3)]
        {
            let mut context = query::context(Coherence::Incoherent);
            // SAFETY: scene committed; `context` and `record` are live, initialised and
            // exclusively borrowed for the call.
            unsafe { sys::rtcOccluded1(self.scene.0.as_ptr(), &mut context, &mut record) };
        }
        #[cfg(embree4)]
        {
            let mut context = query::context();
            let mut args = query::occluded_arguments(Coherence::Incoherent, &mut context);
            // SAFETY: as above; `args` points at `context`, which outlives the call.
            unsafe { sys::rtcOccluded1(self.scene.0.as_ptr(), &mut record, &mut args) };
        }
        query::occluded_from_record(&record)
    }

    /// Traces many rays. On Embree 3 this goes through the stream API
    /// (`rtcIntersect1M`), on Embree 4 (no stream API) through single-ray calls.
    /// Reports any error Embree raised during the batch.
    pub fn intersect_batch(&self, rays: &[Ray], hits: &mut [Hit], coherent: bool) -> Result<()> {
        assert_eq!(rays.len(), hits.len(), "one hit record per ray");
        let coherence = if coherent {
            Coherence::Coherent
        } else {
            Coherence::Incoherent
        };
        for (rays, hits) in rays.chunks(STREAM).zip(hits.chunks_mut(STREAM)) {
            self.intersect_stream(rays.iter().copied(), hits, coherence, Exact::None);
        }
        self.check()
    }

    /// `intersect_exact` of many neighbouring rays (a tile's camera rays),
    /// through the stream API on Embree 3 as one coherent stream: each
    /// record's `id` is its index in the stream, by which the intersect
    /// callback finds its f64 ray. The hits are `intersect_exact`'s bits,
    /// except where two primitives are hit at the same t, which a packet
    /// may break otherwise than one ray (tests.rs,
    /// `streams_answer_as_single_rays`): callers that need the same hits
    /// every time give the same rays in the same order (`render::batch`).
    pub fn intersect_exact_batch(&self, rays: &[Ray64], hits: &mut [Hit]) {
        assert_eq!(rays.len(), hits.len(), "one hit record per ray");
        for (rays, hits) in rays.chunks(STREAM).zip(hits.chunks_mut(STREAM)) {
            let rounded = rays.iter().map(Ray64::rounded);
            self.intersect_stream(rounded, hits, Coherence::Coherent, Exact::Each(rays));
        }
    }

    /// One stream of at most `STREAM` rays.
    fn intersect_stream(
        &self,
        rays: impl ExactSizeIterator<Item = Ray>,
        hits: &mut [Hit],
        coherence: Coherence,
        exact: Exact<'_>,
    ) {
        let mut records = [sys::RTCRayHit::default(); STREAM];
        let records = &mut records[..rays.len()];
        for (id, (record, ray)) in records.iter_mut().zip(rays).enumerate() {
            *record = query::rayhit_record(&ray);
            record.ray.id = id as u32;
        }
        self.intersect_records(records, coherence, exact);
        for (hit, record) in hits.iter_mut().zip(records.iter()) {
            *hit = self.instances.to_world(query::hit_from_record(record));
        }
    }

    #[cfg(embree3)]
    fn intersect_records(
        &self,
        records: &mut [sys::RTCRayHit],
        coherence: Coherence,
        exact: Exact<'_>,
    ) {
        let mut query = Query {
            context: query::context(coherence),
            exact,
        };
        let whole: *mut Query = &mut query;
        // SAFETY: scene committed; `records` is a live slice of initialised RTCRayHit with
        // the stride given; the context, initialised, is the first field of `query`, whose
        // pointer (made from the whole struct) outlives the call; all exclusively borrowed.
        unsafe {
            sys::rtcIntersect1M(
                self.scene.0.as_ptr(),
                whole.cast(),
                records.as_mut_ptr(),
                records.len() as u32,
                std::mem::size_of::<sys::RTCRayHit>(),
            )
        };
    }

    #[cfg(embree4)]
    fn intersect_records(
        &self,
        records: &mut [sys::RTCRayHit],
        coherence: Coherence,
        exact: Exact<'_>,
    ) {
        for record in records {
            self.intersect_record(record, coherence, exact);
        }
    }

    fn intersect_record(
        &self,
        record: &mut sys::RTCRayHit,
        coherence: Coherence,
        exact: Exact<'_>,
    ) {
        #[cfg(embree3)]
        {
            let mut query = Query {
                context: query::context(coherence),
                exact,
            };
            let whole: *mut Query = &mut query;
            // SAFETY: scene committed; the context, initialised, is the first field of
            // `query`, whose pointer (made from the whole struct) outlives the call, as does
            // `record`; both are exclusively borrowed for the call.
            unsafe { sys::rtcIntersect1(self.scene.0.as_ptr(), whole.cast(), record) };
        }
        #[cfg(embree4)]
        {
            let mut query = Query {
                context: query::context(),
                exact,
            };
            let mut args = query::intersect_arguments(coherence, &mut query.context);
            let whole: *mut Query = &mut query;
            args.context = whole.cast();
            // SAFETY: as above; `args` points at the context, the first field of `query`,
            // made from the whole struct; both outlive the call.
            unsafe { sys::rtcIntersect1(self.scene.0.as_ptr(), record, &mut args) };
        }
    }

    /// The bounds of everything in the scene (empty for an empty scene).
    pub fn bounds(&self) -> Bounds {
        let mut b = sys::RTCBounds::default();
        // SAFETY: scene committed; `b` is a live, 16-byte-aligned RTCBounds.
        unsafe { sys::rtcGetSceneBounds(self.scene.0.as_ptr(), &mut b) };
        Bounds {
            min: Vec3::new(b.lower_x, b.lower_y, b.lower_z),
            max: Vec3::new(b.upper_x, b.upper_y, b.upper_z),
        }
    }

    /// The slot that records panics caught in this scene's callbacks.
    pub(crate) fn panics(&self) -> &PanicSlot {
        &self.panics
    }

    /// Errors Embree reported, and panics caught in user-geometry callbacks,
    /// since the last check (renders call this once at the end).
    pub fn check(&self) -> Result<()> {
        self.panics.check("a user-geometry callback")?;
        self.device.check()
    }

    pub fn device(&self) -> &Device {
        &self.device
    }

    /// A raw query on a caller-owned record, for the layout guard tests.
    #[cfg(test)]
    pub(super) fn intersect_raw(&self, record: &mut sys::RTCRayHit) {
        self.intersect_record(record, Coherence::Incoherent, Exact::None);
    }
}
