//! Category frames (the `g` of a sign): shape and colour say what kind of rule a sign states.
//!
//! | category | shape | colours |
//! |---|---|---|
//! | prohibition / restriction | disc with a thick ring | white, red ring, black pictogram |
//! | mandatory action | filled disc | blue, white pictogram |
//! | hazard warning | rounded triangle, apex up | yellow, black border and pictogram |
//! | permission / safe operation | rounded square | green, white pictogram |
//! | target / zone designation | square with corner brackets | white, purple brackets and pictogram |
//! | human–robot interaction | hexagon | orange, white pictogram |
//! | maintenance / service | pentagon ("house") | teal, white pictogram |
//! | system state / infrastructure | rounded panel with a status bar | navy, cyan border and pictogram |
//!
//! Shapes are pairwise different, so the category survives colour shifts and small sizes.

use serde::{Deserialize, Serialize};
use tiny_skia::{Pixmap, Transform};

use crate::draw::geom::{circle, polygon, polyline, rect, regular_polygon, rounded_rect, v2};
use crate::draw::{self, Rgba};

/// The eight functional categories of the robot signage taxonomy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    Prohibition,
    Mandatory,
    Hazard,
    Permission,
    TargetZone,
    HumanRobot,
    Maintenance,
    SystemState,
}

impl Category {
    pub const ALL: [Category; 8] = [
        Category::Prohibition,
        Category::Mandatory,
        Category::Hazard,
        Category::Permission,
        Category::TargetZone,
        Category::HumanRobot,
        Category::Maintenance,
        Category::SystemState,
    ];
}

/// What the frame leaves for the glyphs: fill ("paper") and ink colours, and the content box
/// as fractions of the sign size (x, y, w, h).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    pub fill: Rgba,
    pub ink: Rgba,
    pub content: (f32, f32, f32, f32),
}

const RED: Rgba = [206, 32, 41, 255];
const BLUE: Rgba = [0, 86, 166, 255];
const YELLOW: Rgba = [250, 200, 20, 255];
const GREEN: Rgba = [20, 140, 70, 255];
const PURPLE: Rgba = [118, 50, 200, 255];
const ORANGE: Rgba = [232, 108, 18, 255];
const TEAL: Rgba = [10, 124, 128, 255];
const NAVY: Rgba = [20, 34, 70, 255];
const CYAN: Rgba = [40, 210, 235, 255];
const INK: Rgba = [16, 16, 16, 255];

/// Draws the frame of `category` on an `s`-px square at the top of `pm`.
pub fn draw(pm: &mut Pixmap, category: Category, s: f32) -> Style {
    let ts = Transform::from_scale(s, s);
    let white = draw::WHITE;
    let outline = (0.02, [255, 255, 255, 255]); // white rim keeps signs readable on dark scenes
    match category {
        Category::Prohibition => {
            if let Some(p) = circle(v2(0.5, 0.5), 0.47) {
                draw::fill_outlined(pm, &p, RED, outline.1, outline.0, ts);
            }
            if let Some(p) = circle(v2(0.5, 0.5), 0.37) {
                draw::fill(pm, &p, white, ts);
            }
            Style { fill: white, ink: INK, content: (0.22, 0.22, 0.56, 0.56) }
        }
        Category::Mandatory => {
            if let Some(p) = circle(v2(0.5, 0.5), 0.47) {
                draw::fill_outlined(pm, &p, BLUE, outline.1, outline.0, ts);
            }
            Style { fill: BLUE, ink: white, content: (0.19, 0.19, 0.62, 0.62) }
        }
        Category::Hazard => {
            let corners = [v2(0.5, 0.05), v2(0.97, 0.9), v2(0.03, 0.9)];
            if let Some(p) = polygon(&corners) {
                draw::stroke(pm, &p, INK, 0.1, ts);
                draw::fill(pm, &p, YELLOW, ts);
                draw::stroke(pm, &p, INK, 0.045, ts);
            }
            Style { fill: YELLOW, ink: INK, content: (0.3, 0.38, 0.4, 0.46) }
        }
        Category::Permission => {
            if let Some(p) = rounded_rect(0.04, 0.04, 0.92, 0.92, 0.12) {
                draw::fill_outlined(pm, &p, GREEN, outline.1, outline.0, ts);
            }
            Style { fill: GREEN, ink: white, content: (0.12, 0.12, 0.76, 0.76) }
        }
        Category::TargetZone => {
            if let Some(p) = rect(0.04, 0.04, 0.92, 0.92) {
                draw::fill(pm, &p, white, ts);
                draw::stroke(pm, &p, PURPLE, 0.02, ts);
            }
            let (a, b, l) = (0.06, 0.94, 0.24);
            for (corner, dx, dy) in [((a, a), 1.0, 1.0), ((b, a), -1.0, 1.0), ((a, b), 1.0, -1.0), ((b, b), -1.0, -1.0)]
            {
                let c = v2(corner.0, corner.1);
                if let Some(p) = polyline(&[v2(c.x, c.y + dy * l), c, v2(c.x + dx * l, c.y)]) {
                    draw::stroke(pm, &p, PURPLE, 0.07, ts);
                }
            }
            Style { fill: white, ink: PURPLE, content: (0.15, 0.15, 0.7, 0.7) }
        }
        Category::HumanRobot => {
            if let Some(p) = regular_polygon(v2(0.5, 0.5), 0.49, 6, 0.0) {
                draw::fill_outlined(pm, &p, ORANGE, outline.1, outline.0, ts);
            }
            Style { fill: ORANGE, ink: white, content: (0.19, 0.17, 0.62, 0.66) }
        }
        Category::Maintenance => {
            if let Some(p) = polygon(&[v2(0.5, 0.03), v2(0.96, 0.36), v2(0.96, 0.96), v2(0.04, 0.96), v2(0.04, 0.36)]) {
                draw::fill_outlined(pm, &p, TEAL, outline.1, outline.0, ts);
            }
            Style { fill: TEAL, ink: white, content: (0.16, 0.3, 0.68, 0.62) }
        }
        Category::SystemState => {
            if let Some(p) = rounded_rect(0.04, 0.04, 0.92, 0.92, 0.08) {
                draw::fill(pm, &p, NAVY, ts);
                draw::stroke(pm, &p, CYAN, 0.04, ts);
            }
            for (i, x) in [0.68, 0.77, 0.86].into_iter().enumerate() {
                let color = [[60, 220, 90, 255], [250, 200, 20, 255], CYAN][i];
                if let Some(p) = circle(v2(x, 0.13), 0.035) {
                    draw::fill(pm, &p, color, ts);
                }
            }
            Style { fill: NAVY, ink: CYAN, content: (0.14, 0.2, 0.72, 0.7) }
        }
    }
}
