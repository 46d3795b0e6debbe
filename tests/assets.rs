//! Models as modelling programs export them (issue 16): OBJ files whose
//! library or materials are missing, vertex normals, texture coordinates and
//! textures, PLY files.

mod common;

use common::{scratch, sturmray, write};

#[test]
fn a_blender_export_without_its_library_renders_grey_with_warnings() {
    let dir = scratch("blender");
    write(
        &dir,
        "b.obj",
        "mtllib b.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl None\nf 1 2 3 4\n",
    );
    let out = sturmray(&dir, &["render", "b.obj", "-o", "b.exr", "--width", "16"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("b.obj:1: material library"), "{err}");
    assert!(err.contains("b.mtl not found"), "{err}");
    assert!(err.contains("b.obj:6: material `None` is not defined"), "{err}");
    assert!(dir.join("b.exr").is_file());
}
