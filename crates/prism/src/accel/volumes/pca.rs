//! Principal axes of a point set: the eigenvectors of its covariance, by cyclic Jacobi
//! rotations (a 3×3 symmetric matrix converges in a handful of sweeps).

use glam::{DMat3, DVec3};

/// Orthonormal principal axes of `points` (the identity for fewer than two points).
pub(super) fn principal_axes(points: &[DVec3]) -> [DVec3; 3] {
    if points.len() < 2 {
        return [DVec3::X, DVec3::Y, DVec3::Z];
    }
    let mean = points.iter().sum::<DVec3>() / points.len() as f64;
    let mut c = [[0.0f64; 3]; 3];
    for p in points {
        let q = *p - mean;
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += q[i] * q[j];
            }
        }
    }
    let v = jacobi_eigenvectors(c);
    [v.x_axis, v.y_axis, v.z_axis].map(|a| a.try_normalize().unwrap_or(DVec3::X))
}

/// Columns are the eigenvectors of the symmetric matrix `a`.
fn jacobi_eigenvectors(mut a: [[f64; 3]; 3]) -> DMat3 {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= f64::EPSILON * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation that zeroes a[p][q] (Golub & Van Loan, sym. Schur 2×2).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * row_p[k] - s * row_q[k];
                a[q][k] = s * row_p[k] + c * row_q[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_long_axis_of_a_stretched_point_cloud() {
        let dir = DVec3::new(1.0, 2.0, -0.5).normalize();
        let side = dir.any_orthonormal_vector();
        let points: Vec<DVec3> = (0..100)
            .map(|i| {
                let s = i as f64 / 99.0 - 0.5;
                10.0 * s * dir + 0.3 * ((i % 7) as f64 - 3.0) * side
            })
            .collect();
        let axes = principal_axes(&points);
        let best = axes.iter().map(|a| a.dot(dir).abs()).fold(0.0, f64::max);
        assert!(best > 0.999, "{axes:?}");
        for i in 0..3 {
            for j in 0..i {
                assert!(axes[i].dot(axes[j]).abs() < 1e-9);
            }
        }
    }
}
