use nanobeam::report::svg::*;

fn frf_like() -> LinePlot {
    let x: Vec<f64> = (1..200).map(|i| 10.0 * i as f64).collect();
    let y: Vec<f64> = x.iter().map(|&f| 1.0 / ((f - 500.0).abs() + 5.0)).collect();
    LinePlot {
        title: "FRF".into(),
        x_axis: Axis::log("frequency (GHz)"),
        y_axis: Axis::log("|H| (nm/N)"),
        series: vec![Series::new("reference", x.clone(), y.clone())],
        realizations: vec![Series::new("", x.clone(), y.iter().map(|v| v * 1.1).collect())],
        band: Some(Band { name: "99 %".into(), x: x.clone(), lower: y.iter().map(|v| v * 0.5).collect(), upper: y.iter().map(|v| v * 2.0).collect() }),
        ref_lines: vec![RefLine::Vertical(1250.0), RefLine::Horizontal(0.01)],
        ..Default::default()
    }
}

#[test]
fn smoke() {
    let s = line_plot(&frf_like()).unwrap();
    std::fs::write("/tmp/report_smoke.svg", &s).unwrap();
    assert!(s.starts_with("<svg"));
}
