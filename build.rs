//! Turns what `embree-sys` found (its `links = "embree"` metadata) into the
//! cfgs `accel::embree` compiles against, and gives the binaries, tests and
//! benches the rpath of a custom Embree. See ffi/README.md.

use std::env;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(embree3)");
    println!("cargo::rustc-check-cfg=cfg(embree4)");
    println!("cargo::rustc-check-cfg=cfg(embree_inst_prim_id)");
    for var in [
        "DEP_EMBREE_MAJOR",
        "DEP_EMBREE_INST_PRIM_ID",
        "DEP_EMBREE_LIB_DIR",
    ] {
        println!("cargo::rerun-if-env-changed={var}");
    }

    // embree-sys always sets the major version; its build fails before ours
    // runs if it found no Embree.
    let major = env::var("DEP_EMBREE_MAJOR").expect("embree-sys exports DEP_EMBREE_MAJOR");
    println!("cargo::rustc-cfg=embree{major}");
    if env::var("DEP_EMBREE_INST_PRIM_ID").as_deref() == Ok("true") {
        println!("cargo::rustc-cfg=embree_inst_prim_id");
    }
    if let Ok(lib_dir) = env::var("DEP_EMBREE_LIB_DIR") {
        // The binary and the tests find a custom Embree without LD_LIBRARY_PATH.
        println!("cargo::rustc-link-arg=-Wl,-rpath,{lib_dir}");
    }
}
