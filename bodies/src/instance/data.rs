//! The data of one instance, everything an FMU state holds (FMI mode, time, parameters,
//! inputs, the body), and how the physics sees it (parameters, and the load summed from the
//! own inputs and the ports'). Uses
//! `crate::variables` (slots, start values) and `crate::physics`'s types.

use crate::physics::{ports, Body, Dof, Load, Model, Params, Port, PORTS};
use crate::variables::{int, real, start_values};

/// The FMI state of an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// after Instantiate (and Reset)
    Instantiated,
    /// between EnterInitializationMode and ExitInitializationMode
    Initialization,
    /// Step Mode (FMI 2.0: slaveInitialized)
    Step,
    /// after Terminate
    Terminated,
}

impl Mode {
    /// The state as messages name it.
    pub(crate) fn text(self) -> &'static str {
        match self {
            Mode::Instantiated => "the Instantiated state",
            Mode::Initialization => "Initialization Mode",
            Mode::Step => "Step Mode",
            Mode::Terminated => "the Terminated state",
        }
    }

    /// The byte of the serialized state.
    pub(crate) fn to_byte(self) -> u8 {
        self as u8
    }

    /// The mode of a serialized byte.
    pub(crate) fn from_byte(b: u8) -> Option<Mode> {
        [
            Mode::Instantiated,
            Mode::Initialization,
            Mode::Step,
            Mode::Terminated,
        ]
        .get(usize::from(b))
        .copied()
    }
}

/// Everything an FMU state holds: mode, time, parameters, inputs and the body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Data {
    /// FMI state
    pub mode: Mode,
    /// the FMU's time (s)
    pub time: f64,
    /// the start time (s)
    pub start_time: f64,
    /// Real parameters and inputs, by `variables::real` slot
    pub reals: [f64; real::N],
    /// Integer parameters, by `variables::int` slot
    pub ints: [i32; int::N],
    /// the body at `time` (from ExitInitializationMode on)
    pub body: Body,
}

impl Data {
    /// The data of a new (or reset) instance: start values, time 0.
    pub(crate) fn new() -> Self {
        let (reals, ints) = start_values();
        Data {
            mode: Mode::Instantiated,
            time: 0.0,
            start_time: 0.0,
            reals,
            ints,
            body: Body::default(),
        }
    }

    /// The parameters as the physics takes them.
    pub fn params(&self) -> Params {
        use real::*;
        let r = &self.reals;
        let v3 = |i: usize| [r[i], r[i + 1], r[i + 2]];
        let dof = |i: usize| match self.ints[i] {
            0 => Dof::Fixed,
            1 => Dof::Free,
            _ => Dof::Prescribed,
        };
        Params {
            mass: r[MASS],
            inertia: v3(INERTIA),
            gravity: v3(GRAVITY),
            model: if self.ints[int::MODEL] == 1 {
                Model::Rigid
            } else {
                Model::Axes
            },
            dof_r: [0, 1, 2].map(|i| dof(int::DOF_R + i)),
            dof_w: [0, 1, 2].map(|i| dof(int::DOF_W + i)),
            spring: v3(SPRING),
            start_r: v3(START_R),
            start_q: [r[START_Q], r[START_Q + 1], r[START_Q + 2], r[START_Q + 3]],
            start_v: v3(START_V),
            start_w: v3(START_W),
            max_turn: r[MAX_TURN],
            ports: std::array::from_fn(|k| {
                let s = PORT + k * PORT_LEN;
                Port {
                    offset_r: v3(s + PORT_OFFSET_R),
                    offset_q: std::array::from_fn(|i| r[s + PORT_OFFSET_Q + i]),
                }
            }),
        }
    }

    /// The load held over the next step from the body at its start: the own inputs `f`, `m`
    /// and every port's, summed about the centre of mass (`physics::ports::total`).
    pub(crate) fn load(&self, p: &Params) -> Load {
        let r = &self.reals;
        let v3 = |i: usize| [r[i], r[i + 1], r[i + 2]];
        let own = Load {
            f: v3(real::F),
            m: v3(real::M),
        };
        let port_loads: [Load; PORTS] = std::array::from_fn(|k| {
            let s = real::PORT + k * real::PORT_LEN;
            Load {
                f: v3(s + real::PORT_F),
                m: v3(s + real::PORT_M),
            }
        });
        ports::total(&self.body, &p.ports, &own, &port_loads)
    }
}
