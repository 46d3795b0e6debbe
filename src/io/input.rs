//! Opening the files a command reads. Only regular files are read: a FIFO
//! would block and `/dev/zero` would never end. Text inputs are read in
//! chunks and refused at their first NUL byte, so a sparse or binary file
//! costs memory for its real content only, never for its holes.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// Opens `path` for reading if it is a regular file (symbolic links
/// followed); returns the file and its length in bytes.
pub fn open_regular(path: &Path) -> Result<(File, u64)> {
    // Checked before opening: opening a FIFO for reading waits for a writer.
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        // An I/O error like any unreadable file, so callers name the line
        // that asked for it.
        let message = format!(
            "not a regular file (a {}); sturmray reads only regular files",
            kind(&meta.file_type())
        );
        let error = std::io::Error::new(std::io::ErrorKind::InvalidInput, message);
        return Err(Error::io(path, error));
    }
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    Ok((file, meta.len()))
}

fn kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_dir() {
        "directory"
    } else if t.is_fifo() {
        "FIFO"
    } else if t.is_char_device() {
        "character device"
    } else if t.is_block_device() {
        "block device"
    } else if t.is_socket() {
        "socket"
    } else {
        "special file"
    }
}

/// Reads a text input (scene, OBJ, MTL), naming the line of the first NUL
/// byte or the first byte that is not UTF-8.
pub fn read_text(path: &Path) -> Result<String> {
    let (file, len) = open_regular(path)?;
    let mut bytes = Vec::new();
    let mut chunk = vec![0u8; 1 << 16];
    let mut reader = file.take(len);
    loop {
        let n = reader.read(&mut chunk).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        if let Some(at) = chunk[..n].iter().position(|&b| b == 0) {
            bytes.extend_from_slice(&chunk[..at]);
            return Err(not_text(path, &bytes, "a NUL byte: not a text file"));
        }
        bytes.extend_from_slice(&chunk[..n]);
    }
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        not_text(path, valid, "not UTF-8 text")
    })
}

/// An error at the line after the text `before` it.
fn not_text(path: &Path, before: &[u8], message: &str) -> Error {
    Error::Text {
        path: path.to_owned(),
        line: before.iter().filter(|&&b| b == b'\n').count() + 1,
        message: message.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_text_files_are_read() {
        let err = read_text(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(err.contains("character device"), "{err}");
        let err = read_text(Path::new("/")).unwrap_err().to_string();
        assert!(err.contains("directory"), "{err}");

        let dir = std::env::temp_dir().join(format!("sturmray-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.obj");
        std::fs::write(&path, "v 0 0 0\nv 1 0 0\n\0\0\0").unwrap();
        let err = read_text(&path).unwrap_err().to_string();
        assert!(
            err.ends_with("t.obj:3: a NUL byte: not a text file"),
            "{err}"
        );
        std::fs::write(&path, b"ok\n\xff").unwrap();
        let err = read_text(&path).unwrap_err().to_string();
        assert!(err.ends_with("t.obj:2: not UTF-8 text"), "{err}");
        std::fs::write(&path, "v 1 2 3\n").unwrap();
        assert_eq!(read_text(&path).unwrap(), "v 1 2 3\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
