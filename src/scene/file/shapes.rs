//! The analytic objects of a scene file: which parameters each type takes,
//! and the surface and default clip box they make.

use glam::{DAffine3, DMat3, DVec3};

use super::super::obj::MAX_COORDINATE;
use super::super::solids::{self, axis_frame};
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
        let fields: [(&'static str, bool); 20] = [
            ("radius", self.radius.is_some()),
            ("radii", self.radii.is_some()),
            ("major", self.major.is_some()),
            ("minor", self.minor.is_some()),
            ("a", self.a.is_some()),
            ("b", self.b.is_some()),
            ("c", self.c.is_some()),
            ("expr", self.expr.is_some()),
            ("op", self.op.is_some()),
            ("children", self.children.is_some()),
            ("normal", self.normal.is_some()),
            ("distance", self.distance.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("center", self.center.is_some()),
            ("hole", self.hole.is_some()),
            ("base", self.base.is_some()),
            ("cap", self.cap.is_some()),
            ("cap_radius", self.cap_radius.is_some()),
            ("caps", self.caps.is_some()),
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
/// takes, so a type is added in one place; `build` makes the types that are
/// more than one surface.
fn surface(
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
            f.takes(&["radius", "caps"])?;
            let r = f.radius()?;
            (
                diagonal([1.0, 1.0, 0.0], [0.0; 3], -r * r),
                clip([-r, -r, -1.0], [r, r, 1.0]),
            )
        }
        // Apex at the origin, radius r at z = 1; one nappe, z in [0, 1].
        Cone => {
            f.takes(&["radius", "caps"])?;
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
            (Surface::Algebraic(poly.into()), None)
        }
        Plane | Box | Disc | Csg => unreachable!("`build` makes these"),
    })
}

/// What an analytic object is made of, before it is placed.
pub(super) enum Built {
    /// A surface, its clip box (see `surface`), where its own frame sits
    /// in the object's space, and what it bounds.
    Surface {
        surface: Surface,
        clip: Option<Box3>,
        frame: DAffine3,
        body: Body,
    },
    /// The half-space n·p < distance.
    Plane { normal: DVec3, distance: f64 },
    /// A ring in the plane z = 0 of `frame`.
    Disc {
        frame: DAffine3,
        radius: f64,
        hole: f64,
    },
    /// A CSG operation: the loader builds its children.
    Csg,
}

/// What a surface bounds.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Body {
    /// Nothing: an open cylinder or cone, a surface only.
    Open,
    /// F < 0 within its box (see `Shape::crossings`); alone, it shows only
    /// its surface, cut by the box.
    Solid,
    /// A closed solid whose box's faces are surface even alone: a box, a
    /// cylinder or cone with caps.
    Closed,
}

/// The object of type `kind`.
pub(super) fn build(
    kind: ShapeKind,
    f: &ShapeFile,
    constants: &[(&str, f64)],
) -> Result<Built, FieldError> {
    Ok(match kind {
        ShapeKind::Plane => {
            f.takes(&["normal", "distance"])?;
            let normal = DVec3::from(f.normal.ok_or(("", "missing `normal`".to_string()))?);
            nonzero("normal", normal)?;
            let distance = f.distance.unwrap_or(0.0);
            if !distance.is_finite() {
                return Err(("distance", "expected a finite number".into()));
            }
            Built::Plane { normal, distance }
        }
        ShapeKind::Box => {
            f.takes(&["min", "max"])?;
            let corner = |name: &'static str, v: Option<[f64; 3]>| {
                let v = v.ok_or(("", format!("missing `{name}` (a corner)")))?;
                finite(name, DVec3::from(v))
            };
            let (min, max) = (corner("min", f.min)?, corner("max", f.max)?);
            if min.cmpge(max).any() {
                return Err((
                    "max",
                    format!("expected max > min on every axis, found min {min} and max {max}"),
                ));
            }
            // F = −1: inside the whole box, whose faces are the surface.
            let inside = diagonal([0.0; 3], [0.0; 3], -1.0);
            Built::Surface {
                surface: inside,
                clip: Some(Box3 { min, max }),
                frame: DAffine3::IDENTITY,
                body: Body::Closed,
            }
        }
        ShapeKind::Disc => {
            f.takes(&["center", "normal", "radius", "hole"])?;
            let radius = f.radius()?;
            let hole = f.hole.unwrap_or(0.0);
            if !(0.0..radius).contains(&hole) {
                return Err((
                    "hole",
                    format!("expected a number >= 0 and below the radius {radius}, found {hole}"),
                ));
            }
            let center = finite("center", DVec3::from(f.center.unwrap_or([0.0; 3])))?;
            let normal = DVec3::from(f.normal.unwrap_or([0.0, 0.0, 1.0]));
            nonzero("normal", normal)?;
            Built::Disc {
                frame: axis_frame(center, normal),
                radius,
                hole,
            }
        }
        ShapeKind::Csg => {
            f.takes(&["op", "children"])?;
            Built::Csg
        }
        ShapeKind::Cylinder | ShapeKind::Cone if f.base.is_some() || f.cap.is_some() => {
            round(kind, f)?
        }
        _ => {
            let (surface, clip) = surface(kind, f, constants)?;
            let body = match (kind, f.caps) {
                (_, Some(true)) => Body::Closed,
                (ShapeKind::Cylinder | ShapeKind::Cone, _) => Body::Open,
                _ => Body::Solid,
            };
            Built::Surface {
                surface,
                clip,
                frame: DAffine3::IDENTITY,
                body,
            }
        }
    })
}

fn finite(name: &'static str, v: DVec3) -> Result<DVec3, FieldError> {
    if v.abs().max_element() <= MAX_COORDINATE {
        Ok(v)
    } else {
        Err((
            name,
            format!("expected finite numbers of size at most {MAX_COORDINATE:e}, found {v}"),
        ))
    }
}

fn nonzero(name: &'static str, v: DVec3) -> Result<(), FieldError> {
    finite(name, v)?;
    if v.length_squared() > 0.0 {
        Ok(())
    } else {
        Err((name, "a direction cannot be zero".into()))
    }
}

/// POV-Ray's `cylinder { base, cap, radius }` and `cone { base, r0, cap, r1 }`:
/// along z from 0 to the axis's length in their own frame, closed by caps
/// unless `caps = false`.
fn round(kind: ShapeKind, f: &ShapeFile) -> Result<Built, FieldError> {
    let cone = matches!(kind, ShapeKind::Cone);
    if cone {
        f.takes(&["base", "cap", "radius", "cap_radius", "caps"])?;
    } else {
        f.takes(&["base", "cap", "radius", "caps"])?;
    }
    let end = |name: &'static str, v: Option<[f64; 3]>| {
        let v = v.ok_or(("", format!("missing `{name}` (a point on the axis)")))?;
        finite(name, DVec3::from(v))
    };
    let (base, cap) = (end("base", f.base)?, end("cap", f.cap)?);
    let length = (cap - base).length();
    // The ends are finite, so the length is a number: zero, or positive.
    if length == 0.0 {
        return Err((
            "cap",
            "the cap is at the base: the axis has no length".into(),
        ));
    }
    let r0 = f.radius()?;
    let r1 = if cone {
        let r1 = f
            .cap_radius
            .ok_or(("", "missing `cap_radius`".to_string()))?;
        if !(0.0..=MAX_COORDINATE).contains(&r1) {
            return Err((
                "cap_radius",
                format!("expected a number >= 0 and at most {MAX_COORDINATE:e}, found {r1}"),
            ));
        }
        r1
    } else {
        r0
    };
    let (surface, clip) = solids::round(r0, r1, length);
    Ok(Built::Surface {
        surface,
        clip: Some(clip),
        frame: axis_frame(base, cap - base),
        body: if f.caps == Some(false) {
            Body::Open
        } else {
            Body::Closed
        },
    })
}
