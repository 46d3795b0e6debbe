//! The study's plot: time per ray against median root error, one curve per
//! finder through its tolerances, the Pareto front ringed. Error is on a
//! log axis (it spans 1e-2 to 1e-17); time on a linear one from 0, since
//! the finders differ by factors under 3 and ratios read best from 0.

use std::io::Write as _;
use std::path::Path;

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::io::output::write_atomic;
use crate::report::accuracy::Record;

/// Errors below this are drawn at it: a log axis has no zero, and a median
/// of exactly 0 (every root correctly rounded) is below any f64 tolerance.
const ERROR_FLOOR: f64 = 1e-17;

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Writes the plot of the pooled records ("all") as SVG (atomically).
pub fn write_svg(path: &Path, records: &[Record]) -> Result<()> {
    let mut svg = String::new();
    draw(
        SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area(),
        records,
    )
    .map_err(|e| Error::Internal(format!("plot {}: {e}", path.display())))?;
    write_atomic(path, |w| {
        w.write_all(svg.as_bytes()).map_err(|e| Error::io(path, e))
    })
}

/// The curves: each finder's (error, ns per ray) points, loosest tolerance first.
fn curves(records: &[Record]) -> Vec<(&'static str, Vec<(f64, f64)>)> {
    let mut out: Vec<(&'static str, Vec<(f64, f64)>)> = Vec::new();
    for r in records.iter().filter(|r| r.set == "all") {
        let point = (r.error_median.max(ERROR_FLOOR), r.ns_per_ray);
        match out.iter_mut().find(|(name, _)| *name == r.method) {
            Some((_, points)) => points.push(point),
            None => out.push((r.method, vec![point])),
        }
    }
    out
}

fn draw<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    records: &[Record],
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    area.fill(&WHITE)?;
    let curves = curves(records);
    let all = curves.iter().flat_map(|(_, p)| p.iter());
    let (mut x0, mut x1, mut y1) = (f64::MAX, f64::MIN, f64::MIN);
    for &(x, y) in all {
        (x0, x1, y1) = (x0.min(x), x1.max(x), y1.max(y));
    }
    if curves.is_empty() {
        (x0, x1, y1) = (ERROR_FLOOR, 1.0, 10.0);
    }
    let mut chart = ChartBuilder::on(&area)
        .caption(
            "sturmray accuracy: time against root error",
            ("sans-serif", 22),
        )
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d((x0 / 3.0..x1 * 3.0).log_scale(), 0.0..y1 * 1.1)?;
    chart
        .configure_mesh()
        .x_desc("median relative root error vs exact (0 drawn at 1e-17)")
        .y_desc("ns per ray (one thread)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0}"))
        .draw()?;
    for (i, (name, points)) in curves.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                colour.stroke_width(2),
            ))?
            .label(*name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
    }
    let front = records
        .iter()
        .filter(|r| r.set == "all" && r.pareto)
        .map(|r| (r.error_median.max(ERROR_FLOOR), r.ns_per_ray));
    chart
        .draw_series(front.map(|p| Circle::new(p, 8, BLACK.stroke_width(1))))?
        .label("Pareto front")
        .legend(|(x, y)| Circle::new((x + 10, y), 6, BLACK.stroke_width(1)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .draw()?;
    area.present()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(method: &'static str, error: f64, ns: f64, pareto: bool) -> Record {
        Record {
            set: "all".into(),
            method,
            tolerance: 1e-6,
            rays: 10,
            ns_per_ray: ns,
            error_median: error,
            error_max: error,
            missed: 0,
            false_hits: 0,
            image_rmse: None,
            image_coverage: None,
            pareto,
        }
    }

    #[test]
    fn writes_an_svg_with_every_curve_and_the_front() {
        let records = vec![
            record("sturm-bisect", 1e-3, 900.0, false),
            record("sturm-bisect", 1e-9, 1500.0, false),
            record("sturm-newton", 1e-3, 700.0, true),
            record("sturm-newton", 0.0, 800.0, true),
        ];
        let dir = std::env::temp_dir().join(format!("sturmray-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("accuracy.svg");
        write_svg(&path, &records).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
        for text in ["sturm-bisect", "sturm-newton", "Pareto front"] {
            assert!(svg.contains(text), "{text} missing");
        }
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(curves(&records).len(), 2);
        assert_eq!(curves(&records)[1].1[1].0, ERROR_FLOOR);
    }
}
