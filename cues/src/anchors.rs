//! Image-space anchors of the source and target, and how to get them from any simulator.
//!
//! Scene-anchored cues only need pixel positions. A simulator provides them by implementing
//! [`Projector`] for its camera; [`Anchors::from_world`] does the rest (projected radius
//! from the object's box, behind-camera detection).

use serde::{Deserialize, Serialize};

/// A projected anchor: pixel position (u right, v down, may lie outside the image), optional
/// projected radius in pixels, and whether the point is in front of the camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    pub u: f64,
    pub v: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    pub in_front: bool,
}

impl Anchor {
    /// An anchor in front of the camera at (u, v).
    pub fn at(u: f64, v: f64) -> Anchor {
        Anchor { u, v, radius: None, in_front: true }
    }

    /// The same anchor with a projected radius.
    pub fn with_radius(self, r: f64) -> Anchor {
        Anchor { radius: Some(r), ..self }
    }

    /// Usable for drawing: in front of the camera and finite.
    pub fn usable(&self) -> bool {
        self.in_front && self.u.is_finite() && self.v.is_finite()
    }

    /// Inside a `width` × `height` image.
    pub fn inside(&self, width: u32, height: u32) -> bool {
        self.usable() && self.u >= 0.0 && self.v >= 0.0 && self.u < width as f64 && self.v < height as f64
    }
}

/// Anchors of the cue's source and target (either may be absent).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Anchors {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<Anchor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<Anchor>,
}

/// A camera that maps world points to (u, v, depth): pixels with u right and v down, depth
/// along the viewing direction (positive in front). Return `None` where the projection is
/// undefined; a point behind the camera may return a non-positive depth or `None`.
pub trait Projector {
    fn project(&self, world: [f64; 3]) -> Option<[f64; 3]>;
}

/// A world-space anchor: a centre and optionally the half extents of the object's
/// axis-aligned box (for the projected radius).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WorldAnchor {
    pub center: [f64; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_extents: Option<[f64; 3]>,
}

impl Anchor {
    /// Projects a world anchor. The radius is half the larger side of the box around the
    /// projected corners that lie in front of the camera.
    pub fn from_world(projector: &dyn Projector, world: &WorldAnchor) -> Anchor {
        let Some([u, v, depth]) = projector.project(world.center) else {
            return Anchor { u: f64::NAN, v: f64::NAN, radius: None, in_front: false };
        };
        let in_front = depth > 0.0 && u.is_finite() && v.is_finite();
        let radius = world.half_extents.filter(|_| in_front).and_then(|h| {
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for i in 0..8 {
                let sign = |bit: usize| if i >> bit & 1 == 1 { 1.0 } else { -1.0 };
                let corner = [
                    world.center[0] + sign(0) * h[0],
                    world.center[1] + sign(1) * h[1],
                    world.center[2] + sign(2) * h[2],
                ];
                if let Some([cu, cv, cd]) = projector.project(corner)
                    && cd > 0.0
                    && cu.is_finite()
                    && cv.is_finite()
                {
                    lo = [lo[0].min(cu), lo[1].min(cv)];
                    hi = [hi[0].max(cu), hi[1].max(cv)];
                }
            }
            (hi[0] >= lo[0]).then(|| ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 2.0).max(1.0))
        });
        Anchor { u, v, radius, in_front }
    }
}

impl Anchors {
    /// The anchors of the same frame mirrored left–right (`width` pixels wide): `u` becomes
    /// `width − u`, which mirrors the drawing coordinates (pixel `x` covers `[x, x + 1)`), so a
    /// symmetric mark drawn at the mirrored anchor and mirrored back lands where it was.
    pub fn mirrored(&self, width: u32) -> Anchors {
        let mirror = |a: Anchor| Anchor { u: width as f64 - a.u, ..a };
        Anchors { source: self.source.map(mirror), target: self.target.map(mirror) }
    }

    /// Projects the source and target world anchors with `projector`.
    pub fn from_world(
        projector: &dyn Projector,
        source: Option<&WorldAnchor>,
        target: Option<&WorldAnchor>,
    ) -> Anchors {
        Anchors {
            source: source.map(|w| Anchor::from_world(projector, w)),
            target: target.map(|w| Anchor::from_world(projector, w)),
        }
    }
}

/// A pinhole camera in the paper's convention (appendix B): camera-to-world rotation R_wc
/// (columns = camera axes in world frame, MuJoCo style: x right, y up, looking along −z),
/// centre c, vertical field of view, image size; f = H / (2 tan(fovy/2)), c = ((W−1)/2, (H−1)/2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PinholeCamera {
    pub position: [f64; 3],
    /// Row-major 3×3 camera-to-world rotation.
    pub rotation: [[f64; 3]; 3],
    pub fovy_deg: f64,
    pub width: u32,
    pub height: u32,
}

impl Projector for PinholeCamera {
    fn project(&self, world: [f64; 3]) -> Option<[f64; 3]> {
        let d = [world[0] - self.position[0], world[1] - self.position[1], world[2] - self.position[2]];
        let r = &self.rotation;
        // x_c = S R_wcᵀ (X − c), with S = diag(1, −1, −1) turning MuJoCo's camera (y up, −z
        // forward) into the renderer's (y down, +z forward).
        let xm = r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2];
        let ym = r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2];
        let zm = r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2];
        let (x, y, z) = (xm, -ym, -zm);
        let f = self.height as f64 / (2.0 * libm::tan(self.fovy_deg.to_radians() / 2.0));
        if !f.is_finite() || z.abs() < 1e-12 {
            return None;
        }
        let u = f * x / z + (self.width as f64 - 1.0) / 2.0;
        let v = f * y / z + (self.height as f64 - 1.0) / 2.0;
        Some([u, v, z])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera at the origin looking along world −z (identity rotation), 90° fov, 101² px.
    fn camera() -> PinholeCamera {
        PinholeCamera {
            position: [0.0; 3],
            rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            fovy_deg: 90.0,
            width: 101,
            height: 101,
        }
    }

    #[test]
    fn pinhole_projects_like_the_paper() {
        let cam = camera();
        let [u, v, z] = cam.project([0.0, 0.0, -1.0]).unwrap();
        assert!((u - 50.0).abs() < 1e-9 && (v - 50.0).abs() < 1e-9 && (z - 1.0).abs() < 1e-12);
        // World +y is up, so it appears above the centre (smaller v); f = 50.5 px at 90°.
        let [u, v, _] = cam.project([0.5, 0.5, -1.0]).unwrap();
        assert!((u - 75.25).abs() < 1e-9 && (v - 24.75).abs() < 1e-9, "{u} {v}");
    }

    #[test]
    fn anchors_behind_the_camera_are_marked() {
        let cam = camera();
        let behind = Anchor::from_world(&cam, &WorldAnchor { center: [0.0, 0.0, 1.0], half_extents: None });
        assert!(!behind.in_front && !behind.usable());
        let boxed =
            Anchor::from_world(&cam, &WorldAnchor { center: [0.0, 0.0, -2.0], half_extents: Some([0.1, 0.1, 0.1]) });
        let r = boxed.radius.unwrap();
        // Half-size 0.1 m at 1.9–2.1 m with f = 50.5 px: about 2.66 px.
        assert!(boxed.inside(101, 101) && (r - 50.5 * 0.1 / 1.9).abs() < 1e-6, "{r}");
    }
}
