//! The crate's error type. Every variant carries what a person needs to fix
//! the problem: the file, the line or column, and what was expected.

use std::path::PathBuf;

/// Errors sturmray reports. `main` maps [`Error::is_bad_input`] to exit code 2.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A scene file (TOML) that cannot be read or is not valid.
    #[error("{}: {message}", path.display())]
    Scene { path: PathBuf, message: String },

    /// An OBJ or MTL file that cannot be read or is malformed; `line` is 1-based, 0 when the
    /// whole file is at fault.
    #[error("{}{}: {message}", path.display(), line_suffix(*line))]
    Mesh {
        path: PathBuf,
        line: usize,
        message: String,
    },

    /// A text input (scene, OBJ, MTL) that is not text: a NUL byte or bytes
    /// that are not UTF-8 at `line` (1-based).
    #[error("{}:{line}: {message}", path.display())]
    Text {
        path: PathBuf,
        line: usize,
        message: String,
    },

    /// A scene in POV-Ray's language that cannot be read: the file (the
    /// scene or one it includes), 1-based line and column, and what is wrong.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Syntax {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },

    /// Other bad input: command-line values, ray files, output paths.
    #[error("{0}")]
    Input(String),

    /// A file that could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },

    /// An error reported by Embree, or a refused Embree library.
    #[error("Embree: {0}")]
    Embree(String),

    /// A panic caught inside a callback or worker, turned into an error.
    #[error("internal error: {0}")]
    Internal(String),
}

fn line_suffix(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}")
    }
}

impl Error {
    /// True when the user can fix the cause by changing their input (exit code 2).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            Error::Scene { .. }
                | Error::Mesh { .. }
                | Error::Text { .. }
                | Error::Syntax { .. }
                | Error::Input(_)
                | Error::Io { .. }
        )
    }

    /// An [`Error::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
