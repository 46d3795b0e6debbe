//! NumPy `.npy` files: rays in, hits out (the `trace` contract in ARCHITECTURE.md).
//!
//! The format is small enough to write by hand
//! (<https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html>):
//! the magic `\x93NUMPY`, a version byte pair, the header length (u16 in
//! version 1, u32 in versions 2 and 3), then an ASCII Python dict literal with
//! the keys `descr`, `fortran_order` and `shape`, padded with spaces and a
//! final `\n` so the data starts on a 64-byte boundary, then the raw data.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::math::{Hit, Ray, Vec3};

const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// NumPy aligns the data to 64 bytes so it can be memory-mapped and read with
/// SIMD loads; readers accept any multiple of 16, writers should use 64.
const ALIGN: usize = 64;

/// The hit record as a NumPy structured dtype. The field order and types are
/// the contract; one record is 32 bytes with no padding.
const HITS_DESCR: &str = "[('t', '<f4'), ('geom_id', '<u4'), ('prim_id', '<u4'), \
                          ('u', '<f4'), ('v', '<f4'), ('ng', '<f4', (3,))]";
const HIT_RECORD_BYTES: usize = 32;

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
    let bad = |msg: String| Error::Input(format!("{}: {msg}", path.display()));
    let mut reader = BufReader::new(file.take(len));

    let (header, start) = read_header(&mut reader, len).map_err(bad)?;
    let header = parse_header(&header).map_err(bad)?;
    let elem = match &header.descr {
        Lit::Str(s) if s == "<f4" => Elem::F32,
        Lit::Str(s) if s == "<f8" => Elem::F64,
        other => {
            return Err(bad(format!(
                "rays must be little-endian float32 ('<f4') or float64 ('<f8'), \
                 found dtype {} (use arr.astype('<f4'))",
                other.repr()
            )));
        }
    };
    if header.fortran_order {
        return Err(bad("rays must be in C order, found fortran_order True \
             (use np.ascontiguousarray)"
            .into()));
    }
    let (n, cols) = match header.shape.as_slice() {
        &[n, cols @ (6 | 8)] => (n, cols),
        shape => {
            return Err(bad(format!(
                "rays must have shape (N, 6) or (N, 8), found {}",
                shape_repr(shape)
            )));
        }
    };

    // Checked against the file's size before anything is allocated.
    let need = n
        .checked_mul(cols)
        .and_then(|v| v.checked_mul(elem.size()))
        .and_then(|v| u64::try_from(v).ok())
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
    // A float64 value can overflow to inf or underflow to zero in float32:
    // say so, or the message would contradict the numbers the user wrote.
    let as_f32 = if elem == Elem::F64 { " as float32" } else { "" };

    // Row by row, each checked as it arrives, into a list that grows with
    // what was read: memory follows the file's real content, and a sparse
    // hole (zeros: a zero direction) is refused at its first row.
    let mut rays = Vec::with_capacity(n.min(1 << 16));
    let mut row = vec![0u8; cols * elem.size()];
    let mut values = [0.0f32; 8];
    for i in 0..n {
        reader
            .read_exact(&mut row)
            .map_err(|e| Error::io(path, e))?;
        for (v, bytes) in values.iter_mut().zip(row.chunks_exact(elem.size())) {
            *v = elem.decode(bytes);
        }
        let ray = checked_ray(&values[..cols], as_f32)
            .map_err(|problem| bad(format!("ray {i} (0-based row): {problem}")))?;
        rays.push(ray);
    }
    Ok(rays)
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
    let header = header_bytes("'<f4'", &format!("({}, 8)", rays.len()));
    write_file(path, &header, |w| {
        for r in rays {
            for v in [
                r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar,
            ] {
                w.write_all(&v.to_le_bytes())?;
            }
        }
        Ok(())
    })
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
    let header = header_bytes("'<f4'", &format!("({}, 3)", positions.len()));
    write_file(positions_path, &header, |w| {
        positions
            .iter()
            .flat_map(|p| p.to_array())
            .try_for_each(|v| w.write_all(&v.to_le_bytes()))
    })?;
    let header = header_bytes("'<u4'", &format!("({}, 3)", triangles.len()));
    write_file(triangles_path, &header, |w| {
        triangles
            .iter()
            .flatten()
            .try_for_each(|i| w.write_all(&i.to_le_bytes()))
    })
}

/// Writes hits as one structured array of shape (N,) with the fields `t`,
/// `geom_id`, `prim_id`, `u`, `v` and `ng` (3 × f32), which `np.load` reads
/// as is. A miss is written as t = inf, both ids 4294967295 and zeros for u,
/// v and ng, whatever else the record holds, so a backend's leftovers (Embree
/// leaves u, v and Ng of earlier rays on a miss) never reach the file.
pub fn write_hits(path: &Path, hits: &[Hit]) -> Result<()> {
    let header = header_bytes(HITS_DESCR, &format!("({},)", hits.len()));
    write_file(path, &header, |w| {
        for hit in hits {
            let h = if hit.is_hit() { hit } else { &Hit::MISS };
            let mut rec = [0u8; HIT_RECORD_BYTES];
            rec[0..4].copy_from_slice(&h.t.to_le_bytes());
            rec[4..8].copy_from_slice(&h.geom_id.to_le_bytes());
            rec[8..12].copy_from_slice(&h.prim_id.to_le_bytes());
            rec[12..16].copy_from_slice(&h.u.to_le_bytes());
            rec[16..20].copy_from_slice(&h.v.to_le_bytes());
            rec[20..24].copy_from_slice(&h.ng.x.to_le_bytes());
            rec[24..28].copy_from_slice(&h.ng.y.to_le_bytes());
            rec[28..32].copy_from_slice(&h.ng.z.to_le_bytes());
            w.write_all(&rec)?;
        }
        Ok(())
    })
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Elem {
    F32,
    F64,
}

impl Elem {
    fn size(self) -> usize {
        match self {
            Elem::F32 => 4,
            Elem::F64 => 8,
        }
    }

    /// One little-endian value of `size()` bytes, as f32.
    fn decode(self, bytes: &[u8]) -> f32 {
        match self {
            Elem::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
            Elem::F64 => {
                let mut b = [0u8; 8];
                b.copy_from_slice(bytes);
                f64::from_le_bytes(b) as f32
            }
        }
    }
}

/// Streams a file through a buffer, so a large hit array is never held
/// twice, and writes it atomically.
fn write_file(
    path: &Path,
    header: &[u8],
    body: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    super::output::write_atomic(path, |w| {
        w.write_all(header)
            .and_then(|()| body(w))
            .map_err(|e| Error::io(path, e))
    })
}

/// Magic, version, length and the padded header dict, in NumPy's own layout
/// (keys sorted, trailing `, }`), so files compare equal to `np.save` output.
fn header_bytes(descr: &str, shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': {shape}, }}");
    // Version 1 stores the length in a u16; switch to version 2 only when the
    // dict cannot fit, as NumPy does.
    let (version, len_bytes) = if dict.len() + 1 + MAGIC.len() + 2 + 2 <= usize::from(u16::MAX) {
        (1u8, 2)
    } else {
        (2u8, 4)
    };
    let prefix = MAGIC.len() + 2 + len_bytes;
    let unpadded = prefix + dict.len() + 1; // + '\n'
    let padded = unpadded.div_ceil(ALIGN) * ALIGN;
    let header_len = padded - prefix;

    let mut out = Vec::with_capacity(padded);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[version, 0]);
    if version == 1 {
        out.extend_from_slice(&(header_len as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(header_len as u32).to_le_bytes());
    }
    out.extend_from_slice(dict.as_bytes());
    out.resize(padded - 1, b' ');
    out.push(b'\n');
    out
}

/// np.load refuses longer headers by default (its `max_header_size`), so
/// every file NumPy reads fits; it bounds what a hostile length makes us read.
const MAX_HEADER: u64 = 10_000;

/// Reads the magic, version and header dict of a .npy file of `len` bytes;
/// returns the dict's text and the offset where the data starts.
fn read_header(r: &mut impl Read, len: u64) -> Result<(String, u64), String> {
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
    Ok((text, start + size))
}

const NOT_NPY: &str = "not a NumPy .npy file (expected the magic \\x93NUMPY at the start)";

/// The three keys of a .npy header.
#[derive(Debug, PartialEq)]
struct Header {
    /// A string such as `'<f4'` for simple dtypes, a list for structured ones.
    descr: Lit,
    fortran_order: bool,
    shape: Vec<usize>,
}

fn parse_header(text: &str) -> Result<Header, String> {
    let bad_header = |why: String| format!("malformed .npy header ({why}): {}", text.trim_end());
    let mut p = LitParser::new(text);
    let lit = p.value().map_err(&bad_header)?;
    p.end().map_err(&bad_header)?;
    let Lit::Dict(entries) = lit else {
        return Err(bad_header("expected a dict".into()));
    };

    let (mut descr, mut fortran, mut shape) = (None, None, None);
    for (key, value) in entries {
        let Lit::Str(key) = key else {
            return Err(bad_header(format!("key {} is not a string", key.repr())));
        };
        match key.as_str() {
            "descr" => descr = Some(value),
            "fortran_order" => match value {
                Lit::Bool(b) => fortran = Some(b),
                other => {
                    return Err(bad_header(format!(
                        "fortran_order must be True or False, found {}",
                        other.repr()
                    )));
                }
            },
            "shape" => {
                let Lit::Tuple(dims) = value else {
                    return Err(bad_header(format!(
                        "shape must be a tuple, found {}",
                        value.repr()
                    )));
                };
                let dims = dims
                    .into_iter()
                    .map(|d| match d {
                        Lit::Int(n) => Ok(n),
                        other => Err(bad_header(format!(
                            "shape entries must be integers, found {}",
                            other.repr()
                        ))),
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                shape = Some(dims);
            }
            // np.load refuses extra keys too; a file with them was not
            // written by NumPy and may mean something we would ignore.
            other => return Err(bad_header(format!("unexpected key {other:?}"))),
        }
    }
    match (descr, fortran, shape) {
        (Some(descr), Some(fortran_order), Some(shape)) => Ok(Header {
            descr,
            fortran_order,
            shape,
        }),
        _ => Err(bad_header(
            "expected the keys 'descr', 'fortran_order' and 'shape'".into(),
        )),
    }
}

fn shape_repr(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => {
            let dims: Vec<String> = shape.iter().map(ToString::to_string).collect();
            format!("({})", dims.join(", "))
        }
    }
}

/// The Python literals a .npy header can contain.
#[derive(Debug, PartialEq)]
enum Lit {
    Str(String),
    Int(usize),
    Bool(bool),
    None,
    Tuple(Vec<Lit>),
    List(Vec<Lit>),
    Dict(Vec<(Lit, Lit)>),
}

impl Lit {
    /// Python-like text for error messages.
    fn repr(&self) -> String {
        let join = |items: &[Lit]| items.iter().map(Lit::repr).collect::<Vec<_>>().join(", ");
        match self {
            Lit::Str(s) => format!("'{s}'"),
            Lit::Int(n) => n.to_string(),
            Lit::Bool(true) => "True".into(),
            Lit::Bool(false) => "False".into(),
            Lit::None => "None".into(),
            Lit::Tuple(items) if items.len() == 1 => format!("({},)", items[0].repr()),
            Lit::Tuple(items) => format!("({})", join(items)),
            Lit::List(items) => format!("[{}]", join(items)),
            Lit::Dict(entries) => {
                let parts: Vec<String> = entries
                    .iter()
                    .map(|(k, v)| format!("{}: {}", k.repr(), v.repr()))
                    .collect();
                format!("{{{}}}", parts.join(", "))
            }
        }
    }
}

/// A recursive-descent parser for the subset of Python literal syntax NumPy
/// writes (and `ast.literal_eval` would accept): strings, non-negative
/// integers (with Python 2's `L` suffix), True/False/None, tuples, lists and
/// dicts, with arbitrary whitespace and trailing commas.
struct LitParser<'a> {
    s: &'a [u8],
    pos: usize,
    depth: usize,
}

/// Deep enough for any dtype; bounds recursion on hostile input.
const MAX_DEPTH: usize = 32;

impl<'a> LitParser<'a> {
    fn new(text: &'a str) -> Self {
        LitParser {
            s: text.as_bytes(),
            pos: 0,
            depth: 0,
        }
    }

    fn skip_ws(&mut self) {
        while self.pos < self.s.len() && self.s[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_ws();
        self.s.get(self.pos).copied()
    }

    fn expect(&mut self, c: u8) -> Result<(), String> {
        match self.peek() {
            Some(x) if x == c => {
                self.pos += 1;
                Ok(())
            }
            Some(x) => Err(format!(
                "expected '{}' at byte {}, found '{}'",
                c as char, self.pos, x as char
            )),
            None => Err(format!("expected '{}', found the end", c as char)),
        }
    }

    fn end(&mut self) -> Result<(), String> {
        match self.peek() {
            None => Ok(()),
            Some(_) => Err(format!("unexpected text at byte {}", self.pos)),
        }
    }

    fn value(&mut self) -> Result<Lit, String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err("nested too deeply".into());
        }
        let v = match self.peek() {
            Some(b'{') => self.dict(),
            Some(b'(') => {
                self.pos += 1;
                // A parenthesised single value without a comma is just that
                // value in Python, not a tuple.
                let (items, trailing_comma) = self.items(b')')?;
                if items.len() == 1 && !trailing_comma {
                    Ok(items.into_iter().next().expect("one item"))
                } else {
                    Ok(Lit::Tuple(items))
                }
            }
            Some(b'[') => {
                self.pos += 1;
                Ok(Lit::List(self.items(b']')?.0))
            }
            Some(b'\'' | b'"') => self.string(),
            Some(b'u' | b'b') if matches!(self.s.get(self.pos + 1), Some(b'\'' | b'"')) => {
                self.pos += 1;
                self.string()
            }
            Some(c) if c.is_ascii_digit() => self.int(),
            Some(c) if c.is_ascii_alphabetic() => self.word(),
            Some(c) => Err(format!("unexpected '{}' at byte {}", c as char, self.pos)),
            None => Err("unexpected end".into()),
        };
        self.depth -= 1;
        v
    }

    /// Comma-separated values up to `close`; also says whether a trailing
    /// comma was present (it makes `(1,)` a tuple).
    fn items(&mut self, close: u8) -> Result<(Vec<Lit>, bool), String> {
        let mut items = Vec::new();
        let mut trailing_comma = false;
        loop {
            if self.peek() == Some(close) {
                self.pos += 1;
                return Ok((items, trailing_comma));
            }
            items.push(self.value()?);
            trailing_comma = false;
            match self.peek() {
                Some(b',') => {
                    self.pos += 1;
                    trailing_comma = true;
                }
                Some(c) if c == close => {}
                _ => {
                    return Err(format!(
                        "expected ',' or '{}' at byte {}",
                        close as char, self.pos
                    ));
                }
            }
        }
    }

    fn dict(&mut self) -> Result<Lit, String> {
        self.expect(b'{')?;
        let mut entries = Vec::new();
        loop {
            if self.peek() == Some(b'}') {
                self.pos += 1;
                return Ok(Lit::Dict(entries));
            }
            let key = self.value()?;
            self.expect(b':')?;
            let value = self.value()?;
            entries.push((key, value));
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b'}') => {}
                _ => return Err(format!("expected ',' or '}}' at byte {}", self.pos)),
            }
        }
    }

    fn string(&mut self) -> Result<Lit, String> {
        let quote = self.s[self.pos];
        self.pos += 1;
        let mut out = Vec::new();
        while let Some(&c) = self.s.get(self.pos) {
            self.pos += 1;
            match c {
                _ if c == quote => {
                    return String::from_utf8(out)
                        .map(Lit::Str)
                        .map_err(|_| "string is not UTF-8".to_string());
                }
                b'\\' => {
                    let &e = self.s.get(self.pos).ok_or("unterminated string")?;
                    self.pos += 1;
                    out.push(match e {
                        b'n' => b'\n',
                        b't' => b'\t',
                        other => other,
                    });
                }
                b'\n' => return Err("unterminated string".into()),
                _ => out.push(c),
            }
        }
        Err("unterminated string".into())
    }

    fn int(&mut self) -> Result<Lit, String> {
        let start = self.pos;
        let mut n: usize = 0;
        while let Some(&c) = self.s.get(self.pos) {
            if !c.is_ascii_digit() {
                break;
            }
            n = n
                .checked_mul(10)
                .and_then(|n| n.checked_add(usize::from(c - b'0')))
                .ok_or_else(|| format!("integer at byte {start} is too large"))?;
            self.pos += 1;
        }
        if matches!(self.s.get(self.pos), Some(b'L' | b'l')) {
            self.pos += 1;
        }
        Ok(Lit::Int(n))
    }

    fn word(&mut self) -> Result<Lit, String> {
        let start = self.pos;
        while self.pos < self.s.len()
            && (self.s[self.pos].is_ascii_alphanumeric() || self.s[self.pos] == b'_')
        {
            self.pos += 1;
        }
        match &self.s[start..self.pos] {
            b"True" => Ok(Lit::Bool(true)),
            b"False" => Ok(Lit::Bool(false)),
            b"None" => Ok(Lit::None),
            w => Err(format!(
                "unexpected name '{}' at byte {start}",
                String::from_utf8_lossy(w)
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// A path in the temp folder unique to this process and test.
    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("sturmray-npy-{}-{name}.npy", std::process::id()))
    }

    /// Builds a .npy file from a header dict and raw data, padding the
    /// header like NumPy would.
    fn npy(dict: &str, data: &[u8]) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&[1, 0]);
        let mut h = dict.to_string();
        while !(10 + h.len() + 1).is_multiple_of(64) {
            h.push(' ');
        }
        h.push('\n');
        out.extend_from_slice(&(h.len() as u16).to_le_bytes());
        out.extend_from_slice(h.as_bytes());
        out.extend_from_slice(data);
        out
    }

    /// A whole file's parsed header and its data bytes.
    fn split(bytes: &[u8]) -> (Header, &[u8]) {
        let (text, start) = read_header(&mut &bytes[..], bytes.len() as u64).unwrap();
        (parse_header(&text).unwrap(), &bytes[start as usize..])
    }

    fn f4(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn read_bytes(name: &str, bytes: &[u8]) -> Result<Vec<Ray>> {
        let path = temp(name);
        std::fs::write(&path, bytes).unwrap();
        let r = read_rays(&path);
        std::fs::remove_file(&path).unwrap();
        r
    }

    fn input_err(r: Result<Vec<Ray>>) -> String {
        match r {
            Err(Error::Input(msg)) => msg,
            other => panic!("expected Error::Input, got {other:?}"),
        }
    }

    #[test]
    fn reads_n_by_6_with_default_interval() {
        let bytes = npy(
            "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 6), }",
            &f4(&[1., 2., 3., 0., 0., -1., -1., -2., -3., 0.5, 0., 0.]),
        );
        let rays = read_bytes("n6", &bytes).unwrap();
        assert_eq!(
            rays,
            vec![
                Ray::new(Vec3::new(1., 2., 3.), Vec3::new(0., 0., -1.)),
                Ray::new(Vec3::new(-1., -2., -3.), Vec3::new(0.5, 0., 0.)),
            ]
        );
        assert_eq!(rays[0].tnear, 0.0);
        assert_eq!(rays[0].tfar, f32::INFINITY);
    }

    #[test]
    fn reads_f8_and_unusual_header_spelling() {
        // Key order, double quotes, Python 2 longs and no trailing comma all
        // occur in files written by other tools.
        let data: Vec<u8> = [0.0f64, 1.0, 2.0, 1.0, 0.0, 0.0, 0.25, 9.5]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let bytes = npy(
            "{\"shape\": (1L,8L), \"fortran_order\":False,\"descr\":\"<f8\"}",
            &data,
        );
        let rays = read_bytes("f8", &bytes).unwrap();
        assert_eq!(rays.len(), 1);
        assert_eq!(rays[0].origin, Vec3::new(0., 1., 2.));
        assert_eq!(rays[0].dir, Vec3::X);
        assert_eq!((rays[0].tnear, rays[0].tfar), (0.25, 9.5));
    }

    #[test]
    fn empty_array_gives_no_rays() {
        let bytes = npy(
            "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 8), }",
            &[],
        );
        assert!(read_bytes("empty", &bytes).unwrap().is_empty());
    }

    #[test]
    fn rays_round_trip_bit_exactly() {
        let rays = vec![
            Ray {
                origin: Vec3::new(0.1, -2.5, 1e-30),
                dir: Vec3::new(-0.0, 1.0, 3.0e7),
                tnear: 1e-4,
                tfar: 12.0,
            },
            Ray::new(Vec3::new(7., 8., 9.), Vec3::new(1., 1., 1.)),
        ];
        let path = temp("roundtrip");
        write_rays(&path, &rays).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let back = read_rays(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        // The (N, 8) '<f4' dict needs 70 bytes with the prefix: padded to 128,
        // the length np.save gives it too.
        assert_eq!(bytes.len(), 128 + rays.len() * 32);
        assert_eq!(back, rays);
        // Bitwise, so -0.0 and the exact tnear survive too.
        for (a, b) in back.iter().zip(&rays) {
            assert_eq!(a.dir.x.to_bits(), b.dir.x.to_bits());
            assert_eq!(a.tnear.to_bits(), b.tnear.to_bits());
        }
    }

    #[test]
    fn mesh_files_hold_the_positions_and_indices_in_order() {
        let positions = [Vec3::new(0., 1., 2.), Vec3::new(-3., 4.5, 6.)];
        let triangles = [[0, 1, 1], [1, 0, u32::MAX]];
        let (p, t) = (temp("mesh-positions"), temp("mesh-triangles"));
        write_mesh(&p, &t, &positions, &triangles).unwrap();
        let (p_bytes, t_bytes) = (std::fs::read(&p).unwrap(), std::fs::read(&t).unwrap());
        std::fs::remove_file(&p).unwrap();
        std::fs::remove_file(&t).unwrap();

        let (h, data) = split(&p_bytes);
        assert_eq!((h.descr, h.shape), (Lit::Str("<f4".into()), vec![2, 3]));
        assert_eq!(data, f4(&[0., 1., 2., -3., 4.5, 6.]));
        let (h, data) = split(&t_bytes);
        assert_eq!((h.descr, h.shape), (Lit::Str("<u4".into()), vec![2, 3]));
        let indices: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        assert_eq!(data, indices);
    }

    #[test]
    fn hits_file_has_exact_header_and_records() {
        let hits = [
            Hit {
                t: 1.5,
                geom_id: 3,
                prim_id: 7,
                u: 0.25,
                v: 0.5,
                ng: Vec3::new(0., 0., -2.),
            },
            // A miss carrying leftovers, as Embree leaves them.
            Hit {
                u: 0.9,
                ng: Vec3::X,
                ..Hit::MISS
            },
        ];
        let path = temp("hits");
        write_hits(&path, &hits).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();

        // The dict text is exactly what np.save writes for this dtype (NumPy
        // 1.x/2.x without the growth padding it adds for appendable arrays).
        let dict = "{'descr': [('t', '<f4'), ('geom_id', '<u4'), ('prim_id', '<u4'), \
                    ('u', '<f4'), ('v', '<f4'), ('ng', '<f4', (3,))], \
                    'fortran_order': False, 'shape': (2,), }";
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let hlen = usize::from(u16::from_le_bytes([bytes[8], bytes[9]]));
        let data_start = 10 + hlen;
        assert_eq!(data_start % 64, 0);
        assert_eq!(&bytes[10..10 + dict.len()], dict.as_bytes());
        assert!(
            bytes[10 + dict.len()..data_start - 1]
                .iter()
                .all(|&b| b == b' ')
        );
        assert_eq!(bytes[data_start - 1], b'\n');
        assert_eq!(bytes.len(), data_start + 2 * 32);

        let mut expect = Vec::new();
        expect.extend(f4(&[1.5]));
        expect.extend(3u32.to_le_bytes());
        expect.extend(7u32.to_le_bytes());
        expect.extend(f4(&[0.25, 0.5, 0., 0., -2.]));
        expect.extend(f4(&[f32::INFINITY]));
        expect.extend(u32::MAX.to_le_bytes());
        expect.extend(u32::MAX.to_le_bytes());
        expect.extend(f4(&[0.; 5]));
        assert_eq!(&bytes[data_start..], &expect[..]);

        // The header parses back with our own reader's parser.
        let (h, data) = split(&bytes);
        assert_eq!(h.shape, vec![2]);
        assert!(!h.fortran_order);
        assert_eq!(data.len(), 64);
    }

    #[test]
    fn rejects_malformed_files_naming_the_path() {
        let ok = f4(&[0., 0., 0., 1., 0., 0.]);
        let cases: &[(&str, Vec<u8>, &str)] = &[
            ("magic", b"\x93NUMPX\x01\x00".to_vec(), "magic"),
            (
                "fortran",
                npy(
                    "{'descr': '<f4', 'fortran_order': True, 'shape': (1, 6), }",
                    &ok,
                ),
                "fortran_order",
            ),
            (
                "dtype",
                npy(
                    "{'descr': '<i4', 'fortran_order': False, 'shape': (1, 6), }",
                    &ok,
                ),
                "'<i4'",
            ),
            (
                "bigendian",
                npy(
                    "{'descr': '>f4', 'fortran_order': False, 'shape': (1, 6), }",
                    &ok,
                ),
                "'>f4'",
            ),
            (
                "structured",
                npy(
                    "{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (6,), }",
                    &ok,
                ),
                "[('a', '<f4')]",
            ),
            (
                "shape",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                    &ok,
                ),
                "(2, 3)",
            ),
            (
                "shape1d",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (6,), }",
                    &ok,
                ),
                "(6,)",
            ),
            (
                "truncated",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 6), }",
                    &ok,
                ),
                "truncated",
            ),
            (
                "trailing",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 6), }",
                    &ok,
                ),
                "after the data",
            ),
            (
                "badheader",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 6), ",
                    &ok,
                ),
                "malformed .npy header",
            ),
            (
                "extrakey",
                npy(
                    "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 6), 'x': 1}",
                    &ok,
                ),
                "unexpected key",
            ),
            (
                "shortlen",
                b"\x93NUMPY\x01\x00\xff\x00{".to_vec(),
                "truncated",
            ),
            (
                "version",
                b"\x93NUMPY\x04\x00\x00\x00".to_vec(),
                "version 4.0",
            ),
        ];
        for (name, bytes, needle) in cases {
            let msg = input_err(read_bytes(name, bytes));
            assert!(msg.contains(needle), "{name}: {msg}");
            assert!(msg.contains("sturmray-npy-"), "{name}: no path in {msg}");
        }
    }

    #[test]
    fn rejects_bad_rays_naming_the_row() {
        let header = "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }";
        let good = [0., 0., 0., 0., 1., 0., 0., 1.];
        let cases: &[(&str, [f32; 8], &str)] = &[
            (
                "nan_origin",
                [f32::NAN, 0., 0., 0., 1., 0., 0., 1.],
                "origin",
            ),
            (
                "inf_dir",
                [0., 0., 0., 0., f32::INFINITY, 0., 0., 1.],
                "direction",
            ),
            ("zero_dir", [0., 0., 0., 0., 0., -0., 0., 1.], "is zero"),
            ("neg_tnear", [0., 0., 0., 0., 1., 0., -1., 1.], "tnear"),
            ("nan_tfar", [0., 0., 0., 0., 1., 0., 0., f32::NAN], "tfar"),
        ];
        for (name, row, needle) in cases {
            let mut values = good.to_vec();
            values.extend_from_slice(&good);
            values.extend_from_slice(row);
            let msg = input_err(read_bytes(name, &npy(header, &f4(&values))));
            assert!(msg.contains("ray 2 "), "{name}: {msg}");
            assert!(msg.contains(needle), "{name}: {msg}");
        }
        // An empty interval is allowed: the ray simply misses.
        let mut values = good.to_vec();
        values.extend_from_slice(&good);
        values.extend_from_slice(&[0., 0., 0., 0., 1., 0., 5., 1.]);
        assert_eq!(
            read_bytes("empty_interval", &npy(header, &f4(&values)))
                .unwrap()
                .len(),
            3
        );
    }

    #[test]
    fn f8_overflow_is_reported_as_float32() {
        let data: Vec<u8> = [0.0f64, 0.0, 1e300, 1.0, 0.0, 0.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let bytes = npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 6), }",
            &data,
        );
        let msg = input_err(read_bytes("f8overflow", &bytes));
        assert!(
            msg.contains("ray 0 ") && msg.contains("as float32"),
            "{msg}"
        );
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let path = temp("does-not-exist");
        assert!(matches!(read_rays(&path), Err(Error::Io { .. })));
    }

    #[test]
    fn literal_parser_follows_python() {
        let parse = |s: &str| {
            let mut p = LitParser::new(s);
            let v = p.value().unwrap();
            p.end().unwrap();
            v
        };
        assert_eq!(parse("(3,)"), Lit::Tuple(vec![Lit::Int(3)]));
        assert_eq!(parse("(3)"), Lit::Int(3));
        assert_eq!(parse("()"), Lit::Tuple(vec![]));
        assert_eq!(
            parse(" ( 4 , 5 , ) "),
            Lit::Tuple(vec![Lit::Int(4), Lit::Int(5)])
        );
        assert_eq!(parse(r"'a\'b'"), Lit::Str("a'b".into()));
        assert_eq!(parse("u'x'"), Lit::Str("x".into()));
        assert!(
            LitParser::new(
                "(((((((((((((((((((((((((((((((((((1)))))))))))))))))))))))))))))))))))"
            )
            .value()
            .is_err()
        );
        assert!(
            LitParser::new("99999999999999999999999999")
                .value()
                .is_err()
        );
        assert!(LitParser::new("{'a' 1}").value().is_err());
    }
}
