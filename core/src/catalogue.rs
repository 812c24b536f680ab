//! The catalogue: the registry of systems, sizes erased ([`registry`]), and scenes — what a
//! user asks for, resolved against a system's presets and checked field by field
//! ([`scene`]).

pub mod custom;
pub mod registry;
pub mod scene;
