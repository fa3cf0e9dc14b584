//! SVG plots of experiment results: learning curves with confidence bands and
//! reference lines, per-episode scatter plots of values, and bar charts of
//! fixed policies with confidence intervals.
//!
//! Every plot has its title above the chart, wrapped to fit the width, and
//! its legend below the chart, where it covers no data. Plots are drawn with
//! plotters into a string and written atomically (temporary file, then
//! rename), so a reader never sees half a plot.

use std::io;
use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use atomic_file::write_atomic;

/// Width of every plot, and its height with a one-line title and one row of
/// legend (longer titles and legends add rows), in pixels.
pub const PLOT_SIZE: (u32, u32) = (900, 560);

/// Title font size and the height of one title line.
const TITLE_SIZE: u32 = 20;
const TITLE_LINE: u32 = 26;
/// Legend font size and the height of one legend row.
const LEGEND_SIZE: u32 = 14;
const LEGEND_ROW: u32 = 24;
/// Space above the title and below the legend.
const PAD: u32 = 10;
/// Horizontal margin of title and legend.
const SIDE: u32 = 18;

/// A horizontal line at a known value (an optimum, a published result).
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// The legend text.
    pub label: String,
    /// Its height on the vertical axis.
    pub value: f64,
}

/// One bar of a bar chart: a mean and its confidence interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Bar {
    /// The label under the bar.
    pub label: String,
    /// The bar's height.
    pub mean: f64,
    /// Lower end of the interval (NaN: none drawn).
    pub low: f64,
    /// Upper end of the interval.
    pub high: f64,
}

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
pub fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Font family of every text.
pub const FONT: &str = "sans-serif";

/// Draws learning curves into an SVG file at `path`: one coloured line per
/// series (its mean), a translucent band of the same colour for its
/// confidence interval (none where an interval has no width, as for a single
/// run), a dashed grey line per reference, the title above and the legend
/// below the chart.
///
/// The x range spans the data; the y range spans every finite mean, interval
/// end and reference with a 5% margin. Points with a non-finite `x` or `mean`
/// are skipped and break the line; points with a non-finite `low` or `high`
/// break the band. Fails with [`PlotError::NoSeries`] or
/// [`PlotError::NoFinitePoints`] when there is nothing to draw.
pub fn plot_curves(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    references: &[Reference],
) -> Result<(), PlotError> {
    if series.is_empty() {
        return Err(PlotError::NoSeries {
            path: path.to_path_buf(),
        });
    }
    let drawn = |p: &CurvePoint| p.x.is_finite() && p.mean.is_finite();
    let banded = |p: &CurvePoint| drawn(p) && p.low.is_finite() && p.high.is_finite();
    let mut xy: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| &s.points)
        .filter(|p| drawn(p))
        .flat_map(|p| [(p.x, p.mean), (p.x, p.low), (p.x, p.high)])
        .filter(|(_, y)| y.is_finite())
        .collect();
    let Some(&(x0, _)) = xy.first() else {
        return Err(PlotError::NoFinitePoints {
            path: path.to_path_buf(),
        });
    };
    xy.extend(references.iter().filter(|r| r.value.is_finite()).map(|r| (x0, r.value)));
    let Some(frame) = Frame::of(&xy, 0.0, 0.05) else {
        return Err(PlotError::NoFinitePoints {
            path: path.to_path_buf(),
        });
    };
    let mut legend: Vec<(String, Swatch)> = series
        .iter()
        .enumerate()
        .map(|(i, s)| (s.label.clone(), Swatch::Line(colour(i))))
        .collect();
    legend.extend(
        references
            .iter()
            .filter(|r| r.value.is_finite())
            .map(|r| (r.label.clone(), Swatch::Dashed(REFERENCE))),
    );
    write_svg(path, title, &legend, |area| {
        let mut chart = frame.chart(area, x_label, y_label)?;
        for (i, s) in series.iter().enumerate() {
            let band = colour(i).mix(0.2).filled();
            chart.draw_series(
                s.points
                    .split(|p| !banded(p))
                    .filter(|run| run.len() > 1 && run.iter().any(|p| p.high > p.low))
                    .map(|run| {
                        let upper = run.iter().map(|p| (p.x, p.high));
                        let lower = run.iter().rev().map(|p| (p.x, p.low));
                        Polygon::new(upper.chain(lower).collect::<Vec<_>>(), band)
                    }),
            )?;
        }
        for r in references.iter().filter(|r| r.value.is_finite()) {
            chart.draw_series(DashedLineSeries::new(
                [(frame.x.start, r.value), (frame.x.end, r.value)],
                8,
                6,
                REFERENCE.stroke_width(2),
            ))?;
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
            chart.draw_series(
                runs.iter()
                    .filter(|run| run.len() > 1)
                    .map(|run| PathElement::new(run.iter().map(|p| (p.x, p.mean)).collect::<Vec<_>>(), line)),
            )?;
        }
        Ok(())
    })
}

/// Draws points into an SVG file at `path`: one colour per `(label, points)`
/// series, small dots (e.g. one per episode: the values of the actions in the
/// initial observation, as in the thesis's Figures 6.5 to 6.10), the title
/// above and the legend below the chart. Points with a non-finite coordinate
/// are skipped; both ranges span the data with a small margin. Fails with
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
    let legend: Vec<(String, Swatch)> = series
        .iter()
        .enumerate()
        .map(|(i, (label, _))| (label.clone(), Swatch::Dot(colour(i))))
        .collect();
    write_svg(path, title, &legend, |area| {
        let mut chart = frame.chart(area, x_label, y_label)?;
        for (i, (_, points)) in series.iter().enumerate() {
            let dot = colour(i).mix(0.75).filled();
            chart.draw_series(points.iter().copied().filter(finite).map(|p| Circle::new(p, 2, dot)))?;
        }
        Ok(())
    })
}

/// Draws a bar chart into an SVG file at `path`: one bar per entry with its
/// confidence interval as an error bar, its value written above it, the title
/// above and the bars' labels along the horizontal axis. The vertical axis
/// starts at zero (or below, for negative values). Fails with
/// [`PlotError::NoSeries`] when there is no bar and
/// [`PlotError::NoFinitePoints`] when no mean is finite.
pub fn plot_bars(path: &Path, title: &str, y_label: &str, unit: &str, bars: &[Bar]) -> Result<(), PlotError> {
    if bars.is_empty() {
        return Err(PlotError::NoSeries {
            path: path.to_path_buf(),
        });
    }
    let mut ys: Vec<f64> = vec![0.0];
    ys.extend(
        bars.iter()
            .flat_map(|b| [b.mean, b.low, b.high])
            .filter(|v| v.is_finite()),
    );
    if !bars.iter().any(|b| b.mean.is_finite()) {
        return Err(PlotError::NoFinitePoints {
            path: path.to_path_buf(),
        });
    }
    let low = ys.iter().copied().fold(f64::INFINITY, f64::min);
    let high = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = (high - low).max(1e-9);
    let frame = Frame {
        x: -0.5..bars.len() as f64 - 0.5,
        y: (if low < 0.0 { low - 0.05 * span } else { 0.0 })..high + 0.12 * span,
    };
    let names: Vec<String> = bars.iter().map(|b| b.label.clone()).collect();
    write_svg(path, title, &[], |area| {
        let mut chart = ChartBuilder::on(area)
            .margin(SIDE)
            .x_label_area_size(40)
            .y_label_area_size(76)
            .build_cartesian_2d(frame.x.clone(), frame.y.clone())?;
        let y_decimals = decimals(&frame.y);
        let y_tick = move |v: &f64| tick(*v, y_decimals);
        let x_tick = |v: &f64| {
            let i = v.round();
            if (v - i).abs() < 1e-6 && i >= 0.0 {
                names.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        };
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(bars.len() * 2 + 1)
            .y_labels(TICKS)
            .x_label_formatter(&x_tick)
            .y_label_formatter(&y_tick)
            .y_desc(y_label)
            .axis_desc_style((FONT, 16))
            .label_style((FONT, 14))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(BLACK.mix(0.04))
            .draw()?;
        let value_decimals = y_decimals.max(1);
        for (i, bar) in bars.iter().enumerate().filter(|(_, b)| b.mean.is_finite()) {
            let x = i as f64;
            chart.draw_series([Rectangle::new(
                [(x - 0.32, 0.0), (x + 0.32, bar.mean)],
                colour(i).mix(0.85).filled(),
            )])?;
            let whisker = BLACK.stroke_width(2);
            if bar.low.is_finite() && bar.high.is_finite() && bar.high > bar.low {
                chart.draw_series([
                    PathElement::new(vec![(x, bar.low), (x, bar.high)], whisker),
                    PathElement::new(vec![(x - 0.08, bar.low), (x + 0.08, bar.low)], whisker),
                    PathElement::new(vec![(x - 0.08, bar.high), (x + 0.08, bar.high)], whisker),
                ])?;
            }
            let top = if bar.high.is_finite() {
                bar.high.max(bar.mean)
            } else {
                bar.mean
            };
            let text = format!("{:.value_decimals$}{unit}", bar.mean);
            chart.draw_series([Text::new(
                text,
                (x, top + 0.03 * span),
                (FONT, 14)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
            )])?;
        }
        Ok(())
    })
}

/// The colour of reference lines.
const REFERENCE: RGBColor = RGBColor(90, 90, 90);

/// How a legend entry is drawn.
#[derive(Debug, Clone, Copy)]
enum Swatch {
    /// A line segment (a curve).
    Line(RGBColor),
    /// A dashed segment (a reference).
    Dashed(RGBColor),
    /// A dot (a scatter series).
    Dot(RGBColor),
}

/// The ranges of a plot.
struct Frame {
    /// Horizontal range.
    x: Range<f64>,
    /// Vertical range.
    y: Range<f64>,
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
        Some(Frame {
            x: padded(x0, x1, x_margin),
            y: padded(y0, y1, y_margin),
        })
    }

    /// A chart with labelled axes and a light grid (the title and the legend
    /// are drawn around it).
    fn chart<'a, 'b>(
        &self,
        root: &'a DrawingArea<SVGBackend<'b>, Shift>,
        x_label: &str,
        y_label: &str,
    ) -> Result<Chart<'a, 'b>, DrawingAreaErrorKind<io::Error>> {
        let mut chart = ChartBuilder::on(root)
            .margin(SIDE)
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

/// A generous estimate of the width of `text` at font size `size`, in pixels
/// (sans-serif glyphs average about half the size; capitals and digits more).
pub fn text_width(text: &str, size: u32) -> f64 {
    text.chars()
        .map(|c| match c {
            'i' | 'l' | 'j' | '.' | ',' | ':' | ';' | '\'' | '|' | '!' | ' ' | '(' | ')' | '[' | ']' => 0.33,
            'm' | 'w' | 'M' | 'W' => 0.9,
            c if c.is_uppercase() || c.is_ascii_digit() => 0.66,
            _ => 0.56,
        })
        .sum::<f64>()
        * f64::from(size)
}

/// `title` broken at spaces into lines no wider than `width` pixels at `size`.
pub(crate) fn wrap(title: &str, width: f64, size: u32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in title.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if !line.is_empty() && text_width(&candidate, size) > width {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// The legend's entries laid out in rows no wider than `width`: per row, the
/// entries with their x offsets.
fn legend_rows(entries: &[(String, Swatch)], width: f64) -> Vec<Vec<(f64, usize)>> {
    let mut rows: Vec<Vec<(f64, usize)>> = Vec::new();
    let mut x = 0.0;
    for (i, (label, _)) in entries.iter().enumerate() {
        let w = 34.0 + text_width(label, LEGEND_SIZE) + 24.0;
        if rows.is_empty() || (x + w > width && x > 0.0) {
            rows.push(Vec::new());
            x = 0.0;
        }
        if let Some(row) = rows.last_mut() {
            row.push((x, i));
        }
        x += w;
    }
    rows
}

/// Renders a plot into a string, then writes it to `path` atomically: the
/// title (wrapped) on top, the chart drawn by `draw` in the middle, the legend
/// below. The height grows with the title's lines and the legend's rows.
fn write_svg(
    path: &Path,
    title: &str,
    legend: &[(String, Swatch)],
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult,
) -> Result<(), PlotError> {
    let (width, base_height) = PLOT_SIZE;
    let inner = f64::from(width - 2 * SIDE);
    let lines = wrap(title, inner, TITLE_SIZE);
    let rows = legend_rows(legend, inner);
    let title_height = PAD + TITLE_LINE * lines.len() as u32;
    let legend_height = if rows.is_empty() {
        0
    } else {
        LEGEND_ROW * rows.len() as u32 + PAD
    };
    // A one-line title and a one-row legend give the base height.
    let chart_height = base_height - (PAD + TITLE_LINE) - (LEGEND_ROW + PAD);
    let height = title_height + chart_height + legend_height;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        let result = (|| -> DrawResult {
            root.fill(&WHITE)?;
            let (top, rest) = root.split_vertically(title_height);
            let (middle, bottom) = rest.split_vertically(chart_height);
            let style = (FONT, TITLE_SIZE)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top));
            for (i, line) in lines.iter().enumerate() {
                top.draw(&Text::new(
                    line.clone(),
                    ((width / 2) as i32, (PAD + TITLE_LINE * i as u32) as i32),
                    style.clone(),
                ))?;
            }
            draw(&middle)?;
            for (r, row) in rows.iter().enumerate() {
                let row_width = row
                    .last()
                    .map_or(0.0, |&(x, i)| x + 34.0 + text_width(&legend[i].0, LEGEND_SIZE));
                let left = (f64::from(width) - row_width).max(0.0) / 2.0;
                let y = (LEGEND_ROW * r as u32 + LEGEND_ROW / 2) as i32;
                for &(x, i) in row {
                    let x = (left + x) as i32;
                    let (label, swatch) = &legend[i];
                    match *swatch {
                        Swatch::Line(c) => {
                            bottom.draw(&PathElement::new(vec![(x, y), (x + 26, y)], c.stroke_width(3)))?;
                        }
                        Swatch::Dashed(c) => {
                            for k in 0..3 {
                                let from = x + k * 10;
                                bottom.draw(&PathElement::new(vec![(from, y), (from + 6, y)], c.stroke_width(2)))?;
                            }
                        }
                        Swatch::Dot(c) => bottom.draw(&Circle::new((x + 13, y), 4, c.filled()))?,
                    }
                    bottom.draw(&Text::new(
                        label.clone(),
                        (x + 34, y),
                        (FONT, LEGEND_SIZE)
                            .into_font()
                            .color(&BLACK)
                            .pos(Pos::new(HPos::Left, VPos::Center)),
                    ))?;
                }
            }
            root.present()
        })();
        result.map_err(|source| PlotError::Draw {
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
    fn long_titles_wrap_within_the_width() {
        let title = "Figure 6.3: Parr and Russell's grid, short term: Sarsa(0.9) and epsilon-SoSMC without exploration after the initial phase";
        let lines = wrap(title, 864.0, 20);
        assert!(lines.len() >= 2, "{lines:?}");
        assert!(lines.iter().all(|l| text_width(l, 20) <= 864.0), "{lines:?}");
        assert_eq!(lines.join(" "), title);
        assert_eq!(wrap("short", 864.0, 20), ["short"]);
        assert_eq!(wrap("", 864.0, 20), [""]);
    }

    #[test]
    fn a_single_value_gets_a_visible_range() {
        assert_eq!(padded(3.0, 3.0, 0.05), 2.5..3.5);
        assert_eq!(padded(-100.0, -100.0, 0.05), -110.0..-90.0);
        assert_eq!(padded(0.0, 10.0, 0.05), -0.5..10.5);
    }
}
