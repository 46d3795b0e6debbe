use super::*;
use proptest::prelude::*;
use std::time::Instant;

const TORUS: &str = "(x^2+y^2+z^2+R^2-r^2)^2 - 4*R^2*(x^2+y^2)";

fn consts() -> Vec<(&'static str, f64)> {
    vec![("R", 1.0), ("r", 0.25)]
}

fn ok(text: &str) -> Trivariate {
    parse(text, &consts()).unwrap_or_else(|e| panic!("{text:?}: {e}"))
}

fn err(text: &str) -> ParseError {
    match parse(text, &consts()) {
        Ok(p) => panic!("{text:?} parsed as {p}"),
        Err(e) => e,
    }
}

fn terms(list: &[([u8; 3], f64)]) -> Trivariate {
    Trivariate::from_terms(list.iter().copied())
}

#[test]
fn torus_expands_to_the_known_polynomial() {
    for (big_r, r) in [(1.0, 0.25), (2.0, 0.5), (1.0, 0.02), (3.0, 1.0)] {
        let p = parse(TORUS, &[("R", big_r), ("r", r)]).unwrap();
        // (x²+y²+z²)² − 2(R²+r²)(x²+y²) + 2(R²−r²)z² + (R²−r²)², by hand.
        let (a, b) = (big_r * big_r, r * r);
        let want = terms(&[
            ([4, 0, 0], 1.0),
            ([2, 2, 0], 2.0),
            ([2, 0, 2], 2.0),
            ([2, 0, 0], -2.0 * (a + b)),
            ([0, 4, 0], 1.0),
            ([0, 2, 2], 2.0),
            ([0, 2, 0], -2.0 * (a + b)),
            ([0, 0, 4], 1.0),
            ([0, 0, 2], 2.0 * (a - b)),
            ([0, 0, 0], (a - b) * (a - b)),
        ]);
        assert_eq!(p.terms().len(), want.terms().len(), "{p}");
        for (got, want) in p.terms().iter().zip(want.terms()) {
            assert_eq!(got.0, want.0, "{p}");
            assert!(
                (got.1 - want.1).abs() <= 1e-15 * want.1.abs().max(1.0),
                "{p}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn goursat_tangle_cube() {
    let p = ok("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8");
    assert_eq!(
        p,
        terms(&[
            ([4, 0, 0], 1.0),
            ([2, 0, 0], -5.0),
            ([0, 4, 0], 1.0),
            ([0, 2, 0], -5.0),
            ([0, 0, 4], 1.0),
            ([0, 0, 2], -5.0),
            ([0, 0, 0], 11.8),
        ])
    );
    assert_eq!(p.degree(), 4);
}

#[test]
fn numbers() {
    let x = |c: f64| terms(&[([1, 0, 0], c)]);
    assert_eq!(ok("12*x"), x(12.0));
    assert_eq!(ok("1.5*x"), x(1.5));
    assert_eq!(ok(".5*x"), x(0.5));
    assert_eq!(ok("2.*x"), x(2.0));
    assert_eq!(ok("1e-3*x"), x(1e-3));
    assert_eq!(ok("2.5E+2*x"), x(250.0));
    assert_eq!(ok("x/4"), x(0.25));
    assert_eq!(ok("x / (R + 1) / 2"), x(0.25));
}

#[test]
fn precedence_and_associativity() {
    let x2 = terms(&[([2, 0, 0], 1.0)]);
    assert_eq!(ok("-x^2"), x2.neg());
    assert_eq!(ok("(-x)^2"), x2);
    assert_eq!(ok("2^3^2*x"), terms(&[([1, 0, 0], 512.0)]));
    assert_eq!(ok("(2^3)^2*x"), terms(&[([1, 0, 0], 64.0)]));
    assert_eq!(ok("x^2^2"), terms(&[([4, 0, 0], 1.0)]));
    assert_eq!(ok("x*-y"), terms(&[([1, 1, 0], -1.0)]));
    assert_eq!(ok("-x*y"), terms(&[([1, 1, 0], -1.0)]));
    assert_eq!(ok("x - -y"), terms(&[([1, 0, 0], 1.0), ([0, 1, 0], 1.0)]));
    assert_eq!(ok("+x"), ok("x"));
    assert_eq!(ok("(x)"), ok("x"));
    assert_eq!(ok("((((x))))"), ok("x"));
    assert_eq!(ok("x - y - z"), ok("x - (y + z)"));
    assert_eq!(ok("x / 2 / 2"), ok("x / 4"));
    assert_eq!(
        ok("x + 2*y^2"),
        terms(&[([1, 0, 0], 1.0), ([0, 2, 0], 2.0)])
    );
    assert_eq!(ok("x^0 + z"), terms(&[([0, 0, 1], 1.0), ([0, 0, 0], 1.0)]));
    // Whitespace of every kind, including the newlines of a TOML string.
    assert_eq!(ok(" x\t*\n y "), terms(&[([1, 1, 0], 1.0)]));
    // An exponent may be a constant expression.
    assert_eq!(
        parse("x^(2*n) + y^n", &[("n", 2.0)]).unwrap(),
        terms(&[([4, 0, 0], 1.0), ([0, 2, 0], 1.0)])
    );
    // Division by a divisor whose x cancels is division by a constant.
    assert_eq!(ok("x/(x-x+2)"), terms(&[([1, 0, 0], 0.5)]));
}

#[test]
fn longer_names() {
    let p = parse(
        "alpha*x^2 + R2*y_1",
        &[("alpha", 2.0), ("R2", 3.0), ("y_1", 4.0)],
    );
    assert_eq!(p.unwrap(), terms(&[([2, 0, 0], 2.0), ([0, 0, 0], 12.0)]));
    // Case matters: X is not x.
    let e = err("X + y");
    assert_eq!(e.column, 1);
    assert!(e.message.contains("did you mean 'x'?"), "{e}");
}

#[test]
fn implicit_multiplication_is_an_error_at_the_second_factor() {
    let e = err("2x");
    assert_eq!(e.column, 2);
    assert!(e.message.contains("found 'x'"), "{e}");
    assert!(e.message.contains("implicit multiplication"), "{e}");
    assert_eq!(err("x y").column, 3);
    assert_eq!(err("(x)(y)").column, 4);
    assert_eq!(err("3 4*x").column, 3);
    assert_eq!(err("x + 2e").column, 6);
    let e = err("(x + 2 y)");
    assert_eq!(e.column, 8);
    assert!(e.message.contains("or ')'"), "{e}");
}

#[test]
fn unbalanced_parentheses() {
    let e = err("(x + 1");
    assert_eq!(e.column, 7);
    assert_eq!(
        e.message,
        "expected ')' to close the '(' at column 1 but found the end of the expression"
    );
    let e = err("x^2 )");
    assert_eq!(e.column, 5);
    assert!(e.message.contains("no matching '('"), "{e}");
    let e = err("()");
    assert_eq!(e.column, 2);
    assert!(
        e.message
            .starts_with("expected a number, a name or '(' but found ')'")
    );
    assert_eq!(err("((x)").column, 5);
}

#[test]
fn syntax_errors_name_column_and_expectation() {
    let e = err("x^2 + *3");
    assert_eq!(
        e.to_string(),
        "column 7: expected a number, a name or '(' but found '*'"
    );
    let e = err("x^2 +");
    assert_eq!(e.column, 6);
    assert!(
        e.message.ends_with("but found the end of the expression"),
        "{e}"
    );
    let e = err("x**2");
    assert_eq!(e.column, 3);
    assert!(e.message.contains("write '^'"), "{e}");
    let e = err("x + y # comment");
    assert_eq!(e.column, 7);
    assert!(e.message.contains("found '#'"), "{e}");
    let e = err("x + α");
    assert_eq!(e.column, 5, "columns count characters, not bytes");
    let e = err("x + 1.2.3");
    assert_eq!(e.column, 8);
}

#[test]
fn empty_input() {
    assert_eq!(err("").to_string(), "column 1: the expression is empty");
    assert_eq!(err("  \n ").column, 1);
}

#[test]
fn division_by_variables_or_zero() {
    let e = err("x/y");
    assert_eq!(e.column, 3);
    assert!(e.message.contains("cannot divide"), "{e}");
    let e = err("x/(1 + y^2)");
    assert_eq!(e.column, 3);
    let e = err("x/(R-1)");
    assert_eq!(e.column, 3);
    assert_eq!(e.message, "division by zero");
}

#[test]
fn bad_exponents() {
    let e = err("x^-1");
    assert_eq!(e.column, 3);
    assert!(
        e.message.contains("non-negative integer but it is -1"),
        "{e}"
    );
    let e = err("x^2.5");
    assert_eq!(e.column, 3);
    assert!(e.message.contains("it is 2.5"), "{e}");
    let e = err("x^y");
    assert_eq!(e.column, 3);
    assert!(e.message.contains("must be a constant"), "{e}");
    let e = err("x + R^0.5");
    assert!(e.message.contains("it is 0.5"), "{e}");
}

#[test]
fn unknown_names_suggest_the_closest() {
    let e = err("x^2 + rr");
    assert_eq!(e.column, 7);
    assert!(
        e.message
            .starts_with("unknown name 'rr': did you mean 'r'?"),
        "{e}"
    );
    assert!(e.message.contains("x, y, z, R, r"), "{e}");
    let e = err("x + banana");
    assert!(!e.message.contains("did you mean"), "{e}");
    // A constant that shadows a variable is ambiguous.
    let e = parse("x + y", &[("x", 1.0)]).unwrap_err();
    assert_eq!(e.column, 1);
    assert!(e.message.contains("rename the constant"), "{e}");
    let e = parse("x + a", &[("a", f64::INFINITY)]).unwrap_err();
    assert_eq!(e.column, 5);
}

#[test]
fn degree_limit() {
    let e = err("x^36");
    assert_eq!(e.column, 2);
    assert!(e.message.contains("36") && e.message.contains("35"), "{e}");
    let e = err("x^17 * y^19");
    assert_eq!(e.column, 6);
    assert!(
        e.message.contains("degree 36") && e.message.contains("35"),
        "{e}"
    );
    let e = err("(x^2 + y)^18");
    assert!(e.message.contains("degree 36"), "{e}");
    // Exactly 35 is fine (POV-Ray's limit), and so is a huge power of a
    // constant.
    assert_eq!(ok("(x^2+y^2+z^2-1)^17 * x").degree(), 35);
    assert_eq!(ok("x + 2^100").terms()[1].1, 2f64.powi(100));
    assert!(err("x^1e30").message.contains("above the limit of 35"));
}

#[test]
fn runaway_exponents_fail_fast() {
    let start = Instant::now();
    for text in [
        "(x+y+z)^1000",
        "(x+y+z)^4294967296",
        "((x+y)^8)^8",
        "(x+1)^18 * (y+1)^18",
    ] {
        let e = err(text);
        assert!(e.message.contains("limit of 35"), "{text}: {e}");
    }
    assert!(start.elapsed().as_millis() < 100, "{:?}", start.elapsed());
}

#[test]
fn constant_or_zero_expressions_are_refused() {
    let e = err("R + 2*r");
    assert_eq!(
        e.to_string(),
        "column 1: the expression does not depend on x, y or z"
    );
    let e = err("x - x");
    assert_eq!(
        e.to_string(),
        "column 1: the expression is identically zero"
    );
    let e = err("0*x^2");
    assert!(e.message.contains("identically zero"), "{e}");
}

#[test]
fn overflow_and_huge_literals() {
    let e = err("x * 1e400");
    assert_eq!(e.column, 5);
    assert!(e.message.contains("too large"), "{e}");
    // Constants must be f64 numbers; a polynomial's scale is kept apart,
    // so 1e400·x is the surface x = 0 (normalised), not an overflow.
    let e = err("1e200*1e200*x");
    assert_eq!(e.column, 6);
    assert!(e.message.contains("overflows"), "{e}");
    assert!(err("x + 10^400").message.contains("overflows"));
    let p = ok("1e200*x * 1e200");
    assert_eq!((p.terms().len(), p.terms()[0].0), (1, [1, 0, 0]), "{p}");
}

#[test]
fn a_scale_factor_does_not_change_the_surface() {
    // k·F, normalised, is F normalised times k's mantissa: exactly F for
    // powers of two (also where k·F itself leaves the f64 range), every
    // coefficient in the same ratio to rounding otherwise.
    let f = ok(TORUS).normalized().0;
    for k in ["0.5^1070", "2^1000", "1e308", "1e-310", "-1e-300", "3"] {
        let g = ok(&format!("{k}*({TORUS})")).normalized().0;
        assert_eq!(g.terms().len(), f.terms().len(), "{k}: {g}");
        let ratio = g.terms()[0].1 / f.terms()[0].1;
        if k.contains('^') {
            assert_eq!(ratio, 1.0, "{k}");
        }
        for (a, b) in g.terms().iter().zip(f.terms()) {
            assert_eq!(a.0, b.0, "{k}");
            assert!(
                (a.1 - ratio * b.1).abs() <= 1e-12 * a.1.abs(),
                "{k}: {g} for {f}"
            );
        }
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let text = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    assert!(err(&text).message.contains("levels deep"));
    let text = format!("{}x", "-".repeat(100_000));
    assert!(err(&text).message.contains("levels deep"));
    let text = format!("x{}", "^1".repeat(100_000));
    assert!(err(&text).message.contains("levels deep"));
    let ok_depth = format!("{}x{}", "(".repeat(150), ")".repeat(150));
    assert_eq!(ok(&ok_depth), ok("x"));
}

#[test]
fn display_round_trips_through_parse() {
    for text in [
        TORUS,
        "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8",
        "-x*y*z/3 + 1e-30*z^7",
    ] {
        let p = ok(text);
        assert_eq!(ok(&p.to_string()), p, "{p}");
    }
}

// ---- property test: random expressions, printed, parsed, evaluated ----

/// A small expression tree, evaluated independently of the parser.
#[derive(Clone, Debug)]
enum Ast {
    Num(f64),
    Var(usize),
    Const(usize),
    Neg(Box<Ast>),
    Add(Box<Ast>, Box<Ast>),
    Sub(Box<Ast>, Box<Ast>),
    Mul(Box<Ast>, Box<Ast>),
    /// Divisor: a nonzero number or constant.
    Div(Box<Ast>, Box<Ast>),
    Pow(Box<Ast>, u32),
}

const NAMES: [(&str, f64); 3] = [("R", 1.5), ("r2", 0.3), ("k_3", -2.0)];

fn degree(a: &Ast) -> usize {
    match a {
        Ast::Num(_) | Ast::Const(_) => 0,
        Ast::Var(_) => 1,
        Ast::Neg(a) => degree(a),
        Ast::Add(a, b) | Ast::Sub(a, b) => degree(a).max(degree(b)),
        Ast::Mul(a, b) => degree(a) + degree(b),
        Ast::Div(a, _) => degree(a),
        Ast::Pow(a, n) => degree(a) * *n as usize,
    }
}

/// (value, Σ of absolute values): the second bounds the rounding error
/// that cancellation can leave.
fn eval(a: &Ast, p: [f64; 3]) -> (f64, f64) {
    match a {
        Ast::Num(v) => (*v, v.abs()),
        Ast::Var(i) => (p[*i], p[*i].abs()),
        Ast::Const(i) => (NAMES[*i].1, NAMES[*i].1.abs()),
        Ast::Neg(a) => {
            let (v, m) = eval(a, p);
            (-v, m)
        }
        Ast::Add(a, b) => {
            let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
            (u + v, m + n)
        }
        Ast::Sub(a, b) => {
            let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
            (u - v, m + n)
        }
        Ast::Mul(a, b) => {
            let ((u, m), (v, n)) = (eval(a, p), eval(b, p));
            (u * v, m * n)
        }
        Ast::Div(a, b) => {
            let ((u, m), (v, _)) = (eval(a, p), eval(b, p));
            (u / v, m / v.abs())
        }
        Ast::Pow(a, n) => {
            let (v, m) = eval(a, p);
            let mut value = 1.0;
            let mut magnitude = 1.0;
            for _ in 0..*n {
                value *= v;
                magnitude *= m;
            }
            (value, magnitude)
        }
    }
}

/// Precedence levels of the grammar: sum 1, product 2, unary 3, power 4,
/// primary 5.
fn level(a: &Ast) -> u8 {
    match a {
        Ast::Add(..) | Ast::Sub(..) => 1,
        Ast::Mul(..) | Ast::Div(..) => 2,
        Ast::Neg(_) => 3,
        Ast::Pow(..) => 4,
        Ast::Num(_) | Ast::Var(_) | Ast::Const(_) => 5,
    }
}

/// Prints with only the parentheses the grammar needs, so the parser's
/// precedence and associativity are what the test exercises.
fn print(a: &Ast, style: u8) -> String {
    let wrap = |child: &Ast, min: u8| {
        let text = print(child, style);
        if level(child) < min {
            format!("({text})")
        } else {
            text
        }
    };
    let (lo, hi) = if style.is_multiple_of(2) {
        ("", "")
    } else {
        (" ", " ")
    };
    match a {
        Ast::Num(v) if style >= 2 => format!("{v:e}"),
        Ast::Num(v) => format!("{v}"),
        Ast::Var(i) => ["x", "y", "z"][*i].to_owned(),
        Ast::Const(i) => NAMES[*i].0.to_owned(),
        Ast::Neg(a) => format!("-{}", wrap(a, 3)),
        Ast::Add(a, b) => format!("{}{lo}+{hi}{}", wrap(a, 1), wrap(b, 2)),
        Ast::Sub(a, b) => format!("{}{lo}-{hi}{}", wrap(a, 1), wrap(b, 2)),
        Ast::Mul(a, b) => format!("{}{lo}*{hi}{}", wrap(a, 2), wrap(b, 3)),
        Ast::Div(a, b) => format!("{}{lo}/{hi}{}", wrap(a, 2), wrap(b, 3)),
        Ast::Pow(a, n) => format!("{}^{n}", wrap(a, 5)),
    }
}

fn arb_ast() -> impl Strategy<Value = Ast> {
    let leaf = prop_oneof![
        1 => (0.0..5.0f64).prop_map(Ast::Num),
        1 => (0u32..10).prop_map(|k| Ast::Num(f64::from(k))),
        4 => (0usize..3).prop_map(Ast::Var),
        1 => (0usize..3).prop_map(Ast::Const),
    ];
    let divisor = prop_oneof![
        (0.1..5.0f64).prop_map(Ast::Num),
        (0usize..3).prop_map(Ast::Const),
    ];
    leaf.prop_recursive(6, 48, 2, move |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| Ast::Neg(Box::new(a))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Ast::Mul(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Ast::Add(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Ast::Sub(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Ast::Mul(Box::new(a), Box::new(b))),
            (inner.clone(), divisor.clone()).prop_map(|(a, b)| Ast::Div(Box::new(a), Box::new(b))),
            (inner.clone(), 0u32..5).prop_map(|(a, n)| Ast::Pow(Box::new(a), n)),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn prop_printed_expressions_parse_to_their_value(
        ast in arb_ast().prop_filter("degree within the limit", |a| degree(a) <= MAX_DEGREE),
        style in 0u8..4,
        points in prop::collection::vec(prop::array::uniform3(-2.0..2.0f64), 4),
    ) {
        let text = print(&ast, style);
        match parse(&text, &NAMES) {
            Ok(poly) => {
                prop_assert!(poly.degree() <= degree(&ast));
                for &p in &points {
                    let (want, magnitude) = eval(&ast, p);
                    let got = poly.eval(p);
                    prop_assert!(
                        (got - want).abs() <= 1e-11 * magnitude.max(1e-300),
                        "{text}: at {p:?} the polynomial {poly} gives {got}, the tree {want}"
                    );
                }
            }
            Err(e) => {
                // Only a constant value may be refused; check it is one.
                prop_assert!(
                    e.message.contains("does not depend") || e.message.contains("identically zero"),
                    "{text}: {e}"
                );
                let (first, _) = eval(&ast, points[0]);
                for &p in &points[1..] {
                    let (v, magnitude) = eval(&ast, p);
                    prop_assert!((v - first).abs() <= 1e-11 * magnitude.max(1.0), "{text}: {e}");
                }
            }
        }
    }

    #[test]
    fn prop_display_round_trips_exactly(
        list in prop::collection::vec(((0u8..=6, 0u8..=5, 0u8..=5), prop_oneof![-1e3..1e3f64, Just(1.0), Just(-1.0), -1e-30..1e-30f64, -1e30..1e30f64]), 1..20),
    ) {
        let poly = Trivariate::from_terms(list.into_iter().map(|((a, b, c), k)| ([a, b, c], k)));
        prop_assume!(poly.degree() > 0);
        let text = poly.to_string();
        prop_assert_eq!(parse(&text, &[]).unwrap(), poly, "{}", text);
    }

    #[test]
    fn prop_arbitrary_text_never_panics(text in "[xyzR0-9 .e+*/^()-]{0,40}") {
        let _ = parse(&text, &NAMES);
    }
}
