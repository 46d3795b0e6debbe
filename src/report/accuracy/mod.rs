//! `sturmray accuracy`: what accuracy costs in time. Every root finder at
//! every tolerance on the same polynomials, in the same run: time per ray,
//! root error and missed and false hits against the exact rational
//! reference ([`crate::poly::exact`]), and the image error of a small render
//! against a reference render.
//!
//! Times are ratios within one run: each pass is repeated, interleaved with
//! the other finders' passes, and the best pass counts, so a noisy moment
//! of the machine hurts every finder alike.

pub mod cases;
pub mod certified;
pub mod measure;
pub mod plot;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::error::Result;
use crate::io::output::write_atomic;
use crate::poly::solve::{Method, Solver};
use cases::CaseSet;
use measure::{Errors, Finder, ImageError};

/// The tolerances studied, loosest first.
pub const TOLERANCES: [f64; 7] = [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14];

/// The reference render's root finder: bisection proves a bracket at every
/// step, and 1e-15 is below f64 resolution for |t| ≥ 1, so its roots are
/// the f64 polynomial's to adjacent floats. (Renders cannot use the exact
/// path; the root errors and hit counts are against the exact one.)
pub const REFERENCE: Solver = Solver {
    method: Method::SturmBisect,
    tolerance: 1e-15,
    max_iterations: 200,
};

/// What to measure.
pub struct Study {
    pub sets: Vec<CaseSet>,
    pub finders: Vec<Finder>,
    pub tolerances: Vec<f64>,
    /// Timed passes per configuration; the fastest counts.
    pub reps: usize,
}

impl Study {
    /// Every scene of [`cases::SCENES`] and the synthetic sets, every
    /// finder at every tolerance. `quick` takes fewer rays and passes: a
    /// run under a minute in a release build.
    pub fn standard(root: &Path, quick: bool) -> Result<Study> {
        let (width, synthetic, reps) = if quick { (32, 200, 2) } else { (96, 1000, 5) };
        Ok(Study {
            sets: cases::all_cases(root, width, synthetic)?,
            finders: Finder::ALL.to_vec(),
            tolerances: TOLERANCES.to_vec(),
            reps,
        })
    }
}

/// One finder at one tolerance on one set, or on all sets pooled (`set` =
/// "all").
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    pub set: String,
    pub method: &'static str,
    pub tolerance: f64,
    /// Polynomials solved (rays that entered a shape's box).
    pub rays: usize,
    pub ns_per_ray: f64,
    /// Relative root error |t − t_exact| / max(1, |t_exact|) over the rays
    /// both hit.
    pub error_median: f64,
    pub error_max: f64,
    pub missed: usize,
    pub false_hits: usize,
    /// Beauty RMSE against the reference render (scenes only, and not for
    /// the warm start, which the renderer does not use); for "all", the
    /// mean over the scenes.
    pub image_rmse: Option<f64>,
    /// Pixels covered in one render and not the other (summed for "all").
    pub image_coverage: Option<usize>,
    /// On the Pareto front of time against median error ("all" only).
    pub pareto: bool,
}

/// What one configuration gave on one set.
struct Outcome {
    seconds: f64,
    rays: usize,
    errors: Errors,
    image: Option<ImageError>,
}

/// Runs the study; progress goes to stderr. Returns the per-set records
/// followed by the pooled ones.
pub fn run(study: &Study) -> Result<Vec<Record>> {
    let configs: Vec<(Finder, f64)> = study
        .finders
        .iter()
        .flat_map(|&f| study.tolerances.iter().map(move |&t| (f, t)))
        .collect();
    let mut outcomes: BTreeMap<(usize, usize), Outcome> = BTreeMap::new();
    for (s, set) in study.sets.iter().enumerate() {
        crate::io::console::note(format_args!(
            "accuracy: {} ({} rays): exact reference",
            set.name,
            set.cases.len()
        ));
        let reference = measure::reference(&set.cases);
        let reference_image = match &set.scene {
            Some(scene) => Some(measure::render_with(scene, REFERENCE)?),
            None => None,
        };
        for (c, &(finder, tolerance)) in configs.iter().enumerate() {
            let found = finder.solve(tolerance, &set.cases);
            let image = match (&set.scene, &reference_image, finder) {
                (Some(scene), Some(reference), Finder::Cold(_)) => {
                    let solver = finder.solver(tolerance);
                    Some(measure::render_with(scene, solver)?.error_from(reference))
                }
                _ => None,
            };
            outcomes.insert(
                (s, c),
                Outcome {
                    seconds: f64::INFINITY,
                    rays: set.cases.len(),
                    errors: Errors::compare(&found, &reference),
                    image,
                },
            );
        }
    }
    crate::io::console::note(format_args!(
        "accuracy: timing {} passes of each",
        study.reps
    ));
    for _ in 0..study.reps {
        for (s, set) in study.sets.iter().enumerate() {
            for (c, &(finder, tolerance)) in configs.iter().enumerate() {
                let seconds = measure::time(finder, tolerance, &set.cases);
                let o = outcomes.get_mut(&(s, c)).expect("every outcome was made");
                o.seconds = o.seconds.min(seconds);
            }
        }
    }
    let mut records = Vec::new();
    for ((s, c), o) in &outcomes {
        records.push(record(&study.sets[*s].name, configs[*c], o));
    }
    for (c, &config) in configs.iter().enumerate() {
        let mut pooled = Outcome {
            seconds: 0.0,
            rays: 0,
            errors: Errors::default(),
            image: None,
        };
        let mut images = Vec::new();
        for s in 0..study.sets.len() {
            let o = &outcomes[&(s, c)];
            pooled.seconds += o.seconds;
            pooled.rays += o.rays;
            pooled.errors.extend(&o.errors);
            images.extend(o.image);
        }
        if !images.is_empty() {
            pooled.image = Some(ImageError {
                rmse: images.iter().map(|i| i.rmse).sum::<f64>() / images.len() as f64,
                coverage: images.iter().map(|i| i.coverage).sum(),
            });
        }
        records.push(record("all", config, &pooled));
    }
    mark_pareto(&mut records);
    Ok(records)
}

fn record(set: &str, (finder, tolerance): (Finder, f64), o: &Outcome) -> Record {
    Record {
        set: set.to_string(),
        method: finder.name(),
        tolerance,
        rays: o.rays,
        ns_per_ray: 1e9 * o.seconds / o.rays.max(1) as f64,
        error_median: o.errors.quantile(0.5),
        error_max: o.errors.quantile(1.0),
        missed: o.errors.missed,
        false_hits: o.errors.false_hits,
        image_rmse: o.image.map(|i| i.rmse),
        image_coverage: o.image.map(|i| i.coverage),
        pareto: false,
    }
}

/// Marks the pooled records no other pooled record beats in both time and
/// median error (and strictly in one).
fn mark_pareto(records: &mut [Record]) {
    let points: Vec<(f64, f64)> = records
        .iter()
        .filter(|r| r.set == "all")
        .map(|r| (r.ns_per_ray, r.error_median))
        .collect();
    for r in records.iter_mut().filter(|r| r.set == "all") {
        let (time, error) = (r.ns_per_ray, r.error_median);
        r.pareto = !points
            .iter()
            .any(|&(t, e)| t <= time && e <= error && (t < time || e < error));
    }
}

/// Whether a record is the renderer's default root finder.
pub fn is_default(r: &Record) -> bool {
    let d = Solver::default();
    r.method == d.method.name() && r.tolerance == d.tolerance
}

/// The pooled table (one row per finder and tolerance, times also as a
/// ratio to the default's), then every set's misses for the default.
pub fn table(records: &[Record]) -> String {
    let default_ns = records
        .iter()
        .find(|r| r.set == "all" && is_default(r))
        .map(|r| r.ns_per_ray);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<15} {:>7} {:>9} {:>7} {:>9} {:>9} {:>7} {:>6} {:>9} {:>6}  ",
        "method",
        "tol",
        "ns/ray",
        "×dflt",
        "err p50",
        "err max",
        "missed",
        "false",
        "img rmse",
        "img px"
    );
    for r in records.iter().filter(|r| r.set == "all") {
        let ratio = default_ns.map_or(String::from("-"), |d| format!("{:.2}", r.ns_per_ray / d));
        let _ = writeln!(
            out,
            "{:<15} {:>7.0e} {:>9.0} {:>7} {:>9.1e} {:>9.1e} {:>7} {:>6} {:>9} {:>6}{}{}",
            r.method,
            r.tolerance,
            r.ns_per_ray,
            ratio,
            r.error_median,
            r.error_max,
            r.missed,
            r.false_hits,
            r.image_rmse.map_or("-".into(), |e| format!("{e:.1e}")),
            r.image_coverage.map_or("-".into(), |c| c.to_string()),
            if r.pareto { "  pareto" } else { "" },
            if is_default(r) { "  (default)" } else { "" },
        );
    }
    let d = Solver::default();
    let _ = writeln!(
        out,
        "\ndefault ({} at {:.0e}) per set, against the exact reference:",
        d.method.name(),
        d.tolerance
    );
    let _ = writeln!(
        out,
        "{:<28} {:>6} {:>7} {:>6} {:>9} {:>9}",
        "set", "rays", "missed", "false", "err p50", "err max"
    );
    for r in records.iter().filter(|r| r.set != "all" && is_default(r)) {
        let _ = writeln!(
            out,
            "{:<28} {:>6} {:>7} {:>6} {:>9.1e} {:>9.1e}",
            r.set, r.rays, r.missed, r.false_hits, r.error_median, r.error_max
        );
    }
    out
}

/// The `accuracy` command's study, run from the current folder (it reads
/// [`scene_files`]).
pub fn command(quick: bool) -> Result<Vec<Record>> {
    run(&Study::standard(Path::new("."), quick)?)
}

/// The scene files the standard study reads, from `root`.
pub fn scene_files(root: &Path) -> Vec<std::path::PathBuf> {
    cases::SCENES.iter().map(|s| root.join(s)).collect()
}

/// Writes the records as JSON (atomically).
pub fn write_json(path: &Path, records: &[Record]) -> Result<()> {
    let text = serde_json::to_string_pretty(records)
        .map_err(|e| crate::error::Error::Internal(format!("records to JSON: {e}")))?;
    write_atomic(path, |w| {
        writeln!(w, "{text}").map_err(|e| crate::error::Error::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pooled(method: &'static str, ns: f64, error: f64) -> Record {
        Record {
            set: "all".into(),
            method,
            tolerance: 1e-12,
            rays: 1,
            ns_per_ray: ns,
            error_median: error,
            error_max: error,
            missed: 0,
            false_hits: 0,
            image_rmse: None,
            image_coverage: None,
            pareto: false,
        }
    }

    #[test]
    fn pareto_front_keeps_the_undominated_points() {
        let mut records = vec![
            pooled("a", 100.0, 1e-6),
            pooled("b", 200.0, 1e-12),
            pooled("c", 150.0, 1e-6),  // slower than a, no more accurate
            pooled("d", 300.0, 1e-12), // slower than b, as accurate
            pooled("e", 50.0, 1e-2),
        ];
        let mut per_set = pooled("a", 1.0, 0.0);
        per_set.set = "scene:x".into();
        records.push(per_set);
        mark_pareto(&mut records);
        let front: Vec<bool> = records.iter().map(|r| r.pareto).collect();
        assert_eq!(front, [true, true, false, false, true, false]);
    }

    #[test]
    fn table_marks_the_default_and_lists_its_sets() {
        let mut default = pooled("sturm-newton", 100.0, 1e-15);
        default.tolerance = Solver::default().tolerance;
        let mut per_set = default.clone();
        per_set.set = "scene:thin".into();
        per_set.missed = 3;
        let text = table(&[pooled("sturm-bisect", 150.0, 1e-15), default, per_set]);
        assert!(text.contains("(default)"), "{text}");
        assert!(text.contains("1.50"), "ratio to the default: {text}");
        let line = text.lines().find(|l| l.starts_with("scene:thin")).unwrap();
        assert_eq!(line.split_whitespace().nth(2), Some("3"), "{line}");
    }
}
