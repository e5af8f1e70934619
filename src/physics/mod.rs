//! Pure connector physics: plain data in, plain data out, no FMI types, no allocation.
//!
//! The parts, each using only those before it (the layout test checks that no two files use
//! each other): `math` (Real, Dual, rotations); `kinematics` (the connection types' component
//! positions and gradients); `disc` (the uniform disc's friction direction); `friction` (the
//! PLANAR friction law, uses disc); `connector` (behaviours, forces, node loads, energy, uses
//! kinematics and friction); `events` (the event functions and their location), `init` (the state
//! at the end of initialization) and `step` (a communication step along the input path, uses
//! events), all on connector. Nothing here uses the model, the instance or the FMI boundaries.

pub mod connector;
pub mod disc;
pub mod events;
pub mod friction;
pub mod init;
pub mod kinematics;
pub mod math;
pub mod step;
