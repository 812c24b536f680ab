//! What a run measures: the integrals' error series (the integrals are the model's,
//! `model::integral`) and the hidden latitude ([`latitude`]), downsampled into buckets
//! ([`bucket`]) and classified ([`classify`]); the driver that runs a method and streams the
//! series to an observer ([`simulate`]), taking whole turns off an angle as it goes, and
//! looking at the clock as often as its steps' cost allows ([`pace`]); the
//! measured properties of a method ([`properties`]) and the reference solution
//! ([`reference`]). Work–precision, which measures scenes, is the catalogue's.

pub mod bucket;
pub mod classify;
pub mod gap;
pub mod latitude;
pub mod observables;
pub mod pace;
pub mod properties;
pub mod reference;
pub mod section;
pub mod simulate;
mod whole_turns;
