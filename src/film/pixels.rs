//! A film's pixels: a vector that starts as zero bytes.
//!
//! A pass writes every pixel of a fresh buffer once (see
//! `render::render_from`), and the kernel maps the buffer's pages as the
//! render threads first write them. At 800x600 a film is 50 MB, 12,000
//! faults of 4 KiB pages. The buffer was once a map advised for
//! transparent huge pages, which spared 4-6 ms of a render on an idle
//! machine but, where another program had just run (POV-Ray, in the speed
//! comparison), made the kernel compact memory in the faults: render
//! times 1.4-1.6x those of small pages on four of five scenes, and far
//! more spread (see ARCHITECTURE.md, "Passes write the film in place").

use std::ops::{Deref, DerefMut};

use super::Pixel;

/// A film's pixels, row by row.
#[derive(Debug, PartialEq)]
pub struct Pixels(Vec<Pixel>);

impl Pixels {
    /// `len` pixels of zero bytes, which the caller overwrites before
    /// reading (a zero `Pixel` is not `Pixel::default()`: its depth is 0).
    pub fn zeroed(len: usize) -> Pixels {
        Pixels(bytemuck::zeroed_vec(len))
    }

    /// `len` copies of `pixel`.
    pub fn filled(len: usize, pixel: Pixel) -> Pixels {
        Pixels(vec![pixel; len])
    }
}

impl From<Vec<Pixel>> for Pixels {
    fn from(pixels: Vec<Pixel>) -> Pixels {
        Pixels(pixels)
    }
}

impl Deref for Pixels {
    type Target = [Pixel];

    fn deref(&self) -> &[Pixel] {
        &self.0
    }
}

impl DerefMut for Pixels {
    fn deref_mut(&mut self) -> &mut [Pixel] {
        &mut self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeroed_and_filled_buffers_hold_what_they_say() {
        for len in [0, 1, 7, 100_003] {
            let zeroed = Pixels::zeroed(len);
            assert_eq!(zeroed.len(), len);
            assert!(zeroed.iter().all(|p| *p == bytemuck::Zeroable::zeroed()));
            let filled = Pixels::filled(len, Pixel::default());
            assert_eq!(filled.len(), len);
            assert!(filled.iter().all(|p| *p == Pixel::default()));
        }
    }
}
