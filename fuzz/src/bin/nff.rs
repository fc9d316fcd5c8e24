//! The `nff` fuzz target (see prism_fuzz::targets::nff).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::nff);
}
