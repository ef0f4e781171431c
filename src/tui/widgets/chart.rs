//! A line chart of time series that stays cheap and faithful at any length: each series is
//! downsampled to about two points per terminal column, keeping every window's extremes.

use super::super::theme::Theme;
use super::fmt_num;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph};

/// A bordered chart of `series` (legend name, values) over the times `t` (s), its values in
/// `unit`: the unit is the middle label of the y axis and "t (s)" the middle one of the time
/// axis; with two series or more a legend runs along the bottom border (a coloured line, or the
/// series' marker on a monochrome terminal, before each name). "not recorded" when there is
/// nothing to draw.
pub fn draw_chart(
    frame: &mut Frame,
    area: Rect,
    theme: Theme,
    title: &str,
    unit: &str,
    t: &[f64],
    series: &[(&str, Vec<f64>)],
) {
    let points = (area.width as usize * 2).max(2);
    let series: Vec<(&str, Vec<(f64, f64)>)> = series
        .iter()
        .map(|(name, values)| (*name, downsample(t, values, points)))
        .collect();
    let mut block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {title} "));
    if series.len() > 1 {
        block = block.title_bottom(legend(theme, series.iter().map(|s| s.0)));
    }
    if series.is_empty() || t.is_empty() {
        frame.render_widget(Paragraph::new("not recorded").block(block), area);
        return;
    }
    let (t0, t1) = (t[0], *t.last().unwrap_or(&t[0]));
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|p| p.1))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    let (lo, hi) = axis_bounds(lo, hi);
    let datasets = series
        .iter()
        .enumerate()
        .map(|(i, (name, data))| {
            Dataset::default()
                .name(*name)
                .marker(marker(theme, i))
                .graph_type(GraphType::Line)
                .style(theme.series(i))
                .data(data)
        })
        .collect();
    let chart = Chart::new(datasets)
        .block(block)
        // The legend is on the border: none inside the plot.
        .legend_position(None)
        .x_axis(Axis::default().bounds([t0, t1.max(t0 + 1e-9)]).labels([
            fmt_num(t0),
            "t (s)".into(),
            fmt_num(t1),
        ]))
        .y_axis(Axis::default().bounds([lo, hi]).labels([
            fmt_num(lo),
            unit.to_string(),
            fmt_num(hi),
        ]));
    frame.render_widget(chart, area);
}

/// The y axis of values from `lo` to `hi`: a bound that is round-off next to the span (an
/// energy of -1e-12 J on a 0.3 J axis) is 0, and the bounds go out to the span's second
/// significant digit, so the two labels read as short round numbers (0.0778 and -0.0576 become
/// 0.08 and -0.06). A flat series gets ±1 around its value. (Two labels and a unit are all the
/// axis shows: a ticks crate would be more than this needs.)
pub fn axis_bounds(lo: f64, hi: f64) -> (f64, f64) {
    if hi <= lo || !lo.is_finite() || !hi.is_finite() {
        return (lo - 1.0, hi + 1.0);
    }
    let span = hi - lo;
    let zero_tiny = |v: f64| if v.abs() <= 1e-6 * span { 0.0 } else { v };
    let (lo, hi) = (zero_tiny(lo), zero_tiny(hi));
    let step = 10f64.powf((hi - lo).log10().floor() - 1.0);
    // Out to a whole step, unless the bound is on one already (within round-off).
    let out = |v: f64, round: fn(f64) -> f64| {
        let k = v / step;
        if (k - k.round()).abs() < 1e-9 {
            v
        } else {
            round(k) * step
        }
    };
    (out(lo, f64::floor), out(hi, f64::ceil))
}

/// Monochrome terminals tell series apart by their markers, colour ones by colour.
fn marker(theme: Theme, i: usize) -> Marker {
    const MARKERS: [Marker; 4] = [Marker::Braille, Marker::Dot, Marker::Block, Marker::Bar];
    if theme.mono {
        MARKERS[i % MARKERS.len()]
    } else {
        Marker::Braille
    }
}

/// ` ━ a  ━ b ` in the series' colours (their markers on a monochrome terminal).
fn legend<'a>(theme: Theme, names: impl Iterator<Item = &'a str>) -> Line<'static> {
    let mut spans = vec![Span::raw(" ")];
    for (i, name) in names.enumerate() {
        let swatch = match marker(theme, i) {
            _ if !theme.mono => "━",
            Marker::Dot => "•",
            Marker::Block => "█",
            Marker::Bar => "▄",
            _ => "⣿",
        };
        if i > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(swatch, theme.series(i)));
        spans.push(Span::raw(format!(" {name}")));
    }
    spans.push(Span::raw(" "));
    Line::from(spans)
}

/// About `n` points: the extremes of the samples in each of n/2 equal time windows, placed at
/// the window's centre, so peaks stay visible and the picture depends on the trajectory, not on
/// where the integrator happened to step.
pub fn downsample(t: &[f64], v: &[f64], n: usize) -> Vec<(f64, f64)> {
    let len = t.len().min(v.len());
    if len <= n {
        return (0..len).map(|i| (t[i], v[i])).collect();
    }
    let buckets = (n / 2).max(1);
    let (t0, t1) = (t[0], t[len - 1]);
    let width = (t1 - t0) / buckets as f64;
    let mut out = Vec::with_capacity(n);
    let mut i = 0;
    for k in 0..buckets {
        let end = if k + 1 == buckets {
            f64::INFINITY
        } else {
            t0 + (k + 1) as f64 * width
        };
        let start = i;
        while i < len && t[i] < end {
            i += 1;
        }
        if i == start {
            continue;
        }
        let window = &v[start..i];
        let (imin, imax) = (0..window.len()).fold((0, 0), |(lo, hi), j| {
            (
                if window[j] < window[lo] { j } else { lo },
                if window[j] > window[hi] { j } else { hi },
            )
        });
        let centre = t0 + (k as f64 + 0.5) * width;
        let (first, second) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((centre, window[first]));
        if second != first {
            out.push((centre, window[second]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_bounds_are_round_and_round_off_is_zero() {
        // The energy axis: -1.285e-12 J under a 0.2731 J top.
        let labels = |(lo, hi): (f64, f64)| (fmt_num(lo), fmt_num(hi));
        let owned = |a: &str, b: &str| (a.to_string(), b.to_string());
        assert_eq!(axis_bounds(-1.285e-12, 0.2731).0, 0.0);
        assert_eq!(labels(axis_bounds(-1.285e-12, 0.2731)), owned("0", "0.28"));
        assert_eq!(labels(axis_bounds(-0.0576, 0.0778)), owned("-0.06", "0.08"));
        // Bounds already round stay; large spans round at their second digit.
        assert_eq!(axis_bounds(0.0, 8.0), (0.0, 8.0));
        assert_eq!(labels(axis_bounds(-3.0, 1234.0)), owned("-100", "1300"));
        // A real small value is kept: only values tiny next to the span are zero.
        assert_eq!(labels(axis_bounds(-0.004, 0.2)), owned("-0.01", "0.2"));
        // Every value stays inside; a flat series gets room.
        for (a, b) in [(0.1234, 0.1299), (-7.77e-5, 3.3e-5), (12.0, 12.5)] {
            let (lo, hi) = axis_bounds(a, b);
            assert!(
                lo <= a && b <= hi && hi - lo < 3.0 * (b - a),
                "{a} {b}: {lo} {hi}"
            );
        }
        assert_eq!(axis_bounds(2.0, 2.0), (1.0, 3.0));
    }

    #[test]
    fn downsampling_keeps_every_window_extreme_and_ignores_step_placement() {
        // A spike at t = 0.503 in a 0..1 s signal sampled finely, two ways.
        let spike = |t: f64| {
            if (t - 0.503).abs() < 1e-3 {
                5.0
            } else {
                t.sin()
            }
        };
        let fine: Vec<f64> = (0..=10_000).map(|i| i as f64 * 1e-4).collect();
        let shifted: Vec<f64> = (0..=9_001)
            .map(|i| (i as f64 * 1.111e-4).min(1.0))
            .collect();
        let a = downsample(
            &fine,
            &fine.iter().map(|&t| spike(t)).collect::<Vec<_>>(),
            100,
        );
        let b = downsample(
            &shifted,
            &shifted.iter().map(|&t| spike(t)).collect::<Vec<_>>(),
            100,
        );
        assert!(a.len() <= 100 && b.len() <= 100);
        let peak = |s: &[(f64, f64)]| s.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert_eq!(peak(&a), 5.0);
        assert_eq!(peak(&b), 5.0);
        // Same windows, same centres: the two samplings put the spike at the same time.
        let at = |s: &[(f64, f64)]| s.iter().find(|p| p.1 == 5.0).unwrap().0;
        assert_eq!(at(&a), at(&b));
        // Short histories pass through untouched.
        assert_eq!(
            downsample(&[0.0, 1.0], &[2.0, 3.0], 10),
            vec![(0.0, 2.0), (1.0, 3.0)]
        );
    }
}
