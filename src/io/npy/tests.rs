//! Tests of the .npy reader and writers: exact bytes out, every refusal in.

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
fn split(bytes: &[u8]) -> (NpyHeader, &[u8]) {
    let (header, start) = read_header(&mut &bytes[..], bytes.len() as u64).unwrap();
    (header, &bytes[start as usize..])
}

/// A header's dtype as NumPy spells it and its shape.
fn descr_shape(h: &NpyHeader) -> (String, Vec<u64>) {
    (numpy_descr(&h.dtype()), h.shape().to_vec())
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
    // Byte for byte the header np.save writes.
    let header = npy(
        "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }",
        &[],
    );
    assert_eq!(bytes[..128], header[..]);
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
    assert_eq!(descr_shape(&h), ("'<f4'".into(), vec![2, 3]));
    assert_eq!(data, f4(&[0., 1., 2., -3., 4.5, 6.]));
    let (h, data) = split(&t_bytes);
    assert_eq!(descr_shape(&h), ("'<u4'".into(), vec![2, 3]));
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
            inst_id: 2,
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
                ('inst_id', '<u4'), ('u', '<f4'), ('v', '<f4'), ('ng', '<f4', (3,))], \
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
    assert_eq!(bytes.len(), data_start + 2 * 36);

    let mut expect = Vec::new();
    expect.extend(f4(&[1.5]));
    expect.extend(3u32.to_le_bytes());
    expect.extend(7u32.to_le_bytes());
    expect.extend(2u32.to_le_bytes());
    expect.extend(f4(&[0.25, 0.5, 0., 0., -2.]));
    expect.extend(f4(&[f32::INFINITY]));
    expect.extend(u32::MAX.to_le_bytes());
    expect.extend(u32::MAX.to_le_bytes());
    expect.extend(u32::MAX.to_le_bytes());
    expect.extend(f4(&[0.; 5]));
    assert_eq!(&bytes[data_start..], &expect[..]);

    // The header parses back with our own reader (npyz's parser).
    let (h, data) = split(&bytes);
    assert_eq!(h.shape(), [2]);
    assert_eq!(h.order(), Order::C);
    assert_eq!(data.len(), 72);
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
fn header_text_is_read_as_python_reads_it() {
    let parse = |s: &str| -> Value { python3_spelling(s).unwrap().parse().unwrap() };
    let int = |n: u32| Value::Integer(n.into());
    assert_eq!(parse("(3,)"), Value::Tuple(vec![int(3)]));
    assert_eq!(parse("()"), Value::Tuple(vec![]));
    assert_eq!(parse(" ( 4 , 5 , ) "), Value::Tuple(vec![int(4), int(5)]));
    assert_eq!(parse(r"'a\'b'"), Value::String("a'b".into()));
    // Python 2's spellings, outside strings only.
    assert_eq!(parse("u'x'"), Value::String("x".into()));
    assert_eq!(parse("(1L, 2l)"), Value::Tuple(vec![int(1), int(2)]));
    assert_eq!(parse("'1L u'"), Value::String("1L u".into()));
    assert_eq!(parse(r"'x\'1L'"), Value::String("x'1L".into()));
    assert!(
        python3_spelling("{'a' 1}")
            .unwrap()
            .parse::<Value>()
            .is_err()
    );

    // Nesting is bounded before py_literal sees it (it would take hours), and
    // brackets inside strings do not count.
    let deep = format!("{}1{}", "(".repeat(35), ")".repeat(35));
    assert!(python3_spelling(&deep).unwrap_err().contains("nested"));
    assert!(python3_spelling("'(((((((((((((('").is_ok());
    assert!(python3_spelling("('(((((((((((((' , ((((((((((((1))))))))))))").is_err());

    // In a file: a parenthesised shape (Python's `(3)` is 3, not a tuple), a
    // deep one and one too large for any machine are refused by name, quickly
    // and without a panic.
    for (name, shape, needle) in [
        ("paren", "(3)".to_string(), "malformed .npy header"),
        ("deep", deep, "nested more than 8 deep"),
        (
            "huge",
            "(99999999999999999999999999, 6)".into(),
            "larger than u64",
        ),
        (
            "overflow",
            "(4611686018427387904, 8)".into(),
            "(4611686018427387904, 8) is too large",
        ),
        (
            "overflow0",
            "(0, 4611686018427387904, 8)".into(),
            "(0, 4611686018427387904, 8) is too large",
        ),
        (
            "overflow2",
            "(1152921504606846976, 8)".into(),
            "shape (1152921504606846976, 8) is too large",
        ),
    ] {
        let dict = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape}, }}");
        let msg = input_err(read_bytes(name, &npy(&dict, &[])));
        assert!(msg.contains(needle), "{name}: {msg}");
    }
}
