//! The `obj` fuzz target (see prism_fuzz::targets::obj).

fn main() {
    prism_fuzz::run(prism_fuzz::targets::obj);
}
