//! POV-Ray scenes (`.pov`): the reader of POV-Ray's static scene language
//! (issue #20 §4) goes here; until it does, a .pov file is refused.

use std::path::Path;

use super::{LoadOptions, Scene};
use crate::error::{Error, Result};

/// POV-Ray's image size when its command line gives none (800×600).
pub(super) const DEFAULT_SIZE: (u32, u32) = (800, 600);

pub(super) fn load(path: &Path, _options: &LoadOptions) -> Result<Scene> {
    Err(Error::Input(format!(
        "{}: .pov scenes are not read yet",
        path.display()
    )))
}
