//! The percentile plot of latency histograms: one line per histogram, the
//! percentile on a log scale of 1/(1 - q) (so 90%, 99%, 99.9% are evenly
//! spaced), latency on a log scale, and horizontal reference lines (the
//! decision cycle's deadline, the iceoryx2 floor).

use plotters::prelude::*;

use super::Latency;
use learnpnp::experiment::plot::{FONT, PLOT_SIZE, colour};

/// A horizontal line at `micros` labelled `label`.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceLine {
    /// The legend text.
    pub label: String,
    /// Its height in microseconds.
    pub micros: f64,
}

/// Why a plot cannot be drawn.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {what}: {detail}")]
pub struct PlotFailure {
    /// Which plot.
    what: &'static str,
    /// The drawing library's error.
    detail: String,
}

impl PlotFailure {
    /// `what` cannot be drawn because of the drawing library's `error`.
    pub fn new(what: &'static str, error: impl std::fmt::Display) -> Self {
        PlotFailure {
            what,
            detail: error.to_string(),
        }
    }
}

/// The SVG text of the percentile plot of `histograms` with `references`.
pub fn percentile_plot(
    title: &str,
    histograms: &[&Latency],
    references: &[ReferenceLine],
) -> Result<String, PlotFailure> {
    let lines: Vec<(String, Vec<(f64, f64)>)> = histograms
        .iter()
        .filter(|h| h.count() > 0)
        .map(|h| {
            let points = h
                .distribution()
                .into_iter()
                .map(|(q, us)| (1.0 / (1.0 - q).max(1e-7), us.max(0.01)))
                .collect();
            (format!("{} (n = {})", h.name(), h.count()), points)
        })
        .collect();
    let ys = lines
        .iter()
        .flat_map(|(_, p)| p.iter().map(|&(_, y)| y))
        .chain(references.iter().map(|r| r.micros))
        .filter(|y| y.is_finite() && *y > 0.0);
    let (y_min, y_max) = ys.fold((f64::INFINITY, 0.0f64), |(lo, hi), y| (lo.min(y), hi.max(y)));
    let (y_min, y_max) = if y_min.is_finite() {
        (y_min / 2.0, y_max * 2.0)
    } else {
        (0.1, 1.0e6)
    };
    let x_max = lines
        .iter()
        .flat_map(|(_, p)| p.iter().map(|&(x, _)| x))
        .fold(100.0f64, f64::max)
        .min(1.0e7);

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, PLOT_SIZE).into_drawing_area();
        let draw = || -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
            root.fill(&WHITE)?;
            let mut chart = ChartBuilder::on(&root)
                .caption(title, (FONT, 20))
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(72)
                .build_cartesian_2d((1.0..x_max).log_scale(), (y_min..y_max).log_scale())?;
            chart
                .configure_mesh()
                .x_desc("percentile")
                .y_desc("latency (µs)")
                .x_label_formatter(&|x| percentile_label(*x))
                .y_label_formatter(&|y| format!("{y}"))
                .axis_desc_style((FONT, 16))
                .label_style((FONT, 13))
                .bold_line_style(BLACK.mix(0.12))
                .light_line_style(BLACK.mix(0.04))
                .draw()?;
            for (i, (label, points)) in lines.iter().enumerate() {
                let style = colour(i).stroke_width(2);
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), style))?
                    .label(label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
            }
            for (j, r) in references.iter().enumerate() {
                let style = colour(lines.len() + j).stroke_width(1);
                chart
                    .draw_series(DashedLineSeries::new([(1.0, r.micros), (x_max, r.micros)], 8, 5, style))?
                    .label(r.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .margin(12)
                .label_font((FONT, 13))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.4))
                .draw()?;
            root.present()
        };
        draw().map_err(|e| PlotFailure::new("the latency plot", e))?;
    }
    Ok(svg)
}

/// `x = 1/(1 - q)` as a percentile: 1 is 0%, 10 is 90%, 1000 is 99.9%.
fn percentile_label(x: f64) -> String {
    let q = 100.0 * (1.0 - 1.0 / x);
    let decimals = (x.log10().round() as i32 - 2).max(0) as usize;
    format!("{q:.decimals$}%")
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn labels_read_as_percentiles() {
        assert_eq!(percentile_label(1.0), "0%");
        assert_eq!(percentile_label(10.0), "90%");
        assert_eq!(percentile_label(100.0), "99%");
        assert_eq!(percentile_label(1000.0), "99.9%");
        assert_eq!(percentile_label(10000.0), "99.99%");
    }

    #[test]
    fn plot_has_a_line_per_histogram_and_reference() {
        let mut a = Latency::new("round trip");
        let mut b = Latency::new("floor");
        for i in 1..2000u64 {
            a.record(Duration::from_micros(10 + i % 37));
            b.record(Duration::from_micros(3 + i % 5));
        }
        let svg = percentile_plot(
            "latency",
            &[&a, &b],
            &[ReferenceLine {
                label: "deadline 100 ms".into(),
                micros: 100_000.0,
            }],
        )
        .unwrap();
        assert!(svg.contains("round trip (n = 1999)"));
        assert!(svg.contains("floor (n = 1999)"));
        assert!(svg.contains("deadline 100 ms"));
    }
}
