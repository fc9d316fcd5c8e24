//! Writes the binary seed files: corpus/gltf and corpus/glb, small documents that between
//! them use every part of glTF that prism reads (node hierarchies, TRS and matrix
//! transforms, indexed lists, strips and fans, strides, normalized and sparse accessors,
//! cameras, punctual lights, PBR and transmission materials, a PNG texture from a data:
//! URI or a buffer view), and the binary PLY files of corpus/ply (both byte orders).
//! Run from fuzz/: `cargo run --example make_seeds`.

use std::path::Path;

fn f32s(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
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
            out.push(if k <= chunk.len() {
                ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    out
}

fn data_uri(kind: &str, bytes: &[u8]) -> String {
    format!("data:{kind};base64,{}", base64(bytes))
}

/// A GLB container: header, space-padded JSON chunk, zero-padded BIN chunk.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let json = pad(json.as_bytes().to_vec(), b' ');
    let bin = pad(bin.to_vec(), 0);
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// A quad: positions (48 bytes), normals (48), uvs (32), u16 indices (12).
fn quad_buffer() -> Vec<u8> {
    let mut b = f32s(&[-1., -1., 0., 1., -1., 0., 1., 1., 0., -1., 1., 0.]);
    b.extend(f32s(&[0., 0., 1.].repeat(4)));
    b.extend(f32s(&[0., 1., 1., 1., 1., 0., 0., 0.]));
    b.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    b
}

/// The textured quad scene. `buffer` is the buffer's JSON (with or without a uri);
/// `image` is the image's JSON (a data: uri, or bufferView 4 in the GLB).
fn quad_document(buffer: &str, image: &str, png_len: usize) -> String {
    let png_view = if png_len > 0 {
        format!(r#", {{ "buffer": 0, "byteOffset": 140, "byteLength": {png_len} }}"#)
    } else {
        String::new()
    };
    format!(
        r#"{{
  "asset": {{ "version": "2.0", "generator": "prism fuzz seeds" }},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior"],
  "extensions": {{ "KHR_lights_punctual": {{ "lights": [
    {{ "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 20.0, "range": 50 }},
    {{ "type": "directional", "intensity": 2.0 }},
    {{ "type": "spot", "intensity": 5.0, "spot": {{ "innerConeAngle": 0.2, "outerConeAngle": 0.6 }} }}
  ] }} }},
  "scene": 0,
  "scenes": [{{ "nodes": [0, 2, 3, 4, 5] }}],
  "nodes": [
    {{ "name": "parent", "translation": [0.5, 0, -1], "children": [1] }},
    {{ "name": "quad", "mesh": 0, "scale": [2, 1, 1], "rotation": [0, 0.2588190, 0, 0.9659258] }},
    {{ "name": "camera", "camera": 0, "translation": [0, 0, 6] }},
    {{ "name": "lamp", "translation": [0, 3, 3], "extensions": {{ "KHR_lights_punctual": {{ "light": 0 }} }} }},
    {{ "name": "sun", "rotation": [-0.3826834, 0, 0, 0.9238795], "extensions": {{ "KHR_lights_punctual": {{ "light": 1 }} }} }},
    {{ "name": "spot", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,2,4,1], "mesh": 0,
       "extensions": {{ "KHR_lights_punctual": {{ "light": 2 }} }} }}
  ],
  "cameras": [{{ "type": "perspective", "perspective": {{ "yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1 }} }}],
  "meshes": [{{ "name": "Quad", "primitives": [
    {{ "attributes": {{ "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 }}, "indices": 3, "material": 0 }},
    {{ "attributes": {{ "POSITION": 0 }}, "indices": 3, "material": 1 }},
    {{ "attributes": {{ "POSITION": 0, "TEXCOORD_0": 2 }}, "indices": 3, "material": 2 }}
  ] }}],
  "materials": [
    {{ "name": "card", "pbrMetallicRoughness": {{ "baseColorFactor": [0.8, 0.9, 1.0, 1.0],
       "baseColorTexture": {{ "index": 0, "texCoord": 0 }}, "metallicFactor": 0.0, "roughnessFactor": 0.5 }} }},
    {{ "name": "glass", "pbrMetallicRoughness": {{ "metallicFactor": 0.0, "roughnessFactor": 0.0 }},
       "extensions": {{ "KHR_materials_transmission": {{ "transmissionFactor": 1.0 }}, "KHR_materials_ior": {{ "ior": 1.33 }} }} }},
    {{ "name": "gold", "emissiveFactor": [0.1, 0.1, 0], "doubleSided": true, "alphaMode": "MASK",
       "pbrMetallicRoughness": {{ "baseColorFactor": [1.0, 0.8, 0.3, 0.5], "metallicFactor": 1.0, "roughnessFactor": 0.2 }} }}
  ],
  "textures": [{{ "source": 0, "sampler": 0 }}],
  "samplers": [{{ "magFilter": 9728, "wrapS": 33648 }}],
  "images": [{image}],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] }},
    {{ "bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3" }},
    {{ "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2" }},
    {{ "bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR" }}
  ],
  "bufferViews": [
    {{ "buffer": 0, "byteOffset": 0, "byteLength": 48 }},
    {{ "buffer": 0, "byteOffset": 48, "byteLength": 48 }},
    {{ "buffer": 0, "byteOffset": 96, "byteLength": 32 }},
    {{ "buffer": 0, "byteOffset": 128, "byteLength": 12 }}{png_view}
  ],
  "buffers": [{buffer}]
}}
"#
    )
}

/// A strip and a fan over interleaved positions and normalized u16 uvs (stride 16), with
/// u8 indices, a sparse accessor moving one vertex, and an orthographic camera.
fn strip_document() -> String {
    let mut b = Vec::new();
    for (p, uv) in [
        ([0f32, 0., 0.], [0u16, 0]),
        ([1., 0., 0.], [65535, 0]),
        ([0., 1., 0.], [0, 65535]),
        ([1., 1., 0.], [65535, 65535]),
        ([0.5, 2., 0.], [32768, 65535]),
    ] {
        b.extend(f32s(&p));
        b.extend(uv.iter().flat_map(|c| c.to_le_bytes()));
    }
    // 80 bytes of vertices, then indices (u8): strip 0 1 2 3 4, fan 0 1 3 2.
    b.extend([0u8, 1, 2, 3, 4, 0, 1, 3, 2, 0, 0, 0]);
    // Sparse: vertex 4 moves to (0.5, 1.5, 0.25).
    b.extend([4u8, 0, 0, 0]);
    b.extend(f32s(&[0.5, 1.5, 0.25]));
    let uri = data_uri("application/gltf-buffer", &b);
    format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "scenes": [{{ "nodes": [0, 1] }}],
  "nodes": [
    {{ "mesh": 0, "matrix": [2,0,0,0, 0,2,0,0, 0,0,-2,0, 1,0,0,1] }},
    {{ "camera": 0, "translation": [0.5, 0.5, 5] }}
  ],
  "cameras": [{{ "type": "orthographic", "orthographic": {{ "xmag": 2, "ymag": 2, "znear": 0.1, "zfar": 100 }} }}],
  "meshes": [{{ "primitives": [
    {{ "attributes": {{ "POSITION": 0, "TEXCOORD_0": 1 }}, "indices": 2, "mode": 5 }},
    {{ "attributes": {{ "POSITION": 3 }}, "indices": 4, "mode": 6 }},
    {{ "attributes": {{ "POSITION": 0 }}, "mode": 1 }}
  ] }}],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3" }},
    {{ "bufferView": 0, "byteOffset": 12, "componentType": 5123, "normalized": true, "count": 5, "type": "VEC2" }},
    {{ "bufferView": 1, "componentType": 5121, "count": 5, "type": "SCALAR" }},
    {{ "bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3",
       "sparse": {{ "count": 1, "indices": {{ "bufferView": 2, "componentType": 5121 }},
                    "values": {{ "bufferView": 3 }} }} }},
    {{ "bufferView": 1, "byteOffset": 5, "componentType": 5121, "count": 4, "type": "SCALAR" }}
  ],
  "bufferViews": [
    {{ "buffer": 0, "byteOffset": 0, "byteLength": 80, "byteStride": 16 }},
    {{ "buffer": 0, "byteOffset": 80, "byteLength": 12 }},
    {{ "buffer": 0, "byteOffset": 92, "byteLength": 1 }},
    {{ "buffer": 0, "byteOffset": 96, "byteLength": 12 }}
  ],
  "buffers": [{{ "byteLength": {}, "uri": "{uri}" }}]
}}
"#,
        b.len()
    )
}

/// One triangle, no indices, scene, camera, light or material: every default at once.
fn triangle_document(buffer: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}}],"bufferViews":[{{"buffer":0,"byteLength":36}}],"buffers":[{buffer}]}}"#
    )
}

fn triangle_buffer() -> Vec<u8> {
    f32s(&[0., 0., 0., 1., 0., 0., 0., 1., 0.])
}

/// A binary PLY tetrahedron: double positions, a skipped list property on the vertices,
/// ushort-counted int faces with one quad, and a trailing element to step over.
fn binary_ply(big_endian: bool) -> Vec<u8> {
    let order = if big_endian { "big" } else { "little" };
    let mut out = format!(
        "ply\nformat binary_{order}_endian 1.0\nelement vertex 4\nproperty double x\n\
         property double y\nproperty double z\nproperty list uchar short tags\n\
         element face 3\nproperty list ushort int vertex_indices\nelement extra 1\n\
         property float weight\nend_header\n"
    )
    .into_bytes();
    let e = |b: &mut Vec<u8>, le: &[u8]| {
        let mut v = le.to_vec();
        if big_endian {
            v.reverse();
        }
        b.extend(v);
    };
    for p in [[0f64, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
        p.iter().for_each(|c| e(&mut out, &c.to_le_bytes()));
        out.push(1);
        e(&mut out, &7i16.to_le_bytes());
    }
    for face in [&[0i32, 2, 1][..], &[0, 1, 3], &[1, 2, 3, 0]] {
        e(&mut out, &(face.len() as u16).to_le_bytes());
        face.iter().for_each(|i| e(&mut out, &i.to_le_bytes()));
    }
    e(&mut out, &0.5f32.to_le_bytes());
    out
}

fn write(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!("{} ({} bytes)", path.display(), bytes.len());
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let png = std::fs::read(root.join("../scenes/textures/testcard.png")).expect("testcard.png");
    let corpus = root.join("corpus");
    let (gltf, glb_dir) = (corpus.join("gltf"), corpus.join("glb"));
    std::fs::create_dir_all(&gltf).expect("corpus/gltf");
    std::fs::create_dir_all(&glb_dir).expect("corpus/glb");

    let ply = corpus.join("ply");
    std::fs::create_dir_all(&ply).expect("corpus/ply");
    write(&ply.join("binary-le.ply"), &binary_ply(false));
    write(&ply.join("binary-be.ply"), &binary_ply(true));

    let quad = quad_buffer();
    let buffer = format!(
        r#"{{ "byteLength": {}, "uri": "{}" }}"#,
        quad.len(),
        data_uri("application/octet-stream", &quad)
    );
    let image = format!(r#"{{ "uri": "{}" }}"#, data_uri("image/png", &png));
    write(
        &gltf.join("quad.gltf"),
        quad_document(&buffer, &image, 0).as_bytes(),
    );
    write(&gltf.join("strip.gltf"), strip_document().as_bytes());
    let tri = triangle_buffer();
    let tri_buffer = format!(
        r#"{{"byteLength":36,"uri":"{}"}}"#,
        data_uri("application/octet-stream", &tri)
    );
    write(
        &gltf.join("triangle.gltf"),
        triangle_document(&tri_buffer).as_bytes(),
    );

    let mut bin = quad.clone();
    bin.extend(&png);
    let doc = quad_document(
        &format!(r#"{{ "byteLength": {} }}"#, bin.len()),
        r#"{ "bufferView": 4, "mimeType": "image/png" }"#,
        png.len(),
    );
    write(&glb_dir.join("quad.glb"), &glb(&doc, &bin));
    write(
        &glb_dir.join("triangle.glb"),
        &glb(&triangle_document(r#"{"byteLength":36}"#), &tri),
    );
}
