//! Contact sheets: every variant of a family drawn on a real scene frame (agentview, a shipped
//! initial state after the settle steps), one tile per variant, labelled with its name.

use tiny_skia::{Pixmap, PixmapPaint, Transform};
use vifo_cues::draw::geom::{rect, v2};
use vifo_cues::draw::text::{Align, Face, block_path, centered_line, fit, line_width};
use vifo_cues::draw::{self, Rgba};
use vifo_cues::{CueSpec, Family, InsertMode, variants};
use vifo_render::{RgbImage, Renderer};
use vifo_scenes::sim::SceneModel;
use vifo_scenes::view::{Cameras, ImageOrder, SceneView};

use super::start::settled_start;
use super::{EpisodeCue, SceneCueError, instance, task_of};

/// Tiles per row.
const COLUMNS: usize = 4;
const MARGIN: u32 = 10;
const TITLE: u32 = 46;
const LABEL: u32 = 34;
const INK: Rgba = [25, 25, 30, 255];
const GREY: Rgba = [110, 110, 118, 255];
const WARN: Rgba = [200, 40, 30, 255];

/// The task a family is shown on: both ends of the step in clear view, apart enough to judge
/// where an arrow starts and ends, and a short instruction (the sticky note takes ≤ 45
/// characters). Variants the task cannot carry fall back to the first of a few other tasks
/// (`FALLBACK`) that can.
pub const SHOWCASE: &str = "libero_goal/1";
/// Tasks tried in order for a variant the showcase cannot carry (the last two for the signs
/// of state changes: "open the middle drawer of the cabinet", "turn on the stove").
const FALLBACK: [&str; 5] = ["libero_goal/1", "libero_goal/8", "libero_object/0", "libero_goal/0", "libero_goal/7"];

/// One contact sheet.
pub struct Sheet {
    pub family: Family,
    pub image: RgbImage,
    /// Cue ids on the sheet, in tile order.
    pub instances: Vec<String>,
    /// Ids whose expert demonstration failed (their ghosts or pictures show where it stopped).
    pub failed_demos: Vec<String>,
}

/// The instance of `variant` on `task`, or on the first fallback task that can carry it.
fn instance_for(task: &str, family: Family, variant: &str) -> Result<&'static CueSpec, SceneCueError> {
    let mut first_error = None;
    for key in std::iter::once(task).chain(FALLBACK) {
        match instance(&format!("{key}/{family}/{variant}")) {
            Ok(spec) => return Ok(spec),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.expect("the loop ran at least once"))
}

/// One frame with the cue: the task's scene at `init`, agentview at `size`².
fn tile(spec: &CueSpec, size: u32, init: usize, renderer: &mut Renderer) -> Result<(RgbImage, EpisodeCue), SceneCueError> {
    let task = task_of(spec)?;
    let model = SceneModel::build(task).map_err(|e| SceneCueError::Start { task: task.label(), init, why: e.to_string() })?;
    let sim = settled_start(&model, init)?;
    let mut view = SceneView::new(&model);
    view.update(&sim);
    let camera = Cameras::new(size, size).agentview(model.class);
    let mut cue = EpisodeCue::prepare(&sim, &view, renderer, spec, &task.goal, (size, size))?;
    let mut frame = view.render(renderer, &camera, ImageOrder::Upright)?.color;
    cue.apply(&sim, renderer, &camera, &mut frame)?;
    Ok((frame, cue))
}

/// One line of the sheet's heading at `y`, across the sheet between its side margins.
fn heading_line(pm: &mut Pixmap, face: Face, size: f32, text: &str, y: f32, color: Rgba) {
    let (x, w) = (MARGIN as f32, pm.width() as f32 - 2.0 * MARGIN as f32);
    let b = fit(face, text, w, size * 1.3, 6.0, size);
    if let Some(p) = block_path(&b, x, y, w, Align::Left) {
        draw::fill(pm, &p, color, Transform::identity());
    }
}

/// The contact sheet of `family` on `task` (`suite/index`, e.g. [`SHOWCASE`]).
pub fn sheet(family: Family, task: &str, size: u32, init: usize) -> Result<Sheet, SceneCueError> {
    let names: Vec<&str> = variants::of_family(family).map(|v| v.name).collect();
    let rows = names.len().div_ceil(COLUMNS) as u32;
    let cols = names.len().min(COLUMNS) as u32;
    let width = MARGIN + cols * (size + MARGIN);
    let height = TITLE + rows * (size + LABEL + MARGIN);
    let mut pm = Pixmap::new(width, height).ok_or_else(|| SceneCueError::Unsupported {
        cue: family.to_string(),
        why: format!("a {width}x{height} sheet is too large"),
    })?;
    pm.fill(tiny_skia::Color::WHITE);
    let shown = task
        .split_once('/')
        .and_then(|(suite, i)| vifo_scenes::task(suite, i.parse().ok()?))
        .ok_or_else(|| SceneCueError::Unsupported {
            cue: family.to_string(),
            why: format!("no task {task:?} to show it on (expected <suite>/<index>, e.g. {SHOWCASE})"),
        })?;
    let mode = match family.insert_mode() {
        InsertMode::SceneAnchored => "scene-anchored",
        InsertMode::FixedRegion => "fixed-region",
        InsertMode::SimulatorState => "simulator-state overlay",
    };
    let title = format!("{family} {} ({mode})", family.name());
    heading_line(&mut pm, Face::SansBold, 18.0, &title, 4.0, INK);
    let subtitle = format!("{task}: \"{}\" · agentview {size}² · initial state {init}", shown.instruction);
    heading_line(&mut pm, Face::Sans, 13.0, &subtitle, 26.0, GREY);

    let mut renderer = Renderer::default();
    let mut instances = Vec::new();
    let mut failed_demos = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let spec = instance_for(task, family, name)?;
        let (frame, cue) = tile(spec, size, init, &mut renderer)?;
        let x = MARGIN + (i as u32 % COLUMNS as u32) * (size + MARGIN);
        let y = TITLE + (i as u32 / COLUMNS as u32) * (size + LABEL + MARGIN);
        let framed = vifo_cues::RgbImage { width: frame.width, height: frame.height, data: frame.data };
        if let Some(tile_pm) = draw::from_rgb_image(&framed) {
            pm.draw_pixmap(x as i32, y as i32, tile_pm.as_ref(), &PixmapPaint::default(), Transform::identity(), None);
        }
        if let Some(p) = rect(x as f32 - 0.5, y as f32 - 0.5, size as f32 + 1.0, size as f32 + 1.0) {
            draw::stroke(&mut pm, &p, [180, 180, 186, 255], 1.0, Transform::identity());
        }
        let failed = cue.demo().is_some_and(|d| !d.success);
        let mut label = name.to_string();
        if spec.task != task {
            label = format!("{label}  ({})", spec.task);
        }
        if failed {
            label.push_str("  [demo failed]");
            failed_demos.push(spec.id());
        }
        if let Some(p) = centered_line(Face::SansBold, fit_size(&label, size as f32 - 4.0), &label, v2(x as f32 + size as f32 / 2.0, (y + size) as f32 + LABEL as f32 * 0.45)) {
            draw::fill(&mut pm, &p, if failed { WARN } else { INK }, Transform::identity());
        }
        instances.push(spec.id());
    }
    let data = pm.data().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    Ok(Sheet { family, image: RgbImage { width, height, data }, instances, failed_demos })
}

/// The largest font size (≤ 15) at which `text` fits `width` in bold.
fn fit_size(text: &str, width: f32) -> f32 {
    let mut s = 15.0;
    while s > 7.0 && line_width(Face::SansBold, s, text) > width {
        s -= 0.5;
    }
    s
}
