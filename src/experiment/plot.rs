//! SVG plots of experiment results: learning curves with confidence bands, and
//! per-episode scatter plots of values.
//!
//! Plots are drawn with plotters into a string and written atomically
//! (temporary file, then rename), so a reader never sees half a plot.

use std::io;
use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::atomic_file::write_atomic;

/// Width and height of every plot, in pixels.
pub const PLOT_SIZE: (u32, u32) = (900, 560);

/// One point of a learning curve: the mean over runs and its confidence interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Horizontal position (usually the episode).
    pub x: f64,
    /// The mean.
    pub mean: f64,
    /// Lower end of the confidence interval.
    pub low: f64,
    /// Upper end of the confidence interval.
    pub high: f64,
}

/// A labelled learning curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The legend text.
    pub label: String,
    /// The points, drawn in the given order (normally increasing `x`).
    pub points: Vec<CurvePoint>,
}

/// What is wrong with one line of a curve CSV file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CsvProblem {
    /// The file has no header line.
    #[error("the file is empty (expected the header episode,mean,ci_low,ci_high,runs)")]
    Empty,
    /// The header lacks a column the curve needs.
    #[error("the header has no '{column}' column")]
    MissingColumn {
        /// The column's name.
        column: &'static str,
    },
    /// A row is shorter than the header says.
    #[error("no '{column}' field (the row has {fields} field(s))")]
    MissingField {
        /// The column's name.
        column: &'static str,
        /// Fields in the row.
        fields: usize,
    },
    /// A field is not a number.
    #[error("'{text}' in column '{column}' is not a number")]
    NotANumber {
        /// The column's name.
        column: &'static str,
        /// The field's text.
        text: String,
    },
}

/// A plot that cannot be drawn or a curve file that cannot be read; the
/// message starts with the file's path.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Reading or writing the file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// No series were given.
    #[error("{path}: nothing to plot (no series given)")]
    NoSeries {
        /// The plot file.
        path: PathBuf,
    },
    /// Series were given but none has a point with finite coordinates.
    #[error("{path}: nothing to plot (no series has a point with finite coordinates)")]
    NoFinitePoints {
        /// The plot file.
        path: PathBuf,
    },
    /// Plotters failed to draw.
    #[error("{path}: cannot draw the plot: {source}")]
    Draw {
        /// The plot file.
        path: PathBuf,
        /// The drawing error.
        source: DrawingAreaErrorKind<io::Error>,
    },
    /// A line of a curve file is malformed.
    #[error("{path}, line {line}: {source}")]
    Csv {
        /// The curve file.
        path: PathBuf,
        /// The line (1-based; the header is line 1).
        line: usize,
        /// What is wrong.
        source: CsvProblem,
    },
}

/// Result of plotters' drawing calls on the SVG backend.
type DrawResult = Result<(), DrawingAreaErrorKind<io::Error>>;

/// Distinguishable colours (Tableau 10), cycled over the series.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The colour of the `i`-th series.
pub(crate) fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Font family of every text.
pub(crate) const FONT: &str = "sans-serif";

/// Draws learning curves into an SVG file at `path`: one coloured line per
/// series (its mean), a translucent band of the same colour for its
/// confidence interval, a legend and labelled axes.
///
/// The x range spans the data; the y range spans every finite mean and
/// interval end with a 5% margin. Points with a non-finite `x` or `mean` are
/// skipped and break the line; points with a non-finite `low` or `high` break
/// the band. Fails with [`PlotError::NoSeries`] or [`PlotError::NoFinitePoints`]
/// when there is nothing to draw.
pub fn plot_curves(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<(), PlotError> {
    if series.is_empty() {
        return Err(PlotError::NoSeries {
            path: path.to_path_buf(),
        });
    }
    let drawn = |p: &CurvePoint| p.x.is_finite() && p.mean.is_finite();
    let banded = |p: &CurvePoint| drawn(p) && p.low.is_finite() && p.high.is_finite();
    let xy: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| &s.points)
        .filter(|p| drawn(p))
        .flat_map(|p| [(p.x, p.mean), (p.x, p.low), (p.x, p.high)])
        .filter(|(_, y)| y.is_finite())
        .collect();
    let Some(frame) = Frame::of(&xy, 0.0, 0.05) else {
        return Err(PlotError::NoFinitePoints {
            path: path.to_path_buf(),
        });
    };
    write_svg(path, |root| {
        let mut chart = frame.chart(root, title, x_label, y_label)?;
        for (i, s) in series.iter().enumerate() {
            let band = colour(i).mix(0.2).filled();
            chart.draw_series(s.points.split(|p| !banded(p)).filter(|run| run.len() > 1).map(|run| {
                let upper = run.iter().map(|p| (p.x, p.high));
                let lower = run.iter().rev().map(|p| (p.x, p.low));
                Polygon::new(upper.chain(lower).collect::<Vec<_>>(), band)
            }))?;
        }
        for (i, s) in series.iter().enumerate() {
            let line = colour(i).stroke_width(2);
            let runs: Vec<&[CurvePoint]> = s.points.split(|p| !drawn(p)).collect();
            chart.draw_series(
                runs.iter()
                    .filter(|run| run.len() == 1)
                    .flat_map(|run| run.iter())
                    .map(|p| Circle::new((p.x, p.mean), 2, line.filled())),
            )?;
            chart
                .draw_series(
                    runs.iter()
                        .filter(|run| run.len() > 1)
                        .map(|run| PathElement::new(run.iter().map(|p| (p.x, p.mean)).collect::<Vec<_>>(), line)),
                )?
                .label(s.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], line));
        }
        frame.legend(&mut chart)
    })
}

/// Draws points into an SVG file at `path`: one colour per `(label, points)`
/// series, small dots (e.g. one per episode: the values of the actions in the
/// initial observation, as in the thesis's Figures 6.5 to 6.10), a legend and
/// labelled axes. Points with a non-finite coordinate are skipped; both
/// ranges span the data with a small margin. Fails with
/// [`PlotError::NoSeries`] or [`PlotError::NoFinitePoints`] when there is
/// nothing to draw.
pub fn plot_scatter(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    if series.is_empty() {
        return Err(PlotError::NoSeries {
            path: path.to_path_buf(),
        });
    }
    let finite = |(x, y): &(f64, f64)| x.is_finite() && y.is_finite();
    let xy: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|(_, points)| points.iter().copied())
        .filter(finite)
        .collect();
    let Some(frame) = Frame::of(&xy, 0.02, 0.05) else {
        return Err(PlotError::NoFinitePoints {
            path: path.to_path_buf(),
        });
    };
    write_svg(path, |root| {
        let mut chart = frame.chart(root, title, x_label, y_label)?;
        for (i, (label, points)) in series.iter().enumerate() {
            let dot = colour(i).mix(0.75).filled();
            chart
                .draw_series(points.iter().copied().filter(finite).map(|p| Circle::new(p, 2, dot)))?
                .label(label.as_str())
                .legend(move |(x, y)| Circle::new((x + 12, y), 4, colour(i).filled()));
        }
        frame.legend(&mut chart)
    })
}

/// The ranges of a plot and where its legend goes.
struct Frame {
    /// Horizontal range.
    x: Range<f64>,
    /// Vertical range.
    y: Range<f64>,
    /// The corner with the fewest data points.
    legend: SeriesLabelPosition,
}

/// A chart drawn on an SVG string.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

impl Frame {
    /// The frame of finite points `xy`, with margins as fractions of each span;
    /// `None` when there are no points.
    fn of(xy: &[(f64, f64)], x_margin: f64, y_margin: f64) -> Option<Frame> {
        let (first, rest) = xy.split_first()?;
        let (mut x0, mut x1, mut y0, mut y1) = (first.0, first.0, first.1, first.1);
        for &(x, y) in rest {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        let x = padded(x0, x1, x_margin);
        let y = padded(y0, y1, y_margin);
        let legend = legend_corner(xy, &x, &y);
        Some(Frame { x, y, legend })
    }

    /// A titled chart with labelled axes and a light grid.
    fn chart<'a, 'b>(
        &self,
        root: &'a DrawingArea<SVGBackend<'b>, Shift>,
        title: &str,
        x_label: &str,
        y_label: &str,
    ) -> Result<Chart<'a, 'b>, DrawingAreaErrorKind<io::Error>> {
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, 22))
            .margin(18)
            .x_label_area_size(52)
            .y_label_area_size(76)
            .build_cartesian_2d(self.x.clone(), self.y.clone())?;
        let (x_decimals, y_decimals) = (decimals(&self.x), decimals(&self.y));
        let x_tick = move |v: &f64| tick(*v, x_decimals);
        let y_tick = move |v: &f64| tick(*v, y_decimals);
        chart
            .configure_mesh()
            .x_labels(TICKS)
            .y_labels(TICKS)
            .x_label_formatter(&x_tick)
            .y_label_formatter(&y_tick)
            .x_desc(x_label)
            .y_desc(y_label)
            .axis_desc_style((FONT, 16))
            .label_style((FONT, 13))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(BLACK.mix(0.04))
            .draw()?;
        Ok(chart)
    }

    /// Draws the legend of the labelled series.
    fn legend<'a, 'b: 'a>(&self, chart: &mut Chart<'a, 'b>) -> DrawResult {
        chart
            .configure_series_labels()
            .position(self.legend.clone())
            .margin(12)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()
    }
}

/// Most tick labels on an axis.
const TICKS: usize = 10;

/// Decimals that show every tick of `range` exactly: ticks are multiples of
/// 1, 2 or 5 times a power of ten no smaller than a tenth of the span.
fn decimals(range: &Range<f64>) -> usize {
    let step = (range.end - range.start) / TICKS as f64;
    let magnitude = step.log10().floor();
    if magnitude.is_finite() && magnitude < 0.0 {
        // At most 17 digits matter in an f64.
        (-magnitude).min(17.0) as usize
    } else {
        0
    }
}

/// A tick label with `decimals` decimals, never `-0`.
fn tick(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => text,
    }
}

/// `min..max` widened by `margin` times the span on both sides; an empty span
/// is widened to a visible one around its value.
fn padded(min: f64, max: f64, margin: f64) -> Range<f64> {
    let span = max - min;
    if span > 0.0 && span.is_finite() {
        let pad = span * margin;
        min - pad..max + pad
    } else {
        let pad = (min.abs() * 0.1).max(0.5);
        min - pad..max + pad
    }
}

/// The corner of the plot holding the fewest points (upper right on ties),
/// where the legend hides the least data.
fn legend_corner(xy: &[(f64, f64)], x: &Range<f64>, y: &Range<f64>) -> SeriesLabelPosition {
    let width = x.end - x.start;
    let height = y.end - y.start;
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let inside = |&(px, py): &(f64, f64), right: bool, upper: bool| {
        let u = (px - x.start) / width;
        let v = (py - y.start) / height;
        let in_x = if right { u > 0.6 } else { u < 0.4 };
        let in_y = if upper { v > 0.65 } else { v < 0.35 };
        in_x && in_y
    };
    corners
        .into_iter()
        .map(|(pos, right, upper)| {
            let count = xy.iter().filter(|p| inside(p, right, upper)).count();
            (count, pos)
        })
        .min_by_key(|(count, _)| *count)
        .map_or(SeriesLabelPosition::UpperRight, |(_, pos)| pos)
}

/// Renders a plot into a string with `draw`, then writes it to `path` atomically.
fn write_svg(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult,
) -> Result<(), PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, PLOT_SIZE).into_drawing_area();
        root.fill(&WHITE)
            .and_then(|()| draw(&root))
            .and_then(|()| root.present())
            .map_err(|source| PlotError::Draw {
                path: path.to_path_buf(),
                source,
            })?;
    }
    write_atomic(path, svg.as_bytes()).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a learning curve from a CSV file with the header
/// `episode,mean,ci_low,ci_high,runs` (as the experiment command writes it).
///
/// Columns are found by name in the header, so their order does not matter and
/// other columns (including `runs`) are ignored; `episode` becomes
/// [`CurvePoint::x`], `ci_low`/`ci_high` its `low`/`high`. Blank lines are
/// skipped; fields may be `NaN` or `inf`. Errors name the file and the line.
pub fn read_curve_csv(path: &Path) -> Result<Vec<CurvePoint>, PlotError> {
    const COLUMNS: [&str; 4] = ["episode", "mean", "ci_low", "ci_high"];
    let text = std::fs::read_to_string(path).map_err(|source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let problem = |line: usize, source: CsvProblem| PlotError::Csv {
        path: path.to_path_buf(),
        line,
        source,
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let Some((_, header)) = lines.next() else {
        return Err(problem(1, CsvProblem::Empty));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [0; 4];
    for (slot, column) in index.iter_mut().zip(COLUMNS) {
        *slot = names
            .iter()
            .position(|n| *n == column)
            .ok_or_else(|| problem(1, CsvProblem::MissingColumn { column }))?;
    }
    let mut points = Vec::new();
    for (line, row) in lines {
        if row.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        let mut values = [0.0; 4];
        for ((value, &at), column) in values.iter_mut().zip(&index).zip(COLUMNS) {
            let text = fields.get(at).ok_or_else(|| {
                problem(
                    line,
                    CsvProblem::MissingField {
                        column,
                        fields: fields.len(),
                    },
                )
            })?;
            *value = text.parse().map_err(|_| {
                problem(
                    line,
                    CsvProblem::NotANumber {
                        column,
                        text: text.to_string(),
                    },
                )
            })?;
        }
        let [x, mean, low, high] = values;
        points.push(CurvePoint { x, mean, low, high });
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_show_the_step_and_no_negative_zero() {
        assert_eq!(decimals(&(0.0..490.0)), 0);
        assert_eq!(decimals(&(-13.0..-1.0)), 0);
        assert_eq!(decimals(&(-1.2..4.2)), 1);
        assert_eq!(decimals(&(0.0..0.05)), 3);
        assert_eq!(tick(50.0, 0), "50");
        assert_eq!(tick(0.5, 1), "0.5");
        assert_eq!(tick(-1e-17, 1), "0.0");
        assert_eq!(tick(-0.0, 0), "0");
        assert_eq!(tick(-2.0, 0), "-2");
    }

    #[test]
    fn the_legend_goes_where_the_data_is_not() {
        let rising: Vec<(f64, f64)> = (0..100).map(|i| (f64::from(i), f64::from(i))).collect();
        let frame = Frame::of(&rising, 0.0, 0.05).expect("points");
        assert!(matches!(frame.legend, SeriesLabelPosition::LowerRight));
        let falling: Vec<(f64, f64)> = rising.iter().map(|&(x, y)| (x, -y)).collect();
        let frame = Frame::of(&falling, 0.0, 0.05).expect("points");
        assert!(matches!(frame.legend, SeriesLabelPosition::UpperRight));
        assert!(Frame::of(&[], 0.0, 0.0).is_none());
    }

    #[test]
    fn a_single_value_gets_a_visible_range() {
        assert_eq!(padded(3.0, 3.0, 0.05), 2.5..3.5);
        assert_eq!(padded(-100.0, -100.0, 0.05), -110.0..-90.0);
        assert_eq!(padded(0.0, 10.0, 0.05), -0.5..10.5);
    }
}
