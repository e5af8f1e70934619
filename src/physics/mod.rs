//! Pure connector physics: plain data in, plain data out, no FMI types, no allocation.

pub mod connector;
pub mod disc;
pub mod events;
pub mod friction;
pub mod init;
pub mod kinematics;
pub mod math;
pub mod step;
