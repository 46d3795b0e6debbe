//! Wavefront OBJ geometry, read line by line so every error names its line.
//!
//! tobj reads the MTL files, but not the OBJ itself: tobj reports no line
//! numbers and splits an object wherever `usemtl` changes, while the `trace`
//! contract numbers triangles in file order within each `o`/`g` object.
//! Polygons are fan-triangulated (v0, vi, vi+1), as embreex users and tobj do.

mod mtl;

pub(crate) use mtl::{MapSlot, TextureMap, set_map};

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::geometry::Mesh;
use crate::math::{INVALID_ID, Vec2, Vec3};
use crate::shading::Material;

/// The meshes of one OBJ file with the materials its faces name.
/// A triangle without a material has material index `INVALID_ID`.
pub struct ObjFile {
    pub meshes: Vec<Mesh>,
    /// Every name a `usemtl` or a library gave, in order of first appearance;
    /// a triangle's material index points here.
    pub materials: Vec<ObjMaterial>,
    /// `mtllib` files that are not there: a warning each, not an error, as
    /// Blender writes the line whether or not it wrote the file.
    pub missing_libraries: Vec<(usize, PathBuf)>,
    /// Map statements of the libraries that are not read yet (library,
    /// line, keyword): a warning each.
    pub unread_maps: Vec<(PathBuf, usize, String)>,
    /// Triangles of zero area (repeated or collinear corners). They stay in the
    /// meshes, so triangle numbers never shift, and Embree never hits them.
    pub degenerate: usize,
    /// The files read: the OBJ and its material libraries.
    pub sources: Vec<PathBuf>,
    /// What the file holds that is not read, each a warning (a PLY's
    /// per-corner texture coordinates).
    pub unread: Vec<String>,
}

/// Coordinates (OBJ vertices, TOML positions, translations, clip boxes, and
/// every object's world-space bounds) above this in size are refused. The
/// f32 arithmetic multiplies lengths: Embree's triangle test three of them
/// (t = v0 · (e1 × e2), a hit at t = inf beyond about 1e12), light areas and
/// powers two of them times a colour, and a framing camera stands several
/// scene sizes away. At 1e9 every such product stays within f32 (3.4e38).
/// A material name of an OBJ file: what its library defines, or `None`
/// where no library loaded so far defines it (Blender's `usemtl None` for
/// faces without a material). A scene file's material of the same name
/// replaces either; an undefined one without it renders as the default grey.
pub struct ObjMaterial {
    pub name: String,
    pub defined: Option<Material>,
    /// Its texture statements (`map_Kd`, `map_d`, …), read when the scene
    /// takes the material.
    pub(crate) maps: Vec<TextureMap>,
    /// The line that first named it: its `usemtl`, for the warning.
    pub line: usize,
}

pub(super) const MAX_COORDINATE: f64 = 1e9;

struct Reader<'a> {
    path: &'a Path,
    line: usize,
    positions: Vec<Vec3>,
    materials: Vec<ObjMaterial>,
    material_names: HashMap<String, u32>,
    missing_libraries: Vec<(usize, PathBuf)>,
    unread_maps: Vec<(PathBuf, usize, String)>,
    current_material: u32,
    meshes: Vec<Mesh>,
    mesh: Mesh,
    /// Global vertex index → index in the current mesh, `INVALID_ID` if unused.
    local: Vec<u32>,
    /// (vertex, texture coordinate, normal) → index in the current mesh, for
    /// corners with a `vt` or `vn`.
    attributed: HashMap<(u32, u32, u32), u32>,
    /// The global vertex indices the current mesh uses.
    globals: Vec<u32>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    degenerate: usize,
    /// The material libraries read.
    libraries: Vec<PathBuf>,
}

impl Reader<'_> {
    fn error(&self, message: impl Into<String>) -> Error {
        Error::Mesh {
            path: self.path.to_owned(),
            line: self.line,
            message: message.into(),
        }
    }

    /// The `n` numbers after `keyword` (the rest optional, 0 when absent:
    /// `vt u` alone is a 1D texture coordinate), each finite and within the
    /// coordinate limit.
    fn numbers<'w, const N: usize>(
        &self,
        keyword: &str,
        required: usize,
        words: impl Iterator<Item = &'w str>,
    ) -> Result<[f32; N]> {
        let mut values = [0.0f32; N];
        let mut words = words;
        for (axis, value) in values.iter_mut().enumerate() {
            let Some(word) = words.next() else {
                if axis < required {
                    return Err(self.error(format!(
                        "expected {required} coordinates after `{keyword}`, found {axis}"
                    )));
                }
                break;
            };
            *value = word
                .parse::<f32>()
                .map_err(|_| self.error(format!("expected a number, found `{word}`")))?;
            if !value.is_finite() || f64::from(value.abs()) > MAX_COORDINATE {
                return Err(self.error(format!(
                    "coordinate `{word}` is not a finite number below {MAX_COORDINATE:e}"
                )));
            }
        }
        Ok(values)
    }

    /// One index of a face corner, 1-based or negative (counting back from
    /// the last of the `count` defined so far), as a 0-based index.
    fn index(&self, word: &str, part: &str, what: &str, count: usize) -> Result<u32> {
        let index: i64 = part
            .parse()
            .map_err(|_| self.error(format!("expected a {what} index in face, found `{word}`")))?;
        let count = count as i64;
        let global = if index > 0 { index - 1 } else { count + index };
        if index == 0 || global < 0 || global >= count {
            return Err(self.error(format!(
                "{what} index {index} out of range: {count} {what}s defined so far"
            )));
        }
        Ok(global as u32)
    }

    /// Resolves one `v`, `v/t`, `v//n` or `v/t/n` reference to a mesh-local
    /// vertex: one per distinct triple, so a position with two normals (a
    /// crease) or two texture coordinates (a seam) is two vertices.
    fn reference(&mut self, word: &str) -> Result<u32> {
        if word.matches('/').count() > 2 {
            return Err(self.error(format!(
                "expected a face corner v, v/t, v//n or v/t/n, found `{word}`"
            )));
        }
        let mut parts = word.split('/');
        let v = parts.next().unwrap_or("");
        let v = self.index(word, v, "vertex", self.positions.len())?;
        let optional = |part: Option<&str>, what, count| match part {
            None | Some("") => Ok(INVALID_ID),
            Some(part) => self.index(word, part, what, count),
        };
        let t = optional(parts.next(), "texture coordinate", self.uvs.len())?;
        let n = optional(parts.next(), "normal", self.normals.len())?;
        let slot = if t == INVALID_ID && n == INVALID_ID {
            &mut self.local[v as usize]
        } else {
            self.attributed.entry((v, t, n)).or_insert(INVALID_ID)
        };
        if *slot == INVALID_ID {
            *slot = self.mesh.positions.len() as u32;
            self.mesh.positions.push(self.positions[v as usize]);
            self.globals.push(v);
            // Corners without a normal or uv get zero: a triangle with a zero
            // normal at a corner is shaded flat (`Mesh::shading_normal`).
            let mesh = &mut self.mesh;
            if n != INVALID_ID || !mesh.normals.is_empty() {
                mesh.normals.resize(mesh.positions.len() - 1, Vec3::ZERO);
                mesh.normals
                    .push(self.normals.get(n as usize).copied().unwrap_or(Vec3::ZERO));
            }
            if t != INVALID_ID || !mesh.uvs.is_empty() {
                mesh.uvs.resize(mesh.positions.len() - 1, Vec2::ZERO);
                mesh.uvs
                    .push(self.uvs.get(t as usize).copied().unwrap_or(Vec2::ZERO));
            }
        }
        Ok(*slot)
    }

    fn face<'w>(&mut self, words: impl Iterator<Item = &'w str>) -> Result<()> {
        let mut corners = [0u32; 3];
        let mut n = 0;
        for word in words {
            let index = self.reference(word)?;
            // Fan: (v0, v1, v2), (v0, v2, v3), ...
            if n < 3 {
                corners[n] = index;
            } else {
                corners[1] = corners[2];
                corners[2] = index;
            }
            n += 1;
            if n >= 3 {
                let [a, b, c] = corners.map(|i| self.mesh.positions[i as usize]);
                if (b - a).cross(c - a) == Vec3::ZERO {
                    self.degenerate += 1;
                }
                self.mesh.triangles.push(corners);
                self.mesh.materials.push(self.current_material);
            }
        }
        if n < 3 {
            return Err(self.error(format!("a face needs at least 3 vertices, found {n}")));
        }
        Ok(())
    }

    fn finish_mesh(&mut self, next_name: String) {
        let mesh = std::mem::replace(
            &mut self.mesh,
            Mesh {
                name: next_name,
                ..Mesh::default()
            },
        );
        // Reset only the entries this mesh used: `local` spans every vertex of the file.
        for g in self.globals.drain(..) {
            self.local[g as usize] = INVALID_ID;
        }
        self.attributed.clear();
        if !mesh.triangles.is_empty() {
            self.meshes.push(mesh);
        }
    }

    fn material_library(&mut self, rest: &str) -> Result<()> {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        let name = rest.trim();
        if name.is_empty() {
            return Err(self.error("expected a file name after `mtllib`"));
        }
        let file: PathBuf = dir.join(name);
        if !file.exists() {
            self.missing_libraries.push((self.line, file));
            return Ok(());
        }
        // A library that cannot be read is named with the line that asks for it.
        let (materials, mut maps, unread) = mtl::load(&file).map_err(|e| match e {
            Error::Io { .. } => self.error(e.to_string()),
            other => other,
        })?;
        self.unread_maps.extend(
            unread
                .into_iter()
                .map(|(line, keyword)| (file.clone(), line, keyword)),
        );
        self.libraries.push(file);
        for m in &materials {
            let material = ObjMaterial {
                name: m.name.clone(),
                defined: Some(Material::from_mtl(m)),
                maps: maps.remove(&m.name).unwrap_or_default(),
                line: self.line,
            };
            // A later library's definition of a name replaces the earlier one.
            match self.material_names.get(&m.name) {
                Some(&i) => self.materials[i as usize] = material,
                None => {
                    let index = self.materials.len() as u32;
                    self.material_names.insert(m.name.clone(), index);
                    self.materials.push(material);
                }
            }
        }
        Ok(())
    }

    fn use_material(&mut self, name: &str) -> Result<()> {
        let name = name.trim();
        if name.is_empty() {
            return Err(self.error("expected a material name after `usemtl`"));
        }
        self.current_material = match self.material_names.get(name) {
            Some(&i) => i,
            None => {
                let index = self.materials.len() as u32;
                self.material_names.insert(name.to_owned(), index);
                self.materials.push(ObjMaterial {
                    name: name.to_owned(),
                    defined: None,
                    maps: Vec::new(),
                    line: self.line,
                });
                index
            }
        };
        Ok(())
    }
}

/// Reads an OBJ file and the MTL libraries it names.
pub fn load_obj(path: &Path) -> Result<ObjFile> {
    let text = crate::io::input::read_text(path)?;
    let stem = path
        .file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
    let mut r = Reader {
        path,
        line: 0,
        positions: Vec::new(),
        materials: Vec::new(),
        material_names: HashMap::new(),
        missing_libraries: Vec::new(),
        unread_maps: Vec::new(),
        current_material: INVALID_ID,
        meshes: Vec::new(),
        mesh: Mesh {
            name: stem,
            ..Mesh::default()
        },
        local: Vec::new(),
        attributed: HashMap::new(),
        globals: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        degenerate: 0,
        libraries: Vec::new(),
    };
    for (number, line) in text.lines().enumerate() {
        r.line = number + 1;
        // `#` starts a comment, also after a statement.
        let line = line.split('#').next().unwrap_or("").trim();
        let Some(keyword) = line.split_whitespace().next() else {
            continue;
        };
        let rest = line[keyword.len()..].trim_start();
        match keyword {
            "v" => {
                let v = r.numbers::<3>("v", 3, rest.split_whitespace())?;
                r.positions.push(Vec3::from(v));
                r.local.push(INVALID_ID);
            }
            "vn" => {
                let n = r.numbers::<3>("vn", 3, rest.split_whitespace())?;
                r.normals.push(Vec3::from(n));
            }
            "vt" => {
                // A third (w) coordinate of 3D textures is read and dropped.
                let [u, v, _] = r.numbers::<3>("vt", 1, rest.split_whitespace())?;
                r.uvs.push(Vec2::new(u, v));
            }
            "f" => r.face(rest.split_whitespace())?,
            "o" | "g" => {
                if r.mesh.triangles.is_empty() {
                    r.mesh.name = rest.to_owned();
                } else {
                    r.finish_mesh(rest.to_owned());
                }
            }
            "mtllib" => r.material_library(rest)?,
            "usemtl" => r.use_material(rest)?,
            // Smoothing groups (Blender writes `vn` anyway), lines, points and
            // free-form geometry are not rendered.
            _ => {}
        }
    }
    r.line = 0;
    r.finish_mesh(String::new());
    let mut sources = vec![path.to_owned()];
    sources.append(&mut r.libraries);
    Ok(ObjFile {
        meshes: r.meshes,
        materials: r.materials,
        missing_libraries: r.missing_libraries,
        unread_maps: r.unread_maps,
        degenerate: r.degenerate,
        sources,
        unread: Vec::new(),
    })
}
