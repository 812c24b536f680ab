//! What a run measures: the integrals' error series (the integrals are the model's,
//! `model::integral`) and the hidden latitude ([`latitude`]), downsampled into buckets
//! ([`bucket`]) and classified ([`classify`]), the driver that runs a method and streams the series to an observer
//! ([`simulate`]), the measured properties of a method ([`properties`]), the reference
//! solution ([`reference`]) and work–precision ([`work_precision`]).

pub mod bucket;
pub mod classify;
pub mod gap;
pub mod latitude;
pub mod properties;
pub mod reference;
pub mod simulate;
pub mod work_precision;
