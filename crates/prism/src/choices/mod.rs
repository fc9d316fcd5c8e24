//! The choices a render offers, as plain data: for each, its names and its table of keys,
//! from which parsing, printing, help texts and the documentation checks follow. Samplers,
//! filters, integrators, shadow methods and the output transfer are declared here; the
//! accelerators declare their list in `accel` with the same `method_list!`. What a choice
//! does lives with its kind of method (the patterns in `sampling`, the integrators in
//! `integrator`, the passes in `render`), so this module sits below all of them and
//! `options::RenderOptions`, made of these specs, imports nothing that imports it back.

#[macro_use]
mod kinds;
mod keys;
#[macro_use]
mod methods;

pub mod filter;
pub mod integrator;
pub mod sampler;
pub mod shadows;

pub use filter::{FilterKind, MAX_FILTER_RADIUS};
pub use integrator::{IntegratorKind, Strategy};
pub use keys::{
    help_text, markdown, method_doc, parse_params, write_spec, Accepts, Key, KeyDoc, Keyed,
    MethodDoc, Value,
};
pub use sampler::{AdaptiveRule, AdaptiveSpec, SamplerKind};
pub use shadows::{ShadowMethod, ShadowSpec};

/// What pixel values mean: defined with the conversions it chooses between.
pub use crate::transfer::Transfer;

/// For the `serde_as_text!` macro's expansions in other crates.
#[doc(hidden)]
pub use serde;
