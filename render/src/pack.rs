//! Meshes and textures as bytes and back, so that a program can keep what it made of an asset
//! file (a clustered mesh, its coarser copies, a downsized texture) and read it again in a
//! fraction of the time it took to make.
//!
//! The bytes hold each field's values as they are in memory, so they read back bit for bit on
//! the same kind of machine (they are a cache, not an exchange format). Reading checks every
//! length and index before building anything: bad bytes give a [`PackError`], never a mesh the
//! rasterizer would index out of bounds.

use glam::{Vec2, Vec3};
use thiserror::Error;

use crate::cluster::{Cluster, Clusters};
use crate::mesh::{Mesh, MeshError, Points};
use crate::texture::{Filter, Texture, TextureError};

/// Why packed bytes could not be read back.
#[derive(Debug, Error, PartialEq)]
pub enum PackError {
    #[error("packed data ends early")]
    Short,
    #[error("packed data has {0} bytes left over")]
    LeftOver(usize),
    #[error("packed data: {0}")]
    Invalid(&'static str),
    #[error("packed mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("packed texture: {0}")]
    Texture(#[from] TextureError),
}

/// Appends values to a byte buffer.
#[derive(Default)]
pub struct Packer {
    bytes: Vec<u8>,
}

impl Packer {
    pub fn new() -> Packer {
        Packer::default()
    }

    /// The bytes written so far.
    pub fn finish(self) -> Vec<u8> {
        self.bytes
    }

    pub fn u32(&mut self, x: u32) {
        self.bytes.extend_from_slice(&x.to_le_bytes());
    }

    pub fn f32(&mut self, x: f32) {
        self.u32(x.to_bits());
    }

    /// A slice, preceded by its length.
    pub fn slice<T: bytemuck::NoUninit>(&mut self, items: &[T]) {
        self.bytes.extend_from_slice(&(items.len() as u64).to_le_bytes());
        self.bytes.extend_from_slice(bytemuck::cast_slice(items));
    }

    pub fn mesh(&mut self, mesh: &Mesh) {
        let (positions, normals, uvs, triangles) = (mesh.positions(), mesh.normals(), mesh.uvs(), mesh.triangles());
        self.slice(&positions.iter().map(|p| p.to_array()).collect::<Vec<_>>());
        self.slice(&normals.iter().map(|p| p.to_array()).collect::<Vec<_>>());
        self.u32(uvs.is_some() as u32);
        self.slice(&uvs.unwrap_or_default().iter().map(|p| p.to_array()).collect::<Vec<_>>());
        self.slice(triangles);
        let points = mesh.points();
        self.slice(&points.list.iter().map(|p| p.to_array()).collect::<Vec<_>>());
        self.slice(&points.of_vertex);
        self.slice(&points.triangles);
        let clusters = mesh.clusters();
        self.slice(&clusters.list.iter().map(cluster_words).collect::<Vec<_>>());
        self.slice(&clusters.points);
        self.slice(&clusters.loaded_order);
    }

    /// A texture's full-size image and filter (its smaller levels are made again on reading).
    pub fn texture(&mut self, texture: &Texture) {
        let (width, height, texels) = texture.full_level();
        self.u32(width);
        self.u32(height);
        self.u32(matches!(texture.filter(), Filter::Nearest) as u32);
        self.slice(texels);
    }
}

/// Reads back what a [`Packer`] wrote, in the same order.
pub struct Unpacker<'a> {
    rest: &'a [u8],
}

impl<'a> Unpacker<'a> {
    pub fn new(bytes: &'a [u8]) -> Unpacker<'a> {
        Unpacker { rest: bytes }
    }

    /// Succeeds when every byte was read.
    pub fn finish(self) -> Result<(), PackError> {
        if self.rest.is_empty() { Ok(()) } else { Err(PackError::LeftOver(self.rest.len())) }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], PackError> {
        if self.rest.len() < n {
            return Err(PackError::Short);
        }
        let (head, rest) = self.rest.split_at(n);
        self.rest = rest;
        Ok(head)
    }

    pub fn u32(&mut self) -> Result<u32, PackError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("four bytes")))
    }

    pub fn f32(&mut self) -> Result<f32, PackError> {
        self.u32().map(f32::from_bits)
    }

    pub fn slice<T: bytemuck::AnyBitPattern + bytemuck::NoUninit>(&mut self) -> Result<Vec<T>, PackError> {
        let len = u64::from_le_bytes(self.take(8)?.try_into().expect("eight bytes"));
        let bytes = usize::try_from(len).ok().and_then(|n| n.checked_mul(size_of::<T>())).ok_or(PackError::Short)?;
        // A copy, as the buffer need not be aligned for `T`.
        Ok(bytemuck::pod_collect_to_vec(self.take(bytes)?))
    }

    fn vec3s(&mut self) -> Result<Vec<Vec3>, PackError> {
        Ok(self.slice::<[f32; 3]>()?.into_iter().map(Vec3::from_array).collect())
    }

    /// A mesh, checked as [`Mesh::new`] checks one, and its distinct positions and clusters
    /// checked against it.
    pub fn mesh(&mut self) -> Result<Mesh, PackError> {
        let positions = self.vec3s()?;
        let normals = self.vec3s()?;
        let has_uvs = self.u32()? != 0;
        let uvs: Vec<Vec2> = self.slice::<[f32; 2]>()?.into_iter().map(Vec2::from_array).collect();
        let uvs = has_uvs.then_some(uvs);
        let triangles: Vec<[u32; 3]> = self.slice()?;
        Mesh::check(&positions, &normals, uvs.as_deref(), &triangles)?;
        let points = Points { list: self.vec3s()?, of_vertex: self.slice()?, triangles: self.slice()? };
        let n = points.list.len();
        let same_position = |(v, &i): (usize, &u32)| points.list.get(i as usize).is_some_and(|p| p.to_array().map(f32::to_bits) == positions[v].to_array().map(f32::to_bits));
        if points.of_vertex.len() != positions.len() || !points.of_vertex.iter().enumerate().all(same_position) {
            return Err(PackError::Invalid("distinct positions do not match the vertices"));
        }
        let corners = |t: &[u32; 3]| t.map(|v| points.of_vertex[v as usize]);
        if points.triangles.len() != triangles.len() || !triangles.iter().zip(&points.triangles).all(|(t, p)| corners(t) == *p) {
            return Err(PackError::Invalid("triangles' positions do not match the triangles"));
        }
        let list: Vec<Cluster> = self.slice::<[u32; CLUSTER_WORDS]>()?.iter().map(cluster_of_words).collect();
        let clusters = Clusters { list, points: self.slice()?, loaded_order: self.slice()? };
        let in_range = |first: u32, count: u32, len: usize| first.checked_add(count).is_some_and(|end| end as usize <= len);
        if !clusters.list.iter().all(|c| in_range(c.first, c.count, triangles.len()) && in_range(c.first_point, c.point_count, clusters.points.len()))
            || clusters.points.iter().any(|&p| p as usize >= n)
            || !(clusters.loaded_order.is_empty() || clusters.loaded_order.len() == positions.len())
        {
            return Err(PackError::Invalid("clusters refer to triangles or positions the mesh does not have"));
        }
        Ok(Mesh::from_parts(positions, normals, uvs, triangles, clusters, points))
    }

    /// A texture, its smaller levels made as [`Texture::from_rgba8`] makes them.
    pub fn texture(&mut self) -> Result<Texture, PackError> {
        let (width, height) = (self.u32()?, self.u32()?);
        let filter = if self.u32()? != 0 { Filter::Nearest } else { Filter::Bilinear };
        let texels: Vec<[u8; 4]> = self.slice()?;
        Ok(Texture::from_rgba8(width, height, bytemuck::cast_slice(&texels))?.with_filter(filter))
    }
}

/// A cluster's fields as words (floats by their bits).
const CLUSTER_WORDS: usize = 15;

fn cluster_words(c: &Cluster) -> [u32; CLUSTER_WORDS] {
    let f = |v: Vec3| v.to_array().map(f32::to_bits);
    let ([a0, a1, a2], [x0, x1, x2], [c0, c1, c2]) = (f(c.cone_apex), f(c.cone_axis), f(c.centre));
    [c.first, c.count, c.first_point, c.point_count, c0, c1, c2, c.radius.to_bits(), a0, a1, a2, x0, x1, x2, c.cone_cutoff.to_bits()]
}

fn cluster_of_words(w: &[u32; CLUSTER_WORDS]) -> Cluster {
    let v = |i: usize| Vec3::new(f32::from_bits(w[i]), f32::from_bits(w[i + 1]), f32::from_bits(w[i + 2]));
    Cluster {
        first: w[0],
        count: w[1],
        first_point: w[2],
        point_count: w[3],
        centre: v(4),
        radius: f32::from_bits(w[7]),
        cone_apex: v(8),
        cone_axis: v(11),
        cone_cutoff: f32::from_bits(w[14]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip_mesh(mesh: &Mesh) -> Result<Mesh, PackError> {
        let mut p = Packer::new();
        p.mesh(mesh);
        let bytes = p.finish();
        let mut u = Unpacker::new(&bytes);
        let back = u.mesh()?;
        u.finish()?;
        Ok(back)
    }

    #[test]
    fn meshes_and_textures_read_back_bit_for_bit() {
        let sphere = Mesh::sphere(0.05, 48);
        assert!(sphere.triangle_count() > 1000);
        let clustered = sphere.clone().clustered();
        assert!(!clustered.clusters().list.is_empty());
        let coarse = clustered.simplified(0.002).expect("a 48-segment sphere simplifies at 2 mm");
        for mesh in [&sphere, &clustered, &coarse, &Mesh::cuboid(Vec3::new(0.1, 0.2, 0.3))] {
            assert_eq!(&round_trip_mesh(mesh).unwrap(), mesh);
        }
        let rgba: Vec<u8> = (0..5 * 3 * 4).map(|i| (i * 37 % 256) as u8).collect();
        for filter in [Filter::Nearest, Filter::Bilinear] {
            let texture = Texture::from_rgba8(5, 3, &rgba).unwrap().with_filter(filter);
            let mut p = Packer::new();
            p.texture(&texture);
            p.f32(-0.0);
            let bytes = p.finish();
            let mut u = Unpacker::new(&bytes);
            assert_eq!(u.texture().unwrap(), texture);
            assert_eq!(u.f32().unwrap().to_bits(), (-0.0f32).to_bits());
            u.finish().unwrap();
        }
    }

    #[test]
    fn bad_bytes_give_an_error_not_a_mesh() {
        let mesh = Mesh::sphere(0.05, 24).clustered();
        let mut p = Packer::new();
        p.mesh(&mesh);
        let bytes = p.finish();
        // Every truncation is refused.
        for cut in (0..bytes.len()).step_by(97) {
            assert!(Unpacker::new(&bytes[..cut]).mesh().is_err(), "cut at {cut}");
        }
        // A changed byte is either refused or still a mesh whose indices are in range (a float's
        // bits may change its value only); flipping each byte of the index data is refused.
        let mut refused = 0;
        for at in (0..bytes.len()).step_by(13) {
            let mut bad = bytes.clone();
            bad[at] ^= 0x80;
            match Unpacker::new(&bad).mesh() {
                Err(_) => refused += 1,
                Ok(m) => assert!(m.triangles().iter().flatten().all(|&v| (v as usize) < m.vertex_count())),
            }
        }
        assert!(refused > 0);
        let nan = {
            let mut p = Packer::new();
            p.slice(&[[f32::NAN, 0.0, 0.0]]);
            p.slice(&[[0.0f32, 0.0, 1.0]]);
            p.u32(0);
            p.slice::<[f32; 2]>(&[]);
            p.slice::<[u32; 3]>(&[]);
            p.finish()
        };
        assert_eq!(Unpacker::new(&nan).mesh(), Err(PackError::Mesh(MeshError::NonFinite { what: "position", index: 0 })));
        // A texture of 0xffff0003 × 0xffffffff texels, found by the `look-cache` fuzz target: its
        // byte count overflowed before it was refused.
        let huge: [u8; 48] = [0x03, 0x00, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x7f, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0xff, 0xff, 0xff, 0xff, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07, 0x07];
        assert!(matches!(Unpacker::new(&huge).texture(), Err(PackError::Texture(TextureError::WrongLength { .. }))));
    }
}
