//! The access rules, on top of the variable table (`variables`) and the data (`snapshot`): what
//! a value reference reads or writes in the parameters, the node inputs and the outputs, with
//! the table's checks; the snapshot a variant starts from (its table's start values); the raw
//! node inputs as physics nodes and back. Uses `variables`, `snapshot` and physics; neither of
//! those uses it.

use super::cache::OutputCache;
use super::snapshot::{LastEvent, Mode, Snapshot};
use super::variables::{
    Causality, CompOut, CompPar, Field, FrictionField, NodeInputs, ScalarPar, Start, Table,
    VarSpec, NODE_INPUTS, POSE_TWIST,
};
use crate::error::{FmuError, FmuResult};
use crate::physics::connector::{Extrapolation, Outputs, Params, State};
use crate::physics::kinematics::Node;
use crate::physics::math::{quat_from_wxyz, Real, Scalar, Vec3};

/// FMI base types, for the type check of get/set calls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// fmi2Real
    Real,
    /// fmi2Integer
    Integer,
    /// fmi2Boolean
    Boolean,
}

impl Ty {
    /// The type of a variable from its start.
    pub fn of(s: &Start) -> Ty {
        match s {
            Start::Real(_) => Ty::Real,
            Start::Integer(_) => Ty::Integer,
            Start::Boolean(_) => Ty::Boolean,
        }
    }
}

/// The snapshot a variant starts from: the start values of its table written through the
/// access rules, nodes at the origin with identity orientation, in `Mode::Instantiated`.
pub fn initial_snapshot(t: &Table) -> Snapshot {
    let mut params = Params::default();
    let mut inputs = [[0.0; NODE_INPUTS]; 2];
    for v in &t.vars {
        if let Start::Real(Some(x)) = v.start {
            let _ = write_real(&mut params, &mut inputs, v, x);
        }
        if let Start::Integer(Some(x)) = v.start {
            let _ = write_int(&mut params, v, x);
        }
    }
    // nodes rest at the origin with identity orientation until inputs say otherwise
    inputs[0][3] = 1.0;
    inputs[1][3] = 1.0;
    Snapshot {
        variant: t.spec.variant,
        mode: Mode::Instantiated,
        time: 0.0,
        start_time: 0.0,
        params,
        inputs,
        input_der: [[0.0; POSE_TWIST]; 2],
        input_der_set: [[false; POSE_TWIST]; 2],
        state: State::default(),
        event: LastEvent {
            time: 0.0,
            count: 0,
        },
        history: None,
        events: None,
        outputs: OutputCache::new(),
    }
}

/// The nodes from raw inputs (quaternions normalised; a bad one is refused).
pub fn nodes_of(inputs: &[NodeInputs; 2]) -> FmuResult<(Node, Node)> {
    let mut out = [Node::default(); 2];
    nodes_into(inputs, &mut out)?;
    Ok((out[0], out[1]))
}

/// `nodes_of` written into `out` (the per-step path: no copy out of a result).
#[inline]
pub fn nodes_into(inputs: &[NodeInputs; 2], out: &mut [Node; 2]) -> FmuResult<()> {
    for (n, node) in out.iter_mut().enumerate() {
        let u = &inputs[n];
        let q = quat_from_wxyz(u[3], u[4], u[5], u[6]).ok_or_else(|| {
                let nm = ["a", "b"][n];
                FmuError::error(format!(
                    "orientation {nm}.q = ({:?}, {:?}, {:?}, {:?}) is not a rotation: its norm is below 1e-6 or not finite",
                    u[3], u[4], u[5], u[6]
                ))
            })?;
        *node = Node {
            r: Vec3::new(u[0], u[1], u[2]),
            q,
            v: Vec3::new(u[7], u[8], u[9]),
            w: Vec3::new(u[10], u[11], u[12]),
        };
    }
    Ok(())
}

/// Writes an extrapolated node back into the inputs (its pose and twist; the acceleration
/// inputs keep their values).
pub fn write_node(u: &mut NodeInputs, n: &Node) {
    let q = n.q.quaternion();
    u[..POSE_TWIST].copy_from_slice(&[
        n.r.x, n.r.y, n.r.z, q.w, q.i, q.j, q.k, n.v.x, n.v.y, n.v.z, n.w.x, n.w.y, n.w.z,
    ]);
}

/// The node loads side by side, indexed by `RealSlot::Load`: fa, ma, fb, mb.
#[inline]
pub fn node_loads(o: &Outputs) -> [Real; 12] {
    let (fa, ma, fb, mb) = (o.fa, o.ma, o.fb, o.mb);
    [
        fa.x, fa.y, fa.z, ma.x, ma.y, ma.z, fb.x, fb.y, fb.z, mb.x, mb.y, mb.z,
    ]
}

/// Whether `x` may be stored in `v`, from the variable's row alone (the one place ranges are
/// checked: the setters, the start values and a decoded FMU state all come through here):
/// never NaN; infinite only where the row's start is infinite (a stop limit that is not set,
/// no force cap); within the row's `[min, max]`. Relations between parameters (lower stop ≤
/// upper stop, μ_k ≤ μ_s) are the physics' (`Params::check`).
pub fn check_real(v: &VarSpec, x: Real) -> Result<(), String> {
    let infinite_start = matches!(v.start, Start::Real(Some(s)) if s.is_infinite());
    if x.is_nan() || (x.is_infinite() && !infinite_start) {
        return Err("is not finite".to_string());
    }
    check_range(v, x)
}

/// `x` within the row's `[min, max]` (FMI's inclusive bounds; the smallest positive double as
/// the minimum means "> 0").
fn check_range(v: &VarSpec, x: Real) -> Result<(), String> {
    match (v.min, v.max) {
        (Some(min), _) if x < min && min == Real::from_bits(1) => Err("must be > 0".to_string()),
        (Some(min), _) if x < min => Err(format!("must be ≥ {min:?}")),
        (_, Some(max)) if x > max => Err(format!("must be ≤ {max:?}")),
        _ => Ok(()),
    }
}

/// Writes a Real value into parameters or inputs after checking it against its row.
pub fn write_real(
    p: &mut Params,
    u: &mut [NodeInputs; 2],
    v: &VarSpec,
    x: Real,
) -> Result<(), String> {
    check_real(v, x)?;
    match v.field {
        Field::Input { node, idx } => u[node as usize][idx as usize] = x,
        Field::CompParam { par, k } => {
            let k = k as usize;
            match par {
                CompPar::Stiffness => p.k[k] = x,
                CompPar::Damping => p.c[k] = x,
                CompPar::RefValue => p.ref_value[k] = x,
                CompPar::StopLower => p.stop_lower[k] = x,
                CompPar::StopUpper => p.stop_upper[k] = x,
                CompPar::RefGiven => return Err("is not a Real".to_string()),
            }
        }
        Field::Param(s) => {
            use ScalarPar::*;
            let fr = &mut p.friction;
            match s {
                StopK => p.stop.k = x,
                StopC => p.stop.c = x,
                StopKr => p.stop.k_rot = x,
                StopCr => p.stop.c_rot = x,
                ConK => p.constraint.k = x,
                ConC => p.constraint.c = x,
                ConKr => p.constraint.k_rot = x,
                ConCr => p.constraint.c_rot = x,
                MuS => fr.mu_static = x,
                MuK => fr.mu_kinetic = x,
                Decay => fr.decay = x,
                Radius => fr.radius = x,
                Fint => fr.f_int = x,
                Mint => fr.m_int = x,
                StickK => fr.k_stick = x,
                StickKr => fr.k_stick_r1 = x,
                StickC => fr.c_stick = x,
                StickCr => fr.c_stick_r1 = x,
                MaxForce => fr.max_force = x,
                MaxSubstep => p.max_substep = x,
                Coupling | Extrapolation => return Err("is not a Real".to_string()),
            }
        }
        _ => return Err("cannot be set".to_string()),
    }
    Ok(())
}

/// Writes an Integer parameter after checking it against its row's `[min, max]`.
pub fn write_int(p: &mut Params, v: &VarSpec, x: i32) -> Result<(), String> {
    check_range(v, Real::from(x))?;
    match v.field {
        Field::Param(ScalarPar::Coupling) => p.friction.coupling = x,
        Field::Param(ScalarPar::Extrapolation) => {
            p.extrapolation = match x {
                0 => Extrapolation::Hold,
                1 => Extrapolation::Linear,
                2 => Extrapolation::Quadratic,
                _ => Extrapolation::Accelerations,
            }
        }
        _ => return Err("is not an Integer".to_string()),
    }
    Ok(())
}

/// A Real parameter's value.
pub fn read_real_param(p: &Params, f: Field) -> Real {
    use ScalarPar::*;
    let fr = &p.friction;
    match f {
        Field::CompParam { par, k } => {
            let k = k as usize;
            match par {
                CompPar::Stiffness => p.k[k],
                CompPar::Damping => p.c[k],
                CompPar::RefValue => p.ref_value[k],
                CompPar::StopLower => p.stop_lower[k],
                CompPar::StopUpper => p.stop_upper[k],
                CompPar::RefGiven => 0.0,
            }
        }
        Field::Param(s) => match s {
            StopK => p.stop.k,
            StopC => p.stop.c,
            StopKr => p.stop.k_rot,
            StopCr => p.stop.c_rot,
            ConK => p.constraint.k,
            ConC => p.constraint.c,
            ConKr => p.constraint.k_rot,
            ConCr => p.constraint.c_rot,
            MuS => fr.mu_static,
            MuK => fr.mu_kinetic,
            Decay => fr.decay,
            Radius => fr.radius,
            Fint => fr.f_int,
            Mint => fr.m_int,
            StickK => fr.k_stick,
            StickKr => fr.k_stick_r1,
            StickC => fr.c_stick,
            StickCr => fr.c_stick_r1,
            MaxForce => fr.max_force,
            MaxSubstep => p.max_substep,
            Coupling | Extrapolation => 0.0,
        },
        _ => 0.0,
    }
}

/// An Integer parameter's value.
pub fn read_int_param(p: &Params, f: Field) -> i32 {
    match f {
        Field::Param(ScalarPar::Coupling) => p.friction.coupling,
        Field::Param(ScalarPar::Extrapolation) => match p.extrapolation {
            Extrapolation::Hold => 0,
            Extrapolation::Linear => 1,
            Extrapolation::Quadratic => 2,
            Extrapolation::Accelerations => 3,
        },
        _ => 0,
    }
}

/// Node load 3·which + i: fa, ma, fb, mb.
#[inline]
fn load<T: Scalar>(o: &Outputs<T>, j: u8) -> T {
    let v = match j / 3 {
        0 => &o.fa,
        1 => &o.ma,
        2 => &o.fb,
        _ => &o.mb,
    };
    v[(j % 3) as usize]
}

/// A Real output's value.
pub fn read_output<T: Scalar>(o: &Outputs<T>, f: Field) -> T {
    match f {
        Field::Load { which, i } => load(o, 3 * which + i),
        Field::Comp { out, k } => {
            let k = k as usize;
            match out {
                CompOut::Position => o.cp[k],
                CompOut::Motion => o.cu[k],
                CompOut::Velocity => o.cv[k],
                CompOut::Total => o.ctf[k],
                CompOut::Elastic => o.cef[k],
                CompOut::Viscous => o.cvf[k],
                CompOut::Friction => o.csf[k],
                CompOut::Reaction => o.crf[k],
            }
        }
        Field::Friction(ff) => {
            let fr = &o.friction;
            match ff {
                FrictionField::Cnf => fr.cnf,
                FrictionField::Cnm1 => fr.cnm1,
                FrictionField::Csfc => fr.csfc,
                FrictionField::Csmc1 => fr.csmc1,
                FrictionField::Slip => fr.slip,
                FrictionField::SlipR1 => fr.slip_r1,
                FrictionField::Status => T::cst(fr.status as i32 as Real),
                FrictionField::StatusR1 => T::cst(fr.status_r1 as i32 as Real),
            }
        }
        Field::Energy(i) => {
            let e = &o.energy;
            [e.stored, e.damping, e.friction, e.stops][i as usize]
        }
        Field::Event(0) => T::cst(o.event_time),
        Field::Event(_) => T::cst(o.event_count as Real),
        _ => T::zero(),
    }
}

/// How many continuous Real outputs there can be: the node loads, the eight per-component
/// outputs, the PLANAR friction outputs, the energies (`continuous_row`).
pub const CONTINUOUS_LEN: usize = 12 + 8 * 6 + 6 + 4;

/// Where a continuous Real output stands in `continuous_row`; None for any other field.
pub fn continuous_index(f: Field) -> Option<u8> {
    let comp = |out: CompOut| match out {
        CompOut::Position => 0,
        CompOut::Motion => 1,
        CompOut::Velocity => 2,
        CompOut::Total => 3,
        CompOut::Elastic => 4,
        CompOut::Viscous => 5,
        CompOut::Friction => 6,
        CompOut::Reaction => 7,
    };
    match f {
        Field::Load { which, i } => Some(3 * which + i),
        Field::Comp { out, k } => Some(12 + 6 * comp(out) + k),
        Field::Friction(ff) => match ff {
            FrictionField::Cnf => Some(60),
            FrictionField::Cnm1 => Some(61),
            FrictionField::Csfc => Some(62),
            FrictionField::Csmc1 => Some(63),
            FrictionField::Slip => Some(64),
            FrictionField::SlipR1 => Some(65),
            FrictionField::Status | FrictionField::StatusR1 => None,
        },
        Field::Energy(i) => Some(66 + i),
        _ => None,
    }
}

/// Every continuous Real output in one row, at `continuous_index` (the directional
/// derivatives read the unknowns from it: one copy instead of a match per unknown).
#[inline(always)]
pub fn continuous_row<T: Scalar>(o: &Outputs<T>) -> [T; CONTINUOUS_LEN] {
    continuous_row_map(o, |x| x)
}

/// `continuous_row` with `f` applied to every value, written straight into the row (a
/// directional derivative takes the derivatives of the `Dual` outputs, scaled: no row of duals
/// and no copies of the outputs' arrays on the way).
#[inline(always)]
pub fn continuous_row_map<T: Scalar, U: Copy>(
    o: &Outputs<T>,
    f: impl Fn(T) -> U,
) -> [U; CONTINUOUS_LEN] {
    let mut row = [f(T::zero()); CONTINUOUS_LEN];
    let mut put = |at: usize, xs: &[T]| {
        for (r, &x) in row[at..at + xs.len()].iter_mut().zip(xs) {
            *r = f(x);
        }
    };
    for (j, v) in [&o.fa, &o.ma, &o.fb, &o.mb].into_iter().enumerate() {
        put(3 * j, v.as_slice());
    }
    let comps = [&o.cp, &o.cu, &o.cv, &o.ctf, &o.cef, &o.cvf, &o.csf, &o.crf];
    for (j, c) in comps.into_iter().enumerate() {
        put(12 + 6 * j, c);
    }
    let (fr, e) = (&o.friction, &o.energy);
    put(
        60,
        &[
            fr.cnf, fr.cnm1, fr.csfc, fr.csmc1, fr.slip, fr.slip_r1, e.stored, e.damping,
            e.friction, e.stops,
        ],
    );
    row
}

/// What made outputs non-finite, in words: the first Real output of the table that is not
/// finite, and the node input of largest magnitude (the usual cause: a position or velocity so
/// large that a force, an energy or a dissipation power overflows). Off the per-step path.
#[cold]
#[inline(never)]
pub fn non_finite_cause(t: &Table, o: &Outputs, inputs: &[NodeInputs; 2]) -> String {
    let output = t
        .vars
        .iter()
        .filter(|v| v.causality == Causality::Output && Ty::of(&v.start) == Ty::Real)
        .map(|v| (v, read_output(o, v.field)))
        .find(|(_, x)| !x.is_finite());
    let input = t
        .vars
        .iter()
        .filter_map(|v| match v.field {
            Field::Input { node, idx } => Some((v, inputs[node as usize][idx as usize])),
            _ => None,
        })
        .max_by(|(_, x), (_, y)| x.abs().total_cmp(&y.abs()));
    let output = match output {
        Some((v, x)) => format!("output {} would be {x:?}, not finite", v.name),
        None => "an output would not be finite".to_string(),
    };
    match input {
        Some((v, x)) => format!("{output} (largest input: {} = {x:e})", v.name),
        None => output,
    }
}
