//! The scenes `sturmray bench` measures: bumpy spheres generated at run time
//! (10k to 1M triangles; nothing large is stored in the repository), the torus
//! knot and the analytic gallery.

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::geometry::Mesh;
use crate::lights::Light;
use crate::math::Vec3;
use crate::scene::{Camera, RenderSettings, Scene};
use crate::shading::Material;

/// Triangle counts of the generated meshes.
pub fn mesh_sizes(quick: bool) -> &'static [usize] {
    if quick {
        &[10_000, 100_000]
    } else {
        &[10_000, 100_000, 1_000_000]
    }
}

/// The scene files measured besides the generated meshes, under `root`.
pub fn scene_files(root: &Path) -> Vec<PathBuf> {
    let mut files = vec![root.join("knot.toml")];
    let gallery = ["mixed", "quadrics", "tori", "algebraic"];
    files.extend(gallery.map(|name| root.join(format!("gallery/{name}.toml"))));
    files
}

/// Loads the scene files, then appends the generated meshes.
pub fn scenes(files: &[PathBuf], sizes: &[usize]) -> Result<Vec<Scene>> {
    let mut scenes = files
        .iter()
        .map(|f| Scene::load(f))
        .collect::<Result<Vec<_>>>()?;
    scenes.extend(sizes.iter().map(|&n| bumpy_sphere(n)));
    Ok(scenes)
}

/// A closed, bumpy sphere of about `triangles` triangles (at least that many):
/// a cube's six faces, each an n×n grid of quads, pushed out onto the unit
/// sphere and displaced radially by a few smooth waves, so the BVH sees
/// neither a regular grid nor a random soup. Framed by a camera with a point
/// light beside it.
pub fn bumpy_sphere(triangles: usize) -> Scene {
    let n = ((triangles as f64 / 12.0).sqrt().ceil() as usize).max(1);
    let mut positions = Vec::with_capacity(6 * (n + 1) * (n + 1));
    let mut faces = Vec::with_capacity(12 * n * n);
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let base = positions.len() as u32;
            for j in 0..=n {
                for i in 0..=n {
                    let (a, b) = (
                        2.0 * i as f32 / n as f32 - 1.0,
                        2.0 * j as f32 / n as f32 - 1.0,
                    );
                    let mut cube = [0.0f32; 3];
                    cube[axis] = side;
                    cube[(axis + 1) % 3] = side * a;
                    cube[(axis + 2) % 3] = b;
                    let d = Vec3::from(cube).normalize();
                    let bump = 0.04 * (7.0 * d.x).sin() * (9.0 * d.y).sin() * (8.0 * d.z).sin()
                        + 0.01 * (31.0 * d.x + 17.0 * d.z).sin();
                    positions.push((1.0 + bump) * d);
                }
            }
            let at = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
            for j in 0..n {
                for i in 0..n {
                    faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                    faces.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
    }
    let mesh = Mesh {
        name: "bumpy sphere".into(),
        materials: vec![0; faces.len()],
        positions,
        triangles: faces,
        ..Mesh::default()
    };
    let camera = Camera::framing(mesh.bounds(), 640, 480);
    let light = Light::Point {
        position: camera.eye + Vec3::new(0.5, 1.0, 0.0),
        intensity: Vec3::splat(10.0),
    };
    let mut scene = Scene {
        name: format!("sphere-{}", short_count(mesh.triangles.len())),
        camera,
        render: RenderSettings::default(),
        background: Vec3::ZERO,
        environment: None,
        fogs: Vec::new(),
        materials: vec![Material::default_grey()],
        meshes: vec![mesh],
        shapes: Vec::new(),
        prototypes: Vec::new(),
        instances: Vec::new(),
        lights: vec![light],
        light_picker: Default::default(),
        warnings: Vec::new(),
        // Generated, read from no file.
        sources: Vec::new(),
        import: None,
    };
    scene.gather_emitters();
    scene
}

/// 10k, 100k, 1M: the name of a generated mesh.
fn short_count(n: usize) -> String {
    if n >= 1_000_000 {
        format!("{}M", n / 1_000_000)
    } else {
        format!("{}k", n / 1_000)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bumpy_sphere_is_closed_and_has_the_triangles_asked_for() {
        let scene = bumpy_sphere(10_000);
        let mesh = &scene.meshes[0];
        assert!((10_000..11_000).contains(&mesh.triangles.len()));
        assert_eq!(scene.name, "sphere-10k");
        // Every triangle has area and faces outwards (the grids wind consistently).
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 0.0 && n.dot(a + b + c) > 0.0, "{t:?}");
        }
        let radii = mesh.positions.iter().map(|p| p.length());
        assert!(radii.clone().all(|r| (0.94..=1.06).contains(&r)));
    }
}
