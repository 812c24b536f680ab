//! The test systems of MATH.md §2, one file each. Register a new one in [`crate::registry`].

mod cvt;
mod cvt_pendulum;
mod knife_edge;
mod mobile_robot;
mod particle;
mod rolling_disk;

pub use cvt::Cvt;
pub use cvt_pendulum::CvtPendulum;
pub use knife_edge::KnifeEdge;
pub use mobile_robot::MobileRobot;
pub use particle::Particle;
pub use rolling_disk::RollingDisk;
