//! The resolve: each pixel of the visibility buffer shaded once from its triangle's record
//! (perspective-correct colour and UV, textured), and how those records are built and shaded,
//! which the blended pass shares.

use glam::Vec3;

use super::layer::PixelBox;
use super::shadow::ShadowMap;
use super::triangle::{Plane, Planes};
use super::view::View;
use super::{Renderer, ScreenVert, TriRecord, NO_TRIANGLE};
use crate::camera::Intrinsics;
use crate::frame::Frame;
use crate::scene::{Background, Instance, Scene};
use crate::texture::Texture;

impl Renderer {
    /// Shades every pixel of `region` once from the visibility buffer, one run of same-triangle
    /// pixels at a time. With `from > 0`, only pixels of records from `from` on, which all lie
    /// in `region`: `out` holds the others (the static layer's).
    pub(super) fn resolve(&self, scene: &Scene, view: &View, out: &mut Frame, from: u32, region: PixelBox) {
        let shadows = self.shadows_active.then_some(&self.shadow);
        let sky = Sky::new(scene.background, view);
        let w = view.width as usize;
        for j in region.y0..=region.y1 {
            let row = j as usize * w..(j as usize + 1) * w;
            let ids = &self.tri_id[row.clone()];
            let depths = &self.depth[row.clone()];
            let rgb_out = &mut out.color.data[row.start * 3..row.end * 3];
            let depth_out = &mut out.depth[row.clone()];
            let seg_out = &mut out.segmentation[row];
            let fj = j as f32;
            let (mut start, stop) = (region.x0 as usize, region.x1 as usize + 1);
            while start < stop {
                let id = ids[start];
                let end = start + run_length(&ids[start..stop]);
                if from > 0 && (id < from || id == NO_TRIANGLE) {
                    // Already in `out`.
                } else if id == NO_TRIANGLE {
                    for k in start..end {
                        depth_out[k] = f32::INFINITY;
                        seg_out[k] = 0;
                        put_rgb(rgb_out, k, sky.color(k as u32, j));
                    }
                } else {
                    let rec = &self.records[id as usize];
                    seg_out[start..end].fill(rec.segment);
                    if rec.mip == u32::MAX && shadows.is_none() {
                        // Common case: Gouraud colour only.
                        let rows = rec.rgb.map(|p| p.b * fj + p.c);
                        for k in start..end {
                            let z = 1.0 / depths[k];
                            depth_out[k] = z;
                            // Through i32 (the same float): its conversion vectorizes.
                            let fi = k as i32 as f32;
                            put_rgb(rgb_out, k, std::array::from_fn(|c| (rec.rgb[c].a * fi + rows[c]) * z));
                        }
                    } else {
                        let sh = shadows.map(|_| self.shadow_rgb[id as usize]);
                        let texture = texture_of(rec, scene);
                        let mut first = start;
                        if let (Some(tex), None) = (texture, shadows) {
                            // Long runs (large textured triangles) eight pixels at a time.
                            while end - first >= LANES {
                                let shaded = shade_textured8(rec, tex, first, fj, depths[first..first + LANES].try_into().unwrap());
                                put_group(depth_out, rgb_out, first, LANES, shaded);
                                first += LANES;
                            }
                            // A shorter run, or a long one's tail, as one group whose lanes past
                            // the run repeat its last pixel and are not written.
                            let n = end - first;
                            if n >= WIDE_TAIL {
                                let shaded = shade_textured8(rec, tex, first, fj, std::array::from_fn(|l| depths[first + l.min(n - 1)]));
                                put_group(depth_out, rgb_out, first, n, shaded);
                                first = end;
                            }
                        }
                        for k in first..end {
                            let z = 1.0 / depths[k];
                            depth_out[k] = z;
                            let c = shade(rec, sh.as_ref(), shadows, texture, view, k as u32, j, z);
                            put_rgb(rgb_out, k, [c[0], c[1], c[2]]);
                        }
                    }
                }
                start = end;
            }
        }
    }
}

/// How many ids at the start of `ids` (not empty) equal the first, compared eight at a time:
/// runs are long where large triangles fill the view.
#[inline]
fn run_length(ids: &[u32]) -> usize {
    use wide::u32x8;
    let first = u32x8::splat(ids[0]);
    let mut n = 0;
    for chunk in ids.chunks_exact(8) {
        let differ = !u32x8::from(chunk).simd_eq(first).to_bitmask() & 0xFF;
        if differ != 0 {
            return n + differ.trailing_zeros() as usize;
        }
        n += 8;
    }
    n + ids[n..].iter().take_while(|&&x| x == ids[0]).count()
}

/// Writes pixel `k` of a packed RGB row.
#[inline]
fn put_rgb(row: &mut [u8], k: usize, rgb: [f32; 3]) {
    let px = &mut row[3 * k..3 * k + 3];
    px[0] = to_u8(rgb[0]);
    px[1] = to_u8(rgb[1]);
    px[2] = to_u8(rgb[2]);
}

/// The shading record of a set-up screen triangle, plus the shadow-light colour planes when
/// shadows are on.
pub(super) fn build_record(planes: &Planes, sv: &[ScreenVert; 3], inst: &Instance, idx: u32, shadows: bool) -> (TriRecord, Option<[Plane; 3]>) {
    let iz = [sv[0].iz, sv[1].iz, sv[2].iz];
    let per_z = |f: fn(&ScreenVert) -> f32| planes.plane([f(&sv[0]) * iz[0], f(&sv[1]) * iz[1], f(&sv[2]) * iz[2]]);
    let texture = inst.material.texture.as_deref().filter(|_| inst.mesh.uvs().is_some());
    let mip = texture.map_or(u32::MAX, |t| mip_level(t, sv, planes.area2));
    let rec = TriRecord {
        iz: planes.plane(iz),
        rgb: [per_z(|v| v.lit.base[0]), per_z(|v| v.lit.base[1]), per_z(|v| v.lit.base[2])],
        uv: if texture.is_some() { [per_z(|v| v.uv.x), per_z(|v| v.uv.y)] } else { [Plane::default(); 2] },
        instance: idx,
        segment: inst.segment,
        mip,
        alpha: inst.material.rgba[3].clamp(0.0, 1.0),
    };
    let sh = shadows.then(|| [per_z(|v| v.lit.shadowed[0]), per_z(|v| v.lit.shadowed[1]), per_z(|v| v.lit.shadowed[2])]);
    (rec, sh)
}

/// The mip level whose texels best match this triangle's pixels (one level per triangle).
fn mip_level(t: &Texture, sv: &[ScreenVert; 3], screen_area2: f32) -> u32 {
    let (d1, d2) = (sv[1].uv - sv[0].uv, sv[2].uv - sv[0].uv);
    let uv_area2 = (d1.x * d2.y - d1.y * d2.x).abs() * t.width() as f32 * t.height() as f32;
    t.level_for_density(uv_area2 / screen_area2) as u32
}

/// The texture a record samples (`None` when untextured).
#[inline]
pub(super) fn texture_of<'a>(rec: &TriRecord, scene: &'a Scene) -> Option<&'a Texture> {
    scene.instances[rec.instance as usize].material.texture.as_deref().filter(|_| rec.mip != u32::MAX)
}

/// Colour (RGBA, `[0, 1]`) of pixel `(i, j)` of a triangle at view depth `z`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(super) fn shade(
    rec: &TriRecord,
    shadow_rgb: Option<&[Plane; 3]>,
    shadow: Option<&ShadowMap>,
    texture: Option<&Texture>,
    view: &View,
    i: u32,
    j: u32,
    z: f32,
) -> [f32; 4] {
    let (fi, fj) = (i as f32, j as f32);
    let mut rgb = [rec.rgb[0].eval(fi, fj) * z, rec.rgb[1].eval(fi, fj) * z, rec.rgb[2].eval(fi, fj) * z];
    if let (Some(sh), Some(map)) = (shadow_rgb, shadow) {
        let p = Vec3::new((fi - view.k.cx) / view.k.fx * z, (fj - view.k.cy) / view.k.fy * z, z);
        let vis = map.visibility(p);
        for c in 0..3 {
            rgb[c] += sh[c].eval(fi, fj) * z * vis;
        }
    }
    let mut out = [rgb[0].clamp(0.0, 1.0), rgb[1].clamp(0.0, 1.0), rgb[2].clamp(0.0, 1.0), rec.alpha];
    if let Some(tex) = texture {
        let t = tex.sample_level(rec.uv[0].eval(fi, fj) * z, rec.uv[1].eval(fi, fj) * z, rec.mip as usize);
        for (o, t) in out.iter_mut().zip(t) {
            *o *= t;
        }
    }
    out
}

/// Pixels shaded together by [`shade_textured8`].
const LANES: usize = 8;
/// The shortest run (or long run's tail) shaded as one such group rather than pixel by pixel.
const WIDE_TAIL: usize = 4;

/// [`shade`] for the eight pixels from column `first` of row `j` (as `fj`) of a textured
/// triangle without shadows, whose `1/z` are `iz`: their view depths, and their colours as
/// [`to_u8`] rounds them, by channel. Each lane does the same float operations as one pixel
/// alone, so the bits are the same.
#[inline]
fn shade_textured8(rec: &TriRecord, tex: &Texture, first: usize, fj: f32, iz: [f32; LANES]) -> ([f32; LANES], [[u8; LANES]; 3]) {
    use wide::f32x8;
    let (zero, one) = (f32x8::ZERO, f32x8::ONE);
    // Through i32, as the scalar resolve converts columns (the same floats).
    let fi = f32x8::from(std::array::from_fn::<f32, LANES, _>(|l| (first + l) as i32 as f32));
    let z = one / f32x8::from(iz);
    let eval = |p: &Plane| (f32x8::splat(p.a) * fi + f32x8::splat(p.b * fj + p.c)) * z;
    let texel = tex.sample_level_rgb8(eval(&rec.uv[0]), eval(&rec.uv[1]), rec.mip as usize);
    let rgb = std::array::from_fn(|c| {
        // `f32::clamp(0, 1)`, which keeps NaN, then the texel.
        let x = eval(&rec.rgb[c]);
        let x = x.simd_lt(zero).select(zero, x);
        let x = x.simd_gt(one).select(one, x) * texel[c];
        // `to_u8`: NaN and below 0 → 0, above 1 → 1, rounded in the low mantissa bits.
        let y = x.simd_gt(zero).select(x, zero);
        let y = y.simd_lt(one).select(y, one) * f32x8::splat(255.0) + f32x8::splat(8_388_608.0);
        y.to_array().map(|y| (y.to_bits() & 0xFF) as u8)
    });
    (z.to_array(), rgb)
}

/// Writes the first `n` pixels of a group that [`shade_textured8`] shaded from column `first`.
#[inline]
fn put_group(depth_out: &mut [f32], rgb_out: &mut [u8], first: usize, n: usize, (z, rgb): ([f32; LANES], [[u8; LANES]; 3])) {
    depth_out[first..first + n].copy_from_slice(&z[..n]);
    for l in 0..n {
        rgb_out[3 * (first + l)..3 * (first + l) + 3].copy_from_slice(&[rgb[0][l], rgb[1][l], rgb[2][l]]);
    }
}

/// `[0, 1]` → `0..=255`, rounding to nearest (ties to even; NaN → 0). Adding 2^23 leaves
/// the rounded integer in the low mantissa bits, which is cheaper than a saturating cast.
#[inline]
pub(super) fn to_u8(x: f32) -> u8 {
    // Not `clamp`, which passes NaN through.
    #[allow(clippy::manual_clamp)]
    let y = x.max(0.0).min(1.0) * 255.0 + 8_388_608.0;
    (y.to_bits() & 0xFF) as u8
}

/// Background colour per pixel.
struct Sky {
    solid: Option<[f32; 3]>,
    up: [f32; 3],
    down: [f32; 3],
    /// World z of the camera's right, down and forward axes (for the gradient).
    zr: f32,
    zd: f32,
    zf: f32,
    k: Intrinsics,
    inv_fx: f32,
    inv_fy: f32,
}

impl Sky {
    fn new(bg: Background, view: &View) -> Sky {
        let z = view.rot.transpose().z_axis; // Row 2 of camera → world.
        let (solid, up, down) = match bg {
            Background::Solid(c) => (Some(c), c, c),
            Background::Gradient { up, down } => (None, up, down),
        };
        Sky { solid, up, down, zr: z.x, zd: z.y, zf: z.z, k: view.k, inv_fx: 1.0 / view.k.fx, inv_fy: 1.0 / view.k.fy }
    }

    #[inline]
    fn color(&self, i: u32, j: u32) -> [f32; 3] {
        if let Some(c) = self.solid {
            return c;
        }
        let (x, y) = ((i as f32 - self.k.cx) * self.inv_fx, (j as f32 - self.k.cy) * self.inv_fy);
        let dz = (self.zr * x + self.zd * y + self.zf) / (x * x + y * y + 1.0).sqrt();
        let t = 0.5 + 0.5 * dz;
        std::array::from_fn(|c| self.down[c] + (self.up[c] - self.down[c]) * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::raster::{RenderOptions, Renderer};
    use glam::Vec2;

    #[test]
    fn run_length_counts_the_leading_equal_ids() {
        for len in 1..40usize {
            for cut in 0..=len {
                let ids: Vec<u32> = (0..len).map(|k| if k < cut.max(1) { 7 } else { 8 }).collect();
                assert_eq!(run_length(&ids), cut.max(1), "len {len}, cut {cut}");
            }
        }
    }

    #[test]
    fn the_opaque_resolve_writes_what_shade_computes() {
        // A lit, textured (bilinear, mipmapped) sphere and box and a lit untextured plane behind
        // them: every pixel must get the bits `shade` gives it, also where the resolve's own
        // row-hoisted Gouraud loop (the plane) or its eight-wide textured groups (the box's faces:
        // long runs, their tails and short runs) stand in for `shade`.
        use crate::{Instance, Material, Mesh, Texture, Transform};
        use std::sync::Arc;
        let data: Vec<u8> = (0..32 * 32 * 3).map(|i| ((i * 37) % 251) as u8).collect();
        let tex = Arc::new(Texture::from_rgb8(32, 32, &data).unwrap());
        let textured = Material { rgba: [0.9, 0.8, 0.7, 1.0], specular: 0.5, shininess: 0.3, texture: Some(tex), uv_scale: Vec2::splat(3.0), ..Material::default() };
        let sphere = Instance::new(Arc::new(Mesh::sphere(0.5, 24)), Transform::IDENTITY, 1).with_material(textured.clone());
        let block = Instance::new(Arc::new(Mesh::cuboid(Vec3::splat(0.3))), Transform::from_translation(Vec3::new(-0.9, 0.2, -0.2)), 3).with_material(textured);
        let plane = Instance::new(Arc::new(Mesh::plane(2.0, 2.0)), Transform::from_translation(Vec3::new(0.0, 0.0, -1.0)), 2)
            .with_material(Material { rgba: [0.4, 0.5, 0.6, 1.0], specular: 0.3, ..Material::default() });
        let scene = Scene { instances: vec![sphere, block, plane], ..Scene::default() };
        let camera = Camera::look_at(Vec3::new(0.3, -1.5, 1.2), Vec3::ZERO, Vec3::Z, 50.0, 96, 80);
        let mut r = Renderer::new(RenderOptions::default());
        let frame = r.render(&scene, &camera).unwrap();
        let view = View::new(&camera);
        let (mut textured_px, mut plain_px) = (0, 0);
        for (p, (&id, &iz)) in r.tri_id.iter().zip(&r.depth).enumerate() {
            if id == NO_TRIANGLE {
                continue;
            }
            let rec = &r.records[id as usize];
            let texture = texture_of(rec, &scene);
            *if texture.is_some() { &mut textured_px } else { &mut plain_px } += 1;
            let (i, j) = ((p % 96) as u32, (p / 96) as u32);
            let c = shade(rec, None, None, texture, &view, i, j, 1.0 / iz);
            assert_eq!(frame.color.data[3 * p..3 * p + 3], [to_u8(c[0]), to_u8(c[1]), to_u8(c[2])], "pixel ({i}, {j})");
        }
        assert!(textured_px > 1000 && plain_px > 1000, "{textured_px} textured and {plain_px} plain pixels");
        let textured_runs = || r.tri_id.chunks(96).flat_map(|row| row.chunk_by(|a, b| a == b)).filter(|run| run[0] != NO_TRIANGLE && texture_of(&r.records[run[0] as usize], &scene).is_some());
        let wide_px: usize = textured_runs().map(|run| run.len() / LANES * LANES).sum();
        let tail_px: usize = textured_runs().map(|run| run.len() % LANES).filter(|&n| n >= WIDE_TAIL).sum();
        assert!(wide_px > 300 && tail_px > 50, "{wide_px} pixels shaded eight at a time, {tail_px} in shorter groups");
    }
}
