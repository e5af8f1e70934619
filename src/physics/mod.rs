//! Pure connector physics: plain data in, plain data out, no FMI types, no allocation.

pub mod kinematics;
pub mod math;
