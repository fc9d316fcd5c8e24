//! The `mtl` fuzz target (see prism_fuzz::targets::mtl).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::mtl);
}
