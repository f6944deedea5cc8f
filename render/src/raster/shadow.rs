//! Optional shadow mapping for one light.
//!
//! The scene is rendered depth-only from the light (perspective for a spot light, orthographic
//! fitted to the scene for a directional one), with no face culling, as MuJoCo does. The main
//! pass then removes that light's contribution from pixels whose surface lies behind the
//! nearest surface the light sees.

use glam::{Mat3, Vec3};

use super::triangle::{orientation, snap, Setup};
use crate::camera::Camera;
use crate::scene::{LightKind, Scene};
use crate::transform::{cross, dot, mul_mat3, mul_mat3_mat3, normalize, Transform};

/// Light-space points closer than this (m) to a spot light are not drawn into its map.
const SPOT_NEAR: f32 = 0.01;
/// Widest spot-light shadow frustum (half-angle, degrees); point lights use this too.
const MAX_HALF_ANGLE_DEG: f32 = 80.0;

#[derive(Clone, Copy, Debug)]
enum Projection {
    /// `s = f · x / z + c`, key `1 / z`.
    Perspective { f: f32 },
    /// `s = scale · x + c`, key `−z`.
    Orthographic { scale: f32 },
}

/// A depth map seen from one light, plus the transform from the main camera into it.
pub(crate) struct ShadowMap {
    size: u32,
    /// Per texel the largest key (nearest surface) seen; `f32::NEG_INFINITY` where empty.
    keys: Vec<f32>,
    projection: Projection,
    /// Light-space rotation (rows: light x, y, z axes in world) and origin.
    light_rot: Mat3,
    origin: Vec3,
    /// Camera coordinates → light coordinates.
    from_camera: Transform,
    scratch: Vec<(Vec3, (i64, i64), f32)>,
}

impl Default for ShadowMap {
    fn default() -> Self {
        ShadowMap {
            size: 0,
            keys: Vec::new(),
            projection: Projection::Orthographic { scale: 1.0 },
            light_rot: Mat3::IDENTITY,
            origin: Vec3::ZERO,
            from_camera: Transform::IDENTITY,
            scratch: Vec::new(),
        }
    }
}

impl ShadowMap {
    /// Renders the map for the first shadow-casting light of `scene`; returns false (and keeps
    /// no map) if there is none.
    pub(crate) fn build(&mut self, scene: &Scene, camera: &Camera, size: u32) -> bool {
        let Some(light) = scene.lights.iter().find(|l| l.cast_shadow) else {
            return false;
        };
        let size = size.clamp(16, 8192);
        let (origin, forward, projection) = match light.kind {
            LightKind::Spot { position, direction, cutoff_deg, .. } => {
                let half = cutoff_deg.clamp(1.0, MAX_HALF_ANGLE_DEG).to_radians();
                let f = size as f32 / (2.0 * libm::tanf(half));
                (position, normalize(direction), Projection::Perspective { f })
            }
            LightKind::Directional { direction } => {
                let (center, radius) = scene_bounds(scene);
                let forward = normalize(direction);
                let radius = radius.max(1e-3);
                (center - forward * (radius + 1.0), forward, Projection::Orthographic { scale: size as f32 / (2.0 * radius) })
            }
        };
        if !(origin.is_finite() && forward.length_squared() > 0.0) {
            return false;
        }
        let helper = if forward.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
        let x = normalize(cross(forward, helper));
        let y = cross(forward, x);
        // Rows are the light axes: world → light is `light_rot * (p − origin)`.
        self.light_rot = Mat3::from_cols(x, y, forward).transpose();
        self.origin = origin;
        self.projection = projection;
        self.size = size;
        self.keys.clear();
        self.keys.resize(size as usize * size as usize, f32::NEG_INFINITY);
        // Camera coordinates → world: R · diag(1, −1, −1) · c + position.
        let cam_to_world = Mat3::from_cols(camera.rotation.x_axis, -camera.rotation.y_axis, -camera.rotation.z_axis);
        self.from_camera = Transform {
            linear: mul_mat3_mat3(&self.light_rot, &cam_to_world),
            translation: mul_mat3(&self.light_rot, camera.position - origin),
        };
        for inst in &scene.instances {
            self.draw(inst);
        }
        true
    }

    fn draw(&mut self, inst: &crate::scene::Instance) {
        let t = &inst.transform;
        if !(t.linear.is_finite() && t.translation.is_finite()) {
            return;
        }
        let linear = mul_mat3_mat3(&self.light_rot, &t.linear);
        let trans = mul_mat3(&self.light_rot, t.translation - self.origin);
        let c = (self.size as f32 - 1.0) * 0.5;
        let projection = self.projection;
        self.scratch.clear();
        self.scratch.extend(inst.mesh.positions().iter().map(|&p| {
            let l = mul_mat3(&linear, p) + trans;
            let (s, key) = match projection {
                Projection::Perspective { f } if l.z >= SPOT_NEAR => {
                    let iz = 1.0 / l.z;
                    ((f * l.x * iz + c, f * l.y * iz + c), iz)
                }
                Projection::Perspective { .. } => ((f32::NAN, f32::NAN), f32::NAN),
                Projection::Orthographic { scale } => ((scale * l.x + c, scale * l.y + c), -l.z),
            };
            (l, (snap(s.0), snap(s.1)), key)
        }));
        for tri in inst.mesh.triangles() {
            let [a, b, c] = tri.map(|i| self.scratch[i as usize]);
            if !(a.2.is_finite() && b.2.is_finite() && c.2.is_finite()) {
                continue; // Behind or too close to a spot light.
            }
            let mut v = [a.1, b.1, c.1];
            let mut keys = [a.2, b.2, c.2];
            if orientation(v) < 0 {
                v.swap(1, 2);
                keys.swap(1, 2);
            }
            let Some(setup) = Setup::new(v, self.size, self.size) else { continue };
            let plane = setup.plane(keys);
            let map = &mut self.keys;
            setup.for_each_pixel(&plane, self.size, |idx, _, _, key| {
                if key > map[idx] {
                    map[idx] = key;
                }
            });
        }
    }

    /// 1 if the light reaches camera-space point `p`, else 0.
    #[inline]
    pub(crate) fn visibility(&self, p: Vec3) -> f32 {
        let l = self.from_camera.transform_point(p);
        let c = (self.size as f32 - 1.0) * 0.5;
        let (sx, sy, texel) = match self.projection {
            Projection::Perspective { f } => {
                if !(l.z > SPOT_NEAR) {
                    return 1.0;
                }
                (f * l.x / l.z + c, f * l.y / l.z + c, l.z / f)
            }
            Projection::Orthographic { scale } => (scale * l.x + c, scale * l.y + c, 1.0 / scale),
        };
        let (i, j) = ((sx + 0.5).floor(), (sy + 0.5).floor());
        if !(i >= 0.0 && j >= 0.0 && i < self.size as f32 && j < self.size as f32) {
            return 1.0;
        }
        let key = self.keys[j as usize * self.size as usize + i as usize];
        if key == f32::NEG_INFINITY {
            return 1.0;
        }
        let nearest = match self.projection {
            Projection::Perspective { .. } => 1.0 / key,
            Projection::Orthographic { .. } => -key,
        };
        // A few texels of slope bias hide self-shadowing ("acne").
        let bias = 3.0 * texel + 1e-3;
        if nearest < l.z - bias { 0.0 } else { 1.0 }
    }
}

/// Centre and radius of a sphere enclosing every instance's bounding sphere.
fn scene_bounds(scene: &Scene) -> (Vec3, f32) {
    let spheres: Vec<(Vec3, f32)> = scene
        .instances
        .iter()
        .filter(|i| i.transform.linear.is_finite() && i.transform.translation.is_finite())
        .map(|i| {
            let b = i.mesh.bounds();
            (i.transform.transform_point(b.center), b.radius * i.transform.max_scale())
        })
        .collect();
    if spheres.is_empty() {
        return (Vec3::ZERO, 1.0);
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &(c, r) in &spheres {
        lo = lo.min(c - Vec3::splat(r));
        hi = hi.max(c + Vec3::splat(r));
    }
    let center = (lo + hi) * 0.5;
    let radius = spheres.iter().map(|&(c, r)| dot(c - center, c - center).sqrt() + r).fold(0.0f32, f32::max);
    (center, radius)
}
