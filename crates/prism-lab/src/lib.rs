//! prism-lab: the tools that measure the prism engine rather than use it. [`bench`](mod@bench)
//! times
//! the acceleration and shadow methods on a fixed workload and holds each to the reference
//! answers; [`metrics`] says how far one image is from another (RMSE, PSNR, SSIM, FLIP);
//! [`reference`](mod@reference) computes exact images (the box-filtered checkerboard) to measure
//! sampling
//! error against.

pub mod bench;
pub mod metrics;
pub mod reference;
