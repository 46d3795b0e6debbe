//! Models as modelling programs export them (issue 16): OBJ files whose
//! library or materials are missing, vertex normals, texture coordinates and
//! textures, PLY files.

mod common;

use common::{beauty, png_bytes, scratch, sturmray, write};

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
    assert!(
        err.contains("b.obj:6: material `None` is not defined"),
        "{err}"
    );
    assert!(dir.join("b.exr").is_file());
}

/// A UV sphere of radius 1 (`rings` bands of latitude, `segments` of
/// longitude) as OBJ text; with `normals`, each vertex carries the exact
/// sphere normal (`vn`, the corners `v//n`).
fn uv_sphere(rings: usize, segments: usize, normals: bool) -> String {
    use std::f64::consts::PI;
    use std::fmt::Write;
    let mut obj = String::new();
    for i in 0..=rings {
        let theta = PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = 2.0 * PI * j as f64 / segments as f64;
            let (x, y, z) = (
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            writeln!(obj, "v {x} {y} {z}").unwrap();
            if normals {
                writeln!(obj, "vn {x} {y} {z}").unwrap();
            }
        }
    }
    let corner = |i: usize, j: usize| {
        let k = i * segments + j % segments + 1;
        if normals {
            format!("{k}//{k}")
        } else {
            k.to_string()
        }
    };
    for i in 0..rings {
        for j in 0..segments {
            // Counter-clockwise seen from outside.
            let (a, b, c, d) = (
                corner(i, j),
                corner(i, j + 1),
                corner(i + 1, j + 1),
                corner(i + 1, j),
            );
            writeln!(obj, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
        }
    }
    obj
}

/// A scene of one grey object lit along the view direction, seen from +z.
fn lit_object(object: &str, integrator: &str) -> String {
    format!(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 30\nwidth = 48\nheight = 48\n\
         [render]\nspp = 1\nintegrator = \"{integrator}\"\nmax_depth = 0\n\
         [materials.grey]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
         [[objects]]\n{object}\nmaterial = \"grey\"\n\
         [[lights]]\ntype = \"directional\"\ndirection = [-0.3, -0.2, -1]\nirradiance = [3, 3, 3]\n"
    )
}

/// The mean absolute difference of two renders' beauty over the pixels both
/// hit, relative to the mean brightness there.
fn relative_difference(
    a: &sturmray::render::RenderOutput,
    b: &sturmray::render::RenderOutput,
) -> f32 {
    let (la, lb) = (a.film.layers(), b.film.layers());
    let (mut diff, mut sum, mut n) = (0.0, 0.0, 0);
    for i in 0..la.beauty.len() {
        if la.depth[i].is_finite() && lb.depth[i].is_finite() {
            diff += (la.beauty[i][1] - lb.beauty[i][1]).abs();
            sum += lb.beauty[i][1];
            n += 1;
        }
    }
    assert!(n > 500, "{n} pixels hit by both");
    diff / sum
}

#[test]
fn a_coarse_sphere_with_vertex_normals_shades_as_the_analytic_one() {
    use sturmray::accel::{Accel, Backend};
    use sturmray::render::{RenderOptions, render};
    use sturmray::scene::Scene;
    let dir = scratch("smooth");
    // 16 × 32: 960 triangles, facets 11.25 degrees wide. (Measured: the
    // smooth mesh differs by 0.8%, the flat one by 4%; at 12 × 24 the smooth
    // one differs by 1.4%, most of it along the silhouette, where the chords
    // lie inside the sphere.)
    write(&dir, "smooth.obj", &uv_sphere(16, 32, true));
    write(&dir, "flat.obj", &uv_sphere(16, 32, false));
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    for integrator in ["whitted", "path"] {
        let load = |name: &str, object: &str| {
            let path = write(&dir, name, &lit_object(object, integrator));
            Scene::load(&path).unwrap()
        };
        let sphere = load("sphere.toml", "type = \"sphere\"\nradius = 1");
        let smooth = load("smooth.toml", "type = \"mesh\"\nfile = \"smooth.obj\"");
        let flat = load("flat.toml", "type = \"mesh\"\nfile = \"flat.obj\"");
        for backend in Backend::ALL {
            let image = |scene: &Scene| {
                let accel = Accel::build(scene, backend, None).unwrap();
                render(scene, &accel, &options).unwrap()
            };
            let exact = image(&sphere);
            let smooth = relative_difference(&image(&smooth), &exact);
            let flat = relative_difference(&image(&flat), &exact);
            assert!(
                smooth < 0.01,
                "{integrator}, {backend:?}: smooth differs by {smooth}"
            );
            // The same mesh without its normals is visibly faceted: the
            // comparison can tell.
            assert!(
                flat > 3.0 * smooth,
                "{integrator}, {backend:?}: flat {flat}"
            );
        }
    }
}

/// The square [-1, 1]² in z = 0 with texture coordinates [0, 1]² (v up).
const UV_SQUARE: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

/// The square `mesh` (a file name and its bytes) filling a 32 × 32 image
/// seen head-on, lit head-on by an irradiance of π (so a Lambert surface's
/// radiance is its albedo), with `material` as its `[materials.m]` table,
/// `settings` added to its `[render]` table and `files` beside it.
fn render_square(
    name: &str,
    material: &str,
    settings: &str,
    mesh: (&str, &[u8]),
    files: &[(&str, &[u8])],
) -> Vec<[f32; 3]> {
    use sturmray::accel::Backend;
    use sturmray::scene::Scene;
    let dir = scratch(name);
    for (file, bytes) in files.iter().chain([&mesh]) {
        std::fs::write(dir.join(file), bytes).unwrap();
    }
    // tan(fov / 2) = 1/4: the square's edges are the image's.
    let fov = 2.0 * 0.25f64.atan().to_degrees();
    let text = format!(
        "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = {fov}\nwidth = 32\nheight = 32\n\
         [render]\nspp = 1\n{settings}\n[materials.m]\n{material}\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"{}\"\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\n\
         irradiance = [3.14159265, 3.14159265, 3.14159265]\n",
        mesh.0
    );
    let scene = Scene::load(&write(&dir, "s.toml", &text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let mut images = Backend::ALL.iter().map(|&backend| beauty(&scene, backend));
    let first = images.next().unwrap();
    // Every backend finds the same texels; barycentrics differ in the last
    // bits between backends, so the filtered colours may too.
    for other in images {
        for (a, b) in other.iter().zip(&first) {
            let d = (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, f32::max);
            assert!(d < 1e-4, "{a:?} against {b:?}");
        }
    }
    first
}

/// The pixel whose centre is at texture coordinates (u, v) of the square.
fn at(image: &[[f32; 3]], u: f32, v: f32) -> sturmray::math::Vec3 {
    let (x, y) = ((u * 32.0) as usize, ((1.0 - v) * 32.0) as usize);
    sturmray::math::Vec3::from(image[y * 32 + x])
}

fn close(a: sturmray::math::Vec3, b: sturmray::math::Vec3) -> bool {
    (a - b).abs().max_element() < 1e-3 * b.max_element().max(1.0)
}

#[test]
fn a_uv_checker_lands_on_the_right_squares() {
    let image = render_square(
        "checker",
        "type = \"diffuse\"\nalbedo = { checker = [[0.8, 0.1, 0.1], [0.1, 0.1, 0.8]], scale = 0.25 }",
        "",
        ("square.obj", UV_SQUARE.as_bytes()),
        &[],
    );
    let (a, b) = (
        sturmray::math::Vec3::new(0.8, 0.1, 0.1),
        sturmray::math::Vec3::new(0.1, 0.1, 0.8),
    );
    // Squares of 0.25 in uv: square (i, j) is `a` where i + j is even.
    for i in 0..4 {
        for j in 0..4 {
            let (u, v) = (0.125 + 0.25 * i as f32, 0.125 + 0.25 * j as f32);
            let expected = if (i + j) % 2 == 0 { a } else { b };
            let found = at(&image, u, v);
            assert!(close(found, expected), "({i}, {j}): {found} for {expected}");
        }
    }
}

/// An 8 × 8 RGBA PNG whose quadrants are one colour each (8-bit sRGB):
/// top left red, top right green, bottom left blue, bottom right grey 50%.
fn quadrants_png() -> Vec<u8> {
    let mut data = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            data.extend_from_slice(match (x < 4, y < 4) {
                (true, true) => &[255, 0, 0, 255],
                (false, true) => &[0, 255, 0, 255],
                (true, false) => &[0, 0, 255, 255],
                (false, false) => &[188, 188, 188, 255],
            });
        }
    }
    png_bytes(8, 8, png::ColorType::Rgba, &data)
}

#[test]
fn an_image_texture_is_srgb_decoded_and_lands_on_its_texels() {
    use sturmray::math::Vec3;
    let png = quadrants_png();
    // The scene file's own texture, and the same image through an MTL's map_Kd.
    let toml = render_square(
        "texture",
        "type = \"diffuse\"\nalbedo = { texture = \"q.png\" }",
        "",
        ("square.obj", UV_SQUARE.as_bytes()),
        &[("q.png", &png)],
    );
    // sRGB 188 is linear 0.503.
    let grey = Vec3::splat(((188.0 / 255.0 + 0.055) / 1.055f32).powf(2.4));
    for (u, v, expected) in [
        (0.25, 0.75, Vec3::X),
        (0.75, 0.75, Vec3::Y),
        (0.25, 0.25, Vec3::Z),
        (0.75, 0.25, grey),
    ] {
        let found = at(&toml, u, v);
        assert!(close(found, expected), "({u}, {v}): {found} for {expected}");
    }
}

#[test]
fn map_kd_is_read_once_and_a_missing_texture_is_a_warning() {
    use sturmray::scene::Scene;
    let dir = scratch("map_kd");
    std::fs::write(dir.join("q.png"), quadrants_png()).unwrap();
    write(
        &dir,
        "m.mtl",
        "newmtl a\nKd 0.2 0.2 0.2\nmap_Kd -s 2 2 q.png\nnewmtl b\nmap_Kd q.png\n\
         newmtl c\nKd 0.3 0.3 0.3\nmap_Kd gone.png\nmap_Ns q.png\n",
    );
    let obj = format!("mtllib m.mtl\n{UV_SQUARE}").replace("f 1/1", "usemtl a\nf 1/1")
        + "usemtl b\nf 1/1 2/2 3/3\nusemtl c\nf 1/1 2/2 3/3\n";
    let scene = Scene::load(&write(&dir, "m.obj", &obj)).unwrap();
    let material = |t: usize| &scene.materials[scene.meshes[0].materials[t] as usize];
    let (a, b) = (material(0), material(2));
    let (ta, tb) = (
        a.albedo_map.as_ref().unwrap(),
        b.albedo_map.as_ref().unwrap(),
    );
    assert!(
        std::sync::Arc::ptr_eq(&ta.image, &tb.image),
        "one image for both"
    );
    assert_eq!(ta.scale, sturmray::math::Vec2::splat(2.0));
    // The missing one: a warning naming the library's line, and Kd.
    let c = material(3);
    assert!(c.albedo_map.is_none());
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("m.mtl:8: texture") && warnings.contains("gone.png"),
        "{warnings}"
    );
    assert_eq!(c.albedo, sturmray::math::Vec3::splat(0.3));
    // A map that is not read yet is named, not passed over in silence.
    assert!(
        warnings.contains("m.mtl:9: `map_Ns` is not read yet"),
        "{warnings}"
    );
}

/// `mesh` as a PLY file in `format` (ascii, binary_little_endian or
/// binary_big_endian), with its normals; each pair of triangles that is the
/// fan of a quad (a, b, c), (a, c, d) is written as that quad, so the
/// reader's fan triangulation is tested too.
fn ply_bytes(mesh: &sturmray::geometry::Mesh, format: &str) -> Vec<u8> {
    let mut faces: Vec<Vec<u32>> = Vec::new();
    let mut triangles = mesh.triangles.iter().peekable();
    while let Some(&[a, b, c]) = triangles.next() {
        match triangles.peek() {
            Some(&&[a2, c2, d]) if a2 == a && c2 == c => {
                triangles.next();
                faces.push(vec![a, b, c, d]);
            }
            _ => faces.push(vec![a, b, c]),
        }
    }
    assert!(faces.iter().any(|f| f.len() == 4));
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        faces.len()
    )
    .into_bytes();
    let floats = |v: [f32; 3], out: &mut Vec<u8>| match format {
        "ascii" => out.extend(format!("{} {} {} ", v[0], v[1], v[2]).bytes()),
        "binary_little_endian" => v.iter().for_each(|x| out.extend(x.to_le_bytes())),
        _ => v.iter().for_each(|x| out.extend(x.to_be_bytes())),
    };
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        floats(p.to_array(), &mut out);
        floats(n.to_array(), &mut out);
        if format == "ascii" {
            out.push(b'\n');
        }
    }
    for face in faces {
        if format == "ascii" {
            let list: Vec<String> = face.iter().map(u32::to_string).collect();
            out.extend(format!("{} {}\n", face.len(), list.join(" ")).bytes());
            continue;
        }
        out.push(face.len() as u8);
        for i in face {
            let i = i as i32;
            out.extend(if format == "binary_little_endian" {
                i.to_le_bytes()
            } else {
                i.to_be_bytes()
            });
        }
    }
    out
}

#[test]
fn the_same_mesh_as_obj_and_as_ply_gives_the_same_hits_on_every_backend() {
    use sturmray::accel::{Accel, Backend};
    use sturmray::math::{Ray, Vec3};
    use sturmray::scene::Scene;
    let dir = scratch("ply");
    let obj = Scene::load(&write(&dir, "sphere.obj", &uv_sphere(8, 16, true))).unwrap();
    let reference = &obj.meshes[0];
    // A grid of rays from +z over the sphere and past its edge.
    let rays: Vec<Ray> = (0..24 * 24)
        .map(|k| {
            let (x, y) = ((k % 24) as f32 / 10.0 - 1.15, (k / 24) as f32 / 10.0 - 1.15);
            Ray::new(Vec3::new(x, y, 5.0), Vec3::new(0.01, 0.02, -1.0))
        })
        .collect();
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let name = format!("{format}.ply");
        std::fs::write(dir.join(&name), ply_bytes(reference, format)).unwrap();
        // The bare file, and the same file as a TOML mesh object.
        let bare = Scene::load(&dir.join(&name)).unwrap();
        let toml = format!("[[objects]]\ntype = \"mesh\"\nfile = \"{name}\"\n");
        let placed = Scene::load(&write(&dir, &format!("{format}.toml"), &toml)).unwrap();
        for ply in [&bare, &placed] {
            let mesh = &ply.meshes[0];
            assert_eq!(mesh.positions, reference.positions, "{format}");
            assert_eq!(mesh.normals, reference.normals, "{format}");
            assert_eq!(mesh.triangles, reference.triangles, "{format}");
            // The poles' zero-area triangles, counted as the OBJ's are.
            let expected: Vec<String> = obj
                .warnings
                .iter()
                .map(|w| w.replace("sphere.obj", &name))
                .collect();
            assert!(expected[0].contains("28 degenerate"), "{expected:?}");
            assert_eq!(ply.warnings, expected, "{format}");
        }
        for backend in Backend::ALL {
            let (a, b) = (
                Accel::build(&obj, backend, None).unwrap(),
                Accel::build(&bare, backend, None).unwrap(),
            );
            let mut hits = 0;
            for ray in &rays {
                let (ha, hb) = (a.intersect(ray), b.intersect(ray));
                assert_eq!(ha, hb, "{format}, {backend:?}, {ray:?}");
                hits += usize::from(ha.is_hit());
            }
            assert!(hits > 200 && hits < rays.len(), "{hits} hits");
        }
    }
}

#[test]
fn per_vertex_colours_of_a_ply_shade_as_its_albedo() {
    // The square of UV_SQUARE, red on the left (x = -1), blue on the right;
    // 188 is sRGB for a linear 0.5.
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\n\
               property float x\nproperty float y\nproperty float z\n\
               property uchar red\nproperty uchar green\nproperty uchar blue\n\
               element face 1\nproperty list uchar uint vertex_indices\nend_header\n\
               -1 -1 0 188 0 0\n1 -1 0 0 0 188\n1 1 0 0 0 188\n-1 1 0 188 0 0\n4 0 1 2 3\n";
    for integrator in ["whitted", "path"] {
        let image = render_square(
            &format!("colours_{integrator}"),
            "type = \"diffuse\"\nalbedo = [0.8, 0.8, 0.8]",
            &format!("integrator = \"{integrator}\"\nmax_depth = 0"),
            ("square.ply", ply.as_bytes()),
            &[],
        );
        let (left, middle, right) = (
            at(&image, 0.02, 0.5),
            at(&image, 0.5, 0.5),
            at(&image, 0.98, 0.5),
        );
        // The material's grey is replaced, and the colours blend linearly
        // across: red at the left edge, blue at the right (the edge pixels'
        // centres are 1/64 in, hence the 0.01 allowed).
        let half = ((188.0 / 255.0 + 0.055) / 1.055f32).powf(2.4);
        assert!(
            (left.x - half).abs() < 0.01 && left.z < 0.01,
            "{integrator}: {left}"
        );
        assert!(
            (right.z - half).abs() < 0.01 && right.x < 0.01,
            "{integrator}: {right}"
        );
        assert!(left.y == 0.0 && middle.y == 0.0, "{integrator}: {middle}");
        assert!(
            (middle.x + middle.z - half).abs() < 1e-3 && middle.x > 0.2 && middle.z > 0.2,
            "{integrator}: {middle}"
        );
    }
}
