//! Measuring acceleration structures on a fixed workload: the same primary and shadow rays
//! for every method (`rays`), then build time, memory, traversal work per ray and ray
//! throughput for each (`measure`). `prism bench` runs these over scenes × methods.

mod clock;
mod digest;
mod measure;
mod rays;
mod shadows;

pub use clock::{Clock, Stopwatch};
pub use digest::HitDigest;
pub use measure::{measure_all, measure_all_expecting, MeasureOptions, Measured, RayKindResult};
pub use rays::{RaySet, RaySetSize, ShadowRay};
pub use shadows::{measure_shadow_methods, ShadowMeasured};
