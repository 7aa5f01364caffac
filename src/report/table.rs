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

/// Reusable buffers of [`Self::push_lower_exp`] and [`Self::push_int`].
pub struct NumberFormatter {
    float: zmij::Buffer,
    int: itoa::Buffer,
}

impl Default for NumberFormatter {
    fn default() -> Self {
        Self { float: zmij::Buffer::new(), int: itoa::Buffer::default() }
    }
}

impl NumberFormatter {
    /// Appends exactly what `write!(out, "{x:e}")` appends (Rust's shortest
    /// round-trip digits in scientific form: `3e11`, `-1.05e0`, `0e0`, `NaN`,
    /// `inf`), several times faster: the digits come from `zmij` (Schubfach
    /// family: shortest round-trip, closest to x, the same digit string as
    /// core's Grisu/Dragon shortest mode, checked on random bit patterns in
    /// the tests below) and are rearranged here from its positional/exponent
    /// layout. zmij replaced `ryu` (faster digit generation, `benches/README.md`, "Measurements cited by src/"; zmij is the crate
    /// serde_json itself uses now, already in the lock file). Where two shortest candidates are
    /// equally close (an exact decimal tie, see [`may_tie`]) the shortest-digit
    /// libraries round to even and core rounds up, so those few values go
    /// through core.
    pub fn push_lower_exp(&mut self, out: &mut String, x: f64) {
        if !x.is_finite() || x == 0.0 || may_tie(x) {
            use std::fmt::Write as _;
            let _ = write!(out, "{x:e}");
            return;
        }
        let s = self.float.format_finite(x).as_bytes();
        let (negative, s) = match s.split_first() {
            Some((b'-', rest)) => (true, rest),
            _ => (false, s),
        };
        // zmij writes "ddd.ddd", "0.000ddd", "d.ddde[+-]dd" or "de[+-]dd"
        let (mantissa, exponent) = match s.iter().position(|&c| c == b'e') {
            Some(i) => {
                let (sign, digits) = match &s[i + 1..] {
                    [b'-', rest @ ..] => (-1, rest),
                    [b'+', rest @ ..] => (1, rest),
                    rest => (1, rest),
                };
                (&s[..i], sign * digits.iter().fold(0i32, |acc, &d| 10 * acc + i32::from(d - b'0')))
            }
            None => (s, 0),
        };
        // the longest mantissa is "0.0000" + 17 digits or 17 digits + ".0"
        let mut digits = [0u8; 32];
        let (mut n, mut point) = (0usize, None);
        for &c in mantissa {
            if c == b'.' {
                point = Some(n);
            } else {
                digits[n] = c;
                n += 1;
            }
        }
        // value = 0.d₁d₂… × 10^(point + exponent)
        let mut point = point.unwrap_or(n) as i32;
        let mut start = 0;
        while start < n && digits[start] == b'0' {
            start += 1;
            point -= 1;
        }
        let mut end = n;
        while end > start + 1 && digits[end - 1] == b'0' {
            end -= 1;
        }
        // sign, digit, '.', ≤ 16 digits: assembled in one buffer, pushed once
        let mut text = [0u8; 20];
        let mut len = 0;
        if negative {
            text[0] = b'-';
            len = 1;
        }
        text[len] = digits[start];
        len += 1;
        if end > start + 1 {
            text[len] = b'.';
            len += 1;
            text[len..len + end - start - 1].copy_from_slice(&digits[start + 1..end]);
            len += end - start - 1;
        }
        text[len] = b'e';
        len += 1;
        // ASCII only (pushing it char by char instead of validating it as
        // UTF-8 was measured slower: 7 % of a calibrate instead of ~1 %)
        out.push_str(std::str::from_utf8(&text[..len]).unwrap_or_default());
        out.push_str(self.int.format(point - 1 + exponent));
    }

    /// Appends the decimal form of an integer (what `write!(out, "{i}")` appends).
    pub fn push_int<I: itoa::Integer>(&mut self, out: &mut String, i: I) {
        out.push_str(self.int.format(i));
    }
}

/// Whether the shortest digits of x can be an exact tie between two
/// candidates. A tie at n ≤ 17 digits needs x's exact decimal expansion to end
/// in a 5 at digit n + 1, so to have at most 18 significant digits. With
/// x = m·2^e, m odd: for e ≥ 0 (an integer) below 2^53 the exact integer is the
/// only candidate of its length (the rounding interval is ±½ ulp ≤ ½); for
/// e < 0 the expansion m·5^(−e)·10^e has exactly as many significant digits as
/// the odd integer m·5^(−e), at least log10(m) + (−e)·log10 5. Conservative
/// (false positives only cost speed): anything with fewer than 20 is a candidate.
/// Chain draws (52-bit mantissas, e ≤ −14) need ≥ 25 digits: never here.
fn may_tie(x: f64) -> bool {
    const LOG10_5: f64 = 0.698_970_004_336_018_8;
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1u64 << 52) - 1);
    let (mut m, mut e) = if biased == 0 { (fraction, -1074) } else { (fraction | (1u64 << 52), biased - 1075) };
    let tz = m.trailing_zeros();
    m >>= tz;
    e += i64::from(tz);
    if e >= 0 {
        return x.abs() >= 9_007_199_254_740_992.0; // 2^53
    }
    let bit_length = 64 - m.leading_zeros();
    let min_digits = f64::from(bit_length - 1) * std::f64::consts::LOG10_2 + (-e) as f64 * LOG10_5;
    min_digits < 20.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Byte-identical to `{:e}` on 200 000 random bit patterns (every
    /// exponent and sign; NaN/∞ included) and on the edge values.
    #[test]
    fn push_lower_exp_equals_core_formatting() {
        let mut f = NumberFormatter::default();
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            3e11,
            1.05,
            1e-5,
            1e16,
            1e15,
            123456789012345680.0,
            0.1,
            f64::MIN_POSITIVE,
            f64::MAX,
            5e-324,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            // exact ties: zmij (like ryu) rounds these to even, core up
            f64::from_bits(0x4312_9879_088f_f039),
            1.25,
            9_007_199_254_740_993.0 * 2.0,
            1e23,
        ];
        // every double of the form k/2^j with few bits (short exact expansions)
        for j in 0..60 {
            for k in [1u64, 3, 5, 7, 1001, (1 << 52) + 1, (1 << 53) - 1] {
                values.push(k as f64 / 2f64.powi(j));
                values.push(k as f64 * 2f64.powi(j));
            }
        }
        for _ in 0..200_000 {
            // splitmix64
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            values.push(f64::from_bits(z ^ (z >> 31)));
        }
        // and values like a chain's: a few significant digits at every scale
        for k in -30..30 {
            values.push(1.05 * 10f64.powi(k));
            values.push(-(3.0f64).powi(k));
        }
        for x in values {
            let mut s = String::new();
            f.push_lower_exp(&mut s, x);
            assert_eq!(s, format!("{x:e}"), "bits {:#x}", x.to_bits());
        }
        let mut s = String::new();
        f.push_int(&mut s, 19_999usize);
        assert_eq!(s, "19999");
    }
}
