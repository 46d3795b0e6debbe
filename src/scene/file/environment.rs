//! `[environment]`: the environment light, from an equirectangular map or a
//! constant radiance. The map is the scene's lighting, not an optional
//! texture: a missing or unreadable one is an error naming it (exit 2).

use std::path::Path;
use std::sync::Arc;

use super::check::Check;
use super::schema::EnvironmentFile;
use crate::error::Result;
use crate::lights::{Environment, EnvironmentSource};

/// The environment `file` asks for, its map read from `dir`; the map's path
/// joins `sources`, so no output is written over it.
pub(super) fn environment(
    check: &Check,
    dir: &Path,
    file: &EnvironmentFile,
    sources: &mut Vec<std::path::PathBuf>,
) -> Result<Arc<Environment>> {
    let scale = file.scale.unwrap_or(1.0);
    if !(scale >= 0.0 && scale.is_finite()) {
        let message = format!("expected a number >= 0, found {scale}");
        return Err(check.error("environment.scale", message));
    }
    let rotation = file.rotation.unwrap_or(0.0);
    if !rotation.is_finite() {
        let message = format!("expected a finite angle in degrees, found {rotation}");
        return Err(check.error("environment.rotation", message));
    }
    let environment = match (&file.file, file.radiance) {
        (Some(_), Some(_)) => {
            let message = "takes a map `file` or a constant `radiance`, not both";
            return Err(check.error("environment", message));
        }
        (None, None) => {
            let message = "expected a map `file` or a constant `radiance = [r, g, b]`";
            return Err(check.error("environment", message));
        }
        (None, Some(radiance)) => {
            let radiance = check.colour("environment.radiance", radiance)?;
            let mut environment = Environment::constant(radiance * scale);
            environment.source.radiance = Some(radiance.to_array());
            environment.source.scale = scale;
            environment
        }
        (Some(name), None) => {
            let path = dir.join(name);
            let image =
                crate::io::texture::read(&path).map_err(|e| check.error("environment.file", e))?;
            sources.push(path.clone());
            let source = EnvironmentSource {
                file: Some(path),
                sha256: Some(image.sha256),
                radiance: None,
                scale,
                rotation,
            };
            Environment::map(image.width as usize, &image.texels, source)
        }
    };
    Ok(Arc::new(environment))
}
