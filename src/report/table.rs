//! Plain tables (Markdown, CSV) and number formatting.
//!
//! CSV is written by hand rather than with a CSV crate because none is among
//! the project's dependencies and the writer needs only RFC 4180 quoting.

/// A table of already-formatted cells.
///
/// Rows may be shorter or longer than `headers`: both renderers use as many
/// columns as the widest line and leave missing cells empty, so no cell is
/// ever dropped silently.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Table {
    pub headers: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// An empty table with these column headers.
    pub fn new<S: Into<String>>(headers: impl IntoIterator<Item = S>) -> Self {
        Self { headers: headers.into_iter().map(Into::into).collect(), rows: Vec::new() }
    }

    /// Appends a row.
    pub fn push_row<S: Into<String>>(&mut self, row: impl IntoIterator<Item = S>) -> &mut Self {
        self.rows.push(row.into_iter().map(Into::into).collect());
        self
    }

    fn n_columns(&self) -> usize {
        self.rows.iter().map(Vec::len).chain(std::iter::once(self.headers.len())).max().unwrap_or(0)
    }

    /// GitHub-flavoured Markdown: a header line, a `---` separator line and
    /// one line per row, columns padded to equal width (in characters).
    /// `|` in a cell is escaped as `\|`, a line break becomes `<br>`.
    pub fn to_markdown(&self) -> String {
        let n = self.n_columns();
        let escape = |s: &str| s.replace('|', "\\|").replace("\r\n", "<br>").replace('\n', "<br>");
        let pad = |line: &[String]| -> Vec<String> {
            (0..n).map(|i| line.get(i).map(|s| escape(s)).unwrap_or_default()).collect()
        };
        let header = pad(&self.headers);
        let body: Vec<Vec<String>> = self.rows.iter().map(|r| pad(r)).collect();
        let widths: Vec<usize> = (0..n)
            .map(|i| {
                std::iter::once(&header)
                    .chain(body.iter())
                    .map(|line| line[i].chars().count())
                    .max()
                    .unwrap_or(0)
                    .max(3)
            })
            .collect();
        let render = |line: &[String]| -> String {
            let cells: Vec<String> =
                line.iter().zip(&widths).map(|(c, &w)| format!("{c}{}", " ".repeat(w - c.chars().count()))).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut out = render(&header);
        let dashes: Vec<String> = widths.iter().map(|&w| "-".repeat(w)).collect();
        out.push_str(&format!("| {} |\n", dashes.join(" | ")));
        for line in &body {
            out.push_str(&render(line));
        }
        out
    }

    /// RFC 4180 CSV with `\n` line ends: a field is quoted when it contains
    /// a comma, a double quote, a line break, or leading/trailing spaces;
    /// inside quotes a `"` is doubled.
    pub fn to_csv(&self) -> String {
        let n = self.n_columns();
        let mut out = String::new();
        for line in std::iter::once(&self.headers).chain(self.rows.iter()) {
            let cells: Vec<String> = (0..n).map(|i| csv_field(line.get(i).map(String::as_str).unwrap_or(""))).collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }
}

/// One CSV field, quoted when needed (see [`Table::to_csv`]).
pub fn csv_field(s: &str) -> String {
    let needs_quotes = s.contains([',', '"', '\n', '\r']) || s.starts_with(' ') || s.ends_with(' ');
    if needs_quotes {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `x` rounded to `sig` significant digits (`sig` ≥ 1; 0 is treated as 1).
///
/// Fixed notation when the decimal exponent of the rounded value lies in
/// [-3, 5), e.g. `fmt_sig(133.333, 3) = "133"`, `fmt_sig(0.0715, 2) = "0.072"`;
/// scientific otherwise, e.g. `fmt_sig(8.3776e11, 3) = "8.38e11"`,
/// `fmt_sig(4.6e-6, 2) = "4.6e-6"`. Zero is `0` followed by `sig - 1`
/// decimals; NaN and infinities print as `NaN`, `inf`, `-inf`.
pub fn fmt_sig(x: f64, sig: usize) -> String {
    let sig = sig.max(1);
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    // Rust's `{:e}` rounds to the requested mantissa digits and reports the
    // exponent *after* rounding (9.996 -> 1.00e1), which is what decides the
    // notation.
    let sci = format!("{:.*e}", sig - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("`{:e}` output always has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` exponent is an integer");
    if x == 0.0 || (-3..5).contains(&exp) {
        // Format the already-rounded value so that digits beyond `sig` are
        // zeros (1234.5 at 2 digits -> "1200") and no second rounding occurs.
        let rounded: f64 = sci.parse().expect("`{:e}` output parses back");
        let decimals = (sig as i32 - 1 - if x == 0.0 { 0 } else { exp }).max(0) as usize;
        format!("{:.*}", decimals, rounded)
    } else {
        format!("{mantissa}e{exp}")
    }
}

/// An interval `[lo, hi]` with both ends at `sig` significant digits.
pub fn fmt_interval(lo: f64, hi: f64, sig: usize) -> String {
    format!("[{}, {}]", fmt_sig(lo, sig), fmt_sig(hi, sig))
}
