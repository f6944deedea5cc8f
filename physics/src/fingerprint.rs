//! A hash of the simulation state's bits, to check determinism cheaply.

use rapier3d::prelude::*;

/// FNV-1a hash over the exact bits of every body pose and velocity and every multibody
/// generalized coordinate and velocity. Two worlds with the same fingerprint are, for all
/// practical purposes, in the same state; one flipped bit changes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Fingerprint(pub u64);

impl Fingerprint {
    pub(crate) fn of(bodies: &RigidBodySet, multibodies: &MultibodyJointSet) -> Self {
        let mut h = Hasher::new();
        for (handle, body) in bodies.iter() {
            let (index, generation) = handle.into_raw_parts();
            h.u64(u64::from(index) << 32 | u64::from(generation));
            let pose = body.position();
            h.vec(pose.translation);
            let q = pose.rotation;
            h.f64s(&[q.x, q.y, q.z, q.w]);
            h.vec(body.linvel());
            h.vec(body.angvel());
        }
        for multibody in multibodies.multibodies() {
            for link in multibody.links() {
                h.f64s(&link.joint().coords());
            }
            h.f64s(multibody.generalized_velocity().as_slice());
        }
        Fingerprint(h.0)
    }
}

struct Hasher(u64);

impl Hasher {
    fn new() -> Self {
        Hasher(0xcbf2_9ce4_8422_2325)
    }

    fn u64(&mut self, v: u64) {
        for byte in v.to_le_bytes() {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }

    fn f64s(&mut self, values: &[f64]) {
        for v in values {
            self.u64(v.to_bits());
        }
    }

    fn vec(&mut self, v: Vector) {
        self.f64s(&[v.x, v.y, v.z]);
    }
}
