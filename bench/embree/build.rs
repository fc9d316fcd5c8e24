//! Compiles the C shim over Embree 3 and links the system library (Debian's libembree-dev).

fn main() {
    println!("cargo:rerun-if-changed=src/shim.c");
    cc::Build::new()
        .file("src/shim.c")
        .opt_level(2)
        .warnings(true)
        .compile("embree_shim");
    println!("cargo:rustc-link-lib=embree3");
}
