//! glTF 2.0 scenes end to end, on tiny files the tests write: a textured quad under a
//! node hierarchy, with a camera and lights, as .gltf (data: URI or external .bin) and as
//! .glb. Geometry, camera, lights and materials come out as documented; the quad renders
//! the same as the equivalent TOML scene and at any scale; malformed files give errors that
//! say what is wrong; and no mutation of a valid file makes the loader panic.

use crate::common;
use glam::{Quat, Vec2};
use prism::geometry::{ShapeHit, TriangleMesh};
use prism::light::Light;
use prism::math::{Color, Vec3};
use prism::render::{render, Film};
use prism::shading::{FresnelMode, Highlight, Texture};
use prism::Scene;
use prism_io::scene::{load, LoadError};

use common::mesh_files::{glb, render_at};
use common::mutate::{self, apply, Mutation};
use common::scratch::ScratchDir;
use proptest::prelude::*;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

// ---- building test files ----------------------------------------------------------------

fn temp_dir(name: &str) -> ScratchDir {
    ScratchDir::new("gltf", name)
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write test file");
    path
}

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

const POSITIONS: [[f32; 3]; 4] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];
const NORMAL: [f32; 3] = [0.0, 0.0, 1.0];
/// glTF texture coordinates: v runs down the image, so the top-left corner is (0, 0).
const UVS: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
const INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];
/// positions 48 bytes, normals 48, uvs 32, indices 12.
const BUFFER_LEN: usize = 140;

fn quad_buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for p in POSITIONS {
        p.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for _ in 0..4 {
        NORMAL.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for uv in UVS {
        uv.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    INDICES.iter().for_each(|i| b.extend(i.to_le_bytes()));
    assert_eq!(b.len(), BUFFER_LEN);
    b
}

fn quad_buffer_uri() -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        base64(&quad_buffer())
    )
}

/// The quad's node transform: scale, then 30° about y, then translate.
const QUAD_SCALE: [f32; 3] = [2.0, 1.0, 1.0];
const QUAD_TURN_DEGREES: f32 = 30.0;
const QUAD_TRANSLATION: [f32; 3] = [0.5, 0.0, -1.0];
/// The sun points 45° down from −Z, towards −Y.
const SUN_TILT_DEGREES: f32 = -45.0;

fn quat(axis: Vec3, degrees: f32) -> [f32; 4] {
    Quat::from_axis_angle(axis, degrees.to_radians()).to_array()
}

/// The test scene: the quad under a parent node that translates it (the quad's own node
/// scales and turns it), a camera at z = 6, a coloured point light and a white sun.
fn quad_document(buffer_uri: Option<&str>) -> Value {
    let mut buffer = json!({ "byteLength": BUFFER_LEN });
    if let Some(uri) = buffer_uri {
        buffer["uri"] = json!(uri);
    }
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior"],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 20.0 },
            { "type": "directional", "intensity": 2.0 }
        ] } },
        "scene": 0,
        "scenes": [{ "nodes": [0, 2, 3, 4] }],
        "nodes": [
            { "name": "parent", "translation": QUAD_TRANSLATION, "children": [1] },
            { "name": "quad", "mesh": 0, "scale": QUAD_SCALE,
              "rotation": quat(Vec3::Y, QUAD_TURN_DEGREES) },
            { "name": "camera", "camera": 0, "translation": [0.0, 0.0, 6.0] },
            { "name": "lamp", "translation": [0.0, 3.0, 3.0],
              "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "name": "sun", "rotation": quat(Vec3::X, SUN_TILT_DEGREES),
              "extensions": { "KHR_lights_punctual": { "light": 1 } } }
        ],
        "cameras": [{ "type": "perspective",
                      "perspective": { "yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1 } }],
        "meshes": [{ "name": "Quad", "primitives": [{
            "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 },
            "indices": 3, "material": 0 }] }],
        "materials": [{ "name": "red", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.2, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5 } }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2" },
            { "bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 48 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 48 },
            { "buffer": 0, "byteOffset": 96, "byteLength": 32 },
            { "buffer": 0, "byteOffset": 128, "byteLength": 12 }
        ],
        "buffers": [buffer]
    })
}

fn pretty(doc: &Value) -> Vec<u8> {
    serde_json::to_vec_pretty(doc).expect("serialisable")
}

fn quad_glb() -> Vec<u8> {
    glb(&pretty(&quad_document(None)), &quad_buffer())
}

fn load_doc(dir: &str, doc: &Value) -> Result<Scene, LoadError> {
    load(&write(&temp_dir(dir), "scene.gltf", &pretty(doc)))
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).abs().max_element() <= tolerance * b.abs().max_element().max(1.0)
}

fn quad_world(p: [f32; 3]) -> Vec3 {
    let turn = Quat::from_rotation_y(QUAD_TURN_DEGREES.to_radians());
    turn * (Vec3::from(QUAD_SCALE) * Vec3::from(p)) + Vec3::from(QUAD_TRANSLATION)
}

/// The shading normal and uv at vertex `v` of triangle `tri` (0, 1 or 2 in its order).
fn at_vertex(mesh: &TriangleMesh, tri: u32, v: usize) -> (Vec3, Vec2) {
    let (u, w) = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)][v];
    let s = mesh.surface(tri, &ShapeHit { t: 1.0, u, v: w });
    (s.ns, s.uv)
}

fn texture_film() -> Film {
    // Top row red, green; bottom row blue, white.
    let mut film = Film::new(2, 2);
    film.set(0, 0, Color::new(1.0, 0.0, 0.0));
    film.set(1, 0, Color::new(0.0, 1.0, 0.0));
    film.set(0, 1, Color::new(0.0, 0.0, 1.0));
    film.set(1, 1, Color::ONE);
    film
}

fn write_texture(dir: &Path) -> PathBuf {
    let path = dir.join("card.png");
    prism_io::output::write_image(&path, &texture_film()).expect("texture written");
    path
}

// ---- what a valid file gives -------------------------------------------------------------

#[test]
fn the_node_hierarchy_places_the_quad() {
    let scene = load_doc("hierarchy", &quad_document(Some(&quad_buffer_uri()))).unwrap();
    assert_eq!(scene.geometry.meshes.len(), 1);
    let mesh = &scene.geometry.meshes[0];
    assert_eq!(mesh.triangle_count(), 2);
    assert_eq!(mesh.indices(), &[[0, 1, 2], [0, 2, 3]]);
    for (got, p) in mesh.positions().iter().zip(POSITIONS) {
        assert!(
            close(*got, quad_world(p), 1e-6),
            "{got} vs {}",
            quad_world(p)
        );
    }
    // Normals turn with the quad; the scale along x does not tilt them (they have no x).
    let turned = Quat::from_rotation_y(QUAD_TURN_DEGREES.to_radians()) * Vec3::Z;
    let (n, uv) = at_vertex(mesh, 1, 2);
    assert!(close(n, turned, 1e-6), "{n}");
    // Vertex 3 is the image's top-left corner: glTF uv (0, 0), prism uv (0, 1).
    assert_eq!(uv, Vec2::new(0.0, 1.0));
}

#[test]
fn the_camera_follows_its_node_and_aspect_ratio() {
    let scene = load_doc("camera", &quad_document(Some(&quad_buffer_uri()))).unwrap();
    let c = scene.camera;
    assert_eq!(c.eye, Vec3::new(0.0, 0.0, 6.0));
    assert!(close((c.look_at - c.eye).normalize(), Vec3::NEG_Z, 1e-6));
    assert!(close(c.up.normalize(), Vec3::Y, 1e-6));
    // Landscape: prism's field of view spans the height, as yfov does.
    assert!((c.fov_degrees - 0.8f32.to_degrees()).abs() < 1e-4);
    assert_eq!((scene.options.width, scene.options.height), (640, 427));

    // A portrait camera: prism's field of view spans the (shorter) width.
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["cameras"][0]["perspective"]["aspectRatio"] = json!(0.5);
    let scene = load_doc("camera-portrait", &doc).unwrap();
    assert_eq!((scene.options.width, scene.options.height), (320, 640));
    let expected = 2.0 * (0.5 * 0.4f32.tan()).atan();
    assert!((scene.camera.fov_degrees - expected.to_degrees()).abs() < 1e-4);
}

#[test]
fn an_orthographic_camera_takes_its_window_and_shape() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["cameras"][0] = json!({ "type": "orthographic",
        "orthographic": { "xmag": 3.0, "ymag": 1.5, "znear": 0.1, "zfar": 100.0 } });
    let scene = load_doc("camera-ortho", &doc).unwrap();
    // A window twice as wide as high: the image takes that shape, and the view is
    // 2·ymag = 3 units across its shorter side.
    assert_eq!(
        scene.camera.projection,
        prism::camera::Projection::Orthographic { size: 3.0 }
    );
    assert_eq!((scene.options.width, scene.options.height), (640, 320));
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 0.0, 6.0));
    // The quad, turned 30° about y, spans its true width on the film: 2·2·cos 30° = 3.46
    // units of the 6 across, whatever the camera's distance.
    let film = render_at(&scene, 64, 32);
    let lit = (0..64)
        .filter(|&x| film.get(x, 16) != Default::default())
        .count();
    let expected = 64.0 * 4.0 * 30f32.to_radians().cos() / 6.0;
    assert!(
        (lit as f32 - expected).abs() <= 2.0,
        "{lit} columns show the quad, expected about {expected}"
    );
}

#[test]
fn lights_keep_their_colour_ratio_and_are_exposed_for_the_scene() {
    let scene = load_doc("lights", &quad_document(Some(&quad_buffer_uri()))).unwrap();
    let [Light::Point {
        position,
        color: point,
    }, Light::Directional {
        direction,
        color: sun,
    }] = scene.lights[..]
    else {
        panic!(
            "expected a point light then a directional one: {:?}",
            scene.lights
        );
    };
    assert_eq!(position, Vec3::new(0.0, 3.0, 3.0));
    let tilted = Quat::from_rotation_x(SUN_TILT_DEGREES.to_radians()) * Vec3::NEG_Z;
    assert!(close(direction, tilted, 1e-6), "{direction}");
    // Irradiance at the centre of the quad's bounds, in glTF units, then scaled to sum to 1.
    let bounds = scene.geometry.world_bounds();
    let d2 = position.distance_squared(bounds.center());
    let lum = |c: Color| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    let point_gltf = Color::new(1.0, 0.5, 0.25) * 20.0 / d2;
    let sun_gltf = Color::splat(2.0);
    let total = lum(point_gltf) + lum(sun_gltf);
    assert!(close(point, point_gltf / total, 1e-5), "{point}");
    assert!(close(sun, sun_gltf / total, 1e-5), "{sun}");
    assert!((lum(point) + lum(sun) - 1.0).abs() < 1e-5);
}

#[test]
fn metallic_roughness_becomes_a_whitted_material() {
    let scene = load_doc("material", &quad_document(Some(&quad_buffer_uri()))).unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.name, "red");
    assert_eq!(m.color, Texture::Solid(Color::new(0.8, 0.2, 0.1)));
    // Roughness 0.5: gloss (1 − r)² = 0.25; a dielectric mirrors 4 % of that.
    assert!((m.reflect - 0.01).abs() < 1e-6);
    assert!((m.diffuse - 0.99).abs() < 1e-6);
    assert_eq!(m.ambient, m.diffuse);
    assert_eq!(m.specular, 0.5);
    assert_eq!(m.shininess, 30.0);
    assert_eq!(m.highlight, Highlight::BlinnPhong);
    assert_eq!((m.transmit, m.fresnel), (Color::ZERO, FresnelMode::Off));

    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = json!(1.0);
    doc["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = json!(0.0);
    let metal = &load_doc("metal", &doc).unwrap().materials[0];
    assert_eq!((metal.reflect, metal.diffuse), (1.0, 0.0));

    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["materials"][0]["extensions"] = json!({
        "KHR_materials_transmission": { "transmissionFactor": 1.0 },
        "KHR_materials_ior": { "ior": 1.33 }
    });
    let glass = &load_doc("glass", &doc).unwrap().materials[0];
    // KHR_materials_transmission: the base colour tints what passes.
    assert_eq!(
        (glass.transmit, glass.ior),
        (Color::new(0.8, 0.2, 0.1), 1.33)
    );
    assert_eq!(glass.fresnel, FresnelMode::Exact);
    assert_eq!(glass.diffuse, 0.0);
}

#[test]
fn a_primitive_without_material_gets_gltfs_default_white() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["meshes"][0]["primitives"][0]
        .as_object_mut()
        .unwrap()
        .remove("material");
    let scene = load_doc("default-material", &doc).unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.color, Texture::Solid(Color::ONE));
    // glTF's default is metallic and fully rough: nothing sharp to mirror.
    assert_eq!((m.diffuse, m.reflect, m.specular), (1.0, 0.0, 0.0));
}

#[test]
fn glb_and_external_buffers_load_the_same_scene_as_a_data_uri() {
    let dir = temp_dir("containers");
    let reference = load_doc("containers-ref", &quad_document(Some(&quad_buffer_uri()))).unwrap();
    let from_glb = load(&write(&dir, "quad.glb", &quad_glb())).unwrap();
    write(&dir, "quad data.bin", &quad_buffer());
    let external = quad_document(Some("quad%20data.bin"));
    let from_file = load(&write(&dir, "quad.gltf", &pretty(&external))).unwrap();
    for scene in [&from_glb, &from_file] {
        assert_eq!(scene.geometry.meshes, reference.geometry.meshes);
        assert_eq!(scene.camera, reference.camera);
        assert_eq!(scene.lights, reference.lights);
        assert_eq!(scene.materials, reference.materials);
    }
}

#[test]
fn a_byte_order_mark_is_ignored() {
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(pretty(&quad_document(Some(&quad_buffer_uri()))));
    let scene = load(&write(&temp_dir("bom"), "bom.gltf", &bytes)).unwrap();
    assert_eq!(scene.geometry.meshes.len(), 1);
}

#[test]
fn base_colour_textures_come_from_files_data_uris_and_buffer_views() {
    let dir = temp_dir("textures");
    let png = std::fs::read(write_texture(&dir)).unwrap();
    let with_image = |image: Value, factor: [f32; 4]| {
        let mut doc = quad_document(Some(&quad_buffer_uri()));
        let pbr = &mut doc["materials"][0]["pbrMetallicRoughness"];
        pbr["baseColorTexture"] = json!({ "index": 0 });
        pbr["baseColorFactor"] = json!(factor);
        doc["textures"] = json!([{ "source": 0 }]);
        doc["images"] = json!([image]);
        doc
    };
    let texel_top_left = |scene: &Scene| match &scene.materials[0].color {
        // The texel centre of the image's top-left texel, in prism's uv.
        Texture::Image(img) => img.eval(Vec2::new(0.25, 0.75)),
        other => panic!("expected an image texture, got {other:?}"),
    };

    let file = with_image(json!({ "uri": "card.png" }), [1.0; 4]);
    let scene = load(&write(&dir, "file.gltf", &pretty(&file))).unwrap();
    assert_eq!(texel_top_left(&scene), Color::new(1.0, 0.0, 0.0));

    let data = with_image(
        json!({ "uri": format!("data:image/png;base64,{}", base64(&png)) }),
        [0.5, 1.0, 1.0, 1.0],
    );
    let scene = load(&write(&dir, "data.gltf", &pretty(&data))).unwrap();
    assert_eq!(
        texel_top_left(&scene),
        Color::new(0.5, 0.0, 0.0),
        "tinted by the factor"
    );

    // In a GLB: the image is a buffer view after the quad's data.
    let mut bin = quad_buffer();
    bin.extend(&png);
    let mut doc = with_image(
        json!({ "bufferView": 4, "mimeType": "image/png" }),
        [1.0; 4],
    );
    doc["buffers"][0] = json!({ "byteLength": bin.len() });
    doc["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "buffer": 0, "byteOffset": BUFFER_LEN, "byteLength": png.len() }));
    let scene = load(&write(&dir, "view.glb", &glb(&pretty(&doc), &bin))).unwrap();
    assert_eq!(texel_top_left(&scene), Color::new(1.0, 0.0, 0.0));
}

/// A primitive whose triangles all have zero area (three points on a line) shows nothing:
/// it is left out with a warning naming its mesh, and the quad beside it loads.
#[test]
fn a_primitive_of_zero_area_faces_is_left_out_with_a_warning() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    let line: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    doc["buffers"].as_array_mut().unwrap().push(json!({
        "byteLength": line.len(),
        "uri": format!("data:application/octet-stream;base64,{}", base64(&line)),
    }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!(
        { "buffer": 1, "byteOffset": 0, "byteLength": line.len() }
    ));
    doc["accessors"].as_array_mut().unwrap().push(json!(
        { "bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3",
          "min": [0.0, 0.0, 0.0], "max": [2.0, 0.0, 0.0] }
    ));
    doc["meshes"].as_array_mut().unwrap().push(json!(
        { "name": "Flat", "primitives": [{ "attributes": { "POSITION": 4 } }] }
    ));
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "name": "flat", "mesh": 1 }));
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(5));
    let scene = load_doc("gltf-zero-area", &doc).expect("the quad loads");
    assert_eq!(scene.geometry.meshes.len(), 1, "only the quad");
    let w = scene.warnings.join("\n");
    assert!(
        w.contains(
            "scene.gltf: mesh 1 ('Flat'), primitive 0 has only faces of zero area (1); it is \
             left out"
        ),
        "{w}"
    );
}

#[test]
fn a_mirroring_transform_keeps_the_outside_outside() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["nodes"][1] = json!({ "mesh": 0, "scale": [-1.0, 1.0, 1.0] });
    let attributes = &mut doc["meshes"][0]["primitives"][0]["attributes"];
    attributes.as_object_mut().unwrap().remove("NORMAL");
    let scene = load_doc("mirror", &doc).unwrap();
    let mesh = &scene.geometry.meshes[0];
    assert_eq!(mesh.indices(), &[[0, 2, 1], [0, 3, 2]]);
    let ng = mesh
        .surface(
            0,
            &ShapeHit {
                t: 1.0,
                u: 0.3,
                v: 0.3,
            },
        )
        .ng;
    assert!(ng.z > 0.99, "the quad still faces +z: {ng}");
}

#[test]
fn interleaved_strips_without_indices_are_read() {
    // Position and normal interleaved (24-byte stride), drawn as a strip of 4 vertices.
    let mut bytes = Vec::new();
    for p in [POSITIONS[0], POSITIONS[1], POSITIONS[3], POSITIONS[2]] {
        p.iter()
            .chain(&NORMAL)
            .for_each(|c| bytes.extend(c.to_le_bytes()));
    }
    let doc = json!({
        "asset": { "version": "2.0" },
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "mode": 5 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3" },
            { "bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3" }
        ],
        "bufferViews": [{ "buffer": 0, "byteLength": 96, "byteStride": 24 }],
        "buffers": [{ "byteLength": 96,
                      "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes)) }]
    });
    let scene = load_doc("strip", &doc).unwrap();
    let mesh = &scene.geometry.meshes[0];
    assert_eq!(mesh.indices(), &[[0, 1, 2], [1, 3, 2]]);
    assert_eq!(mesh.positions()[3], Vec3::from(POSITIONS[2]));
    assert!(mesh.has_normals());
    assert_eq!(at_vertex(mesh, 1, 1).0, Vec3::Z);
}

#[test]
fn without_camera_or_lights_the_scene_is_framed_and_lit() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["scenes"][0]["nodes"] = json!([0]);
    let scene = load_doc("defaults", &doc).unwrap();
    let bounds = scene.geometry.world_bounds();
    let c = scene.camera;
    assert_eq!(c.look_at, bounds.center());
    let forward = (c.look_at - c.eye).normalize();
    for i in 0..8 {
        let corner = Vec3::select(
            glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0),
            bounds.max,
            bounds.min,
        );
        let angle = (corner - c.eye)
            .normalize()
            .dot(forward)
            .acos()
            .to_degrees();
        assert!(
            angle < c.fov_degrees / 2.0,
            "corner {corner} is {angle}° off axis"
        );
    }
    let [Light::Directional { direction, color }] = scene.lights[..] else {
        panic!("expected one default light: {:?}", scene.lights);
    };
    assert_eq!(color, Color::ONE);
    assert!(
        direction.dot(forward) > 0.0 && direction.y < 0.0,
        "from behind and above"
    );
    let film = render_at(&scene, 32, 24);
    assert!(film.get(16, 12).max_element() > 0.2, "the quad is lit");
}

#[test]
fn the_example_scene_loads_and_renders() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/spheres.gltf");
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        ["floor", "chrome", "glass", "red plastic", "rough gold"]
    );
    assert!(matches!(scene.materials[0].color, Texture::Image(_)));
    assert_eq!(scene.geometry.meshes.len(), 5);
    assert_eq!(scene.lights.len(), 2);
    let film = render_at(&scene, 48, 32);
    assert!(film
        .pixels
        .iter()
        .all(|p| p.is_finite() && p.min_element() >= 0.0));
    assert!(film.pixels.iter().any(|p| p.max_element() > 0.3));
}

// ---- the same scene in other forms -------------------------------------------------------

#[test]
fn the_quad_renders_like_the_same_toml_scene() {
    let dir = temp_dir("toml");
    write_texture(&dir);
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    // One white sun; the exposure makes its prism colour exactly 1.
    doc["scenes"][0]["nodes"] = json!([0, 2, 4]);
    doc["extensions"]["KHR_lights_punctual"]["lights"][1]["intensity"] = json!(1.0);
    doc["nodes"][4]["extensions"]["KHR_lights_punctual"]["light"] = json!(1);
    let pbr = &mut doc["materials"][0]["pbrMetallicRoughness"];
    pbr["baseColorFactor"] = json!([1.0, 1.0, 1.0, 1.0]);
    pbr["baseColorTexture"] = json!({ "index": 0 });
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([{ "uri": "card.png" }]);
    let gltf = load(&write(&dir, "quad.gltf", &pretty(&doc))).unwrap();

    let fmt = |v: &[f32]| {
        let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        format!("[{}]", items.join(", "))
    };
    let positions: Vec<String> = POSITIONS.iter().map(|p| fmt(p)).collect();
    // prism's v runs up the image.
    let uvs: Vec<String> = UVS.iter().map(|[u, v]| fmt(&[*u, 1.0 - v])).collect();
    let sun = Quat::from_rotation_x(SUN_TILT_DEGREES.to_radians()) * Vec3::NEG_Z;
    let toml = format!(
        r#"
[camera]
eye = [0, 0, 6]
look_at = [0, 0, 0]
fov = {fov:?}

[materials.card]
texture = {{ type = "image", path = "card.png" }}
ambient = 0.99
diffuse = 0.99
specular = 0.5
shininess = 30
highlight = "blinn-phong"
reflect = 0.01

[[lights]]
type = "directional"
direction = {sun}

[[objects]]
type = "mesh"
material = "card"
positions = [{positions}]
normals = [[0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, 1]]
uvs = [{uvs}]
indices = [[0, 1, 2], [0, 2, 3]]
transform = {{ scale = {scale}, rotate = [0, {turn:?}, 0], translate = {translate} }}
"#,
        fov = 0.8f32.to_degrees(),
        sun = fmt(&sun.to_array()),
        positions = positions.join(", "),
        uvs = uvs.join(", "),
        scale = fmt(&QUAD_SCALE),
        turn = QUAD_TURN_DEGREES,
        translate = fmt(&QUAD_TRANSLATION),
    );
    let toml = load(&write(&dir, "quad.toml", toml.as_bytes())).unwrap();

    let a = render_at(&gltf, 96, 64);
    let b = render_at(&toml, 96, 64);
    let lit = a.pixels.iter().filter(|p| p.max_element() > 0.05).count();
    assert!(
        lit > 96 * 64 / 10,
        "the quad covers the image: {lit} lit pixels"
    );
    let worst = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-3, "largest pixel difference {worst}");
}

#[test]
fn the_scene_renders_the_same_at_any_scale() {
    // Only the point light: a point light's irradiance falls with distance, a directional
    // one's does not, so in glTF's physical units their balance depends on the scene's
    // size. Alone, the exposure makes a light independent of it.
    let mut reference = quad_document(Some(&quad_buffer_uri()));
    reference["scenes"][0]["nodes"] = json!([0, 2, 3]);
    let reference = render_at(&load_doc("scale-1", &reference).unwrap(), 48, 32);
    for scale in [1e-3f32, 1e3] {
        // Everything under one root node that scales the world.
        let mut doc = quad_document(Some(&quad_buffer_uri()));
        doc["nodes"].as_array_mut().unwrap().push(json!({
            "scale": [scale, scale, scale], "children": [0, 2, 3]
        }));
        doc["scenes"][0]["nodes"] = json!([5]);
        let scene = load_doc(&format!("scale-{scale}"), &doc).unwrap();
        let film = render_at(&scene, 48, 32);
        let differing = film
            .pixels
            .iter()
            .zip(&reference.pixels)
            .filter(|(p, q)| (**p - **q).abs().max_element() > 1e-3)
            .count();
        // Pixels whose centre grazes the quad's edge may flip; nothing else may change.
        assert!(differing <= 4, "scale {scale}: {differing} pixels differ");
    }
}

// ---- malformed files ---------------------------------------------------------------------

fn invalid_message(result: Result<Scene, LoadError>) -> String {
    match result {
        Err(LoadError::Invalid { message, .. }) => message,
        Err(other) => panic!("expected an Invalid error, got {other}"),
        Ok(_) => panic!("expected an error, the file loaded"),
    }
}

#[test]
fn bad_json_is_located_by_line_and_column() {
    let text = "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"scenes\": [{\"nodes\": []}]\n  \"nodes\": []\n}\n";
    let dir = temp_dir("syntax");
    let path = write(&dir, "broken.gltf", text.as_bytes());
    match load(&path) {
        Err(LoadError::Syntax {
            path: p,
            line,
            column,
            message,
        }) => {
            assert!(p.ends_with("broken.gltf"));
            assert_eq!((line, column), (4, 3), "{message}");
            assert!(message.contains("expected"), "{message}");
            assert!(
                !message.contains("at line"),
                "the position is not repeated: {message}"
            );
        }
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn an_accessor_index_out_of_range_names_the_reference_and_what_exists() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["meshes"][0]["primitives"][0]["indices"] = json!(9);
    let message = invalid_message(load_doc("bad-index", &doc));
    assert!(
        message.contains("meshes[0].primitives[0].indices"),
        "{message}"
    );
    assert!(message.contains("accessor 9"), "{message}");
    assert!(message.contains("4 accessors"), "{message}");
}

#[test]
fn a_position_accessor_out_of_range_is_an_error_not_a_panic() {
    // gltf-json 1.4's own validator indexes with this one unchecked.
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    let message = invalid_message(load_doc("bad-position", &doc));
    assert!(message.contains("refers to accessor 7"), "{message}");
}

#[test]
fn accessor_data_beyond_its_buffer_view_is_an_error() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["accessors"][0]["count"] = json!(5);
    let message = invalid_message(load_doc("overrun", &doc));
    assert!(message.contains("POSITION"), "{message}");
    assert!(message.contains("do not fit in bufferView 0"), "{message}");
}

#[test]
fn a_missing_buffer_file_names_the_uri() {
    let doc = quad_document(Some("nowhere.bin"));
    let message = invalid_message(load_doc("missing-buffer", &doc));
    assert!(message.contains("buffer 0"), "{message}");
    assert!(message.contains("'nowhere.bin'"), "{message}");
}

#[test]
fn a_truncated_glb_says_so() {
    let bytes = quad_glb();
    let dir = temp_dir("truncated");
    for cut in [5, bytes.len() / 2, bytes.len() - 1] {
        let message = invalid_message(load(&write(&dir, "cut.glb", &bytes[..cut])));
        assert!(message.contains("GLB"), "{message}");
        if cut >= 12 {
            assert!(message.contains("truncated"), "cut at {cut}: {message}");
        }
    }
}

#[test]
fn unsupported_required_extensions_and_cycles_are_refused() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let message = invalid_message(load_doc("draco", &doc));
    assert!(message.contains("KHR_draco_mesh_compression"), "{message}");

    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["nodes"][1]["children"] = json!([0]);
    let message = invalid_message(load_doc("cycle", &doc));
    assert!(message.contains("reached twice"), "{message}");
}

#[test]
fn points_and_lines_are_skipped() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["meshes"][0]["primitives"][0]["mode"] = json!(1);
    let scene = load_doc("lines", &doc).unwrap();
    assert!(scene.geometry.primitives.is_empty());
}

// ---- robustness --------------------------------------------------------------------------

const MUTATION_BYTES: &[u8] = b"[]{}:\",.-+ 0123456789eE\"\x00\xff";
const MUTATION_VALUES: &[&str] = &[
    "-1",
    "0",
    "1",
    "3",
    "7",
    "255",
    "65535",
    "4294967295",
    "4294967296",
    "1e39",
    "-0.0",
    "0.5",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    mutate::text_damage(16, 32, MUTATION_BYTES, MUTATION_VALUES)
}

proptest! {
    #![proptest_config(mutate::config(1024))]

    /// Form 0 mutates a .glb's bytes (headers included); form 1 mutates its JSON and packs
    /// it again, so the mutation reaches the document; form 2 mutates a .gltf whose buffer
    /// is a data: URI.
    #[test]
    fn mutated_files_never_panic(
        form in 0usize..3,
        mutations in prop::collection::vec(mutation(), 1..5),
    ) {
        let (name, bytes) = match form {
            0 => {
                let mut bytes = quad_glb();
                mutations.iter().for_each(|m| apply(&mut bytes, m));
                ("mutated.glb", bytes)
            }
            1 => {
                let mut json = pretty(&quad_document(None));
                mutations.iter().for_each(|m| apply(&mut json, m));
                ("repacked.glb", glb(&json, &quad_buffer()))
            }
            _ => {
                let mut json = pretty(&quad_document(Some(&quad_buffer_uri())));
                mutations.iter().for_each(|m| apply(&mut json, m));
                ("mutated.gltf", json)
            }
        };
        let dir = temp_dir("proptest");
        let path = write(&dir, name, &bytes);
        match load(&path) {
            Ok(scene) => prop_assert!(scene.validate().is_ok()),
            Err(LoadError::Syntax { line, column, message, .. }) => {
                prop_assert!(line >= 1 && column >= 1, "{line}:{column}");
                prop_assert!(!message.is_empty());
            }
            Err(LoadError::Invalid { message, .. }) => prop_assert!(!message.is_empty()),
            Err(other) => prop_assert!(false, "unexpected error kind: {other}"),
        }
    }
}

#[test]
fn emissive_factor_makes_an_area_light() {
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["materials"][0]["emissiveFactor"] = json!([1.0, 0.5, 0.25]);
    let scene = load_doc("emissive", &doc).unwrap_or_else(|e| panic!("{e}"));
    let lamp = scene.materials.iter().find(|m| m.name == "red").unwrap();
    assert_eq!(lamp.emission, Color::new(1.0, 0.5, 0.25));
    let mut dark = quad_document(Some(&quad_buffer_uri()));
    dark["materials"][0]["emissiveFactor"] = json!([-1.0, 0.0, 0.0]);
    assert!(load_doc("emissive-negative", &dark).is_err());
}

/// A material's normalTexture becomes a normal map with its scale, its texels read as
/// data (no sRGB curve), and it changes the picture; a scale that is not a number is an
/// error.
#[test]
fn a_normal_texture_is_a_normal_map() {
    let dir = temp_dir("normal-map");
    write_texture(&dir);
    // Tilted towards +u: (191, 128, 255) is about (0.5, 0, 1) in the tangent frame.
    image::RgbImage::from_pixel(2, 2, image::Rgb([191, 128, 255]))
        .save(dir.join("normals.png"))
        .unwrap();
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["textures"] = json!([{ "source": 0 }, { "source": 1 }]);
    doc["images"] = json!([{ "uri": "card.png" }, { "uri": "normals.png" }]);
    let plain = load(&write(&dir, "plain.gltf", &pretty(&doc))).unwrap();
    assert!(plain.materials.iter().all(|m| m.normal_map.is_none()));
    doc["materials"][0]["normalTexture"] = json!({ "index": 1, "scale": 0.5 });
    let mapped = load(&write(&dir, "mapped.gltf", &pretty(&doc))).unwrap();
    let map = mapped.materials[0]
        .normal_map
        .as_ref()
        .expect("a normal map");
    assert_eq!(map.scale, 0.5);
    // The texels are data: 128 is 128/255, not its sRGB decoding (about 0.216).
    let texel = map.texture.eval(prism::math::Vec2::new(0.5, 0.5));
    assert_eq!(texel, prism::math::Color::new(191.0, 128.0, 255.0) / 255.0);
    let (a, b) = (render_at(&plain, 48, 32), render_at(&mapped, 48, 32));
    assert_ne!(a.pixels, b.pixels, "the normal map changes the shading");
    doc["materials"][0]["normalTexture"] = json!({ "index": 1, "scale": "x" });
    assert!(load(&write(&dir, "bad.gltf", &pretty(&doc))).is_err());
}

/// What prism reads and does not render is said once per file, naming each feature and
/// how often it appears; a file with none of it loads without a warning.
#[test]
fn features_not_rendered_are_named_in_one_warning() {
    let dir = temp_dir("dropped");
    write_texture(&dir);
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    let plain = load(&write(&dir, "plain.gltf", &pretty(&doc))).unwrap();
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    doc["textures"] = json!([{ "source": 0, "sampler": 0 }]);
    doc["samplers"] = json!([{ "wrapS": 33071 }]);
    doc["images"] = json!([{ "uri": "card.png" }]);
    doc["materials"][0]["emissiveTexture"] = json!({ "index": 0, "texCoord": 1 });
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
    doc["materials"][0]["alphaMode"] = json!("BLEND");
    doc["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_texture_transform"]);
    doc["animations"] = json!([]);
    let scene = load(&write(&dir, "dropped.gltf", &pretty(&doc))).unwrap();
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let w = &scene.warnings[0];
    assert!(
        w.contains("dropped.gltf: read but not rendered as authored"),
        "{w}"
    );
    for dropped in [
        "textures reading several TEXCOORD sets, all drawn with the first one's (1)",
        "texture samplers that clamp or mirror, drawn repeating (1)",
        "extension KHR_texture_transform",
    ] {
        assert!(w.contains(dropped), "{dropped}: {w}");
    }
    assert!(
        !w.contains("KHR_lights_punctual") && !w.contains("emissiveTexture"),
        "rendered features are not named: {w}"
    );
    assert!(
        w.contains("alphaMode MASK or BLEND, drawn opaque (1)"),
        "{w}"
    );
    assert!(
        !w.contains("animations"),
        "an empty list is nothing dropped: {w}"
    );
}

/// occlusionTexture scales the ambient term per texel: its red channel with the strength
/// applied, 1 + s·(r − 1), read as data; a strength outside 0..=1 is an error.
#[test]
fn an_occlusion_texture_scales_the_ambient_term() {
    let dir = temp_dir("occlusion");
    write_texture(&dir);
    image::RgbImage::from_pixel(2, 2, image::Rgb([64, 200, 200]))
        .save(dir.join("occlusion.png"))
        .unwrap();
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["textures"] = json!([{ "source": 0 }, { "source": 1 }]);
    doc["images"] = json!([{ "uri": "card.png" }, { "uri": "occlusion.png" }]);
    let plain = load(&write(&dir, "plain.gltf", &pretty(&doc))).unwrap();
    doc["materials"][0]["occlusionTexture"] = json!({ "index": 1, "strength": 0.5 });
    let occluded = load(&write(&dir, "occluded.gltf", &pretty(&doc))).unwrap();
    let m = &occluded.materials[0];
    let expected = 1.0 + 0.5 * (64.0 / 255.0 - 1.0);
    let got = m.ambient_occlusion(prism::math::Vec2::new(0.5, 0.5));
    assert!((got - expected).abs() < 1e-6, "{got} against {expected}");
    assert_eq!(
        plain.materials[0].ambient_occlusion(prism::math::Vec2::ZERO),
        1.0
    );
    let (a, b) = (render_at(&plain, 48, 32), render_at(&occluded, 48, 32));
    let sum = |f: &prism::render::Film| f.pixels.iter().map(|p| p.x as f64).sum::<f64>();
    assert!(
        sum(&b) < sum(&a),
        "less ambient light reaches the occluded quad"
    );
    doc["materials"][0]["occlusionTexture"] = json!({ "index": 1, "strength": 2.0 });
    let err = load(&write(&dir, "bad.gltf", &pretty(&doc))).unwrap_err();
    assert!(
        err.to_string().contains("expected a number from 0 to 1"),
        "{err}"
    );
}

/// A base colour texture whose image file is not there is a warning (the model loads with
/// its baseColorFactor), as a missing MTL image is; a broken image stays an error.
#[test]
fn a_missing_base_colour_image_is_a_warning() {
    let dir = temp_dir("missing-image");
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    let pbr = &mut doc["materials"][0]["pbrMetallicRoughness"];
    pbr["baseColorFactor"] = json!([0.25, 0.5, 0.75, 1.0]);
    pbr["baseColorTexture"] = json!({ "index": 0 });
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([{ "uri": "not-here.png" }]);
    let scene = load(&write(&dir, "quad.gltf", &pretty(&doc))).unwrap();
    let w = scene.warnings.join("\n");
    assert!(
        w.contains("quad.gltf: material 0: its baseColorTexture's image"),
        "{w}"
    );
    assert!(w.contains("not-here.png is missing"), "{w}");
    assert_eq!(
        scene.materials[0].color,
        prism::shading::Texture::Solid(prism::math::Color::new(0.25, 0.5, 0.75))
    );
    write(&dir, "not-here.png", b"not a png");
    assert!(
        load(&dir.join("quad.gltf")).is_err(),
        "a broken image is an error"
    );
}

/// A normal, occlusion, metallic-roughness or emissive texture whose image file is not
/// there is a warning naming it, as a missing base colour image is: the material does
/// without that map.
#[test]
fn a_missing_normal_or_occlusion_image_is_a_warning() {
    let dir = temp_dir("missing-maps");
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    let material = &mut doc["materials"][0];
    material["normalTexture"] = json!({ "index": 0 });
    material["occlusionTexture"] = json!({ "index": 1 });
    material["emissiveTexture"] = json!({ "index": 2 });
    material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": 3 });
    doc["textures"] = json!([{ "source": 0 }, { "source": 1 }, { "source": 2 }, { "source": 3 }]);
    doc["images"] = json!([
        { "uri": "normal.png" },
        { "uri": "occlusion.png" },
        { "uri": "emissive.png" },
        { "uri": "metal.png" }
    ]);
    let scene = load(&write(&dir, "quad.gltf", &pretty(&doc))).unwrap();
    let w = scene.warnings.join("\n");
    for (what, file) in [
        ("normalTexture", "normal.png"),
        ("occlusionTexture", "occlusion.png"),
        ("emissiveTexture", "emissive.png"),
        ("metallicRoughnessTexture", "metal.png"),
    ] {
        assert!(
            w.contains(&format!("material 0: its {what}'s image"))
                && w.contains(&format!("{file} is missing")),
            "{what}: {w}"
        );
    }
    let m = &scene.materials[0];
    assert!(m.normal_map.is_none() && m.occlusion.is_none());
}

/// The quad of `doc` with its node transforms removed, seen head on from z = 5 with
/// nothing lighting it but the ambient light `ambient` and the background `background`:
/// the scene of the per-texel tests below, whose pixels have closed forms.
fn head_on(doc: &mut Value, dir: &Path, ambient: f32, background: f32) -> Scene {
    for key in ["translation", "scale", "rotation"] {
        for node in 0..2 {
            doc["nodes"][node].as_object_mut().unwrap().remove(key);
        }
    }
    let mut scene = load(&write(dir, "quad.gltf", &pretty(doc))).unwrap();
    common::mesh_files::head_on(&mut scene, Vec::new(), ambient, background);
    scene
}

/// A 4 × 1 PNG of the given texels, left to right, written to `dir/name`.
fn strip(dir: &Path, name: &str, texels: [[u8; 3]; 4]) {
    let mut img = image::RgbImage::new(4, 1);
    for (x, t) in texels.into_iter().enumerate() {
        img.put_pixel(x as u32, 0, image::Rgb(t));
    }
    img.save(dir.join(name)).unwrap();
}

/// The red value of the head-on quad's pixel at u = 0.25 (the middle of the texture's left
/// half) and at u = 0.75, in a 16 × 16 render with `integrator`.
fn left_and_right(scene: &Scene, integrator: &str) -> (f32, f32) {
    let mut options = scene.options.clone();
    options.width = 16;
    options.height = 16;
    options.integrator = integrator.parse().unwrap();
    options.max_depth = 2;
    options.samples = 4;
    let prepared = scene.prepare(&options.accel);
    let film = render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
        .unwrap()
        .film;
    // The view spans x from −0.88 to 0.88 at the quad; u = (x + 1)/2. Pixels 2 and 12
    // lie within the halves' inner texels, where bilinear lookups blend no other texel.
    (film.get(2, 8).x, film.get(12, 8).x)
}

/// metallicRoughnessTexture is looked up per texel, metallic in its blue channel and
/// roughness in its green one, times the factors: a metal texel is a mirror showing the
/// background, a rough dielectric one next to it reflects the ambient light (Whitted) or
/// the background (path tracer) diffusely in the base colour; one mean value would make
/// the two halves alike.
#[test]
fn a_metallic_roughness_texture_is_looked_up_per_texel() {
    let dir = temp_dir("metal-rough");
    let (metal, matte) = ([255, 0, 255], [255, 255, 0]);
    strip(&dir, "mr.png", [metal, metal, matte, matte]);
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([{ "uri": "mr.png" }]);
    doc["materials"][0]["pbrMetallicRoughness"] = json!({
        "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 1.0, "roughnessFactor": 1.0,
        "metallicRoughnessTexture": { "index": 0 } });
    let scene = head_on(&mut doc, &dir, 0.8, 0.6);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
    // Whitted: the mirror shows the background (0.6); the matte half ka·C·Ia = 0.5·0.8.
    let (l, r) = left_and_right(&scene, "whitted");
    assert!(close(l, 0.6) && close(r, 0.4), "Whitted: {l} {r}");
    // Path tracer: the mirror shows the background, the Lambert half 0.5 of it.
    let (l, r) = left_and_right(&scene, "path");
    assert!(close(l, 0.6) && close(r, 0.3), "path: {l} {r}");
}

/// emissiveTexture is looked up per texel (sRGB-decoded), times emissiveFactor and
/// KHR_materials_emissive_strength: the emitting texels glow, their dark neighbours stay
/// dark, in both integrators; one mean colour would light both halves alike.
#[test]
fn an_emissive_texture_glows_texel_by_texel() {
    let dir = temp_dir("emissive-texture");
    let (on, off) = ([255, 255, 255], [0, 0, 0]);
    strip(&dir, "glow.png", [on, on, off, off]);
    let mut doc = quad_document(Some(&quad_buffer_uri()));
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([{ "uri": "glow.png" }]);
    doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    doc["materials"][0] = json!({
        "pbrMetallicRoughness": { "baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                  "metallicFactor": 0.0, "roughnessFactor": 1.0 },
        "emissiveFactor": [1.0, 0.5, 0.25],
        "emissiveTexture": { "index": 0 },
        "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 3.0 } } });
    let scene = head_on(&mut doc, &dir, 0.0, 0.0);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials[0].emission, Color::new(3.0, 1.5, 0.75));
    for integrator in ["whitted", "path"] {
        let (l, r) = left_and_right(&scene, integrator);
        assert!((l - 3.0).abs() < 1e-5 && r == 0.0, "{integrator}: {l} {r}");
    }
    doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] =
        json!(-1.0);
    let err = load(&write(&dir, "bad.gltf", &pretty(&doc))).unwrap_err();
    assert!(err.to_string().contains("emissiveStrength is -1"), "{err}");
}

// ---- tangents for normal maps ------------------------------------------------------------

/// The quad with a normal map tilted towards +x of tangent space (the image a data URI),
/// `normals` per vertex and, where given, a TANGENT accessor of `tangents` (any count),
/// placed by a node that only scales by `scale`. Vertex 1 and 3 may leave the z = 0 plane
/// (`fold`), bending the quad along its shared edge 0–2.
fn tangent_quad(
    normals: [[f32; 3]; 4],
    tangents: Option<&[[f32; 4]]>,
    fold: f32,
    scale: f32,
) -> Value {
    let mut positions = POSITIONS;
    positions[1][2] = fold;
    positions[3][2] = fold;
    let mut b = Vec::new();
    for p in positions {
        p.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for n in normals {
        n.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    for uv in UVS {
        uv.iter().for_each(|c| b.extend(c.to_le_bytes()));
    }
    INDICES.iter().for_each(|i| b.extend(i.to_le_bytes()));
    let mut doc = quad_document(None);
    doc["nodes"][0] = json!({ "name": "parent", "children": [1] });
    doc["nodes"][1] = json!({ "name": "quad", "mesh": 0, "scale": [scale, scale, scale] });
    doc["accessors"][0]["min"] = json!([-1.0, -1.0, fold.min(0.0)]);
    doc["accessors"][0]["max"] = json!([1.0, 1.0, fold.max(0.0)]);
    if let Some(ts) = tangents {
        let offset = b.len();
        for t in ts {
            t.iter().for_each(|c| b.extend(c.to_le_bytes()));
        }
        doc["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": b.len() - offset }));
        doc["accessors"].as_array_mut().unwrap().push(
            json!({ "bufferView": 4, "componentType": 5126, "count": ts.len(), "type": "VEC4" }),
        );
        doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(4);
    }
    doc["buffers"][0] = json!({ "byteLength": b.len(),
        "uri": format!("data:application/octet-stream;base64,{}", base64(&b)) });
    // (255, 128, 255): about (1, 0, 1) in the tangent frame, 45° towards its +x.
    let mut png = Vec::new();
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 128, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    doc["textures"] = json!([{ "source": 0 }]);
    doc["images"] = json!([{ "uri": format!("data:image/png;base64,{}", base64(&png)) }]);
    doc["materials"][0]["normalTexture"] = json!({ "index": 0 });
    doc
}

/// The normal-mapped shading normal of `scene`'s first mesh at the centre of triangle `tri`
/// in the file's tangent frame, and the one the triangle's uv frame gives.
fn mapped_normals(scene: &Scene, tri: u32) -> (Vec3, Vec3) {
    let mesh = &scene.geometry.meshes[0];
    let sp = mesh.surface(
        tri,
        &ShapeHit {
            t: 1.0,
            u: 1.0 / 3.0,
            v: 1.0 / 3.0,
        },
    );
    let map = scene.materials[0]
        .normal_map
        .as_ref()
        .expect("a normal map");
    let (x, y) = mesh.tangent_frame(tri, sp.p, sp.ns).expect("tangents");
    let (dpdu, dpdv) = mesh.uv_derivatives(tri).expect("uvs");
    (
        map.perturb_in_frame(sp.ns, x, y, sp.uv),
        map.perturb(sp.ns, dpdu, dpdv, sp.uv),
    )
}

/// A TANGENT along +y, where the uvs run +x: the map's +x tilts the normal towards +y, not
/// towards +x as the uv frame would; and the file's TANGENT is no longer reported dropped.
#[test]
fn a_files_tangents_turn_the_normal_their_way() {
    let doc = tangent_quad([NORMAL; 4], Some(&[[0.0, 1.0, 0.0, 1.0]; 4]), 0.0, 1.0);
    let scene = load_doc("tangents-file", &doc).unwrap_or_else(|e| panic!("{e}"));
    let (file, uv_frame) = mapped_normals(&scene, 0);
    let half = std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(file, Vec3::new(0.0, half, half), 0.01), "{file}");
    assert!(
        close(uv_frame, Vec3::new(half, 0.0, half), 0.01),
        "{uv_frame}"
    );
    let w = scene.warnings.join("\n");
    assert!(!w.contains("TANGENT"), "{w}");
    // Handedness −1 mirrors y, which this texel does not use; the tangent itself stays.
    let doc = tangent_quad([NORMAL; 4], Some(&[[0.0, 1.0, 0.0, -1.0]; 4]), 0.0, 1.0);
    let scene = load_doc("tangents-left", &doc).unwrap();
    let mesh = &scene.geometry.meshes[0];
    let (x, y) = mesh.tangent_frame(0, Vec3::ZERO, Vec3::Z).unwrap();
    assert!(
        close(x, Vec3::Y, 1e-6) && close(y, Vec3::X, 1e-6),
        "{x} {y}"
    );
}

/// Node scales of 1e-3 and 1e3 keep the file's tangents (directions, normalised).
#[test]
fn a_files_tangents_survive_the_node_transform() {
    let tangent = [[0.6, 0.8, 0.0, 1.0]; 4];
    let mapped = |scale: f32| {
        let doc = tangent_quad([NORMAL; 4], Some(&tangent), 0.0, scale);
        mapped_normals(&load_doc("tangents-scale", &doc).unwrap(), 1).0
    };
    let unit = mapped(1.0);
    let want = (Vec3::new(0.6, 0.8, 0.0) + Vec3::Z).normalize();
    assert!(close(unit, want, 0.01), "{unit}");
    for scale in [1e-3, 1e3] {
        assert!(close(mapped(scale), unit, 1e-6), "scale {scale}");
    }
}

/// A TANGENT accessor with one value too few is an error naming the file, the mesh and the
/// attribute.
#[test]
fn a_tangent_accessor_of_the_wrong_count_is_an_error() {
    let doc = tangent_quad([NORMAL; 4], Some(&[[1.0, 0.0, 0.0, 1.0]; 3]), 0.0, 1.0);
    let message = match load_doc("tangents-count", &doc) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("a short TANGENT accessor loaded"),
    };
    for part in [
        "scene.gltf",
        "mesh 0 ('Quad')",
        "TANGENT has 3 elements",
        "POSITION has 4",
    ] {
        assert!(message.contains(part), "{part} not in: {message}");
    }
}

/// Without TANGENT, a normal-mapped primitive with normals and uvs gets MikkTSpace
/// tangents: on a quad folded along its diagonal, whose two triangles' uv frames differ,
/// the generated frames agree at the vertices the triangles share. A primitive without a
/// normal texture gets none.
#[test]
fn generated_tangents_are_continuous_at_shared_vertices() {
    let mut doc = tangent_quad([NORMAL; 4], None, 0.5, 1.0);
    let scene = load_doc("tangents-generated", &doc).unwrap();
    let mesh = &scene.geometry.meshes[0];
    assert!(mesh.tangents().is_some(), "tangents were generated");
    let [a, b, c] = mesh.indices()[0];
    let shared: Vec<u32> = mesh.indices()[1]
        .into_iter()
        .filter(|v| [a, b, c].contains(v))
        .collect();
    assert_eq!(shared.len(), 2, "no vertex was split: {:?}", mesh.indices());
    let uv_tangent = |tri: u32| mesh.uv_derivatives(tri).unwrap().0.normalize();
    assert!(
        !close(uv_tangent(0), uv_tangent(1), 0.05),
        "the uv frames differ, so the test means something"
    );
    for v in shared {
        let p = mesh.positions()[v as usize];
        let f0 = mesh.tangent_frame(0, p, Vec3::Z).unwrap();
        let f1 = mesh.tangent_frame(1, p, Vec3::Z).unwrap();
        assert!(
            close(f0.0, f1.0, 1e-5) && close(f0.1, f1.1, 1e-5),
            "{f0:?} {f1:?}"
        );
        // Along u, as the uvs run, and right-handed.
        assert!(f0.0.x > 0.9 && f0.1.y > 0.9, "{f0:?}");
    }
    doc["materials"][0]
        .as_object_mut()
        .unwrap()
        .remove("normalTexture");
    let plain = load_doc("tangents-none", &doc).unwrap();
    assert!(plain.geometry.meshes[0].tangents().is_none());
}
