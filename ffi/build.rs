//! Finds Embree's header, generates the bindings with bindgen, links the
//! matching library and tells dependents what it found. See README.md.

use std::env;
use std::path::{Path, PathBuf};
use std::process::exit;

const INSTALL_HINT: &str = "on Debian or Ubuntu run `make setup` or \
`apt-get install libembree-dev libclang-dev`; for a custom Embree set EMBREE_DIR \
to a folder holding include/ and lib/";

struct Found {
    include_dir: PathBuf,
    lib_dir: Option<PathBuf>,
    major: u32,
}

fn fail(message: &str) -> ! {
    eprintln!("\nsturmray build error: {message}\n  ({INSTALL_HINT})\n");
    exit(1)
}

/// The include dir holding `embree4/rtcore.h` or else `embree3/rtcore.h`.
fn probe(include_dir: &Path) -> Option<u32> {
    [4, 3].into_iter().find(|major| {
        include_dir
            .join(format!("embree{major}/rtcore.h"))
            .is_file()
    })
}

fn find_embree() -> Found {
    if let Some(dir) = env::var_os("EMBREE_DIR") {
        let dir = PathBuf::from(dir);
        let include_dir = dir.join("include");
        let Some(major) = probe(&include_dir) else {
            fail(&format!(
                "EMBREE_DIR={} has no include/embree4/rtcore.h or include/embree3/rtcore.h",
                dir.display()
            ));
        };
        return Found {
            include_dir,
            lib_dir: Some(dir.join("lib")),
            major,
        };
    }
    let system = ["/usr/local/include", "/usr/include"];
    for dir in system {
        if let Some(major) = probe(Path::new(dir)) {
            return Found {
                include_dir: PathBuf::from(dir),
                lib_dir: None,
                major,
            };
        }
    }
    fail(
        "Embree's header (embree4/rtcore.h or embree3/rtcore.h) was not found in /usr/local/include or /usr/include",
    )
}

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=embree.h");
    for var in ["EMBREE_DIR", "LIBCLANG_PATH", "BINDGEN_EXTRA_CLANG_ARGS"] {
        println!("cargo::rerun-if-env-changed={var}");
    }

    let found = find_embree();
    println!("cargo::metadata=major={}", found.major);
    if let Some(lib_dir) = &found.lib_dir {
        println!("cargo::rustc-link-search=native={}", lib_dir.display());
        // A link argument does not reach the final binary from a dependency,
        // so the rpath is the dependent's to add (sturmray's build.rs does).
        println!("cargo::metadata=lib_dir={}", lib_dir.display());
    }
    println!("cargo::rustc-link-lib=dylib=embree{}", found.major);

    let mut builder = bindgen::Builder::default()
        .header("embree.h")
        .clang_arg(format!("-I{}", found.include_dir.display()))
        .allowlist_function("rtc.*")
        .allowlist_type("RTC.*")
        .allowlist_var("RTC.*")
        .default_enum_style(bindgen::EnumVariation::Consts)
        .derive_default(true)
        .layout_tests(true)
        .generate_comments(false);
    if found.major == 4 {
        builder = builder.clang_arg("-DSTURMRAY_EMBREE4");
    }
    // bindgen panics when it cannot load libclang; turn that into a hint.
    let generated =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    let bindings = match generated {
        Ok(Ok(bindings)) => bindings,
        Ok(Err(err)) => fail(&format!("bindgen could not read Embree's header: {err}")),
        Err(_) => fail("bindgen could not load libclang"),
    };
    let text = bindings.to_string();
    // Embree 4.3+ built with instance arrays (the default) adds `instPrimID` to
    // RTCHit and the query context; the Rust side initialises it only if the
    // header has it.
    println!(
        "cargo::metadata=inst_prim_id={}",
        text.contains("instPrimID")
    );
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(err) = std::fs::write(out.join("embree_sys.rs"), text) {
        fail(&format!("cannot write the bindings: {err}"));
    }
}
