//! The risk lines under the fragility view: for the selected curve, its mean annual frequency
//! at the site of the risk.json beside the results (`rocklab risk` or a study's `risk`
//! section), with its interval, the probability in the stated years and the ratio to bare;
//! and the variant's P695 margin when there is one.

use super::super::super::theme::Theme;
use crate::numfmt::fmt_sig;
use crate::report::fragility::Curve;
use crate::risk::RiskReport;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), fmt_sig)
}

/// The lines for the selected curve (none if the risk has no row for it).
pub fn lines(risk: &RiskReport, curve: &Curve) -> Vec<String> {
    let Some(row) = risk
        .rows
        .iter()
        .find(|r| r.variant == curve.variant && r.damage_state == curve.damage_state)
    else {
        return Vec::new();
    };
    let unit = risk.hazard.curve.im.unit();
    let mut first = format!("risk at {}: ", risk.hazard.source);
    match row.maf {
        Some(maf) => {
            first.push_str(&format!(
                "MAF {}/yr [{}, {}], P({} yr) {}",
                fmt_sig(maf),
                opt(row.maf_lo),
                opt(row.maf_hi),
                risk.years,
                opt(row.p_years)
            ));
            if let Some(r) = row.ratio_to_bare {
                first.push_str(&format!(
                    ", {}× bare [{}, {}]",
                    fmt_sig(r),
                    opt(row.ratio_lo),
                    opt(row.ratio_hi)
                ));
            }
        }
        None => first.push_str("no MAF"),
    }
    let mut second = format!(
        "80 % of it from {} {unit} to {} {unit}; {}",
        opt(row.deagg_p10),
        opt(row.deagg_p90),
        row.status
    );
    if let Some(m) = risk
        .margins
        .iter()
        .find(|m| m.variant == row.variant && m.damage_state == row.damage_state)
    {
        second.push_str(&format!(
            "; P695 CMR {} against ACMR10 {}",
            fmt_sig(m.margin.cmr),
            fmt_sig(m.margin.acmr_10)
        ));
    }
    vec![first, second]
}

pub fn draw(risk: &RiskReport, curve: Option<&Curve>, theme: Theme, frame: &mut Frame, area: Rect) {
    let text: Vec<Line> = curve
        .map(|c| lines(risk, c))
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                Line::raw(l)
            } else {
                Line::styled(l, theme.dim())
            }
        })
        .collect();
    frame.render_widget(Paragraph::new(text), area);
}
