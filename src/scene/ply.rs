//! PLY meshes (the Stanford models' format), ASCII and binary of either
//! byte order, read by ply-rs-bw one element at a time straight into a
//! [`Mesh`]'s buffers: the same memory per triangle as an OBJ's, and no map
//! per element. Vertices may carry normals, texture coordinates (`s`/`t`,
//! `u`/`v` or `texture_u`/`texture_v`) and colours (`red`, `green`,
//! `blue`); faces are `vertex_indices` (or `vertex_index`) lists,
//! fan-triangulated as OBJ polygons are. Other elements are read and dropped.

use std::io::{BufRead, BufReader};
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    BeginList, ElementDef, Encoding, Header, Property, PropertyAccess, PropertyAccessResult,
};

use super::obj::{MAX_COORDINATE, ObjFile};
use crate::error::{Error, Result};
use crate::geometry::Mesh;
use crate::math::{INVALID_ID, Vec2, Vec3};
use crate::shading::srgb_to_linear;

/// One vertex as read. What the header declares decides which parts the
/// mesh keeps; a part it does not declare stays zero.
#[derive(Default)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [f32; 2],
    colour: [f32; 3],
    /// A coordinate that is not a finite number within the limit.
    bad: Option<(&'static str, f64)>,
}

/// The vertex properties sturmray reads, by name: (part, axis).
fn vertex_slot(name: &str) -> Option<(Part, usize)> {
    Some(match name {
        "x" => (Part::Position, 0),
        "y" => (Part::Position, 1),
        "z" => (Part::Position, 2),
        "nx" => (Part::Normal, 0),
        "ny" => (Part::Normal, 1),
        "nz" => (Part::Normal, 2),
        "s" | "u" | "texture_u" | "texture_s" => (Part::Uv, 0),
        "t" | "v" | "texture_v" | "texture_t" => (Part::Uv, 1),
        "red" | "r" => (Part::Colour, 0),
        "green" | "g" => (Part::Colour, 1),
        "blue" | "b" => (Part::Colour, 2),
        _ => return None,
    })
}

#[derive(Clone, Copy, PartialEq)]
enum Part {
    Position,
    Normal,
    Uv,
    Colour,
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let Some((part, axis)) = vertex_slot(name) else {
            return PropertyAccessResult::Ignored;
        };
        // Integer colours span their type's range; float ones are 0 to 1.
        let full_scale = match property {
            Property::UChar(_) => 255.0,
            Property::UShort(_) => 65535.0,
            _ => 1.0,
        };
        let value = match property {
            Property::Double(v) => v,
            other => match other.to_f32_lossy() {
                Some(v) => f64::from(v),
                None => return PropertyAccessResult::UnsupportedType,
            },
        };
        if !(value.is_finite() && value.abs() <= MAX_COORDINATE) {
            self.bad.get_or_insert((part.described(), value));
        }
        let value = value as f32;
        match part {
            Part::Position => self.position[axis] = value,
            Part::Normal => self.normal[axis] = value,
            Part::Uv => self.uv[axis] = value,
            Part::Colour => self.colour[axis] = (value / full_scale).clamp(0.0, 1.0),
        }
        PropertyAccessResult::Set
    }
}

impl Part {
    /// One value of this part, for the error of a bad one.
    fn described(self) -> &'static str {
        match self {
            Part::Position => "a position",
            Part::Normal => "a normal",
            Part::Uv => "a texture coordinate",
            Part::Colour => "a colour",
        }
    }
}

/// One face as read: its vertex indices.
#[derive(Default)]
struct Face {
    signed: Vec<i32>,
    unsigned: Vec<u32>,
    /// Indices of another integer type (uchar, short...), or a negative one.
    other: Option<Vec<u32>>,
    negative: bool,
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Face::default()
    }

    fn begin_list_int(&mut self, name: &str, _len: usize) -> BeginList<'_, i32> {
        if is_index_list(name) {
            BeginList::Fill(&mut self.signed)
        } else {
            BeginList::UseSetter
        }
    }

    fn begin_list_uint(&mut self, name: &str, _len: usize) -> BeginList<'_, u32> {
        if is_index_list(name) {
            BeginList::Fill(&mut self.unsigned)
        } else {
            BeginList::UseSetter
        }
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !is_index_list(name) {
            return PropertyAccessResult::Ignored;
        }
        match property.to_u32_list() {
            Some(list) => self.other = Some(list),
            // A signed list with a negative index, or a float list.
            None => self.negative = true,
        }
        PropertyAccessResult::Set
    }
}

impl Face {
    /// The indices, whichever integer type the file declared them as (an
    /// `int` list is turned into `u32` in place).
    fn into_indices(self) -> std::result::Result<Vec<u32>, &'static str> {
        if self.negative || self.signed.iter().any(|&i| i < 0) {
            return Err("a negative or non-integer vertex index");
        }
        Ok(match self.other {
            Some(list) => list,
            None if !self.signed.is_empty() => self.signed.into_iter().map(|i| i as u32).collect(),
            None => self.unsigned,
        })
    }
}

/// Any other element: read (the format has no way to skip one) and dropped.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Ignored
    }
}

/// Where in the file an element is, for errors: the line of an ASCII file,
/// the element's number in a binary one.
struct Place<'a> {
    path: &'a Path,
    ascii: bool,
    line: usize,
}

impl Place<'_> {
    fn error(&self, element: &ElementDef, number: usize, message: impl std::fmt::Display) -> Error {
        Error::Mesh {
            path: self.path.to_owned(),
            line: if self.ascii { self.line } else { 0 },
            message: format!("{} {number}: {message}", element.name),
        }
    }
}

/// Reads element after element of one kind in the file's encoding.
fn read_element<E: PropertyAccess, R: BufRead>(
    parser: &Parser<E>,
    reader: &mut R,
    header: &Header,
    element: &ElementDef,
    place: &mut Place,
    line: &mut String,
    number: usize,
) -> Result<E> {
    let read = match header.encoding {
        Encoding::Ascii => {
            line.clear();
            place.line += 1;
            match reader.read_line(line) {
                Ok(0) => return Err(place.error(element, number, "the file ends here")),
                Ok(_) => {
                    return parser.read_ascii_element(line, element).map_err(|_| {
                        let names: Vec<&str> =
                            element.properties.keys().map(String::as_str).collect();
                        let message = format!(
                            "expected the numbers of {}, found `{}`",
                            names.join(" "),
                            line.trim()
                        );
                        place.error(element, number, message)
                    });
                }
                Err(e) => return Err(place.error(element, number, e)),
            }
        }
        Encoding::BinaryLittleEndian => parser.read_little_endian_element(reader, element),
        Encoding::BinaryBigEndian => parser.read_big_endian_element(reader, element),
    };
    read.map_err(|e| place.error(element, number, first_line(&e.to_string())))
}

/// The first line of the crate's message (it appends the line it read).
fn first_line(message: &str) -> &str {
    message.lines().next().unwrap_or(message)
}

/// Reads a PLY file as one mesh named after the file, without materials
/// (its triangles have material `INVALID_ID`: the scene's default grey, or
/// the object's material).
pub fn load_ply(path: &Path) -> Result<ObjFile> {
    let (file, _) = crate::io::input::open_regular(path)?;
    let mut reader = Reader::new(BufReader::new(file));
    let header = Parser::<Ignored>::new()
        .read_header(&mut reader)
        .map_err(|e| Error::Mesh {
            path: path.to_owned(),
            line: e.line().unwrap_or(0),
            message: format!("not a readable PLY header: {}", first_line(&e.to_string())),
        })?;
    let mut place = Place {
        path,
        ascii: header.encoding == Encoding::Ascii,
        // The reader counts the line it would read next.
        line: reader.line().saturating_sub(1),
    };
    let mut mesh = Mesh {
        name: path
            .file_stem()
            .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned()),
        ..Mesh::default()
    };
    let mut line = String::new();
    let mut has_faces = false;
    let mut unread = Vec::new();
    let (vertices, faces, others) = (Parser::new(), Parser::new(), Parser::<Ignored>::new());
    let reader = reader.get_mut();
    for element in header.elements.values() {
        // A corrupt count cannot make us reserve more than the file could hold.
        let reserve = element.count.min(1 << 20);
        match element.name.as_str() {
            "vertex" => {
                let declares = |part: Part| {
                    element
                        .properties
                        .keys()
                        .any(|name| vertex_slot(name).is_some_and(|(p, _)| p == part))
                };
                let normals = declares(Part::Normal);
                let uvs = declares(Part::Uv);
                let colours = declares(Part::Colour);
                if u32::try_from(element.count).is_err() {
                    return Err(place.error(element, 0, "more vertices than sturmray can index"));
                }
                mesh.positions.reserve(reserve);
                for number in 0..element.count {
                    let v: Vertex = read_element(
                        &vertices, reader, &header, element, &mut place, &mut line, number,
                    )?;
                    if let Some((what, value)) = v.bad {
                        return Err(place.error(
                            element,
                            number,
                            format!(
                                "{what} of {value:e} is not a finite number below \
                                 {MAX_COORDINATE:e}"
                            ),
                        ));
                    }
                    mesh.positions.push(Vec3::from(v.position));
                    if normals {
                        mesh.normals.push(Vec3::from(v.normal));
                    }
                    if uvs {
                        mesh.uvs.push(Vec2::from(v.uv));
                    }
                    if colours {
                        mesh.colours.push(Vec3::from(v.colour.map(srgb_to_linear)));
                    }
                }
            }
            "face" => {
                has_faces = true;
                // meshlab writes uv per face corner (wedge texture coordinates),
                // which would need a vertex per corner: said, not read.
                if let Some(name) = (element.properties.keys())
                    .find(|name| matches!(name.as_str(), "texcoord" | "texcoords"))
                {
                    unread.push(format!(
                        "{}: the faces' per-corner texture coordinates (`{name}`, as meshlab \
                         writes them) are not read: the mesh has no uv, and textures on it \
                         show their plain colour",
                        path.display()
                    ));
                }
                mesh.triangles.reserve(reserve);
                for number in 0..element.count {
                    let face: Face = read_element(
                        &faces, reader, &header, element, &mut place, &mut line, number,
                    )?;
                    let indices = face
                        .into_indices()
                        .map_err(|message| place.error(element, number, message))?;
                    if indices.len() < 3 {
                        return Err(place.error(
                            element,
                            number,
                            format!("a face needs at least 3 vertices, found {}", indices.len()),
                        ));
                    }
                    // Fan: (v0, v1, v2), (v0, v2, v3), ... as OBJ polygons.
                    for pair in indices[1..].windows(2) {
                        mesh.triangles.push([indices[0], pair[0], pair[1]]);
                    }
                }
            }
            _ => {
                for number in 0..element.count {
                    read_element(
                        &others, reader, &header, element, &mut place, &mut line, number,
                    )?;
                }
            }
        }
    }
    if !has_faces {
        return Err(Error::Mesh {
            path: path.to_owned(),
            line: 0,
            message: "expected a `face` element with `vertex_indices` lists".into(),
        });
    }
    finish(path, mesh, unread)
}

/// Checks every index against the vertices (faces may come before them in
/// the file) and counts degenerate triangles, as the OBJ reader does.
fn finish(path: &Path, mut mesh: Mesh, unread: Vec<String>) -> Result<ObjFile> {
    let count = mesh.positions.len();
    let mut degenerate = 0;
    for (number, triangle) in mesh.triangles.iter().enumerate() {
        if let Some(&bad) = triangle.iter().find(|&&i| i as usize >= count) {
            return Err(Error::Mesh {
                path: path.to_owned(),
                line: 0,
                message: format!(
                    "triangle {number}: vertex index {bad} out of range: {count} vertices"
                ),
            });
        }
        let [a, b, c] = triangle.map(|i| mesh.positions[i as usize]);
        if (b - a).cross(c - a) == Vec3::ZERO {
            degenerate += 1;
        }
    }
    mesh.materials = vec![INVALID_ID; mesh.triangles.len()];
    let meshes = if mesh.triangles.is_empty() {
        Vec::new()
    } else {
        vec![mesh]
    };
    Ok(ObjFile {
        meshes,
        materials: Vec::new(),
        missing_libraries: Vec::new(),
        unread_maps: Vec::new(),
        degenerate,
        sources: vec![path.to_owned()],
        unread,
    })
}

#[cfg(test)]
mod tests;
