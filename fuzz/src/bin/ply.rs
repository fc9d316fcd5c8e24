//! The `ply` fuzz target (see prism_fuzz::targets::ply).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::ply);
}
