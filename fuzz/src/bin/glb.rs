//! The `glb` fuzz target (see prism_fuzz::targets::glb).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::glb);
}
