//! `meadow::harness::plot` without a GPU: every chart kind writes a decodable PNG of the requested size
//! that shows the series colours; bad input is refused as `Error::BadInput` and writes nothing.

use std::path::{Path, PathBuf};

use meadow::harness::plot::{self, Panel, Scale, Series};
use meadow::Error;

/// The first palette colours of `plot` (Tableau 10), in series order.
const BLUE: [u8; 3] = [0x4e, 0x79, 0xa7];
const ORANGE: [u8; 3] = [0xf2, 0x8e, 0x2b];
const RED: [u8; 3] = [0xe1, 0x57, 0x59];
const GREEN: [u8; 3] = [0x59, 0xa1, 0x4f];

/// A fresh, empty directory for one test under the system temp dir.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("meadow-plot-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch directory");
    dir
}

/// Decode `path`, check its size and that it is not one flat colour; return its RGB pixels.
fn load(path: &Path, size: (u32, u32)) -> Vec<[u8; 3]> {
    let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8();
    assert_eq!(image.dimensions(), size, "{}", path.display());
    let pixels: Vec<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    assert!(pixels.iter().any(|p| *p != pixels[0]), "{} is one flat colour", path.display());
    pixels
}

/// Number of pixels of exactly `colour`.
fn count(pixels: &[[u8; 3]], colour: [u8; 3]) -> usize {
    pixels.iter().filter(|&&p| p == colour).count()
}

fn series(label: &str, points: &[(f64, f64)]) -> Series {
    Series { label: label.into(), points: points.to_vec() }
}

fn panel(x_scale: Scale, y_scale: Scale, series: Vec<Series>) -> Panel {
    Panel { title: "GPU time".into(), x_label: "blades".into(), y_label: "time (ms)".into(), x_scale, y_scale, series }
}

/// Three series on a log-log panel and a linear one.
fn three_series() -> Vec<Panel> {
    let blades = [1e3, 1e4, 1e5, 1e6];
    let line = |label: &str, k: f64| series(label, &blades.map(|b| (b, 0.05 + k * b * 1e-6)));
    vec![
        panel(Scale::Log, Scale::Log, vec![line("pulling", 1.0), line("instanced", 2.0), line("indirect", 4.0)]),
        panel(Scale::Log, Scale::Linear, vec![line("pulling", 1.0), line("instanced", 2.0), line("indirect", 4.0)]),
    ]
}

#[test]
fn line_panels_draw_each_series_in_its_colour() {
    let dir = scratch("lines");
    let out = dir.join("lines.png");
    plot::line_panels(&out, (1000, 450), "bench", &three_series(), 2).unwrap();
    let pixels = load(&out, (1000, 450));
    for (name, colour) in [("first", BLUE), ("second", ORANGE), ("third", RED)] {
        assert!(count(&pixels, colour) > 100, "{name} series colour {colour:?} missing");
    }
    assert_eq!(count(&pixels, GREEN), 0, "a fourth series colour appeared with three series");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn histogram_draws_bars_and_percentile_lines() {
    let dir = scratch("hist");
    let out = dir.join("hist.png");
    let values: Vec<f64> = (0..1000).map(|i| 4.0 + ((i * 7919) % 1000) as f64 / 500.0).collect();
    plot::histogram(&out, (800, 500), "frame time", "frame time (ms)", &values, 40).unwrap();
    let pixels = load(&out, (800, 500));
    // Bars are the first palette colour at 75 % over white.
    let bar = BLUE.map(|c| (0.75 * f64::from(c) + 0.25 * 255.0).round() as u8);
    let near = |p: &[u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(&a, b)| a.abs_diff(b) <= 1);
    assert!(pixels.iter().filter(|p| near(p, bar)).count() > 1000, "no bar fill {bar:?}");
    assert!(count(&pixels, ORANGE) > 100, "no p95 line");
    assert!(count(&pixels, RED) > 100, "no p99 line");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bars_draw_each_group_in_its_colour() {
    let dir = scratch("bars");
    let out = dir.join("bars.png");
    let categories: Vec<String> = ["per blade", "instanced", "indirect"].map(String::from).to_vec();
    let groups = vec![("10k".to_string(), vec![850.0, 95.0, 40.0]), ("1M".to_string(), vec![910.0, 90.0, 35.0])];
    plot::bars(&out, (900, 500), "submission", "ns per draw", &categories, &groups).unwrap();
    let pixels = load(&out, (900, 500));
    assert!(count(&pixels, BLUE) > 1000, "first group colour missing");
    assert!(count(&pixels, ORANGE) > 1000, "second group colour missing");
    assert_eq!(count(&pixels, RED), 0, "a third group colour appeared with two groups");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bar_panels_draw_every_panel_and_refuse_bad_ones() {
    let dir = scratch("bar-panels");
    let out = dir.join("panels.png");
    let rows: Vec<String> = ["default", "inside", "above"].map(String::from).to_vec();
    let time = plot::BarPanel {
        title: "frame time".into(),
        value_label: "GPU ms".into(),
        categories: rows.clone(),
        groups: vec![
            ("brute force".into(), vec![900.0, 950.0, 700.0]),
            ("GPU-driven".into(), vec![300.0, 200.0, 250.0]),
        ],
    };
    // The second panel's only group is the third colour: it shows only if that panel is drawn.
    let diff = plot::BarPanel {
        title: "difference".into(),
        value_label: "%".into(),
        categories: rows,
        groups: vec![("a".into(), vec![0.0; 3]), ("b".into(), vec![0.0; 3]), ("p99".into(), vec![2.0, 3.5, 1.0])],
    };
    plot::bar_panels(&out, (1000, 450), "lod", &[time.clone(), diff.clone()], 2).unwrap();
    let pixels = load(&out, (1000, 450));
    for (name, colour) in [("first", BLUE), ("second", ORANGE), ("third", RED)] {
        assert!(count(&pixels, colour) > 500, "{name} group colour {colour:?} missing");
    }
    std::fs::remove_file(&out).unwrap();
    refused("no panels", &dir, plot::bar_panels(&out, (1000, 450), "t", &[], 1), "no panels");
    refused("zero columns", &dir, plot::bar_panels(&out, (1000, 450), "t", std::slice::from_ref(&time), 0), "columns");
    refused("too small", &dir, plot::bar_panels(&out, (400, 200), "t", &[time.clone(), diff], 2), "too small");
    let mut nan = time;
    nan.groups[1].1[2] = f64::NAN;
    refused("NaN", &dir, plot::bar_panels(&out, (1000, 450), "t", &[nan], 1), "not finite");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Single points, equal values, zeros, narrow and huge ranges are padded, not refused.
#[test]
fn degenerate_data_still_draws() {
    let dir = scratch("degenerate");
    let size = (600, 400);
    let cases: Vec<(&str, Vec<Panel>)> = vec![
        ("one-point", vec![panel(Scale::Linear, Scale::Linear, vec![series("a", &[(4.0, 2.5)])])]),
        ("one-point-log", vec![panel(Scale::Log, Scale::Log, vec![series("a", &[(1e4, 3.0)])])]),
        ("flat", vec![panel(Scale::Linear, Scale::Linear, vec![series("a", &[(0.0, 0.0), (0.0, 0.0)])])]),
        ("narrow-log", vec![panel(Scale::Log, Scale::Linear, vec![series("a", &[(300.0, 1.0), (310.0, 1.1)])])]),
        ("huge-log", vec![panel(Scale::Log, Scale::Log, vec![series("a", &[(1e-300, 1e-90), (1e100, 1e90)])])]),
        ("offset", vec![panel(Scale::Linear, Scale::Linear, vec![series("a", &[(0.0, 1e9), (1.0, 1e9 + 1e-3)])])]),
    ];
    for (name, panels) in cases {
        let out = dir.join(format!("{name}.png"));
        plot::line_panels(&out, size, name, &panels, 1).unwrap_or_else(|e| panic!("{name}: {e}"));
        load(&out, size);
    }
    plot::histogram(&dir.join("h-equal.png"), size, "equal", "ms", &[3.0; 10], 20).unwrap();
    plot::histogram(&dir.join("h-one.png"), size, "one", "ms", &[0.0], 1).unwrap();
    let one = vec!["only".to_string()];
    plot::bars(&dir.join("b-zero.png"), size, "zero", "ns", &one, &[(String::new(), vec![0.0])]).unwrap();
    plot::bars(&dir.join("b-neg.png"), size, "neg", "%", &one, &[("d".into(), vec![-5.0])]).unwrap();
    for name in ["h-equal", "h-one", "b-zero", "b-neg"] {
        load(&dir.join(format!("{name}.png")), size);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rewriting_replaces_the_file_and_leaves_no_temp_files() {
    let dir = scratch("rewrite");
    let out = dir.join("lines.png");
    plot::line_panels(&out, (600, 400), "first", &three_series()[..1], 1).unwrap();
    plot::line_panels(&out, (700, 400), "second", &three_series()[..1], 1).unwrap();
    load(&out, (700, 400));
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["lines.png"], "stray files");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_directory_is_an_io_error() {
    let dir = scratch("missing");
    let err = plot::line_panels(&dir.join("no/such/dir/x.png"), (600, 400), "t", &three_series()[..1], 1).unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Assert `result` is `BadInput` mentioning `needle` and that `dir` stayed empty.
fn refused(case: &str, dir: &Path, result: meadow::Result<()>, needle: &str) {
    match result {
        Err(Error::BadInput(message)) => {
            assert!(message.contains(needle), "{case}: '{message}' does not mention '{needle}'");
            assert!(!message.contains('\n'), "{case}: message is not one line: {message}");
        }
        other => panic!("{case}: expected BadInput, got {other:?}"),
    }
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 0, "{case}: a file was written");
}

#[test]
fn bad_input_is_refused_and_writes_nothing() {
    let dir = scratch("bad");
    let out = dir.join("out.png");
    let size = (600, 400);
    let lines = |case: &str, size, panels: &[Panel], columns, needle| {
        refused(case, &dir, plot::line_panels(&out, size, "t", panels, columns), needle);
    };
    let one = |x_scale, y_scale, points: &[(f64, f64)]| vec![panel(x_scale, y_scale, vec![series("s", points)])];
    let (lin, log) = (Scale::Linear, Scale::Log);
    lines("no panels", size, &[], 1, "no panels");
    lines("no series", size, &[panel(lin, lin, vec![])], 1, "no series");
    lines("no points", size, &one(lin, lin, &[]), 1, "no points");
    lines("NaN", size, &one(lin, lin, &[(1.0, f64::NAN)]), 1, "not finite");
    lines("inf", size, &one(lin, lin, &[(f64::INFINITY, 1.0)]), 1, "not finite");
    lines("huge", size, &one(lin, lin, &[(1e300, 1.0)]), 1, "beyond");
    lines("log of 0", size, &one(log, lin, &[(0.0, 1.0), (10.0, 2.0)]), 1, "log axis");
    lines("log of negative", size, &one(lin, log, &[(1.0, -1.0)]), 1, "log axis");
    lines("zero width", (0, 400), &three_series(), 1, "non-zero");
    lines("zero height", (600, 0), &three_series(), 1, "non-zero");
    lines("too big", (100_000, 400), &three_series(), 1, "exceeds");
    lines("too small", (300, 200), &three_series(), 2, "too small");
    lines("zero columns", size, &three_series(), 0, "columns");

    let hist = |case: &str, size, values: &[f64], bins, needle| {
        refused(case, &dir, plot::histogram(&out, size, "t", "ms", values, bins), needle);
    };
    hist("empty", size, &[], 10, "no values");
    hist("NaN", size, &[1.0, f64::NAN], 10, "not finite");
    hist("zero bins", size, &[1.0], 0, "bins");
    hist("zero size", (0, 0), &[1.0], 10, "non-zero");

    let cats: Vec<String> = vec!["a".into(), "b".into()];
    let bars = |case: &str, size, categories: &[String], groups: &[(String, Vec<f64>)], needle| {
        refused(case, &dir, plot::bars(&out, size, "t", "ns", categories, groups), needle);
    };
    bars("no categories", size, &[], &[("g".into(), vec![])], "at least one category");
    bars("no groups", size, &cats, &[], "at least one category");
    bars("length mismatch", size, &cats, &[("g".into(), vec![1.0])], "has 1 values for 2 categories");
    bars("NaN", size, &cats, &[("g".into(), vec![1.0, f64::NAN])], "not finite");
    bars("zero size", (600, 0), &cats, &[("g".into(), vec![1.0, 2.0])], "non-zero");
    let _ = std::fs::remove_dir_all(&dir);
}
