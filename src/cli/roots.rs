//! `sturmray roots`: JSON lines in, one JSON line out per line, for people
//! debugging a surface's polynomial and as a test harness.
//!
//! In: `{"coeffs": [c0, c1, ...], "interval": [a, b], "method": "...",
//! "tolerance": 1e-12}`, lowest degree first, degree up to
//! [`MAX_EXACT_DEGREE`](sturmray::poly::exact::MAX_EXACT_DEGREE); `interval` defaults to (−MAX, MAX], every root an
//! f64 can hold, `method` to the renderer's default. Any finite
//! coefficients are accepted, subnormal ones included; only all zeros is
//! the zero polynomial.
//! Out: `{"roots": [...], "count": n, "multiplicity": [...], "bound":
//! [...]}`: the distinct roots in (a, b], increasing, each within the
//! tolerance of its own root relative to the root's magnitude (or correctly
//! rounded where f64 cannot get that close), with its exact multiplicity
//! and its certified error bound; `count` is the exact Sturm count of the
//! rational coefficients, always the length of the list. Every answer
//! carries the same proof, [`Certificate`]: the method's f64 answer is
//! given only when the exact isolation certifies it, else the exact path
//! answers (see `Solver::certified`); above degree [`MAX_DEGREE`] (the f64
//! path's fixed storage) the exact path answers alone. `--explain` adds the
//! certificate; `--sturm` the f64 Sturm sequence and its sign table, for
//! debugging the fast path (its counts are f64's and may differ). A bad
//! line gives `{"error": "...", "line": n}`.

use std::io::{BufRead, Write};

use serde::Deserialize;
use serde_json::{Value, json};

use sturmray::error::{Error, Result};
use sturmray::poly::MAX_DEGREE;
use sturmray::poly::exact::Certificate;
use sturmray::poly::query::{Answer, Query};
use sturmray::poly::sturm::SturmSequence;
use sturmray::poly::univariate::Poly;

/// Find polynomial roots: JSON lines {"coeffs": [c0, c1, ...], "interval": [a, b],
/// "method": "..."} on stdin, one JSON line out per line.
#[derive(clap::Args)]
pub struct Args {
    /// Also print the f64 Sturm sequence and its sign table at a and b
    /// (degree 35 or less).
    #[arg(long)]
    sturm: bool,
    /// Also print the certificate: the exact count's Sturm variations, each
    /// root's isolating interval with exact ends, the square-free factors.
    #[arg(long)]
    explain: bool,
}

/// What to print beside the answer.
#[derive(Clone, Copy, Default)]
struct Extras {
    sturm: bool,
    explain: bool,
}

/// Answers stdin on stdout; any bad line makes the command's error (exit 2)
/// once every line is answered.
pub fn run(Args { sturm, explain }: Args) -> anyhow::Result<()> {
    let extras = Extras { sturm, explain };
    let any_bad = answer_all(std::io::stdin().lock(), std::io::stdout().lock(), extras)?;
    if any_bad {
        let message = "some lines were not understood (see their error lines)";
        return Err(Error::Input(message.into()).into());
    }
    Ok(())
}

/// A line as read: the library's query, with its unknown keys refused.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    coeffs: Vec<f64>,
    interval: Option<[f64; 2]>,
    method: Option<String>,
    tolerance: Option<f64>,
}

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
fn answer(line: &str, extras: Extras) -> Result<Value, String> {
    let line: Line = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let q = Query {
        coeffs: line.coeffs,
        interval: line.interval,
        method: line.method,
        tolerance: line.tolerance,
    };
    let Answer {
        certificate,
        found_by,
    } = q.answer()?;
    let [a, b] = q.interval();
    let roots = certificate.values();
    let multiplicity: Vec<u32> = certificate.roots.iter().map(|r| r.multiplicity).collect();
    let bound: Vec<f64> = certificate.roots.iter().map(|r| r.bound).collect();
    let count = roots.len();
    let mut reply = json!({
        "roots": roots,
        "count": count,
        "multiplicity": multiplicity,
        "bound": bound,
    });
    if extras.explain {
        reply["certificate"] = explain(&certificate, &found_by);
    }
    if extras.sturm && q.coeffs.len() <= MAX_DEGREE + 1 {
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

/// The certificate as JSON: the argument, step by step.
fn explain(c: &Certificate, found_by: &str) -> Value {
    let roots: Vec<Value> = c
        .roots
        .iter()
        .map(|r| {
            json!({
                "value": r.value,
                "interval": r.interval,
                "interval_f64": r.interval_f64,
                "distinct_in_interval": r.distinct_in_interval,
                "multiplicity": r.multiplicity,
                "bound": r.bound,
            })
        })
        .collect();
    let factors: Vec<Value> = c
        .factors
        .iter()
        .map(|&(degree, multiplicity)| json!({"degree": degree, "multiplicity": multiplicity}))
        .collect();
    json!({
        "found_by": found_by,
        "degree": c.degree,
        "square_free_degree": c.square_free_degree,
        "square_free_factors": factors,
        "sturm_chain_members": c.chain_len,
        "count": {
            "interval": c.interval,
            "variations": c.variations,
            "distinct_roots": c.count,
        },
        "roots": roots,
    })
}

/// Answers every line of `input`; returns whether any line was bad.
fn answer_all(input: impl BufRead, mut output: impl Write, extras: Extras) -> Result<bool> {
    let mut any_bad = false;
    let write_error = |e: std::io::Error| Error::Input(format!("cannot write the answers: {e}"));
    for (index, line) in input.lines().enumerate() {
        let line =
            line.map_err(|e| Error::Input(format!("cannot read line {}: {e}", index + 1)))?;
        if line.trim().is_empty() {
            continue;
        }
        let reply = answer(&line, extras).unwrap_or_else(|message| {
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

    fn ask(lines: &str, extras: Extras) -> (Vec<Value>, bool) {
        let mut out = Vec::new();
        let bad = answer_all(lines.as_bytes(), &mut out, extras).unwrap();
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
        let (r, bad) = ask(input, Extras::default());
        assert!(bad);
        assert_eq!(r[0]["roots"], json!([-1.0, 1.0]));
        assert_eq!(r[0]["count"], 2);
        assert_eq!(r[0]["multiplicity"], json!([1, 1]));
        assert_eq!(r[1]["count"], 3);
        assert_eq!(r[2]["line"], 3);
        // (1 - t)^3: one distinct root, exactly 1, in (0, 2].
        assert_eq!(r[3]["roots"], json!([1.0]));
        assert_eq!(r[3]["count"], 1);
        assert_eq!(r[3]["multiplicity"], json!([3]));
        assert_eq!(
            r[3]["bound"],
            json!([0.0]),
            "the rational root 1 is found exactly"
        );
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
        assert!(!answer_all(input.as_bytes(), closed, Extras::default()).unwrap());
        // Any other failure to write is one.
        let full = Closed(std::io::ErrorKind::StorageFull);
        let err = answer_all(input.as_bytes(), full, Extras::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("cannot write the answers"), "{err}");
    }

    #[test]
    fn sturm_table_of_t4_minus_t2() {
        let sturm = Extras {
            sturm: true,
            explain: false,
        };
        let (r, _) = ask(
            r#"{"coeffs": [0, 0, -1, 0, 1], "interval": [-2, 2]}"#,
            sturm,
        );
        let s = &r[0]["sturm"];
        assert_eq!(
            (s["variations_a"].as_u64(), s["variations_b"].as_u64()),
            (Some(3), Some(0))
        );
        assert_eq!(r[0]["count"], 3);
        assert_eq!(s["signs_a"][0], 1);
    }

    #[test]
    fn degree_above_35_and_the_certificate() {
        // x^100 − 1: ±1; x^129 is refused.
        let mut c = vec![0.0; 101];
        c[0] = -1.0;
        c[100] = 1.0;
        let mut too_high = vec![0.0; 130];
        too_high[129] = 1.0;
        too_high[0] = -1.0;
        let line = |c: &[f64]| json!({ "coeffs": c }).to_string();
        let explain = Extras {
            sturm: true,
            explain: true,
        };
        let (r, bad) = ask(&format!("{}\n{}\n", line(&c), line(&too_high)), explain);
        assert!(bad);
        assert_eq!(r[0]["roots"], json!([-1.0, 1.0]));
        assert_eq!(r[0]["multiplicity"], json!([1, 1]));
        assert_eq!(r[0]["bound"], json!([0.0, 0.0]));
        assert!(r[0].get("sturm").is_none(), "no f64 table above degree 35");
        let cert = &r[0]["certificate"];
        assert_eq!(cert["found_by"], "exact (degree above 35: no f64 path)");
        assert_eq!(cert["count"]["distinct_roots"], 2);
        assert_eq!(cert["degree"], 100);
        assert!(r[1]["error"].as_str().unwrap().contains("degree <= 128"));
        // A double root within a window: its interval and multiplicity.
        let (r, _) = ask(r#"{"coeffs": [1, 2, 1], "interval": [-3, 0]}"#, explain);
        let root = &r[0]["certificate"]["roots"][0];
        assert_eq!(root["multiplicity"], 2);
        assert_eq!(
            r[0]["certificate"]["square_free_factors"][0]["multiplicity"],
            2
        );
        assert!(root["interval_f64"][0].as_f64().unwrap() <= -1.0);
        assert!(root["interval_f64"][1].as_f64().unwrap() >= -1.0);
    }
}
