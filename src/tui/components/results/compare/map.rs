//! The compare screen's maps view: the overturning maps of the selected pair, cell by cell.

use super::*;

fn cell_style(c: MapCell, theme: Theme) -> Style {
    match c {
        MapCell::BothSurvive => theme.safe(),
        MapCell::OnlyBSurvives => theme.ok(),
        MapCell::OnlyASurvives => theme.warn(),
        MapCell::BothOverturn => theme.overturned(),
        MapCell::Missing => theme.failed(),
    }
}

/// The overturning maps of the selected pair, cell by cell: where both survive, only B, only
/// A, both overturn, or a side failed or did not run; with a legend and counts.
pub(super) fn draw_map(
    view: &CompareView,
    data: &Results,
    theme: Theme,
    mut lines: Vec<Line<'static>>,
    frame: &mut Frame,
    area: Rect,
) {
    let maps = match view.map_pairs(data) {
        Ok(m) => m,
        Err(e) if data.maps.is_empty() => {
            let _ = e;
            lines.push(Line::raw("no overturning maps in these results"));
            frame.render_widget(Paragraph::new(lines), area);
            return;
        }
        Err(e) => {
            lines.push(Line::styled(e, theme.error()));
            frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
            return;
        }
    };
    let sel = view.pair.min(maps.len() - 1);
    let m = &maps[sel];
    let title = format!(
        "overturning maps (pair {}/{}, ↑↓): A {}  vs  B {}",
        sel + 1,
        maps.len(),
        m.a,
        m.b
    );
    lines.extend(
        naming::wrap(&title, area.width as usize)
            .into_iter()
            .map(|l| Line::styled(l, theme.title())),
    );
    let ylabel = 8;
    let (nx, ny) = (m.xs.len(), m.ys.len());
    let room_w = (area.width as usize).saturating_sub(ylabel + 2);
    let cell = (room_w / nx.max(1)).clamp(1, 6);
    let count_x = (room_w / cell).min(nx);
    let room_y = (area.height as usize)
        .saturating_sub(lines.len() + 5)
        .max(1);
    let room_y = if room_y < ny {
        // Rows are hidden: the line under the map says how many.
        room_y.saturating_sub(1).max(1)
    } else {
        room_y
    };
    let cell_h = (room_y / ny.max(1)).clamp(1, 2);
    let count_y = (room_y / cell_h).min(ny);
    lines.push(Line::styled(m.y_axis.clone(), theme.dim()));
    for r in 0..count_y * cell_h {
        let iy = ny - 1 - r / cell_h;
        let label = if r % cell_h == 0 {
            format!("{:>7} ", fmt_num(m.ys[iy]))
        } else {
            " ".repeat(ylabel)
        };
        let mut spans = vec![Span::styled(label, theme.dim())];
        for c in m.cells[iy].iter().take(count_x) {
            spans.push(Span::styled(
                c.glyph().to_string().repeat(cell),
                cell_style(*c, theme),
            ));
        }
        lines.push(Line::from(spans));
    }
    if let Some(more) = more_marker(0, ny - count_y) {
        lines.push(Line::styled(
            format!("{more} rows of {}", m.y_axis),
            theme.dim(),
        ));
    }
    let st = Strip {
        first: 0,
        count: count_x,
        cell,
    };
    lines.push(axis_line(&m.xs, &st, ylabel, &m.x_axis));
    // The legend with counts, whole entries per line.
    let mut legend: Vec<Span> = Vec::new();
    let mut used = 0;
    for c in MapCell::ALL {
        let text = format!(" {} {}  ", c.meaning(), m.count(c));
        let need = 1 + text.chars().count();
        if used + need > area.width as usize && used > 0 {
            lines.push(Line::from(std::mem::take(&mut legend)));
            used = 0;
        }
        used += need;
        legend.push(Span::styled(c.glyph().to_string(), cell_style(c, theme)));
        legend.push(Span::raw(text));
    }
    lines.push(Line::from(legend));
    frame.render_widget(Paragraph::new(lines), area);
}
