//! A scene's histories stacked like the paper's Figs. 8/9/14, with the energy partition as a
//! stacked area (Fig. 15).

use super::range_of;
use crate::report::figure::{
    Axes, Canvas, Dash, FigureOptions, FigureSize, LegendEntry, SeriesStyle, Swatch, build_chart,
    draw_line, err, render, split_figure,
};
use crate::sim::{History, HistoryColumn};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One panel of a scene's histories: lines, or a stacked area with a line on top.
struct HistoryPanel {
    y_label: String,
    lines: Vec<(Vec<f64>, SeriesStyle)>,
    stack: Vec<(Vec<f64>, RGBColor)>,
}

/// At most `n` points per series: the min and max of each bucket, so peaks survive.
fn decimate(t: &[f64], y: &[f64], n: usize) -> Vec<(f64, f64)> {
    if t.len() <= n {
        return t.iter().copied().zip(y.iter().copied()).collect();
    }
    let bucket = t.len().div_ceil(n / 2);
    let mut out = Vec::with_capacity(n + 2);
    for (tc, yc) in t.chunks(bucket).zip(y.chunks(bucket)) {
        let (imin, imax) = yc.iter().enumerate().fold((0, 0), |(a, b), (i, v)| {
            (
                if *v < yc[a] { i } else { a },
                if *v > yc[b] { i } else { b },
            )
        });
        for i in if imin <= imax {
            [imin, imax]
        } else {
            [imax, imin]
        } {
            out.push((tc[i], yc[i]));
        }
    }
    out
}

/// A scene's histories as the paper's Figs. 8/9/14/15: rotation (and deformation), ground
/// acceleration, flywheel velocities, device force, and the energy partition stacked.
pub fn plot_history(
    path: &Path,
    options: &FigureOptions,
    title: &str,
    scene: &crate::scene::Scene,
    history: &History,
) -> crate::error::Result<()> {
    use HistoryColumn as C;
    let t = history
        .column(C::T)
        .ok_or_else(|| crate::error::error!("the history has no time column"))?;
    let col = |c: C| history.column(c);
    let nonzero = |v: &Option<Vec<f64>>| v.as_ref().is_some_and(|v| v.iter().any(|x| *x != 0.0));
    let solid = |i: usize| SeriesStyle {
        marker: None,
        dash: Dash::Solid,
        ..SeriesStyle::nth(i)
    };
    let mut panels: Vec<HistoryPanel> = Vec::new();
    let mut legend: Vec<LegendEntry> = Vec::new();
    let alpha = scene.structure.alpha();
    let flexible = col(C::U).is_some();
    if let Some(theta) = col(C::Theta) {
        panels.push(if flexible {
            HistoryPanel {
                y_label: "θ [rad]".into(),
                lines: vec![(theta, solid(0))],
                stack: vec![],
            }
        } else {
            HistoryPanel {
                y_label: "θ/α".into(),
                lines: vec![(theta.iter().map(|v| v / alpha).collect(), solid(0))],
                stack: vec![],
            }
        });
    }
    if let Some(u) = col(C::U) {
        panels.push(HistoryPanel {
            y_label: "u [m]".into(),
            lines: vec![(u, solid(0))],
            stack: vec![],
        });
    }
    if let Some(ag) = col(C::GroundAccel) {
        panels.push(HistoryPanel {
            y_label: "ag [g]".into(),
            lines: vec![(ag.iter().map(|v| v / 9.81).collect(), solid(0))],
            stack: vec![],
        });
    }
    let (va, vb) = (col(C::FlywheelAVel), col(C::FlywheelBVel));
    if nonzero(&va) || nonzero(&vb) {
        let mut lines = Vec::new();
        let a_style = solid(2);
        let b_style = SeriesStyle {
            dash: Dash::Short,
            ..solid(4)
        };
        if let Some(v) = va.filter(|v| v.iter().any(|x| *x != 0.0)) {
            lines.push((v, a_style));
            legend.push(LegendEntry {
                label: C::FlywheelAVel.label().into(),
                swatch: Swatch::Line(a_style),
            });
        }
        if let Some(v) = vb.filter(|v| v.iter().any(|x| *x != 0.0)) {
            lines.push((v, b_style));
            legend.push(LegendEntry {
                label: C::FlywheelBVel.label().into(),
                swatch: Swatch::Line(b_style),
            });
        }
        panels.push(HistoryPanel {
            y_label: "ẏ [m/s]".into(),
            lines,
            stack: vec![],
        });
    }
    let fd = col(C::DeviceForce);
    if nonzero(&fd) {
        panels.push(HistoryPanel {
            y_label: "Fd [N]".into(),
            lines: vec![(fd.expect("checked"), solid(0))],
            stack: vec![],
        });
    }
    // Energy partition: every stored or dissipated term stacked, the input work on top.
    let terms: Vec<C> = history
        .columns
        .iter()
        .copied()
        .filter(|c| c.energy().is_some() && *c != C::EInput)
        .collect();
    if !terms.is_empty() {
        let mut stack = Vec::new();
        for (i, name) in terms.iter().enumerate() {
            let v = col(*name).expect("listed");
            if v.iter().all(|x| *x == 0.0) {
                continue;
            }
            let color =
                crate::report::figure::PALETTE[(i + 1) % crate::report::figure::PALETTE.len()];
            legend.push(LegendEntry {
                label: name.label().into(),
                swatch: Swatch::Fill(color.mix(0.55).rgb_blend()),
            });
            stack.push((v, color));
        }
        let input_style = solid(0);
        let mut lines = vec![];
        if let Some(e) = col(C::EInput) {
            lines.push((e, input_style));
            legend.push(LegendEntry {
                label: C::EInput.label().into(),
                swatch: Swatch::Line(input_style),
            });
        }
        panels.push(HistoryPanel {
            y_label: "E [J]".into(),
            lines,
            stack,
        });
    }
    let canvas = options.canvas(
        FigureSize::mm(160.0, 32.0 * panels.len() as f64 + 22.0),
        "the scene history figure",
    )?;
    render(
        path,
        options,
        canvas,
        |r| draw_history(r, canvas, title, &legend, &t, &panels),
        |r| draw_history(r, canvas, title, &legend, &t, &panels),
    )
}

trait Blend {
    fn rgb_blend(&self) -> RGBColor;
}

impl Blend for RGBAColor {
    /// The colour of this translucent colour over white, for legend boxes.
    fn rgb_blend(&self) -> RGBColor {
        let (r, g, b) = self.rgb();
        let a = self.alpha();
        let f = |c: u8| (c as f64 * a + 255.0 * (1.0 - a)).round() as u8;
        RGBColor(f(r), f(g), f(b))
    }
}

fn draw_history<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    t: &[f64],
    panels: &[HistoryPanel],
) -> crate::error::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((panels.len().max(1), 1));
    let (t0, t1) = range_of(t.iter().copied());
    const POINTS: usize = 4000;
    for (i, (area, panel)) in areas.iter().zip(panels).enumerate() {
        // Cumulative sums of the stack.
        let mut cumulative: Vec<Vec<f64>> = Vec::new();
        let mut acc = vec![0.0; t.len()];
        for (v, _) in &panel.stack {
            for (a, x) in acc.iter_mut().zip(v) {
                *a += x;
            }
            cumulative.push(acc.clone());
        }
        let (y0, y1) = range_of(
            panel
                .lines
                .iter()
                .flat_map(|(v, _)| v.iter().copied())
                .chain(cumulative.iter().flatten().copied())
                .chain(if panel.stack.is_empty() {
                    None
                } else {
                    Some(0.0)
                }),
        );
        let pad = 0.05 * (y1 - y0);
        let mut chart = build_chart(
            area,
            canvas,
            &Axes {
                x: (t0, t1),
                y: (y0 - pad, y1 + pad),
                x_label: if i + 1 == panels.len() { "t [s]" } else { "" },
                y_label: &panel.y_label,
                title: "",
                y_labels_below: None,
            },
        )?;
        let mut lower = vec![0.0; t.len()];
        for (upper, (_, color)) in cumulative.iter().zip(&panel.stack) {
            let top = decimate(t, upper, POINTS);
            let bottom = decimate(t, &lower, POINTS);
            let mut poly = top;
            poly.extend(bottom.into_iter().rev());
            chart
                .draw_series(std::iter::once(Polygon::new(
                    poly,
                    color.mix(0.55).filled(),
                )))
                .map_err(err)?;
            lower.clone_from(upper);
        }
        for (v, style) in &panel.lines {
            let pts = decimate(t, v, POINTS);
            // Thin lines: plotters leaves gaps between many short wide segments.
            draw_line(&mut chart, canvas, &pts, *style, 0.7)?;
        }
    }
    root.present().map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_the_extremes() {
        let t: Vec<f64> = (0..10_000).map(|i| i as f64).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|x| (x * 0.01).sin() * if *x == 4321.0 { 5.0 } else { 1.0 })
            .collect();
        let d = decimate(&t, &y, 500);
        assert!(d.len() <= 502, "{}", d.len());
        let max = d.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let true_max = y.iter().copied().fold(f64::MIN, f64::max);
        assert_eq!(max, true_max);
    }
}
