//! Body mass properties computed the way MuJoCo's compiler does for LIBERO's assets.
//!
//! robosuite compiles with `inertiagrouprange="0 0"`, so only collision geoms carry mass. Each
//! geom's mass is `density × volume` unless the XML gives `mass`; its inertia is the solid-shape
//! formula. A body with one geom takes that geom's frame and moments unchanged; with several, the
//! moments are summed about the common centre of mass (parallel-axis theorem) and diagonalised,
//! principal moments in decreasing order.

use super::frames::{self, Mat3};
use super::model::{ColliderShape, Inertial};

/// How a collision geom's mass is specified in the XML.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MassSource {
    /// kg/m³ (MuJoCo's default is 1000; LIBERO's scanned assets use 100).
    Density(f64),
    /// An explicit `mass` attribute in kg.
    Mass(f64),
}

/// A collision geom as the mass computation sees it (pose in the body frame, unit quaternion).
#[derive(Clone, Copy, Debug)]
pub(crate) struct MassiveGeom<'a> {
    pub shape: &'a ColliderShape,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub mass: MassSource,
}

/// Mass properties of a body made of `geoms` (all zero when there are none).
pub(crate) fn from_geoms(geoms: &[MassiveGeom]) -> Inertial {
    let parts: Vec<GeomInertia> = geoms
        .iter()
        .map(|g| {
            let (mass, diag) = shape_mass(g.shape, g.mass);
            GeomInertia {
                pos: g.pos,
                quat: g.quat,
                mass,
                diag,
            }
        })
        .collect();
    match parts.as_slice() {
        [] => Inertial {
            mass: 0.0,
            com: [0.0; 3],
            inertia: [0.0; 3],
            quat_wxyz: [1.0, 0.0, 0.0, 0.0],
        },
        [one] => Inertial {
            mass: one.mass,
            com: one.pos,
            inertia: one.diag,
            quat_wxyz: one.quat,
        },
        _ => combine(&parts),
    }
}

/// One geom's mass and principal moments, with the pose of its principal axes.
struct GeomInertia {
    pos: [f64; 3],
    quat: [f64; 4],
    mass: f64,
    diag: [f64; 3],
}

/// Mass and principal moments (about the geom's own axes) of one solid shape.
fn shape_mass(shape: &ColliderShape, source: MassSource) -> (f64, [f64; 3]) {
    let volume = match *shape {
        ColliderShape::Box { half_size: s } => 8.0 * s[0] * s[1] * s[2],
        ColliderShape::Capsule {
            radius: r,
            half_length: h,
        } => core::f64::consts::PI * (r * r * 2.0 * h + 4.0 * r * r * r / 3.0),
    };
    let mass = match source {
        MassSource::Density(density) => density * volume,
        MassSource::Mass(mass) => mass,
    };
    let diag = match *shape {
        ColliderShape::Box { half_size: s } => [
            mass * (s[1] * s[1] + s[2] * s[2]) / 3.0,
            mass * (s[0] * s[0] + s[2] * s[2]) / 3.0,
            mass * (s[0] * s[0] + s[1] * s[1]) / 3.0,
        ],
        ColliderShape::Capsule {
            radius: r,
            half_length: h,
        } => {
            // Cylinder plus two hemispheres shifted along the axis (MuJoCo's formula).
            let height = 2.0 * h;
            let sphere_mass = mass * 4.0 * r / (4.0 * r + 3.0 * height);
            let cylinder_mass = mass - sphere_mass;
            let sphere_moment = 2.0 * sphere_mass * r * r / 5.0;
            let across = cylinder_mass * (3.0 * r * r + height * height) / 12.0
                + sphere_moment
                + sphere_mass * height * (3.0 * r + 2.0 * height) / 8.0;
            [across, across, cylinder_mass * r * r / 2.0 + sphere_moment]
        }
    };
    (mass, diag)
}

/// Several geoms: common centre of mass, summed tensor, principal axes.
fn combine(parts: &[GeomInertia]) -> Inertial {
    let mass: f64 = parts.iter().map(|p| p.mass).sum();
    let mut com = [0.0; 3];
    for p in parts {
        for (c, x) in com.iter_mut().zip(p.pos) {
            *c += p.mass * x;
        }
    }
    let com = com.map(|c| c / mass);
    let mut tensor = [[0.0; 3]; 3];
    for p in parts {
        let own = frames::rotate_diagonal(&frames::to_matrix(p.quat), p.diag);
        let d = [p.pos[0] - com[0], p.pos[1] - com[1], p.pos[2] - com[2]];
        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        for i in 0..3 {
            for j in 0..3 {
                let shift = if i == j { d2 } else { 0.0 } - d[i] * d[j];
                tensor[i][j] += own[i][j] + p.mass * shift;
            }
        }
    }
    let (inertia, axes) = principal_axes(tensor);
    Inertial {
        mass,
        com,
        inertia,
        quat_wxyz: frames::from_matrix(&axes),
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: eigenvalues in
/// decreasing order and a proper rotation whose columns are the matching eigenvectors.
pub(crate) fn principal_axes(mut a: Mat3) -> ([f64; 3], Mat3) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
    for _sweep in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= scale * 1e-18 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // a ← Jᵀ a J and v ← v J for the plane rotation J in (p, q).
            for row in a.iter_mut() {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = [0, 1, 2].map(|k| c * row_p[k] - s * row_q[k]);
            a[q] = [0, 1, 2].map(|k| s * row_p[k] + c * row_q[k]);
            for row in v.iter_mut() {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let values = order.map(|i| a[i][i]);
    let mut axes = [[0.0; 3]; 3];
    for (col, &src) in order.iter().enumerate() {
        for row in 0..3 {
            axes[row][col] = v[row][src];
        }
    }
    if determinant(&axes) < 0.0 {
        for row in axes.iter_mut() {
            row[2] = -row[2];
        }
    }
    (values, axes)
}

fn determinant(m: &Mat3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(pos: [f64; 3], half: f64) -> (ColliderShape, [f64; 3]) {
        (
            ColliderShape::Box {
                half_size: [half; 3],
            },
            pos,
        )
    }

    #[test]
    fn single_box_keeps_its_own_frame_and_unsorted_moments() {
        let shape = ColliderShape::Box {
            half_size: [0.1, 0.2, 0.3],
        };
        let quat = frames::normalize([1.0, 0.0, 0.0, 1.0]);
        let body = from_geoms(&[MassiveGeom {
            shape: &shape,
            pos: [0.1, 0.0, 0.0],
            quat,
            mass: MassSource::Density(1000.0),
        }]);
        assert!((body.mass - 48.0).abs() < 1e-12);
        assert_eq!(body.com, [0.1, 0.0, 0.0]);
        assert_eq!(body.quat_wxyz, quat);
        // m (b² + c²) / 3 etc. in the box's own axis order, not sorted.
        assert!((body.inertia[0] - 48.0 * 0.13 / 3.0).abs() < 1e-12);
        assert!((body.inertia[2] - 48.0 * 0.05 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn two_cubes_follow_the_parallel_axis_theorem() {
        let (a, pa) = cube([-0.5, 0.0, 0.0], 0.1);
        let (b, pb) = cube([0.5, 0.0, 0.0], 0.1);
        let id = [1.0, 0.0, 0.0, 0.0];
        let body = from_geoms(&[
            MassiveGeom {
                shape: &a,
                pos: pa,
                quat: id,
                mass: MassSource::Mass(1.0),
            },
            MassiveGeom {
                shape: &b,
                pos: pb,
                quat: id,
                mass: MassSource::Mass(1.0),
            },
        ]);
        let own = 2.0 * (0.01 + 0.01) / 3.0;
        assert!((body.mass - 2.0).abs() < 1e-15);
        assert!(body.com.iter().all(|c| c.abs() < 1e-15));
        // Largest moments are about y and z (each cube 0.5 m off axis), smallest about x.
        assert!(
            (body.inertia[0] - (own + 0.5)).abs() < 1e-12,
            "{:?}",
            body.inertia
        );
        assert!((body.inertia[1] - (own + 0.5)).abs() < 1e-12);
        assert!((body.inertia[2] - own).abs() < 1e-12);
        let x_axis = frames::rotate(body.quat_wxyz, [0.0, 0.0, 1.0]);
        assert!(
            (x_axis[0].abs() - 1.0).abs() < 1e-12,
            "smallest moment axis {x_axis:?}"
        );
    }

    #[test]
    fn capsule_mass_is_cylinder_plus_sphere() {
        let shape = ColliderShape::Capsule {
            radius: 0.1,
            half_length: 0.2,
        };
        let (mass, diag) = shape_mass(&shape, MassSource::Density(1000.0));
        let expected = 1000.0 * core::f64::consts::PI * (0.01 * 0.4 + 4.0 * 0.001 / 3.0);
        assert!((mass - expected).abs() < 1e-9);
        assert!(diag[0] == diag[1] && diag[0] > diag[2]);
    }

    #[test]
    fn jacobi_recovers_a_rotated_tensor() {
        let q = frames::normalize([0.9, 0.2, -0.3, 0.1]);
        let r = frames::to_matrix(q);
        let tensor = frames::rotate_diagonal(&r, [3.0, 1.0, 2.0]);
        let (values, axes) = principal_axes(tensor);
        assert!(
            (values[0] - 3.0).abs() < 1e-12
                && (values[1] - 2.0).abs() < 1e-12
                && (values[2] - 1.0).abs() < 1e-12
        );
        let back = frames::rotate_diagonal(&axes, values);
        for i in 0..3 {
            for j in 0..3 {
                assert!((back[i][j] - tensor[i][j]).abs() < 1e-12);
            }
        }
        assert!((determinant(&axes) - 1.0).abs() < 1e-12);
    }
}
