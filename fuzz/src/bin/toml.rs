//! The `toml` fuzz target (see prism_fuzz::targets::toml).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::toml);
}
