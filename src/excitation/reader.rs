//! Readers for ground-acceleration files: PEER NGA AT2 (both header styles), plain two-column
//! (t, a) and one-column files with a known dt. Every error names the file and the line.

use super::G;
use super::record::Series;
use crate::numfmt::fmt_exact;
use std::fmt;

/// A file that cannot be read as an acceleration history.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ParseError {
    /// File path or name of the embedded file.
    pub origin: String,
    /// 1-based line number; 0 when the problem concerns the file as a whole.
    pub line: usize,
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.origin, self.message)
        } else {
            write!(f, "{}:{}: {}", self.origin, self.line, self.message)
        }
    }
}

/// Units of the acceleration values in a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    G,
    CmPerS2,
    MPerS2,
}

impl Units {
    fn to_mps2(self) -> f64 {
        match self {
            Units::G => G,
            Units::CmPerS2 => 0.01,
            Units::MPerS2 => 1.0,
        }
    }

    /// Units named in free header text ("IN UNITS OF G", "# units: cm/s2 ..."): None if the
    /// text names no units, an error message if it names units that are not an acceleration's
    /// (a velocity record, `furlongs`).
    pub fn named_in(text: &str) -> Option<Result<Units, String>> {
        let t = text.to_ascii_lowercase();
        let tail = t
            .split_once("units of")
            .or_else(|| t.split_once("units:"))
            .map(|(_, rest)| rest.trim())?;
        let word = tail
            .split_whitespace()
            .next()
            .unwrap_or("")
            .trim_end_matches([',', '.', ';', ')', '(']);
        Some(Units::from_word(word))
    }

    /// Units of acceleration by name (`g`, `cm/s2`, `gal`, `m/s^2`, …).
    pub fn from_word(word: &str) -> Result<Units, String> {
        let w = word
            .to_ascii_lowercase()
            .replace("sec", "s")
            .replace("**", "^");
        let per_s2 = |unit: &str| {
            ["s2", "s^2", "s/s"]
                .iter()
                .any(|tail| w == format!("{unit}/{tail}"))
        };
        if w == "g" || w.starts_with("g(") {
            Ok(Units::G)
        } else if per_s2("cm") || w == "gal" {
            Ok(Units::CmPerS2)
        } else if per_s2("m") {
            Ok(Units::MPerS2)
        } else if ["cm/s", "m/s", "in/s", "cm", "m", "in"].contains(&w.as_str()) {
            Err(format!(
                "units '{}' are a velocity's or a displacement's: rocklab reads ground \
                 acceleration (g, cm/s2 or m/s2)",
                excerpt(word)
            ))
        } else {
            Err(format!(
                "unknown units '{}': expected g, cm/s2 (gal) or m/s2",
                excerpt(word)
            ))
        }
    }

    /// The unit's name as an index or header writes it.
    pub fn name(self) -> &'static str {
        match self {
            Units::G => "g",
            Units::CmPerS2 => "cm/s2",
            Units::MPerS2 => "m/s2",
        }
    }
}

/// The smallest time step accepted (s). Recorded motions are sampled at 0.001–0.02 s; steps
/// far below 1 µs are typos or garbage, and they would make a scene's breakpoints closer than
/// the integrator can resolve.
pub const MIN_DT: f64 = 1e-6;

/// The largest time step accepted (s): a sample a second or more apart records nothing a
/// rocking structure responds to, and a huge step (1e308) would make the record's length
/// infinite (reported as a bad duration the user never gave).
pub const MAX_DT: f64 = 1.0;

/// The largest ground acceleration a record may hold (m/s², 100 g). The strongest motions
/// ever recorded peak near 4 g; a value far past that is a file in other units than it says
/// (cm/s² read as g), a corrupt value, or garbage, and run as given it stalls the integrator
/// ("step size underflow") with no word of the file.
pub const MAX_ACCELERATION: f64 = 100.0 * G;

/// A sample of line `line`, in `units`, refused past [`MAX_ACCELERATION`].
fn plausible(value: f64, units: Units, origin: &str, line: usize) -> Result<(), ParseError> {
    if (value * units.to_mps2()).abs() <= MAX_ACCELERATION {
        return Ok(());
    }
    Err(err(
        origin,
        line,
        format!(
            "{} {} is not a plausible ground acceleration: the strongest recorded are near 4 g, \
             and rocklab reads at most 100 g; check the file's units (cm/s2 read as g?) and \
             values",
            fmt_exact(value),
            units.name()
        ),
    ))
}

/// A time step that is finite, at least [`MIN_DT`] and at most [`MAX_DT`].
fn checked_dt(dt: f64, origin: &str, line: usize, what: &str) -> Result<f64, ParseError> {
    if dt.is_finite() && (MIN_DT..=MAX_DT).contains(&dt) {
        Ok(dt)
    } else {
        Err(err(
            origin,
            line,
            format!(
                "{what} {} s is not a usable time step: it must be finite, ≥ {MIN_DT:e} s and \
                 ≤ {MAX_DT} s",
                fmt_exact(dt)
            ),
        ))
    }
}

/// Samples in m/s², each finite after the unit conversion.
fn scaled(
    values: impl Iterator<Item = f64>,
    scale: f64,
    origin: &str,
) -> Result<Vec<f64>, ParseError> {
    values
        .map(|v| v * scale)
        .map(|a| {
            a.is_finite()
                .then_some(a)
                .ok_or_else(|| err(origin, 0, "an acceleration overflows to infinity in m/s²"))
        })
        .collect()
}

/// Characters of a file's text a message quotes at most: a bad line may be megabytes long
/// (a binary file, a line without breaks), and the message must stay a line.
const EXCERPT_CHARS: usize = 60;

/// `text` trimmed, as a message quotes it: whole if short, else its start, `…` and its length.
pub fn excerpt(text: &str) -> String {
    let text = text.trim();
    match text.char_indices().nth(EXCERPT_CHARS) {
        None => text.to_string(),
        Some((cut, _)) => format!("{}… ({} characters)", &text[..cut], text.chars().count()),
    }
}

fn err(origin: &str, line: usize, message: impl Into<String>) -> ParseError {
    ParseError {
        origin: origin.to_string(),
        line,
        message: message.into(),
    }
}

/// Split one line into numbers. Handles separators (spaces, tabs, commas), Fortran `D`
/// exponents and values printed with no space between them (`1.234E-01-5.678E-02`), which
/// fixed-width AT2 writers produce when a value fills its field.
pub fn numbers_in(line: &str, origin: &str, line_no: usize) -> Result<Vec<f64>, ParseError> {
    let mut out = Vec::new();
    for token in line.split(|c: char| c.is_whitespace() || c == ',') {
        if token.is_empty() {
            continue;
        }
        let bytes = token.as_bytes();
        let mut start = 0;
        for i in 1..=bytes.len() {
            let boundary = i == bytes.len()
                || (matches!(bytes[i], b'+' | b'-')
                    && !matches!(bytes[i - 1], b'e' | b'E' | b'd' | b'D'));
            if boundary {
                let piece = &token[start..i];
                let value = piece
                    .replace(['d', 'D'], "E")
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        err(
                            origin,
                            line_no,
                            format!(
                                "'{}' is not a number (in '{}')",
                                excerpt(piece),
                                excerpt(line)
                            ),
                        )
                    })?;
                out.push(value);
                start = i;
            }
        }
    }
    Ok(out)
}

/// What a records index says of a file, checked against what the file says of itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Expected {
    /// Time step; a one-column file without a `# dt:` line takes it.
    pub dt: Option<f64>,
    /// Units; a file that names none takes them, one that names others is refused.
    pub units: Option<Units>,
    /// Number of samples.
    pub npts: Option<usize>,
}

/// Read an acceleration history. The format is detected from the content: a line mentioning
/// NPTS among the first six makes it an AT2 file; otherwise `#` comment lines may give
/// `dt:`, `units:` and `npts:`, and the data are one column (a, needs a dt from the header or
/// from `dt`) or two columns (t, a; uniform spacing required). Units default to g.
pub fn parse(text: &str, origin: &str, dt: Option<f64>) -> Result<Series, ParseError> {
    parse_expecting(
        text,
        origin,
        &Expected {
            dt,
            ..Expected::default()
        },
    )
}

/// [`parse`], refusing a file whose units or sample count disagree with `expected`.
pub fn parse_expecting(
    text: &str,
    origin: &str,
    expected: &Expected,
) -> Result<Series, ParseError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(err(origin, 0, "the file is empty"));
    }
    let is_at2 = text
        .lines()
        .take(6)
        .any(|l| !l.trim_start().starts_with('#') && l.to_ascii_uppercase().contains("NPTS"));
    let (series, named_units) = if is_at2 {
        parse_at2(text, origin, expected.units)?
    } else {
        parse_columns(text, origin, expected)?
    };
    if let (Some(want), Some((line, got))) = (expected.units, named_units)
        && want != got
    {
        return Err(err(
            origin,
            line,
            format!(
                "the file gives its values in {} but the records index says units: \"{}\"",
                got.name(),
                want.name()
            ),
        ));
    }
    if let Some(npts) = expected.npts
        && npts != series.npts()
    {
        return Err(err(
            origin,
            0,
            format!(
                "the records index says npts: {npts} but the file holds {} samples",
                series.npts()
            ),
        ));
    }
    Ok(series)
}

/// The units a header line names, with its line number (1-based), or the line's error.
fn header_units(
    line: &str,
    line_no: usize,
    origin: &str,
) -> Result<Option<(usize, Units)>, ParseError> {
    match Units::named_in(line) {
        None => Ok(None),
        Some(Ok(u)) => Ok(Some((line_no, u))),
        Some(Err(why)) => Err(err(origin, line_no, why)),
    }
}

/// PEER NGA AT2: free header lines, then a line with NPTS and DT in either the NGA-West1
/// style (`1991    0.0100    NPTS, DT`) or the NGA-West2 style (`NPTS=  1991, DT=   .0100 SEC`),
/// then the values in g (or in the units the header names), the same number on every line
/// but the last. A header naming velocity or displacement is refused; values past NPTS are
/// refused unless they are zeros filling the line that completes NPTS (padding some writers
/// add).
fn parse_at2(
    text: &str,
    origin: &str,
    default_units: Option<Units>,
) -> Result<(Series, Option<(usize, Units)>), ParseError> {
    let lines: Vec<&str> = text.lines().collect();
    let header_idx = lines
        .iter()
        .take(6)
        .position(|l| l.to_ascii_uppercase().contains("NPTS"))
        .expect("checked by the caller");
    let header_line = header_idx + 1;
    let (npts, dt) = at2_npts_dt(lines[header_idx], origin, header_line)?;
    let mut named = None;
    for (i, line) in lines[..header_idx].iter().enumerate() {
        let upper = line.to_ascii_uppercase();
        if (upper.contains("VELOCITY") || upper.contains("DISPLACEMENT"))
            && !upper.contains("ACCELERATION")
        {
            return Err(err(
                origin,
                i + 1,
                format!(
                    "the header says '{}': rocklab reads ground acceleration (an AT2 file), \
                     not velocity (VT2) or displacement (DT2)",
                    excerpt(line)
                ),
            ));
        }
        if named.is_none() {
            named = header_units(line, i + 1, origin)?;
        }
    }
    let units = named.map(|n| n.1).or(default_units).unwrap_or(Units::G);
    let dt = checked_dt(dt, origin, header_line, "DT")?;
    // Never trust the header with the allocation (NPTS = 1E12 asked for 8 TB): reserve what
    // the text can hold at most (two bytes per number), then compare with NPTS.
    let mut values = Vec::with_capacity(npts.min(text.len() / 2 + 1));
    let mut last_data_line = header_line;
    // (line, count) of the first data line: every later line but the last has as many.
    let mut width: Option<(usize, usize)> = None;
    let mut short_line: Option<usize> = None;
    for (i, line) in lines.iter().enumerate().skip(header_idx + 1) {
        let nums = numbers_in(line, origin, i + 1)?;
        if nums.is_empty() {
            continue;
        }
        for &v in &nums {
            plausible(v, units, origin, i + 1)?;
        }
        if values.len() >= npts {
            return Err(err(
                origin,
                i + 1,
                format!(
                    "the header (line {header_line}) says NPTS = {npts}, but the data go on \
                     past value {npts} (here); fix NPTS or remove the extra values"
                ),
            ));
        }
        if let Some(short) = short_line {
            return Err(err(
                origin,
                short,
                format!(
                    "{} values on this line but {} on line {}: only the last data line may be \
                     shorter (a value missing here would shift every later sample)",
                    numbers_in(lines[short - 1], origin, short)?.len(),
                    width.map_or(0, |w| w.1),
                    width.map_or(0, |w| w.0)
                ),
            ));
        }
        match width {
            None => width = Some((i + 1, nums.len())),
            Some((first, n)) if nums.len() > n => {
                return Err(err(
                    origin,
                    i + 1,
                    format!(
                        "{} values on this line but {n} on line {first}, the first data line: \
                         every data line holds as many values (the last may hold fewer)",
                        nums.len()
                    ),
                ));
            }
            Some((_, n)) if nums.len() < n => short_line = Some(i + 1),
            Some(_) => {}
        }
        last_data_line = i + 1;
        let room = npts - values.len();
        if nums.len() > room {
            // Past NPTS on the line that completes it: allowed as zero padding only.
            if nums[room..].iter().any(|v| *v != 0.0) {
                return Err(err(
                    origin,
                    i + 1,
                    format!(
                        "the header (line {header_line}) says NPTS = {npts}, but this line holds \
                         {} values past the last one; fix NPTS or remove the extra values",
                        nums.len() - room
                    ),
                ));
            }
            values.extend_from_slice(&nums[..room]);
        } else {
            values.extend(nums);
        }
    }
    if values.len() < npts {
        return Err(err(
            origin,
            header_line,
            format!(
                "the header says NPTS = {npts} but the data hold only {} values (last data on line {last_data_line}); the file may be truncated",
                values.len()
            ),
        ));
    }
    let accel = scaled(values.into_iter(), units.to_mps2(), origin)?;
    Ok((Series::new(0.0, dt, accel).read_in(units), named))
}

fn at2_npts_dt(line: &str, origin: &str, line_no: usize) -> Result<(usize, f64), ParseError> {
    let bad = |why: &str| {
        err(
            origin,
            line_no,
            format!(
                "bad AT2 header '{}': {why}; expected 'NPTS= 1991, DT= .0100 SEC' or '1991 0.0100 NPTS, DT'",
                excerpt(line)
            ),
        )
    };
    let upper = line.to_ascii_uppercase();
    let keyed = upper.contains("NPTS=") || upper.contains("NPTS =");
    // A key given twice would be read at its first place and the other value ignored.
    for key in ["NPTS", "DT"] {
        let given = upper
            .match_indices(key)
            .filter(|(at, _)| {
                let before = upper[..*at].chars().next_back();
                !before.is_some_and(|c| c.is_ascii_alphanumeric())
                    && upper[at + key.len()..].trim_start().starts_with('=')
            })
            .count();
        if given > 1 {
            return Err(bad(&format!(
                "{key}= is given more than once ({given} times), so which value is meant is \
                 unclear; give it once"
            )));
        }
    }
    let (npts, dt) = if keyed {
        let value_after = |key: &str| -> Option<f64> {
            let rest = &upper[upper.find(key)? + key.len()..];
            let rest = rest.trim_start().strip_prefix('=')?.trim_start();
            let end = rest
                .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | 'E')))
                .unwrap_or(rest.len());
            rest[..end].parse().ok()
        };
        (
            value_after("NPTS").ok_or_else(|| bad("no number after NPTS="))?,
            value_after("DT").ok_or_else(|| bad("no number after DT="))?,
        )
    } else {
        let before = &upper[..upper.find("NPTS").unwrap_or(upper.len())];
        let nums = numbers_in(before, origin, line_no).map_err(|_| bad("non-numeric value"))?;
        match nums[..] {
            [n, d, ..] => (n, d),
            _ => return Err(bad("NPTS and DT must precede 'NPTS, DT'")),
        }
    };
    if npts > usize::MAX as f64 {
        return Err(bad(&format!(
            "NPTS = {npts:e} is more values than any file holds"
        )));
    }
    if !(npts >= 1.0 && npts.fract() == 0.0) {
        return Err(bad(&format!(
            "NPTS = {} is not a positive integer",
            fmt_exact(npts)
        )));
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(bad(&format!("DT = {} must be > 0", fmt_exact(dt))));
    }
    Ok((npts as usize, dt))
}

/// `# key: value` comment lines of a column file; each key may appear once.
#[derive(Default)]
struct ColumnHeader {
    dt: Option<(usize, f64)>,
    units: Option<(usize, Units)>,
    npts: Option<(usize, usize)>,
}

impl ColumnHeader {
    /// Read one comment (`#` removed); other comments are free text.
    fn read(&mut self, comment: &str, line: usize, origin: &str) -> Result<(), ParseError> {
        let c = comment.trim().to_ascii_lowercase();
        let value_of = |key: &str| {
            let rest = c.strip_prefix(key)?.trim_start();
            let rest = rest.strip_prefix(':').or_else(|| rest.strip_prefix('='))?;
            Some(rest.split_whitespace().next().unwrap_or("").to_string())
        };
        let twice = |key: &str, first: usize| {
            err(
                origin,
                line,
                format!("a second '# {key}:' line (the first is line {first}); give it once"),
            )
        };
        if let Some(v) = value_of("dt") {
            if let Some((first, _)) = self.dt {
                return Err(twice("dt", first));
            }
            let dt = v
                .parse::<f64>()
                .ok()
                .filter(|d| *d > 0.0 && d.is_finite())
                .ok_or_else(|| err(origin, line, format!("bad '# dt:' value '{}'", excerpt(&v))))?;
            self.dt = Some((line, dt));
        } else if let Some(v) = value_of("units") {
            if let Some((first, _)) = self.units {
                return Err(twice("units", first));
            }
            let units = Units::from_word(v.trim_end_matches([',', '.', ';']))
                .map_err(|why| err(origin, line, why))?;
            self.units = Some((line, units));
        } else if let Some(v) = value_of("npts") {
            if let Some((first, _)) = self.npts {
                return Err(twice("npts", first));
            }
            let n = v.parse::<usize>().map_err(|_| {
                err(
                    origin,
                    line,
                    format!("bad '# npts:' value '{}': a count of samples", excerpt(&v)),
                )
            })?;
            self.npts = Some((line, n));
        }
        Ok(())
    }
}

fn parse_columns(
    text: &str,
    origin: &str,
    expected: &Expected,
) -> Result<(Series, Option<(usize, Units)>), ParseError> {
    let dt_given = expected.dt;
    let mut header = ColumnHeader::default();
    let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if let Some(comment) = trimmed.strip_prefix('#') {
            header.read(comment, i + 1, origin)?;
            continue;
        }
        if trimmed.is_empty() {
            continue;
        }
        let nums = numbers_in(trimmed, origin, i + 1)?;
        rows.push((i + 1, nums));
    }
    if let Some((line, n)) = header.npts
        && n != rows.len()
    {
        return Err(err(
            origin,
            line,
            format!(
                "'# npts: {n}' but the file holds {} data rows; fix the count or the data",
                rows.len()
            ),
        ));
    }
    let dt_header = header.dt.map(|d| d.1);
    let units = header
        .units
        .map(|u| u.1)
        .or(expected.units)
        .unwrap_or(Units::G);
    let Some((first_line, first)) = rows.first() else {
        return Err(err(
            origin,
            0,
            "no data lines (only comments or blank lines)",
        ));
    };
    let columns = first.len();
    if let Some((line, r)) = rows.iter().find(|(_, r)| r.len() != columns) {
        return Err(err(
            origin,
            *line,
            format!(
                "{} values on this line but {columns} on line {first_line}; expected one column (a) or two (t, a)",
                r.len()
            ),
        ));
    }
    if matches!(columns, 1 | 2) {
        // The acceleration is the last column (a, or t and a).
        for (line, r) in &rows {
            plausible(r[columns - 1], units, origin, *line)?;
        }
    }
    let scale = units.to_mps2();
    match columns {
        1 => {
            if let (Some(given), Some(header)) = (dt_given, dt_header)
                && given != header
            {
                return Err(err(
                    origin,
                    0,
                    format!(
                        "dt {given} given for this file differs from its '# dt: {header}' header"
                    ),
                ));
            }
            let dt = dt_given
                .or(dt_header)
                .filter(|d| *d > 0.0 && d.is_finite())
                .ok_or_else(|| {
                    err(
                        origin,
                        0,
                        "a one-column file needs a time step > 0: add a '# dt: 0.01' header line",
                    )
                })?;
            let dt = checked_dt(dt, origin, 0, "dt")?;
            let accel = scaled(rows.iter().map(|(_, r)| r[0]), scale, origin)?;
            Ok((Series::new(0.0, dt, accel).read_in(units), header.units))
        }
        2 => {
            let n = rows.len();
            if n < 2 {
                return Err(err(
                    origin,
                    *first_line,
                    "a two-column file needs at least two rows",
                ));
            }
            let t0 = rows[0].1[0];
            let dt = (rows[n - 1].1[0] - t0) / (n - 1) as f64;
            if dt.is_nan() || dt <= 0.0 {
                return Err(err(origin, rows[n - 1].0, "times must increase"));
            }
            let dt = checked_dt(dt, origin, rows[n - 1].0, "the time step")?;
            if t0 < 0.0 {
                return Err(err(
                    origin,
                    *first_line,
                    format!("negative start time {t0}"),
                ));
            }
            // Printed times carry rounding; a step more than 1% off the first is a real gap.
            let step = rows[1].1[0] - t0;
            for pair in rows.windows(2) {
                let (line, r) = (&pair[1].0, &pair[1].1);
                if (r[0] - pair[0].1[0] - step).abs() > 0.01 * step {
                    return Err(err(
                        origin,
                        *line,
                        format!(
                            "time {} breaks the uniform step {step} of the first rows; resample to a uniform step",
                            r[0]
                        ),
                    ));
                }
            }
            let accel = scaled(rows.iter().map(|(_, r)| r[1]), scale, origin)?;
            Ok((Series::new(t0, dt, accel).read_in(units), header.units))
        }
        _ => Err(err(
            origin,
            *first_line,
            format!("{columns} values per line; expected one column (a) or two (t, a)"),
        )),
    }
}
