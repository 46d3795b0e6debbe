//! MTL maps beyond `map_Kd` (issue 16 §1): `map_d` cut-outs on every
//! backend and for every kind of ray; bump and normal maps; the maps that
//! scale a material's constants at each hit (`map_Ks`, `map_Pr`, `map_Pm`,
//! `map_Ke`), the last in both integrators' lights.

mod common;

use common::{png_bytes, scratch, sturmray, write};
use sturmray::accel::{Accel, Backend};
use sturmray::math::{Hit, Ray, Vec3};
use sturmray::scene::{Interaction, Scene};
use sturmray::shading::{Bsdf, Metal, Plastic, Surface};

/// An 8 × 8 PNG mask, opaque on its left half (u < 0.5) and clear on its
/// right: with an alpha channel (RGBA, black and white, so the luminance
/// would say the opposite), or grey without one (white left, black right).
fn half_mask(alpha: bool) -> Vec<u8> {
    let mut data = Vec::new();
    for _ in 0..8 {
        for x in 0..8 {
            let opaque = x < 4;
            if alpha {
                // Black where opaque, white where clear: only the alpha tells.
                let c = if opaque { 0 } else { 255 };
                data.extend_from_slice(&[c, c, c, if opaque { 255 } else { 0 }]);
            } else {
                data.push(if opaque { 255 } else { 0 });
            }
        }
    }
    let colour = if alpha {
        png::ColorType::Rgba
    } else {
        png::ColorType::Grayscale
    };
    png_bytes(8, 8, colour, &data)
}

/// Two squares over x, y ∈ [-1, 1]: `leaf` at z = 1 with uv (its material
/// cut by `mask.png`), `wall` at z = 0, opaque.
const LEAF_OBJ: &str = "mtllib m.mtl\n\
    o leaf\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl leaf\nf 1/1 2/2 3/3 4/4\n\
    o wall\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl wall\nf 5 6 7 8\n";

const LEAF_MTL: &str = "newmtl leaf\nKd 0.2 0.8 0.2\nmap_d mask.png\nnewmtl wall\nKd 0.5 0.5 0.5\n";

/// The leaf and wall in a folder with `mask`, as a bare OBJ scene.
fn leaf_scene(dir: &std::path::Path, mask: &[u8]) -> Scene {
    std::fs::write(dir.join("mask.png"), mask).unwrap();
    write(dir, "m.mtl", LEAF_MTL);
    Scene::load(&write(dir, "leaf.obj", LEAF_OBJ)).unwrap()
}

/// Rays straight down from z = 5 on a grid over the squares, clear of the
/// mask's middle (x = 0), where bilinear filtering blends the halves, and
/// off the squares' diagonal (x = y), where both triangles are hit.
fn down_rays() -> Vec<Ray> {
    let mut rays = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            let x = -0.9 + 0.2 * i as f32 + if i < 4 { 0.0 } else { 0.05 };
            let y = -0.87 + 0.2 * j as f32;
            rays.push(Ray::new(Vec3::new(x, y, 5.0), Vec3::new(0.0, 0.0, -1.0)));
        }
    }
    rays
}

/// Whether `t` is the exact `expected` (4 or 5 for these rays) to within an
/// ulp. Embree picks its kernels by the CPU at run time and its t is not
/// always the correctly rounded one: Embree 3.13.5 on an AMD EPYC with AVX2
/// and no AVX-512 gives 3.9999998 here, one ulp below 4, where other
/// machines give 4 (as src/accel/rust_bvh/tests.rs's `at_one`).
fn at(t: f32, expected: f32) -> bool {
    (t - expected).abs() <= expected * f32::EPSILON
}

/// What each ray must find: over the opaque half the leaf (geometry 0, t =
/// 4), over the clear half the wall behind it (geometry 1, t = 5).
fn check_hits(accel: &Accel, rays: &[Ray], what: &str) {
    let mut batch = vec![Hit::MISS; rays.len()];
    accel.intersect_batch(rays, &mut batch, true).unwrap();
    for (ray, batched) in rays.iter().zip(&batch) {
        let hit = accel.intersect(ray);
        let opaque = ray.origin.x < 0.0;
        let (geom_id, t) = if opaque { (0, 4.0) } else { (1, 5.0) };
        assert_eq!(hit.geom_id, geom_id, "{what}: {ray:?}");
        assert!(at(hit.t, t), "{what}: t = {}, {ray:?}", hit.t);
        assert_eq!(*batched, hit, "{what}: batch, {ray:?}");
        // A shadow ray that ends between the squares is blocked only by the leaf.
        let mut shadow = *ray;
        shadow.tfar = 4.5;
        assert_eq!(accel.occluded(&shadow), opaque, "{what}: shadow {ray:?}");
        // All hits: the leaf only where it is there, and the wall always.
        let mut all = Vec::new();
        accel.intersect_all(ray, &mut all);
        let found: Vec<u32> = all.iter().map(|h| h.geom_id).collect();
        let expected = if opaque { vec![0, 1] } else { vec![1] };
        assert_eq!(found, expected, "{what}: all hits {ray:?}");
    }
    accel.check().unwrap();
}

#[test]
fn rays_pass_the_cut_out_parts_on_every_backend() {
    for alpha in [true, false] {
        let dir = scratch("cutout");
        let scene = leaf_scene(&dir, &half_mask(alpha));
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        for backend in Backend::ALL {
            let accel = Accel::build(&scene, backend, None).unwrap();
            check_hits(&accel, &down_rays(), &format!("alpha {alpha}, {backend:?}"));
        }
    }
}

#[test]
fn instances_keep_their_prototypes_cut_outs() {
    let dir = scratch("cutout_instances");
    leaf_scene(&dir, &half_mask(true));
    let toml = "[[prototypes.leaf.objects]]\ntype = \"mesh\"\nfile = \"leaf.obj\"\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"leaf\"\n\
                transform = { translate = [0, 0, -1] }\n";
    let scene = Scene::load(&write(&dir, "i.toml", toml)).unwrap();
    // Moved 1 down: rays from z = 4 see what rays from 5 saw before.
    let rays: Vec<Ray> = down_rays()
        .into_iter()
        .map(|r| Ray::new(r.origin - Vec3::Z, r.dir))
        .collect();
    for backend in Backend::ALL {
        let accel = Accel::build(&scene, backend, None).unwrap();
        for ray in &rays {
            let hit = accel.intersect(ray);
            let expected = if ray.origin.x < 0.0 {
                (0, 4.0)
            } else {
                (1, 5.0)
            };
            assert_eq!(hit.geom_id, expected.0, "{backend:?}: {ray:?}");
            assert!(at(hit.t, expected.1), "{backend:?}: t = {}, {ray:?}", hit.t);
            assert_eq!(hit.inst_id, 0, "{backend:?}");
        }
    }
}

/// A square at z = 1 over x, y ∈ [-1, 1] with uv, of an opaque material.
const BOARD_OBJ: &str = "mtllib b.mtl\no board\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl board\nf 1/1 2/2 3/3 4/4\n";

#[test]
fn an_instances_own_material_decides_its_cut_outs_on_every_backend() {
    // As pbrt's and Mitsuba's instances: the instance's material replaces
    // the prototype's, its `map_d` with it. Three leaves, at x = 0, 10, 20:
    // the first keeps the leaf's mask, the second's material has none (the
    // whole leaf is there), and a board whose own material is opaque takes
    // the leaf's mask from its instance's material (set through the
    // library, as TOML materials have no `map_d`).
    let dir = scratch("cutout_override");
    leaf_scene(&dir, &half_mask(true));
    write(&dir, "b.mtl", "newmtl board\nKd 0.5 0.5 0.5\n");
    write(&dir, "board.obj", BOARD_OBJ);
    let toml = "[materials.plain]\ntype = \"diffuse\"\n\
                [[prototypes.leaf.objects]]\ntype = \"mesh\"\nfile = \"leaf.obj\"\n\
                [[prototypes.board.objects]]\ntype = \"mesh\"\nfile = \"board.obj\"\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"leaf\"\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"leaf\"\nmaterial = \"plain\"\n\
                transform = { translate = [10, 0, 0] }\n\
                [[objects]]\ntype = \"instance\"\nprototype = \"board\"\n\
                transform = { translate = [20, 0, 0] }\n";
    let mut scene = Scene::load(&write(&dir, "i.toml", toml)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let leaf = scene.prototypes[1].meshes[0].materials[0];
    assert!(scene.materials[leaf as usize].maps.alpha.is_some());
    scene.instances[2].material = Some(leaf);
    for backend in Backend::ALL {
        let accel = Accel::build(&scene, backend, None).unwrap();
        for ray in down_rays() {
            let opaque = ray.origin.x < 0.0;
            for (inst, shift) in [(0, 0.0), (1, 10.0), (2, 20.0)] {
                let ray = Ray::new(ray.origin + Vec3::X * shift, ray.dir);
                let hit = accel.intersect(&ray);
                let mut shadow = ray;
                shadow.tfar = 4.5;
                let mut all = Vec::new();
                accel.intersect_all(&ray, &mut all);
                let what = format!("{backend:?}, instance {inst}: {ray:?}");
                // The leaf (or board) is there where its instance's mask,
                // if any, is opaque.
                let there = opaque || inst == 1;
                assert_eq!(accel.occluded(&shadow), there, "{what}");
                let expected = match (there, inst) {
                    (true, _) => Some((0, 4.0)),
                    (false, 2) => None,
                    (false, _) => Some((1, 5.0)),
                };
                let found = hit.is_hit().then_some(hit.geom_id);
                assert_eq!(found, expected.map(|(id, _)| id), "{what}");
                if let Some((_, t)) = expected {
                    assert!(at(hit.t, t), "{what}: t = {}", hit.t);
                }
                assert_eq!(
                    all.iter().filter(|h| at(h.t, 4.0)).count(),
                    usize::from(there),
                    "{what}"
                );
                if hit.is_hit() {
                    assert_eq!(hit.inst_id, inst, "{what}");
                }
            }
        }
        accel.check().unwrap();
    }
}

#[test]
fn a_missing_mask_is_a_warning_and_nothing_is_cut() {
    let dir = scratch("cutout_missing");
    write(&dir, "m.mtl", LEAF_MTL);
    let scene = Scene::load(&write(&dir, "leaf.obj", LEAF_OBJ)).unwrap();
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("m.mtl:3: texture") && warnings.contains("mask.png"),
        "{warnings}"
    );
    for backend in Backend::ALL {
        let accel = Accel::build(&scene, backend, None).unwrap();
        for ray in down_rays() {
            assert_eq!(accel.intersect(&ray).geom_id, 0, "{backend:?}");
        }
    }
}

#[test]
fn a_render_with_cut_outs_is_the_same_for_any_thread_count() {
    let dir = scratch("cutout_threads");
    leaf_scene(&dir, &half_mask(true));
    let mut images = Vec::new();
    for threads in ["1", "2"] {
        let out = format!("t{threads}.exr");
        let run = sturmray(
            &dir,
            &[
                "render",
                "leaf.obj",
                "-o",
                &out,
                "--width",
                "24",
                "--spp",
                "2",
                "--threads",
                threads,
            ],
        );
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        images.push(std::fs::read(dir.join(&out)).unwrap());
    }
    assert_eq!(images[0], images[1]);
}

#[test]
fn a_checker_on_an_analytic_shape_moves_with_it() {
    let dir = scratch("object_checker");
    let offset = Vec3::new(5.17, 0.41, -0.2);
    let toml = format!(
        "[materials.c]\ntype = \"diffuse\"\n\
         albedo = {{ checker = [[1, 0, 0], [0, 0, 1]], scale = 0.3 }}\n\
         [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"c\"\n\
         [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"c\"\n\
         transform = {{ translate = [{}, {}, {}] }}\n",
        offset.x, offset.y, offset.z
    );
    let scene = Scene::load(&write(&dir, "c.toml", &toml)).unwrap();
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let albedo = |ray: &Ray| {
        let hit = accel.intersect(ray);
        assert!(hit.is_hit(), "{ray:?}");
        let it = scene.interaction(ray, &hit);
        (
            it.surface(&scene.materials[it.material as usize]).albedo,
            it.p,
        )
    };
    let mut differs_in_world_space = 0;
    for k in 0..100 {
        let (x, y) = ((k % 10) as f32 * 0.14 - 0.63, (k / 10) as f32 * 0.14 - 0.62);
        let ray = Ray::new(Vec3::new(x, y, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let moved = Ray::new(ray.origin + offset, ray.dir);
        let ((a, _), (b, p)) = (albedo(&ray), albedo(&moved));
        assert_eq!(a, b, "{ray:?}");
        // The scene material's checker, unplaced, would lie in world space.
        differs_in_world_space +=
            usize::from(scene.materials[0].albedo_at(p, Vec3::ZERO, None) != b);
    }
    // So the test can fail: in world space the pattern would not follow.
    assert!(differs_in_world_space > 10, "{differs_in_world_space}");
}

/// A 16 × 1 grey PNG, 8 bits: `value(x)` for texel x.
fn grey_row(value: impl Fn(u32) -> u8) -> Vec<u8> {
    let data: Vec<u8> = (0..16).map(value).collect();
    png_bytes(16, 1, png::ColorType::Grayscale, &data)
}

/// A 1 × 1 RGB PNG of one colour.
fn rgb_png(rgb: [u8; 3]) -> Vec<u8> {
    png_bytes(1, 1, png::ColorType::Rgb, &rgb)
}

/// The square [-1, 1]² at z = 0 (u along x, v along y), whose material
/// `m` is `mtl` (after its Kd), with `image` as `map.png`, and the
/// shading points where rays down the z axis at each of `at` meet it.
fn square_hits(
    name: &str,
    mtl: &str,
    image: &[u8],
    at: &[(f32, f32)],
) -> (Scene, Vec<Interaction>) {
    let dir = scratch(name);
    std::fs::write(dir.join("map.png"), image).unwrap();
    write(&dir, "m.mtl", &format!("newmtl m\nKd 0.5 0.5 0.5\n{mtl}\n"));
    let obj = "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";
    let scene = Scene::load(&write(&dir, "m.obj", obj)).unwrap();
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let hits = at
        .iter()
        .map(|&(x, y)| {
            let ray = Ray::new(Vec3::new(x, y, 3.0), Vec3::new(0.0, 0.0, -1.0));
            scene.interaction(&ray, &accel.intersect(&ray))
        })
        .collect();
    (scene, hits)
}

/// The shading and geometric normals where a ray down the z axis at (x, y)
/// meets the square of [`square_hits`].
fn mapped_normals(name: &str, mtl: &str, image: &[u8], x: f32, y: f32) -> (Vec3, Vec3) {
    let (scene, hits) = square_hits(name, mtl, image, &[(x, y)]);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    (hits[0].ns, hits[0].n)
}

#[test]
fn a_linear_height_ramp_tilts_the_normal_by_its_slope() {
    // Heights rising 16/255 a texel, 16 texels across u: dh/du = 256/255
    // (bilinear between texel centres, linear data); × -bm 0.5, over a
    // square 2 wide in u: the height rises s = 0.5 · 256/255 per 2 along x.
    let ramp = grey_row(|x| (16 * x) as u8);
    let (ns, n) = mapped_normals("bump", "bump -bm 0.5 map.png", &ramp, -0.1, 0.3);
    let slope = 0.5 * 256.0 / 255.0 / 2.0;
    let expected = Vec3::new(-slope, 0.0, 1.0).normalize();
    assert!((ns - expected).length() < 1e-3, "{ns} for {expected}");
    assert_eq!(n, Vec3::Z, "the geometric normal stays");
    // Twice the multiplier, twice the slope; a flat map changes nothing.
    let (steeper, _) = mapped_normals("bump2", "map_Bump -bm 1 map.png", &ramp, -0.1, 0.3);
    assert!(
        (steeper.x / steeper.z + 2.0 * slope).abs() < 1e-3,
        "{steeper}"
    );
    let (flat, _) = mapped_normals("bump0", "bump map.png", &grey_row(|_| 90), 0.2, 0.3);
    assert_eq!(flat, Vec3::Z);
}

#[test]
fn a_normal_map_turns_the_normal_in_the_tangent_frame() {
    // (0.6, 0, 0.8) in tangent space: RGB (0.8, 0.5, 0.9), as 8 bits.
    let map = rgb_png([204, 128, 230]);
    let (ns, n) = mapped_normals("norm", "norm map.png", &map, 0.3, -0.2);
    let decoded = |c: f32| 2.0 * c / 255.0 - 1.0;
    let expected = Vec3::new(decoded(204.0), decoded(128.0), decoded(230.0)).normalize();
    // The tangent is dp/du = +x, the bitangent +y, the normal +z.
    assert!((ns - expected).length() < 1e-5, "{ns} for {expected}");
    assert!(ns.x > 0.55, "{ns}");
    assert_eq!(n, Vec3::Z);
}

/// A 64 × 1 RGB PNG: texels x < 32 `left`, the others `right`.
fn halves_png(left: u8, right: u8) -> Vec<u8> {
    let data: Vec<u8> = (0..64)
        .flat_map(|x| [if x < 32 { left } else { right }; 3])
        .collect();
    png_bytes(64, 1, png::ColorType::Rgb, &data)
}

/// The material's values at the hit.
fn surface(scene: &Scene, it: &Interaction) -> Surface {
    it.surface(&scene.materials[it.material as usize])
}

#[test]
fn a_black_specular_map_removes_the_highlight() {
    // Plastic (Ks 0.5, Ns 100) whose map_Ks is black on the left, white on
    // the right: u < 0.5 is x < 0.
    let mtl = "Ks 0.5 0.5 0.5\nNs 100\nmap_Ks -clamp on map.png";
    let (scene, hits) = square_hits(
        "map_ks",
        mtl,
        &halves_png(0, 255),
        &[(-0.5, 0.0), (0.5, 0.0)],
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = &scene.materials[hits[0].material as usize];
    let (dark, bright) = (surface(&scene, &hits[0]), surface(&scene, &hits[1]));
    assert_eq!(
        (dark.specular, bright.specular),
        (Vec3::ZERO, Vec3::splat(0.5))
    );
    // Seen and lit along the mirror direction, 30 degrees off the normal.
    let wo = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
    let wi = Vec3::new(-wo.x, 0.0, wo.z);
    let diffuse = Vec3::splat(0.5) / std::f32::consts::PI;
    // Whitted's local model: the lobe is gone, Lambert alone is left.
    assert_eq!(material.local_brdf(&dark, Vec3::Z, wo, wi), diffuse);
    assert!(material.local_brdf(&bright, Vec3::Z, wo, wi).x > diffuse.x + 1.0);
    // The path tracer's: the coat's F0 is the mapped Ks, zero here.
    let Bsdf::Plastic(Plastic { specular, .. }) = Bsdf::at(material, &dark) else {
        panic!("plastic");
    };
    assert_eq!(specular, Vec3::ZERO);
    let frame = hits[0].frame();
    let eval = |s: &Surface| Bsdf::at(material, s).eval(&frame, wo, wi).x;
    assert!(
        eval(&dark) < 0.2 && eval(&bright) > 1.0,
        "{} {}",
        eval(&dark),
        eval(&bright)
    );
}

#[test]
fn roughness_and_metalness_maps_vary_a_metal_across_its_surface() {
    // Linear data maps: 26/255 ≈ 0.1 on the left, 1 on the right.
    let (scene, hits) = square_hits(
        "map_pr",
        "Pm 1\nPr 0.5\nmap_Pr -clamp on map.png",
        &halves_png(26, 255),
        &[(-0.5, 0.0), (0.5, 0.0)],
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = &scene.materials[hits[0].material as usize];
    let roughness = |it: &Interaction| {
        let Bsdf::Metal(Metal { roughness, .. }) = Bsdf::at(material, &surface(&scene, it)) else {
            panic!("a metal");
        };
        roughness
    };
    // Pr × map, and GGX α is its square.
    let smooth = 0.5 * 26.0 / 255.0;
    assert!((roughness(&hits[0]) - smooth * smooth).abs() < 1e-6);
    assert!((roughness(&hits[1]) - 0.25).abs() < 1e-6);
    // Where the metalness map is below one half the metal is its
    // dielectric counterpart: plastic of F0 0.04 over the albedo.
    let (scene, hits) = square_hits(
        "map_pm",
        "Pr 0.5\nmap_Pm -clamp on map.png",
        &halves_png(0, 255),
        &[(-0.5, 0.0), (0.5, 0.0)],
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = &scene.materials[hits[0].material as usize];
    assert_eq!(
        Bsdf::at(material, &surface(&scene, &hits[0])),
        Bsdf::Plastic(Plastic {
            albedo: Vec3::splat(0.5),
            specular: Vec3::splat(sturmray::shading::DIELECTRIC_F0),
            roughness: 0.25,
        })
    );
    assert_eq!(
        Bsdf::at(material, &surface(&scene, &hits[1])),
        Bsdf::Metal(Metal {
            f0: Vec3::splat(0.5),
            roughness: 0.25,
        })
    );
}

#[test]
fn a_missing_map_warns_and_keeps_the_constant_and_a_map_without_a_parameter_warns() {
    let (scene, hits) = square_hits(
        "map_missing",
        "Ks 0.3 0.3 0.3\nmap_Ks gone.png\nmap_Pr map.png",
        &halves_png(0, 255),
        &[(0.5, 0.0)],
    );
    let warnings = scene.warnings.join("\n");
    assert!(
        warnings.contains("m.mtl:4: texture") && warnings.contains("gone.png"),
        "{warnings}"
    );
    // Plastic has no roughness to scale: map_Pr is named and left out.
    assert!(
        warnings.contains("m.mtl:5: material `m` is plastic"),
        "{warnings}"
    );
    assert_eq!(scene.warnings.len(), 2, "{warnings}");
    let material = &scene.materials[hits[0].material as usize];
    assert!(material.maps.roughness.is_none() && material.maps.specular.is_none());
    assert_eq!(surface(&scene, &hits[0]).specular, Vec3::splat(0.3));
}

/// A floor [-2, 2]² at z = 0 (Kd 0.5) under a downward-facing lamp over
/// [-0.5, 0.5]² at z = 1.5, as OBJ text; the lamp is the faces `lamp`
/// gives (after the floor's four vertices).
fn lamp_obj(lamp: &str) -> String {
    format!(
        "mtllib m.mtl\nv -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n\
         usemtl floor\nf 1 2 3 4\n{lamp}"
    )
}

/// The scene around a lamp OBJ: a camera in front, above, `integrator`.
fn lamp_scene(dir: &std::path::Path, name: &str, obj: &str, integrator: &str) -> Scene {
    write(dir, &format!("{name}.obj"), obj);
    let toml = format!(
        "[camera]\neye = [0, -5, 4]\nlook_at = [0, 0, 0]\nfov = 50\nwidth = 32\nheight = 24\n\
         [render]\nspp = 64\nintegrator = \"{integrator}\"\n\
         [[objects]]\ntype = \"mesh\"\nfile = \"{name}.obj\"\n"
    );
    let scene = Scene::load(&write(dir, &format!("{name}.toml"), &toml)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    scene
}

#[test]
fn an_emission_map_lights_the_floor_as_the_lamp_cut_at_its_dark_edge() {
    use sturmray::render::{RenderOptions, render};
    let dir = scratch("map_ke");
    // Black where u < 0.5 (x < 0), white beyond; clamped, so nothing
    // wraps in at the edges. The seam's bilinear ramp is symmetric about
    // u = 0.5, so the lamp's power is the half lamp's exactly.
    std::fs::write(dir.join("half.png"), halves_png(0, 255)).unwrap();
    write(
        &dir,
        "m.mtl",
        "newmtl floor\nKd 0.5 0.5 0.5\n\
         newmtl lamp\nKd 0 0 0\nKe 4 4 4\nmap_Ke -clamp on half.png\n\
         newmtl half\nKd 0 0 0\nKe 4 4 4\nnewmtl dark\nKd 0 0 0\n",
    );
    // The corners go round so that the lamp faces down (-z).
    let mapped = lamp_obj(
        "v -0.5 -0.5 1.5\nv -0.5 0.5 1.5\nv 0.5 0.5 1.5\nv 0.5 -0.5 1.5\n\
         vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\nusemtl lamp\nf 5/1 6/2 7/3 8/4\n",
    );
    let cut = lamp_obj(
        "v -0.5 -0.5 1.5\nv -0.5 0.5 1.5\nv 0 0.5 1.5\nv 0 -0.5 1.5\nv 0.5 0.5 1.5\n\
         v 0.5 -0.5 1.5\nusemtl dark\nf 5 6 7 8\nusemtl half\nf 8 7 9 10\n",
    );
    let options = RenderOptions {
        threads: Some(2),
        ..RenderOptions::default()
    };
    for integrator in ["whitted", "path"] {
        let image = |name: &str, obj: &str| {
            let scene = lamp_scene(&dir, name, obj, integrator);
            let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
            render(&scene, &accel, &options)
                .unwrap()
                .film
                .layers()
                .beauty
        };
        let (mapped, cut) = (image("mapped", &mapped), image("cut", &cut));
        // Image columns left of the middle see x < 0 (the camera looks
        // along +y from x = 0).
        for (half, columns) in [("left", 0..16), ("right", 16..32)] {
            let pixels = |image: &[[f32; 3]]| -> Vec<f64> {
                (0..24 * 32)
                    .filter(|i| columns.contains(&(i % 32)))
                    .map(|i| f64::from(image[i][1]))
                    .collect()
            };
            let (a, b) = (pixels(&mapped), pixels(&cut));
            let n = a.len() as f64;
            let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
            // The two renders differ only by their noise: the same camera
            // rays meet the same floor, where one lamp is sampled uniformly
            // over its whole area and the other over its bright half. The
            // pixels' differences are independent estimates of zero, so
            // their mean lies within 4 standard errors of it (a chance of
            // 6e-5 of failing per comparison if nothing were wrong); the
            // standard error comes from the same differences.
            let d: Vec<f64> = a.iter().zip(&b).map(|(a, b)| a - b).collect();
            let (md, mb) = (mean(&d), mean(&b));
            let se = (d.iter().map(|x| (x - md) * (x - md)).sum::<f64>() / (n - 1.0) / n).sqrt();
            assert!(
                md.abs() <= 4.0 * se,
                "{integrator}, {half}: mapped {} against cut {mb} (standard error {se})",
                mean(&a)
            );
            // And the comparison can fail: its noise is a small part of
            // the difference between the halves.
            assert!(se < 0.02 * mb, "{integrator}, {half}: {se} of {mb}");
        }
        let brightness = |image: &[[f32; 3]], columns: std::ops::Range<usize>| -> f64 {
            (0..24 * 32)
                .filter(|i| columns.contains(&(i % 32)))
                .map(|i| f64::from(image[i][1]))
                .sum()
        };
        // The floor's half under the bright half of the lamp is the
        // brighter. A lamp 1.5 above the floor lights both halves of it
        // (measured: 4.28 against 3.04 with Whitted), so the margin is small;
        // an ignored map would give equal halves (and fail above as well).
        assert!(
            brightness(&mapped, 16..32) > 1.25 * brightness(&mapped, 0..16),
            "{integrator}: {} {}",
            brightness(&mapped, 16..32),
            brightness(&mapped, 0..16)
        );
    }
}
