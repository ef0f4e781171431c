//! Measures read off a history (as `simulate --history` writes it: resampled rows plus the
//! rows either side of each event), shared by the rows that time forces, contacts and jumps.

/// ∫ |f| dt over the rows with `from ≤ t < to` (trapezoid between consecutive rows).
pub fn impulse(t: &[f64], f: &[f64], from: f64, to: f64) -> f64 {
    (1..t.len())
        .filter(|&i| t[i - 1] >= from && t[i] < to)
        .map(|i| 0.5 * (f[i].abs() + f[i - 1].abs()) * (t[i] - t[i - 1]))
        .sum()
}

/// The share of the time in `[from, to)` during which |f| is above `floor` (a row's interval
/// counts as engaged when both its ends are).
pub fn engaged_share(t: &[f64], f: &[f64], floor: f64, from: f64, to: f64) -> f64 {
    let (mut on, mut all) = (0.0, 0.0);
    for i in (1..t.len()).filter(|&i| t[i - 1] >= from && t[i] < to) {
        let dt = t[i] - t[i - 1];
        all += dt;
        if f[i].abs() > floor && f[i - 1].abs() > floor {
            on += dt;
        }
    }
    if all > 0.0 { on / all } else { 0.0 }
}

/// The force floor under which a clutch counts as disengaged: the tanh-smoothed spring leaves
/// a force many orders of magnitude below its peak on a disengaged clutch.
pub fn contact_floor(f: &[f64]) -> f64 {
    1e-6 * f.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Maximal runs of rows where |f| is above the contact floor: one per contact, as index
/// ranges (at least two rows each).
pub fn contacts(f: &[f64]) -> Vec<std::ops::Range<usize>> {
    let floor = contact_floor(f);
    let mut out = Vec::new();
    let mut start = None;
    for (i, x) in f.iter().enumerate() {
        match (x.abs() > floor, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                if i - s >= 2 {
                    out.push(s..i);
                }
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start.filter(|s| f.len() - s >= 2) {
        out.push(s..f.len());
    }
    out
}

/// Times where y changes sign, interpolated linearly between rows.
pub fn crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    (1..t.len())
        .filter(|&i| y[i - 1] * y[i] < 0.0)
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * y[i - 1] / (y[i - 1] - y[i]))
        .collect()
}

/// The share of the total fall of `e` that happens at instants (between two rows of the same
/// time, i.e. across an event's jump) rather than over time.
pub fn sudden_share(t: &[f64], e: &[f64]) -> f64 {
    let (mut sudden, mut all) = (0.0, 0.0);
    for i in 1..t.len() {
        let fall = e[i - 1] - e[i];
        if fall > 0.0 {
            all += fall;
            if t[i] - t[i - 1] <= 1e-12 {
                sudden += fall;
            }
        }
    }
    if all > 0.0 { sudden / all } else { 0.0 }
}
