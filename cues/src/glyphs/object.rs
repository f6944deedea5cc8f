//! Object silhouettes, chosen from an object's name.

use serde::{Deserialize, Serialize};
use tiny_skia::{PathBuilder, Pixmap, Transform};

use super::Pen;
use crate::draw::geom::{circle, ellipse, line, polygon, polyline, quad, rect, rounded_rect, v2};

/// The silhouettes we can draw. LIBERO's objects map onto these by name ([`ObjectShape::for_name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectShape {
    Bowl,
    Plate,
    Mug,
    Bottle,
    Carton,
    Can,
    Pot,
    Pan,
    Book,
    Basket,
    Cabinet,
    Stove,
    Microwave,
    Rack,
    Human,
    Station,
    Generic,
}

impl ObjectShape {
    /// Picks a silhouette from words in the name ("black bowl" → bowl, "bbq sauce" → bottle,
    /// "top drawer of the cabinet" → cabinet). Unknown names get a generic block.
    pub fn for_name(name: &str) -> ObjectShape {
        const KEYWORDS: &[(&str, ObjectShape)] = &[
            ("microwave", ObjectShape::Microwave),
            ("drawer", ObjectShape::Cabinet),
            ("cabinet", ObjectShape::Cabinet),
            ("shelf", ObjectShape::Cabinet),
            ("stove", ObjectShape::Stove),
            ("rack", ObjectShape::Rack),
            ("basket", ObjectShape::Basket),
            ("tray", ObjectShape::Basket),
            ("caddy", ObjectShape::Basket),
            ("compartment", ObjectShape::Basket),
            ("bowl", ObjectShape::Bowl),
            ("ramekin", ObjectShape::Bowl),
            ("plate", ObjectShape::Plate),
            ("mug", ObjectShape::Mug),
            ("cup", ObjectShape::Mug),
            ("moka", ObjectShape::Pot),
            ("pot", ObjectShape::Pot),
            ("pan", ObjectShape::Pan),
            ("book", ObjectShape::Book),
            ("bottle", ObjectShape::Bottle),
            ("dressing", ObjectShape::Bottle),
            ("ketchup", ObjectShape::Bottle),
            ("bbq", ObjectShape::Bottle),
            ("soup", ObjectShape::Can),
            ("tomato sauce", ObjectShape::Can),
            ("can", ObjectShape::Can),
            ("cheese", ObjectShape::Carton),
            ("butter", ObjectShape::Carton),
            ("milk", ObjectShape::Carton),
            ("juice", ObjectShape::Carton),
            ("pudding", ObjectShape::Carton),
            ("cookie", ObjectShape::Carton),
            ("box", ObjectShape::Carton),
            ("person", ObjectShape::Human),
            ("human", ObjectShape::Human),
            ("charger", ObjectShape::Station),
            ("dock", ObjectShape::Station),
        ];
        KEYWORDS.iter().find(|(k, _)| name.contains(k)).map_or(ObjectShape::Generic, |(_, s)| *s)
    }
}

/// Draws the silhouette in the unit box.
pub fn draw(pm: &mut Pixmap, shape: ObjectShape, pen: Pen, ts: Transform) {
    let w = 0.05; // detail line width
    match shape {
        ObjectShape::Bowl => {
            let mut pb = PathBuilder::new();
            pb.move_to(0.06, 0.42);
            pb.line_to(0.94, 0.42);
            pb.cubic_to(0.94, 0.72, 0.72, 0.84, 0.5, 0.84);
            pb.cubic_to(0.28, 0.84, 0.06, 0.72, 0.06, 0.42);
            pb.close();
            pen.fill(pm, pb.finish(), ts);
            pen.fill(pm, rect(0.36, 0.8, 0.28, 0.08), ts);
            pen.cut(pm, ellipse(v2(0.5, 0.42), 0.44, 0.07), w, ts);
        }
        ObjectShape::Plate => {
            pen.fill(pm, ellipse(v2(0.5, 0.62), 0.46, 0.18), ts);
            pen.cut(pm, ellipse(v2(0.5, 0.6), 0.28, 0.09), w, ts);
            pen.fill(pm, rect(0.3, 0.76, 0.4, 0.06), ts);
        }
        ObjectShape::Mug => {
            pen.line(pm, rounded_rect(0.58, 0.38, 0.28, 0.32, 0.12), 0.09, ts);
            pen.fill(pm, rounded_rect(0.14, 0.26, 0.52, 0.62, 0.06), ts);
            pen.cut(pm, line(v2(0.2, 0.36), v2(0.6, 0.36)), w, ts);
        }
        ObjectShape::Bottle => {
            let mut pb = PathBuilder::new();
            pb.move_to(0.43, 0.06);
            pb.line_to(0.57, 0.06);
            pb.line_to(0.57, 0.3);
            pb.cubic_to(0.57, 0.36, 0.7, 0.38, 0.7, 0.46);
            pb.line_to(0.7, 0.9);
            pb.line_to(0.3, 0.9);
            pb.line_to(0.3, 0.46);
            pb.cubic_to(0.3, 0.38, 0.43, 0.36, 0.43, 0.3);
            pb.close();
            pen.fill(pm, pb.finish(), ts);
            pen.cut(pm, rect(0.36, 0.56, 0.28, 0.2), w, ts);
        }
        ObjectShape::Carton => {
            pen.fill(
                pm,
                polygon(&[v2(0.12, 0.34), v2(0.34, 0.16), v2(0.9, 0.16), v2(0.9, 0.7), v2(0.68, 0.9), v2(0.12, 0.9)]),
                ts,
            );
            pen.cut(pm, polyline(&[v2(0.12, 0.34), v2(0.68, 0.34), v2(0.9, 0.16)]), w, ts);
            pen.cut(pm, line(v2(0.68, 0.34), v2(0.68, 0.9)), w, ts);
        }
        ObjectShape::Can => {
            pen.fill(pm, rect(0.24, 0.2, 0.52, 0.66), ts);
            pen.fill(pm, ellipse(v2(0.5, 0.2), 0.26, 0.08), ts);
            pen.fill(pm, ellipse(v2(0.5, 0.86), 0.26, 0.08), ts);
            pen.cut(pm, ellipse(v2(0.5, 0.2), 0.2, 0.05), w, ts);
            pen.cut(pm, quad(v2(0.24, 0.44), v2(0.5, 0.52), v2(0.76, 0.44)), w, ts);
            pen.cut(pm, quad(v2(0.24, 0.66), v2(0.5, 0.74), v2(0.76, 0.66)), w, ts);
        }
        ObjectShape::Pot => {
            pen.fill(pm, polygon(&[v2(0.26, 0.9), v2(0.74, 0.9), v2(0.64, 0.56), v2(0.36, 0.56)]), ts);
            pen.fill(pm, polygon(&[v2(0.34, 0.54), v2(0.66, 0.54), v2(0.72, 0.2), v2(0.28, 0.2)]), ts);
            pen.fill(pm, polygon(&[v2(0.3, 0.24), v2(0.14, 0.2), v2(0.32, 0.34)]), ts);
            pen.line(pm, polyline(&[v2(0.7, 0.26), v2(0.88, 0.3), v2(0.84, 0.62), v2(0.66, 0.7)]), 0.07, ts);
            pen.fill(pm, circle(v2(0.5, 0.14), 0.06), ts);
        }
        ObjectShape::Pan => {
            pen.fill(pm, ellipse(v2(0.36, 0.58), 0.3, 0.16), ts);
            pen.cut(pm, ellipse(v2(0.36, 0.55), 0.22, 0.1), w, ts);
            pen.line(pm, line(v2(0.64, 0.54), v2(0.95, 0.4)), 0.08, ts);
        }
        ObjectShape::Book => {
            pen.fill(pm, polygon(&[v2(0.16, 0.22), v2(0.72, 0.12), v2(0.84, 0.78), v2(0.28, 0.9)]), ts);
            pen.cut(pm, line(v2(0.26, 0.24), v2(0.36, 0.84)), w, ts);
            pen.cut(pm, line(v2(0.42, 0.36), v2(0.68, 0.31)), w, ts);
        }
        ObjectShape::Basket => {
            pen.line(pm, quad(v2(0.2, 0.44), v2(0.5, -0.02), v2(0.8, 0.44)), 0.07, ts);
            pen.fill(pm, polygon(&[v2(0.06, 0.44), v2(0.94, 0.44), v2(0.8, 0.9), v2(0.2, 0.9)]), ts);
            for x in [0.34, 0.5, 0.66] {
                pen.cut(pm, line(v2(x, 0.5), v2(x, 0.84)), 0.04, ts);
            }
            pen.cut(pm, line(v2(0.14, 0.64), v2(0.86, 0.64)), 0.04, ts);
        }
        ObjectShape::Cabinet => {
            pen.fill(pm, rect(0.16, 0.08, 0.68, 0.86), ts);
            for y in [0.36, 0.64] {
                pen.cut(pm, line(v2(0.16, y), v2(0.84, y)), w, ts);
            }
            for y in [0.22, 0.5, 0.78] {
                pen.cut(pm, line(v2(0.4, y), v2(0.6, y)), 0.06, ts);
            }
        }
        ObjectShape::Stove => {
            pen.fill(pm, rect(0.06, 0.36, 0.88, 0.5), ts);
            pen.cut(pm, ellipse(v2(0.3, 0.52), 0.16, 0.08), w, ts);
            pen.cut(pm, ellipse(v2(0.7, 0.52), 0.16, 0.08), w, ts);
            for x in [0.3, 0.5, 0.7] {
                pen.hole(pm, circle(v2(x, 0.75), 0.045), ts);
            }
        }
        ObjectShape::Microwave => {
            pen.fill(pm, rect(0.06, 0.22, 0.88, 0.6), ts);
            pen.hole(pm, rect(0.14, 0.3, 0.5, 0.44), ts);
            for y in [0.36, 0.52, 0.68] {
                pen.hole(pm, circle(v2(0.78, y), 0.04), ts);
            }
        }
        ObjectShape::Rack => {
            pen.line(pm, rect(0.1, 0.2, 0.8, 0.7), 0.07, ts);
            pen.line(pm, line(v2(0.1, 0.2), v2(0.9, 0.9)), 0.05, ts);
            pen.line(pm, line(v2(0.9, 0.2), v2(0.1, 0.9)), 0.05, ts);
            pen.line(pm, line(v2(0.5, 0.2), v2(0.1, 0.55)), 0.05, ts);
            pen.line(pm, line(v2(0.5, 0.2), v2(0.9, 0.55)), 0.05, ts);
        }
        ObjectShape::Human => {
            pen.fill(pm, circle(v2(0.5, 0.2), 0.12), ts);
            pen.fill(pm, rounded_rect(0.3, 0.36, 0.4, 0.36, 0.12), ts);
            pen.line(pm, line(v2(0.4, 0.7), v2(0.38, 0.94)), 0.12, ts);
            pen.line(pm, line(v2(0.6, 0.7), v2(0.62, 0.94)), 0.12, ts);
        }
        ObjectShape::Station => {
            pen.fill(pm, rounded_rect(0.22, 0.12, 0.56, 0.8, 0.06), ts);
            pen.hole(
                pm,
                polygon(&[
                    v2(0.56, 0.22),
                    v2(0.36, 0.54),
                    v2(0.5, 0.54),
                    v2(0.44, 0.82),
                    v2(0.64, 0.46),
                    v2(0.5, 0.46),
                ]),
                ts,
            );
        }
        ObjectShape::Generic => {
            pen.fill(
                pm,
                polygon(&[v2(0.5, 0.1), v2(0.88, 0.3), v2(0.88, 0.72), v2(0.5, 0.92), v2(0.12, 0.72), v2(0.12, 0.3)]),
                ts,
            );
            pen.cut(pm, polyline(&[v2(0.12, 0.3), v2(0.5, 0.5), v2(0.88, 0.3)]), w, ts);
            pen.cut(pm, line(v2(0.5, 0.5), v2(0.5, 0.92)), w, ts);
        }
    }
}
