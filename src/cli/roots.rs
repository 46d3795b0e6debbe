//! `sturmray roots`: JSON lines in, one JSON line out per line, for people
//! debugging a surface's polynomial and as a test harness.
//!
//! In: `{"coeffs": [c0, c1, ...], "interval": [a, b], "method": "...",
//! "tolerance": 1e-12}`, lowest degree first; `interval` defaults to
//! (−MAX, MAX], every root an f64 can hold, `method` to the renderer's
//! default. Any finite coefficients are accepted, subnormal ones included;
//! only all zeros is the zero polynomial.
//! Out: `{"roots": [...], "count": n}`: the distinct roots in (a, b],
//! increasing, each within the tolerance of its own root, relative to the
//! root's magnitude (or correctly rounded where f64 cannot get that close),
//! and `count` the exact Sturm count of the rational
//! coefficients, always the length of the list: the method's f64 answer is
//! given only when the exact isolation certifies it, else the exact path
//! answers (see `Solver::certified_roots`). With `--sturm`, the f64 Sturm
//! sequence and its sign table, for debugging the fast path (its counts
//! are f64's and may differ). A bad line gives `{"error": "...", "line": n}`.

use std::io::{BufRead, Write};

use serde::Deserialize;
use serde_json::{Value, json};

use sturmray::error::{Error, Result};
use sturmray::poly::MAX_DEGREE;
use sturmray::poly::exact::{Isolation, Relative};
use sturmray::poly::solve::{Method, Solver};
use sturmray::poly::sturm::SturmSequence;
use sturmray::poly::univariate::{Poly, nonzero};

/// Find polynomial roots: JSON lines {"coeffs": [c0, c1, ...], "interval": [a, b],
/// "method": "..."} on stdin, one JSON line out per line.
#[derive(clap::Args)]
pub struct Args {
    /// Also print the Sturm sequence and its sign table at a and b.
    #[arg(long)]
    sturm: bool,
}

/// Answers stdin on stdout; any bad line makes the command's error (exit 2)
/// once every line is answered.
pub fn run(Args { sturm }: Args) -> anyhow::Result<()> {
    let any_bad = answer_all(std::io::stdin().lock(), std::io::stdout().lock(), sturm)?;
    if any_bad {
        let message = "some lines were not understood (see their error lines)";
        return Err(Error::Input(message.into()).into());
    }
    Ok(())
}

/// The method name of the exact rational path (not a renderer method: it allocates).
const EXACT: &str = "exact";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Query {
    coeffs: Vec<f64>,
    interval: Option<[f64; 2]>,
    method: Option<String>,
    tolerance: Option<f64>,
}

/// The interval when none is given: every root an f64 can hold (a root
/// beyond ±MAX has no f64 to print).
const DEFAULT_INTERVAL: [f64; 2] = [-f64::MAX, f64::MAX];

fn signs(sturm: &SturmSequence, t: f64) -> Vec<i32> {
    sturm
        .members()
        .iter()
        .map(|m| {
            let v = m.eval(t);
            if v > 0.0 {
                1
            } else if v < 0.0 {
                -1
            } else {
                0
            }
        })
        .collect()
}

/// Answers one line; Err is the message of an error line.
fn answer(line: &str, with_sturm: bool) -> Result<Value, String> {
    let q: Query = serde_json::from_str(line).map_err(|e| e.to_string())?;
    if q.coeffs.is_empty() || q.coeffs.len() > MAX_DEGREE + 1 {
        return Err(format!(
            "coeffs: expected 1 to {} numbers (degree <= {MAX_DEGREE}), found {}",
            MAX_DEGREE + 1,
            q.coeffs.len()
        ));
    }
    if q.coeffs.iter().any(|c| !c.is_finite()) {
        return Err("coeffs: every coefficient must be finite".into());
    }
    // From the bits: this thread reads subnormals as zero, and a subnormal
    // coefficient is an ordinary nonzero number here.
    match q.coeffs.iter().rposition(|&c| nonzero(c)) {
        None => return Err("the polynomial is identically zero (every coefficient is 0)".into()),
        Some(0) => return Err("the polynomial is a nonzero constant: it has no roots".into()),
        Some(_) => {}
    }
    let [a, b] = q.interval.unwrap_or(DEFAULT_INTERVAL);
    if !(a.is_finite() && b.is_finite() && a < b) {
        return Err(format!("interval: expected finite a < b, found [{a}, {b}]"));
    }
    let mut solver = Solver::default();
    if let Some(t) = q.tolerance {
        if !(t > 0.0 && t < 1.0) {
            return Err(format!("tolerance: expected a number in (0, 1), found {t}"));
        }
        solver.tolerance = t;
    }
    let not_finite = "coeffs: every coefficient must be finite";
    // Both answers are proven to list exactly the exact count's roots: the
    // exact path by construction, the f64 one by `certified_roots`.
    let roots = match q.method.as_deref() {
        Some(EXACT) => Isolation::new(&q.coeffs, a, b)
            .and_then(|isolation| isolation.roots(solver.tolerance, Relative::Magnitude))
            .ok_or(not_finite)?,
        name => {
            if let Some(name) = name {
                solver.method = name
                    .parse::<Method>()
                    .map_err(|e| format!("{e}, {EXACT}"))?;
            }
            solver.certified_roots(&q.coeffs, a, b).ok_or(not_finite)?
        }
    };
    let count = roots.len();
    let mut reply = json!({ "roots": roots, "count": count });
    if with_sturm {
        let sturm = SturmSequence::new(&Poly::new(&q.coeffs));
        let sequence: Vec<&[f64]> = sturm.members().iter().map(Poly::coeffs).collect();
        reply["sturm"] = json!({
            "sequence": sequence,
            "signs_a": signs(&sturm, a),
            "signs_b": signs(&sturm, b),
            "variations_a": sturm.sign_variations(a),
            "variations_b": sturm.sign_variations(b),
        });
    }
    Ok(reply)
}

/// Answers every line of `input`; returns whether any line was bad.
fn answer_all(input: impl BufRead, mut output: impl Write, with_sturm: bool) -> Result<bool> {
    let mut any_bad = false;
    let write_error = |e: std::io::Error| Error::Input(format!("cannot write the answers: {e}"));
    for (index, line) in input.lines().enumerate() {
        let line =
            line.map_err(|e| Error::Input(format!("cannot read line {}: {e}", index + 1)))?;
        if line.trim().is_empty() {
            continue;
        }
        let reply = answer(&line, with_sturm).unwrap_or_else(|message| {
            any_bad = true;
            json!({ "error": message, "line": index + 1 })
        });
        match writeln!(output, "{reply}") {
            // A reader that stops early (`| head`) wants no more answers.
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => break,
            other => other.map_err(write_error)?,
        }
    }
    Ok(any_bad)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ask(lines: &str, sturm: bool) -> (Vec<Value>, bool) {
        let mut out = Vec::new();
        let bad = answer_all(lines.as_bytes(), &mut out, sturm).unwrap();
        let replies = String::from_utf8(out)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        (replies, bad)
    }

    #[test]
    fn roots_counts_and_bad_lines() {
        let input = r#"{"coeffs": [-1, 0, 1], "interval": [-2, 2]}
{"coeffs": [0, -1, 0, 1], "interval": [-2, 2], "method": "sturm-bisect"}
not json
{"coeffs": [1, -3, 3, -1], "interval": [0, 2], "method": "exact"}
{"coeffs": [1, 2], "interval": [3, 1]}
{"coeffs": [-1, 0, 1], "method": "newton-magic"}
{"coeffs": [2]}
{"coeffs": [-1, 0, 1]}
"#;
        let (r, bad) = ask(input, false);
        assert!(bad);
        assert_eq!(r[0], json!({"roots": [-1.0, 1.0], "count": 2}));
        assert_eq!(r[1]["count"], 3);
        assert_eq!(r[2]["line"], 3);
        // (1 - t)^3: one distinct root, exactly 1, in (0, 2].
        assert_eq!(r[3], json!({"roots": [1.0], "count": 1}));
        assert!(r[4]["error"].as_str().unwrap().contains("interval"));
        assert!(r[5]["error"].as_str().unwrap().contains("sturm-newton"));
        assert!(r[6]["error"].as_str().unwrap().contains("no roots"));
        assert_eq!(r[7]["count"], 2, "default interval holds every root");
    }

    /// An output that refuses every write, as a pipe whose reader is gone.
    struct Closed(std::io::ErrorKind);

    impl Write for Closed {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(self.0.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_reader_that_stops_early_is_no_error() {
        let input = "{\"coeffs\": [-1, 0, 1]}\n".repeat(3);
        let closed = Closed(std::io::ErrorKind::BrokenPipe);
        assert!(!answer_all(input.as_bytes(), closed, false).unwrap());
        // Any other failure to write is one.
        let full = Closed(std::io::ErrorKind::StorageFull);
        let err = answer_all(input.as_bytes(), full, false)
            .unwrap_err()
            .to_string();
        assert!(err.contains("cannot write the answers"), "{err}");
    }

    #[test]
    fn sturm_table_of_t4_minus_t2() {
        let (r, _) = ask(r#"{"coeffs": [0, 0, -1, 0, 1], "interval": [-2, 2]}"#, true);
        let s = &r[0]["sturm"];
        assert_eq!(
            (s["variations_a"].as_u64(), s["variations_b"].as_u64()),
            (Some(3), Some(0))
        );
        assert_eq!(r[0]["count"], 3);
        assert_eq!(s["signs_a"][0], 1);
    }
}
