//! Procedural meshes for built-in scenes, tests and benchmarks.

use super::TriangleMesh;
use crate::math::{Vec2, Vec3};

/// A planar quad `a b c d` (counter-clockwise seen from the front) as two triangles, with
/// uv running over `[0, u_max] × [0, v_max]` from `a`.
pub fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3, u_max: f32, v_max: f32) -> TriangleMesh {
    let uvs = vec![
        Vec2::ZERO,
        Vec2::new(u_max, 0.0),
        Vec2::new(u_max, v_max),
        Vec2::new(0.0, v_max),
    ];
    TriangleMesh::new(
        vec![a, b, c, d],
        vec![[0, 1, 2], [0, 2, 3]],
        None,
        Some(uvs),
    )
    .expect("a quad's indices are in range")
}

/// A closed parametric surface sampled on a `nu × nv` grid that wraps in both directions
/// (a torus-like topology), with smooth normals from finite differences. Gives 2·nu·nv
/// triangles; `f(u, v)` gets u, v in [0, 1).
pub fn wrapped_grid(nu: u32, nv: u32, f: impl Fn(f32, f32) -> Vec3) -> TriangleMesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    let mut normals = Vec::with_capacity((nu * nv) as usize);
    let mut uvs = Vec::with_capacity((nu * nv) as usize);
    let (du, dv) = (1.0 / nu as f32, 1.0 / nv as f32);
    for j in 0..nv {
        for i in 0..nu {
            let (u, v) = (i as f32 * du, j as f32 * dv);
            let p = f(u, v);
            let tu = f(u + 0.5 * du, v) - f(u - 0.5 * du, v);
            let tv = f(u, v + 0.5 * dv) - f(u, v - 0.5 * dv);
            positions.push(p);
            normals.push(tu.cross(tv));
            uvs.push(Vec2::new(u, v));
        }
    }
    let id = |i: u32, j: u32| (j % nv) * nu + (i % nu);
    let mut indices = Vec::with_capacity(2 * (nu * nv) as usize);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    TriangleMesh::new(positions, indices, Some(normals), Some(uvs))
        .expect("grid indices are in range")
}

/// A bumpy torus knot tube of about `triangles` triangles: a dense, self-weaving mesh for
/// benchmarks (the (3, 2) knot, radius about 1.5).
pub fn torus_knot(triangles: u32) -> TriangleMesh {
    use std::f32::consts::TAU;
    let nv = ((triangles as f32 / 2.0 / 16.0).sqrt() as u32).max(3);
    let nu = (triangles / 2 / nv).max(3);
    let curve = |t: f32| {
        let (p, q) = (3.0, 2.0);
        let r = 1.0 + 0.35 * (q * t * TAU).cos();
        Vec3::new(
            r * (p * t * TAU).cos(),
            r * (p * t * TAU).sin(),
            0.35 * (q * t * TAU).sin(),
        )
    };
    wrapped_grid(nu, nv, |u, v| {
        let c = curve(u);
        let tangent = (curve(u + 1e-3) - curve(u - 1e-3)).normalize();
        let side = tangent.cross(Vec3::Z).normalize();
        let up = side.cross(tangent);
        let bump = 1.0 + 0.15 * (40.0 * u * TAU).sin() * (6.0 * v * TAU).sin();
        let radius = 0.18 * bump;
        let a = v * TAU;
        c + radius * (a.cos() * side + a.sin() * up)
    })
}
