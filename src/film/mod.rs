//! The film: per-pixel f64 sums and sample counts, so averages do not depend
//! on the order samples arrive in.

mod pixels;

pub use pixels::Pixels;

/// The most memory a render holds per pixel at once: two buffers of sums,
/// the film and the pass writing into the next (see `render::render_from`).
/// The f32 layers written out afterwards (40 bytes a pixel) come once the
/// second buffer is gone.
pub const RENDER_BYTES_PER_PIXEL: u64 = 2 * size_of::<Pixel>() as u64;

use crate::math::{LUMINANCE, Vec3};

/// What one camera sample measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub radiance: Vec3,
    /// The reconstruction filter's weight of this sample (1 for box, tent and
    /// Gaussian; negative in Mitchell's lobes). Radiance is averaged with it.
    pub weight: f32,
    /// Distance to the first hit, inf on a miss.
    pub depth: f32,
    /// Unit normal of the first hit facing the camera, zero on a miss.
    pub normal: Vec3,
    /// Diffuse reflectance of the first hit, zero on a miss.
    pub albedo: Vec3,
}

impl Sample {
    /// Keeps NaN and infinite values off the film: a sample whose radiance or
    /// weight is not finite counts as black (pbrt-v4 does the same). Returns
    /// whether it had to; the render counts those, so they are seen, not hidden.
    pub fn sanitize(&mut self) -> bool {
        if self.radiance.is_finite() && self.weight.is_finite() {
            return false;
        }
        self.radiance = Vec3::ZERO;
        if !self.weight.is_finite() {
            self.weight = 0.0;
        }
        true
    }
}

// Zeroable: a render's pass buffer starts as zero bytes (see render::render_from).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Zeroable)]
pub struct Pixel {
    /// Σ weight · radiance.
    pub radiance: [f64; 3],
    /// Σ weight: the beauty pass divides by it, as pbrt-v4's film does, so a
    /// region of constant radiance stays constant whatever the weights.
    pub weight: f64,
    pub normal: [f64; 3],
    pub albedo: [f64; 3],
    /// The nearest depth of any sample (a minimum, so edges stay sharp).
    pub depth: f32,
    pub samples: u32,
    /// Σ y and Σ y² of the samples' weighted luminance y: what adaptive
    /// sampling decides from, kept here so a resumed render decides the same.
    pub luminance: [f64; 2],
}

impl Default for Pixel {
    fn default() -> Self {
        Pixel {
            radiance: [0.0; 3],
            weight: 0.0,
            normal: [0.0; 3],
            albedo: [0.0; 3],
            depth: f32::INFINITY,
            samples: 0,
            luminance: [0.0; 2],
        }
    }
}

fn accumulate(sum: &mut [f64; 3], v: Vec3) {
    for (s, x) in sum.iter_mut().zip(v.to_array()) {
        *s += f64::from(x);
    }
}

fn weighted_average(sum: [f64; 3], weight: f64) -> [f32; 3] {
    if weight == 0.0 {
        return [0.0; 3];
    }
    // A filter with negative lobes can leave a weight sum near zero, whose
    // quotient would overflow f32 to infinity: an image holds finite values.
    let most = f64::from(f32::MAX);
    sum.map(|s| (s / weight).clamp(-most, most) as f32)
}

fn average(sum: [f64; 3], n: u32) -> [f32; 3] {
    let n = f64::from(n.max(1));
    sum.map(|s| (s / n) as f32)
}

impl Pixel {
    /// Adds another film's sums for the same pixel (more samples of it).
    pub fn merge(&mut self, o: &Pixel) {
        let add = |a: &mut [f64; 3], b: [f64; 3]| a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        add(&mut self.radiance, o.radiance);
        self.weight += o.weight;
        add(&mut self.normal, o.normal);
        add(&mut self.albedo, o.albedo);
        self.depth = self.depth.min(o.depth);
        self.samples += o.samples;
        self.luminance[0] += o.luminance[0];
        self.luminance[1] += o.luminance[1];
    }

    pub fn add(&mut self, s: &Sample) {
        accumulate(&mut self.radiance, s.radiance * s.weight);
        self.weight += f64::from(s.weight);
        accumulate(&mut self.normal, s.normal);
        accumulate(&mut self.albedo, s.albedo);
        self.depth = self.depth.min(s.depth);
        self.samples += 1;
        let y = f64::from(s.radiance.dot(LUMINANCE) * s.weight);
        self.luminance[0] += y;
        self.luminance[1] += y * y;
    }
}

/// A half-open rectangle of pixels, [x0, x1) × [y0, y1), row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Region {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl Region {
    /// The whole of a width × height image.
    pub fn whole(width: usize, height: usize) -> Region {
        Region {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    pub fn width(&self) -> usize {
        self.x1 - self.x0
    }

    pub fn height(&self) -> usize {
        self.y1 - self.y0
    }

    pub fn area(&self) -> usize {
        self.width() * self.height()
    }

    /// Non-empty and inside a width × height image.
    pub fn fits(&self, width: usize, height: usize) -> bool {
        self.x0 < self.x1 && self.y0 < self.y1 && self.x1 <= width && self.y1 <= height
    }
}

/// The pixel sums of a region of a width × height image.
#[derive(Debug)]
pub struct Film {
    /// The whole image's size.
    pub width: usize,
    pub height: usize,
    /// The pixels this film holds, row by row.
    pub region: Region,
    pub pixels: Pixels,
}

/// The film's averages as f32 layers, ready for an image file.
pub struct Layers {
    pub beauty: Vec<[f32; 3]>,
    pub depth: Vec<f32>,
    pub normal: Vec<[f32; 3]>,
    pub albedo: Vec<[f32; 3]>,
}

impl Film {
    /// An empty film of the whole image.
    pub fn new(width: usize, height: usize) -> Film {
        Film::of_region(width, height, Region::whole(width, height))
    }

    /// An empty film of `region` of a width × height image.
    pub fn of_region(width: usize, height: usize, region: Region) -> Film {
        Film {
            width,
            height,
            region,
            pixels: Pixels::filled(region.area(), Pixel::default()),
        }
    }

    /// The pixel at image coordinates (x, y), which must lie in the region.
    pub fn pixel(&self, x: usize, y: usize) -> &Pixel {
        &self.pixels[self.index(x, y)]
    }

    pub fn pixel_mut(&mut self, x: usize, y: usize) -> &mut Pixel {
        let i = self.index(x, y);
        &mut self.pixels[i]
    }

    fn index(&self, x: usize, y: usize) -> usize {
        let r = self.region;
        debug_assert!((r.x0..r.x1).contains(&x) && (r.y0..r.y1).contains(&y));
        (y - r.y0) * r.width() + (x - r.x0)
    }

    pub fn layers(&self) -> Layers {
        Layers {
            beauty: self
                .pixels
                .iter()
                .map(|p| weighted_average(p.radiance, p.weight))
                .collect(),
            depth: self.pixels.iter().map(|p| p.depth).collect(),
            normal: self
                .pixels
                .iter()
                .map(|p| average(p.normal, p.samples))
                .collect(),
            albedo: self
                .pixels
                .iter()
                .map(|p| average(p.albedo, p.samples))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_weight_sum_near_zero_gives_finite_values() {
        // Mitchell's negative lobes: weights that nearly cancel.
        let v = weighted_average([1e30, -1e30, 0.5], 1e-12);
        assert_eq!(v, [f32::MAX, -f32::MAX, 5e11]);
    }

    #[test]
    fn averages_and_nearest_depth() {
        let mut film = Film::new(2, 1);
        let s = |r: f32, d: f32| Sample {
            radiance: Vec3::splat(r),
            weight: 1.0,
            depth: d,
            normal: Vec3::Z,
            albedo: Vec3::splat(0.5),
        };
        film.pixels[1].add(&s(1.0, 3.0));
        film.pixels[1].add(&s(2.0, 2.0));
        let layers = film.layers();
        assert_eq!(layers.beauty, vec![[0.0; 3], [1.5; 3]]);
        assert_eq!(layers.depth, vec![f32::INFINITY, 2.0]);
        assert_eq!(layers.normal[1], [0.0, 0.0, 1.0]);
        assert_eq!(layers.albedo[1], [0.5; 3]);
    }
}
