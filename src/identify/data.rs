//! The measured records `nanobeam identify` reads, recognised from the CSV
//! header (exact names, units in them):
//!
//! | header | kind |
//! |---|---|
//! | `omega_rad_s,h_re_m_per_n,h_im_m_per_n` | complex receptance (swept sine, FRF estimate) |
//! | `omega_rad_s,h_abs_m_per_n` | receptance magnitude only |
//! | `omega_rad_s,psd_m2_s_per_rad` | displacement power spectral density |
//! | `time_s,displacement_m` | free decay / impulse response, uniform sampling |
//! | `time_s,thermal_<name>_m[,…]` | thermal motion, uniform sampling: turned into the PSD record ([`thermal`]) |
//!
//! Accepted layout (what lab software writes): comma-separated, the header
//! line first with exactly those names; LF or CRLF line endings; spaces or
//! tabs around any field or name; a UTF-8 byte-order mark before the header;
//! empty lines (e.g. a trailing newline) are skipped; numbers in any form
//! Rust's `f64` parser reads (`1e-9`, `1.0E-09`, `0.001`). Not accepted:
//! other separators, comment lines, quoted units or extra columns.
//!
//! Rules (each broken rule is one [`InputError`] naming the column, the data
//! row — 1-based, the header not counted — the value and what is allowed):
//! every value finite; frequencies ≥ 0 and strictly increasing; magnitudes
//! ≥ 0 and PSD values > 0 (the PSD is fitted on a log scale); times strictly
//! increasing and uniform: |t_k − t_0 − k·Δt| ≤ 10⁻³·Δt with
//! Δt = (t_last − t_0)/(n − 1). That tolerance admits the rounding of times
//! printed with ≥ 7 significant digits over ≤ 10⁴ samples (relative rounding
//! 5·10⁻⁷ of t ≤ 10⁴Δt is ≤ 5·10⁻³Δt only beyond that), while a timing error
//! of 10⁻³Δt moves a sample of a mode below the Nyquist frequency by at most
//! π·10⁻³ of its amplitude.

use num_complex::Complex64;

use crate::error::InputError;

#[path = "thermal.rs"]
mod thermal;

/// Fewest rows any record may have (the smallest fit, one mode and a
/// constant, has 5 real parameters).
pub const MIN_ROWS: usize = 8;

/// A measured record.
#[derive(Debug, Clone, PartialEq)]
pub enum Measurement {
    /// Complex receptance H(ω) in m/N.
    Complex { omega_rad_s: Vec<f64>, h_m_per_n: Vec<Complex64> },
    /// |H(ω)| in m/N.
    Magnitude { omega_rad_s: Vec<f64>, h_abs_m_per_n: Vec<f64> },
    /// One-sided displacement PSD in m²·s/rad.
    Psd { omega_rad_s: Vec<f64>, psd_m2_s_per_rad: Vec<f64> },
    /// Uniformly sampled displacement in m.
    Time { time_s: Vec<f64>, displacement_m: Vec<f64> },
}

/// The accepted headers, in the order of [`Measurement`]'s variants.
pub const HEADERS: [&[&str]; 4] = [
    &["omega_rad_s", "h_re_m_per_n", "h_im_m_per_n"],
    &["omega_rad_s", "h_abs_m_per_n"],
    &["omega_rad_s", "psd_m2_s_per_rad"],
    &["time_s", "displacement_m"],
];

fn allowed_headers() -> String {
    HEADERS.iter().map(|h| h.join(",")).collect::<Vec<_>>().join(" | ")
}

impl Measurement {
    /// Number of samples.
    pub fn len(&self) -> usize {
        match self {
            Self::Complex { omega_rad_s, .. } | Self::Magnitude { omega_rad_s, .. } | Self::Psd { omega_rad_s, .. } => {
                omega_rad_s.len()
            }
            Self::Time { time_s, .. } => time_s.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The name of the abscissa column.
    pub fn abscissa_name(&self) -> &'static str {
        match self {
            Self::Time { .. } => "time_s",
            _ => "omega_rad_s",
        }
    }

    /// Parses and validates a CSV record (header line first).
    pub fn from_csv(text: &str) -> Result<Self, InputError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut reader = csv::ReaderBuilder::new().has_headers(true).trim(csv::Trim::All).from_reader(text.as_bytes());
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| InputError::new("header", "(unreadable)", format!("a CSV header line ({e})")))?
            .iter()
            .map(str::to_string)
            .collect();
        // a thermal-motion record (thermal.rs) is read like a time record with more columns
        let thermal = thermal::is_thermal(&header);
        let kind = if thermal { 3 } else { kind_of(&header)? };
        let names: Vec<&str> =
            if thermal { header.iter().map(String::as_str).collect() } else { HEADERS[kind].to_vec() };
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        for (r, record) in reader.records().enumerate() {
            let row = r + 1;
            let record = record.map_err(|e| {
                InputError::new(format!("row {row}"), "(unreadable)", format!("{} fields ({e})", names.len()))
            })?;
            if record.len() != names.len() {
                return Err(InputError::new(
                    format!("row {row}"),
                    format!("{} fields", record.len()),
                    format!("{} fields ({})", names.len(), names.join(",")),
                ));
            }
            for (c, field) in record.iter().enumerate() {
                let v: f64 = field.parse().map_err(|_| {
                    InputError::new(format!("{} (row {row})", names[c]), format!("`{field}`"), "a finite number")
                })?;
                if !v.is_finite() {
                    return Err(InputError::new(format!("{} (row {row})", names[c]), v, "a finite number"));
                }
                columns[c].push(v);
            }
        }
        if columns[0].len() < MIN_ROWS {
            return Err(InputError::new("rows", columns[0].len(), format!(">= {MIN_ROWS} data rows")));
        }
        check_abscissa(names[0], &columns[0])?;
        let mut cols = columns.into_iter();
        let x = cols.next().unwrap_or_default();
        let y = cols.next().unwrap_or_default();
        Ok(match kind {
            0 => {
                let im = cols.next().unwrap_or_default();
                let h = y.iter().zip(&im).map(|(&re, &im)| Complex64::new(re, im)).collect();
                Self::Complex { omega_rad_s: x, h_m_per_n: h }
            }
            1 => {
                check_each(names[1], &y, |v| v >= 0.0, ">= 0")?;
                Self::Magnitude { omega_rad_s: x, h_abs_m_per_n: y }
            }
            2 => {
                check_each(names[1], &y, |v| v > 0.0, "> 0 (the PSD is fitted on a log scale)")?;
                Self::Psd { omega_rad_s: x, psd_m2_s_per_rad: y }
            }
            _ => {
                check_uniform(&x)?;
                if thermal {
                    return thermal::psd_record(&x, &std::iter::once(y).chain(cols).collect::<Vec<_>>());
                }
                Self::Time { time_s: x, displacement_m: y }
            }
        })
    }
}

/// Index into [`HEADERS`] of a header, or the error naming the first unknown
/// (or the missing) column.
fn kind_of(header: &[String]) -> Result<usize, InputError> {
    if let Some(k) = HEADERS.iter().position(|h| h.len() == header.len() && h.iter().zip(header).all(|(a, b)| a == b)) {
        return Ok(k);
    }
    let known: Vec<&str> = HEADERS.iter().flat_map(|h| h.iter().copied()).collect();
    if let Some((i, name)) = header.iter().enumerate().find(|(_, n)| !known.contains(&n.as_str())) {
        return Err(InputError::new(
            format!("column {}", i + 1),
            format!("`{name}`"),
            format!("a known column; headers: {}", allowed_headers()),
        ));
    }
    Err(InputError::new("header", format!("`{}`", header.join(",")), format!("one of: {}", allowed_headers())))
}

fn check_each(name: &str, v: &[f64], ok: impl Fn(f64) -> bool, allowed: &str) -> Result<(), InputError> {
    match v.iter().position(|&x| !ok(x)) {
        Some(i) => Err(InputError::new(format!("{name} (row {})", i + 1), v[i], allowed)),
        None => Ok(()),
    }
}

fn check_abscissa(name: &str, x: &[f64]) -> Result<(), InputError> {
    if name == "omega_rad_s" {
        check_each(name, x, |v| v >= 0.0, ">= 0")?;
    }
    for i in 1..x.len() {
        if x[i] <= x[i - 1] {
            return Err(InputError::new(
                format!("{name} (row {})", i + 1),
                x[i],
                format!("> {} (row {}): strictly increasing", x[i - 1], i),
            ));
        }
    }
    Ok(())
}

/// Uniform sampling within 10⁻³ of the mean step (see the module doc).
fn check_uniform(t: &[f64]) -> Result<(), InputError> {
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    for (k, &tk) in t.iter().enumerate() {
        let expected = t[0] + k as f64 * dt;
        if (tk - expected).abs() > 1e-3 * dt {
            return Err(InputError::new(
                format!("time_s (row {})", k + 1),
                tk,
                format!("{expected:e} ± {:e} (uniform sampling, step {dt:e} s)", 1e-3 * dt),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(header: &str, n: usize, f: impl Fn(usize) -> String) -> String {
        let mut s = format!("{header}\n");
        for i in 0..n {
            s.push_str(&f(i));
            s.push('\n');
        }
        s
    }

    #[test]
    fn each_header_selects_its_kind() {
        let c = rows("omega_rad_s,h_re_m_per_n,h_im_m_per_n", 10, |i| format!("{},1e-9,-2e-9", i + 1));
        assert!(matches!(Measurement::from_csv(&c), Ok(Measurement::Complex { .. })));
        let m = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},1e-9", i + 1));
        assert!(matches!(Measurement::from_csv(&m), Ok(Measurement::Magnitude { .. })));
        let p = rows("omega_rad_s,psd_m2_s_per_rad", 10, |i| format!("{},1e-30", i + 1));
        assert!(matches!(Measurement::from_csv(&p), Ok(Measurement::Psd { .. })));
        let t = rows("time_s,displacement_m", 10, |i| format!("{:e},1e-12", i as f64 * 1e-13));
        assert!(matches!(Measurement::from_csv(&t), Ok(Measurement::Time { .. })));
    }

    #[test]
    fn lab_layouts_read_like_the_plain_one() {
        let plain = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},{}e-12", i + 1, i + 2));
        let lab = format!(
            "\u{feff} omega_rad_s ,\th_abs_m_per_n\r\n{}\r\n\r\n",
            (0..10).map(|i| format!(" {}.0 , {}.0E-12 ", i + 1, i + 2)).collect::<Vec<_>>().join("\r\n")
        );
        assert_eq!(Measurement::from_csv(&lab).unwrap(), Measurement::from_csv(&plain).unwrap());
        let semicolon = rows("omega_rad_s;h_abs_m_per_n", 10, |i| format!("{};1", i + 1));
        assert_eq!(Measurement::from_csv(&semicolon).unwrap_err().field, "column 1");
    }

    #[test]
    fn bad_records_name_column_row_and_rule() {
        let unknown = rows("omega_rad_s,h_real", 10, |i| format!("{i},1"));
        let e = Measurement::from_csv(&unknown).unwrap_err();
        assert_eq!((e.field.as_str(), e.value.as_str()), ("column 2", "`h_real`"));
        let missing = rows("omega_rad_s,h_re_m_per_n", 10, |i| format!("{i},1"));
        assert_eq!(Measurement::from_csv(&missing).unwrap_err().field, "header");
        let nan =
            rows("omega_rad_s,h_abs_m_per_n", 10, |i| if i == 4 { "5,NaN".into() } else { format!("{},1", i + 1) });
        assert_eq!(Measurement::from_csv(&nan).unwrap_err().field, "h_abs_m_per_n (row 5)");
        let back = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},1", if i == 6 { 2 } else { i + 1 }));
        assert_eq!(Measurement::from_csv(&back).unwrap_err().field, "omega_rad_s (row 7)");
        let jitter = rows("time_s,displacement_m", 10, |i| format!("{:e},0", if i == 3 { 3.1 } else { i as f64 }));
        assert_eq!(Measurement::from_csv(&jitter).unwrap_err().field, "time_s (row 4)");
        let short = rows("omega_rad_s,h_abs_m_per_n", 3, |i| format!("{},1", i + 1));
        assert_eq!(Measurement::from_csv(&short).unwrap_err().field, "rows");
        let ragged =
            rows("omega_rad_s,h_abs_m_per_n", 10, |i| if i == 2 { "3".into() } else { format!("{},1", i + 1) });
        assert_eq!(Measurement::from_csv(&ragged).unwrap_err().field, "row 3");
    }
}
