//! Writing the files a command makes, so that none is ever lost or torn.
//!
//! Every output goes through [`write_atomic`]: the bytes go to a temporary
//! file in the target's folder, which is synced and then renamed over the
//! target. A full disk, a write error or a kill at any moment leaves either
//! the previous file or the complete new one, never a mixture. Before any
//! work, [`check_distinct`] refuses a command whose outputs would replace one
//! of its inputs or one another, comparing files rather than spellings.

use std::fs::File;
use std::io::BufWriter;
use std::os::unix::fs::MetadataExt;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Writes a file atomically: `body` writes the contents into a buffered
/// temporary file beside `path`, which is synced and renamed over `path`.
/// On any error the temporary is removed and `path` is left as it was. A
/// symbolic link at `path` is followed, so the file it points to is
/// replaced, as a plain write would have done.
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_owned());
    let (temporary, file) = create_temporary(&target).map_err(|e| Error::io(path, e))?;
    let mut writer = BufWriter::new(file);
    let written = body(&mut writer).and_then(|()| {
        let file = writer
            .into_inner()
            .map_err(|e| Error::io(path, e.into_error()))?;
        // The replaced file's permissions carry over, as a plain write
        // would keep them.
        if let Ok(old) = std::fs::metadata(&target) {
            file.set_permissions(old.permissions())
                .map_err(|e| Error::io(path, e))?;
        }
        // Synced before the rename: otherwise a crash could leave the new
        // name pointing at blocks that were never written.
        file.sync_all().map_err(|e| Error::io(path, e))?;
        std::fs::rename(&temporary, &target).map_err(|e| Error::io(path, e))
    });
    if written.is_err() {
        // Best effort: the error being reported matters more than this one.
        let _ = std::fs::remove_file(&temporary);
        return written;
    }
    // The rename itself is durable once the folder is synced. Some file
    // systems refuse to sync a folder; the new file is in place all the
    // same, so that is no reason to fail the command.
    if let Ok(dir) = File::open(folder(&target)) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// The folder a file is in ("." for a bare file name).
fn folder(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// A new file beside `target`, named after it and this process, that no
/// other file has: `.NAME.PID.N.tmp`.
fn create_temporary(target: &Path) -> std::io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    // Shortened to at most 64 bytes (whole characters), so a name near the
    // file system's limit (255 bytes) still has room.
    let full = target.file_name().unwrap_or_default().to_string_lossy();
    let mut end = full.len().min(64);
    while !full.is_char_boundary(end) {
        end -= 1;
    }
    let name = &full[..end];
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temporary = folder(target).join(format!(".{name}.{}.{n}.tmp", std::process::id()));
        match File::options()
            .write(true)
            .create_new(true)
            .open(&temporary)
        {
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            other => return other.map(|file| (temporary, file)),
        }
    }
}

/// Makes sure an output can be written before any work is done, so a long
/// render is not lost at the end: creates its folder (so `out/` need not
/// exist), refuses a target that is not a regular file (replacing a device
/// or a folder is never what was meant), and creates and removes a
/// temporary file beside it, as [`write_atomic`] will.
pub fn prepare(path: &Path) -> Result<()> {
    let dir = folder(path);
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    if let Ok(meta) = std::fs::metadata(path)
        && !meta.is_file()
    {
        let what = if meta.is_dir() {
            "a directory"
        } else {
            "a device, FIFO or socket"
        };
        return Err(Error::Input(format!(
            "{}: is {what}; sturmray writes its outputs only as regular files",
            path.display()
        )));
    }
    // Replacing it by rename would succeed (only the folder's permission
    // counts), but a read-only file says it is not to be written.
    if std::fs::metadata(path).is_ok_and(|m| m.permissions().readonly()) {
        return Err(Error::Input(format!(
            "{}: is read-only; sturmray does not replace it",
            path.display()
        )));
    }
    let (temporary, _) = create_temporary(path).map_err(|e| Error::io(path, e))?;
    std::fs::remove_file(&temporary).map_err(|e| Error::io(&temporary, e))
}

/// A file a command reads or writes, with what it is to the command (for
/// messages: "the scene", "--stats", ...).
pub struct Role<'a> {
    pub what: String,
    pub path: &'a Path,
}

impl<'a> Role<'a> {
    pub fn new(what: impl Into<String>, path: &'a Path) -> Self {
        Role {
            what: what.into(),
            path,
        }
    }
}

/// Refuses outputs that are the same file as an input or as another output:
/// writing them would destroy the input, or one output would replace the
/// other. Paths count as the same file when they name the same inode (hard
/// and symbolic links, `./a/../b`) or, for files not yet made, the same
/// place once the existing part of the path is resolved.
pub fn check_distinct(inputs: &[Role], outputs: &[Role]) -> Result<()> {
    let id = |role: &Role| identity(role.path).map_err(|e| Error::io(role.path, e));
    let inputs: Vec<(Identity, &Role)> = inputs
        .iter()
        .map(|r| Ok((id(r)?, r)))
        .collect::<Result<_>>()?;
    let mut seen: Vec<(Identity, &Role)> = Vec::with_capacity(outputs.len());
    for output in outputs {
        let me = id(output)?;
        let clash = inputs.iter().chain(&seen).find(|(other, _)| *other == me);
        if let Some((_, other)) = clash {
            return Err(Error::Input(format!(
                "{} {} and {} {} are the same file: sturmray never writes over a file \
                 the command reads or another of its outputs (choose another output path)",
                output.what,
                output.path.display(),
                other.what,
                other.path.display()
            )));
        }
        seen.push((me, output));
    }
    Ok(())
}

/// What makes two paths the same file.
#[derive(PartialEq, Eq)]
enum Identity {
    /// An existing file: its device and inode.
    Inode(u64, u64),
    /// A file not yet made: its absolute path with every existing folder
    /// resolved.
    Place(PathBuf),
}

fn identity(path: &Path) -> std::io::Result<Identity> {
    if let Ok(meta) = std::fs::metadata(path) {
        return Ok(Identity::Inode(meta.dev(), meta.ino()));
    }
    // Resolve the longest part of the path that exists; what follows it
    // cannot contain links, so it is joined as written (`..` steps back).
    let absolute = std::path::absolute(path)?;
    let parts: Vec<Component> = absolute.components().collect();
    let prefix = |k: usize| parts[..k].iter().collect::<PathBuf>();
    let mut k = parts.len();
    while k > 1 && std::fs::symlink_metadata(prefix(k)).is_err() {
        k -= 1;
    }
    let mut place = std::fs::canonicalize(prefix(k)).unwrap_or_else(|_| prefix(k));
    for part in &parts[k..] {
        match part {
            Component::ParentDir => {
                place.pop();
            }
            Component::CurDir => {}
            other => place.push(other),
        }
    }
    Ok(Identity::Place(place))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("sturmray-output-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_failed_write_leaves_the_previous_file_and_no_temporary() {
        let dir = dir("atomic");
        let path = dir.join("a.bin");
        write_atomic(&path, |w| {
            w.write_all(b"first").map_err(|e| Error::io(&path, e))
        })
        .unwrap();
        let err = write_atomic(&path, |w| {
            w.write_all(b"half").map_err(|e| Error::io(&path, e))?;
            Err(Error::Input("stopped".into()))
        })
        .unwrap_err();
        assert_eq!(err.to_string(), "stopped");
        assert_eq!(std::fs::read(&path).unwrap(), b"first");
        // No temporary is left beside it.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        // A link is followed: the file it names is replaced, the link stays.
        let link = dir.join("link.bin");
        std::os::unix::fs::symlink("a.bin", &link).unwrap();
        write_atomic(&link, |w| {
            w.write_all(b"second").map_err(|e| Error::io(&path, e))
        })
        .unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions_and_read_only_ones_are_refused() {
        use std::os::unix::fs::PermissionsExt;
        let dir = dir("permissions");
        let path = dir.join("private.exr");
        std::fs::write(&path, "old").unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomic(&path, |w| {
            w.write_all(b"new").map_err(|e| Error::io(&path, e))
        })
        .unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);

        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o444)).unwrap();
        let err = prepare(&path).unwrap_err().to_string();
        assert!(err.contains("read-only"), "{err}");
        // A name of 250 bytes in four-byte characters: its temporary still fits.
        let long = dir.join("🦀".repeat(62));
        write_atomic(&long, |w| {
            w.write_all(b"x").map_err(|e| Error::io(&long, e))
        })
        .unwrap();
        assert_eq!(std::fs::read(&long).unwrap(), b"x");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_same_file_is_found_under_any_spelling() {
        let dir = dir("distinct");
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "").unwrap();
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::os::unix::fs::symlink(&scene, dir.join("link.toml")).unwrap();
        std::fs::hard_link(&scene, dir.join("hard.toml")).unwrap();
        let input = [Role::new("the scene", &scene)];
        for same in [
            dir.join("sub/../s.toml"),
            dir.join("./link.toml"),
            dir.join("hard.toml"),
        ] {
            let err = check_distinct(&input, &[Role::new("the image", &same)])
                .unwrap_err()
                .to_string();
            assert!(err.contains("the scene") && err.contains("s.toml"), "{err}");
        }
        // Outputs not yet made: the same place, spelled two ways.
        let (a, b) = (dir.join("new/x.exr"), dir.join("sub/../new/./x.exr"));
        let outputs = [Role::new("the image", &a), Role::new("--stats", &b)];
        assert!(check_distinct(&input, &outputs).is_err());
        let c = dir.join("new/y.exr");
        let outputs = [Role::new("the image", &a), Role::new("--stats", &c)];
        check_distinct(&input, &outputs).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
