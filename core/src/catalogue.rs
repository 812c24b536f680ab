//! The catalogue: the registry of systems, sizes erased ([`registry`]), systems given as
//! formulas compiled for a scene ([`custom`]), scenes — what a user asks for, resolved against
//! a system's presets and checked field by field ([`scene`]) — and work–precision measured on
//! a scene ([`work_precision`]).

pub mod custom;
pub mod registry;
pub mod scene;
pub mod work_precision;
