//! How surfaces respond to light: the Whitted material, Fresnel reflectance, the optics of
//! mirror reflection and Snell refraction, textures for the diffuse colour, and `Bsdf`,
//! the path tracer's lobes built from a material.

mod bsdf;
pub mod fresnel;
mod material;
pub mod normal_map;
pub mod optics;
mod texture;

pub use bsdf::{Bsdf, BsdfSample};
pub use fresnel::FresnelMode;
pub use material::{Highlight, Material, SpecularWeights};
pub use normal_map::NormalMap;
pub use texture::{Checker, CheckerSpace, ImageTexture, Texture};
