//! Small rotation helpers on plain arrays (quaternions `[w, x, y, z]`, row-major 3×3 matrices).
//!
//! Plain arithmetic and `sqrt` only, plus `libm` for angles, so results are the same bits on
//! every platform.

pub(crate) type Mat3 = [[f64; 3]; 3];

/// `q / |q|`, as MuJoCo normalises every quaternion it reads from XML.
pub(crate) fn normalize(q: [f64; 4]) -> [f64; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// Rotation of `angle` radians about the unit `axis`.
pub(crate) fn about_axis(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let (s, c) = (libm::sin(angle / 2.0), libm::cos(angle / 2.0));
    [c, axis[0] * s, axis[1] * s, axis[2] * s]
}

/// Rotation matrix of a unit quaternion.
pub(crate) fn to_matrix(q: [f64; 4]) -> Mat3 {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// Unit quaternion (with `w >= 0`) of a proper rotation matrix.
pub(crate) fn from_matrix(m: &Mat3) -> [f64; 4] {
    let trace = m[0][0] + m[1][1] + m[2][2];
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            0.25 * s,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
        [
            (m[2][1] - m[1][2]) / s,
            0.25 * s,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
        [
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            0.25 * s,
            (m[1][2] + m[2][1]) / s,
        ]
    } else {
        let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
        [
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            0.25 * s,
        ]
    };
    let q = normalize(q);
    if q[0] < 0.0 {
        [-q[0], -q[1], -q[2], -q[3]]
    } else {
        q
    }
}

/// `m · v`.
pub(crate) fn apply(m: &Mat3, v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// Rotates `v` by the unit quaternion `q`.
pub(crate) fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    apply(&to_matrix(q), v)
}

/// `R · diag(d) · Rᵀ`: a diagonal tensor expressed in the rotated frame.
pub(crate) fn rotate_diagonal(r: &Mat3, d: [f64; 3]) -> Mat3 {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = r[i][0] * d[0] * r[j][0] + r[i][1] * d[1] * r[j][1] + r[i][2] * d[2] * r[j][2];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_round_trip_keeps_the_rotation() {
        let q = normalize([0.3, -0.5, 0.7, 0.2]);
        let back = from_matrix(&to_matrix(q));
        for i in 0..4 {
            assert!((q[i] - back[i]).abs() < 1e-12, "{q:?} vs {back:?}");
        }
        // A rotation with w < 0 comes back as the same rotation with w >= 0.
        let neg = from_matrix(&to_matrix([-q[0], -q[1], -q[2], -q[3]]));
        assert!((neg[0] - q[0]).abs() < 1e-12);
    }

    #[test]
    fn quarter_turn_about_x_maps_z_to_minus_y() {
        let q = about_axis([1.0, 0.0, 0.0], core::f64::consts::FRAC_PI_2);
        let v = rotate(q, [0.0, 0.0, 1.0]);
        assert!(
            v[0].abs() < 1e-12 && (v[1] + 1.0).abs() < 1e-12 && v[2].abs() < 1e-12,
            "{v:?}"
        );
    }
}
