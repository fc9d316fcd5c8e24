//! How surfaces respond to light: the Whitted material, Fresnel reflectance, the optics of
//! mirror reflection and Snell refraction, textures for the diffuse colour, glTF's
//! metallic-roughness inputs, and `Bsdf`, the path tracer's lobes built from a material's
//! coefficients at a hit.

mod bsdf;
mod coefficients;
pub mod fresnel;
mod material;
pub mod normal_map;
pub mod optics;
mod pbr;
mod texture;

pub(crate) use bsdf::DiffuseLobe;
pub use bsdf::{Bsdf, BsdfSample, MaterialLobes};
pub use coefficients::{Coefficients, SpecularWeights};
pub use fresnel::FresnelMode;
pub use material::{Highlight, Material};
pub use normal_map::{BumpMap, NormalMap};
pub use pbr::{MetalRough, Pbr};
pub use texture::{Checker, CheckerSpace, ImageTexture, Texture};
