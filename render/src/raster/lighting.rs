//! Per-vertex lighting as OpenGL's fixed-function pipeline computes it with MuJoCo's settings.
//!
//! MuJoCo (`render_gl3.c`) enables `GL_LIGHTING` with `GL_COLOR_MATERIAL` tracking ambient and
//! diffuse, a local viewer, one-sided lighting, a global ambient of 0 whenever any light exists
//! (0.3 otherwise), and the headlight as a directional light along the view direction. Colours
//! are computed at vertices, clamped to `[0, 1]` and interpolated (Gouraud), like OpenGL.
//!
//! Everything here works in renderer camera coordinates (x right, y down, z forward, eye at the
//! origin), so the view vector is just `-p`.

use glam::{Vec3, Vec4};

use crate::camera::Camera;
use crate::scene::{LightKind, Material, Scene};
use crate::transform::normalize;

/// Lights are stored four to a block, one per lane of a `Vec4`, and applied one after another
/// to [`VERTEX_LANES`] vertices at once ([`LightRig::shade_lanes`]).
const LANES: usize = 4;

/// Up to four lights in camera coordinates. Unused lanes have zero colours.
#[derive(Clone, Copy, Debug)]
struct LightBlock {
    /// Position of a positional light; unit vector towards a directional one.
    x: Vec4,
    y: Vec4,
    z: Vec4,
    /// Spot lights with a cutoff below 180° (1 per lane, else 0). Lane flags are kept as
    /// floats and turned into masks with `cmpgt` where used, because glam's mask type differs
    /// between its SIMD and scalar (`scalar-math`) builds.
    spot: Vec4,
    /// Unit spot axis and cosine of the cutoff angle.
    ax: Vec4,
    ay: Vec4,
    az: Vec4,
    cos_cutoff: Vec4,
    /// Integer spot exponents as bit masks (`exponent_bits[b]`: the lanes whose exponent has
    /// bit `b`) and the number of bits in use; lanes with a non-integer exponent are listed in
    /// `fractional` instead.
    exponent_bits: [Vec4; 8],
    bits: u32,
    fractional: [Option<f32>; LANES],
    /// Attenuation `1 / (a0 + a1 d + a2 d²)` (1, 0, 0 for directional lights).
    a0: Vec4,
    a1: Vec4,
    a2: Vec4,
    ambient: [Vec4; 3],
    diffuse: [Vec4; 3],
    specular: [Vec4; 3],
    /// 1 in the lane of the shadow-casting light.
    shadow: Vec4,
    /// What each lane computes per vertex; see [`LaneKind`].
    kind: [LaneKind; LANES],
}

/// How much of a light's term depends on the vertex. Each kind computes exactly what the
/// general positional formula gives for it, in fewer operations.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LaneKind {
    /// No light: its term is exactly +0 and is left out.
    Unused,
    /// A directional light: the unit vector to it, as the general formula normalizes it (the
    /// same for every vertex, since `x − p·0` is `x` once `x` has no negative zero); no spot,
    /// and an attenuation of exactly 1.
    Directional([f32; 3]),
    /// A positional light whose attenuation does not depend on distance (`a1 = a2 = 0`):
    /// `1 / a0`, or 1 where `a0` is not positive, as the general formula gives it.
    Constant(f32),
    Positional,
}

impl Default for LightBlock {
    fn default() -> Self {
        LightBlock {
            x: Vec4::ZERO,
            y: Vec4::ZERO,
            z: Vec4::ZERO,
            spot: Vec4::ZERO,
            ax: Vec4::ZERO,
            ay: Vec4::ZERO,
            az: Vec4::ZERO,
            cos_cutoff: Vec4::ZERO,
            exponent_bits: [Vec4::ZERO; 8],
            bits: 0,
            fractional: [None; LANES],
            a0: Vec4::ONE,
            a1: Vec4::ZERO,
            a2: Vec4::ZERO,
            ambient: [Vec4::ZERO; 3],
            diffuse: [Vec4::ZERO; 3],
            specular: [Vec4::ZERO; 3],
            shadow: Vec4::ZERO,
            kind: [LaneKind::Unused; LANES],
        }
    }
}

/// The frame's lights, moved into camera coordinates once per frame.
#[derive(Default)]
pub(crate) struct LightRig {
    blocks: Vec<LightBlock>,
    lights: usize,
    /// Whether a lane holds the shadow-casting light (else every contribution goes to `base`).
    shadowing: bool,
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
    /// [`Power::of`] for each vertex lane of [`LightRig::shade_lanes`].
    #[inline]
    fn of_vertex_lanes(&self, x: wide::f32x8) -> wide::f32x8 {
        match *self {
            Power::Int(k) => repeated_squaring(x, wide::f32x8::ONE, k),
            _ => wide::f32x8::from(x.to_array().map(|v| self.of(v))),
        }
    }

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

    /// Rebuilds the rig for `camera`; the first shadow-casting light is kept apart when
    /// `shadows` is on.
    pub(crate) fn prepare(&mut self, scene: &Scene, camera: &Camera, shadows: bool) {
        for inst in &scene.instances {
            let e = phong_exponent(&inst.material);
            if e != e.floor() && self.pow_tables.len() < MAX_POW_TABLES && !self.pow_tables.iter().any(|(te, _)| *te == e) {
                let table = (0..=POW_SAMPLES).map(|i| libm::powf(i as f32 / POW_SAMPLES as f32, e)).collect();
                self.pow_tables.push((e, table));
            }
        }
        self.blocks.clear();
        self.lights = 0;
        let h = &scene.headlight;
        if h.active {
            // Directional, travelling along the view axis (+z in camera coordinates).
            self.push(Vec3::new(0.0, 0.0, -1.0), None, [h.ambient, h.diffuse, h.specular], false);
        }
        let mut shadow_taken = false;
        for light in &scene.lights {
            let colours = [light.ambient, light.diffuse, light.specular];
            let casts = shadows && light.cast_shadow && !shadow_taken;
            shadow_taken |= casts;
            match light.kind {
                LightKind::Directional { direction } => {
                    self.push(-normalize(camera.direction_to_camera(direction)), None, colours, casts);
                }
                LightKind::Spot { position, direction, cutoff_deg, exponent, attenuation } => {
                    let spot = Spot {
                        axis: normalize(camera.direction_to_camera(direction)),
                        cos_cutoff: (cutoff_deg < 180.0).then(|| libm::cosf(cutoff_deg.clamp(0.0, 90.0).to_radians())),
                        exponent: exponent.clamp(0.0, 128.0),
                        attenuation,
                    };
                    self.push(camera.world_to_camera(position), Some(spot), colours, casts);
                }
            }
        }
        self.shadowing = shadow_taken;
        self.global_ambient = if self.lights > 0 { 0.0 } else { 0.3 };
    }

    /// Adds a light in the next free lane: `at` is the position of a positional light
    /// (`spot` given) or the unit vector towards a directional one.
    fn push(&mut self, at: Vec3, spot: Option<Spot>, colours: [[f32; 3]; 3], casts_shadow: bool) {
        let lane = self.lights % LANES;
        if lane == 0 {
            self.blocks.push(LightBlock::default());
        }
        self.lights += 1;
        let b = self.blocks.last_mut().expect("a block was just ensured");
        // A directional light's vector loses any negative zero (`-0 + 0 = +0`), so that
        // `x − p·0` is `x` for every vertex `p` and the vector can be normalized once.
        let at = if spot.is_some() { at } else { at + Vec3::ZERO };
        (b.x[lane], b.y[lane], b.z[lane]) = (at.x, at.y, at.z);
        b.kind[lane] = match &spot {
            None => {
                let dist = (at.x * at.x + at.y * at.y + at.z * at.z).sqrt();
                let inv = if dist > 0.0 { 1.0 / dist } else { 0.0 };
                LaneKind::Directional([at.x * inv, at.y * inv, at.z * inv])
            }
            Some(Spot { attenuation: [a0, a1, a2], .. }) if *a1 == 0.0 && *a2 == 0.0 => LaneKind::Constant(if *a0 > 0.0 { 1.0 / a0 } else { 1.0 }),
            Some(_) => LaneKind::Positional,
        };
        if let Some(s) = spot {
            [b.a0[lane], b.a1[lane], b.a2[lane]] = s.attenuation;
            if let Some(cos) = s.cos_cutoff {
                b.spot[lane] = 1.0;
                (b.ax[lane], b.ay[lane], b.az[lane]) = (s.axis.x, s.axis.y, s.axis.z);
                b.cos_cutoff[lane] = cos;
                if s.exponent == s.exponent.floor() {
                    let e = s.exponent as u32;
                    for (bit, mask) in b.exponent_bits.iter_mut().enumerate() {
                        mask[lane] = if (e >> bit) & 1 == 1 { 1.0 } else { 0.0 };
                    }
                    b.bits = b.bits.max(u32::BITS - e.leading_zeros());
                } else {
                    b.fractional[lane] = Some(s.exponent);
                }
            }
        }
        for (target, source) in [&mut b.ambient, &mut b.diffuse, &mut b.specular].into_iter().zip(colours) {
            for (t, value) in target.iter_mut().zip(source) {
                t[lane] = value;
            }
        }
        b.shadow[lane] = if casts_shadow { 1.0 } else { 0.0 };
    }

    /// Lights a vertex at camera-space `p` with (not necessarily unit) normal `n` (clipped and
    /// blended triangles, which are few: one vertex in every lane).
    pub(crate) fn shade(&self, s: &Surface<'_>, p: Vec3, n: Vec3) -> Lit {
        let lanes = |v: Vec3| [[v.x; VERTEX_LANES], [v.y; VERTEX_LANES], [v.z; VERTEX_LANES]];
        self.shade_lanes(s, lanes(p), lanes(n)).lit(0)
    }
}

/// Vertices lit at once by [`LightRig::shade_lanes`].
pub(crate) const VERTEX_LANES: usize = 8;

/// Lit colours of [`VERTEX_LANES`] vertices by coordinate: RGBA from the unshadowed lights and
/// RGB from the shadow-casting one, before the clamp (which unlit surfaces skip).
pub(crate) struct LitLanes {
    base: [[f32; VERTEX_LANES]; 4],
    shadowed: [[f32; VERTEX_LANES]; 3],
    clamped: bool,
}

impl LitLanes {
    /// Lane `l`'s colour, clamped to `[0, 1]` per channel as OpenGL clamps per pass.
    pub(crate) fn lit(&self, l: usize) -> Lit {
        let clamp = |x: f32| if self.clamped { x.clamp(0.0, 1.0) } else { x };
        Lit {
            base: [clamp(self.base[0][l]), clamp(self.base[1][l]), clamp(self.base[2][l]), self.base[3][l]],
            shadowed: [clamp(self.shadowed[0][l]), clamp(self.shadowed[1][l]), clamp(self.shadowed[2][l])],
        }
    }
}

impl LightRig {
    /// Lights eight vertices at once (camera-space positions `p` and not necessarily unit
    /// normals `n`, by coordinate), one vertex per SIMD lane and one light after another. The
    /// lanes are `wide`'s, which fall back to plain `f32`s where the target has no SIMD: the
    /// same IEEE operations either way, so the same results natively and in wasm.
    pub(crate) fn shade_lanes(&self, s: &Surface<'_>, p: [[f32; VERTEX_LANES]; 3], n: [[f32; VERTEX_LANES]; 3]) -> LitLanes {
        type V = wide::f32x8;
        let splat = V::splat;
        if s.unlit {
            return LitLanes { base: [s.rgb.x, s.rgb.y, s.rgb.z, s.alpha].map(|c| [c; VERTEX_LANES]), shadowed: [[0.0; VERTEX_LANES]; 3], clamped: false };
        }
        let zero = V::ZERO;
        let normalized = |x: V, y: V, z: V| {
            let len = (x * x + y * y + z * z).sqrt();
            let (scale, keep) = (V::ONE / len, len.simd_gt(zero));
            (keep.select(x * scale, zero), keep.select(y * scale, zero), keep.select(z * scale, zero))
        };
        let (px, py, pz) = (V::from(p[0]), V::from(p[1]), V::from(p[2]));
        let (nx, ny, nz) = normalized(V::from(n[0]), V::from(n[1]), V::from(n[2]));
        // The eye is at the origin: the view vector is `-p`.
        let (vx, vy, vz) = normalized(-px, -py, -pz);
        let rgb = s.rgb.to_array();
        let ambient = s.emission + s.rgb * self.global_ambient;
        let mut base = [splat(ambient.x), splat(ambient.y), splat(ambient.z)];
        let mut shadowed = [zero; 3];
        for b in &self.blocks {
            // OpenGL's terms per light (RGB), then summed in lane order.
            let mut terms = [[zero; LANES]; 3];
            for l in 0..LANES {
                let lane = |v: Vec4| splat(v[l]);
                // Unit vector to the light, and the spot and attenuation factor (`None`: 1).
                let (lx, ly, lz, factor) = match b.kind[l] {
                    LaneKind::Unused => continue,
                    LaneKind::Directional([x, y, z]) => (splat(x), splat(y), splat(z), None),
                    kind => {
                        let lx = lane(b.x) - px;
                        let ly = lane(b.y) - py;
                        let lz = lane(b.z) - pz;
                        let dist = (lx * lx + ly * ly + lz * lz).sqrt();
                        let inv = dist.simd_gt(zero).select(V::ONE / dist, zero);
                        let (lx, ly, lz) = (lx * inv, ly * inv, lz * inv);
                        // Spot cone: max(−l·axis, 0)^exponent inside the cutoff, 0 outside; 1
                        // for other lights. (`fast_max(x, 0)` gives 0 for NaN, as `f32::max`
                        // does.)
                        let cos = (-(lx * lane(b.ax) + ly * lane(b.ay) + lz * lane(b.az))).fast_max(zero);
                        let (mut power, mut spot) = (cos, V::ONE);
                        for mask in &b.exponent_bits[..b.bits as usize] {
                            if mask[l] > 0.0 {
                                spot *= power;
                            }
                            power *= power;
                        }
                        if let Some(e) = b.fractional[l] {
                            spot = V::from(cos.to_array().map(|c| libm::powf(c, e)));
                        }
                        let spot = if b.spot[l] > 0.0 { cos.simd_ge(lane(b.cos_cutoff)).select(spot, zero) } else { V::ONE };
                        let attenuation = match kind {
                            LaneKind::Constant(inv_a0) => splat(inv_a0),
                            _ => {
                                let den = lane(b.a0) + lane(b.a1) * dist + lane(b.a2) * dist * dist;
                                den.simd_gt(zero).select(V::ONE / den, V::ONE)
                            }
                        };
                        (lx, ly, lz, Some(spot * attenuation))
                    }
                };
                // Diffuse and Blinn-Phong specular (only where the light is in front of the surface).
                let ndl = nx * lx + ny * ly + nz * lz;
                let (hx, hy, hz) = (lx + vx, ly + vy, lz + vz);
                let hlen = (hx * hx + hy * hy + hz * hz).sqrt();
                let ndh = hlen.simd_gt(zero).select(((nx * hx + ny * hy + nz * hz) * (V::ONE / hlen)).fast_max(zero), zero);
                let front = ndl.simd_gt(zero);
                let diffuse = front.select(ndl, zero);
                let specular = front.select(s.power.of_vertex_lanes(ndh) * splat(s.specular), zero);
                for k in 0..3 {
                    let term = lane(b.ambient[k]) * splat(rgb[k]) + lane(b.diffuse[k]) * (diffuse * splat(rgb[k])) + lane(b.specular[k]) * specular;
                    terms[k][l] = factor.map_or(term, |f| term * f);
                }
            }
            for (k, t) in terms.iter().enumerate() {
                if !self.shadowing {
                    base[k] += t[0] + t[1] + t[2] + t[3];
                    continue;
                }
                // Each light goes to exactly one of the two sums.
                let plain = |l: usize| t[l] * splat(1.0 - b.shadow[l]);
                let cast = |l: usize| t[l] * splat(b.shadow[l]);
                base[k] += plain(0) + plain(1) + plain(2) + plain(3);
                shadowed[k] += cast(0) + cast(1) + cast(2) + cast(3);
            }
        }
        LitLanes {
            base: [base[0].to_array(), base[1].to_array(), base[2].to_array(), [s.alpha; VERTEX_LANES]],
            shadowed: shadowed.map(|c| c.to_array()),
            clamped: true,
        }
    }
}

/// A positional light's spot parameters while it is being added to a block.
struct Spot {
    axis: Vec3,
    cos_cutoff: Option<f32>,
    exponent: f32,
    attenuation: [f32; 3],
}

/// `x^k` by repeated squaring (a fixed sequence of multiplications).
#[inline]
fn powi(x: f32, k: u32) -> f32 {
    repeated_squaring(x, 1.0, k)
}

/// `x^k` by repeated squaring from `one`, for a scalar or lanes: the same multiplications in the
/// same order either way, so lanes and scalars agree bit for bit.
#[inline]
fn repeated_squaring<T: Copy + std::ops::MulAssign>(x: T, one: T, mut k: u32) -> T {
    let (mut base, mut acc) = (x, one);
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
    use crate::scene::{Headlight, Light, LightKind};

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
        for &(x, e) in &[(0.9f32, 10u32), (0.5, 64), (0.99, 1), (0.0, 3), (0.7, 128)] {
            let want = libm::powf(x, e as f32);
            assert!((powi(x, e) - want).abs() <= 1e-6 * want.max(1e-30));
            let lanes = Power::Int(e).of_vertex_lanes(wide::f32x8::splat(x)).to_array();
            assert_eq!(lanes, [powi(x, e); VERTEX_LANES]);
        }
        assert_eq!(powi(0.0, 0), 1.0);
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
        assert!((lit.base[0] - 0.7 * 0.5 * c * powi(c, 10)).abs() < 1e-5);
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
    fn each_lane_is_lit_as_its_vertex_alone() {
        let mut scene = Scene::default();
        let mut spot = Light::mujoco_spot(Vec3::new(0.3, -0.2, 1.5), Vec3::new(0.1, 0.0, -1.0));
        spot.kind = LightKind::Spot { position: Vec3::new(0.3, -0.2, 1.5), direction: Vec3::new(0.1, 0.0, -1.0), cutoff_deg: 60.0, exponent: 2.5, attenuation: [0.5, 0.3, 0.2] };
        spot.ambient = [0.1, 0.05, 0.0];
        scene.lights.push(spot);
        scene.lights.push(Light::mujoco_spot(Vec3::new(-1.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -1.0)));
        scene.lights.push(Light::mujoco_directional(Vec3::new(0.2, 0.3, -1.0)));
        scene.lights.push(Light { cast_shadow: false, ..Light::mujoco_spot(Vec3::new(0.0, 2.0, 1.0), Vec3::new(0.0, -1.0, -0.5)) });
        let materials = [
            Material { shininess: 0.5, ..mat(0.5) },
            Material { shininess: 0.1, ..mat(1.0) },
            Material { rgba: [1.5, 0.2, -0.1, 0.7], unlit: true, ..mat(0.0) },
            Material { emission: 0.3, shininess: 1.0, ..mat(0.8) },
        ];
        scene.instances = materials.iter().map(|m| crate::Instance::new(std::sync::Arc::new(crate::Mesh::plane(1.0, 1.0)), crate::Transform::IDENTITY, 1).with_material(m.clone())).collect();
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 64);
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        for shadows in [false, true] {
            let mut rig = LightRig::default();
            rig.prepare(&scene, &cam, shadows);
            for m in &materials {
                let s = rig.surface(m);
                for _ in 0..20 {
                    let mut p = [[0.0; VERTEX_LANES]; 3];
                    let mut n = [[0.0; VERTEX_LANES]; 3];
                    for l in 0..VERTEX_LANES {
                        for k in 0..3 {
                            p[k][l] = next() + if k == 2 { 2.0 } else { 0.0 };
                            // One lane with a zero normal, which normalizes to zero.
                            n[k][l] = if l == 5 { 0.0 } else { next() };
                        }
                    }
                    let lanes = rig.shade_lanes(&s, p, n);
                    for l in 0..VERTEX_LANES {
                        let one = rig.shade(&s, Vec3::new(p[0][l], p[1][l], p[2][l]), Vec3::new(n[0][l], n[1][l], n[2][l]));
                        assert_eq!(lanes.lit(l), one, "shadows {shadows}, material {m:?}, lane {l}");
                    }
                }
            }
        }
    }

    /// One light's term as the general positional formula computes it for one vertex
    /// (directional lights with `x − p·0`, attenuation from the distance), without the shortcuts
    /// of [`LaneKind`].
    fn general_term(b: &LightBlock, l: usize, s: &Surface<'_>, p: Vec3, n: Vec3) -> [f32; 3] {
        let positional = if matches!(b.kind[l], LaneKind::Directional(_)) { 0.0 } else { 1.0 };
        let unit = |v: Vec3| {
            let len = (v.x * v.x + v.y * v.y + v.z * v.z).sqrt();
            let inv = if len > 0.0 { 1.0 / len } else { 0.0 };
            Vec3::new(v.x * inv, v.y * inv, v.z * inv)
        };
        let (n, v) = (unit(n), unit(-p));
        let raw = Vec3::new(b.x[l] - p.x * positional, b.y[l] - p.y * positional, b.z[l] - p.z * positional);
        let dist = (raw.x * raw.x + raw.y * raw.y + raw.z * raw.z).sqrt();
        let l_unit = unit(raw);
        let cos = (-(l_unit.x * b.ax[l] + l_unit.y * b.ay[l] + l_unit.z * b.az[l])).max(0.0);
        let spot = match (b.spot[l] > 0.0, b.fractional[l]) {
            (false, _) => 1.0,
            (true, _) if cos < b.cos_cutoff[l] => 0.0,
            (true, Some(e)) => libm::powf(cos, e),
            (true, None) => (0..b.bits as usize).fold((cos, 1.0f32), |(power, spot), bit| (power * power, if b.exponent_bits[bit][l] > 0.0 { spot * power } else { spot })).1,
        };
        let den = b.a0[l] + b.a1[l] * dist + b.a2[l] * dist * dist;
        let factor = spot * if den > 0.0 { 1.0 / den } else { 1.0 };
        let ndl = n.x * l_unit.x + n.y * l_unit.y + n.z * l_unit.z;
        let h = Vec3::new(l_unit.x + v.x, l_unit.y + v.y, l_unit.z + v.z);
        let hlen = (h.x * h.x + h.y * h.y + h.z * h.z).sqrt();
        let ndh = if hlen > 0.0 { ((n.x * h.x + n.y * h.y + n.z * h.z) * (1.0 / hlen)).max(0.0) } else { 0.0 };
        let (diffuse, specular) = if ndl > 0.0 { (ndl, s.power.of(ndh) * s.specular) } else { (0.0, 0.0) };
        std::array::from_fn(|k| (b.ambient[k][l] * s.rgb[k] + b.diffuse[k][l] * (diffuse * s.rgb[k]) + b.specular[k][l] * specular) * factor)
    }

    #[test]
    fn each_light_kind_gives_what_the_general_formula_gives() {
        // The headlight and a directional light with exact zeros (negative ones in camera
        // coordinates), spots with constant and distance attenuation, an integer and a
        // fractional exponent, and an unused lane in the second block.
        let mut scene = Scene::default();
        scene.lights.push(Light::mujoco_directional(Vec3::new(0.0, 0.0, -1.0)));
        scene.lights.push(Light::mujoco_spot(Vec3::new(1.0, 1.0, 4.0), Vec3::new(0.0, -0.15, -1.0)));
        let mut far = Light::mujoco_spot(Vec3::new(-0.5, 0.4, 1.2), Vec3::new(0.2, 0.0, -1.0));
        far.kind = LightKind::Spot { position: Vec3::new(-0.5, 0.4, 1.2), direction: Vec3::new(0.2, 0.0, -1.0), cutoff_deg: 70.0, exponent: 3.5, attenuation: [0.5, 0.3, 0.2] };
        scene.lights.push(far);
        scene.lights.push(Light::mujoco_directional(Vec3::new(0.3, -0.2, -1.0)));
        let m = Material { shininess: 0.5, ..mat(0.7) };
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 64);
        let mut rig = LightRig::default();
        rig.prepare(&scene, &cam, false);
        let kinds: Vec<LaneKind> = rig.blocks.iter().flat_map(|b| b.kind).collect();
        assert!(matches!(kinds[..], [LaneKind::Directional(_), LaneKind::Directional(_), LaneKind::Constant(_), LaneKind::Positional, LaneKind::Directional(_), LaneKind::Unused, ..]), "{kinds:?}");
        let s = rig.surface(&m);
        let mut seed = 777u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            // Some exact zeros of both signs among the coordinates.
            match seed >> 28 {
                0 => 0.0,
                1 => -0.0,
                _ => (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0,
            }
        };
        for _ in 0..2000 {
            let p = Vec3::new(next(), next(), next() + 2.0);
            let n = Vec3::new(next(), next(), next());
            let mut want = [0.0f32; 3];
            for (bi, b) in rig.blocks.iter().enumerate() {
                let used = (rig.lights - bi * LANES).min(LANES);
                let t: Vec<[f32; 3]> = (0..LANES).map(|l| if l < used { general_term(b, l, &s, p, n) } else { [0.0; 3] }).collect();
                for (k, w) in want.iter_mut().enumerate() {
                    *w += t[0][k] + t[1][k] + t[2][k] + t[3][k];
                }
            }
            let got = rig.shade(&s, p, n);
            for (k, w) in want.iter().enumerate() {
                assert_eq!(got.base[k].to_bits(), w.clamp(0.0, 1.0).to_bits(), "channel {k} at {p:?}, normal {n:?}");
            }
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
