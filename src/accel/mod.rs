//! Acceleration structures: the BVH a scene is traced through.

#[allow(unsafe_code)]
pub mod embree;
