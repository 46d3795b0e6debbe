//! Analytic shapes for the geometry tests: a surface moved into place, and
//! a CSG tree as the one scene shape it is.

use glam::{DAffine3, DVec3};

use sturmray::geometry::{Box3, Csg, Shape, Surface};
use sturmray::poly::solve::Solver;

/// `surface` moved to `at`, cut by `clip` (in its own space), material 0.
pub fn placed(surface: Surface, at: DVec3, clip: Option<Box3>) -> Shape {
    Shape::new(
        surface,
        DAffine3::from_translation(at),
        clip,
        0,
        Solver::default(),
    )
    .unwrap()
}

/// A whole tree as one shape, as a scene holds it.
pub fn tree_shape(csg: Csg) -> Shape {
    placed(Surface::Csg(Box::new(csg)), DVec3::ZERO, None)
}
