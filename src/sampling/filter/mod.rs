//! Reconstruction filters by filter importance sampling (pbrt-v4): a pixel's
//! sample is placed at an offset from the pixel centre drawn with density
//! proportional to the filter, so each sample counts for its own pixel only
//! (ARCHITECTURE.md: no splatting). The film then averages `weight ×
//! radiance` over the pixel's samples and divides by their count: the weights
//! have mean 1, so images keep their brightness.
//!
//! All four filters are separable, f(x, y) = f₁(x) f₁(y), and are sampled one
//! axis at a time. Box, tent and Gaussian are sampled exactly (weight 1). The
//! Mitchell-Netravali filter has negative lobes: its offsets are drawn from a
//! table of |f₁| (one axis, built once by [`FilterSampler::new`]) and carry the
//! weight f(p) / (pdf(p) ∫f), which is sign(f(p)) × ∫|f|/∫f up to the table's
//! resolution and, unlike that constant, unbiased whatever the resolution.

use std::fmt;
use std::str::FromStr;

use crate::error::{Error, Result};

/// A separable reconstruction filter; offsets and radii are in pixels.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Filter {
    /// 1 on [−radius, radius]²; radius 0.5 is plain jittering in the pixel.
    Box { radius: f32 },
    /// max(0, 1 − |x|/radius) per axis (pbrt's triangle filter).
    Tent { radius: f32 },
    /// exp(−x²/(2σ²)) per axis, cut off at |x| = radius.
    Gaussian { radius: f32, sigma: f32 },
    /// Mitchell and Netravali's cubic with parameters B and C, stretched over
    /// [−radius, radius] (its natural support is [−2, 2]).
    Mitchell { radius: f32, b: f32, c: f32 },
}

/// Where a sample goes and what it weighs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel centre, in pixels, within the filter's radius.
    pub offset: [f32; 2],
    /// The sample's weight; its mean over samples is 1. Exactly 1 for the
    /// box, tent and Gaussian; negative in the Mitchell filter's negative lobes.
    pub weight: f32,
}

const NAMES: &str = "box, tent, gaussian or mitchell";

impl Filter {
    /// Box of radius 0.5: one pixel, as jittering without a filter.
    pub const BOX: Filter = Filter::Box { radius: 0.5 };
    /// Tent of radius 1.
    pub const TENT: Filter = Filter::Tent { radius: 1.0 };
    /// Gaussian of radius 1.5 and σ 0.5 (cut off at 3σ).
    pub const GAUSSIAN: Filter = Filter::Gaussian {
        radius: 1.5,
        sigma: 0.5,
    };
    /// Mitchell of radius 2 with B = C = 1/3, the authors' recommendation.
    pub const MITCHELL: Filter = Filter::Mitchell {
        radius: 2.0,
        b: 1.0 / 3.0,
        c: 1.0 / 3.0,
    };

    /// The name [`FromStr`] reads.
    pub fn name(&self) -> &'static str {
        match self {
            Filter::Box { .. } => "box",
            Filter::Tent { .. } => "tent",
            Filter::Gaussian { .. } => "gaussian",
            Filter::Mitchell { .. } => "mitchell",
        }
    }

    /// The half-width of the support on each axis, in pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box { radius }
            | Filter::Tent { radius }
            | Filter::Gaussian { radius, .. }
            | Filter::Mitchell { radius, .. } => radius,
        }
    }

    /// Checks the parameters: a finite positive radius and σ, finite B and C.
    pub fn validate(&self) -> Result<()> {
        let radius = self.radius();
        if !(radius.is_finite() && radius > 0.0) {
            return Err(Error::Input(format!(
                "{} filter: radius must be a positive number of pixels, not {radius}",
                self.name()
            )));
        }
        match *self {
            Filter::Gaussian { sigma, .. } if !(sigma.is_finite() && sigma > 0.0) => {
                Err(Error::Input(format!(
                    "gaussian filter: sigma must be positive, not {sigma}"
                )))
            }
            Filter::Mitchell { b, c, .. } if !(b.is_finite() && c.is_finite()) => {
                Err(Error::Input(format!(
                    "mitchell filter: B and C must be finite, not {b} and {c}"
                )))
            }
            _ => Ok(()),
        }
    }

    /// The filter's value at `offset` (unnormalised: 1 at the centre for the
    /// box, tent and Gaussian), 0 outside the support.
    pub fn evaluate(&self, offset: [f32; 2]) -> f32 {
        (self.eval_1d(f64::from(offset[0])) * self.eval_1d(f64::from(offset[1]))) as f32
    }

    /// The integral of [`Filter::evaluate`] over the plane.
    pub fn integral(&self) -> f32 {
        let i = self.integral_1d();
        (i * i) as f32
    }

    /// The sampler for this filter, after [`Filter::validate`].
    pub fn sampler(&self) -> Result<FilterSampler> {
        FilterSampler::new(*self)
    }

    /// f₁(x), the filter along one axis.
    fn eval_1d(&self, x: f64) -> f64 {
        let (x, r) = (x.abs(), f64::from(self.radius()));
        if x > r {
            return 0.0;
        }
        match *self {
            Filter::Box { .. } => 1.0,
            Filter::Tent { .. } => (1.0 - x / r).max(0.0),
            Filter::Gaussian { sigma, .. } => {
                let s = f64::from(sigma);
                (-x * x / (2.0 * s * s)).exp()
            }
            Filter::Mitchell { b, c, .. } => mitchell_1d(2.0 * x / r, f64::from(b), f64::from(c)),
        }
    }

    /// ∫ f₁ over [−radius, radius].
    fn integral_1d(&self) -> f64 {
        let r = f64::from(self.radius());
        match *self {
            Filter::Box { .. } => 2.0 * r,
            Filter::Tent { .. } => r,
            Filter::Gaussian { sigma, .. } => {
                let s = f64::from(sigma);
                s * (2.0 * std::f64::consts::PI).sqrt() * erf(r / (s * std::f64::consts::SQRT_2))
            }
            // The cubic integrates to 1 over [−2, 2] for every B and C.
            Filter::Mitchell { .. } => r / 2.0,
        }
    }
}

/// The Mitchell-Netravali cubic on its natural support [−2, 2].
fn mitchell_1d(x: f64, b: f64, c: f64) -> f64 {
    let x = x.abs();
    if x <= 1.0 {
        ((12.0 - 9.0 * b - 6.0 * c) * x * x * x
            + (-18.0 + 12.0 * b + 6.0 * c) * x * x
            + (6.0 - 2.0 * b))
            / 6.0
    } else if x <= 2.0 {
        ((-b - 6.0 * c) * x * x * x
            + (6.0 * b + 30.0 * c) * x * x
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c))
            / 6.0
    } else {
        0.0
    }
}

/// The box filter of radius 0.5.
impl Default for Filter {
    fn default() -> Self {
        Filter::BOX
    }
}

/// Reads a filter's name (any case): "box", "tent" (or "triangle"),
/// "gaussian", "mitchell", each with its default parameters
/// ([`Filter::BOX`], [`Filter::TENT`], [`Filter::GAUSSIAN`], [`Filter::MITCHELL`]).
impl FromStr for Filter {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "box" => Ok(Filter::BOX),
            "tent" | "triangle" => Ok(Filter::TENT),
            "gaussian" => Ok(Filter::GAUSSIAN),
            "mitchell" => Ok(Filter::MITCHELL),
            _ => Err(Error::Input(format!(
                "unknown filter {s:?}: expected {NAMES}"
            ))),
        }
    }
}

/// The name and parameters, as `sturmray info` shows them.
impl fmt::Display for Filter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Filter::Box { radius } | Filter::Tent { radius } => {
                write!(f, "{} (radius {radius})", self.name())
            }
            Filter::Gaussian { radius, sigma } => {
                write!(f, "gaussian (radius {radius}, sigma {sigma})")
            }
            Filter::Mitchell { radius, b, c } => {
                write!(f, "mitchell (radius {radius}, B {b}, C {c})")
            }
        }
    }
}

/// Draws [`FilterSample`]s for one filter. Build it once per render (it
/// validates the filter and, for Mitchell, tabulates one axis); sampling then
/// allocates nothing and depends only on `u`.
#[derive(Clone, Debug)]
pub struct FilterSampler {
    filter: Filter,
    method: Method,
}

#[derive(Clone, Debug)]
enum Method {
    Box {
        radius: f32,
    },
    Tent {
        radius: f32,
    },
    /// x = σ√2 · erf⁻¹(v · erf(radius / (σ√2))), v uniform in [−1, 1).
    Gaussian {
        radius: f32,
        scale: f64,
        edge: f64,
    },
    Tabulated(Box<Table>),
}

/// Cells of the Mitchell table across [−radius, radius]. A multiple of 4, so
/// the cubic's knots at ±radius/2 and the centre fall on cell edges; 256
/// keeps 97% of weights within 5% of ±∫|f|/∫f (pbrt-v4 uses 32 per unit of
/// radius, 64 here at radius 2, on a 2D table).
const CELLS: usize = 256;

/// |f₁| as a piecewise-constant density over [−radius, radius].
#[derive(Clone, Debug)]
struct Table {
    radius: f32,
    /// cdf[i] = mass of cells before i; cdf[0] = 0, cdf[CELLS] = 1. In f64
    /// so that the small cells near the edges keep their probabilities.
    cdf: [f64; CELLS + 1],
    /// 1 / (density of cell i × ∫f₁): a sample's weight is f₁(x) times this.
    inv_density: [f32; CELLS],
}

impl FilterSampler {
    /// The sampler for `filter`, or the error [`Filter::validate`] gives.
    pub fn new(filter: Filter) -> Result<FilterSampler> {
        filter.validate()?;
        let method = match filter {
            Filter::Box { radius } => Method::Box { radius },
            Filter::Tent { radius } => Method::Tent { radius },
            Filter::Gaussian { radius, sigma } => {
                let scale = f64::from(sigma) * std::f64::consts::SQRT_2;
                // Below 1, so that u = 0 maps to a finite erf⁻¹ even when the
                // cut-off is many σ out and erf rounds to 1 there.
                Method::Gaussian {
                    radius,
                    scale,
                    edge: erf(f64::from(radius) / scale).min(1.0 - f64::EPSILON),
                }
            }
            Filter::Mitchell { .. } => Method::Tabulated(Box::new(Table::new(&filter))),
        };
        Ok(FilterSampler { filter, method })
    }

    pub fn filter(&self) -> Filter {
        self.filter
    }

    /// The offset for the uniforms `u` (`u[0]` for x, `u[1]` for y) and its weight.
    pub fn sample(&self, u: [f32; 2]) -> FilterSample {
        let (x, wx) = self.sample_1d(u[0]);
        let (y, wy) = self.sample_1d(u[1]);
        FilterSample {
            offset: [x, y],
            weight: wx * wy,
        }
    }

    /// One axis: an offset in [−radius, radius] and its weight.
    fn sample_1d(&self, u: f32) -> (f32, f32) {
        match &self.method {
            // For radius 0.5 the factor is 1: the offset is u − 0.5 bit for
            // bit, jittering by u about the pixel centre.
            Method::Box { radius } => ((u - 0.5) * (2.0 * radius), 1.0),
            Method::Tent { radius } => {
                // Inverse CDF of each half, increasing in u; 2 − 2u is exact.
                let x = if u < 0.5 {
                    (2.0 * u).sqrt() - 1.0
                } else {
                    1.0 - (2.0 - 2.0 * u).sqrt()
                };
                ((x * radius).clamp(-radius, *radius), 1.0)
            }
            Method::Gaussian {
                radius,
                scale,
                edge,
            } => {
                let v = 2.0 * f64::from(u) - 1.0;
                let x = (scale * erf_inv(v * edge)) as f32;
                (x.clamp(-radius, *radius), 1.0)
            }
            Method::Tabulated(table) => {
                let (x, inv_density) = table.sample(u);
                (
                    x,
                    (self.filter.eval_1d(f64::from(x)) * f64::from(inv_density)) as f32,
                )
            }
        }
    }
}

impl Table {
    fn new(filter: &Filter) -> Table {
        let radius = filter.radius();
        let r = f64::from(radius);
        let width = 2.0 * r / CELLS as f64;
        // Each cell's ∫|f₁| by Simpson's rule on 4 panels: exact where the
        // cubic keeps its sign, close where a zero crosses the cell.
        let mut mass = [0.0f64; CELLS];
        for (i, m) in mass.iter_mut().enumerate() {
            let a = -r + i as f64 * width;
            let h = width / 4.0;
            let f = |k: usize| filter.eval_1d(a + k as f64 * h).abs();
            *m = h / 3.0 * (f(0) + 4.0 * f(1) + 2.0 * f(2) + 4.0 * f(3) + f(4));
        }
        let total: f64 = mass.iter().sum();
        let integral = filter.integral_1d();
        let mut cdf = [0.0f64; CELLS + 1];
        let mut inv_density = [0.0f32; CELLS];
        let mut running = 0.0f64;
        for i in 0..CELLS {
            running += mass[i];
            cdf[i + 1] = running / total;
            // density = (mass / total) / width; a cell of zero mass is never
            // chosen, and its entry stays 0.
            if mass[i] > 0.0 {
                inv_density[i] = (total * width / (mass[i] * integral)) as f32;
            }
        }
        cdf[CELLS] = 1.0;
        Table {
            radius,
            cdf,
            inv_density,
        }
    }

    /// An offset with density ∝ the tabulated |f₁|, and 1 / (density × ∫f₁) there.
    fn sample(&self, u: f32) -> (f32, f32) {
        // The last cell whose start is ≤ u: cells of zero mass (cdf[i + 1] =
        // cdf[i]) are skipped, and cdf[CELLS] = 1 > u bounds it.
        let u = f64::from(u);
        let i = self.cdf[1..CELLS].partition_point(|&c| c <= u);
        let (lo, hi) = (self.cdf[i], self.cdf[i + 1]);
        let t = ((u - lo) / (hi - lo)).clamp(0.0, 1.0);
        let r = f64::from(self.radius);
        let x = (-r + (i as f64 + t) * (2.0 * r / CELLS as f64)) as f32;
        (x.clamp(-self.radius, self.radius), self.inv_density[i])
    }
}

/// The error function, |error| < 1.5e-7 (Abramowitz and Stegun 7.1.26).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    (1.0 - poly * (-x * x).exp()).copysign(x)
}

/// The inverse error function on (−1, 1), relative error about 1e-7 (Giles,
/// "Approximating the erfinv function", single-precision version); ±1 and
/// beyond give ±∞ and NaN, which callers clamp.
fn erf_inv(x: f64) -> f64 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        [
            3.432_739_39e-7,
            -3.523_387_7e-6,
            -4.391_506_54e-6,
            2.185_808_7e-4,
            -1.253_725_03e-3,
            -4.177_681_64e-3,
            2.466_407_27e-1,
            1.501_409_41,
        ]
        .iter()
        .fold(2.810_226_36e-8, |p, &c| c + p * w)
    } else {
        let w = w.sqrt() - 3.0;
        [
            1.009_505_58e-4,
            1.349_343_22e-3,
            -3.673_428_44e-3,
            5.739_507_73e-3,
            -7.622_461_3e-3,
            9.438_870_47e-3,
            1.001_674_06,
            2.832_976_82,
        ]
        .iter()
        .fold(-2.002_142_57e-4, |p, &c| c + p * w)
    };
    p * x
}

#[cfg(test)]
mod tests;
