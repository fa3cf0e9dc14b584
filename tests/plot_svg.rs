//! SVG plots and curve CSV files.

use std::fs;
use std::path::PathBuf;

use learnpnp::experiment::plot::{
    CsvProblem, CurvePoint, PlotError, Series, plot_curves, plot_scatter, read_curve_csv,
};

/// A fresh, empty directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("plot_svg_{test}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn curve(label: &str, offset: f64) -> Series {
    Series {
        label: label.to_string(),
        points: (0..50)
            .map(|i| {
                let x = f64::from(i) * 10.0;
                let mean = offset + (1.0 - (-x / 150.0).exp()) * 8.0;
                CurvePoint {
                    x,
                    mean,
                    low: mean - 0.5,
                    high: mean + 0.5,
                }
            })
            .collect(),
    }
}

fn point(x: f64, mean: f64) -> CurvePoint {
    CurvePoint {
        x,
        mean,
        low: mean - 1.0,
        high: mean + 1.0,
    }
}

#[test]
fn two_curves_have_title_axes_and_legend() {
    let dir = scratch("curves");
    let path = dir.join("curves.svg");
    let series = [curve("SoSMC", -10.0), curve("Sarsa & TD(λ)", -12.0)];
    plot_curves(&path, "Penalty kick", "episode", "reward per episode", &series, &[]).expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(svg.contains("width=\"900\"") && svg.contains("height=\"560\""));
    for text in [
        "Penalty kick",
        "episode",
        "reward per episode",
        "SoSMC",
        "Sarsa &amp; TD(λ)",
    ] {
        assert!(svg.contains(text), "missing {text}");
    }
    // A translucent band per series.
    assert!(svg.matches("<polygon").count() >= 2);
    assert!(svg.contains("opacity=\"0.2"));
    // Only the plot itself is left in the directory.
    assert_eq!(fs::read_dir(&dir).expect("list").count(), 1);
}

#[test]
fn nan_points_are_skipped() {
    let dir = scratch("gaps");
    let path = dir.join("gaps.svg");
    let mut s = curve("with gaps", 0.0);
    s.points[10].mean = f64::NAN;
    s.points[20].low = f64::NAN;
    s.points[30].x = f64::INFINITY;
    let flat = Series {
        label: "flat".into(),
        points: vec![point(0.0, 3.0), point(1.0, 3.0)],
    };
    let lonely = Series {
        label: "single point".into(),
        points: vec![point(5.0, 1.0), point(f64::NAN, 1.0)],
    };
    plot_curves(&path, "gaps", "x", "y", &[s, flat, lonely], &[]).expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    assert!(svg.contains("single point"));
}

#[test]
fn nothing_to_plot_is_an_error() {
    let dir = scratch("empty");
    let path = dir.join("empty.svg");
    let err = plot_curves(&path, "t", "x", "y", &[], &[]).expect_err("no series");
    assert!(matches!(err, PlotError::NoSeries { .. }), "{err:?}");
    assert!(err.to_string().contains("empty.svg"), "{err}");
    let nan = Series {
        label: "nan".into(),
        points: vec![point(f64::NAN, 1.0), point(1.0, f64::NAN)],
    };
    let band_only = Series {
        label: "band only".into(),
        points: vec![CurvePoint {
            x: 1.0,
            mean: f64::NAN,
            low: 0.0,
            high: 1.0,
        }],
    };
    let none = Series {
        label: "none".into(),
        points: vec![],
    };
    let err = plot_curves(&path, "t", "x", "y", &[nan, band_only, none], &[]).expect_err("all NaN");
    assert!(matches!(err, PlotError::NoFinitePoints { .. }), "{err:?}");
    let err = plot_scatter(&path, "t", "x", "y", &[]).expect_err("no series");
    assert!(matches!(err, PlotError::NoSeries { .. }), "{err:?}");
    let err = plot_scatter(&path, "t", "x", "y", &[("a".into(), vec![(f64::NAN, 0.0)])]).expect_err("all NaN");
    assert!(matches!(err, PlotError::NoFinitePoints { .. }), "{err:?}");
    assert!(!path.exists());
}

#[test]
fn scatter_of_action_values() {
    let dir = scratch("scatter");
    let path = dir.join("values.svg");
    let series: Vec<(String, Vec<(f64, f64)>)> = ["left", "right", "center", "wait"]
        .iter()
        .enumerate()
        .map(|(a, name)| {
            let points = (0..200)
                .map(|e| {
                    let e = f64::from(e);
                    (e, a as f64 + (e / 20.0).sin())
                })
                .collect();
            (name.to_string(), points)
        })
        .collect();
    plot_scatter(&path, "Values in the initial observation", "episode", "value", &series).expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    for text in ["Values in the initial observation", "episode", "value", "left", "wait"] {
        assert!(svg.contains(text), "missing {text}");
    }
    assert!(svg.matches("<circle").count() >= 800);
}

#[test]
fn an_unwritable_path_is_an_io_error() {
    let dir = scratch("unwritable");
    let path = dir.join("no such directory").join("plot.svg");
    let err = plot_curves(&path, "t", "x", "y", &[curve("a", 0.0)], &[]).expect_err("no directory");
    assert!(matches!(err, PlotError::Io { .. }), "{err:?}");
}

#[test]
fn curve_csv_round_trips() {
    let dir = scratch("csv");
    let path = dir.join("curve.csv");
    fs::write(
        &path,
        "episode,mean,ci_low,ci_high,runs,extra\n\
         0,-10.5,-11,-10,20,x\n\
         \n\
         100, -3.25 ,-4.5,-2,20,y\r\n\
         200,NaN,NaN,NaN,0,z\n",
    )
    .expect("write");
    let points = read_curve_csv(&path).expect("read");
    assert_eq!(points.len(), 3);
    assert_eq!(points[0], point(0.0, -10.5).with(-11.0, -10.0));
    assert_eq!(points[1], point(100.0, -3.25).with(-4.5, -2.0));
    assert_eq!(points[2].x, 200.0);
    assert!(points[2].mean.is_nan());
}

#[test]
fn columns_are_found_by_name() {
    let dir = scratch("columns");
    let path = dir.join("curve.csv");
    fs::write(&path, "runs,ci_high,ci_low,mean,episode\n5,3,1,2,7\n").expect("write");
    assert_eq!(read_curve_csv(&path).expect("read"), [point(7.0, 2.0).with(1.0, 3.0)]);
}

#[test]
fn bad_curve_files_name_file_and_line() {
    let dir = scratch("bad_csv");
    let path = dir.join("curve.csv");
    let cases = [
        (
            "episode,mean,ci_low,ci_high,runs\n0,1,0,2,3\n10,1,zero,2,3\n",
            3,
            CsvProblem::NotANumber {
                column: "ci_low",
                text: "zero".into(),
            },
        ),
        (
            "episode,mean,ci_low,ci_high,runs\n0,1,0\n",
            2,
            CsvProblem::MissingField {
                column: "ci_high",
                fields: 3,
            },
        ),
        (
            "episode,average,ci_low,ci_high,runs\n",
            1,
            CsvProblem::MissingColumn { column: "mean" },
        ),
        ("", 1, CsvProblem::Empty),
    ];
    for (text, line, problem) in cases {
        fs::write(&path, text).expect("write");
        let err = read_curve_csv(&path).expect_err("bad file");
        let message = err.to_string();
        assert!(message.contains(&format!("curve.csv, line {line}:")), "{message}");
        match err {
            PlotError::Csv { line: l, source, .. } => {
                assert_eq!(l, line);
                assert_eq!(source, problem);
            }
            other => panic!("{other:?}"),
        }
    }
    let err = read_curve_csv(&dir.join("absent.csv")).expect_err("missing");
    assert!(matches!(err, PlotError::Io { .. }), "{err:?}");
}

/// Test helper: a point with explicit interval ends.
trait WithInterval {
    fn with(self, low: f64, high: f64) -> Self;
}

impl WithInterval for CurvePoint {
    fn with(self, low: f64, high: f64) -> Self {
        CurvePoint { low, high, ..self }
    }
}

#[test]
fn errors_can_travel_across_threads() {
    fn thread_safe<T: std::error::Error + Send + Sync + 'static>() {}
    thread_safe::<PlotError>();
    thread_safe::<CsvProblem>();
}

/// The `y` of every `<text>` element holding `text` exactly.
fn text_ys(svg: &str, text: &str) -> Vec<f64> {
    let mut ys = Vec::new();
    let mut rest = svg;
    while let Some(at) = rest.find("<text ") {
        let element = &rest[at..];
        let end = element.find("</text>").expect("closed text");
        let open_end = element.find('>').expect("tag end");
        if element[open_end + 1..end].trim() == text {
            let y = element
                .split(" y=\"")
                .nth(1)
                .and_then(|v| v.split('"').next())
                .expect("a y");
            ys.push(y.parse().expect("a number"));
        }
        rest = &element[end..];
    }
    ys
}

/// Every `<text>` element's content.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text ")
        .skip(1)
        .map(|t| {
            let body = &t[t.find('>').expect("tag end") + 1..t.find("</text>").expect("closed")];
            body.trim()
                .replace("&apos;", "'")
                .replace("&quot;", "\"")
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&")
        })
        .collect()
}

#[test]
fn long_titles_wrap_and_legends_sit_below_the_data() {
    let dir = scratch("long_title");
    let path = dir.join("long.svg");
    let title = "Figure 6.3: Parr and Russell's grid, short term: Sarsa(0.9) and epsilon-SoSMC without exploration after the initial phase";
    let series: Vec<Series> = (0..6)
        .map(|i| curve(&format!("a rather long curve label {i}"), f64::from(i)))
        .collect();
    plot_curves(&path, title, "learning episodes", "return", &series, &[]).expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    // The title comes in several lines that together are the title, none wider than the plot.
    let all = texts(&svg);
    let lines: Vec<&String> = all.iter().take_while(|t| title.contains(t.as_str())).collect();
    assert!(lines.len() >= 2, "{all:?}");
    assert_eq!(lines.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(" "), title);
    for line in &lines {
        assert!(
            learnpnp::experiment::plot::text_width(line, 20) <= 900.0 - 36.0,
            "{line}"
        );
    }
    // Every legend entry is below the horizontal axis's description.
    let axis = text_ys(&svg, "learning episodes")[0];
    for s in &series {
        let ys = text_ys(&svg, &s.label);
        assert_eq!(ys.len(), 1, "{}", s.label);
        assert!(ys[0] > axis, "{} at {} above the axis at {axis}", s.label, ys[0]);
    }
    let height: f64 = svg
        .split("height=\"")
        .nth(1)
        .and_then(|v| v.split('"').next())
        .expect("h")
        .parse()
        .expect("n");
    assert!(height > 560.0, "the plot grows with its title and legend: {height}");
}

#[test]
fn a_reference_is_a_dashed_line_in_the_legend_and_single_runs_have_no_band() {
    let dir = scratch("reference");
    let path = dir.join("ref.svg");
    // One run: the interval has no width.
    let one_run = Series {
        label: "one run".to_string(),
        points: (0..20)
            .map(|i| {
                let mean = f64::from(i) / 100.0;
                CurvePoint {
                    x: f64::from(i),
                    mean,
                    low: mean,
                    high: mean,
                }
            })
            .collect(),
    };
    let optimum = learnpnp::experiment::plot::Reference {
        label: "optimum: 0.264".to_string(),
        value: 0.264,
    };
    plot_curves(&path, "t", "x", "y", &[one_run], &[optimum]).expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    assert_eq!(svg.matches("<polygon").count(), 0, "no band for one run");
    assert!(texts(&svg).iter().any(|t| t == "optimum: 0.264"));
    // The dashed line: several short grey segments at one height.
    let grey = svg.matches("stroke=\"#5A5A5A\"").count();
    assert!(grey >= 10, "{grey} grey segments");
}

#[test]
fn fixed_policies_are_bars_with_their_intervals() {
    use learnpnp::experiment::plot::{Bar, plot_bars};
    let dir = scratch("bars");
    let path = dir.join("bars.svg");
    let bars = [
        Bar {
            label: "random".to_string(),
            mean: 5.1,
            low: 4.8,
            high: 5.4,
        },
        Bar {
            label: "hand-coded".to_string(),
            mean: 16.2,
            low: 15.5,
            high: 16.9,
        },
    ];
    plot_bars(
        &path,
        "Keepaway: fixed policies",
        "mean episode duration (s)",
        " s",
        &bars,
    )
    .expect("plot");
    let svg = fs::read_to_string(&path).expect("svg");
    let all = texts(&svg);
    for text in ["random", "hand-coded", "5.1 s", "16.2 s", "mean episode duration (s)"] {
        assert!(all.iter().any(|t| t == text), "missing {text}: {all:?}");
    }
    assert!(!all.iter().any(|t| t.contains("learning episodes")));
    // Two bars and, for each, a whisker with two caps.
    assert!(svg.matches("<rect").count() >= 3, "background and two bars");
    assert!(svg.matches("stroke-width=\"2\"").count() >= 6);
    assert!(plot_bars(&path, "t", "y", "", &[]).is_err());
}
