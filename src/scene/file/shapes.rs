//! The analytic objects of a scene file: which parameters each type takes,
//! and the surface and default clip box they make.

use glam::{DMat3, DVec3};

use super::super::obj::MAX_COORDINATE;
use super::schema::{ShapeFile, ShapeKind};
use crate::geometry::{Box3, Quadric, Surface};
use crate::poly::expr;

/// An error in one object: the parameter at fault ("" for the object as a
/// whole), so the message can name its line, and what was expected.
pub(super) type FieldError = (&'static str, String);

fn positive(name: &'static str, v: Option<f64>, meaning: &str) -> Result<f64, FieldError> {
    let v = v.ok_or(("", format!("missing `{name}` ({meaning})")))?;
    if v > 0.0 && v <= MAX_COORDINATE {
        Ok(v)
    } else {
        Err((
            name,
            format!("expected a number > 0 and at most {MAX_COORDINATE:e}, found {v}"),
        ))
    }
}

impl ShapeFile {
    /// The parameters set in the file, by name, to refuse the ones a type does not use.
    fn given(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        let fields: [(&'static str, bool); 8] = [
            ("radius", self.radius.is_some()),
            ("radii", self.radii.is_some()),
            ("major", self.major.is_some()),
            ("minor", self.minor.is_some()),
            ("a", self.a.is_some()),
            ("b", self.b.is_some()),
            ("c", self.c.is_some()),
            ("expr", self.expr.is_some()),
        ];
        for (name, set) in fields {
            if set {
                names.push(name);
            }
        }
        names
    }

    /// Refuses a parameter that the type, which takes `allowed`, does not use.
    fn takes(&self, allowed: &[&str]) -> Result<(), FieldError> {
        match self.given().into_iter().find(|g| !allowed.contains(g)) {
            Some(extra) => Err((
                extra,
                format!(
                    "`{extra}` does not apply to this type (it takes {})",
                    allowed.join(", ")
                ),
            )),
            None => Ok(()),
        }
    }

    fn radius(&self) -> Result<f64, FieldError> {
        positive("radius", self.radius, "the radius")
    }

    fn radii<const N: usize>(&self) -> Result<[f64; N], FieldError> {
        let radii = self
            .radii
            .as_ref()
            .ok_or(("", format!("missing `radii` ({N} semi-axes)")))?;
        let radii: [f64; N] = radii.as_slice().try_into().map_err(|_| {
            (
                "radii",
                format!("expected {N} numbers, found {}", radii.len()),
            )
        })?;
        for r in radii {
            positive("radii", Some(r), "")?;
        }
        Ok(radii)
    }
}

/// Diagonal quadric Σ sᵢ xᵢ² + b·x + c.
fn diagonal(s: [f64; 3], b: [f64; 3], c: f64) -> Surface {
    Surface::Quadric(Quadric {
        a: DMat3::from_diagonal(DVec3::from(s)),
        b: DVec3::from(b),
        c,
    })
}

fn clip(min: [f64; 3], max: [f64; 3]) -> Option<Box3> {
    Some(Box3 {
        min: DVec3::from(min),
        max: DVec3::from(max),
    })
}

/// The surface of an analytic object and its default clip box (None when the
/// surface bounds itself or, for general quadrics and algebraic surfaces, when
/// the file must give one). Each type's arm first names the parameters it
/// takes, so a type is added in one place.
pub(super) fn surface(
    kind: ShapeKind,
    f: &ShapeFile,
    constants: &[(&str, f64)],
) -> Result<(Surface, Option<Box3>), FieldError> {
    use ShapeKind::*;
    let inv2 = |r: f64| 1.0 / (r * r);
    Ok(match kind {
        Sphere => {
            f.takes(&["radius"])?;
            (
                Surface::Sphere {
                    radius: f.radius()?,
                },
                None,
            )
        }
        Ellipsoid => {
            f.takes(&["radii"])?;
            let [a, b, c] = f.radii::<3>()?;
            (
                diagonal([inv2(a), inv2(b), inv2(c)], [0.0; 3], -1.0),
                clip([-a, -b, -c], [a, b, c]),
            )
        }
        // Axis z, z in [-1, 1].
        Cylinder => {
            f.takes(&["radius"])?;
            let r = f.radius()?;
            (
                diagonal([1.0, 1.0, 0.0], [0.0; 3], -r * r),
                clip([-r, -r, -1.0], [r, r, 1.0]),
            )
        }
        // Apex at the origin, radius r at z = 1; one nappe, z in [0, 1].
        Cone => {
            f.takes(&["radius"])?;
            let r = f.radius()?;
            (
                diagonal([1.0, 1.0, -r * r], [0.0; 3], 0.0),
                clip([-r, -r, 0.0], [r, r, 1.0]),
            )
        }
        // x²/a² + y²/b² − z²/c² = 1, z in [-1, 1].
        Hyperboloid1 => {
            f.takes(&["radii"])?;
            let [a, b, c] = f.radii::<3>()?;
            let k = (1.0 + inv2(c)).sqrt();
            (
                diagonal([inv2(a), inv2(b), -inv2(c)], [0.0; 3], -1.0),
                clip([-a * k, -b * k, -1.0], [a * k, b * k, 1.0]),
            )
        }
        // x²/a² + y²/b² − z²/c² = −1: two sheets, |z| in [c, c + 1].
        Hyperboloid2 => {
            f.takes(&["radii"])?;
            let [a, b, c] = f.radii::<3>()?;
            let h = c + 1.0;
            let k = (h * h * inv2(c) - 1.0).sqrt();
            (
                diagonal([inv2(a), inv2(b), -inv2(c)], [0.0; 3], 1.0),
                clip([-a * k, -b * k, -h], [a * k, b * k, h]),
            )
        }
        // z = x²/a² + y²/b², z in [0, 1].
        Paraboloid => {
            f.takes(&["radii"])?;
            let [a, b] = f.radii::<2>()?;
            (
                diagonal([inv2(a), inv2(b), 0.0], [0.0, 0.0, -1.0], 0.0),
                clip([-a, -b, 0.0], [a, b, 1.0]),
            )
        }
        // z = x²/a² − y²/b², over x in [-a, a], y in [-b, b].
        HyperbolicParaboloid => {
            f.takes(&["radii"])?;
            let [a, b] = f.radii::<2>()?;
            (
                diagonal([inv2(a), -inv2(b), 0.0], [0.0, 0.0, -1.0], 0.0),
                clip([-a, -b, -1.0], [a, b, 1.0]),
            )
        }
        Quadric => {
            f.takes(&["a", "b", "c"])?;
            let a = f.a.ok_or((
                "",
                "missing `a` (a symmetric 3×3 matrix, as rows)".to_string(),
            ))?;
            let m = DMat3::from_cols_array_2d(&a).transpose();
            let b = DVec3::from(f.b.unwrap_or([0.0; 3]));
            let c = f.c.unwrap_or(0.0);
            for (name, finite) in [
                ("a", m.is_finite()),
                ("b", b.is_finite()),
                ("c", c.is_finite()),
            ] {
                if !finite {
                    return Err((name, "expected finite numbers".into()));
                }
            }
            let scale = m.to_cols_array().iter().fold(1.0f64, |s, v| s.max(v.abs()));
            if !m.abs_diff_eq(m.transpose(), 1e-12 * scale) {
                return Err(("a", "the matrix must be symmetric".into()));
            }
            let surface = Surface::Quadric(crate::geometry::Quadric { a: m, b, c });
            (surface, None)
        }
        Torus => {
            f.takes(&["major", "minor"])?;
            let major = positive("major", f.major, "the radius of the tube's centre circle")?;
            let minor = positive("minor", f.minor, "the radius of the tube")?;
            (Surface::Torus { major, minor }, None)
        }
        Algebraic => {
            f.takes(&["expr"])?;
            let missing = (
                "",
                "missing `expr`, e.g. \"x^4 + y^4 + z^4 - 1\"".to_string(),
            );
            let text = f.expr.as_deref().ok_or(missing)?;
            let poly = expr::parse(text, constants).map_err(|e| ("expr", e.to_string()))?;
            (Surface::Algebraic(Box::new(poly)), None)
        }
    })
}
