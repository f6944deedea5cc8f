//! Grouped bar charts of Table 2: one PNG per metric, one group of eight bars (F1–F8) per
//! policy, with the policy's Avg. as a black line across its group; and Orig. SR per suite.
//! Each bar carries its 95 % interval as a whisker ([`super::interval`]).
//! Drawn with tiny-skia and the DejaVu text helpers of `vifo-cues`, so no system fonts are
//! involved.

use tiny_skia::{PathBuilder, Pixmap, Rect, Transform};
use vifo_cues::Family;
use vifo_cues::draw::geom::v2;
use vifo_cues::draw::text::{Face, centered_line, line_width};
use vifo_cues::draw::{Rgba, fill, rgb};

use super::{Interval, Metric, Report};

const W: u32 = 960;
const H: u32 = 440;
const LEFT: f32 = 56.0;
const RIGHT: f32 = 150.0;
const TOP: f32 = 48.0;
const BOTTOM: f32 = 70.0;

/// One colour per family (Tableau 10), in family order.
pub(crate) const COLOURS: [[u8; 3]; 8] = [
    [78, 121, 167],
    [242, 142, 43],
    [225, 87, 89],
    [118, 183, 178],
    [89, 161, 79],
    [237, 201, 72],
    [176, 122, 161],
    [255, 157, 167],
];

/// The paper's column headers.
pub(crate) fn short_name(f: Family) -> &'static str {
    match f {
        Family::F1 => "F1 Text",
        Family::F2 => "F2 Geom.",
        Family::F3 => "F3 Ghost",
        Family::F4 => "F4 Pict.",
        Family::F5 => "F5 Gest.",
        Family::F6 => "F6 Sign",
        Family::F7 => "F7 Light.",
        Family::F8 => "F8 Code",
    }
}

pub(crate) fn rect(pm: &mut Pixmap, x: f32, y: f32, w: f32, h: f32, color: Rgba) {
    if let Some(r) = Rect::from_xywh(x, y, w.max(0.5), h.max(0.5)) {
        fill(pm, &PathBuilder::from_rect(r), color, Transform::identity());
    }
}

/// A line of text centred at (x, y), shrunk and then shortened with "…" to fit `max_w`.
pub(crate) fn label(pm: &mut Pixmap, text: &str, x: f32, y: f32, size: f32, max_w: f32, color: Rgba) {
    let mut size = size;
    while size > 8.0 && line_width(Face::Sans, size, text) > max_w {
        size -= 1.0;
    }
    let mut shown = text.to_string();
    let mut chars: Vec<char> = text.chars().collect();
    while line_width(Face::Sans, size, &shown) > max_w && chars.len() > 1 {
        chars.pop();
        shown = chars.iter().collect::<String>() + "…";
    }
    if let Some(path) = centered_line(Face::Sans, size, &shown, v2(x, y)) {
        fill(pm, &path, color, Transform::identity());
    }
}

/// A value axis on the frame (x0, x1, y0, y1) from 0 to `max`: grey grid lines every `step`
/// labelled with the value and `unit` left of x0, and the base line.
pub(crate) fn axis(pm: &mut Pixmap, (x0, x1, y0, y1): (f32, f32, f32, f32), max: f32, step: f32, unit: &str) {
    let ink = rgb([30, 30, 30]);
    let mut tick = 0.0;
    while tick <= max + 1e-3 {
        let y = y1 - tick / max * (y1 - y0);
        rect(pm, x0, y - 0.5, x1 - x0, 1.0, rgb([215, 215, 215]));
        label(pm, &format!("{tick:.0}{unit}"), x0 - 24.0, y, 11.0, 44.0, ink);
        tick += step;
    }
    rect(pm, x0, y1, x1 - x0, 1.5, ink);
}

/// A bar from the base line y1 of a frame whose top y0 stands for `max`, up to `value`
/// (clamped to the frame).
pub(crate) fn bar(pm: &mut Pixmap, (y0, y1): (f32, f32), max: f32, x: f32, w: f32, value: f64, color: Rgba) {
    let h = (value as f32).clamp(0.0, max) / max * (y1 - y0);
    rect(pm, x, y1 - h, w, h, color);
}

/// The whisker of a bar's 95 % interval, centred at x on a frame as [`bar`]'s: a vertical line
/// from `interval.low` to `interval.high` with caps `cap` wide.
fn whisker(pm: &mut Pixmap, (y0, y1): (f32, f32), max: f32, x: f32, cap: f32, interval: Interval, color: Rgba) {
    let y = |v: f64| y1 - (v as f32).clamp(0.0, max) / max * (y1 - y0);
    let (top, bottom) = (y(interval.high), y(interval.low));
    rect(pm, x - 0.75, top, 1.5, bottom - top, color);
    for end in [top, bottom] {
        rect(pm, x - cap / 2.0, end - 0.75, cap, 1.5, color);
    }
}

/// A rate's bar in a slot `slot_w` wide at x (less a `gap` between bars) on a 0–100 % frame as
/// [`bar`]'s, with the whisker of its 95 % interval.
#[allow(clippy::too_many_arguments)]
pub(crate) fn rate_bar(pm: &mut Pixmap, (y0, y1): (f32, f32), x: f32, slot_w: f32, gap: f32, rate: f64, interval: Interval, color: Rgba) {
    bar(pm, (y0, y1), 100.0, x + gap / 2.0, slot_w - gap, rate, color);
    whisker(pm, (y0, y1), 100.0, x + slot_w / 2.0, (slot_w / 2.0).min(8.0), interval, WHISKER_INK);
}

/// The whiskers' colour: dark, and none of the bars'.
pub(crate) const WHISKER_INK: Rgba = rgb([70, 70, 70]);

/// What the whiskers are, after a chart's title.
pub(crate) const WHISKERS: &str = "; whiskers: 95 % intervals";

/// Legend text starting at x, vertically centred on y.
pub(crate) fn legend_text(pm: &mut Pixmap, text: &str, x: f32, y: f32, color: Rgba) {
    let w = line_width(Face::Sans, 12.0, text);
    label(pm, text, x + w / 2.0, y, 12.0, w + 1.0, color);
}

/// A legend in one row under a chart's title: a colour square and its name per entry, the
/// entries spread evenly from x0 to x1.
pub(crate) fn legend_row(pm: &mut Pixmap, entries: &[(&str, [u8; 3])], x0: f32, x1: f32, color: Rgba) {
    for (i, (name, colour)) in entries.iter().enumerate() {
        let x = x0 + i as f32 * (x1 - x0) / entries.len() as f32;
        rect(pm, x, 38.0, 12.0, 12.0, rgb(*colour));
        legend_text(pm, name, x + 18.0, 44.0, color);
    }
}

/// The PNG bytes of the chart of one Table 2 metric.
pub fn family_chart(report: &Report, metric: Metric) -> Result<Vec<u8>, String> {
    let mut pm = Pixmap::new(W, H).ok_or("chart size")?;
    pm.fill(tiny_skia::Color::WHITE);
    let (x0, x1, y0, y1) = (LEFT, W as f32 - RIGHT, TOP, H as f32 - BOTTOM);
    let black = rgb([30, 30, 30]);
    let direction = if metric.higher_is_better() { "higher is better" } else { "lower is better" };
    label(
        &mut pm,
        &format!("{} per cue family (%), {direction}{WHISKERS}", metric.name()),
        W as f32 / 2.0,
        22.0,
        18.0,
        W as f32,
        black,
    );
    for tick in [0.0f32, 25.0, 50.0, 75.0, 100.0] {
        let y = y1 - tick / 100.0 * (y1 - y0);
        rect(&mut pm, x0, y - 0.5, x1 - x0, 1.0, rgb([215, 215, 215]));
        label(&mut pm, &format!("{tick:.0}"), x0 - 22.0, y, 12.0, 40.0, black);
    }
    let rows: Vec<_> = report.table2.iter().filter(|r| r.metric == metric).collect();
    if rows.is_empty() {
        label(&mut pm, "no data", (x0 + x1) / 2.0, (y0 + y1) / 2.0, 16.0, x1 - x0, black);
    }
    let group_w = (x1 - x0) / rows.len().max(1) as f32;
    let inner = group_w * 0.84;
    let bar_w = inner / Family::ALL.len() as f32;
    for (g, row) in rows.iter().enumerate() {
        let start = x0 + g as f32 * group_w + (group_w - inner) / 2.0;
        for (i, family) in Family::ALL.iter().enumerate() {
            let Some(rate) = row.families.get(family) else { continue };
            if let (Some(p), Some(interval)) = (rate.percent(), Interval::of(rate)) {
                rate_bar(&mut pm, (y0, y1), start + i as f32 * bar_w, bar_w, 2.0, p, interval, rgb(COLOURS[i]));
            }
        }
        if let Some(avg) = row.avg {
            let y = y1 - (avg as f32).clamp(0.0, 100.0) / 100.0 * (y1 - y0);
            rect(&mut pm, start - 3.0, y - 1.5, inner + 6.0, 3.0, black);
        }
        label(&mut pm, &row.policy, start + inner / 2.0, y1 + 18.0, 13.0, group_w - 6.0, black);
    }
    rect(&mut pm, x0, y1, x1 - x0, 1.5, black);
    let lx = x1 + 24.0;
    for (i, family) in Family::ALL.iter().enumerate() {
        let y = y0 + 8.0 + i as f32 * 22.0;
        rect(&mut pm, lx, y - 6.0, 12.0, 12.0, rgb(COLOURS[i]));
        legend_text(&mut pm, short_name(*family), lx + 20.0, y, black);
    }
    let y = y0 + 8.0 + 8.0 * 22.0;
    rect(&mut pm, lx - 2.0, y - 1.5, 16.0, 3.0, black);
    legend_text(&mut pm, "Avg.", lx + 20.0, y, black);
    encode_png(&pm)
}

/// The PNG bytes of Orig. SR per suite: one group per policy, one bar per suite (LIBERO's
/// colours in its suite order), the policy's Orig. SR over every suite as a black line.
pub fn suite_chart(report: &Report) -> Result<Vec<u8>, String> {
    let mut pm = Pixmap::new(W, H).ok_or("chart size")?;
    pm.fill(tiny_skia::Color::WHITE);
    let ink = rgb([30, 30, 30]);
    label(&mut pm, &format!("Orig. SR per suite (%), higher is better{WHISKERS}"), W as f32 / 2.0, 20.0, 18.0, W as f32, ink);
    let (x0, x1, y0, y1) = (LEFT, W as f32 - 20.0, TOP + 24.0, H as f32 - BOTTOM);
    axis(&mut pm, (x0, x1, y0, y1), 100.0, 25.0, "");
    let mut suites: Vec<&str> = Vec::new();
    for p in &report.suites {
        if !suites.contains(&p.part.as_str()) {
            suites.push(&p.part);
        }
    }
    let rows: Vec<_> = report.table1.iter().filter(|r| r.orig_sr.total > 0).collect();
    if rows.is_empty() {
        label(&mut pm, "no original-protocol episodes", (x0 + x1) / 2.0, (y0 + y1) / 2.0, 16.0, x1 - x0, ink);
    }
    let colour = |i: usize| COLOURS[i % COLOURS.len()];
    let group_w = (x1 - x0) / rows.len().max(1) as f32;
    let inner = group_w * 0.8;
    let bar_w = inner / suites.len().max(1) as f32;
    for (g, row) in rows.iter().enumerate() {
        let start = x0 + g as f32 * group_w + (group_w - inner) / 2.0;
        for (i, suite) in suites.iter().enumerate() {
            let Some(part) = report.suites.iter().find(|p| p.part == *suite && p.row.policy == row.policy) else { continue };
            if let (Some(v), Some(interval)) = (part.row.orig_sr.percent(), part.row.orig_sr_ci95) {
                rate_bar(&mut pm, (y0, y1), start + i as f32 * bar_w, bar_w, 1.0, v, interval, rgb(colour(i)));
            }
        }
        if let Some(all) = row.orig_sr.percent() {
            let y = y1 - (all as f32).clamp(0.0, 100.0) / 100.0 * (y1 - y0);
            rect(&mut pm, start - 3.0, y - 1.5, inner + 6.0, 3.0, ink);
        }
        label(&mut pm, &row.policy, start + inner / 2.0, y1 + 18.0, 13.0, group_w - 6.0, ink);
    }
    let mut entries: Vec<(&str, [u8; 3])> = suites.iter().enumerate().map(|(i, s)| (*s, colour(i))).collect();
    entries.push(("all suites (line)", [30, 30, 30]));
    legend_row(&mut pm, &entries, x0, x1, ink);
    encode_png(&pm)
}

/// The opaque pixmap as an RGB PNG (premultiplied and straight colour agree when opaque).
pub(crate) fn encode_png(pm: &Pixmap) -> Result<Vec<u8>, String> {
    let rgb: Vec<u8> = pm.data().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let img = image::RgbImage::from_raw(pm.width(), pm.height(), rgb).ok_or("pixel buffer size")?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}
