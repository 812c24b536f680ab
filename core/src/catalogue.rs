//! The catalogue: the registry of systems, sizes erased ([`registry`]), systems given as
//! formulas compiled for a scene ([`custom`]), scenes — what a user asks for, resolved against
//! a system's presets and checked field by field ([`scene`]) — work–precision measured on
//! a scene ([`work_precision`]), and what a run will cost, estimated before it starts
//! ([`cost`]).

pub mod cost;
pub mod custom;
pub mod registry;
pub mod scene;
pub mod work_precision;
