//! SVG figures: well-formed, deterministic, data actually drawn, bad data rejected.

use nanobeam::report::svg::*;
use nanobeam::report::ReportError;
use std::collections::BTreeMap;

/// Counts opening, closing and self-closing tags per element name and checks
/// that every opened element is closed (a well-formedness proxy without an
/// XML parser among the dependencies).
fn assert_well_formed(svg: &str) {
    assert!(svg.starts_with("<svg"), "does not start with <svg: {}", &svg[..svg.len().min(80)]);
    assert!(svg.trim_end().ends_with("</svg>"), "does not end with </svg>");
    let mut balance: BTreeMap<String, i64> = BTreeMap::new();
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unterminated tag") + start;
        let tag = &rest[start + 1..end];
        let name: String = tag.trim_start_matches('/').chars().take_while(|c| c.is_alphanumeric()).collect();
        assert!(!name.is_empty(), "empty tag name in <{tag}>");
        if tag.starts_with('/') {
            *balance.entry(name).or_default() -= 1;
        } else if !tag.ends_with('/') {
            *balance.entry(name).or_default() += 1;
        }
        rest = &rest[end + 1..];
    }
    for (name, b) in balance {
        assert_eq!(b, 0, "element <{name}> opened/closed imbalance {b}");
    }
}

fn count(svg: &str, needle: &str) -> usize {
    svg.matches(needle).count()
}

fn frf_like() -> LinePlot {
    let x: Vec<f64> = (1..200).map(|i| 10.0 * i as f64).collect();
    let y: Vec<f64> = x.iter().map(|&f| 1.0 / ((f - 500.0).abs() + 5.0)).collect();
    LinePlot {
        title: "FRF".into(),
        x_axis: Axis::log("frequency (GHz)"),
        y_axis: Axis::log("|H| (nm/N)"),
        series: vec![
            Series::new("reference", x.clone(), y.clone()),
            Series::new("mean", x.clone(), y.iter().map(|v| v * 0.9).collect()),
        ],
        realizations: vec![Series::new("", x.clone(), y.iter().map(|v| v * 1.1).collect())],
        band: Some(Band {
            name: "99 % envelope".into(),
            x: x.clone(),
            lower: y.iter().map(|v| v * 0.5).collect(),
            upper: y.iter().map(|v| v * 2.0).collect(),
        }),
        ref_lines: vec![RefLine::Vertical(1250.0), RefLine::Horizontal(0.01)],
        ..Default::default()
    }
}

fn chains() -> Vec<NamedValues> {
    // Deterministic pseudo-chains (no RNG needed): smooth oscillations.
    (0..3)
        .map(|c| {
            NamedValues::new(
                format!("Case 1{}", ['A', 'B', 'C'][c]),
                (0..5000).map(|i| 1.0 + 0.1 * c as f64 + 0.05 * ((i as f64) * 0.37 + c as f64).sin()).collect(),
            )
        })
        .collect()
}

fn all_figures() -> Vec<(&'static str, String)> {
    let hm = Heatmap {
        title: "ω1/ω1'".into(),
        x_axis: Axis::linear("e0a (nm)"),
        y_axis: Axis::log("Ω (rad/s)"),
        x: (0..10).map(|i| 0.2 * i as f64).collect(),
        y: (0..8).map(|j| 1e10 * 10f64.powf(j as f64 * 0.4)).collect(),
        z: (0..8).map(|j| (0..10).map(|i| 1.0 - 0.02 * i as f64 - 0.01 * j as f64).collect()).collect(),
        z_label: "ω1/ω1' (-)".into(),
        ..Default::default()
    };
    let ch = chains();
    vec![
        ("line", line_plot(&frf_like()).unwrap()),
        ("heatmap", heatmap(&hm).unwrap()),
        (
            "trace",
            trace_plot(&TracePlot {
                title: "e0a".into(),
                y_label: "e0a (nm)".into(),
                chains: ch.clone(),
                reference: Some(1.1),
                ..Default::default()
            })
            .unwrap(),
        ),
        (
            "histogram",
            histogram(&HistogramPlot {
                title: "e0a".into(),
                x_label: "e0a (nm)".into(),
                groups: ch.clone(),
                reference: Some(1.1),
                ..Default::default()
            })
            .unwrap(),
        ),
        (
            "pair",
            pair_plot(&PairPlot {
                title: "pairs".into(),
                names: ch.iter().map(|c| c.name.clone()).collect(),
                columns: ch.iter().map(|c| c.values.clone()).collect(),
                reference: Some(vec![1.0, 1.1, 1.2]),
                ..Default::default()
            })
            .unwrap(),
        ),
        (
            "bar",
            bar_chart(&BarChart {
                title: "classes".into(),
                y_label: "P(M|D) (-)".into(),
                categories: vec!["N=1".into(), "N=2".into()],
                values: vec![0.25, 0.75],
                ..Default::default()
            })
            .unwrap(),
        ),
        (
            "residual",
            residual_plot(&ResidualPlot {
                title: "residuals".into(),
                labels: ["ω1", "ω2", "ω3", "ζ1", "ζ2", "ζ3"].map(String::from).to_vec(),
                groups: vec![
                    NamedValues::new("before", vec![0.5, -3.0, 1.0, 4.0, -0.2, 0.1]),
                    NamedValues::new("after", vec![0.1, -0.5, 0.3, 0.9, -0.2, 0.0]),
                ],
                ..Default::default()
            })
            .unwrap(),
        ),
    ]
}

#[test]
fn every_figure_is_well_formed_svg() {
    for (name, svg) in all_figures() {
        if let Ok(dir) = std::env::var("REPORT_SVG_DUMP") {
            std::fs::write(format!("{dir}/{name}.svg"), &svg).unwrap();
        }
        assert_well_formed(&svg);
    }
}

#[test]
fn figures_are_byte_identical_across_runs_and_threads() {
    let first = all_figures();
    let again = std::thread::spawn(all_figures).join().unwrap();
    assert_eq!(first, again);
}

#[test]
fn line_plot_draws_legend_entries_and_every_element_kind() {
    let svg = line_plot(&frf_like()).unwrap();
    for label in ["reference", "mean", "99 % envelope", "frequency (GHz)", "|H| (nm/N)", "FRF"] {
        assert!(svg.contains(label), "missing text {label}");
    }
    // Removing the band, the realizations and the reference lines must remove drawn elements.
    let bare = line_plot(&LinePlot { band: None, realizations: vec![], ref_lines: vec![], ..frf_like() }).unwrap();
    assert!(count(&svg, "<polygon") > count(&bare, "<polygon"), "band not drawn as a polygon");
    assert!(count(&svg, "<polyline") > count(&bare, "<polyline"), "realizations / dashed lines not drawn");
    assert!(svg.contains("#BEBEBE"), "realization grey missing");
}

/// The tick labels of an SVG: the text of every `<text>` element.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0.trim().to_string()))
        .collect()
}

#[test]
fn a_log_axis_of_tiny_values_is_labelled() {
    // A thermal displacement PSD (m²·s/rad) spans about 1e-41 to 1e-34; plotters'
    // own log key points drop everything below f64::EPSILON, which left such an
    // axis without a single number.
    let x: Vec<f64> = (0..=300).map(|i| 1e11 * 10f64.powf(i as f64 / 100.0)).collect();
    let y: Vec<f64> = x.iter().map(|&w| 1e-34 / (1.0 + (w / 2e12).powi(4))).collect();
    let spec = LinePlot {
        x_axis: Axis::log("frequency (rad/s)"),
        y_axis: Axis::log("PSD (m²·s/rad)"),
        series: vec![Series::new("measured", x, y)],
        ..Default::default()
    };
    let labels = texts(&line_plot(&spec).unwrap());
    for decade in ["1e-34", "1e-36", "1e-38", "1e11", "1e12", "1e13"] {
        assert!(labels.iter().any(|l| l == decade), "no tick label {decade} in {labels:?}");
    }
}

#[test]
fn log_axis_skips_non_positive_values_and_rejects_all_non_positive() {
    let mut spec = frf_like();
    spec.band = None;
    spec.series[0].y[0] = -1.0; // skipped, not an error
    spec.series[1].y[3] = f64::NAN;
    assert!(line_plot(&spec).is_ok());
    let bad = LinePlot {
        series: vec![Series::new("neg", vec![1.0, 2.0], vec![-1.0, 0.0])],
        x_axis: Axis::log("x"),
        y_axis: Axis::log("y"),
        ..Default::default()
    };
    assert!(matches!(line_plot(&bad), Err(ReportError::InvalidData { .. })));
}

#[test]
fn mismatched_lengths_name_the_series() {
    let spec = LinePlot { series: vec![Series::new("omega_1", vec![1.0, 2.0], vec![1.0])], ..Default::default() };
    let err = line_plot(&spec).unwrap_err().to_string();
    assert!(err.contains("omega_1"), "{err}");
    let r = ResidualPlot {
        labels: vec!["ω1".into()],
        groups: vec![NamedValues::new("after", vec![1.0, 2.0])],
        ..Default::default()
    };
    assert!(residual_plot(&r).unwrap_err().to_string().contains("after"));
    let b = BarChart { categories: vec!["a".into()], values: vec![], ..Default::default() };
    assert!(bar_chart(&b).is_err());
    let p = PairPlot {
        names: vec!["a".into(), "b".into()],
        columns: vec![vec![1.0, 2.0], vec![1.0]],
        ..Default::default()
    };
    assert!(pair_plot(&p).unwrap_err().to_string().contains('b'));
}

#[test]
fn heatmap_draws_every_cell_with_the_scale_endpoints() {
    let (nx, ny) = (7, 5);
    let hm = Heatmap {
        x: (0..nx).map(|i| i as f64).collect(),
        y: (0..ny).map(|j| 10f64.powi(j)).collect(),
        y_axis: Axis::log("Ω (rad/s)"),
        z: (0..ny).map(|j| (0..nx).map(|i| (i + nx * j as usize) as f64).collect()).collect(),
        ..Default::default()
    };
    let svg = heatmap(&hm).unwrap();
    assert_well_formed(&svg);
    // background + nx*ny cells + 128 colour-bar steps, at least
    assert!(count(&svg, "<rect") >= 1 + (nx * ny as usize) + 128);
    let hex = |c: plotters::style::RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    assert!(svg.contains(&hex(viridis(0.0))), "minimum colour missing");
    assert!(svg.contains(&hex(viridis(1.0))), "maximum colour missing");
    let bad = Heatmap { z: vec![vec![1.0; nx]; ny as usize - 1], ..hm.clone() };
    assert!(heatmap(&bad).is_err());
    let unsorted = Heatmap { x: (0..nx).rev().map(|i| i as f64).collect(), ..hm };
    assert!(heatmap(&unsorted).is_err());
}

#[test]
fn viridis_endpoints_and_monotone_lightness() {
    assert_eq!((viridis(0.0).0, viridis(0.0).1, viridis(0.0).2), (68, 1, 84));
    assert_eq!((viridis(1.0).0, viridis(1.0).1, viridis(1.0).2), (253, 231, 37));
    assert_eq!(viridis(-5.0), viridis(0.0));
    assert_eq!(viridis(7.0), viridis(1.0));
    // viridis is designed with monotonically increasing lightness; green is a good proxy.
    let g: Vec<u8> = (0..=100).map(|k| viridis(k as f64 / 100.0).1).collect();
    assert!(g.windows(2).all(|w| w[1] >= w[0]));
}

#[test]
fn trace_plot_thins_long_chains_to_the_cap() {
    let long = NamedValues::new("c", (0..100_000).map(|i| (i as f64).sin()).collect());
    let svg = trace_plot(&TracePlot { chains: vec![long], max_points: 1000, ..Default::default() }).unwrap();
    // The chain is the polyline with the most points; its point count is capped.
    let max_pts =
        svg.split("points=\"").skip(1).map(|s| s.split('"').next().unwrap().split_whitespace().count()).max().unwrap();
    assert!((900..=1000).contains(&max_pts), "{max_pts} points drawn");
}
