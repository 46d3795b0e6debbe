//! Dyadic numbers m·2^e: exact f64 values, their sums and midpoints, which
//! the exact path evaluates at so that isolating never takes a gcd.

use std::cmp::Ordering;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Float, One, Signed, ToPrimitive, Zero};

/// m·2^e, normalised (m odd, or m = 0 and e = 0), so equal values are equal
/// representations and midpoints never need a gcd.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Dyadic {
    pub(super) m: BigInt,
    pub(super) e: i64,
}

impl Dyadic {
    fn new(m: BigInt, e: i64) -> Dyadic {
        match m.trailing_zeros() {
            None => Dyadic::zero(),
            Some(tz) => Dyadic {
                m: m >> tz,
                e: e + tz as i64,
            },
        }
    }

    pub(super) fn zero() -> Dyadic {
        Dyadic {
            m: BigInt::zero(),
            e: 0,
        }
    }

    pub(super) fn pow2(e: i64) -> Dyadic {
        Dyadic {
            m: BigInt::one(),
            e,
        }
    }

    /// Exact, for finite x.
    pub(super) fn from_f64(x: f64) -> Dyadic {
        let (mantissa, exponent, sign) = Float::integer_decode(x);
        Dyadic::new(
            BigInt::from(mantissa) * BigInt::from(sign),
            i64::from(exponent),
        )
    }

    pub(super) fn is_zero(&self) -> bool {
        self.m.is_zero()
    }

    pub(super) fn signum(&self) -> i32 {
        sign_of(&self.m)
    }

    pub(super) fn neg(&self) -> Dyadic {
        Dyadic {
            m: -&self.m,
            e: self.e,
        }
    }

    pub(super) fn abs(&self) -> Dyadic {
        Dyadic {
            m: self.m.abs(),
            e: self.e,
        }
    }

    /// ⌊log2 |x|⌋ for x ≠ 0.
    pub(super) fn log2_floor(&self) -> i64 {
        self.m.bits() as i64 - 1 + self.e
    }

    /// Both mantissas over the common exponent min(e₁, e₂).
    fn aligned(&self, other: &Dyadic) -> (BigInt, BigInt, i64) {
        let e = self.e.min(other.e);
        (
            &self.m << (self.e - e) as u64,
            &other.m << (other.e - e) as u64,
            e,
        )
    }

    pub(super) fn sub(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic::new(a - b, e)
    }

    pub(super) fn add(&self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic::new(a + b, e)
    }

    pub(super) fn mid(&self, other: &Dyadic) -> Dyadic {
        let sum = self.add(other);
        Dyadic::new(sum.m, sum.e - 1)
    }

    pub(super) fn mul(&self, other: &Dyadic) -> Dyadic {
        Dyadic::new(&self.m * &other.m, self.e + other.e)
    }

    pub(super) fn to_rational(&self) -> BigRational {
        if self.e >= 0 {
            BigRational::from_integer(&self.m << self.e as u64)
        } else {
            // m is odd, so m / 2^k is already in lowest terms.
            BigRational::new_raw(self.m.clone(), BigInt::one() << (-self.e) as u64)
        }
    }

    /// Correctly rounded (num-rational's conversion rounds to nearest, ties
    /// to even), ±∞ beyond the f64 range.
    pub(super) fn to_f64(&self) -> f64 {
        self.to_rational().to_f64().unwrap_or(f64::NAN)
    }
}

impl Ord for Dyadic {
    fn cmp(&self, other: &Dyadic) -> Ordering {
        let (a, b, _) = self.aligned(other);
        a.cmp(&b)
    }
}

impl PartialOrd for Dyadic {
    fn partial_cmp(&self, other: &Dyadic) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The sign of an integer: -1, 0 or 1.
pub(super) fn sign_of(x: &BigInt) -> i32 {
    if x.is_zero() {
        0
    } else if x.is_negative() {
        -1
    } else {
        1
    }
}
