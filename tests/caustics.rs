//! Caustics by the photon pass: a mirror's caustic against the closed form of
//! its mirror-image light, locally and in total at the default radius, a glass
//! sphere's focused spot, the default radius set by the caustic and not by the
//! floor, the plan deciding when the pass exists, and determinism across
//! thread counts.

mod common;

use std::f32::consts::PI;

use common::{scratch, sturmray, write};
use sturmray::accel::{Accel, Backend};
use sturmray::math::Vec3;
use sturmray::render::photon::RadiusFrom;
use sturmray::render::{PhotonMap, Plan, RenderOptions, render, thread_pool};
use sturmray::scene::Scene;

/// A square [-s, s]² at height z, as OBJ text.
fn square(s: f32, z: f32) -> String {
    format!("v -{s} -{s} {z}\nv {s} -{s} {z}\nv {s} {s} {z}\nv -{s} {s} {z}\nf 1 2 3 4\n")
}

/// Loads `text` as a scene beside a floor, [-4, 4]² at z = 0, and a square
/// mirror, [-3, 3]² at z = 1.2.
fn load(name: &str, text: &str) -> Scene {
    load_on(name, 4.0, text)
}

/// `load` with a floor [-half, half]².
fn load_on(name: &str, half: f32, text: &str) -> Scene {
    let dir = scratch(name);
    write(&dir, "floor.obj", &square(half, 0.0));
    write(&dir, "mirror.obj", &square(3.0, 1.2));
    Scene::load(&write(&dir, "s.toml", text)).unwrap()
}

fn options(threads: usize) -> RenderOptions {
    RenderOptions {
        threads: Some(threads),
        ..RenderOptions::default()
    }
}

fn build_map(scene: &Scene, accel: &Accel, threads: usize) -> PhotonMap {
    let settings = scene.render.photons;
    let pool = thread_pool(Some(threads)).unwrap();
    let never = || false;
    let (map, counts) = pool
        .install(|| {
            PhotonMap::build(
                scene,
                accel,
                settings.count,
                settings.radius,
                scene.render.max_depth,
                &never,
            )
        })
        .expect("nothing stops the pass");
    // Every photon leaves its light on a ray.
    assert!(counts.rays.photon >= u64::from(settings.count));
    assert_eq!(counts.stored, map.len());
    map
}

/// A point light of intensity I = 1 at height 1 between a diffuse floor and a
/// mirror of reflectance 0.8 at height 1.2, looked at from just above the light.
const MIRROR: &str = r#"
[camera]
eye = [0, 0, 1.1]
look_at = [0, 0, 0]
fov = 2
width = 9
height = 9
[render]
spp = 1
photons = { count = 1_000_000, radius = 0.1 }
[materials.paint]
type = "diffuse"
albedo = [0.5, 0.5, 0.5]
[materials.chrome]
type = "mirror"
albedo = [0.8, 0.8, 0.8]
[[objects]]
type = "mesh"
file = "floor.obj"
material = "paint"
[[objects]]
type = "mesh"
file = "mirror.obj"
material = "chrome"
[[lights]]
type = "point"
position = [0, 0, 1]
intensity = [1, 1, 1]
"#;

/// The mirror's caustic irradiance at floor point x: the mirror-image light,
/// at height 2·1.2 − 1 = 1.4, times the reflectance: R·I·cosθ/d² = R h / d³.
fn mirror_irradiance(x: Vec3) -> f32 {
    let image = Vec3::new(0.0, 0.0, 1.4);
    let d = image.distance(x);
    0.8 * 1.4 / (d * d * d)
}

/// The mean of `mirror_irradiance` over the disk of radius r around `c` on the
/// floor (midpoint rule in polar coordinates): what a gather of that radius
/// estimates.
fn disk_mean(c: Vec3, r: f32) -> f32 {
    let (rings, sectors) = (64, 64);
    let mut sum = 0.0;
    for i in 0..rings {
        let rho = (i as f32 + 0.5) / rings as f32 * r;
        for j in 0..sectors {
            let phi = (j as f32 + 0.5) / sectors as f32 * 2.0 * PI;
            let x = c + rho * Vec3::new(phi.cos(), phi.sin(), 0.0);
            sum += mirror_irradiance(x) * rho;
        }
    }
    // ∫ E ρ dρ dφ over the disk, divided by its area π r².
    sum * (r / rings as f32) * (2.0 * PI / sectors as f32) / (PI * r * r)
}

#[test]
fn a_mirror_caustic_matches_the_mirror_image_light() {
    let scene = load("mirror", MIRROR);
    assert!(Plan::for_scene(&scene).photon);
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let map = build_map(&scene, &accel, 2);
    let r = map.radius().value;
    // Five disjoint gather disks. Together they hold about 5 600 of the million
    // photons, so the sum's relative standard deviation is about 1/√5600 ≈ 1.3 %;
    // 5 % is about four of them.
    let centres = [(0.0, 0.0), (0.5, 0.0), (-0.5, 0.0), (0.0, 0.5), (0.0, -0.5)];
    let (mut got, mut expected) = (0.0, 0.0);
    for (x, y) in centres {
        let c = Vec3::new(x, y, 0.0);
        got += map.caustic(c, Vec3::Z, |_| Vec3::ONE).x;
        expected += disk_mean(c, r);
    }
    assert!(
        (got / expected - 1.0).abs() < 0.05,
        "caustic irradiance {got} vs {expected}"
    );
    // The floor's underside, facing away from the light, receives nothing.
    assert_eq!(map.caustic(Vec3::ZERO, -Vec3::Z, |_| Vec3::ONE), Vec3::ZERO);

    // Rendered: the floor under the camera shows ρ/π times the direct irradiance
    // (I/1² = 1, exact by the shadow ray) plus the caustic's. The centre disk
    // alone holds about 1 300 photons: σ ≈ 2.8 % of the caustic part, under
    // 1 % of the total; 4 % leaves room for that and the pixel's offset from
    // the disk's centre.
    let expected = 0.5 / PI * (1.0 + disk_mean(Vec3::ZERO, r));
    // The path tracer gathers the same map. At depth 1 its paths end after the
    // floor's bounce reaches the mirror (no floor-mirror-floor interreflection),
    // so it must show exactly what the Whitted tree shows.
    let path = load(
        "mirror-path",
        &MIRROR.replace("spp = 1", "spp = 1\nintegrator = \"path\"\nmax_depth = 1"),
    );
    for scene in [&scene, &path] {
        let out = render(scene, &accel, &options(2)).unwrap();
        assert!(out.stats.photon >= 1_000_000);
        let pixel = out.film.layers().beauty[4 * 9 + 4][0];
        assert!(
            (pixel / expected - 1.0).abs() < 0.04,
            "{:?}: pixel {pixel} vs {expected}",
            scene.render.integrator
        );
    }
}

/// A glass ball of radius 0.5 at height 1 over the floor, a point light of
/// intensity 9 above it (irradiance 1 at the floor's centre without the ball),
/// seen obliquely; `photons` is the count.
fn glass(name: &str, photons: u32, extra: &str) -> Scene {
    let settings = format!("photons = {{ count = {photons}, radius = 0.05 }}\n{extra}");
    glass_on(name, 4.0, &settings)
}

/// The glass ball over a floor [-half, half]², with `render` lines of its own.
fn glass_on(name: &str, half: f32, render: &str) -> Scene {
    load_on(
        name,
        half,
        &format!(
            r#"
[camera]
eye = [0, -3, 1.5]
look_at = [0, 0, 0]
fov = 30
width = 32
height = 32
[render]
spp = 1
{render}
[materials.paint]
type = "diffuse"
albedo = [0.8, 0.8, 0.8]
[materials.glass]
type = "dielectric"
ior = 1.5
[[objects]]
type = "mesh"
file = "floor.obj"
material = "paint"
[[objects]]
type = "sphere"
radius = 0.5
material = "glass"
transform = {{ translate = [0, 0, 1] }}
[[lights]]
type = "point"
position = [0, 0, 3]
intensity = [9, 9, 9]
"#
        ),
    )
}

#[test]
fn the_mirror_caustics_total_power_is_right_at_the_default_radius() {
    // The default count and radius: 200 000 photons, the radius they call for.
    let scene = load(
        "mirror-default",
        &MIRROR.replace("photons = { count = 1_000_000, radius = 0.1 }", ""),
    );
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let map = build_map(&scene, &accel, 2);
    let radius = map.radius();
    assert_eq!(radius.from, RadiusFrom::Photons);
    let r = radius.value;
    // Gathers on a grid of spacing h = r/2 over the floor and a rim r wide
    // around it, so each photon lies in about π r²/h² ≈ 12.6 disks wherever it
    // is: Σ gather · h² is the total caustic power the floor receives.
    let h = r / 2.0;
    let n = ((4.0 + r) / h).ceil() as i32;
    let mut gathered = 0.0f64;
    for i in -n..=n {
        for j in -n..=n {
            let p = Vec3::new(i as f32 * h, j as f32 * h, 0.0);
            gathered += f64::from(map.caustic(p, Vec3::Z, |_| Vec3::ONE).x);
        }
    }
    gathered *= f64::from(h * h);
    // The closed form: the mirror-image light's irradiance over [-4, 4]²
    // (midpoint rule, 800² cells, far finer than the irradiance varies).
    let cells = 800;
    let side = 8.0 / cells as f32;
    let mut expected = 0.0f64;
    for i in 0..cells {
        for j in 0..cells {
            let x = Vec3::new(
                -4.0 + (i as f32 + 0.5) * side,
                -4.0 + (j as f32 + 0.5) * side,
                0.0,
            );
            expected += f64::from(mirror_irradiance(x) * side * side);
        }
    }
    // The map holds tens of thousands of photons (about 0.5% noise in their
    // total), and the grid counts each in 12.6 disks on average, within a few
    // tenths of a percent over so many: 2% is four times both together.
    assert!(
        (gathered / expected - 1.0).abs() < 0.02,
        "caustic power {gathered} vs {expected} at radius {r}"
    );
}

#[test]
fn the_default_radius_is_the_caustics_scale_not_the_floors() {
    // The glass ball's caustic on a floor 8 units wide and on one 2000 wide:
    // the old rule, 1/200 of the scene's diagonal, gave 0.06 and 14.1.
    let radius = |name: &str, half: f32| {
        let scene = glass_on(name, half, "");
        let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
        let map = build_map(&scene, &accel, 2);
        map.radius()
    };
    let small = radius("floor-8", 4.0);
    let large = radius("floor-2000", 1000.0);
    assert_eq!(large.from, RadiusFrom::Photons);
    // The ball of radius 0.5 focuses the light into a spot a few tenths
    // across: the radius is a fraction of that.
    assert!(large.value > 0.0 && large.value < 0.05, "{large:?}");
    // The wide floor adds only the 1% of photons that glass throws far away,
    // too sparse to count: they shift the middle half of the distances the
    // rule averages by half a percent of them, a few percent of the radius.
    assert!(
        (large.value / small.value - 1.0).abs() < 0.1,
        "{large:?} vs {small:?}"
    );
}

#[test]
fn a_glass_ball_focuses_a_bright_spot_under_itself() {
    let lit = glass("glass", 100_000, "");
    let accel = Accel::build(&lit, Backend::Embree, None).unwrap();
    let map = build_map(&lit, &accel, 2);
    // The ball (a lens of focal length nR/2(n−1) = 0.75) images the light just
    // below the floor: far more than the irradiance 1 the bare light gives.
    let spot = map.caustic(Vec3::ZERO, Vec3::Z, |_| Vec3::ONE).x;
    assert!(spot > 5.0, "caustic irradiance {spot}");

    let with = render(&lit, &accel, &options(2)).unwrap();
    let dark = glass("glass-dark", 0, "");
    let without = render(&dark, &accel, &options(2)).unwrap();
    assert_eq!(without.stats.photon, 0);
    let (a, b) = (with.film.layers().beauty, without.film.layers().beauty);
    // The floor's centre, at the image's centre, is in the ball's shadow for
    // direct light; the caustic lights it brighter than any pixel direct light
    // lights anywhere.
    let centre = a[16 * 32 + 16][0];
    let brightest_direct = b.iter().map(|p| p[0]).fold(0.0, f32::max);
    assert!(
        centre > 2.0 * brightest_direct,
        "{centre} vs {brightest_direct}"
    );
    assert!(b[16 * 32 + 16][0] < 0.01 * centre);
    // Photons only add light.
    assert!(a.iter().zip(&b).all(|(p, q)| p[0] >= q[0]));
}

#[test]
fn the_plan_has_a_photon_pass_only_for_light_specular_diffuse() {
    // Glass, a diffuse floor and a light: yes.
    let caustic = glass("plan-yes", 2_000, "");
    assert!(Plan::for_scene(&caustic).photon);
    assert!(
        Plan::for_scene(&caustic)
            .to_string()
            .contains("photon pass yes")
    );
    let accel = Accel::build(&caustic, Backend::Embree, None).unwrap();
    assert!(render(&caustic, &accel, &options(2)).unwrap().stats.photon >= 2_000);

    // The path tracer gathers photons too.
    let path = glass("plan-path", 2_000, "integrator = \"path\"");
    assert!(Plan::for_scene(&path).photon);

    // No photons asked for, or no lights: no pass.
    assert!(!Plan::for_scene(&glass("plan-zero", 0, "")).photon);
    let mut dark = caustic.clone();
    dark.lights.clear();
    assert!(!Plan::for_scene(&dark).photon);

    // A diffuse-only scene: no pass and not one photon ray.
    let diffuse = load(
        "plan-diffuse",
        &MIRROR.replace("material = \"chrome\"", "material = \"paint\""),
    );
    let plan = Plan::for_scene(&diffuse);
    assert!(
        !plan.photon && plan.to_string().contains("photon pass no"),
        "{plan}"
    );
    let accel = Accel::build(&diffuse, Backend::Embree, None).unwrap();
    assert_eq!(
        render(&diffuse, &accel, &options(2)).unwrap().stats.photon,
        0
    );

    // Only specular surfaces, nothing diffuse to catch the light: no pass.
    let only_glass = load(
        "plan-glass-only",
        &MIRROR.replace("material = \"paint\"", "material = \"chrome\""),
    );
    assert!(!Plan::for_scene(&only_glass).photon);
}

#[test]
fn photon_map_and_render_are_the_same_for_any_thread_count() {
    let scene = glass("threads", 20_000, "");
    let accel = Accel::build(&scene, Backend::Embree, None).unwrap();
    let one = build_map(&scene, &accel, 1);
    assert!(!one.is_empty());
    assert_eq!(one, build_map(&scene, &accel, 2));
    let bits = |threads| -> Vec<u64> {
        let out = render(&scene, &accel, &options(threads)).unwrap();
        out.film
            .pixels
            .iter()
            .flat_map(|p| p.radiance.map(f64::to_bits))
            .collect()
    };
    assert_eq!(bits(1), bits(2));
}

#[test]
fn photon_settings_are_checked_and_named() {
    let dir = scratch("photon-errors");
    for (setting, key) in [
        (
            "photons = { count = 10, radius = 0 }",
            "render.photons.radius",
        ),
        (
            "photons = { count = 10, radius = -1 }",
            "render.photons.radius",
        ),
        ("photons = { count = 10, radus = 1 }", "radus"),
        ("photons = { count = -1 }", "count"),
    ] {
        let path = write(&dir, "bad.toml", &format!("[render]\n{setting}\n"));
        let err = Scene::load(&path).unwrap_err().to_string();
        assert!(err.contains(key), "{setting}: {err}");
    }
    // Left out: 200 000 photons and a radius from the photons.
    let scene = glass("photon-defaults", 1, "").render.photons;
    let unset = MIRROR.replace("photons = { count = 1_000_000, radius = 0.1 }", "");
    let defaults = load("photon-unset", &unset).render.photons;
    assert_eq!((defaults.count, defaults.radius), (200_000, None));
    assert_eq!(scene.radius, Some(0.05));
}

#[test]
fn the_cli_prints_the_plan_and_counts_photon_rays() {
    let dir = scratch("photon-cli");
    write(&dir, "floor.obj", &square(4.0, 0.0));
    write(&dir, "mirror.obj", &square(3.0, 1.2));
    let text = MIRROR.replace("1_000_000", "5_000");
    write(&dir, "s.toml", &text);
    let info = sturmray(&dir, &["info", "s.toml"]);
    assert!(info.status.success());
    assert!(String::from_utf8_lossy(&info.stdout).contains("photon pass yes"));
    for (photons, expect_rays) in [("5000", true), ("0", false)] {
        let out = sturmray(
            &dir,
            &[
                "render",
                "s.toml",
                "--photons",
                photons,
                "--stats",
                "st.json",
            ],
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join("st.json")).unwrap()).unwrap();
        let rays = stats["rays"]["photon"].as_u64().unwrap();
        assert_eq!(rays >= 5000, expect_rays, "--photons {photons}: {rays}");
        assert_eq!(rays == 0, !expect_rays);
        // The report names the radius and where it came from.
        let report = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            report.contains("radius 1.000e-1 (render.photons.radius)"),
            expect_rays,
            "{report}"
        );
    }
    write(&dir, "u.toml", &text.replace(", radius = 0.1", ""));
    let out = sturmray(&dir, &["render", "u.toml"]);
    let report = String::from_utf8_lossy(&out.stderr);
    assert!(
        report.contains("(from the photons: 16 within it around a typical one of 4096 sampled)"),
        "{report}"
    );
    let diffuse = MIRROR.replace("material = \"chrome\"", "material = \"paint\"");
    write(&dir, "d.toml", &diffuse);
    let info = sturmray(&dir, &["info", "d.toml"]);
    assert!(String::from_utf8_lossy(&info.stdout).contains("photon pass no"));
}
