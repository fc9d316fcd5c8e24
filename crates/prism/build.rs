//! Tells the engine's tests which SIMD kernels the building machine can run, so that a
//! test of a kernel this CPU lacks shows as ignored, with the reason, in the test runner's
//! count (the tests also check at run time and pass without work there).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-check-cfg=cfg(prism_host_avx2)");
    println!("cargo:rustc-check-cfg=cfg(prism_host_avx512)");
    #[cfg(target_arch = "x86_64")]
    {
        // The 8-wide kernels' own condition (`simd8::available`).
        if std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("popcnt")
        {
            println!("cargo:rustc-cfg=prism_host_avx2");
        }
        // The sixteen-lane kernels' (`simd8::avx512_available`).
        if std::arch::is_x86_feature_detected!("avx512f") {
            println!("cargo:rustc-cfg=prism_host_avx512");
        }
    }
}
