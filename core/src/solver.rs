//! Solver kernels shared by the implicit methods: Newton's iteration on the saddle systems
//! of the steps ([`newton`]), double-double arithmetic,
//! the tracking of sin ζ and cos ζ along Newton's iterates, the passenger's kernel, and the
//! reduced ODE that Dop853 solves ([`reduced_ode`]).

pub(crate) mod angle_tracker;
pub(crate) mod double_double;
pub mod newton;
pub(crate) mod passenger_kernel;
pub mod reduced_ode;
