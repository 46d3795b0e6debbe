//! NumPy `.npy` files: rays in, hits out (the `trace` contract in ARCHITECTURE.md).
//!
//! npyz (<https://docs.rs/npyz>) reads the headers and writes the arrays.
//! What stays here is what sturmray promises beyond the format: the rays'
//! checks and messages, limits that hold before anything large is allocated,
//! and hits files that are byte for byte what `np.save` writes.

use std::io::{BufReader, Read, Write};
use std::path::Path;

use npyz::{AutoSerialize, DType, NpyFile, NpyHeader, Order, TypeWrite, WriterBuilder};
use py_literal::Value;

use crate::error::{Error, Result};
use crate::math::{Hit, Ray, Vec3};

const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// NumPy aligns the data to 64 bytes so it can be memory-mapped and read with
/// SIMD loads; readers accept any multiple of 16, writers should use 64.
const ALIGN: usize = 64;

/// One hit as a NumPy structured record: the field order and types are the
/// contract, 36 bytes with no padding. npyz derives the dtype from it
/// (`[('t', '<f4'), …, ('ng', '<f4', (3,))]`; npyz's default dtypes are in
/// the host's byte order, little-endian on every target Embree runs on, which
/// the header test pins) and writes the records.
#[derive(npyz::Serialize, npyz::AutoSerialize)]
struct HitRecord {
    t: f32,
    geom_id: u32,
    prim_id: u32,
    inst_id: u32,
    u: f32,
    v: f32,
    ng: [f32; 3],
}

impl From<&Hit> for HitRecord {
    /// A miss is written as [`Hit::MISS`], whatever else the record holds, so
    /// a backend's leftovers (Embree leaves u, v and Ng of earlier rays on a
    /// miss) never reach the file.
    fn from(hit: &Hit) -> Self {
        let h = if hit.is_hit() { hit } else { &Hit::MISS };
        HitRecord {
            t: h.t,
            geom_id: h.geom_id,
            prim_id: h.prim_id,
            inst_id: h.inst_id,
            u: h.u,
            v: h.v,
            ng: h.ng.to_array(),
        }
    }
}

/// Reads rays from a `.npy` array of shape (N, 6) (origin, direction) or
/// (N, 8) (adding tnear, tfar), little-endian float32 or float64, C order.
///
/// Without the last two columns tnear is 0 and tfar infinity. Every ray must
/// have a finite origin, a finite non-zero direction, a tnear that is neither
/// NaN nor negative and a tfar that is not NaN (Embree's valid segments lie in
/// [0, inf]). A tfar below tnear is allowed: the interval is empty and the ray
/// misses, which is how embreex callers switch rays off.
pub fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    let (file, len) = super::input::open_regular(path)?;
    let bad = |msg| refused(path, msg);
    let mut reader = BufReader::new(file.take(len));

    let (header, start) = read_header(&mut reader, len).map_err(bad)?;
    let elem = match numpy_descr(&header.dtype()).as_str() {
        "'<f4'" => Elem::F32,
        "'<f8'" => Elem::F64,
        other => {
            return Err(bad(format!(
                "rays must be little-endian float32 ('<f4') or float64 ('<f8'), \
                 found dtype {other} (use arr.astype('<f4'))"
            )));
        }
    };
    if header.order() == Order::Fortran {
        return Err(bad("rays must be in C order, found fortran_order True \
             (use np.ascontiguousarray)"
            .into()));
    }
    let (n, cols) = match *header.shape() {
        [n, cols @ (6 | 8)] => (n, cols),
        ref shape => {
            return Err(bad(format!(
                "rays must have shape (N, 6) or (N, 8), found {}",
                shape_repr(shape)
            )));
        }
    };

    // Checked against the file's size before anything is allocated.
    let need = n
        .checked_mul(cols * elem.size())
        .ok_or_else(|| bad(format!("shape ({n}, {cols}) is too large")))?;
    let have = len - start;
    if have < need {
        return Err(bad(format!(
            "truncated: shape ({n}, {cols}) needs {need} data bytes, the file has {have}"
        )));
    }
    if have > need {
        // np.save never leaves trailing bytes, so extra data means the header
        // and the contents disagree; guessing which one is right would hide it.
        return Err(bad(format!(
            "{} bytes after the data of shape ({n}, {cols}); the header does not match the contents",
            have - need
        )));
    }
    let data = NpyFile::with_header(header, reader);
    let cols = cols as usize;
    match elem {
        Elem::F32 => checked_rays(path, data, cols, |v: f32| v, ""),
        // A float64 value can overflow to inf or underflow to zero in float32:
        // say so, or the message would contradict the numbers the user wrote.
        Elem::F64 => checked_rays(path, data, cols, |v: f64| v as f32, " as float32"),
    }
}

/// The rays of a file's data, `cols` values a row, each row checked as it
/// arrives, into a list that grows with what was read: memory follows the
/// file's real content, and a sparse hole (zeros: a zero direction) is
/// refused at its first row.
fn checked_rays<T: npyz::Deserialize>(
    path: &Path,
    data: NpyFile<impl Read>,
    cols: usize,
    to_f32: fn(T) -> f32,
    as_f32: &str,
) -> Result<Vec<Ray>> {
    let bad = |msg| refused(path, msg);
    // The dtype was checked to be T's, so npyz has no reason to refuse it.
    let values = data.data::<T>().map_err(|e| bad(e.to_string()))?;
    let mut rays = Vec::with_capacity((values.len() / cols as u64).min(1 << 16) as usize);
    let mut row = [0.0f32; 8];
    for (k, value) in values.enumerate() {
        row[k % cols] = to_f32(value.map_err(|e| Error::io(path, e))?);
        if k % cols == cols - 1 {
            let ray = checked_ray(&row[..cols], as_f32)
                .map_err(|problem| bad(format!("ray {} (0-based row): {problem}", rays.len())))?;
            rays.push(ray);
        }
    }
    Ok(rays)
}

/// A ray file refused: `msg` after the file's name.
fn refused(path: &Path, msg: String) -> Error {
    Error::Input(format!("{}: {msg}", path.display()))
}

/// The ray of one row (origin, direction, and tnear, tfar if given), or
/// what is wrong with it: whatever any backend would refuse (`Ray::problem`),
/// said here with the file's name and the row.
fn checked_ray(row: &[f32], as_f32: &str) -> Result<Ray, String> {
    let (tnear, tfar) = match row {
        &[.., tnear, tfar] if row.len() == 8 => (tnear, tfar),
        _ => (0.0, f32::INFINITY),
    };
    let ray = Ray {
        origin: Vec3::new(row[0], row[1], row[2]),
        dir: Vec3::new(row[3], row[4], row[5]),
        tnear,
        tfar,
    };
    match ray.problem() {
        Some(problem) => Err(format!("{problem}{as_f32}")),
        None => Ok(ray),
    }
}

/// Writes rays as a (N, 8) little-endian float32 array: origin, direction,
/// tnear, tfar. [`read_rays`] reads it back unchanged.
pub fn write_rays(path: &Path, rays: &[Ray]) -> Result<()> {
    let values = rays.iter().flat_map(|r| {
        [
            r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar,
        ]
    });
    write_2d(path, 8, values)
}

/// Writes a triangle mesh for programs outside sturmray (the C harness under
/// benches/): the positions as a (V, 3) float32 array, the triangles as a
/// (T, 3) uint32 array of vertex indices, both little-endian, C order.
pub fn write_mesh(
    positions_path: &Path,
    triangles_path: &Path,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<()> {
    write_2d(
        positions_path,
        3,
        positions.iter().flat_map(|p| p.to_array()),
    )?;
    write_2d(triangles_path, 3, triangles.iter().flatten().copied())
}

/// Writes a 2-D array of `cols` columns, row after row, atomically. npyz
/// leaves room in the header for a 20-digit row count and pads the count it
/// writes with spaces; for the float32 and uint32 arrays written here the
/// header is 128 bytes with any count, so it is byte for byte the one
/// `np.save` writes (the round-trip test pins it).
fn write_2d<T: AutoSerialize>(
    path: &Path,
    cols: u64,
    values: impl IntoIterator<Item = T>,
) -> Result<()> {
    super::output::write_atomic(path, |w| {
        let write = || {
            let mut array = npyz::WriteOptions::new()
                .default_dtype()
                .writer(w)
                .begin_2d(cols)?;
            array.extend(values)?;
            array.finish()
        };
        write().map_err(|e| Error::io(path, e))
    })
}

/// Writes hits as one structured array of shape (N,) of [`HitRecord`]s,
/// which `np.load` reads as is, streamed through a buffer so a large hit
/// array is never held twice, and atomically.
pub fn write_hits(path: &Path, hits: &[Hit]) -> Result<()> {
    let dtype = HitRecord::default_dtype();
    let header = numpy_header_1d(&numpy_descr(&dtype), hits.len());
    let records = <HitRecord as npyz::Serialize>::writer(&dtype)
        .map_err(|e| Error::Internal(format!("the hit record's own dtype: {e}")))?;
    super::output::write_atomic(path, |w| {
        w.write_all(&header)
            .and_then(|()| {
                hits.iter()
                    .try_for_each(|hit| records.write_one(&mut *w, &HitRecord::from(hit)))
            })
            .map_err(|e| Error::io(path, e))
    })
}

/// Writes the per-ray offsets of `trace --all-hits` as a 1-D little-endian
/// uint64 array of N + 1 values: ray i's hits are rows offsets[i] to
/// offsets[i + 1] of the hits file.
pub fn write_offsets(path: &Path, offsets: &[u64]) -> Result<()> {
    write_1d(path, "'<u8'", offsets.len(), |w| {
        offsets
            .iter()
            .try_for_each(|o| w.write_all(&o.to_le_bytes()))
    })
}

/// Writes one bool per ray (`trace --any-hit`) as a 1-D array.
pub fn write_bools(path: &Path, values: &[bool]) -> Result<()> {
    write_1d(path, "'|b1'", values.len(), |w| {
        values.iter().try_for_each(|&b| w.write_all(&[u8::from(b)]))
    })
}

/// Writes a 1-D array of `len` values of `descr` with the header `np.save`
/// writes, the values by `body`, atomically.
fn write_1d(
    path: &Path,
    descr: &str,
    len: usize,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let header = numpy_header_1d(descr, len);
    super::output::write_atomic(path, |w| {
        w.write_all(&header)
            .and_then(|()| body(&mut *w))
            .map_err(|e| Error::io(path, e))
    })
}

/// The header `np.save` writes for a 1-D array of `len` records of `descr`,
/// kept here because npyz spells a record `[…, ]` and pads for a 20-digit
/// count, which NumPy reads but never writes: hits files stay byte for byte
/// what they were.
fn numpy_header_1d(descr: &str, len: usize) -> Vec<u8> {
    let dict = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': ({len},), }}");
    // Version 1, whose length is a u16: a record's descr and one count are
    // far below 64 KiB.
    let prefix = MAGIC.len() + 2 + 2;
    let padded = (prefix + dict.len() + 1).div_ceil(ALIGN) * ALIGN;
    let mut out = Vec::with_capacity(padded);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&((padded - prefix) as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out.resize(padded - 1, b' ');
    out.push(b'\n');
    out
}

/// A dtype as NumPy spells it (`'<f4'`, `[('t', '<f4'), ('ng', '<f4', (3,))]`),
/// for the hits header and for messages: npyz's `DType::descr` ends a record
/// with `, ]`.
fn numpy_descr(dtype: &DType) -> String {
    match dtype {
        DType::Plain(ty) => format!("'{ty}'"),
        DType::Record(fields) => {
            let fields: Vec<String> = fields
                .iter()
                .map(|f| format!("('{}', {})", f.name, field_type(&f.dtype)))
                .collect();
            format!("[{}]", fields.join(", "))
        }
        DType::Array(..) => format!("({})", field_type(dtype)),
    }
}

/// A record field's type: its element dtype, then its shape if it is an array.
fn field_type(dtype: &DType) -> String {
    let mut shape = Vec::new();
    let mut elem = dtype;
    while let DType::Array(n, inner) = elem {
        shape.push(*n);
        elem = inner;
    }
    match shape.as_slice() {
        [] => numpy_descr(elem),
        shape => format!("{}, {}", numpy_descr(elem), shape_repr(shape)),
    }
}

fn shape_repr(shape: &[u64]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => {
            let dims: Vec<String> = shape.iter().map(ToString::to_string).collect();
            format!("({})", dims.join(", "))
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Elem {
    F32,
    F64,
}

impl Elem {
    fn size(self) -> u64 {
        match self {
            Elem::F32 => 4,
            Elem::F64 => 8,
        }
    }
}

/// np.load refuses longer headers by default (its `max_header_size`), so
/// every file NumPy reads fits; it bounds what a hostile length makes us read
/// (npyz would allocate whatever the length field says).
const MAX_HEADER: u64 = 10_000;

/// Reads the header of a .npy file of `len` bytes: the magic, version and
/// length are checked here, then the dict (see [`checked_dict`]) is handed
/// to npyz. Returns the header and the offset where the data starts.
fn read_header(r: &mut impl Read, len: u64) -> Result<(NpyHeader, u64), String> {
    let failed = |e: std::io::Error| format!("cannot read the header: {e}");
    let mut prefix = [0u8; 8];
    if len < 8 {
        return Err(NOT_NPY.into());
    }
    r.read_exact(&mut prefix).map_err(failed)?;
    if &prefix[..6] != MAGIC {
        return Err(NOT_NPY.into());
    }
    let (major, minor) = (prefix[6], prefix[7]);
    // The header's length is a u16 in version 1, a u32 in 2 and 3.
    let width = match major {
        1 => 2,
        // Version 3 differs from 2 only in allowing UTF-8 in the header,
        // which a valid rays header never needs; accept it all the same.
        2 | 3 => 4,
        _ => {
            return Err(format!(
                ".npy format version {major}.{minor} is not supported (expected 1.0, 2.0 or 3.0)"
            ));
        }
    };
    let start = 8 + width as u64;
    if len < start {
        return Err("truncated header".into());
    }
    let mut size = [0u8; 4];
    r.read_exact(&mut size[..width]).map_err(failed)?;
    let size = u64::from(u32::from_le_bytes(size));
    if start + size > len {
        return Err(format!(
            "truncated: the header claims {size} bytes, the file is shorter"
        ));
    }
    if size > MAX_HEADER {
        return Err(format!(
            "the header claims {size} bytes; NumPy reads at most {MAX_HEADER}"
        ));
    }
    let mut text = vec![0u8; size as usize];
    r.read_exact(&mut text).map_err(failed)?;
    let text = String::from_utf8(text)
        .map_err(|_| "the header is not text (expected a Python dict literal)".to_string())?;
    let dict = checked_dict(&text)?;

    // npyz reads the same magic and version, with the length of the dict it
    // is given (no longer than the file's: see `python3_spelling`).
    let mut bytes = prefix.to_vec();
    bytes.extend_from_slice(&(dict.len() as u32).to_le_bytes()[..width]);
    bytes.extend_from_slice(dict.as_bytes());
    let header =
        NpyHeader::from_reader(&bytes[..]).map_err(|e| malformed(&text, &e.to_string()))?;
    Ok((header, start + size))
}

const NOT_NPY: &str = "not a NumPy .npy file (expected the magic \\x93NUMPY at the start)";

fn malformed(text: &str, why: &str) -> String {
    format!("malformed .npy header ({why}): {}", text.trim_end())
}

/// The header's dict in the spelling npyz reads (see [`python3_spelling`]),
/// after the checks npyz does not make: no key beyond `descr`,
/// `fortran_order` and `shape` (np.load refuses them too; a file with them
/// was not written by NumPy and may mean something we would ignore), and a
/// shape whose size fits in a u64 (npyz multiplies the dimensions unchecked,
/// which panics in a debug build).
fn checked_dict(text: &str) -> Result<String, String> {
    let spelled = python3_spelling(text).map_err(|why| malformed(text, &why))?;
    let dict = spelled
        .trim_end()
        .parse::<Value>()
        .map_err(|e| malformed(text, &syntax_error(&e)))?;
    let Value::Dict(entries) = &dict else {
        return Err(malformed(text, "expected a dict"));
    };
    for (key, value) in entries {
        match key {
            Value::String(key) if key == "shape" => {
                if let Value::Tuple(dims) | Value::List(dims) = value
                    && !fits_u64(dims)
                {
                    return Err(format!("shape {value} is too large"));
                }
            }
            Value::String(key) if key == "descr" || key == "fortran_order" => {}
            Value::String(other) => {
                return Err(malformed(text, &format!("unexpected key {other:?}")));
            }
            other => return Err(malformed(text, &format!("key {other} is not a string"))),
        }
    }
    Ok(spelled)
}

/// Whether the product of the dimensions that are non-zero integers fits in
/// a u64, so that every partial product npyz forms (its strides, its count)
/// does too. Other entries are npyz's to refuse.
fn fits_u64(dims: &[Value]) -> bool {
    dims.iter()
        .filter_map(|d| match d {
            Value::Integer(n) => u64::try_from(n).ok(),
            _ => None,
        })
        .filter(|&d| d != 0)
        .try_fold(1u64, u64::checked_mul)
        .is_some()
}

/// One line of py_literal's syntax error, which is pest's multi-line
/// picture of the text: what was expected and where (the header is one
/// line, so its column).
fn syntax_error(error: &py_literal::ParseError) -> String {
    let text = error.to_string();
    let column = text
        .lines()
        .find_map(|l| l.split_once("--> "))
        .and_then(|(_, at)| at.split_once(':'))
        .map(|(_, column)| column);
    let what = text.lines().find_map(|l| l.trim().strip_prefix("= "));
    match (what, column) {
        (Some(what), Some(column)) => format!("{what} at column {column}"),
        _ => text.split_whitespace().collect::<Vec<_>>().join(" "),
    }
}

/// Deep enough for any rays header (2) and a record dtype or two; see
/// [`python3_spelling`] for why it is small.
const MAX_DEPTH: usize = 8;

/// The header's text as py_literal (npyz's parser) reads it, or why not.
///
/// NumPy still reads headers written under Python 2, whose integers may end
/// in `L` and whose strings may start with `u`; py_literal, like Python 3's
/// parser, reads neither, so both are dropped outside strings. And the
/// brackets nest at most [`MAX_DEPTH`] deep: py_literal's parser backtracks,
/// doubling its work at each level of brackets that end without a comma, so
/// thirty nested parentheses in a hostile header would take hours.
fn python3_spelling(text: &str) -> Result<String, String> {
    let s = text.as_bytes();
    let mut out = Vec::with_capacity(s.len());
    let mut depth = 0usize;
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        match c {
            b'\'' | b'"' => {
                // A whole string, copied as is, ending where py_literal ends
                // it: at the next unescaped quote of its kind (it reads `'''`
                // as an empty string and a quote, never as a long string).
                let mut end = i + 1;
                while end < s.len() && s[end] != c {
                    end += if s[end] == b'\\' { 2 } else { 1 };
                }
                let end = (end + 1).min(s.len());
                out.extend_from_slice(&s[i..end]);
                i = end;
                continue;
            }
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_DEPTH {
                    return Err(format!("nested more than {MAX_DEPTH} deep"));
                }
            }
            // Below zero the parse fails there, before any deeper text.
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b'L' | b'l' if out.last().is_some_and(u8::is_ascii_digit) => {
                i += 1;
                continue;
            }
            b'u' | b'U'
                if matches!(s.get(i + 1), Some(b'\'' | b'"'))
                    && !out
                        .last()
                        .is_some_and(|&p| p.is_ascii_alphanumeric() || p == b'_') =>
            {
                i += 1;
                continue;
            }
            _ => {}
        }
        out.push(c);
        i += 1;
    }
    // Only ASCII bytes were dropped, so the text is still UTF-8.
    Ok(String::from_utf8_lossy(&out).into_owned())
}

#[cfg(test)]
mod tests;
