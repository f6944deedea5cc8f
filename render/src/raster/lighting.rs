//! Per-vertex lighting as OpenGL's fixed-function pipeline computes it with MuJoCo's settings.
//!
//! MuJoCo (`render_gl3.c`) enables `GL_LIGHTING` with `GL_COLOR_MATERIAL` tracking ambient and
//! diffuse, a local viewer, one-sided lighting, a global ambient of 0 whenever any light exists
//! (0.3 otherwise), and the headlight as a directional light along the view direction. Colours
//! are computed at vertices, clamped to `[0, 1]` and interpolated (Gouraud), like OpenGL.
//!
//! Everything here works in renderer camera coordinates (x right, y down, z forward, eye at the
//! origin), so the view vector is just `-p`.

use glam::Vec3;

use crate::camera::Camera;
use crate::scene::{LightKind, Material, Scene};
use crate::transform::{dot, normalize};

/// Where a light's rays come from, in camera coordinates.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// Unit vector from any surface point towards the light.
    Directional { to_light: Vec3 },
    /// A positional light; `cos_cutoff = None` for a point light (cutoff 180°).
    Spot { position: Vec3, axis: Vec3, cos_cutoff: Option<f32>, exponent: f32, attenuation: [f32; 3] },
}

#[derive(Clone, Copy, Debug)]
struct CamLight {
    source: Source,
    ambient: Vec3,
    diffuse: Vec3,
    specular: Vec3,
}

/// The frame's lights, moved into camera coordinates once per frame.
#[derive(Default)]
pub(crate) struct LightRig {
    /// Lights whose contribution is never shadowed.
    plain: Vec<CamLight>,
    /// The one light whose contribution is kept apart so the shadow test can remove it.
    shadowed: Option<CamLight>,
    global_ambient: f32,
    /// `x^e` tables for the scene's non-integer Phong exponents, kept across frames.
    pow_tables: Vec<(f32, Vec<f32>)>,
}

/// Samples per `x^e` table over `[0, 1]`; linear interpolation between them is accurate to
/// about 0.002 even for `e = 128`, below one 8-bit colour step.
const POW_SAMPLES: usize = 1024;
/// At most this many distinct non-integer exponents get a table; others use `libm::powf`.
const MAX_POW_TABLES: usize = 32;

/// How a surface raises `n·h` to its Phong exponent.
#[derive(Clone, Copy, Debug)]
enum Power<'a> {
    /// Integer exponent: repeated squaring.
    Int(u32),
    Table(&'a [f32]),
    Libm(f32),
}

impl Power<'_> {
    #[inline]
    fn of(&self, x: f32) -> f32 {
        match *self {
            Power::Int(k) => powi(x, k),
            Power::Table(t) => {
                let f = x.clamp(0.0, 1.0) * POW_SAMPLES as f32;
                let i = (f as usize).min(POW_SAMPLES - 1);
                t[i] + (t[i + 1] - t[i]) * (f - i as f32)
            }
            Power::Libm(e) => libm::powf(x, e),
        }
    }
}

/// A material's lighting parameters, prepared once per instance.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface<'a> {
    rgb: Vec3,
    alpha: f32,
    specular: f32,
    power: Power<'a>,
    emission: Vec3,
    unlit: bool,
}

/// MuJoCo's Phong exponent for a material (NaN → 0).
fn phong_exponent(m: &Material) -> f32 {
    (m.shininess * 128.0).clamp(0.0, 128.0)
}

/// A lit vertex colour: the part from unshadowed lights (RGBA, alpha = material alpha) and the
/// part from the shadow-casting light (RGB), each clamped to `[0, 1]` as OpenGL clamps per pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Lit {
    pub base: [f32; 4],
    pub shadowed: [f32; 3],
}

impl LightRig {
    /// Lighting parameters of material `m` for this rig.
    pub(crate) fn surface(&self, m: &Material) -> Surface<'_> {
        let rgb = Vec3::new(m.rgba[0], m.rgba[1], m.rgba[2]);
        let e = phong_exponent(m);
        let power = if e == e.floor() {
            Power::Int(e as u32)
        } else {
            self.pow_tables.iter().find(|(te, _)| *te == e).map_or(Power::Libm(e), |(_, t)| Power::Table(t))
        };
        Surface { rgb, alpha: m.rgba[3].clamp(0.0, 1.0), specular: m.specular, power, emission: rgb * m.emission, unlit: m.unlit }
    }

    /// Rebuilds the rig for `camera`; the first shadow-casting light is split off when
    /// `shadows` is on.
    pub(crate) fn prepare(&mut self, scene: &Scene, camera: &Camera, shadows: bool) {
        self.plain.clear();
        self.shadowed = None;
        for inst in &scene.instances {
            let e = phong_exponent(&inst.material);
            if e != e.floor() && self.pow_tables.len() < MAX_POW_TABLES && !self.pow_tables.iter().any(|(te, _)| *te == e) {
                let table = (0..=POW_SAMPLES).map(|i| libm::powf(i as f32 / POW_SAMPLES as f32, e)).collect();
                self.pow_tables.push((e, table));
            }
        }
        let to_cam = |v: Vec3| camera.direction_to_camera(v);
        let h = &scene.headlight;
        if h.active {
            self.plain.push(CamLight {
                source: Source::Directional { to_light: Vec3::new(0.0, 0.0, -1.0) },
                ambient: Vec3::from(h.ambient),
                diffuse: Vec3::from(h.diffuse),
                specular: Vec3::from(h.specular),
            });
        }
        for light in &scene.lights {
            let source = match light.kind {
                LightKind::Directional { direction } => Source::Directional { to_light: -normalize(to_cam(direction)) },
                LightKind::Spot { position, direction, cutoff_deg, exponent, attenuation } => Source::Spot {
                    position: camera.world_to_camera(position),
                    axis: normalize(to_cam(direction)),
                    cos_cutoff: (cutoff_deg < 180.0).then(|| libm::cosf(cutoff_deg.clamp(0.0, 90.0).to_radians())),
                    exponent: exponent.clamp(0.0, 128.0),
                    attenuation,
                },
            };
            let cam_light = CamLight {
                source,
                ambient: Vec3::from(light.ambient),
                diffuse: Vec3::from(light.diffuse),
                specular: Vec3::from(light.specular),
            };
            if shadows && light.cast_shadow && self.shadowed.is_none() {
                self.shadowed = Some(cam_light);
            } else {
                self.plain.push(cam_light);
            }
        }
        let any = !self.plain.is_empty() || self.shadowed.is_some();
        self.global_ambient = if any { 0.0 } else { 0.3 };
    }

    /// Lights a vertex at camera-space `p` with (not necessarily unit) normal `n`.
    pub(crate) fn shade(&self, s: &Surface<'_>, p: Vec3, n: Vec3) -> Lit {
        if s.unlit {
            return Lit { base: [s.rgb.x, s.rgb.y, s.rgb.z, s.alpha], shadowed: [0.0; 3] };
        }
        let n = normalize(n);
        let view = normalize(-p);
        let mut c = s.emission + s.rgb * self.global_ambient;
        for l in &self.plain {
            c += contribution(l, s, p, n, view);
        }
        let sh = self.shadowed.as_ref().map_or(Vec3::ZERO, |l| contribution(l, s, p, n, view));
        let c = c.clamp(Vec3::ZERO, Vec3::ONE);
        let sh = sh.clamp(Vec3::ZERO, Vec3::ONE);
        Lit { base: [c.x, c.y, c.z, s.alpha], shadowed: [sh.x, sh.y, sh.z] }
    }
}

/// One light's term of the OpenGL lighting equation.
fn contribution(l: &CamLight, s: &Surface<'_>, p: Vec3, n: Vec3, view: Vec3) -> Vec3 {
    let (to_light, factor) = match l.source {
        Source::Directional { to_light } => (to_light, 1.0),
        Source::Spot { position, axis, cos_cutoff, exponent, attenuation } => {
            let d = position - p;
            let dist = dot(d, d).sqrt();
            let to_light = if dist > 0.0 { d * (1.0 / dist) } else { Vec3::ZERO };
            let spot = match cos_cutoff {
                None => 1.0,
                Some(cos_cut) => {
                    let c = dot(-to_light, axis).max(0.0);
                    if c < cos_cut { 0.0 } else { pow(c, exponent) }
                }
            };
            let att = match attenuation {
                [1.0, 0.0, 0.0] => 1.0, // MuJoCo's default: skip the division.
                [a0, a1, a2] => {
                    let den = a0 + a1 * dist + a2 * dist * dist;
                    if den > 0.0 { 1.0 / den } else { 1.0 }
                }
            };
            (to_light, att * spot)
        }
    };
    if !(factor > 0.0) {
        return Vec3::ZERO;
    }
    let mut c = l.ambient * s.rgb;
    let ndl = dot(n, to_light);
    if ndl > 0.0 {
        c += l.diffuse * s.rgb * ndl;
        if s.specular > 0.0 {
            let half = normalize(to_light + view);
            let ndh = dot(n, half).max(0.0);
            c += l.specular * (s.specular * s.power.of(ndh));
        }
    }
    c * factor
}

/// `x^e` for `x ≥ 0`, bit-identical on every platform: integer exponents by repeated
/// squaring, others through `libm`. `0^0 = 1` as in OpenGL implementations.
fn pow(x: f32, e: f32) -> f32 {
    if e == e.floor() && (0.0..=256.0).contains(&e) { powi(x, e as u32) } else { libm::powf(x, e) }
}

/// `x^k` by repeated squaring (a fixed sequence of multiplications).
#[inline]
fn powi(x: f32, mut k: u32) -> f32 {
    let (mut base, mut acc) = (x, 1.0f32);
    while k > 0 {
        if k & 1 == 1 {
            acc *= base;
        }
        base *= base;
        k >>= 1;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Headlight, Light};

    fn rig(scene: &Scene) -> LightRig {
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 64);
        let mut r = LightRig::default();
        r.prepare(scene, &cam, false);
        r
    }

    fn mat(specular: f32) -> Material {
        Material { rgba: [0.5, 0.5, 0.5, 1.0], specular, ..Material::default() }
    }

    #[test]
    fn pow_matches_libm_for_integer_exponents() {
        for &(x, e) in &[(0.9f32, 10.0f32), (0.5, 64.0), (0.99, 1.0), (0.0, 3.0)] {
            assert!((pow(x, e) - libm::powf(x, e)).abs() <= 1e-6 * libm::powf(x, e).max(1e-30));
        }
        assert_eq!(pow(0.0, 0.0), 1.0);
    }

    #[test]
    fn headlight_facing_surface_gets_ambient_plus_diffuse_plus_specular() {
        let scene = Scene::default();
        let r = rig(&scene);
        // A surface 2 m in front, facing the camera: n·L = 1, n·H = 1.
        let lit = r.shade(&r.surface(&mat(0.5)), Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -1.0));
        let expect = 0.1 * 0.5 + 0.4 * 0.5 + 0.5 * 0.5;
        assert!((lit.base[0] - expect).abs() < 1e-6, "{lit:?}");
        // Facing away: ambient only.
        let back = r.shade(&r.surface(&mat(0.5)), Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, 1.0));
        assert!((back.base[0] - 0.05).abs() < 1e-6);
    }

    #[test]
    fn spot_light_respects_cutoff_and_exponent() {
        let mut scene = Scene { headlight: Headlight { active: false, ..Headlight::default() }, ..Scene::default() };
        // Light 1 m above the origin pointing down (world); camera looks down from z = 2.
        let mut light = Light::mujoco_spot(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0));
        light.specular = [0.0; 3];
        scene.lights.push(light);
        let r = rig(&scene);
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 64);
        let up_normal = cam.world_to_camera(cam.position + Vec3::Z);
        let on_axis = r.shade(&r.surface(&mat(0.0)), cam.world_to_camera(Vec3::ZERO), up_normal);
        assert!((on_axis.base[0] - 0.7 * 0.5).abs() < 1e-6, "{on_axis:?}");
        // 30° off-axis: cos^10 fall-off and n·L = cos 30°.
        let off = Vec3::new(libm::tanf(30f32.to_radians()), 0.0, 0.0);
        let lit = r.shade(&r.surface(&mat(0.0)), cam.world_to_camera(off), up_normal);
        let c = 30f32.to_radians().cos();
        assert!((lit.base[0] - 0.7 * 0.5 * c * pow(c, 10.0)).abs() < 1e-5);
        // Beyond the 45° cutoff: dark (no global ambient because a light exists).
        let far = r.shade(&r.surface(&mat(0.0)), cam.world_to_camera(Vec3::new(2.0, 0.0, 0.0)), up_normal);
        assert_eq!(far.base[0], 0.0);
    }

    #[test]
    fn non_integer_exponents_use_an_accurate_table() {
        let m = Material { shininess: 0.1, ..mat(1.0) };
        let scene = Scene { instances: vec![crate::Instance::new(std::sync::Arc::new(crate::Mesh::plane(1.0, 1.0)), crate::Transform::IDENTITY, 1).with_material(m.clone())], ..Scene::default() };
        let r = rig(&scene);
        let s = r.surface(&m);
        assert!(matches!(s.power, Power::Table(_)));
        for k in 0..=100 {
            let x = k as f32 / 100.0;
            assert!((s.power.of(x) - libm::powf(x, 12.8)).abs() < 2e-3, "{x}");
        }
    }

    #[test]
    fn no_lights_means_global_ambient() {
        let scene = Scene { headlight: Headlight { active: false, ..Headlight::default() }, ..Scene::default() };
        let r = rig(&scene);
        let lit = r.shade(&r.surface(&mat(0.5)), Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
        assert!((lit.base[0] - 0.15).abs() < 1e-6);
    }
}
