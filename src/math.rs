//! Vectors (glam), rays and hit records shared by every backend, and the
//! orthonormal shading frame.

pub use glam::{DVec3, Mat3, Mat4, Vec2, Vec3};

/// A ray in world space with its parametric interval [tnear, tfar].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub tnear: f32,
    pub tfar: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray {
            origin,
            dir,
            tnear: 0.0,
            tfar: f32::INFINITY,
        }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// Why a backend would refuse this ray, or `None` for a ray every backend
    /// traces. These are the conditions Embree asserts before traversal
    /// (`RayK::valid()` and `tnear >= 0`): a ray that fails them aborts the
    /// process. One more: a direction with no normal float component, which
    /// flush-to-zero turns into a zero vector, has no way to point.
    pub fn problem(&self) -> Option<String> {
        let within = |v: Vec3| v.abs().cmple(Vec3::splat(RAY_LIMIT)).all();
        if !within(self.origin) {
            Some(format!(
                "origin {} must be finite with every component at most {RAY_LIMIT:e} in size \
                 (Embree's limit)",
                sci(self.origin)
            ))
        } else if !within(self.dir) {
            Some(format!(
                "direction {} must be finite with every component at most {RAY_LIMIT:e} in size \
                 (Embree's limit)",
                sci(self.dir)
            ))
        } else if self.dir.abs().max_element() < f32::MIN_POSITIVE {
            Some(format!(
                "direction {} is zero, or below {:e} in every component (read as zero)",
                sci(self.dir),
                f32::MIN_POSITIVE
            ))
        } else if self.tnear.is_nan() || self.tnear < 0.0 {
            Some(format!("tnear {} must be a number >= 0", self.tnear))
        } else if self.tfar.is_nan() {
            Some("tfar is NaN".into())
        } else {
            None
        }
    }
}

/// A ray's origin and direction in f64: a camera ray as the camera computed
/// it, before rounding to the f32 `Ray` the BVHs traverse. Analytic shapes
/// are solved in f64, and a ray that grazes one by less than an f32 ulp of
/// its direction is hit or missed by that rounding alone; POV-Ray computes
/// its rays in double, so the comparison with it needs the f64 ray. A BVH
/// that is handed both (`Accel::intersect_exact`) traverses the rounded ray
/// and gives the shapes this one wherever the ray it is about to test is
/// still that rounding (not a ray moved into an instance's space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray64 {
    pub origin: DVec3,
    pub dir: DVec3,
}

impl Ray64 {
    /// The f32 ray of this one, over [0, inf).
    pub fn rounded(&self) -> Ray {
        Ray::new(self.origin.as_vec3(), self.dir.as_vec3())
    }

    /// `ray`'s own origin and direction, widened.
    pub fn of(ray: &Ray) -> Ray64 {
        Ray64 {
            origin: ray.origin.as_dvec3(),
            dir: ray.dir.as_dvec3(),
        }
    }

    /// What a shape is to solve for `ray`: `exact` if `ray`'s origin and
    /// direction are its rounding, else `ray`'s own widened (a ray with no
    /// f64 ray, or one moved into an instance's space).
    #[inline]
    pub fn for_ray(exact: Option<&Ray64>, ray: &Ray) -> Ray64 {
        match exact {
            Some(e) if e.origin.as_vec3() == ray.origin && e.dir.as_vec3() == ray.dir => *e,
            _ => Ray64::of(ray),
        }
    }
}

/// The larger of a and b by one comparison: `f64::max` without its NaN
/// rule, whose handling costs several instructions a call, which in the
/// per-ray code added up to some 3% of a POV-Ray sample's render loop
/// (`valgrind --tool=callgrind`). Equal to `a.max(b)` wherever a is not NaN
/// (a NaN b gives a, as `max` does); a NaN a gives a.
#[inline(always)]
pub fn larger(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The smaller of a and b by one comparison: `f64::min` as `larger` is
/// `f64::max`, equal to it wherever a is not NaN.
#[inline(always)]
pub fn smaller(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// A vector in scientific notation, for messages about very large or small ones.
pub fn sci<T: std::fmt::LowerExp>(v: impl Into<[T; 3]>) -> String {
    let [x, y, z] = v.into();
    format!("[{x:e}, {y:e}, {z:e}]")
}

/// Embree's bound on the size of every ray origin and direction component
/// (`FLT_LARGE` in its kernels).
pub const RAY_LIMIT: f32 = 1.844e18;

/// `v` scaled to unit length, or zero for a zero or non-finite `v`. In f64,
/// so neither squaring a long vector (a triangle normal of edges 1e10 long
/// is 1e20 long, 1e40 squared) nor a short one overflows or underflows f32.
pub fn unit(v: Vec3) -> Vec3 {
    v.as_dvec3().normalize_or_zero().as_vec3()
}

/// Marks "no geometry" / "no primitive" in hit records, as Embree does.
pub const INVALID_ID: u32 = u32::MAX;

/// Rec. 709 luminance weights: how bright a colour looks, for choosing by
/// brightness (lights by power, adaptive sampling by disagreement).
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// The nearest hit of a ray: distance, which geometry and primitive, the
/// barycentric (u, v) and the unnormalised geometric normal, in world space.
/// A hit on an instance names the instance (`inst_id`, its index in
/// `Scene::instances`) and its prototype's geometry and primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub geom_id: u32,
    pub prim_id: u32,
    /// [`INVALID_ID`] for geometry that is not instanced.
    pub inst_id: u32,
    pub u: f32,
    pub v: f32,
    pub ng: Vec3,
}

impl Hit {
    /// The record of a ray that hit nothing: t = inf, both ids invalid.
    pub const MISS: Hit = Hit {
        t: f32::INFINITY,
        geom_id: INVALID_ID,
        prim_id: INVALID_ID,
        inst_id: INVALID_ID,
        u: 0.0,
        v: 0.0,
        ng: Vec3::ZERO,
    };

    pub fn is_hit(&self) -> bool {
        self.geom_id != INVALID_ID
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub const EMPTY: Bounds = Bounds {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// This box grown by `pad` on every side.
    pub fn grown(self, pad: f32) -> Bounds {
        Bounds {
            min: self.min - Vec3::splat(pad),
            max: self.max + Vec3::splat(pad),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }
}

/// An orthonormal, right-handed shading frame (s × t = n) with the normal as
/// local +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// The frame around a unit normal by Duff et al. 2017 ("Building an
    /// Orthonormal Basis, Revisited"): branchless and accurate for every
    /// normal, including those near −z where Frisvad's original loses
    /// orthogonality. s and t are a smooth-enough but arbitrary rotation about
    /// n; nothing here is anisotropic, so the choice does not matter.
    pub fn from_normal(n: Vec3) -> Frame {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// World to local: the components along s, t and n.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local to world.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// γ(n) = nε / (1 − nε), the bound on the relative error of n f32 operations
/// (Higham; pbrt's `gamma`).
pub fn gamma(n: u32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}

/// Moves a spawned ray's origin off the surface it starts on: along the
/// normal `n`, by the hit point's per-axis error bound `error` projected on
/// the normal, to the side `w` leaves towards, then one float further away
/// (pbrt's OffsetRayOrigin). The ray then cannot re-hit its own surface, and
/// the offset scales with the hit point's magnitude, not a fixed epsilon.
pub fn offset(p: Vec3, error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(error);
    let mut shift = d * n;
    if w.dot(n) < 0.0 {
        shift = -shift;
    }
    let moved = p + shift;
    let away = |x: f32, s: f32| {
        if s > 0.0 {
            x.next_up()
        } else if s < 0.0 {
            x.next_down()
        } else {
            x
        }
    };
    Vec3::new(
        away(moved.x, shift.x),
        away(moved.y, shift.y),
        away(moved.z, shift.z),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_bounds_grow_with_operation_count() {
        assert!(gamma(1) > 0.5 * f32::EPSILON && gamma(1) < 0.51 * f32::EPSILON);
        assert!(gamma(7) > 7.0 * gamma(1) - 1e-12);
    }

    #[test]
    fn offset_moves_to_the_side_the_ray_leaves_on() {
        let p = Vec3::new(1000.0, 0.0, 0.0);
        let err = Vec3::splat(1e-3);
        let n = Vec3::Y;
        let up = offset(p, err, n, Vec3::new(0.3, 1.0, 0.0));
        let down = offset(p, err, n, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y > 1e-3 && down.y < -1e-3);
        assert_eq!((up.x, up.z), (p.x, p.z));
        // A zero error bound leaves the point where it is: there is nothing to clear.
        assert!(offset(Vec3::ZERO, Vec3::ZERO, n, n).y == 0.0);
    }

    #[test]
    fn offset_is_one_point_for_every_direction_on_a_side() {
        // The path tracer finds the normal's side's point once a vertex and
        // gives it to every ray leaving on that side: exact, bit for bit,
        // grazing directions (w · n = 0) included.
        let p = Vec3::new(0.3, -7.0, 1e4);
        let err = Vec3::new(1e-3, 2e-6, 0.5);
        let n = Vec3::new(0.6, 0.0, -0.8);
        let above = offset(p, err, n, n);
        let mut below = None;
        for i in 0..200 {
            let a = i as f32 * 0.1;
            let w = Vec3::new(a.cos(), (a * 1.7).sin(), a.sin());
            let o = offset(p, err, n, w);
            if w.dot(n) < 0.0 {
                assert_ne!(o, above);
                // And one point for the other side too.
                assert_eq!(o, *below.get_or_insert(o));
            } else {
                assert_eq!(
                    o.to_array().map(f32::to_bits),
                    above.to_array().map(f32::to_bits)
                );
            }
        }
        assert!(below.is_some());
        assert_eq!(offset(p, err, n, Vec3::new(0.8, 0.0, 0.6)), above);
    }

    #[test]
    fn unit_vectors_of_long_and_short_vectors() {
        // glam's f32 normalize squares the length: 1e40 overflows, 1e-60 underflows.
        for scale in [1e-30f32, 1.0, 1e20, 3e37] {
            let u = unit(Vec3::new(0.0, 3.0, 4.0) * scale);
            assert!(
                (u - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6,
                "{scale}: {u}"
            );
        }
        assert_eq!(unit(Vec3::ZERO), Vec3::ZERO);
        assert_eq!(unit(Vec3::new(f32::NAN, 0.0, 1.0)), Vec3::ZERO);
    }

    #[test]
    fn frame_is_orthonormal_right_handed_and_invertible() {
        let mut normals = vec![
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::X,
            Vec3::NEG_Y,
            Vec3::new(1e-4, 0.0, -1.0).normalize(),
            Vec3::new(0.0, -1e-7, -1.0).normalize(),
            Vec3::new(0.6, 0.8, -0.0),
        ];
        // 1000 normals spread over the whole sphere by a Fibonacci lattice
        // (equal-area bands in z, golden-angle steps in φ): `math` sits below
        // `sampling`, so its tests cannot draw random directions.
        let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
        normals.extend((0..1000).map(|i| {
            let z = 1.0 - (2 * i + 1) as f32 / 1000.0;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }));
        for n in normals {
            let f = Frame::from_normal(n);
            for (a, b) in [(f.s, f.t), (f.s, f.n), (f.t, f.n)] {
                assert!(a.dot(b).abs() < 1e-6, "{n}: {a} {b}");
            }
            for v in [f.s, f.t] {
                assert!((v.length() - 1.0).abs() < 1e-6, "{n}: {v}");
            }
            assert!((f.s.cross(f.t) - f.n).length() < 1e-6, "{n}");
            let v = Vec3::new(0.2, -0.7, 0.5);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn rays_embree_would_assert_on_have_a_problem() {
        let good = Ray::new(Vec3::splat(RAY_LIMIT), Vec3::new(0.0, 0.0, -RAY_LIMIT));
        assert_eq!(good.problem(), None);
        let at = |origin: Vec3, dir: Vec3, tnear: f32, tfar: f32| Ray {
            origin,
            dir,
            tnear,
            tfar,
        };
        let big = RAY_LIMIT.next_up();
        for (ray, word) in [
            (at(Vec3::new(0.0, big, 0.0), Vec3::Z, 0.0, 1.0), "origin"),
            (
                at(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Z, 0.0, 1.0),
                "origin",
            ),
            (
                at(Vec3::ZERO, Vec3::new(0.0, 0.0, -big), 0.0, 1.0),
                "direction",
            ),
            (
                at(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0), 0.0, 1.0),
                "direction",
            ),
            (at(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0), "zero"),
            (at(Vec3::ZERO, Vec3::splat(1e-39), 0.0, 1.0), "zero"),
            (at(Vec3::ZERO, Vec3::Z, -1e-30, 1.0), "tnear"),
            (at(Vec3::ZERO, Vec3::Z, f32::NAN, 1.0), "tnear"),
            (at(Vec3::ZERO, Vec3::Z, 0.0, f32::NAN), "tfar"),
        ] {
            let problem = ray.problem().unwrap_or_default();
            assert!(problem.contains(word), "{ray:?}: {problem:?}");
        }
        // An empty or endless interval is fine: Embree allows tfar < tnear and infinities.
        assert_eq!(at(Vec3::ZERO, Vec3::Z, 2.0, 1.0).problem(), None);
        assert_eq!(
            at(Vec3::ZERO, Vec3::Z, f32::INFINITY, f32::INFINITY).problem(),
            None
        );
    }

    /// `larger` and `smaller` are `f64::max` and `min` wherever the first
    /// argument is not NaN, a NaN second one included (signed zeros, which
    /// `max` may order either way, compare equal).
    #[test]
    fn larger_and_smaller_are_max_and_min_but_for_a_nan_first_argument() {
        let values = [
            f64::NEG_INFINITY,
            -1e300,
            -1.0,
            -f64::MIN_POSITIVE / 2.0,
            -0.0,
            0.0,
            5e-324,
            0.5,
            1.0,
            1e300,
            f64::INFINITY,
        ];
        for a in values {
            for b in values.into_iter().chain([f64::NAN]) {
                assert_eq!(super::larger(a, b), a.max(b), "larger({a}, {b})");
                assert_eq!(super::smaller(a, b), a.min(b), "smaller({a}, {b})");
            }
        }
        assert!(super::larger(f64::NAN, 1.0).is_nan() && super::smaller(f64::NAN, 1.0).is_nan());
    }
}
