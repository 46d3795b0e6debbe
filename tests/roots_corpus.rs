//! A corpus of polynomials from public root-finder test suites, written
//! out here from their sources (each case names its own), every answer of
//! `Solver::certified` checked against the exact answer:
//! - the certificate itself, re-derived from the exact rational
//!   coefficients (tests/certify);
//! - where the source's roots are rational and its coefficients are exactly
//!   the product of the factors (checked here, in rationals), the values,
//!   multiplicities and count must be those roots' exactly (to the bound);
//! - where the coefficients are the product *rounded* (or the roots are
//!   irrational or complex), the rounded polynomial has roots of its own,
//!   which the certificate proves; the score then says how many of the
//!   source's real roots come back within the source's own tolerance.
//!
//! The score is printed (`cargo test --test roots_corpus -- --nocapture`)
//! and quoted in the README.

// The sources' roots keep every digit they print, past f64's.
#![allow(clippy::excessive_precision)]

mod certify;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
use sturmray::poly::solve::Solver;

/// The coefficients of a case, as the source gives them.
enum Coeffs {
    /// Highest degree first, as printed in the source.
    Printed(&'static [f64]),
    /// lead · ∏ (x − r)^m over `roots`, each coefficient rounded to the
    /// nearest f64 once (the sources compute theirs in f64 from the roots).
    FromRoots(f64),
}

struct Case {
    source: &'static str,
    name: &'static str,
    coeffs: Coeffs,
    interval: (f64, f64),
    /// Real roots as exact rationals ("p/q", an integer, or "1e80") with
    /// multiplicities, when the source's factorisation is all real and
    /// rational (then the list is complete).
    rational: &'static [(&'static str, u32)],
    /// Otherwise the source's real roots (distinct), as it prints them.
    nominal: &'static [f64],
    /// The source's tolerance for its roots (relative).
    source_tol: f64,
}

const ALL: (f64, f64) = (-f64::MAX, f64::MAX);

const FLOCKE: &str = "Flocke, Algorithm 954, ACM TOMS 41(4), 2015: the cubic and quartic test \
                      set (as in ebertolazzi/quarticRootsFlocke, test files)";
const VTK: &str = "VTK, Common/Math/Testing/Cxx/TestPolynomialSolversUnivariate.cxx";
const GSL: &str = "GSL, poly/test.c";
const NUMPY: &str = "numpy, numpy/polynomial/tests/test_polynomial.py (test_polyroots)";
const MULTROOT: &str =
    "MultRoot (Zeng, ACM TOMS 2005) as in JuliaMath/Roots.jl test/tests_multroot.jl";
const MULTROOT_CALGO: &str = "MultRoot test suite, CALGO 835 Drivers/near03.m";
const BOOST_CUBIC: &str = "Boost.Math, test/cubic_roots_test.cpp (its fixed cases; the random \
                           trials draw from std::mt19937 through libstdc++'s distribution)";
const BOOST_QUARTIC: &str = "Boost.Math, test/quartic_roots_test.cpp (its fixed cases, as above)";
const WILKINSON: &str = "Wilkinson-type products (Wilkinson 1959; GSL's and VTK's degree 5 and 19)";

/// VTK's P84, highest degree first: 55x^84 − 79x^72 + 90x^71 + 37x^44 + 49x^21 − 12.
const P84: [f64; 85] = {
    let mut c = [0.0; 85];
    c[0] = 55.0;
    c[12] = -79.0;
    c[13] = 90.0;
    c[40] = 37.0;
    c[63] = 49.0;
    c[84] = -12.0;
    c
};

fn cases() -> Vec<Case> {
    let case = |source, name, coeffs, interval, rational, nominal, source_tol| Case {
        source,
        name,
        coeffs,
        interval,
        rational,
        nominal,
        source_tol,
    };
    use Coeffs::{FromRoots, Printed};
    vec![
        // Flocke's cubics 1-9 and quartics 1-13 (highest degree first).
        case(
            FLOCKE,
            "cubic 1",
            Printed(&[1.0, -1.00000010000001e14, 1.00000010000001e21, -1e21]),
            ALL,
            &[("1", 1), ("10000000", 1), ("1e14", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 2",
            Printed(&[1.0, -3.000003, 3.000006000002, -1.000003000002]),
            ALL,
            &[("1", 1), ("1000001/1000000", 1), ("500001/500000", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 3",
            Printed(&[1.0, 8.999e80, -1.0009e161, 1e238]),
            ALL,
            &[("-1e81", 1), ("1e77", 1), ("1e80", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 4",
            Printed(&[1.0, 1e24, -1.0, -1e24]),
            ALL,
            &[("-1e24", 1), ("-1", 1), ("1", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 5 (double root 1e14)",
            Printed(&[1.0, -1.99999999999999e14, 0.99999999999998e28, 1e28]),
            ALL,
            &[("-1", 1), ("1e14", 2)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 6",
            Printed(&[1.0, -3e5, 3.0000000001e10, -1.0000000001e15]),
            ALL,
            &[],
            &[1e5],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 7",
            Printed(&[1.0, -3.0, 1.00000000000003e14, -1.00000000000001e14]),
            ALL,
            &[],
            &[1.0],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 8",
            Printed(&[1.0, -2.0000001e7, 1.00000020000001e14, -1.00000000000001e14]),
            ALL,
            &[],
            &[1.0],
            1e-12,
        ),
        case(
            FLOCKE,
            "cubic 9",
            Printed(&[1.0, 0.99999999999998e14, -1.99999999999998e14, 2e14]),
            ALL,
            &[],
            &[-1e14],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 1",
            Printed(&[
                1.0,
                -1.001001001e9,
                1.001002001001e15,
                -1.001001001e18,
                1e18,
            ]),
            ALL,
            &[("1", 1), ("1000", 1), ("1000000", 1), ("1000000000", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 2",
            Printed(&[1.0, -4.006, 6.018011, -4.018022006, 1.006011006]),
            ALL,
            &[("1", 1), ("1001/1000", 1), ("501/500", 1), ("1003/1000", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 3",
            Printed(&[1.0, -9.98899e79, -1.1008989e157, -1.010999e233, -1e307]),
            ALL,
            &[("-1e77", 1), ("-1e76", 1), ("-1e74", 1), ("1e80", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 4",
            Printed(&[
                1.0,
                -1.00000000000002e14,
                1.99999999999999e14,
                1.00000000000002e14,
                -2e14,
            ]),
            ALL,
            &[("-1", 1), ("1", 1), ("2", 1), ("1e14", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 5",
            Printed(&[1.0, 1e7, -2.00000000000001e14, -1e7, 2e14]),
            ALL,
            &[("-20000000", 1), ("-1", 1), ("1", 1), ("10000000", 1)],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 6",
            Printed(&[1.0, -9.000002e6, -0.9999981999998e13, 1.9999982e13, -2e13]),
            ALL,
            &[],
            &[-1e6, 1e7],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 7",
            Printed(&[1.0, 2.000011e6, 1.010022000028e12, 1.1110056e13, 2.828e13]),
            ALL,
            &[],
            &[-7.0, -4.0],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 8",
            Printed(&[
                1.0,
                -1.00002011e8,
                2.01101022001e11,
                -1.02200111000011e14,
                1.1000011e15,
            ]),
            ALL,
            &[],
            &[11.0, 1e8],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 9",
            Printed(&[
                1.0,
                -2.0000002e7,
                1.01000040000005e14,
                -2.020001e14,
                5.05e14,
            ]),
            ALL,
            &[],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 10",
            Printed(&[
                1.0,
                -1.9986e4,
                1.00720058e8,
                -1.8600979874e10,
                1.00004909000441e14,
            ]),
            ALL,
            &[],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 11",
            Printed(&[
                1.0,
                -4.006,
                5.6008018e1,
                -1.04148036024e2,
                6.75896068064016e2,
            ]),
            ALL,
            &[],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 12",
            Printed(&[1.0, -4.0e3, 6.00001e6, -4.00002e9, 1.000010000009e12]),
            ALL,
            &[],
            &[],
            1e-12,
        ),
        case(
            FLOCKE,
            "quartic 13",
            Printed(&[1.0, -6.0, 1.01000013e8, -2.04000012e8, 1.00000104000004e14]),
            ALL,
            &[],
            &[],
            1e-12,
        ),
        // VTK's univariate solver tests (highest degree first, its intervals).
        case(
            VTK,
            "JT2 mul(x-i, i=1..19)",
            Printed(&[
                1.0,
                -1.9e2,
                1.6815e4,
                -9.2055e5,
                3.4916946e7,
                -9.739419e8,
                2.069293363e10,
                -3.422525119e11,
                4.465226757381e12,
                -4.628064775191e13,
                3.81922055502195e14,
                -2.50385875546755e15,
                1.29536369899439e16,
                -5.226090336251272e16,
                1.61429736530119e17,
                -3.71384787345228e17,
                6.101160757404918e17,
                -6.686097303411533e17,
                4.315651468176384e17,
                -1.21645100408832e17,
            ]),
            (-14.0, 28.1),
            &[],
            &[
                1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0,
                16.0, 17.0, 18.0, 19.0,
            ],
            2.5e-3 / 19.0,
        ),
        case(
            VTK,
            "JT22 mul(x-i, i=1..18)",
            Printed(&[
                1.,
                -171.,
                13566.,
                -662796.,
                22323822.,
                -549789282.,
                10246937272.,
                -147560703732.,
                1661573386473.,
                -14710753408923.,
                102417740732658.,
                -557921681547048.,
                2.35312504054998e15,
                -7.55152759206302e15,
                1.79507122809215e16,
                -3.03212540077194e16,
                3.40122495938227e16,
                -2.23769880585216e16,
                6.402373705728e15,
            ]),
            (-14.0, 28.1),
            &[],
            &[
                1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0,
                16.0, 17.0, 18.0,
            ],
            0.5e-3 / 18.0,
        ),
        case(
            VTK,
            "JT23 mul(x-i, i=1..17)",
            Printed(&[
                1.,
                -153.,
                10812.,
                -468180.,
                13896582.,
                -299650806.,
                4853222764.,
                -60202693980.,
                577924894833.,
                -4308105301929.,
                24871845297936.,
                -110228466184200.,
                369012649234384.,
                -909299905844112.,
                1.58331397572749e15,
                -1.82160244462464e15,
                1.2234055905792e15,
                -355687428096000.,
            ]),
            (-14.0, 28.1),
            &[],
            &[
                1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0,
                16.0, 17.0,
            ],
            1e-4 / 17.0,
        ),
        case(
            VTK,
            "JT3 mul(x-10^-i, i=1..8)",
            Printed(&[
                1.0,
                -1.1111111e-1,
                1.122334332211e-3,
                -1.123456666543211e-6,
                1.123557787755321e-10,
                -1.123456666543211e-15,
                1.122334332211e-21,
                -1.1111111e-28,
                1e-36,
            ]),
            (-14.0, 28.1),
            &[
                ("1/100000000", 1),
                ("1/10000000", 1),
                ("1/1000000", 1),
                ("1/100000", 1),
                ("1/10000", 1),
                ("1/1000", 1),
                ("1/100", 1),
                ("1/10", 1),
            ],
            &[],
            1.0,
        ),
        case(
            VTK,
            "JT4 (x-1/10)^3(x-5/10)(x-6/10)(x-7/10)",
            Printed(&[1.0, -2.1, 1.64, -5.86e-1, 9.69e-2, -7.37e-3, 2.1e-4]),
            (-14.0, 28.1),
            &[("1/10", 3), ("1/2", 1), ("3/5", 1), ("7/10", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "JT5 (x-1/10)^4(x-2/10)^3(x-3/10)^2(x-4/10)",
            Printed(&[
                1.0, -2.0, 1.75, -8.82e-1, 2.835e-1, -6.072e-2, 8.777e-3, -8.458e-4, 5.204e-5,
                -1.848e-6, 2.88e-8,
            ]),
            (-14.0, 28.1),
            &[("1/10", 4), ("1/5", 3), ("3/10", 2), ("2/5", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "JT62 25e9(x-1/10)(x-998/1000)(x-99999/100000)(x-100002/100000)(x-1001/1000)",
            Printed(&[
                2.5e10,
                -1.0247525e11,
                1.59923224745e11,
                -1.14918219464005e11,
                3.496776469345551e10,
                -2.497519974450501e9,
            ]),
            (-14.0, 28.1),
            &[
                ("1/10", 1),
                ("499/500", 1),
                ("99999/100000", 1),
                ("50001/50000", 1),
                ("1001/1000", 1),
            ],
            &[],
            1e-5,
        ),
        case(
            VTK,
            "JT8 (x+1)^5",
            Printed(&[1.0, 5.0, 10.0, 10.0, 5.0, 1.0]),
            (-14.0, 28.1),
            &[("-1", 5)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "JT9 (x-10^-13)(x+10^13)",
            Printed(&[1.0, 1e13, -1.0]),
            (-1e14, 28.1),
            &[("-1e13", 1), ("1/10000000000000", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P10a (x-10^3)(x-1)(x-10^-3)",
            Printed(&[1.0, -1.001001e3, 1.001001e3, -1.0]),
            (-14.0, 1e4),
            &[("1/1000", 1), ("1", 1), ("1000", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P10b (x-10^6)(x-1)(x-10^-6)",
            Printed(&[1.0, -1.000001000001e6, 1.000001000001e6, -1.0]),
            (-14.0, 1e7),
            &[("1/1000000", 1), ("1", 1), ("1000000", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P10c (x-10^9)(x-1)(x-10^-9)",
            Printed(&[1.0, -1.000000001e9, 1.000000001e9, -1.0]),
            (-14.0, 1e10),
            &[("1/1000000000", 1), ("1", 1), ("1000000000", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "igyp00 (x-2.35)(x-2.37)(x-2.39)",
            Printed(&[1.0, -7.11, 1.68503e1, -1.3311105e1]),
            (-14.0, 28.1),
            &[("47/20", 1), ("237/100", 1), ("239/100", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "igyp01 (x-2.35)^3(x-2.37)",
            Printed(&[1.0, -9.42, 3.3276e1, -5.224285e1, 3.075756375e1]),
            (-14.0, 28.1),
            &[("47/20", 3), ("237/100", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "iliev01 (x-1)(x+2)^2(x+3)^3",
            Printed(&[1.0, 12.0, 54.0, 104.0, 45.0, -108.0, -108.0]),
            (-14.0, 28.1),
            &[("-3", 3), ("-2", 2), ("1", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "iliev02 (x-1)^2(x-2)^4(x-3)^6",
            Printed(&[
                1.0, -28.0, 356.0, -2716.0, 13838.0, -49564.0, 127852.0, -239076.0, 321273.0,
                -302184.0, 188568.0, -69984.0, 11664.0,
            ]),
            (-14.0, 28.1),
            &[("1", 2), ("2", 4), ("3", 6)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "polymult (x-1)^6(x-2)^6(x-3)^6",
            Printed(&[
                1., -36., 606., -6336., 46095., -247716., 1018816., -3278016., 8361951.,
                -17033580., 27767046., -36128736., 37235521., -29981196., 18442620., -8362656.,
                2632176., -513216., 46656.,
            ]),
            (-14.0, 28.1),
            &[("1", 6), ("2", 6), ("3", 6)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "twin01 (x-.39)^4(x-.4)^4(x-.2)^4",
            Printed(&[
                1.,
                -3.96,
                7.1366,
                -7.736316,
                5.61584481,
                -2.874527064,
                1.0633461368,
                -0.286299144,
                0.055658703376,
                -0.007616429184,
                0.00069613420032,
                -3.8146387968e-5,
                9.475854336e-7,
            ]),
            (-14.0, 28.1),
            &[("1/5", 4), ("39/100", 4), ("2/5", 4)],
            &[],
            1e-5,
        ),
        case(
            VTK,
            "toh06a 1+x+...+x^20",
            Printed(&[1.0; 21]),
            (-14.0, 28.1),
            &[],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P4 (x-1)^2(x-2)(x-3)",
            Printed(&[1.0, -7.0, 17.0, -17.0, 6.0]),
            (-14.0, 28.1),
            &[("1", 2), ("2", 1), ("3", 1)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P5 x(x-1)(x-2)(x-3)(x-4)",
            Printed(&[1.0, -10.0, 35.0, -50.0, 24.0, 0.0]),
            ALL,
            &[("0", 1), ("1", 1), ("2", 1), ("3", 1), ("4", 1)],
            &[],
            1e-12,
        ),
        case(
            VTK,
            "P2 (x-1)^2",
            Printed(&[1.0, -2.0, 1.0]),
            (-14.0, 28.1),
            &[("1", 2)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P4_2 (x+4)^2(x-4)^2 on (-4, 4]",
            Printed(&[1.0, 0.0, -32.0, 0.0, 256.0]),
            (-4.0, 4.0),
            &[("-4", 2), ("4", 2)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P12 (x-1)^4(x-2)^4(x-3)^4",
            Printed(&[
                1., -24., 260., -1680., 7206., -21600., 46364., -71760., 79441., -61320., 31320.,
                -9504., 1296.,
            ]),
            (0.0, 20.0),
            &[("1", 4), ("2", 4), ("3", 4)],
            &[],
            1e-7,
        ),
        case(
            VTK,
            "P22 degree 22",
            Printed(&[
                -0.0005, -0.001, 0.05, 0.1, -0.2, 1., 0., -5.1, 0., 4., -1., 0.2, 3., 2.2, 2., -7.,
                -0.3, 3.8, 14., -16., 80., -97.9, 5.,
            ]),
            (-10.0, 10.0),
            &[],
            &[
                -9.5799184021307155490,
                -4.1659457357018254697,
                -1.6909764377051033080,
                0.053377023199573159218,
                1.1281470811227336526,
                1.2804679030668921769,
                1.7510169549495913088,
                9.9112562522641383112,
            ],
            1e-7,
        ),
        case(
            VTK,
            "P4_3 x^4+3x^3-4x^2+1e-18 (Ferrari sees a double root)",
            Printed(&[1.0, 3.0, -4.0, 0.0, 1e-18]),
            ALL,
            &[],
            &[-4.0, -5e-10, 5e-10, 1.0],
            1e-9,
        ),
        case(
            VTK,
            "P3 x(x-10^-4)^2",
            Printed(&[1.0, -2e-4, 1e-8, 0.0]),
            ALL,
            &[("0", 1), ("1/10000", 2)],
            &[],
            1e-12,
        ),
        case(
            VTK,
            "P3_2 x^3+x^2+x+1",
            Printed(&[1.0, 1.0, 1.0, 1.0]),
            ALL,
            &[],
            &[-1.0],
            1e-12,
        ),
        case(
            VTK,
            "P3_3 x^3-2e-6x^2+0.999999999999999e-12x (close pair near 1e-6)",
            Printed(&[1.0, -2e-6, 0.999999999999999e-12, 0.0]),
            ALL,
            &[],
            &[
                0.0,
                1e-6 - 3.1622776601683795e-14,
                1e-6 + 3.1622776601683795e-14,
            ],
            1e-12,
        ),
        case(
            VTK,
            "P10 76x^10+95x^2-14",
            Printed(&[76., 0., 0., 0., 0., 0., 0., 0., 95., 0., -14.]),
            (-10.0, 10.0),
            &[],
            &[-0.38381365387613186613, 0.38381365386885590851],
            1e-7,
        ),
        case(
            VTK,
            "P84 55x^84-79x^72+90x^71+37x^44+49x^21-12",
            Printed(&P84),
            (-10.0, 10.0),
            &[],
            &[-1.0923995943740010262, 0.92872986290603876114],
            1e-7,
        ),
        // Boost.Math's cubic and quartic solver tests, their fixed cases.
        case(
            BOOST_CUBIC,
            "x^3",
            Printed(&[1.0, 0.0, 0.0, 0.0]),
            ALL,
            &[("0", 3)],
            &[],
            1e-15,
        ),
        case(
            BOOST_CUBIC,
            "x^3 + 1",
            Printed(&[1.0, 0.0, 0.0, 1.0]),
            ALL,
            &[],
            &[-1.0],
            1e-15,
        ),
        case(
            BOOST_CUBIC,
            "x^3 - 1",
            Printed(&[1.0, 0.0, 0.0, -1.0]),
            ALL,
            &[],
            &[1.0],
            1e-15,
        ),
        case(
            BOOST_CUBIC,
            "x^3 - 2 (to 2 ulp)",
            Printed(&[1.0, 0.0, 0.0, -2.0]),
            ALL,
            &[],
            &[1.2599210498948731648],
            4.5e-16,
        ),
        case(
            BOOST_CUBIC,
            "x^3 - 8",
            Printed(&[1.0, 0.0, 0.0, -8.0]),
            ALL,
            &[],
            &[2.0],
            1e-15,
        ),
        case(
            BOOST_CUBIC,
            "(x-1)(x-2)(x-3)",
            Printed(&[1.0, -6.0, 11.0, -6.0]),
            ALL,
            &[("1", 1), ("2", 1), ("3", 1)],
            &[],
            4.5e-16,
        ),
        case(
            BOOST_CUBIC,
            "(x+1)^2 (x-2), 'unstable wrt perturbations'",
            Printed(&[1.0, 0.0, -3.0, -2.0]),
            ALL,
            &[("-1", 2), ("2", 1)],
            &[],
            4.5e-16,
        ),
        case(
            BOOST_QUARTIC,
            "x^3 + 1 as a quartic with a zero leading coefficient",
            Printed(&[0.0, 1.0, 0.0, 0.0, 1.0]),
            ALL,
            &[],
            &[-1.0],
            1e-15,
        ),
        case(
            BOOST_QUARTIC,
            "x^3 - 2 as a quartic with a zero leading coefficient",
            Printed(&[0.0, 1.0, 0.0, 0.0, -2.0]),
            ALL,
            &[],
            &[1.2599210498948731648],
            4.5e-16,
        ),
        case(
            BOOST_QUARTIC,
            "x^4 - 1",
            Printed(&[1.0, 0.0, 0.0, 0.0, -1.0]),
            ALL,
            &[],
            &[-1.0, 1.0],
            7e-16,
        ),
        case(
            BOOST_QUARTIC,
            "x^4 - 2 (to 3 ulp)",
            Printed(&[1.0, 0.0, 0.0, 0.0, -2.0]),
            ALL,
            &[],
            &[-1.1892071150027210667, 1.1892071150027210667],
            7e-16,
        ),
        case(
            BOOST_QUARTIC,
            "x(x-1)(x-2)(x-3)",
            Printed(&[1.0, -6.0, 11.0, -6.0, 0.0]),
            ALL,
            &[("0", 1), ("1", 1), ("2", 1), ("3", 1)],
            &[],
            4.5e-16,
        ),
        case(
            BOOST_QUARTIC,
            "(x-1)(x-2)(x-3)(x-4)",
            Printed(&[1.0, -10.0, 35.0, -50.0, 24.0]),
            ALL,
            &[("1", 1), ("2", 1), ("3", 1), ("4", 1)],
            &[],
            4.5e-16,
        ),
        case(
            BOOST_QUARTIC,
            "(x+1)^2 (x-2)(x-3), 'unstable wrt perturbations'",
            Printed(&[1.0, -3.0, -3.0, 7.0, 6.0]),
            ALL,
            &[("-1", 2), ("2", 1), ("3", 1)],
            &[],
            4.5e-16,
        ),
        // GSL's quadratic, cubic and complex solver tests.
        case(
            GSL,
            "(2x-5)^2 = -1",
            Printed(&[4.0, -20.0, 26.0]),
            ALL,
            &[],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(2x-5)^2 = 0",
            Printed(&[4.0, -20.0, 25.0]),
            ALL,
            &[("5/2", 2)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(2x-5)^2 = 4",
            Printed(&[4.0, -20.0, 21.0]),
            ALL,
            &[("3/2", 1), ("7/2", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "x(4x+7)",
            Printed(&[4.0, 7.0, 0.0]),
            ALL,
            &[("-7/4", 1), ("0", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "5x^2 = 20",
            Printed(&[5.0, 0.0, -20.0]),
            ALL,
            &[("-2", 1), ("2", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "3x - 21",
            Printed(&[3.0, -21.0]),
            ALL,
            &[("7", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "x^3 = 27",
            Printed(&[1.0, 0.0, 0.0, -27.0]),
            ALL,
            &[],
            &[3.0],
            1e-9,
        ),
        case(
            GSL,
            "(x-17)^3",
            Printed(&[1.0, -51.0, 867.0, -4913.0]),
            ALL,
            &[("17", 3)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(x-17)^2(x-23)",
            Printed(&[1.0, -57.0, 1071.0, -6647.0]),
            ALL,
            &[("17", 2), ("23", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(x+23)(x-17)^2",
            Printed(&[1.0, -11.0, -493.0, 6647.0]),
            ALL,
            &[("-23", 1), ("17", 2)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(x-17)(x-31)(x-95)",
            Printed(&[1.0, -143.0, 5087.0, -50065.0]),
            ALL,
            &[("17", 1), ("31", 1), ("95", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(x+17)(x-31)(x-95)",
            Printed(&[1.0, -109.0, 803.0, 50065.0]),
            ALL,
            &[("-17", 1), ("31", 1), ("95", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "(x+3)(x^2-4x+13)",
            Printed(&[1.0, -1.0, 1.0, 39.0]),
            ALL,
            &[],
            &[-3.0],
            1e-9,
        ),
        case(
            GSL,
            "Wilkinson 5: (x-1)...(x-5)",
            Printed(&[1.0, -15.0, 85.0, -225.0, 274.0, -120.0]),
            ALL,
            &[("1", 1), ("2", 1), ("3", 1), ("4", 1), ("5", 1)],
            &[],
            1e-9,
        ),
        case(
            GSL,
            "x^8+x^4+1",
            Printed(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
            ALL,
            &[],
            &[],
            1e-9,
        ),
        // numpy's polyroots(polyfromroots(linspace(-1, 1, i))), i = 2..4, and polyroots([1, 2]).
        case(
            NUMPY,
            "1 + 2x",
            Printed(&[2.0, 1.0]),
            ALL,
            &[("-1/2", 1)],
            &[],
            1e-7,
        ),
        case(
            NUMPY,
            "linspace(-1, 1, 2)",
            FromRoots(1.0),
            ALL,
            &[("-1", 1), ("1", 1)],
            &[],
            1e-7,
        ),
        case(
            NUMPY,
            "linspace(-1, 1, 3)",
            FromRoots(1.0),
            ALL,
            &[("-1", 1), ("0", 1), ("1", 1)],
            &[],
            1e-7,
        ),
        case(
            NUMPY,
            "linspace(-1, 1, 4)",
            FromRoots(1.0),
            ALL,
            &[("-1", 1), ("-1/3", 1), ("1/3", 1), ("1", 1)],
            &[],
            1e-7,
        ),
        // MultRoot's multiplicity tests.
        case(
            MULTROOT,
            "(x-1)(x-2)^2(x-3)^3",
            FromRoots(1.0),
            ALL,
            &[("1", 1), ("2", 2), ("3", 3)],
            &[],
            1e-12,
        ),
        case(
            MULTROOT,
            "(x-1)^2(x-2)^2(x-3)^4",
            FromRoots(1.0),
            ALL,
            &[("1", 2), ("2", 2), ("3", 4)],
            &[],
            1e-12,
        ),
        case(
            MULTROOT,
            "(x-1)^28",
            FromRoots(1.0),
            ALL,
            &[("1", 28)],
            &[],
            1e-12,
        ),
        case(
            MULTROOT,
            "(x-1)(x-2)(x-3)^3(x^2+1)",
            FromRoots(1.0),
            ALL,
            &[("1", 1), ("2", 1), ("3", 3)],
            &[],
            1e-12,
        ),
        case(
            MULTROOT_CALGO,
            "near03 (x-0.999)^20(x-1)^20(x+0.5)^5, degree 45",
            FromRoots(1.0),
            ALL,
            &[("-1/2", 5), ("999/1000", 20), ("1", 20)],
            &[],
            1e-12,
        ),
        // Wilkinson-type products, degree 20 to 100.
        case(
            WILKINSON,
            "W20 (x-1)...(x-20)",
            FromRoots(1.0),
            ALL,
            &[
                ("1", 1),
                ("2", 1),
                ("3", 1),
                ("4", 1),
                ("5", 1),
                ("6", 1),
                ("7", 1),
                ("8", 1),
                ("9", 1),
                ("10", 1),
                ("11", 1),
                ("12", 1),
                ("13", 1),
                ("14", 1),
                ("15", 1),
                ("16", 1),
                ("17", 1),
                ("18", 1),
                ("19", 1),
                ("20", 1),
            ],
            &[],
            1e-12,
        ),
        case(
            WILKINSON,
            "(x^2-1)^50, degree 100",
            FromRoots(1.0),
            ALL,
            &[("-1", 50), ("1", 50)],
            &[],
            1e-12,
        ),
        case(
            WILKINSON,
            "x^40 (x-1/2)^30 (x+3/4)^30, degree 100",
            FromRoots(1.0),
            ALL,
            &[("-3/4", 30), ("0", 40), ("1/2", 30)],
            &[],
            1e-12,
        ),
    ]
}

fn parse_rational(s: &str) -> BigRational {
    let int = |t: &str| -> BigInt {
        match t.split_once('e') {
            Some((m, e)) => int_pow(m, e),
            None => t.parse().expect("an integer"),
        }
    };
    match s.split_once('/') {
        Some((n, d)) => BigRational::new(int(n), int(d)),
        None => BigRational::from_integer(int(s)),
    }
}

fn int_pow(m: &str, e: &str) -> BigInt {
    let m: BigInt = m.parse().expect("a mantissa");
    m * num_traits::pow(BigInt::from(10), e.parse().expect("an exponent"))
}

/// lead · ∏ (x − r)^m exactly, lowest degree first.
fn product(lead: &BigRational, roots: &[(&str, u32)]) -> Vec<BigRational> {
    let mut c = vec![lead.clone()];
    for &(r, m) in roots {
        let r = parse_rational(r);
        for _ in 0..m {
            let mut next = vec![BigRational::zero(); c.len() + 1];
            for (i, ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= ci * &r;
            }
            c = next;
        }
    }
    c
}

fn to_f64(x: &BigRational) -> f64 {
    num_traits::ToPrimitive::to_f64(x).expect("in range")
}

#[test]
fn corpus_answers_are_certified_and_right() {
    let solver = Solver::default();
    let (mut exact, mut exact_right, mut rounded, mut rounded_recovered) = (0, 0, 0, 0);
    let mut failures = Vec::new();
    for case in cases() {
        let coeffs: Vec<f64> = match case.coeffs {
            Coeffs::Printed(c) => c.iter().rev().copied().collect(),
            Coeffs::FromRoots(lead) => {
                let lead = BigRational::from_float(lead).unwrap();
                product(&lead, case.rational).iter().map(to_f64).collect()
            }
        };
        let (a, b) = case.interval;
        let (cert, _) = solver.certified(&coeffs, a, b).expect("a valid case");
        let label = format!("{} ({})", case.name, case.source);
        if let Err(e) = certify::check(&coeffs, a, b, solver.tolerance, &cert) {
            failures.push(format!("{label}: certificate: {e}"));
            continue;
        }
        // Are the coefficients exactly the product of the source's factors?
        let lead = BigRational::from_float(*coeffs.last().unwrap()).unwrap();
        let is_exact = !case.rational.is_empty()
            && product(&lead, case.rational)
                == coeffs
                    .iter()
                    .map(|&c| BigRational::from_float(c).unwrap())
                    .collect::<Vec<_>>();
        let within = |got: f64, want: f64, tol: f64| {
            (got - want).abs() <= tol * want.abs().max(f64::MIN_POSITIVE)
        };
        if is_exact {
            exact += 1;
            let want: Vec<(BigRational, u32)> = case
                .rational
                .iter()
                .map(|&(r, m)| (parse_rational(r), m))
                .filter(|(r, _)| {
                    *r > BigRational::from_float(a).unwrap()
                        && *r <= BigRational::from_float(b).unwrap()
                })
                .collect();
            let right = cert.roots.len() == want.len()
                && cert.roots.iter().zip(&want).all(|(got, (r, m))| {
                    let err = (BigRational::from_float(got.value).unwrap() - r).abs_sub_zero();
                    got.multiplicity == *m && err <= BigRational::from_float(got.bound).unwrap()
                });
            if right {
                exact_right += 1;
            } else {
                failures.push(format!(
                    "{label}: exact coefficients, wrong answer {:?}",
                    cert.roots
                ));
            }
        } else {
            rounded += 1;
            let nominal: Vec<f64> = if case.rational.is_empty() {
                case.nominal.to_vec()
            } else {
                case.rational
                    .iter()
                    .map(|&(r, _)| to_f64(&parse_rational(r)))
                    .collect()
            };
            let nominal: Vec<f64> = nominal.into_iter().filter(|&r| a < r && r <= b).collect();
            let values = cert.values();
            let recovered = values.len() == nominal.len()
                && values
                    .iter()
                    .zip(&nominal)
                    .all(|(&g, &w)| within(g, w, case.source_tol.max(solver.tolerance)));
            rounded_recovered += usize::from(recovered);
            if !recovered {
                eprintln!(
                    "{label}: the rounded coefficients' own roots {values:?} (source: {nominal:?})"
                );
            }
        }
    }
    eprintln!(
        "corpus: {} cases certified; exact coefficients: {exact_right}/{exact} answered with the source's roots and \
         multiplicities; rounded or irrational: {rounded_recovered}/{rounded} with the source's real roots within its tolerance",
        exact + rounded
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(exact >= 30, "most cases have exact coefficients ({exact})");
}

/// |x| for the comparisons above.
trait AbsSubZero {
    fn abs_sub_zero(self) -> Self;
}

impl AbsSubZero for BigRational {
    fn abs_sub_zero(self) -> Self {
        if self < BigRational::zero() {
            -self
        } else {
            self
        }
    }
}

#[test]
fn rational_parser() {
    assert_eq!(
        parse_rational("-1e3"),
        BigRational::from_integer(BigInt::from(-1000))
    );
    assert_eq!(
        parse_rational("3/6"),
        BigRational::new(BigInt::one(), BigInt::from(2))
    );
}
