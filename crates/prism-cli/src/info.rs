//! `prism info SCENE`: what a scene contains and what prism builds for it, without
//! rendering: counts by shape type, materials, lights, bounds, camera, memory.

use anyhow::Result;
use prism::accel::AccelSpec;
use prism::geometry::ShapeKind;
use prism::Scene;
use std::time::Instant;

pub(crate) fn print(scene: &Scene, name: &str, accel: &AccelSpec) -> Result<()> {
    let g = &scene.geometry;
    println!("scene              {name}");
    println!("primitives         {}", g.primitives.len());
    for kind in ShapeKind::ALL {
        let n = g
            .primitives
            .iter()
            .filter(|p| p.shape.kind() == kind)
            .count();
        if n > 0 {
            println!("  {:<16} {n}", kind.name());
        }
    }
    let vertices: usize = g.meshes.iter().map(|m| m.vertex_count()).sum();
    println!(
        "meshes             {} ({vertices} vertices)",
        g.meshes.len()
    );
    println!("materials          {}", scene.materials.len());
    for (i, m) in scene.materials.iter().enumerate() {
        let users = g
            .primitives
            .iter()
            .filter(|p| p.material as usize == i)
            .count();
        println!(
            "  {:<16} kd {:.2} ks {:.2} kr {:.2} kt {} ior {:.2} fresnel {:?}  ({users} primitives)",
            m.name,
            m.diffuse,
            m.specular,
            m.reflect,
            grey_or_rgb(m.transmit),
            m.ior,
            m.fresnel
        );
    }
    println!("lights             {}", scene.lights.len());
    print_emitters(scene);
    let b = g.world_bounds();
    if b.is_empty() {
        println!("bounds             (none: only unbounded shapes)");
    } else {
        println!(
            "bounds             [{:.4}, {:.4}, {:.4}] .. [{:.4}, {:.4}, {:.4}] (diagonal {:.4})",
            b.min.x,
            b.min.y,
            b.min.z,
            b.max.x,
            b.max.y,
            b.max.z,
            b.extent().length()
        );
    }
    let c = &scene.camera;
    let view = match c.projection {
        prism::camera::Projection::Perspective => format!("fov {}°", c.fov_degrees),
        prism::camera::Projection::Orthographic { size } => format!("orthographic, {size} across"),
    };
    println!(
        "camera             eye {:?} look-at {:?} up {:?} {view}",
        c.eye.to_array(),
        c.look_at.to_array(),
        c.up.to_array(),
    );
    println!(
        "image              {}×{}, depth {}, min weight {}",
        scene.options.width,
        scene.options.height,
        scene.options.max_depth,
        scene.options.min_weight
    );
    println!("sampling           {}", scene.options.sampling_summary());
    let mesh_bytes: usize = g
        .meshes
        .iter()
        .map(|m| {
            m.vertex_count() * (12 + if m.has_normals() { 12 } else { 0 }) + m.triangle_count() * 12
        })
        .sum();
    let prim_bytes = g.primitives.len() * std::mem::size_of::<prism::geometry::Primitive>();
    println!(
        "memory             {:.1} MiB geometry ({:.1} MiB meshes, {:.1} MiB primitives)",
        (mesh_bytes + prim_bytes) as f64 / 1048576.0,
        mesh_bytes as f64 / 1048576.0,
        prim_bytes as f64 / 1048576.0
    );
    let start = Instant::now();
    let prepared = scene.prepare(accel);
    println!(
        "accelerator        {} (built in {:.1} ms)",
        prepared.intersector.accel.describe(),
        start.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// A colour as one number when it is a grey, else as [r, g, b].
/// The emitting materials and their primitives: the area lights both integrators light
/// the scene by (Whitted's by `area_samples` shadow rays a point); planes, boxes and cones
/// that emit are seen but light nothing.
fn print_emitters(scene: &Scene) {
    use prism::geometry::Shape;
    let g = &scene.geometry;
    let emissive: Vec<usize> = (0..scene.materials.len())
        .filter(|&i| scene.materials[i].mean_emission().max_element() > 0.0)
        .collect();
    let count = |m: usize, sampled: bool| {
        g.primitives
            .iter()
            .filter(|p| p.material as usize == m)
            .filter(|p| !sampled || matches!(p.shape, Shape::Triangle { .. } | Shape::Sphere(_)))
            .count()
    };
    let total: usize = emissive.iter().map(|&m| count(m, true)).sum();
    println!("emitters           {total} primitives (area lights)");
    for m in emissive {
        let (all, sampled) = (count(m, false), count(m, true));
        let seen_only = match all - sampled {
            0 => String::new(),
            n => format!(", {n} seen only (planes, boxes, cones)"),
        };
        let material = &scene.materials[m];
        // A textured emitter's radiance varies over it: its mean stands for it.
        let textured = match material.emission_map {
            Some(_) => " (texture's mean)",
            None => "",
        };
        println!(
            "  {:<16} emission {}{textured}  ({sampled} primitives{seen_only})",
            material.name,
            grey_or_rgb(material.mean_emission())
        );
    }
}

fn grey_or_rgb(c: prism::math::Color) -> String {
    if c.x == c.y && c.y == c.z {
        format!("{:.2}", c.x)
    } else {
        format!("[{:.2}, {:.2}, {:.2}]", c.x, c.y, c.z)
    }
}
