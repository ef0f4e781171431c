//! Numbers as people read them, in one place: labels, tables, messages and figure ticks all
//! format through here so the same value reads the same everywhere.

/// `v` rounded to `digits` significant digits, without trailing zeros: plain decimals from
/// 1e-3 to 1e6, scientific notation (`5.623e-5`) beyond.
pub fn fmt_digits(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let sci = format!("{:.*e}", digits.max(1) - 1, v);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if (-3..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        trim(&format!("{v:.decimals$}"))
    } else {
        format!("{}e{exp}", trim(mantissa))
    }
}

/// A short, exact-enough rendering of a parameter value for labels (scientific from 1e9:
/// `{:.4}` of 1e308 would be 309 digits).
pub fn fmt_num(v: f64) -> String {
    if v == v.round() && v.abs() < 1e9 {
        return format!("{}", v as i64);
    }
    if v.is_nan() || v.abs() >= 1e9 {
        return fmt_digits(v, 6);
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "0" || s == "-0" {
        format!("{v:.3e}")
    } else {
        s.to_string()
    }
}

/// A value as the user wrote it, for messages: the shortest decimals that read back as the
/// same number, in scientific notation below 1e-4 and from 1e9 (Rust's `{}` writes 1e308 as
/// 309 digits).
pub fn fmt_exact(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Four decimals, or four significant digits in scientific notation below 1e-3 and from 1e5:
/// values in summaries.
pub fn fmt_sig(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

/// κ as the check prints it: 3.7 below 100, 1.2e5 above.
pub fn fmt_condition(k: f64) -> String {
    if k < 100.0 {
        format!("{k:.1}")
    } else {
        format!("{k:.1e}")
    }
}

/// A duration in seconds as `< 1 s`, `42 s`, `3 min 5 s` or `1.5 h`.
pub fn fmt_duration(s: f64) -> String {
    if s < 1.0 {
        "< 1 s".into()
    } else if s < 60.0 {
        format!("{s:.0} s")
    } else if s < 3600.0 {
        format!("{:.0} min {:.0} s", (s / 60.0).floor(), s % 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}
