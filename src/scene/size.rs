//! The image size a command asks for (`--width`, `--height`): both sides,
//! or one whose partner follows the scene's aspect ratio. It goes through the
//! same checks as a scene file's size (`camera::size_problem`), with errors
//! that name the flag instead of a key.

use std::path::{Path, PathBuf};

use super::camera::{SizeFault, side_problem, size_problem};
use super::{LoadOptions, Scene, SceneKind, pov};
use crate::error::{Error, Result};

/// `--width` and `--height` as a command was given them: both, either or neither.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SizeRequest {
    pub width: Option<u32>,
    pub height: Option<u32>,
}

impl SizeRequest {
    /// Both sides given.
    pub(super) fn both((width, height): (u32, u32)) -> SizeRequest {
        SizeRequest {
            width: Some(width),
            height: Some(height),
        }
    }

    /// The whole size for a scene whose own is `own`: a side not given
    /// follows `own`'s aspect ratio, rounded to the nearest pixel (halves up)
    /// and at least 1. None when neither side is given.
    pub fn against(self, own: (u32, u32)) -> Option<(u32, u32)> {
        // given · to / of in integers, exact for any u32 (a result beyond u32
        // is then refused as too large by `check`).
        let follow = |given: u32, to: u32, of: u32| {
            let (given, to, of) = (u128::from(given), u128::from(to), u128::from(of.max(1)));
            let side = (2 * given * to + of) / (2 * of);
            u32::try_from(side.max(1)).unwrap_or(u32::MAX)
        };
        match (self.width, self.height) {
            (Some(w), Some(h)) => Some((w, h)),
            (Some(w), None) => Some((w, follow(w, own.1, own.0))),
            (None, Some(h)) => Some((follow(h, own.0, own.1), h)),
            (None, None) => None,
        }
    }

    /// Checks `size`, this request made whole, as a scene file's size is
    /// checked; the error names the flag at fault, or the one given when the
    /// fault is in the side that follows from it.
    pub(super) fn check(self, (width, height): (u32, u32)) -> Result<()> {
        // A side given is blamed before one that follows from it.
        let given = [
            (SizeFault::Width, self.width),
            (SizeFault::Height, self.height),
        ];
        let problem = given
            .into_iter()
            .find_map(|(fault, side)| Some((fault, side_problem(side?)?)))
            .or_else(|| size_problem(width, height));
        let Some((fault, message)) = problem else {
            return Ok(());
        };
        let flag = match (fault, self.width, self.height) {
            (SizeFault::Width, Some(_), _) => "--width".to_string(),
            (SizeFault::Height, _, Some(_)) => "--height".to_string(),
            (SizeFault::Film, Some(_), Some(_)) => "--width and --height".to_string(),
            (_, Some(_), None) => {
                format!("--width {width} (the height {height} follows the scene's aspect ratio)")
            }
            (_, None, _) => {
                format!("--height {height} (the width {width} follows the scene's aspect ratio)")
            }
        };
        Err(Error::Input(format!("{flag}: {message}")))
    }
}

impl Scene {
    /// Loads the scene at `path` at the size `request` asks for (as
    /// [`Scene::load_with`]). A side given alone keeps the scene's own aspect
    /// ratio: a TOML or OBJ scene's camera's, known once the file is read, or
    /// for a .pov file, which has no size of its own, POV-Ray's default
    /// 800×600, since it must be known before the file is read.
    pub fn load_sized(
        path: &Path,
        request: SizeRequest,
        pov_include: Vec<PathBuf>,
    ) -> Result<Scene> {
        let options = LoadOptions {
            size: None,
            pov_include,
        };
        let one_side = request.width.is_some() != request.height.is_some();
        if one_side && SceneKind::of(path)? != SceneKind::Pov {
            let mut scene = Scene::load_with(path, &options)?;
            if let Some(size) = request.against((scene.camera.width, scene.camera.height)) {
                request.check(size)?;
                (scene.camera.width, scene.camera.height) = size;
            }
            return Ok(scene);
        }
        let size = request.against(pov::DEFAULT_SIZE);
        // Checked here too, so an error names the flag that was given.
        if let Some(size) = size {
            request.check(size)?;
        }
        Scene::load_with(path, &LoadOptions { size, ..options })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(width: Option<u32>, height: Option<u32>) -> SizeRequest {
        SizeRequest { width, height }
    }

    #[test]
    fn a_side_alone_keeps_the_aspect_ratio_rounded_and_at_least_one() {
        let own = (640, 480);
        assert_eq!(request(None, None).against(own), None);
        assert_eq!(request(Some(7), Some(9)).against(own), Some((7, 9)));
        // 320·480/640 = 240; 100·640/480 = 133.3 → 133; 2·480/640 = 1.5 → 2
        // (halves up); 1·480/640 = 0.75 → 1; 1·3/640 → 0 → at least 1.
        assert_eq!(request(Some(320), None).against(own), Some((320, 240)));
        assert_eq!(request(None, Some(100)).against(own), Some((133, 100)));
        assert_eq!(request(Some(2), None).against(own), Some((2, 2)));
        assert_eq!(request(Some(1), None).against(own), Some((1, 1)));
        assert_eq!(request(Some(1), None).against((640, 3)), Some((1, 1)));
        // u32::MAX · 65536 does not fit a u32: the result saturates, and the
        // check then refuses it.
        assert_eq!(
            request(Some(u32::MAX), None).against((1, 65536)),
            Some((u32::MAX, u32::MAX))
        );
    }

    #[test]
    fn a_bad_size_names_the_flag_given() {
        let message = |r: SizeRequest, size| r.check(size).unwrap_err().to_string();
        let m = message(request(Some(0), Some(5)), (0, 5));
        assert!(
            m.starts_with("--width: expected 1 to 65536 pixels, found 0"),
            "{m}"
        );
        let m = message(request(Some(5), Some(65537)), (5, 65537));
        assert!(m.starts_with("--height: expected 1 to 65536"), "{m}");
        // Only --height was given: the width that follows from it is at fault.
        let m = message(request(None, Some(60000)), (80000, 60000));
        assert!(
            m.starts_with("--height 60000 (the width 80000 follows"),
            "{m}"
        );
        assert!(m.contains("found 80000"), "{m}");
        // Both bad: the side given is the one named.
        let m = message(request(None, Some(70000)), (93333, 70000));
        assert!(
            m.starts_with("--height: expected 1 to 65536 pixels, found 70000"),
            "{m}"
        );
        assert!(request(Some(640), Some(480)).check((640, 480)).is_ok());
    }
}
