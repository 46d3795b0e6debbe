//! A film's pixels, in memory the kernel may back with huge pages.
//!
//! A pass writes every pixel of a fresh buffer once (see
//! `render::render_from`), and the kernel maps the buffer's pages as they
//! are first written: at 800x600 a film is 50 MB, 12,000 faults of 4 KiB
//! pages, which were more than half the render time of an empty POV-Ray
//! scene (`perf record`). A buffer of 2 MiB or more is therefore its own
//! anonymous mapping, advised as a candidate for transparent huge pages
//! (2 MiB), where the kernel allows them: one fault maps 512 pages' worth.
//! Smaller buffers, and any the system will not map, are ordinary vectors.

use std::fmt;
use std::ops::{Deref, DerefMut};

use memmap2::{Advice, MmapMut};

use super::Pixel;

/// Buffers from this size on are mapped: below one huge page there is
/// nothing to gain.
const MAPPED_BYTES: usize = 2 << 20;

/// A film's pixels, row by row: a slice of `Pixel` whatever holds it.
pub struct Pixels(Storage);

enum Storage {
    Heap(Vec<Pixel>),
    /// `len` pixels at the start of the map (page-aligned, so aligned for `Pixel`).
    Mapped {
        map: MmapMut,
        len: usize,
    },
}

impl Pixels {
    /// `len` pixels of zero bytes, which the caller overwrites before
    /// reading (a zero `Pixel` is not `Pixel::default()`: its depth is 0).
    pub fn zeroed(len: usize) -> Pixels {
        let bytes = len.saturating_mul(size_of::<Pixel>());
        if bytes >= MAPPED_BYTES
            && let Ok(map) = MmapMut::map_anon(bytes)
        {
            // A hint: a kernel without transparent huge pages, or with
            // them off, refuses it, and the map works as well with 4 KiB
            // pages.
            let _ = map.advise(Advice::HugePage);
            return Pixels(Storage::Mapped { map, len });
        }
        Pixels(Storage::Heap(bytemuck::zeroed_vec(len)))
    }

    /// `len` copies of `pixel`.
    pub fn filled(len: usize, pixel: Pixel) -> Pixels {
        let mut pixels = Pixels::zeroed(len);
        pixels.fill(pixel);
        pixels
    }
}

impl From<Vec<Pixel>> for Pixels {
    fn from(pixels: Vec<Pixel>) -> Pixels {
        Pixels(Storage::Heap(pixels))
    }
}

impl Deref for Pixels {
    type Target = [Pixel];

    fn deref(&self) -> &[Pixel] {
        match &self.0 {
            Storage::Heap(pixels) => pixels,
            Storage::Mapped { map, len } => bytemuck::cast_slice(&map[..len * size_of::<Pixel>()]),
        }
    }
}

impl DerefMut for Pixels {
    fn deref_mut(&mut self) -> &mut [Pixel] {
        match &mut self.0 {
            Storage::Heap(pixels) => pixels,
            Storage::Mapped { map, len } => {
                bytemuck::cast_slice_mut(&mut map[..*len * size_of::<Pixel>()])
            }
        }
    }
}

impl PartialEq for Pixels {
    fn eq(&self, other: &Pixels) -> bool {
        **self == **other
    }
}

impl fmt::Debug for Pixels {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&**self, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn marked(i: usize) -> Pixel {
        Pixel {
            samples: i as u32,
            depth: i as f32,
            ..Pixel::default()
        }
    }

    #[test]
    fn mapped_and_heap_buffers_hold_the_same_pixels() {
        let big = MAPPED_BYTES / size_of::<Pixel>() + 3;
        for len in [0, 1, 7, big] {
            let mut pixels = Pixels::zeroed(len);
            assert_eq!(pixels.len(), len);
            assert!(pixels.iter().all(|p| *p == bytemuck::Zeroable::zeroed()));
            for (i, p) in pixels.iter_mut().enumerate() {
                *p = marked(i);
            }
            assert!(pixels.iter().enumerate().all(|(i, p)| *p == marked(i)));
            let heap = Pixels::from((0..len).map(marked).collect::<Vec<_>>());
            assert_eq!(heap, pixels);
        }
        // The large buffer is the mapped kind, the small ones vectors.
        assert!(matches!(Pixels::zeroed(big).0, Storage::Mapped { .. }));
        assert!(matches!(Pixels::zeroed(7).0, Storage::Heap(_)));
    }

    #[test]
    fn filled_buffers_hold_the_pixel_everywhere() {
        let big = MAPPED_BYTES / size_of::<Pixel>() + 1;
        let pixels = Pixels::filled(big, Pixel::default());
        assert!(pixels.iter().all(|p| *p == Pixel::default()));
    }
}
