//! Hostile files and file systems: sturmray never writes over a file it
//! reads or another of its outputs, never leaves a torn output (full disk,
//! second Ctrl-C), trusts no film state, reads no endless input and takes a
//! closed stdout calmly.

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{SQUARE, Scratch, interrupt, plane_scene, scratch, sturmray, write};
use sturmray::io::state::{StateHeader, read_state, write_state};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `square.obj` and `s.toml` (the plane scene) in a fresh folder.
fn plane(name: &str) -> Scratch {
    let dir = scratch(name);
    write(&dir, "square.obj", SQUARE);
    write(&dir, "s.toml", &plane_scene(""));
    dir
}

fn ok(dir: &Path, args: &[&str]) {
    let out = sturmray(dir, args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
}

/// Runs `args` and checks the exit code is 2 with every `needle` in the
/// message.
fn refused(dir: &Path, args: &[&str], needles: &[&str]) -> String {
    let out = sturmray(dir, args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err
}

/// Every file in `dir` with its bytes, sorted by name.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect();
    files.sort();
    files
}

/// A version 1.0 .npy header for float32 rays of `shape`, padded as NumPy pads.
fn npy_header(shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape}, }}");
    let mut header = dict.into_bytes();
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(b' ');
    }
    header.push(b'\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(&header);
    bytes
}

/// A (N, 6) float32 .npy of rays straight down at the square.
fn rays_npy(n: usize) -> Vec<u8> {
    let mut bytes = npy_header(&format!("({n}, 6)"));
    for i in 0..n {
        let x = i as f32 / n as f32 - 0.5;
        for v in [x, 0.0, 3.0, 0.0, 0.0, -1.0f32] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

/// The names in a folder, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn no_output_replaces_an_input_or_another_output() {
    let dir = plane("collide");
    write(&dir, "img.png", "an image the user keeps");
    write(&dir, "p.state", "a state the user keeps");
    std::fs::write(dir.join("r.npy"), rays_npy(4)).unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    std::os::unix::fs::symlink("s.toml", dir.join("link.exr")).unwrap();
    std::fs::hard_link(dir.join("s.toml"), dir.join("hard.exr")).unwrap();
    write(&dir, "lib.mtl", "newmtl red\nKd 1 0 0\n");
    write(
        &dir,
        "lib.obj",
        &format!("mtllib lib.mtl\nusemtl red\n{SQUARE}"),
    );
    let before = snapshot(&dir);
    let cases: &[(&[&str], &[&str])] = &[
        // The preview of img.png is img.png itself.
        (
            &["render", "s.toml", "-o", "img.png"],
            &["the image img.png", "its PNG preview img.png"],
        ),
        (
            &["render", "s.toml", "--tile", "0/2", "-o", "p.state"],
            &["the image p.state", "its film state p.state"],
        ),
        (
            &["render", "s.toml", "-o", "a.exr", "--stats", "a.exr"],
            &["--stats a.exr", "the image a.exr"],
        ),
        (
            &["render", "s.toml", "-o", "a.exr", "--stats", "a.png"],
            &["--stats a.png", "its PNG preview a.png"],
        ),
        (
            &[
                "render",
                "s.toml",
                "-o",
                "a.exr",
                "--stats",
                "sub/../a.state",
            ],
            &["--stats sub/../a.state", "its film state a.state"],
        ),
        (
            &["render", "s.toml", "-o", "s.toml"],
            &["the image s.toml", "the scene s.toml"],
        ),
        (
            &["render", "s.toml", "-o", "./sub/../s.toml"],
            &["the image ./sub/../s.toml", "the scene s.toml"],
        ),
        (
            &["render", "s.toml", "-o", "link.exr"],
            &["the image link.exr", "the scene s.toml"],
        ),
        (
            &["render", "s.toml", "-o", "hard.exr"],
            &["the image hard.exr", "the scene s.toml"],
        ),
        (
            &["render", "square.obj", "-o", "square.obj"],
            &["the image square.obj", "the scene square.obj"],
        ),
        (
            &[
                "render",
                "square.obj",
                "-o",
                "a.exr",
                "--stats",
                "square.obj",
            ],
            &["--stats square.obj", "the scene square.obj"],
        ),
        // The files a scene loads are inputs too: its meshes and their libraries.
        (
            &["render", "s.toml", "-o", "square.obj"],
            &["the image square.obj", "the scene's file square.obj"],
        ),
        (
            &["render", "lib.obj", "-o", "a.exr", "--stats", "lib.mtl"],
            &["--stats lib.mtl", "the scene's file lib.mtl"],
        ),
        (
            &[
                "trace",
                "s.toml",
                "--rays",
                "r.npy",
                "--out",
                "./square.obj",
            ],
            &["--out ./square.obj", "the scene's file square.obj"],
        ),
        (
            &["trace", "s.toml", "--rays", "r.npy", "--out", "r.npy"],
            &["--out r.npy", "--rays r.npy"],
        ),
        (
            &[
                "trace",
                "s.toml",
                "--rays",
                "r.npy",
                "--out",
                "sub/../s.toml",
            ],
            &["--out sub/../s.toml", "the scene s.toml"],
        ),
        (
            &["bench", "--quick", "--scene", "s.toml", "--json", "s.toml"],
            &["--json s.toml", "a bench scene's file s.toml"],
        ),
        (
            &[
                "bench",
                "--quick",
                "--scene",
                "s.toml",
                "--json",
                "square.obj",
            ],
            &["--json square.obj", "a bench scene's file square.obj"],
        ),
    ];
    for (args, needles) in cases {
        refused(&dir, args, needles);
        assert!(snapshot(&dir) == before, "{args:?} changed a file");
    }

    // The studies read the repository's scenes: bench's standard set and
    // accuracy's; refused before any work, so the repository is untouched.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (args, needles) in [
        (
            &["bench", "--quick", "--json", "scenes/knot.toml"][..],
            &[
                "--json scenes/knot.toml",
                "a bench scene's file scenes/knot.toml",
            ][..],
        ),
        (
            &["accuracy", "--quick", "--plot", "scenes/gallery/tori.toml"],
            &["--plot", "a study scene's file ./scenes/gallery/tori.toml"],
        ),
    ] {
        refused(repo, args, needles);
    }

    // merge: the output or its preview over a part or a part's state.
    ok(&dir, &["render", "s.toml", "--tile", "0/2", "-o", "t0.exr"]);
    ok(&dir, &["render", "s.toml", "--tile", "1/2", "-o", "t1.exr"]);
    let before = snapshot(&dir);
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["merge", "t0.exr", "t0.exr", "t1.exr"],
            &["the image t0.exr", "the part t0.exr"],
        ),
        (
            &["merge", "t1.state", "t0.exr", "t1.exr"],
            &["the image t1.state", "the part's film state t1.state"],
        ),
        (
            &["merge", "t0.foo", "t0.exr", "t1.exr", "t0.png"],
            &["its PNG preview t0.png", "the part t0.png"],
        ),
    ];
    for (args, needles) in cases {
        refused(&dir, args, needles);
        assert!(snapshot(&dir) == before, "{args:?} changed a file");
    }
    ok(&dir, &["merge", "m.exr", "t0.exr", "t1.exr"]);
}

/// A tmpfs of 64 KiB mounted on a folder for one test, unmounted at the end.
struct SmallDisk(PathBuf);

impl SmallDisk {
    /// Needs root (CI runs as root on a fresh Debian 12): there is no other
    /// way to get a real full disk, and a test that quietly passed without
    /// one would prove nothing, so it fails saying so.
    fn mount(dir: &Path) -> SmallDisk {
        std::fs::create_dir_all(dir).unwrap();
        let out = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
            .arg(dir)
            .output()
            .expect("mount runs");
        assert!(
            out.status.success(),
            "this test needs a small full file system and mounts a tmpfs for it, which \
             needs root: {}",
            stderr(&out)
        );
        SmallDisk(dir.to_owned())
    }

    /// Fills what is left with a file, so that no write can succeed.
    fn fill(&self) {
        let mut filler = std::fs::File::create(self.0.join("filler")).unwrap();
        let block = [0x55u8; 4096];
        while filler
            .write_all(&block)
            .and_then(|()| filler.flush())
            .is_ok()
        {}
        // Partial blocks too, down to the last byte.
        while filler.write_all(&block[..1]).is_ok() {}
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg("-l").arg(&self.0).status();
    }
}

#[test]
fn a_full_disk_leaves_every_previous_output_whole() {
    let dir = plane("full");
    std::fs::write(dir.join("r.npy"), rays_npy(4)).unwrap();
    ok(&dir, &["render", "s.toml", "--tile", "0/2", "-o", "t0.exr"]);
    ok(&dir, &["render", "s.toml", "--tile", "1/2", "-o", "t1.exr"]);
    let disk = SmallDisk::mount(&dir.join("disk"));
    for (name, text) in [
        ("out.exr", "previous image"),
        ("out.png", "previous preview"),
        ("out.state", "previous state"),
        ("stats.json", "previous stats"),
        ("hits.npy", "previous hits"),
        ("m.exr", "previous merge"),
        ("m.png", "previous merge preview"),
    ] {
        write(&disk.0, name, text);
    }
    disk.fill();
    let before = snapshot(&disk.0);
    let commands: &[&[&str]] = &[
        &["render", "s.toml", "-o", "disk/out.exr"],
        &["render", "s.toml", "--tile", "1/2", "-o", "disk/out.exr"],
        &[
            "render",
            "s.toml",
            "-o",
            "x.exr",
            "--stats",
            "disk/stats.json",
        ],
        &[
            "trace",
            "s.toml",
            "--rays",
            "r.npy",
            "--out",
            "disk/hits.npy",
        ],
        &["merge", "disk/m.exr", "t0.exr", "t1.exr"],
    ];
    for args in commands {
        let err = refused(&dir, args, &["No space left on device"]);
        let named = args[args.len() - 1];
        let named = if args[0] == "merge" { args[1] } else { named };
        let file = Path::new(named).file_stem().unwrap().to_string_lossy();
        assert!(err.contains(&*file), "{args:?}: {err}");
        assert!(
            snapshot(&disk.0) == before,
            "{args:?} changed the full disk"
        );
    }
}

/// Writes a copy of `from`'s state with `edit` applied to it (a valid
/// checksum: the reader must find the fault by itself).
fn edit_state(
    from: &Path,
    to: &Path,
    edit: impl FnOnce(&mut StateHeader, &mut sturmray::film::Film),
) {
    let (mut header, mut film) = read_state(from).unwrap();
    edit(&mut header, &mut film);
    write_state(to, &header, &film).unwrap();
}

#[test]
fn a_damaged_or_foreign_film_state_is_refused() {
    let dir = plane("states");
    ok(&dir, &["render", "s.toml", "--tile", "0/2", "-o", "t0.exr"]);
    ok(&dir, &["render", "s.toml", "--tile", "1/2", "-o", "t1.exr"]);
    let good = std::fs::read(dir.join("t0.state")).unwrap();
    // Refused by merge and by --resume, both with `needles`, or for
    // --resume the file and `resume` instead when given.
    let damaged = |bytes: Vec<u8>, needles: &[&str], resume: &[&str]| {
        std::fs::write(dir.join("t0.state"), &bytes).unwrap();
        refused(&dir, &["merge", "m.exr", "t0.exr", "t1.exr"], needles);
        let resume = match resume {
            [] => needles.to_vec(),
            more => [&needles[..1], more].concat(),
        };
        refused(
            &dir,
            &[
                "render", "s.toml", "--tile", "0/2", "-o", "t0.exr", "--resume",
            ],
            &resume,
        );
        assert_eq!(std::fs::read(dir.join("t0.state")).unwrap(), bytes);
        assert!(!dir.join("m.exr").exists());
    };
    // One flipped bit anywhere in the pixels.
    for at in [good.len() / 2, good.len() - 100] {
        let mut bytes = good.clone();
        bytes[at] ^= 0x10;
        damaged(bytes, &["t0.state", "damaged"], &[]);
    }
    // A state of the old format.
    let mut old = good.clone();
    old[20] = b'1';
    damaged(old, &["t0.state", "format 1"], &[]);

    let t0 = dir.join("t0.state");
    let copy = dir.join("good.state");
    std::fs::write(&copy, &good).unwrap();
    type Edit = Box<dyn FnOnce(&mut StateHeader, &mut sturmray::film::Film)>;
    let crafted: Vec<(Edit, &[&str], &[&str])> = vec![
        (
            Box::new(|_, f| f.pixels[5].radiance[0] = f64::NAN),
            &["t0.state", "pixel (5, 0)", "NaN"],
            &[],
        ),
        (
            Box::new(|_, f| f.pixels[7].weight = f64::INFINITY),
            &["t0.state", "pixel (7, 0)"],
            &[],
        ),
        (
            Box::new(|h, _| h.samples_done = h.spp + 1),
            &["t0.state", "samples_done 2"],
            &[],
        ),
        // Sums with samples_done 0: merge finds the part unfinished first.
        (
            Box::new(|h, _| h.samples_done = 0),
            &["t0.state", "0 of 1"],
            &["pixel (0, 0): 1 samples where the state has taken 0"],
        ),
        (
            Box::new(|_, f| f.pixels[3].samples = 0),
            &["t0.state", "pixel (3, 0)"],
            &[],
        ),
    ];
    for (edit, needles, resume) in crafted {
        edit_state(&copy, &t0, edit);
        let bytes = std::fs::read(&t0).unwrap();
        damaged(bytes, needles, resume);
    }

    // A render stops only where a pass ends; a state claiming otherwise
    // would resume with samples skipped.
    ok(
        &dir,
        &[
            "render", "s.toml", "--tile", "1/2", "-o", "p.exr", "--spp", "20",
        ],
    );
    edit_state(&dir.join("p.state"), &dir.join("p.state"), |h, f| {
        h.samples_done = 2;
        f.pixels.iter_mut().for_each(|p| p.samples = 2);
    });
    refused(
        &dir,
        &[
            "render", "s.toml", "--tile", "1/2", "-o", "p.exr", "--spp", "20", "--resume",
        ],
        &["p.state", "samples_done 2 is not where a pass"],
    );

    // A state from another backend is not resumed, nor merged with others.
    std::fs::write(&t0, &good).unwrap();
    ok(
        &dir,
        &[
            "render",
            "s.toml",
            "--tile",
            "1/2",
            "-o",
            "b1.exr",
            "--backend",
            "bvh",
        ],
    );
    refused(
        &dir,
        &[
            "render", "s.toml", "--tile", "1/2", "-o", "b1.exr", "--resume",
        ],
        &["b1.state", "backend bvh", "backend embree"],
    );
    refused(
        &dir,
        &["merge", "m.exr", "t0.exr", "b1.exr"],
        &["b1.exr", "backend bvh"],
    );
    ok(&dir, &["merge", "m.exr", "t0.exr", "t1.exr"]);
}

/// Waits up to `limit` for a child; kills it if it is still running.
fn wait_at_most(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            let out = child.wait_with_output().unwrap();
            panic!("still running after {limit:?}: {}", stderr(&out));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

#[test]
fn endless_and_special_inputs_are_refused_unread() {
    let dir = plane("endless");
    let mkfifo = |name: &str| {
        let status = Command::new("mkfifo").arg(dir.join(name)).status().unwrap();
        assert!(status.success());
    };
    mkfifo("fifo.npy");
    let limit = Duration::from_secs(20);
    let trace = |rays: &str| spawn(&dir, &["trace", "s.toml", "--rays", rays, "--out", "h.npy"]);
    for (rays, needle) in [
        ("/dev/zero", "character device"),
        ("fifo.npy", "FIFO"),
        (".", "not a regular file"),
    ] {
        let out = wait_at_most(trace(rays), limit);
        assert_eq!(out.status.code(), Some(2), "{rays}: {}", stderr(&out));
        assert!(stderr(&out).contains(needle), "{rays}: {}", stderr(&out));
    }
    // A header that promises 2^31 rows of a sparse file of that size: read
    // row by row, it stops at the hole's first row (a zero direction)
    // instead of allocating for all of them.
    let rows: u64 = 1 << 31;
    let header = npy_header(&format!("({rows}, 6)"));
    let file = std::fs::File::create(dir.join("sparse.npy")).unwrap();
    (&file).write_all(&header).unwrap();
    file.set_len(header.len() as u64 + rows * 24).unwrap();
    let out = wait_at_most(trace("sparse.npy"), limit);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("ray 0 "), "{}", stderr(&out));

    // Film states: a FIFO or a device beside a part.
    ok(&dir, &["render", "s.toml", "--tile", "0/1", "-o", "t.exr"]);
    std::fs::remove_file(dir.join("t.state")).unwrap();
    mkfifo("t.state");
    for args in [
        &["merge", "m.exr", "t.exr"][..],
        &[
            "render", "s.toml", "--tile", "0/1", "-o", "t.exr", "--resume",
        ],
    ] {
        let out = wait_at_most(spawn(&dir, args), limit);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains("t.state") && err.contains("regular file"),
            "{err}"
        );
    }
    std::fs::remove_file(dir.join("t.state")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.join("t.state")).unwrap();
    refused(
        &dir,
        &["merge", "m.exr", "t.exr"],
        &["t.state", "character device"],
    );
}

#[test]
fn a_reader_that_stops_early_is_no_error() {
    let dir = plane("pipe");
    for args in [
        &["info", "s.toml"][..],
        &["explain", "s.toml", "--pixel", "16,12"],
    ] {
        let mut child = spawn(&dir, args);
        // The reader goes away before sturmray writes a byte.
        drop(child.stdout.take());
        let out = wait_at_most(child, Duration::from_secs(60));
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).is_empty(), "{args:?}: {}", stderr(&out));
    }
    // `roots` answers line by line: the reader is gone before the first.
    let lines = "{\"coeffs\": [-1, 0, 1]}\n".repeat(1000);
    write(&dir, "lines.jsonl", &lines);
    let mut child = Command::new(env!("CARGO_BIN_EXE_sturmray"))
        .arg("roots")
        .stdin(std::fs::File::open(dir.join("lines.jsonl")).unwrap())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = wait_at_most(child, Duration::from_secs(60));
    assert_eq!(out.status.code(), Some(0), "roots: {}", stderr(&out));
    assert!(stderr(&out).is_empty(), "roots: {}", stderr(&out));
}

#[test]
fn a_second_ctrl_c_while_writing_waits_for_whole_files() {
    let dir = plane("signals");
    // A big image of one sample: a short render, then long writes.
    let text = plane_scene("").replace("width = 32\nheight = 24", "width = 1000\nheight = 800");
    write(&dir, "big.toml", &text);
    let child = spawn(
        &dir,
        &["render", "big.toml", "--tile", "0/1", "-o", "big.exr"],
    );
    // Signals are caught from the start; threads beyond the main one and
    // the signal handler's (the BVH build's, the render's) mean the output
    // checks, whose temporaries would look like writes, are over.
    let start = Instant::now();
    let tasks = format!("/proc/{}/task", child.id());
    while std::fs::read_dir(&tasks).map_or(0, |t| t.count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(60), "never started");
        std::thread::sleep(Duration::from_millis(1));
    }
    interrupt(&child);
    // Once a temporary appears, the writes have begun: interrupt again.
    while !names(&dir).iter().any(|n| n.starts_with(".big.")) {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "nothing written"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    interrupt(&child);
    let out = wait_at_most(child, Duration::from_secs(120));
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    // Every file whole: the image, its preview and the state of all the work.
    let (w, h, _) = sturmray::io::exr::read_exr(&dir.join("big.exr")).unwrap();
    assert_eq!((w, h), (1000, 800));
    let png = std::fs::File::open(dir.join("big.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(png))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut buf).unwrap();
    // The one pass is kept, or dropped if it outlasted its grace after the
    // first signal (a slow machine): either way the state reads back whole.
    let (header, _) = read_state(&dir.join("big.state")).unwrap();
    assert!(header.samples_done <= 1, "{}", header.samples_done);
    assert_eq!(
        names(&dir),
        [
            "big.exr",
            "big.png",
            "big.state",
            "big.toml",
            "s.toml",
            "square.obj"
        ]
    );
}

#[test]
fn broken_textures_are_warnings_and_the_render_goes_on() {
    let dir = scratch("textures");
    write(&dir, "square.obj", SQUARE);
    let png_header = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\x7f\xff\xff\xff\x7f\xff\xff\xff\x08\x06";
    std::fs::write(dir.join("truncated.png"), png_header).unwrap();
    std::fs::write(dir.join("noise.exr"), [0x76, 0x2f, 0x31, 0x01, 7, 7, 7]).unwrap();
    std::fs::write(dir.join("empty.jpg"), []).unwrap();
    std::fs::create_dir(dir.join("folder.png")).unwrap();
    let mut materials = String::new();
    for (i, file) in [
        "truncated.png",
        "noise.exr",
        "empty.jpg",
        "folder.png",
        "gone.tga",
    ]
    .iter()
    .enumerate()
    {
        materials +=
            &format!("[materials.t{i}]\ntype = \"diffuse\"\nalbedo = {{ texture = \"{file}\" }}\n");
    }
    write(&dir, "s.toml", &plane_scene(&materials));
    let out = sturmray(&dir, &["render", "s.toml", "-o", "t.exr"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    for file in [
        "truncated.png",
        "noise.exr",
        "empty.jpg",
        "folder.png",
        "gone.tga",
    ] {
        assert!(
            err.contains(&format!("texture {file}")) || err.contains(file),
            "{file}: {err}"
        );
    }
    assert_eq!(err.matches("warning").count(), 5, "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
