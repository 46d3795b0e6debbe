//! OpenEXR output: the beauty image and its AOVs in one part (the EXR
//! contract in ARCHITECTURE.md).
//!
//! The file has one layer with the f32 channels `R`, `G`, `B` (beauty), `Z`
//! (depth), `normal.X/Y/Z` and `albedo.R/G/B`, ZIP-compressed scanlines in
//! increasing order, plus the caller's string attributes. Two writes of equal
//! data give byte-identical files: the header carries nothing that changes
//! between runs, and its attributes are stored sorted by name (see
//! `sort_header_attributes` for why this needs doing by hand).

use std::io::{Cursor, Write};
use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, IntegerBounds, Layer,
    LayerAttributes, ReadChannels, ReadLayers, Text, Vec2, WritableImage,
};

use crate::error::{Error, Result};

/// The layers of a rendered image, row-major with row 0 at the top. Every
/// slice holds `width * height` pixels: the data window, at `origin` in a
/// display window of size `display` (the whole image; a tile or crop is a
/// part of it).
#[derive(Clone, Copy, Debug)]
pub struct ImageLayers<'a> {
    pub width: usize,
    pub height: usize,
    pub origin: (usize, usize),
    pub display: (usize, usize),
    pub beauty: &'a [[f32; 3]],
    pub depth: &'a [f32],
    pub normal: &'a [[f32; 3]],
    pub albedo: &'a [[f32; 3]],
}

/// Writes `layers` as a single-part EXR with the channels `R`, `G`, `B`, `Z`,
/// `normal.X/Y/Z`, `albedo.R/G/B` (f32, ZIP) and `attributes` as string
/// attributes of the header.
///
/// Attribute names and values must be ASCII (EXR text is 8-bit and has no
/// declared encoding), names non-empty, unique and not one of the standard
/// EXR attribute names such as `channels` or `compression`.
pub fn write_exr(path: &Path, layers: &ImageLayers, attributes: &[(&str, String)]) -> Result<()> {
    let bad = |msg: String| Error::Input(format!("EXR {}: {msg}", path.display()));
    let (w, h) = (layers.width, layers.height);
    if w == 0 || h == 0 {
        return Err(bad(format!("image size {w}x{h} is empty")));
    }
    let n = w
        .checked_mul(h)
        .ok_or_else(|| bad(format!("image size {w}x{h} is too large")))?;
    for (name, len) in [
        ("beauty", layers.beauty.len()),
        ("depth", layers.depth.len()),
        ("normal", layers.normal.len()),
        ("albedo", layers.albedo.len()),
    ] {
        if len != n {
            return Err(bad(format!(
                "the {name} layer has {len} pixels, expected {n} ({w} x {h})"
            )));
        }
    }

    let (x0, y0) = layers.origin;
    let (dw, dh) = layers.display;
    if x0 + w > dw || y0 + h > dh {
        return Err(bad(format!(
            "the data window {w}x{h} at ({x0}, {y0}) leaves the display window {dw}x{dh}"
        )));
    }
    let position = |v: usize| i32::try_from(v).map_err(|_| bad(format!("{v} is too large")));
    let mut attrs = LayerAttributes {
        layer_position: Vec2(position(x0)?, position(y0)?),
        ..LayerAttributes::default()
    };
    for (i, (name, value)) in attributes.iter().enumerate() {
        // EXR names are NUL-terminated, values length-prefixed.
        if name.is_empty() || name.contains('\0') || !name.is_ascii() || !value.is_ascii() {
            return Err(bad(format!(
                "attribute {name:?} = {value:?}: names must be non-empty without NUL, \
                 and both must be ASCII"
            )));
        }
        if attributes[..i].iter().any(|(other, _)| other == name) {
            return Err(bad(format!("attribute {name:?} is given twice")));
        }
        // Both checked ASCII above, so the conversion cannot fail.
        let text = |s: &str| Text::new_or_none(s).expect("ASCII is valid EXR text");
        attrs
            .other
            .insert(text(name), AttributeValue::Text(text(value)));
    }

    // exr guesses the pLinear flag from the channel name and marks normal.*
    // and albedo.* perceptually linear; albedo is light-linear like R, G, B.
    // The flag only steers lossy compressors, but a header should not claim
    // it, so every channel gets OpenEXR's default, false.
    let channel = |name: &str, values: Vec<f32>| AnyChannel {
        quantize_linearly: false,
        ..AnyChannel::new(name, FlatSamples::F32(values))
    };
    let split3 = |px: &[[f32; 3]], c: usize| px.iter().map(|p| p[c]).collect();
    let channels = vec![
        channel("R", split3(layers.beauty, 0)),
        channel("G", split3(layers.beauty, 1)),
        channel("B", split3(layers.beauty, 2)),
        channel("Z", layers.depth.to_vec()),
        channel("normal.X", split3(layers.normal, 0)),
        channel("normal.Y", split3(layers.normal, 1)),
        channel("normal.Z", split3(layers.normal, 2)),
        channel("albedo.R", split3(layers.albedo, 0)),
        channel("albedo.G", split3(layers.albedo, 1)),
        channel("albedo.B", split3(layers.albedo, 2)),
    ];
    // SMALL_LOSSLESS is ZIP over 16 scanlines in increasing order: lossless,
    // and the fixed order makes exr's parallel compressor emit the blocks in
    // sequence rather than as they finish, which keeps the bytes stable.
    let layer = Layer::new(
        Vec2(w, h),
        attrs,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into_iter().collect()),
    );
    let mut image = Image::from_layer(layer);
    image.attributes.display_window = IntegerBounds::new(Vec2(0, 0), Vec2(dw, dh));

    // Written to memory first so the header can be put in canonical order
    // before anything reaches the disk.
    let mut buf = Cursor::new(Vec::new());
    image.write().to_buffered(&mut buf).map_err(|e| match e {
        exr::error::Error::Io(io) => Error::io(path, io),
        // Only our own inputs can be invalid here (attribute names).
        other => bad(other.to_string()),
    })?;
    let mut bytes = buf.into_inner();
    sort_header_attributes(&mut bytes)
        .map_err(|why| Error::Internal(format!("EXR {}: {why}", path.display())))?;
    super::output::write_atomic(path, |w| {
        w.write_all(&bytes).map_err(|e| Error::io(path, e))
    })
}

/// Channels by name, each with its values row-major.
pub type Channels = Vec<(String, Vec<f32>)>;

/// Reads a single-part EXR: width, height and every channel's values as f32
/// (row-major, row 0 at the top), by name in the file's (alphabetical)
/// channel order. The size is that of the data window.
pub fn read_exr(path: &Path) -> Result<(usize, usize, Channels)> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| read_error(path, e))?;
    let [layer] = image.layer_data.as_slice() else {
        return Err(Error::Input(format!(
            "EXR {}: expected one part, found {}",
            path.display(),
            image.layer_data.len()
        )));
    };
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect();
    Ok((layer.size.0, layer.size.1, channels))
}

/// The string attributes of an EXR's header that are not standard EXR
/// attributes (those [`write_exr`] was given), sorted by name. Reads only
/// the header, so merging can check parts without decoding pixels.
pub fn read_exr_attributes(path: &Path) -> Result<Vec<(String, String)>> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| read_error(path, e))?;
    let mut out: Vec<(String, String)> = meta
        .headers
        .iter()
        .flat_map(|h| {
            h.own_attributes
                .other
                .iter()
                .chain(&h.shared_attributes.other)
        })
        .filter_map(|(name, value)| match value {
            AttributeValue::Text(text) => Some((name.to_string(), text.to_string())),
            _ => None,
        })
        .collect();
    out.sort();
    out.dedup();
    Ok(out)
}

fn read_error(path: &Path, e: exr::error::Error) -> Error {
    match e {
        exr::error::Error::Io(io) => Error::io(path, io),
        other => Error::Input(format!(
            "EXR {}: not a readable OpenEXR file: {other}",
            path.display()
        )),
    }
}

/// Puts the attributes of a single-part EXR header in name order, in place.
///
/// The exr crate keeps custom attributes in a `HashMap` with a randomly
/// seeded hasher and writes them in its iteration order, so two writes of
/// the same image list them differently. The order means nothing to readers;
/// sorting by name (which is also what the reference OpenEXR library writes)
/// makes the bytes canonical. The header's length does not change, so the
/// chunk offsets that follow it stay valid.
fn sort_header_attributes(file: &mut [u8]) -> std::result::Result<(), String> {
    const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    const MULTIPART: u8 = 0x10; // bit 12 of the version field
    if file.len() < 8 || file[..4] != MAGIC {
        return Err("the exr crate wrote no EXR magic".into());
    }
    if file[5] & MULTIPART != 0 {
        return Err("expected a single-part file".into());
    }

    // Each attribute: name NUL, type NUL, i32 little-endian size, value.
    // The list ends with a lone NUL.
    let start = 8;
    let mut pos = start;
    let mut records: Vec<(usize, usize, usize)> = Vec::new(); // (start, name end, end)
    let cstr_end = |from: usize| -> std::result::Result<usize, String> {
        file.get(from..)
            .and_then(|rest| rest.iter().position(|&b| b == 0))
            .map(|i| from + i)
            .ok_or_else(|| "unterminated header string".to_string())
    };
    loop {
        match file.get(pos) {
            None => return Err("unterminated header".into()),
            Some(0) => break,
            Some(_) => {}
        }
        let name_end = cstr_end(pos)?;
        let type_end = cstr_end(name_end + 1)?;
        let size_at = type_end + 1;
        let size = file
            .get(size_at..size_at + 4)
            .map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .and_then(|s| usize::try_from(s).ok())
            .ok_or("bad attribute size")?;
        let end = size_at + 4 + size;
        if end > file.len() {
            return Err("attribute runs past the end".into());
        }
        records.push((pos, name_end, end));
        pos = end;
    }

    let region = &file[start..pos];
    let mut sorted = Vec::with_capacity(region.len());
    records.sort_by_key(|&(s, name_end, _)| &file[s..name_end]);
    for &(s, _, e) in &records {
        sorted.extend_from_slice(&file[s..e]);
    }
    debug_assert_eq!(sorted.len(), region.len());
    file[start..pos].copy_from_slice(&sorted);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("sturmray-exr-{}-{name}.exr", std::process::id()))
    }

    /// A small image whose every channel differs, with values that would
    /// expose a lossy (half float) or misordered store.
    struct Pixels {
        beauty: Vec<[f32; 3]>,
        depth: Vec<f32>,
        normal: Vec<[f32; 3]>,
        albedo: Vec<[f32; 3]>,
    }

    fn pixels(w: usize, h: usize) -> Pixels {
        let n = w * h;
        let f = |i: usize, k: f32| (i as f32 + k) * 1.000_123 + 1e-7;
        Pixels {
            beauty: (0..n).map(|i| [f(i, 0.1), f(i, 0.2), f(i, 0.3)]).collect(),
            depth: (0..n)
                .map(|i| if i == 1 { f32::INFINITY } else { f(i, 0.4) })
                .collect(),
            normal: (0..n).map(|i| [f(i, 0.5), -f(i, 0.6), f(i, 0.7)]).collect(),
            albedo: (0..n).map(|i| [f(i, 0.8), f(i, 0.9), f(i, 0.95)]).collect(),
        }
    }

    fn layers(w: usize, h: usize, p: &Pixels) -> ImageLayers<'_> {
        ImageLayers {
            width: w,
            height: h,
            origin: (0, 0),
            display: (w, h),
            beauty: &p.beauty,
            depth: &p.depth,
            normal: &p.normal,
            albedo: &p.albedo,
        }
    }

    fn attrs() -> Vec<(&'static str, String)> {
        vec![
            ("sturmray.region", "0,0,7,5".into()),
            ("sturmray.spp", "16".into()),
            ("sturmray.seed", "42".into()),
            ("sturmray.scene_hash", "blake3:0123abcd".into()),
            ("sturmray.full_size", "7x5".into()),
            ("sturmray.frame", "0".into()),
            ("sturmray.version", "0.1.0".into()),
            ("z_last", "x".into()),
        ]
    }

    #[test]
    fn round_trip_keeps_every_channel_bitwise() {
        let (w, h) = (7, 5);
        let p = pixels(w, h);
        let path = temp("roundtrip");
        write_exr(&path, &layers(w, h, &p), &attrs()).unwrap();
        let (rw, rh, channels) = read_exr(&path).unwrap();
        let back_attrs = read_exr_attributes(&path).unwrap();
        std::fs::remove_file(&path).unwrap();

        assert_eq!((rw, rh), (w, h));
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        // EXR stores channels sorted by name.
        assert_eq!(
            names,
            [
                "B", "G", "R", "Z", "albedo.B", "albedo.G", "albedo.R", "normal.X", "normal.Y",
                "normal.Z"
            ]
        );
        let get = |name: &str| &channels.iter().find(|(n, _)| n == name).unwrap().1;
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let col = |px: &[[f32; 3]], c: usize| px.iter().map(|p| p[c].to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(get("R")), col(&p.beauty, 0));
        assert_eq!(bits(get("G")), col(&p.beauty, 1));
        assert_eq!(bits(get("B")), col(&p.beauty, 2));
        assert_eq!(bits(get("Z")), bits(&p.depth));
        assert_eq!(bits(get("normal.X")), col(&p.normal, 0));
        assert_eq!(bits(get("normal.Y")), col(&p.normal, 1));
        assert_eq!(bits(get("normal.Z")), col(&p.normal, 2));
        assert_eq!(bits(get("albedo.R")), col(&p.albedo, 0));
        assert_eq!(bits(get("albedo.G")), col(&p.albedo, 1));
        assert_eq!(bits(get("albedo.B")), col(&p.albedo, 2));

        let mut want: Vec<(String, String)> = attrs()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        want.sort();
        assert_eq!(back_attrs, want);
    }

    #[test]
    fn equal_data_gives_identical_bytes() {
        // Tall enough for several ZIP blocks, so block order is exercised.
        let (w, h) = (13, 70);
        let p = pixels(w, h);
        let first = temp("same-a");
        write_exr(&first, &layers(w, h, &p), &attrs()).unwrap();
        let a = std::fs::read(&first).unwrap();
        std::fs::remove_file(&first).unwrap();
        // Many tries: each write builds a fresh randomly seeded HashMap, so
        // an unsorted header would differ in most of them.
        for i in 0..8 {
            let path = temp(&format!("same-{i}"));
            write_exr(&path, &layers(w, h, &p), &attrs()).unwrap();
            let b = std::fs::read(&path).unwrap();
            std::fs::remove_file(&path).unwrap();
            assert!(a == b, "write {i} differs from the first");
        }
        // No clock or host leaks into the header.
        let text = String::from_utf8_lossy(&a[..a.len().min(2000)]);
        assert!(!text.contains("capDate") && !text.contains("utcOffset"));
    }

    #[test]
    fn sorts_header_attributes_by_name() {
        fn attr(name: &str, ty: &str, value: &[u8]) -> Vec<u8> {
            let mut v = name.as_bytes().to_vec();
            v.push(0);
            v.extend_from_slice(ty.as_bytes());
            v.push(0);
            v.extend_from_slice(&(value.len() as i32).to_le_bytes());
            v.extend_from_slice(value);
            v
        }
        let head = [0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
        let tail = [0u8, 9, 9, 9]; // end of header, then "chunk data"
        let build = |parts: &[&Vec<u8>]| {
            let mut f = head.to_vec();
            for p in parts {
                f.extend_from_slice(p);
            }
            f.extend_from_slice(&tail);
            f
        };
        let (a, b, c) = (
            attr("alpha", "string", b"1"),
            attr("beta", "int", &[0, 0, 0, 0]),
            attr("channels", "chlist", b""),
        );
        let mut file = build(&[&c, &a, &b]);
        sort_header_attributes(&mut file).unwrap();
        assert_eq!(file, build(&[&a, &b, &c]));

        let mut multipart = build(&[&a]);
        multipart[5] |= 0x10;
        assert!(sort_header_attributes(&mut multipart).is_err());
        let mut truncated = build(&[&a]);
        truncated.truncate(12);
        assert!(sort_header_attributes(&mut truncated).is_err());
    }

    #[test]
    fn rejects_wrong_lengths_and_bad_attributes() {
        let (w, h) = (3, 2);
        let p = pixels(w, h);
        let path = temp("bad");
        let short_depth = &p.depth[..5];
        let l = ImageLayers {
            depth: short_depth,
            ..layers(w, h, &p)
        };
        match write_exr(&path, &l, &[]) {
            Err(Error::Input(msg)) => {
                assert!(
                    msg.contains("depth") && msg.contains("5") && msg.contains("6"),
                    "{msg}"
                );
                assert!(msg.contains("sturmray-exr-"), "{msg}");
            }
            other => panic!("expected Error::Input, got {other:?}"),
        }
        let l = ImageLayers {
            width: 0,
            height: 0,
            origin: (0, 0),
            display: (0, 0),
            beauty: &[],
            depth: &[],
            normal: &[],
            albedo: &[],
        };
        assert!(matches!(write_exr(&path, &l, &[]), Err(Error::Input(_))));
        for bad in [
            vec![("a", "x".to_string()), ("a", "y".to_string())],
            vec![("", "x".to_string())],
            vec![("a\0b", "x".to_string())],
            vec![("a", "é".to_string())],
            vec![("channels", "x".to_string())],
        ] {
            assert!(
                matches!(
                    write_exr(&path, &layers(w, h, &p), &bad),
                    Err(Error::Input(_))
                ),
                "{bad:?}"
            );
        }
        assert!(!path.exists(), "a refused write must leave no file");
    }

    #[test]
    fn reading_garbage_is_bad_input() {
        let path = temp("garbage");
        std::fs::write(&path, b"not an exr file at all").unwrap();
        let r = read_exr(&path);
        let a = read_exr_attributes(&path);
        std::fs::remove_file(&path).unwrap();
        assert!(matches!(r, Err(Error::Input(_))), "{r:?}");
        assert!(matches!(a, Err(Error::Input(_))), "{a:?}");
        assert!(matches!(read_exr(&temp("missing")), Err(Error::Io { .. })));
    }
}
