//! `type = "csg"` objects and the primitives that are CSG trees on their own
//! (a box, a capped cylinder or cone, a disc): their children, read
//! recursively, become the leaves of one `Csg`, each placed by its parents'
//! transforms and its own, with its own material or its parent's.

use glam::DAffine3;

use super::super::solids::linear;
use super::Objects;
use super::schema::{Object, ShapeFile};
use super::shapes::{Body, Built};
use crate::error::Result;
use crate::geometry::{Leaf, Node, Op, Part, Shape};
use crate::suggest;

/// How deep CSG may nest: far beyond any scene a person writes, far below
/// what the recursion's stack can take, and below the TOML parser's own
/// limit (it refuses inline tables nested about 40 deep, naming the line).
const MAX_DEPTH: usize = 32;

/// What a child inherits from the nodes above it.
pub(super) struct Parent {
    pub to_world: DAffine3,
    pub material: u32,
    pub depth: usize,
}

impl Objects<'_> {
    /// The tree node of the object at `key`, built as `built`, its leaves
    /// appended to `leaves`.
    pub(super) fn node(
        &self,
        key: &str,
        file: &ShapeFile,
        built: Built,
        parent: &Parent,
        leaves: &mut Vec<Leaf>,
    ) -> Result<Node> {
        let check = self.check;
        let to_world = parent.to_world * self.transform(key, &file.transform)?;
        let material = self
            .material(key, &file.material)?
            .unwrap_or(parent.material);
        let inverse = file.inverse.unwrap_or(false);
        let clip = self.clip(key, file)?;
        let solid = |surface, frame: DAffine3, clip| {
            Shape::new(surface, to_world * frame, clip, material, self.solver)
                .map_err(|e| check.error(key, e))
        };
        let part = match built {
            Built::Csg => {
                let inner = Parent {
                    to_world,
                    material,
                    depth: parent.depth + 1,
                };
                return self.operation(key, file, inverse, &inner, leaves);
            }
            Built::Plane { normal, distance } => match clip {
                // Cut by its own box, a plane is a solid like any clipped surface.
                Some(clip) => Part::Solid(solid(
                    linear(normal, distance),
                    DAffine3::IDENTITY,
                    Some(clip),
                )?),
                None => {
                    // n·p < d in object space is n'·q < n'·M(p0) in world space,
                    // n' = (M⁻¹)ᵀ n and p0 = d n / |n|² a point of the plane.
                    let world = to_world.inverse().matrix3.transpose() * normal;
                    let p0 = to_world.transform_point3(distance * normal / normal.length_squared());
                    Part::Plane {
                        normal: world,
                        offset: world.dot(p0),
                    }
                }
            },
            Built::Disc {
                frame,
                radius,
                hole,
            } => Part::Disc {
                to_object: (to_world * frame).inverse(),
                radius,
                hole,
                half_space: false,
            },
            Built::Surface {
                surface,
                clip: default,
                frame,
                body,
            } => {
                let shape = solid(surface, frame, clip.or(default))?;
                match body {
                    Body::Open => Part::Sheet(shape),
                    Body::Solid | Body::Closed => Part::Solid(shape),
                }
            }
        };
        if inverse && matches!(part, Part::Sheet(_) | Part::Disc { .. }) {
            return Err(check.error(
                &format!("{key}.inverse"),
                "a surface with no inside (a disc, an open cylinder or cone) cannot be inverted",
            ));
        }
        leaves.push(Leaf {
            part,
            inverse,
            material,
        });
        Ok(Node::Leaf(leaves.len() as u32 - 1))
    }

    /// A `type = "csg"` node and its children, which inherit `inner`.
    fn operation(
        &self,
        key: &str,
        file: &ShapeFile,
        inverse: bool,
        inner: &Parent,
        leaves: &mut Vec<Leaf>,
    ) -> Result<Node> {
        let check = self.check;
        if inner.depth > MAX_DEPTH {
            return Err(check.error(key, format!("CSG nests deeper than {MAX_DEPTH} levels")));
        }
        const OPS: [(&str, Op); 4] = [
            ("union", Op::Union),
            ("intersection", Op::Intersection),
            ("difference", Op::Difference),
            ("merge", Op::Merge),
        ];
        let expected = "\"union\", \"intersection\", \"difference\" or \"merge\"";
        let name = file
            .op
            .as_deref()
            .ok_or_else(|| check.error(key, format!("missing `op` ({expected})")))?;
        let Some(&(_, op)) = OPS.iter().find(|(n, _)| *n == name) else {
            let hint = suggest::closest(name, OPS.iter().map(|(n, _)| *n))
                .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
            return Err(check.error(
                &format!("{key}.op"),
                format!("unknown op `{name}`: expected {expected}{hint}"),
            ));
        };
        let children = file.children.as_deref().unwrap_or_default();
        if children.is_empty() {
            return Err(check.error(
                &format!("{key}.children"),
                "a csg needs at least one child, e.g. children = [{ type = \"sphere\", radius = 1 }]",
            ));
        }
        let mut nodes = Vec::with_capacity(children.len());
        for (i, child) in children.iter().enumerate() {
            let key = format!("{key}.children[{i}]");
            let (kind, file) = match child.view() {
                Object::Shape(kind, file) => (kind, file),
                Object::Mesh(_) => {
                    return Err(
                        check.error(&key, "a mesh cannot be part of a csg: it has no inside")
                    );
                }
                Object::Instance(_) => {
                    return Err(check.error(
                        &key,
                        "an instance cannot be part of a csg: put the csg in the prototype",
                    ));
                }
            };
            let built = self.built(&key, kind, file)?;
            nodes.push(self.node(&key, file, built, inner, leaves)?);
        }
        Ok(Node::Op {
            op,
            inverse,
            children: nodes,
        })
    }
}
