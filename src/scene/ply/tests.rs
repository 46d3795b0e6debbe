use super::*;

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The error of a file that must not load.
fn message(result: Result<ObjFile>) -> String {
    match result {
        Ok(_) => panic!("the file loaded"),
        Err(e) => e.to_string(),
    }
}

const ASCII_QUAD: &str = "ply\nformat ascii 1.0\ncomment a unit quad\n\
element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
property float s\nproperty float t\n\
property uchar red\nproperty uchar green\nproperty uchar blue\n\
element face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0 0 0 255 0 0\n1 0 0 1 0 0 255 0\n1 1 0 1 1 0 0 255\n0 1 0 0 1 255 255 255\n\
4 0 1 2 3\n";

#[test]
fn an_ascii_quad_is_two_fan_triangles_with_uv_and_linear_colours() {
    let dir = tempfile::tempdir().unwrap();
    let file = load_ply(&write(dir.path(), "quad.ply", ASCII_QUAD.as_bytes())).unwrap();
    let mesh = &file.meshes[0];
    assert_eq!(mesh.name, "quad");
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(mesh.materials, vec![INVALID_ID; 2]);
    assert_eq!(mesh.uvs[2], Vec2::new(1.0, 1.0));
    assert!(mesh.normals.is_empty());
    // 255 is 1 in sRGB and linear alike; white stays white.
    assert_eq!(mesh.colours[0], Vec3::X);
    assert_eq!(mesh.colours[3], Vec3::ONE);
    assert_eq!(file.degenerate, 0);
}

#[test]
fn meshlabs_per_corner_uv_is_a_warning_and_no_uv() {
    let dir = tempfile::tempdir().unwrap();
    let text = "ply\nformat ascii 1.0\ncomment TextureFile tex.png\n\
        element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
        element face 1\nproperty list uchar int vertex_indices\n\
        property list uchar float texcoord\nend_header\n\
        0 0 0\n1 0 0\n0 1 0\n3 0 1 2 6 0 0 1 0 0 1\n";
    let file = load_ply(&write(dir.path(), "wedge.ply", text.as_bytes())).unwrap();
    assert_eq!(file.meshes[0].triangles, vec![[0, 1, 2]]);
    assert!(file.meshes[0].uvs.is_empty());
    assert_eq!(file.unread.len(), 1, "{:?}", file.unread);
    assert!(
        file.unread[0].contains("wedge.ply") && file.unread[0].contains("`texcoord`"),
        "{:?}",
        file.unread
    );
    // A file without them has nothing to say.
    let quad = load_ply(&write(dir.path(), "quad.ply", ASCII_QUAD.as_bytes())).unwrap();
    assert!(quad.unread.is_empty());
}

#[test]
fn malformed_files_are_errors_naming_the_file_and_the_element() {
    let dir = tempfile::tempdir().unwrap();
    // Each case: ASCII_QUAD with one text replaced, and what the error says.
    let face = "4 0 1 2 3\n";
    let cases = [
        ("short", face, "", "face 0"),
        ("word", "1 1 0 1 1", "1 one 0 1 1", "vertex 2"),
        ("range", face, "4 0 1 2 9\n", "vertex index 9"),
        ("line", face, "2 0 1\n", "at least 3"),
        ("negative", face, "3 0 -1 2\n", "negative"),
        ("huge", "1 1 0 1 1", "1 1e30 0 1 1", "finite"),
        ("header", "element vertex 4", "element vertex", "header"),
    ];
    for (name, from, to, expected) in cases {
        let text = ASCII_QUAD.replace(from, to);
        let path = write(dir.path(), &format!("{name}.ply"), text.as_bytes());
        let msg = message(load_ply(&path));
        assert!(
            msg.contains(expected) && msg.contains(&format!("{name}.ply")),
            "{name}: {msg}"
        );
    }
    // An ASCII file's errors name the line: the word is on line 18.
    let text = ASCII_QUAD.replace("1 1 0 1 1", "1 one 0 1 1");
    let msg = message(load_ply(&write(dir.path(), "l.ply", text.as_bytes())));
    assert!(
        msg.contains("l.ply:18: vertex 2: expected the numbers of x y z s t red green blue"),
        "{msg}"
    );
}

#[test]
fn a_truncated_binary_file_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
property float x\nproperty float y\nproperty float z\n\
element face 1\nproperty list uchar uint vertex_indices\nend_header\n"
        .to_vec();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0] {
        bytes.extend(v.to_le_bytes());
    }
    let msg = message(load_ply(&write(dir.path(), "cut.ply", &bytes)));
    assert!(msg.contains("cut.ply") && msg.contains("vertex 2"), "{msg}");
}
