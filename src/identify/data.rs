//! The measured records `nanobeam identify` reads, recognised from the CSV
//! header (exact names, units in them):
//!
//! | header | kind |
//! |---|---|
//! | `omega_rad_s,h_re_m_per_n,h_im_m_per_n` | complex receptance (swept sine, FRF estimate) |
//! | `omega_rad_s,h_abs_m_per_n` | receptance magnitude only |
//! | `omega_rad_s,psd_m2_s_per_rad` | displacement power spectral density |
//! | `time_s,displacement_m` | free decay / impulse response, uniform sampling |
//! | `time_s,thermal_<name>_m[,…]` | thermal motion, uniform sampling: turned into the PSD record ([`super::thermal`]) |
//!
//! Lab units are accepted under their own names ([`UNIT_ALIASES`]):
//! `frequency_hz` for `omega_rad_s`, `h_db_re_1_m_per_n` for
//! `h_abs_m_per_n`, and `psd_{one,two}_sided_m2_per_hz` /
//! `psd_{one,two}_sided_m2_s_per_rad` for `psd_m2_s_per_rad` (one-sided per
//! rad/s), converted on reading; messages name the record's own column.
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

use crate::error::{clip, fmt_num, InputError};

/// Fewest rows any record may have (the smallest fit, one mode and a
/// constant, has 5 real parameters).
pub const MIN_ROWS: usize = 8;

/// Most data rows a record may have. The identification needs 3 samples in
/// each mode's half-power band 2ζω: on a uniform grid up to ω_max, a mode at
/// ω_max/10 with ζ = 1e-4 (a quality factor of 5 000, lighter damping than
/// the nanotube measurements the paper fits) needs a step ≤ 2ζω/3 ≈
/// 6.7e-6·ω_max, i.e. 1.5e5 rows; a ring-down sampled at the same rate and
/// long enough for that mode to decay needs as many. 2e5 leaves margin. Larger
/// records cost time and memory linearly (`benches/README.md`, "Measurements cited by src/") and are checked while reading, before they are held in memory.
pub const MAX_ROWS: usize = 200_000;

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

/// Other accepted column names, in the units labs write, with the canonical
/// column each is read as and the factor or conversion applied on reading:
/// frequency in Hz (ω = 2πf); magnitude in dB re 1 m/N (|H| = 10^(dB/20));
/// PSDs one- or two-sided, per Hz or per rad/s. A one-sided PSD holds the
/// whole variance over f ≥ 0 (twice a two-sided one there), and
/// S(ω) dω = S(f) df with dω = 2π df, so S_ω = S_f/(2π).
pub const UNIT_ALIASES: [(&str, &str, Conversion); 6] = [
    ("frequency_hz", "omega_rad_s", Conversion::Scale(std::f64::consts::TAU)),
    ("h_db_re_1_m_per_n", "h_abs_m_per_n", Conversion::Decibel),
    ("psd_one_sided_m2_per_hz", "psd_m2_s_per_rad", Conversion::Scale(1.0 / std::f64::consts::TAU)),
    ("psd_two_sided_m2_per_hz", "psd_m2_s_per_rad", Conversion::Scale(1.0 / std::f64::consts::PI)),
    ("psd_one_sided_m2_s_per_rad", "psd_m2_s_per_rad", Conversion::Scale(1.0)),
    ("psd_two_sided_m2_s_per_rad", "psd_m2_s_per_rad", Conversion::Scale(2.0)),
];

/// How an alias column's values become the canonical column's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conversion {
    /// Multiply by the factor.
    Scale(f64),
    /// 20·log₁₀ amplitude → amplitude.
    Decibel,
}

impl Conversion {
    /// The values whose conversion is finite, in the column's own unit.
    fn limit(self) -> String {
        match self {
            Conversion::Scale(k) => format!("|value| <= {:.4e}", f64::MAX / k.abs()),
            Conversion::Decibel => format!("<= {:.1} dB", 20.0 * f64::MAX.log10() - 0.05),
        }
    }

    fn apply(self, v: f64) -> f64 {
        match self {
            Conversion::Scale(k) => v * k,
            Conversion::Decibel => 10f64.powf(v / 20.0),
        }
    }
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
        // flexible: a line of whitespace alone is one empty field, skipped
        // below as the reader skips an empty line; every other row must have
        // the header's field count (checked below, naming the row)
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .flexible(true)
            .from_reader(text.as_bytes());
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| {
                let line = text.lines().next().unwrap_or("");
                InputError::new("header", format!("`{}`", clip(line)), format!("a CSV header line ({e})"))
            })?
            .iter()
            .map(str::to_string)
            .collect();
        // an empty name: a trailing comma (issue 69: it was blamed on a valid column)
        if let Some(i) = header.iter().position(String::is_empty) {
            return Err(InputError::new(
                format!("column {} of {}", i + 1, header.len()),
                "''",
                "a named column (a trailing comma on the header line adds an empty one)",
            ));
        }
        let alias = |n: &str| UNIT_ALIASES.iter().find(|a| a.0 == n).copied();
        // a thermal-motion record (`thermal`) is read like a time record with more columns
        let thermal = super::thermal::is_thermal(&header);
        let canonical: Vec<String> = header.iter().map(|n| alias(n).map_or(n.clone(), |a| a.1.to_string())).collect();
        let kind = if thermal { 3 } else { kind_of(&canonical)? };
        // the names in messages are the record's own
        let shown: Vec<&str> = header.iter().map(String::as_str).collect();
        let names: &[&str] = &shown;
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let mut row = 0;
        for record in reader.records() {
            if record.as_ref().is_ok_and(|r| r.iter().all(str::is_empty)) {
                continue;
            }
            row += 1;
            if row > MAX_ROWS {
                return Err(InputError::new(
                    "rows",
                    format!("more than {MAX_ROWS}"),
                    format!("<= {MAX_ROWS} data rows (3 samples per half-power band of a mode with zeta = 1e-4 at a tenth of the top frequency need 1.5e5)"),
                ));
            }
            let record = record.map_err(|e| {
                let line = e.position().and_then(|p| text.lines().nth((p.line() as usize).saturating_sub(1)));
                InputError::new(
                    format!("row {row}"),
                    format!("`{}`", clip(line.unwrap_or(""))),
                    format!("a CSV row of {} fields ({e})", names.len()),
                )
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
        // the abscissa's order and sign in the user's units (a `frequency_hz`
        // of -1e9 was shown as -6.2832e9), then again in SI below
        check_abscissa(names[0], &columns[0])?;
        // the response column as written, for messages (issue 69)
        let raw_y = names.get(1).and_then(|n| alias(n)).map(|_| columns[1].clone());
        for (c, col) in columns.iter_mut().enumerate() {
            if let Some((_, canonical, conversion)) = alias(names[c]) {
                for (r, v) in col.iter_mut().enumerate() {
                    let converted = conversion.apply(*v);
                    if !converted.is_finite() {
                        return Err(InputError::new(
                            format!("{} (row {})", names[c], r + 1),
                            fmt_num(*v),
                            format!("{} (finite as {canonical})", conversion.limit()),
                        ));
                    }
                    *v = converted;
                }
            }
        }
        check_abscissa(names[0], &columns[0])?;
        let written = |e: InputError| as_written(e, raw_y.as_deref(), canonical.get(1).map_or("", String::as_str));
        let mut cols = columns.into_iter();
        let x = cols.next().unwrap_or_default();
        let y = cols.next().unwrap_or_default();
        Ok(match kind {
            0 => {
                let im = cols.next().unwrap_or_default();
                let h: Vec<Complex64> = y.iter().zip(&im).map(|(&re, &im)| Complex64::new(re, im)).collect();
                check_modulus(&h)?;
                check_not_all_zero("h_re_m_per_n,h_im_m_per_n", h.iter().all(|z| z.norm() == 0.0), h.len())?;
                Self::Complex { omega_rad_s: x, h_m_per_n: h }
            }
            1 => {
                let bound = max_abs_response(y.len());
                check_each(
                    names[1],
                    &y,
                    |v| (0.0..=bound).contains(&v),
                    &format!("in [0, {bound:e}] (sqrt(1.8e308 / rows))"),
                )
                .map_err(written)?;
                check_not_all_zero(names[1], y.iter().all(|&v| v == 0.0), y.len())?;
                Self::Magnitude { omega_rad_s: x, h_abs_m_per_n: y }
            }
            2 => {
                check_each(names[1], &y, |v| v > 0.0, "> 0 (the PSD is fitted on a log scale)").map_err(written)?;
                Self::Psd { omega_rad_s: x, psd_m2_s_per_rad: y }
            }
            _ => {
                check_uniform(&x)?;
                let bound = max_abs_response(y.len());
                for (name, column) in names[1..].iter().zip(std::iter::once(&y).chain(cols.as_slice())) {
                    check_each(
                        name,
                        column,
                        |v| v.abs() <= bound,
                        &format!("|value| <= {bound:e} (sqrt(1.8e308 / rows))"),
                    )?;
                }
                check_not_all_zero(names[1], y.iter().all(|&v| v == 0.0), y.len())?;
                if thermal {
                    let segments: Vec<Vec<f64>> = std::iter::once(y).chain(cols).collect();
                    check_not_vanishing(&names[1..], &segments)?;
                    let (omega_rad_s, psd_m2_s_per_rad) = super::thermal::psd_of(&x, &segments)?;
                    return Ok(Self::Psd { omega_rad_s, psd_m2_s_per_rad });
                }
                Self::Time { time_s: x, displacement_m: y }
            }
        })
    }
}

/// "allowed" of an unknown header: the kinds by example, within the one
/// line's 200 characters (issue 69: every header was listed, 330 characters,
/// but the thermal one); docs/identify.md has them all with the unit aliases.
const KNOWN_KINDS: &str = "a record kind's header, e.g. omega_rad_s,h_abs_m_per_n or time_s,displacement_m or time_s,thermal_<name>_m (all: docs/identify.md)";

/// Index into [`HEADERS`] of a header, or the error naming the first unknown
/// (or the missing) column.
fn kind_of(header: &[String]) -> Result<usize, InputError> {
    if let Some(k) = HEADERS.iter().position(|h| h.len() == header.len() && h.iter().zip(header).all(|(a, b)| a == b)) {
        return Ok(k);
    }
    let known: Vec<&str> = HEADERS.iter().flat_map(|h| h.iter().copied()).collect();
    if let Some((i, name)) = header.iter().enumerate().find(|(_, n)| !known.contains(&n.as_str())) {
        return Err(InputError::new(format!("column {}", i + 1), format!("`{}`", clip(name)), KNOWN_KINDS));
    }
    Err(InputError::new("header", format!("`{}`", clip(&header.join(","))), KNOWN_KINDS))
}

/// An error on a converted response column shows the value as the record
/// writes it and says in which unit the range is (issue 69).
fn as_written(mut e: InputError, raw: Option<&[f64]>, canonical: &str) -> InputError {
    let row = e.field.rsplit_once("(row ").and_then(|(_, r)| r.trim_end_matches(')').parse::<usize>().ok());
    if let (Some(raw), Some(r)) = (raw, row) {
        if let Some(&v) = raw.get(r.wrapping_sub(1)) {
            e.allowed = format!("{}, checked as {canonical}", e.allowed);
            e.value = fmt_num(v);
        }
    }
    e
}

fn check_each(name: &str, v: &[f64], ok: impl Fn(f64) -> bool, allowed: &str) -> Result<(), InputError> {
    match v.iter().position(|&x| !ok(x)) {
        Some(i) => Err(InputError::new(format!("{name} (row {})", i + 1), fmt_num(v[i]), allowed)),
        None => Ok(()),
    }
}

fn check_abscissa(name: &str, x: &[f64]) -> Result<(), InputError> {
    if name != "time_s" {
        check_each(name, x, |v| v >= 0.0, ">= 0")?;
    }
    for i in 1..x.len() {
        if x[i] <= x[i - 1] {
            return Err(InputError::new(
                format!("{name} (row {})", i + 1),
                fmt_num(x[i]),
                format!("> {} (row {}): strictly increasing", fmt_num(x[i - 1]), i),
            ));
        }
    }
    Ok(())
}

/// Uniform sampling within 10⁻³ of the mean step (see the module doc). The
/// grid point k is interpolated between t_0 and t_last (never formed as
/// t_0 + k·(t_last − t_0)/(n − 1), whose difference overflows for times of
/// opposite sign near ±f64::MAX), and the span t_last − t_0 must itself be a
/// finite number of seconds: the fit works on times relative to t_0.
fn check_uniform(t: &[f64]) -> Result<(), InputError> {
    let n = t.len();
    let (first, last) = (t[0], t[n - 1]);
    let m = (n - 1) as f64;
    // each term is at most |t| / (n − 1): finite for finite times
    let dt = last / m - first / m;
    for (k, &tk) in t.iter().enumerate() {
        let s = k as f64 / m;
        let expected = first * (1.0 - s) + last * s;
        // an infinite deviation (opposite signs near f64::MAX) fails too
        if !((tk - expected).abs() <= 1e-3 * dt) {
            return Err(InputError::new(
                format!("time_s (row {})", k + 1),
                fmt_num(tk),
                format!("{expected:e} ± {:e} (uniform sampling, step {dt:e} s)", 1e-3 * dt),
            ));
        }
    }
    if !(last - first).is_finite() {
        return Err(InputError::new(
            format!("time_s (row {n})"),
            fmt_num(last),
            format!("a span time_s(row {n}) − time_s(row 1) <= {:e} s (finite; row 1 is {first:e})", f64::MAX),
        ));
    }
    Ok(())
}

/// Below this no displacement (m) is physical (65 decades below the Planck
/// length), and the PSD of values this small underflows to 0 (x²·Δt ≈
/// 1e-200·1e-14 is still normal, 1e-300² is not).
pub const MIN_DISPLACEMENT_M: f64 = 1e-100;

/// Issue 69: a thermal column of values like 1e-300 (not constant) was
/// refused as "a displacement column is constant": name the column, its
/// largest |value| and the unit. All-zero columns are left to the PSD's own check.
fn check_not_vanishing(names: &[&str], columns: &[Vec<f64>]) -> Result<(), InputError> {
    for (name, column) in names.iter().zip(columns) {
        let (row, largest) = column.iter().enumerate().map(|(r, v)| (r, v.abs())).fold((0, 0.0f64), |best, (r, v)| {
            if v > best.1 {
                (r, v)
            } else {
                best
            }
        });
        if largest > 0.0 && largest < MIN_DISPLACEMENT_M {
            return Err(InputError::new(
                format!("{name} (row {}, its largest |value|)", row + 1),
                fmt_num(column[row]),
                format!("displacements in metres, some |value| >= {MIN_DISPLACEMENT_M:e} (thermal motion is ~1e-11 m)"),
            ));
        }
    }
    Ok(())
}

/// The largest |response| of a record of `rows` rows that the fit can
/// square and sum: the residual sums, the noise model's b²|H|² and the
/// record's scale all add |y|² over the rows, which stays finite when every
/// |y| ≤ √(f64::MAX / rows) (1e308 + 1e308i has a finite modulus, 1.4e308,
/// but not a finite square).
fn max_abs_response(rows: usize) -> f64 {
    (f64::MAX / rows.max(1) as f64).sqrt()
}

/// Every complex value's modulus |h| = hypot(re, im) is within
/// [`max_abs_response`]: both parts below f64::MAX do not make it so.
fn check_modulus(h: &[Complex64]) -> Result<(), InputError> {
    let bound = max_abs_response(h.len());
    match h.iter().position(|z| !(z.norm() <= bound)) {
        Some(i) => Err(InputError::new(
            format!("h_re_m_per_n,h_im_m_per_n (row {})", i + 1),
            format!("{:e}{:+e}i (|h| = {:e})", h[i].re, h[i].im, h[i].norm()),
            format!("|h| = hypot(re, im) <= {bound:e} m/N (sqrt(1.8e308 / rows): the fit sums |h|^2 over the rows)"),
        )),
        None => Ok(()),
    }
}

/// A response that is zero on every row has no modes to identify: bad input
/// like a constant one, not a numerical failure of the fit.
fn check_not_all_zero(name: &str, all_zero: bool, rows: usize) -> Result<(), InputError> {
    if all_zero {
        return Err(InputError::new(
            format!("{name} (rows 1..={rows})"),
            "0 on every row",
            "a record with a nonzero response (an all-zero record has no modes)",
        ));
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

    /// Issue 69, defect 10: a line of whitespace alone was refused ("found
    /// record with 1 fields") though blank lines are skipped; now both are,
    /// and the rows after them keep their data-row numbers.
    #[test]
    fn whitespace_only_lines_are_skipped_like_blank_ones() {
        let clean = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},1e-9", i + 1));
        let spaced = clean.replacen("3,1e-9\n", "3,1e-9\n   \n\t\n", 1);
        assert_ne!(clean, spaced);
        let (a, b) = (Measurement::from_csv(&clean).unwrap(), Measurement::from_csv(&spaced).unwrap());
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        // a bad value after them is still named by its data row
        let bad = spaced.replacen("5,1e-9", "5,x", 1);
        let e = Measurement::from_csv(&bad).unwrap_err().to_string();
        assert!(e.contains("(row 5)"), "{e}");
        // a short row is still refused, naming the row
        let short = clean.replacen("4,1e-9", "4", 1);
        let e = Measurement::from_csv(&short).unwrap_err().to_string();
        assert!(e.contains("row 4") && e.contains("1 fields"), "{e}");
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

    /// Hz, dB and the PSD conventions read as their SI equivalents (values
    /// worked by hand: 1 kHz = 6283.185… rad/s, −180 dB = 1e-9 m/N, a
    /// two-sided 1e-20 m²/Hz = one-sided 2e-20 m²/Hz = 2e-20/(2π) m²s/rad).
    #[test]
    fn lab_units_convert_on_reading() {
        let hz = rows("frequency_hz,h_db_re_1_m_per_n", 10, |i| format!("{},-180", 1000 * (i + 1)));
        let Ok(Measurement::Magnitude { omega_rad_s, h_abs_m_per_n }) = Measurement::from_csv(&hz) else {
            panic!("magnitude in Hz and dB")
        };
        assert!((omega_rad_s[0] - 6283.185307179586).abs() < 1e-9);
        assert!((h_abs_m_per_n[3] / 1e-9 - 1.0).abs() < 1e-12);
        let psd = rows("frequency_hz,psd_two_sided_m2_per_hz", 10, |i| format!("{},1e-20", i + 1));
        let Ok(Measurement::Psd { psd_m2_s_per_rad, .. }) = Measurement::from_csv(&psd) else { panic!("psd") };
        assert!((psd_m2_s_per_rad[0] / (2e-20 / std::f64::consts::TAU) - 1.0).abs() < 1e-12);
        let back = rows("frequency_hz,h_db_re_1_m_per_n", 10, |i| format!("{},0", if i == 6 { 2 } else { i + 1 }));
        assert_eq!(Measurement::from_csv(&back).unwrap_err().field, "frequency_hz (row 7)");
        let huge =
            rows("frequency_hz,h_db_re_1_m_per_n", 10, |i| format!("{},{}", i + 1, if i == 2 { 1e5 } else { 0.0 }));
        assert_eq!(Measurement::from_csv(&huge).unwrap_err().field, "h_db_re_1_m_per_n (row 3)");
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

    #[test]
    fn all_zero_records_are_bad_input() {
        // issue 44, defect 5: exit 1 "no model order ... could be solved" before
        let c = rows("omega_rad_s,h_re_m_per_n,h_im_m_per_n", 10, |i| format!("{},0,0", i + 1));
        assert_eq!(Measurement::from_csv(&c).unwrap_err().field, "h_re_m_per_n,h_im_m_per_n (rows 1..=10)");
        let m = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},0", i + 1));
        assert_eq!(Measurement::from_csv(&m).unwrap_err().field, "h_abs_m_per_n (rows 1..=10)");
        let t = rows("time_s,displacement_m", 10, |i| format!("{i}e-12,0.0"));
        assert_eq!(Measurement::from_csv(&t).unwrap_err().field, "displacement_m (rows 1..=10)");
        // one nonzero row is a record
        let one = rows("time_s,displacement_m", 10, |i| format!("{i}e-12,{}", if i == 3 { 1e-12 } else { 0.0 }));
        assert!(Measurement::from_csv(&one).is_ok());
    }

    #[test]
    fn uniform_check_survives_times_near_the_largest_float() {
        // issue 44, defect 6: t_last − t_0 overflowed to inf and every row passed
        let n = 40;
        // the span 2e308 overflows: the grid is built by interpolation
        let grid = |k: usize| {
            let s = k as f64 / (n - 1) as f64;
            -1e308 * (1.0 - s) + 1e308 * s
        };
        let step = 2.0 * (1e308 / (n - 1) as f64);
        let off = rows("time_s,displacement_m", n, |i| {
            let t = if i == 17 { grid(i) + 0.4 * step } else { grid(i) };
            format!("{t:e},{}", if i % 2 == 0 { 1e-12 } else { -1e-12 })
        });
        let e = Measurement::from_csv(&off).unwrap_err();
        assert_eq!(e.field, "time_s (row 18)", "{e}");
        assert!(e.value.contains('e') && e.value.len() < 30, "shortest scientific form: {}", e.value);
        // on the grid, the span itself is not a finite number of seconds
        let on = rows("time_s,displacement_m", n, |i| format!("{:e},{}", grid(i), if i % 2 == 0 { 1.0 } else { -1.0 }));
        assert_eq!(Measurement::from_csv(&on).unwrap_err().field, format!("time_s (row {n})"));
    }

    #[test]
    fn an_overflowing_modulus_names_its_row() {
        // issue 44, user-hostile 10: exit 1 "no model order could be solved" before
        let c = rows("omega_rad_s,h_re_m_per_n,h_im_m_per_n", 10, |i| {
            if i == 6 {
                format!("{},1.5e308,1.5e308", i + 1)
            } else {
                format!("{},1e-9,-2e-9", i + 1)
            }
        });
        let e = Measurement::from_csv(&c).unwrap_err();
        assert_eq!(e.field, "h_re_m_per_n,h_im_m_per_n (row 7)", "{e}");
        // a finite modulus whose square overflows (issue 44 replay: it was
        // blamed on an under-sampled resonance with an infinite noise sd)
        let c = rows("omega_rad_s,h_re_m_per_n,h_im_m_per_n", 10, |i| {
            if i == 3 {
                format!("{},1e308,1e308", i + 1)
            } else {
                format!("{},1e-9,-2e-9", i + 1)
            }
        });
        assert_eq!(Measurement::from_csv(&c).unwrap_err().field, "h_re_m_per_n,h_im_m_per_n (row 4)");
        let m = rows("omega_rad_s,h_abs_m_per_n", 10, |i| format!("{},{}", i + 1, if i == 2 { 1e160 } else { 1e-9 }));
        assert_eq!(Measurement::from_csv(&m).unwrap_err().field, "h_abs_m_per_n (row 3)");
    }
}
