//! The `gltf` fuzz target (see prism_fuzz::targets::gltf).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::gltf);
}
