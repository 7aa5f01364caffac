//! Tables: Markdown shape, CSV quoting (RFC 4180), significant-digit formatting.

use nanobeam::report::table::{csv_field, fmt_interval, fmt_sig, Table};

#[test]
fn markdown_has_header_separator_and_one_line_per_row_with_equal_columns() {
    let mut t = Table::new(["param", "mean", "CI95%"]);
    t.push_row(["e0a (nm)", "1.01", "[0.98, 1.04]"]).push_row(["a|b", "2"]); // short row, pipe
    let md = t.to_markdown();
    let lines: Vec<&str> = md.lines().collect();
    assert_eq!(lines.len(), 2 + t.rows.len());
    assert!(lines[1].chars().all(|c| c == '|' || c == '-' || c == ' '));
    // Every line has the same number of unescaped separators (columns + 1).
    let seps = |l: &str| l.replace("\\|", "").matches('|').count();
    assert!(lines.iter().all(|l| seps(l) == 4), "{md}");
    assert!(md.contains("a\\|b"));
    // Padded to equal width: all lines have the same char length.
    let w = lines[0].chars().count();
    assert!(lines.iter().all(|l| l.chars().count() == w), "{md}");
}

#[test]
fn markdown_and_csv_keep_cells_beyond_the_header() {
    let mut t = Table::new(["a"]);
    t.push_row(["1", "extra"]);
    assert!(t.to_markdown().contains("extra"));
    assert_eq!(t.to_csv(), "a,\n1,extra\n");
}

#[test]
fn csv_quotes_exactly_when_needed() {
    assert_eq!(csv_field("plain"), "plain");
    assert_eq!(csv_field("1,2"), "\"1,2\"");
    assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    assert_eq!(csv_field("two\nlines"), "\"two\nlines\"");
    assert_eq!(csv_field(" padded"), "\" padded\"");
    assert_eq!(csv_field(""), "");
    let mut t = Table::new(["name", "CI"]);
    t.push_row(["Δ", "[0.1, 0.2]"]);
    assert_eq!(t.to_csv(), "name,CI\nΔ,\"[0.1, 0.2]\"\n");
}

#[test]
fn csv_round_trips_through_a_minimal_rfc4180_reader() {
    // A reader written independently of the writer: it must recover the cells.
    fn read(csv: &str) -> Vec<Vec<String>> {
        let (mut rows, mut row, mut cell, mut quoted, mut chars) =
            (vec![], vec![], String::new(), false, csv.chars().peekable());
        while let Some(c) = chars.next() {
            match (quoted, c) {
                (true, '"') if chars.peek() == Some(&'"') => {
                    chars.next();
                    cell.push('"');
                }
                (true, '"') => quoted = false,
                (true, c) => cell.push(c),
                (false, '"') => quoted = true,
                (false, ',') => row.push(std::mem::take(&mut cell)),
                (false, '\n') => {
                    row.push(std::mem::take(&mut cell));
                    rows.push(std::mem::take(&mut row));
                }
                (false, c) => cell.push(c),
            }
        }
        rows
    }
    let cells = [["a,b", "\"q\"", "x\ny"], [" s ", "", "ω1 (GHz)"]];
    let mut t = Table::new(["h1", "h2", "h3"]);
    for r in cells {
        t.push_row(r);
    }
    let back = read(&t.to_csv());
    assert_eq!(back.len(), 3);
    for (i, r) in cells.iter().enumerate() {
        assert_eq!(back[i + 1], r.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    }
}

#[test]
fn fmt_sig_rounds_to_significant_digits_and_switches_notation() {
    assert_eq!(fmt_sig(133.3333, 3), "133");
    assert_eq!(fmt_sig(0.071_49, 2), "0.071");
    assert_eq!(fmt_sig(1234.5, 2), "1200");
    assert_eq!(fmt_sig(9.996, 3), "10.0");
    assert_eq!(fmt_sig(-0.5, 1), "-0.5");
    assert_eq!(fmt_sig(0.0, 3), "0.00");
    assert_eq!(fmt_sig(8.3776e11, 3), "8.38e11");
    assert_eq!(fmt_sig(4.6e-6, 2), "4.6e-6");
    assert_eq!(fmt_sig(99_999.0, 5), "99999");
    assert_eq!(fmt_sig(99_999.0, 4), "1.000e5");
    assert_eq!(fmt_sig(f64::NAN, 3), "NaN");
    assert_eq!(fmt_sig(f64::NEG_INFINITY, 3), "-inf");
    assert_eq!(fmt_interval(0.98, 1.04, 3), "[0.980, 1.04]");
}

#[test]
fn fmt_sig_output_parses_back_within_half_a_unit_in_the_last_digit() {
    for &x in &[1.234_567e-7, 0.000_987_6, 0.5, 2.5173, 271.828, 12_345.678, 6.02e23, -42.4242] {
        for sig in 1..=6 {
            let s = fmt_sig(x, sig);
            let back: f64 = s.parse().unwrap();
            let ulp = 10f64.powi(x.abs().log10().floor() as i32 - sig as i32 + 1);
            // half a unit in the last kept digit, plus float slack for the exponent step
            assert!((back - x).abs() <= 0.5 * ulp * (1.0 + 1e-9) + 1e-300, "{x} {sig} -> {s}");
        }
    }
}
