//! prism-lab: the tools that measure the prism engine rather than use it. [`bench`](mod@bench)
//! times the acceleration and shadow methods on a fixed workload and holds each to the
//! reference answers; [`meshes`] makes the procedural meshes the comparisons share;
//! [`metrics`] says how far one image is from another (RMSE, PSNR, SSIM, FLIP);
//! [`reference`](mod@reference) computes exact images (the box-filtered checkerboard) to
//! measure sampling error against.

pub mod bench;
pub mod meshes;
pub mod metrics;
pub mod reference;
