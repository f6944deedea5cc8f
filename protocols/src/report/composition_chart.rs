//! The paper's appendix statistics figure for an instance set, with the paper's numbers beside
//! it: (a) instances per cue family, (b) instances encoding each semantic component
//! ([`vifo_cues::composition`]). Drawn like the Table 2 charts (tiny-skia, DejaVu paths).

use std::collections::BTreeMap;

use tiny_skia::Pixmap;
use vifo_cues::composition::{Component, Coverage};
use vifo_cues::instances::{FamilyCount, paper};
use vifo_cues::{Family, SetName};

use super::chart::{COLOURS, axis, encode_png, label, legend_text, rect, short_name};

const W: u32 = 1280;
const H: u32 = 520;
const PAPER_GREY: [u8; 3] = [150, 150, 150];
const INK: [u8; 3] = [30, 30, 30];

/// The PNG bytes of both panels for one set.
pub fn composition_figure(
    set: SetName,
    families: &BTreeMap<Family, FamilyCount>,
    coverage: &BTreeMap<Component, Coverage>,
) -> Result<Vec<u8>, String> {
    let mut pm = Pixmap::new(W, H).ok_or("figure size")?;
    pm.fill(tiny_skia::Color::WHITE);
    let ink = vifo_cues::draw::rgb(INK);
    let total: usize = families.values().map(|c| c.instances).sum();
    label(
        &mut pm,
        &format!("LIBERO-VIFO instance set '{set}': {total} instances (paper: {})", paper::INSTANCES),
        W as f32 / 2.0,
        20.0,
        18.0,
        W as f32,
        ink,
    );
    family_panel(&mut pm, families, (50.0, 560.0, 70.0, 440.0));
    coverage_panel(&mut pm, coverage, (650.0, 1250.0, 70.0, 440.0));
    encode_png(&pm)
}

/// (a): one bar per family (this set), a grey bar beside it where the paper states a share.
fn family_panel(pm: &mut Pixmap, families: &BTreeMap<Family, FamilyCount>, frame: (f32, f32, f32, f32)) {
    let (x0, x1, y0, y1) = frame;
    let ink = vifo_cues::draw::rgb(INK);
    label(pm, "(a) Distribution across visual cue families", (x0 + x1) / 2.0, y0 - 30.0, 15.0, x1 - x0, ink);
    let max = 30.0;
    axis(pm, frame, max, 5.0, " %");
    let slot = (x1 - x0) / Family::ALL.len() as f32;
    let paper_share: BTreeMap<Family, f64> = paper::STATED_SHARES.into_iter().collect();
    for (i, family) in Family::ALL.iter().enumerate() {
        let c = families.get(family).copied();
        let share = c.map_or(0.0, |c| c.share * 100.0) as f32;
        let x = x0 + i as f32 * slot + slot * 0.12;
        let bar = slot * 0.36;
        let h = |p: f32| p.clamp(0.0, max) / max * (y1 - y0);
        rect(pm, x, y1 - h(share), bar, h(share), vifo_cues::draw::rgb(COLOURS[i]));
        label(pm, &format!("{share:.1}"), x + bar / 2.0, y1 - h(share) - 9.0, 10.0, bar + 14.0, ink);
        if let Some(p) = paper_share.get(family) {
            let p = (*p * 100.0) as f32;
            rect(pm, x + bar + 2.0, y1 - h(p), bar, h(p), vifo_cues::draw::rgb(PAPER_GREY));
            label(pm, &format!("{p:.1}"), x + bar * 1.5 + 2.0, y1 - h(p) - 9.0, 10.0, bar + 14.0, ink);
        }
        label(pm, short_name(*family), x0 + (i as f32 + 0.5) * slot, y1 + 14.0, 11.0, slot - 2.0, ink);
        let n = c.map_or(0, |c| c.instances);
        let tasks = c.map_or(0, |c| c.tasks);
        label(pm, &format!("{n} · {tasks} tasks"), x0 + (i as f32 + 0.5) * slot, y1 + 30.0, 10.0, slot - 2.0, ink);
    }
    legend(pm, x0, y1 + 56.0, "this set", "paper (stated shares only)");
}

/// (b): per component, this set's percent and the paper's.
fn coverage_panel(pm: &mut Pixmap, coverage: &BTreeMap<Component, Coverage>, frame: (f32, f32, f32, f32)) {
    let (x0, x1, y0, y1) = frame;
    let ink = vifo_cues::draw::rgb(INK);
    label(pm, "(b) Semantic coverage of cue instances", (x0 + x1) / 2.0, y0 - 30.0, 15.0, x1 - x0, ink);
    let max = 100.0;
    axis(pm, frame, max, 20.0, " %");
    let slot = (x1 - x0) / Component::ALL.len() as f32;
    for (i, component) in Component::ALL.iter().enumerate() {
        let c = coverage.get(component);
        let ours = c.map_or(0.0, |c| c.percent) as f32;
        let theirs = component.paper_percent() as f32;
        let x = x0 + i as f32 * slot + slot * 0.14;
        let bar = slot * 0.34;
        let h = |p: f32| p.clamp(0.0, max) / max * (y1 - y0);
        rect(pm, x, y1 - h(ours), bar, h(ours), vifo_cues::draw::rgb(COLOURS[0]));
        label(pm, &format!("{ours:.1}"), x + bar / 2.0, y1 - h(ours) - 9.0, 10.0, bar + 14.0, ink);
        rect(pm, x + bar + 2.0, y1 - h(theirs), bar, h(theirs), vifo_cues::draw::rgb(PAPER_GREY));
        label(pm, &format!("{theirs:.1}"), x + bar * 1.5 + 2.0, y1 - h(theirs) - 9.0, 10.0, bar + 14.0, ink);
        label(pm, component.label(), x0 + (i as f32 + 0.5) * slot, y1 + 14.0, 11.0, slot - 2.0, ink);
        let n = c.map_or(0, |c| c.instances);
        label(pm, &format!("{n} instances"), x0 + (i as f32 + 0.5) * slot, y1 + 30.0, 10.0, slot - 2.0, ink);
    }
    legend(pm, x0, y1 + 56.0, "this set", "paper");
}

fn legend(pm: &mut Pixmap, x: f32, y: f32, ours: &str, theirs: &str) {
    let ink = vifo_cues::draw::rgb(INK);
    rect(pm, x, y - 6.0, 12.0, 12.0, vifo_cues::draw::rgb(COLOURS[0]));
    legend_text(pm, ours, x + 18.0, y, ink);
    rect(pm, x + 120.0, y - 6.0, 12.0, 12.0, vifo_cues::draw::rgb(PAPER_GREY));
    legend_text(pm, theirs, x + 138.0, y, ink);
}
