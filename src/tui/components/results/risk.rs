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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::risk::tests::{options, power_law_hazard, report};

    /// The fragility view's risk lines name the selected curve's own row: its MAF and
    /// interval, P(years), and for the protected variant its ratio to bare; the collapse
    /// state's P695 margin on the second line.
    #[test]
    fn the_lines_show_the_selected_curves_risk() {
        let report = report();
        let hazard = power_law_hazard(1e-4, 2.4);
        let risk = crate::risk::assess(&report, &hazard, "site.csv", |_| Some(5.0), &options());
        for (curve, row) in report.curves.iter().zip(&risk.rows) {
            let lines = lines(&risk, curve);
            assert_eq!(lines.len(), 2, "{lines:?}");
            let expected = format!(
                "risk at site.csv: MAF {}/yr [{}, {}], P(50 yr) {}",
                fmt_sig(row.maf.unwrap()),
                fmt_sig(row.maf_lo.unwrap()),
                fmt_sig(row.maf_hi.unwrap()),
                fmt_sig(row.p_years.unwrap())
            );
            assert!(lines[0].starts_with(&expected), "{lines:?} vs {expected}");
            let ratio = row.ratio_to_bare.map(|r| format!("{}× bare", fmt_sig(r)));
            assert_eq!(
                ratio
                    .as_ref()
                    .is_some_and(|r| lines[0].contains(r.as_str())),
                !curve.variant.is_bare(),
                "{lines:?}"
            );
            assert!(lines[1].contains("P695 CMR"), "{lines:?}");
        }
        // A curve the risk has no row for: no lines.
        let mut other = report.curves[0].clone();
        other.damage_state = 0.3;
        assert!(lines(&risk, &other).is_empty());
    }
}
