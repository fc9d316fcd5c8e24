//! How surfaces respond to light: the Whitted material, Fresnel reflectance, the optics of
//! mirror reflection and Snell refraction, and textures for the diffuse colour.

pub mod fresnel;
mod material;
pub mod optics;
mod texture;

pub use fresnel::FresnelMode;
pub use material::{Highlight, Material, SpecularWeights};
pub use texture::{Checker, CheckerSpace, ImageTexture, Texture};
