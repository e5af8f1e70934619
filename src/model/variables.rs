//! THE variable table: every variable of every variant is one row of `ROWS`, with its value
//! reference written out, name, storage slot (`Field`), causality, variability, type, start,
//! unit and range (min, max). The model descriptions (`modelDescription/<Variant>.xml`), the
//! get/set dispatch, the allowed-set checks and the start values all come from here.
//!
//! A variant composes a translational and a rotational part (`ConnectionType`); its table is
//! the rows its type uses (`present`), each described for the role the type gives the row's
//! component slot (`describe`: RADIAL-THRUST's CP1 is the radial distance r, Bushing's CPR1
//! the flexion angle α1), so a new pairing costs one `VARIANTS` entry.
//!
//! Value references are stable across variants: the same variable has the same VR everywhere.
//! The `Causality` and `Variability` enums are `fmi_shared`'s (the Body FMU's table uses them
//! too).

use crate::physics::kinematics::{ConnectionType, Role, Rotational, Translational};
use crate::physics::math::Real;
use std::sync::OnceLock;

/// Node inputs as set (raw, before normalisation), in the order of `Field::Input`'s `idx`:
/// r(3), q(4: w x y z), v(3), ω(3), and the accelerations v̇(3), ω̇(3) that
/// `cosim.extrapolation = 3` moves the node along.
pub type NodeInputs = [Real; NODE_INPUTS];
/// How many inputs a node has.
pub const NODE_INPUTS: usize = 19;
/// The node's pose and twist: the first 13 inputs (what the outputs depend on; the ones with
/// input derivatives).
pub const POSE_TWIST: usize = 13;
/// The pose and twist of a node, or their input derivatives.
pub type PoseTwist = [Real; POSE_TWIST];

/// The five packaged variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// PLANAR = SLIDE-PLANE + REVOLUTE, with predefined friction.
    Planar,
    /// PROJECTION CARTESIAN.
    ProjectionCartesian,
    /// PROJECTION FLEXION-TORSION.
    ProjectionFlexionTorsion,
    /// PROJECTION CARTESIAN + PROJECTION FLEXION-TORSION.
    Bushing,
    /// RADIAL-THRUST.
    RadialThrust,
}

/// One variant: model identifier, connection type, description.
#[derive(Clone, Copy, Debug)]
pub struct VariantSpec {
    /// The variant.
    pub variant: Variant,
    /// modelIdentifier (also the binary's file name).
    pub model_identifier: &'static str,
    /// Connection type composed from a translational and a rotational part.
    pub connection: ConnectionType,
    /// One line for the model description.
    pub description: &'static str,
}

/// The variants, in packaging order.
pub const VARIANTS: [VariantSpec; 5] = [
    VariantSpec {
        variant: Variant::Planar,
        model_identifier: "Planar",
        connection: ConnectionType {
            trans: Translational::SlidePlane,
            rot: Rotational::Revolute,
        },
        description: "Abaqus PLANAR connector (SLIDE-PLANE + REVOLUTE) with penalty constraints, stops and predefined friction",
    },
    VariantSpec {
        variant: Variant::ProjectionCartesian,
        model_identifier: "ProjectionCartesian",
        connection: ConnectionType {
            trans: Translational::ProjectionCartesian,
            rot: Rotational::None,
        },
        description: "Abaqus PROJECTION CARTESIAN connector on the centred projection triad",
    },
    VariantSpec {
        variant: Variant::ProjectionFlexionTorsion,
        model_identifier: "ProjectionFlexionTorsion",
        connection: ConnectionType {
            trans: Translational::None,
            rot: Rotational::ProjectionFlexionTorsion,
        },
        description: "Abaqus PROJECTION FLEXION-TORSION connector (flexion angles α1, α2, torsion β)",
    },
    VariantSpec {
        variant: Variant::Bushing,
        model_identifier: "Bushing",
        connection: ConnectionType {
            trans: Translational::ProjectionCartesian,
            rot: Rotational::ProjectionFlexionTorsion,
        },
        description: "Bushing: Abaqus PROJECTION CARTESIAN + PROJECTION FLEXION-TORSION on one centred triad",
    },
    VariantSpec {
        variant: Variant::RadialThrust,
        model_identifier: "RadialThrust",
        connection: ConnectionType {
            trans: Translational::RadialThrust,
            rot: Rotational::None,
        },
        description: "Abaqus RADIAL-THRUST connector (radial r and thrust l about e3 of node a)",
    },
];

impl Variant {
    /// The variant's spec.
    pub fn spec(self) -> &'static VariantSpec {
        // VARIANTS is indexed in declaration order of the enum
        &VARIANTS[self as usize]
    }
}

/// FMI causality and variability (Integer outputs are discrete), the same enums as the Body
/// FMU's (`fmi_shared`).
pub use fmi_shared::model_description::{Causality, Variability};

/// FMI base type with its start value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// Real, with start value when the variable has one.
    Real(Option<f64>),
    /// Integer.
    Integer(Option<i32>),
    /// Boolean.
    Boolean(Option<bool>),
}

/// What an output depends on among the inputs (for ModelStructure).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deps {
    /// Positions and orientations.
    Pose,
    /// Every input (velocities enter through dampers or the friction rate).
    All,
    /// No input: an integral over past steps.
    None,
}

/// Per-component outputs (k = Abaqus component, slot k − 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompOut {
    /// CP / CPR
    Position,
    /// CU / CUR
    Motion,
    /// CV / CVR
    Velocity,
    /// CTF / CTM
    Total,
    /// CEF / CEM
    Elastic,
    /// CVF / CVM
    Viscous,
    /// CSF / CSM
    Friction,
    /// CRF / CRM
    Reaction,
}

/// Per-component parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompPar {
    /// elasticity.k<k>
    Stiffness,
    /// damping.c<k>
    Damping,
    /// reference.given<k>
    RefGiven,
    /// reference.value<k>
    RefValue,
    /// stop.lower<k>
    StopLower,
    /// stop.upper<k>
    StopUpper,
}

/// Scalar parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarPar {
    /// stop.stiffness
    StopK,
    /// stop.damping
    StopC,
    /// stop.rotStiffness
    StopKr,
    /// stop.rotDamping
    StopCr,
    /// constraint.stiffness
    ConK,
    /// constraint.damping
    ConC,
    /// constraint.rotStiffness
    ConKr,
    /// constraint.rotDamping
    ConCr,
    /// friction.muStatic
    MuS,
    /// friction.muKinetic
    MuK,
    /// friction.decay
    Decay,
    /// friction.R
    Radius,
    /// friction.Fint
    Fint,
    /// friction.Mint
    Mint,
    /// friction.stickStiffness
    StickK,
    /// friction.stickStiffnessR1
    StickKr,
    /// friction.stickDamping
    StickC,
    /// friction.stickDampingR1
    StickCr,
    /// friction.maxForce
    MaxForce,
    /// friction.coupling
    Coupling,
    /// cosim.extrapolation
    Extrapolation,
    /// cosim.maxSubstep
    MaxSubstep,
}

/// Friction outputs of PLANAR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionField {
    /// CNF
    Cnf,
    /// CNM1
    Cnm1,
    /// CSFC
    Csfc,
    /// CSMC1
    Csmc1,
    /// friction.slip
    Slip,
    /// friction.slipR1
    SlipR1,
    /// friction.status
    Status,
    /// friction.statusR1
    StatusR1,
}

/// The storage a variable refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// Node input: node 0 = a, 1 = b; idx 0..2 r, 3..6 q (w, x, y, z), 7..9 v, 10..12 ω,
    /// 13..15 v̇, 16..18 ω̇.
    Input {
        /// node
        node: u8,
        /// index within the node's 19 inputs
        idx: u8,
    },
    /// Node load: which 0 a.f, 1 a.m, 2 b.f, 3 b.m; component i.
    Load {
        /// which load
        which: u8,
        /// component 0..2
        i: u8,
    },
    /// Per-component output.
    Comp {
        /// which output
        out: CompOut,
        /// slot 0..5
        k: u8,
    },
    /// CSLST<k>.
    StopStatus(u8),
    /// PLANAR friction output.
    Friction(FrictionField),
    /// energy.stored, .damping, .friction, .stops (0..3).
    Energy(u8),
    /// event.time (0), event.count (1).
    Event(u8),
    /// Per-component parameter.
    CompParam {
        /// which parameter
        par: CompPar,
        /// slot 0..5
        k: u8,
    },
    /// Scalar parameter.
    Param(ScalarPar),
}

/// One scalar variable of a variant: a row of `ROWS` with its description for that variant.
#[derive(Clone, Debug, PartialEq)]
pub struct VarSpec {
    /// valueReference
    pub vr: u32,
    /// name
    pub name: String,
    /// storage
    pub field: Field,
    /// causality
    pub causality: Causality,
    /// variability
    pub variability: Variability,
    /// type and start
    pub start: Start,
    /// unit name ("" = none)
    pub unit: &'static str,
    /// description (specific to the variant's role for the variable's slot)
    pub description: String,
    /// input dependencies (outputs only)
    pub deps: Deps,
    /// smallest accepted value, inclusive (FMI `min`); None = unbounded
    pub min: Option<f64>,
    /// largest accepted value, inclusive (FMI `max`); None = unbounded
    pub max: Option<f64>,
}

/// A variant's table with a VR index.
#[derive(Debug)]
pub struct Table {
    /// The variant.
    pub spec: &'static VariantSpec,
    /// Variables in model-description order.
    pub vars: Vec<VarSpec>,
    /// vr → index into `vars`.
    index: Vec<Option<u16>>,
    /// GUID: a hash of the interface the model description shows (see `interface_text`).
    pub guid: String,
}

impl Table {
    /// The variable with value reference `vr`.
    #[inline]
    pub fn get(&self, vr: u32) -> Option<&VarSpec> {
        let i = (*self.index.get(vr as usize)?)?;
        self.vars.get(i as usize)
    }

    /// ModelStructure of output `i` (index into `vars`): the 1-based indices of the variables
    /// it depends on as an output (`Outputs`) and at initialization (`InitialUnknowns`).
    /// None for a variable that is not an output.
    pub fn dependencies(&self, i: usize) -> Option<(Vec<usize>, Vec<usize>)> {
        let v = self.vars.get(i)?;
        if v.causality != Causality::Output {
            return None;
        }
        let index_of = |pred: &dyn Fn(&VarSpec) -> bool| -> Vec<usize> {
            self.vars
                .iter()
                .enumerate()
                .filter(|(_, v)| pred(v))
                .map(|(i, _)| i + 1)
                .collect()
        };
        let inputs = match v.deps {
            Deps::Pose => index_of(&|v| {
                // positions and orientations: node inputs 0..6
                matches!(v.field, Field::Input { idx, .. } if idx < 7)
            }),
            // every pose and twist input: node inputs 0..12 (not the accelerations, which
            // only move the nodes over a step)
            Deps::All => index_of(
                &|v| matches!(v.field, Field::Input { idx, .. } if (idx as usize) < POSE_TWIST),
            ),
            Deps::None => Vec::new(),
        };
        let mut init = inputs.clone();
        if v.deps != Deps::None {
            init.extend(index_of(&|v| v.causality == Causality::Parameter));
            init.sort_unstable();
        }
        Some((inputs, init))
    }
}

/// The table of a variant (built once, then shared).
pub fn table(v: Variant) -> &'static Table {
    static TABLES: [OnceLock<Table>; 5] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    TABLES[v as usize].get_or_init(|| build(v.spec()))
}

/// The variant whose GUID this is.
pub fn variant_by_guid(guid: &str) -> Option<Variant> {
    VARIANTS
        .iter()
        .map(|s| s.variant)
        .find(|&v| table(v).guid == guid)
}

/// A Real as the XML schema spells it (INF, -INF; shortest round-trip otherwise).
pub fn xml_real(x: f64) -> String {
    if x == f64::INFINITY {
        "INF".to_string()
    } else if x == f64::NEG_INFINITY {
        "-INF".to_string()
    } else {
        format!("{x:?}")
    }
}

// ------------------------------------------------------------------------------------------
// The rows: every variable of every variant, in value-reference order (= the order of the
// model description). A variant has the rows `present` admits for its connection type.
// ------------------------------------------------------------------------------------------

/// One row of the variable table.
#[derive(Clone, Copy, Debug)]
struct Row {
    vr: u32,
    name: &'static str,
    field: Field,
    causality: Causality,
    variability: Variability,
    start: Start,
    unit: &'static str,
    /// (min, max), inclusive, as the code accepts them
    range: Range,
    deps: Deps,
    /// Description; for a per-component variable (slot k) the variant's role for the slot
    /// completes it (`describe`).
    what: &'static str,
}

/// Inclusive (min, max); None = unbounded on that side.
type Range = (Option<f64>, Option<f64>);
/// Any value (finite unless the description says otherwise).
const ANY: Range = (None, None);
/// ≥ 0.
const NONNEG: Range = (Some(0.0), None);
/// > 0: the smallest accepted value is the smallest positive double (the code refuses 0).
const POSITIVE: Range = (Some(f64::from_bits(1)), None);
/// 0 or 1 (Integer switches).
const ZERO_ONE: Range = (Some(0.0), Some(1.0));
/// 0 to 3 (cosim.extrapolation).
const ZERO_THREE: Range = (Some(0.0), Some(3.0));

const INF: f64 = f64::INFINITY;

const fn input(
    vr: u32,
    name: &'static str,
    node: u8,
    idx: u8,
    unit: &'static str,
    start: f64,
    what: &'static str,
) -> Row {
    Row {
        vr,
        name,
        field: Field::Input { node, idx },
        causality: Causality::Input,
        variability: Variability::Continuous,
        start: Start::Real(Some(start)),
        unit,
        range: ANY,
        deps: Deps::None,
        what,
    }
}

const fn output(
    vr: u32,
    name: &'static str,
    field: Field,
    start: Start,
    unit: &'static str,
    deps: Deps,
    what: &'static str,
) -> Row {
    let variability = match start {
        Start::Real(_) => Variability::Continuous,
        _ => Variability::Discrete,
    };
    Row {
        vr,
        name,
        field,
        causality: Causality::Output,
        variability,
        start,
        unit,
        range: ANY,
        deps,
        what,
    }
}

const fn load(
    vr: u32,
    name: &'static str,
    which: u8,
    i: u8,
    unit: &'static str,
    what: &'static str,
) -> Row {
    output(
        vr,
        name,
        Field::Load { which, i },
        Start::Real(None),
        unit,
        Deps::All,
        what,
    )
}

const fn comp(
    vr: u32,
    name: &'static str,
    out: CompOut,
    k: u8,
    unit: &'static str,
    deps: Deps,
) -> Row {
    output(
        vr,
        name,
        Field::Comp { out, k },
        Start::Real(None),
        unit,
        deps,
        "",
    )
}

const fn stop_status(vr: u32, name: &'static str, k: u8) -> Row {
    output(
        vr,
        name,
        Field::StopStatus(k),
        Start::Integer(None),
        "",
        Deps::Pose,
        "",
    )
}

const fn friction(
    vr: u32,
    name: &'static str,
    f: FrictionField,
    unit: &'static str,
    what: &'static str,
) -> Row {
    use FrictionField::*;
    let (start, deps) = match f {
        Status | StatusR1 => (Start::Integer(None), Deps::All),
        Slip | SlipR1 => (Start::Real(None), Deps::None),
        _ => (Start::Real(None), Deps::All),
    };
    output(vr, name, Field::Friction(f), start, unit, deps, what)
}

const fn energy(vr: u32, name: &'static str, i: u8, deps: Deps, what: &'static str) -> Row {
    output(
        vr,
        name,
        Field::Energy(i),
        Start::Real(None),
        "J",
        deps,
        what,
    )
}

const fn event(
    vr: u32,
    name: &'static str,
    start: Start,
    unit: &'static str,
    what: &'static str,
) -> Row {
    let field = Field::Event(match start {
        Start::Real(_) => 0,
        _ => 1,
    });
    Row {
        variability: Variability::Discrete,
        ..output(vr, name, field, start, unit, Deps::None, what)
    }
}

#[allow(clippy::too_many_arguments)]
const fn param(
    vr: u32,
    name: &'static str,
    field: Field,
    variability: Variability,
    start: Start,
    unit: &'static str,
    range: Range,
    what: &'static str,
) -> Row {
    Row {
        vr,
        name,
        field,
        causality: Causality::Parameter,
        variability,
        start,
        unit,
        range,
        deps: Deps::None,
        what,
    }
}

#[allow(clippy::too_many_arguments)]
const fn comp_param(
    vr: u32,
    name: &'static str,
    par: CompPar,
    k: u8,
    variability: Variability,
    start: Start,
    unit: &'static str,
    range: Range,
) -> Row {
    param(
        vr,
        name,
        Field::CompParam { par, k },
        variability,
        start,
        unit,
        range,
        "",
    )
}

const fn scalar(
    vr: u32,
    name: &'static str,
    par: ScalarPar,
    start: Start,
    unit: &'static str,
    range: Range,
    what: &'static str,
) -> Row {
    // the friction coupling changes the state's meaning: fixed; the rest may change per step
    let variability = match par {
        ScalarPar::Coupling => Variability::Fixed,
        _ => Variability::Tunable,
    };
    param(
        vr,
        name,
        Field::Param(par),
        variability,
        start,
        unit,
        range,
        what,
    )
}

use CompOut::{Elastic, Friction, Motion, Position, Reaction, Total, Velocity, Viscous};
use CompPar::{Damping, RefGiven, RefValue, Stiffness, StopLower, StopUpper};
use FrictionField::{Cnf, Cnm1, Csfc, Csmc1, Slip, SlipR1, Status, StatusR1};
use Variability::{Fixed, Tunable};

/// Every variable of every variant, value references written out. A row's start equals the
/// physics' default (`Params::default`, checked by a test); its range is what the setters
/// accept (`model::access::check_real`, `write_int`) and its description is what a user reads.
#[rustfmt::skip]
const ROWS: &[Row] = &[
    // ---- inputs: node poses and twists in W (node a: VR 1..13, node b: VR 21..33), and their
    //      accelerations (a: VR 14..19, b: VR 34..39)
    input(1, "a.r[1]", 0, 0, "m", 0.0, "node a position, W component 1"),
    input(2, "a.r[2]", 0, 1, "m", 0.0, "node a position, W component 2"),
    input(3, "a.r[3]", 0, 2, "m", 0.0, "node a position, W component 3"),
    input(4, "a.q.w", 0, 3, "1", 1.0, "node a orientation quaternion (scalar first, node-local to W), w"),
    input(5, "a.q.x", 0, 4, "1", 0.0, "node a orientation quaternion (scalar first, node-local to W), x"),
    input(6, "a.q.y", 0, 5, "1", 0.0, "node a orientation quaternion (scalar first, node-local to W), y"),
    input(7, "a.q.z", 0, 6, "1", 0.0, "node a orientation quaternion (scalar first, node-local to W), z"),
    input(8, "a.v[1]", 0, 7, "m/s", 0.0, "node a velocity, W component 1"),
    input(9, "a.v[2]", 0, 8, "m/s", 0.0, "node a velocity, W component 2"),
    input(10, "a.v[3]", 0, 9, "m/s", 0.0, "node a velocity, W component 3"),
    input(11, "a.w[1]", 0, 10, "rad/s", 0.0, "node a angular velocity, W component 1"),
    input(12, "a.w[2]", 0, 11, "rad/s", 0.0, "node a angular velocity, W component 2"),
    input(13, "a.w[3]", 0, 12, "rad/s", 0.0, "node a angular velocity, W component 3"),
    input(14, "a.dv[1]", 0, 13, "m/s2", 0.0, "node a acceleration, W component 1: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(15, "a.dv[2]", 0, 14, "m/s2", 0.0, "node a acceleration, W component 2: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(16, "a.dv[3]", 0, 15, "m/s2", 0.0, "node a acceleration, W component 3: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(17, "a.dw[1]", 0, 16, "rad/s2", 0.0, "node a angular acceleration, W component 1: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(18, "a.dw[2]", 0, 17, "rad/s2", 0.0, "node a angular acceleration, W component 2: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(19, "a.dw[3]", 0, 18, "rad/s2", 0.0, "node a angular acceleration, W component 3: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(21, "b.r[1]", 1, 0, "m", 0.0, "node b position, W component 1"),
    input(22, "b.r[2]", 1, 1, "m", 0.0, "node b position, W component 2"),
    input(23, "b.r[3]", 1, 2, "m", 0.0, "node b position, W component 3"),
    input(24, "b.q.w", 1, 3, "1", 1.0, "node b orientation quaternion (scalar first, node-local to W), w"),
    input(25, "b.q.x", 1, 4, "1", 0.0, "node b orientation quaternion (scalar first, node-local to W), x"),
    input(26, "b.q.y", 1, 5, "1", 0.0, "node b orientation quaternion (scalar first, node-local to W), y"),
    input(27, "b.q.z", 1, 6, "1", 0.0, "node b orientation quaternion (scalar first, node-local to W), z"),
    input(28, "b.v[1]", 1, 7, "m/s", 0.0, "node b velocity, W component 1"),
    input(29, "b.v[2]", 1, 8, "m/s", 0.0, "node b velocity, W component 2"),
    input(30, "b.v[3]", 1, 9, "m/s", 0.0, "node b velocity, W component 3"),
    input(31, "b.w[1]", 1, 10, "rad/s", 0.0, "node b angular velocity, W component 1"),
    input(32, "b.w[2]", 1, 11, "rad/s", 0.0, "node b angular velocity, W component 2"),
    input(33, "b.w[3]", 1, 12, "rad/s", 0.0, "node b angular velocity, W component 3"),
    input(34, "b.dv[1]", 1, 13, "m/s2", 0.0, "node b acceleration, W component 1: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(35, "b.dv[2]", 1, 14, "m/s2", 0.0, "node b acceleration, W component 2: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(36, "b.dv[3]", 1, 15, "m/s2", 0.0, "node b acceleration, W component 3: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(37, "b.dw[1]", 1, 16, "rad/s2", 0.0, "node b angular acceleration, W component 1: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(38, "b.dw[2]", 1, 17, "rad/s2", 0.0, "node b angular acceleration, W component 2: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    input(39, "b.dw[3]", 1, 18, "rad/s2", 0.0, "node b angular acceleration, W component 3: with cosim.extrapolation = 3 the node moves over the next step along it (ignored otherwise)"),
    // ---- outputs: node loads, what the connector exerts on the node, in W
    load(101, "a.f[1]", 0, 0, "N", "force on node a, W component 1"),
    load(102, "a.f[2]", 0, 1, "N", "force on node a, W component 2"),
    load(103, "a.f[3]", 0, 2, "N", "force on node a, W component 3"),
    load(104, "a.m[1]", 1, 0, "N.m", "moment on node a about its position, W component 1"),
    load(105, "a.m[2]", 1, 1, "N.m", "moment on node a about its position, W component 2"),
    load(106, "a.m[3]", 1, 2, "N.m", "moment on node a about its position, W component 3"),
    load(107, "b.f[1]", 2, 0, "N", "force on node b, W component 1"),
    load(108, "b.f[2]", 2, 1, "N", "force on node b, W component 2"),
    load(109, "b.f[3]", 2, 2, "N", "force on node b, W component 3"),
    load(110, "b.m[1]", 3, 0, "N.m", "moment on node b about its position, W component 1"),
    load(111, "b.m[2]", 3, 1, "N.m", "moment on node b about its position, W component 2"),
    load(112, "b.m[3]", 3, 2, "N.m", "moment on node b about its position, W component 3"),
    // ---- outputs per component slot k = 1..6 (VR 201 + 10·kind + k − 1); described per variant
    comp(201, "CP1", Position, 0, "m", Deps::Pose),
    comp(202, "CP2", Position, 1, "m", Deps::Pose),
    comp(203, "CP3", Position, 2, "m", Deps::Pose),
    comp(204, "CPR1", Position, 3, "rad", Deps::Pose),
    comp(205, "CPR2", Position, 4, "rad", Deps::Pose),
    comp(206, "CPR3", Position, 5, "rad", Deps::Pose),
    comp(211, "CU1", Motion, 0, "m", Deps::Pose),
    comp(212, "CU2", Motion, 1, "m", Deps::Pose),
    comp(213, "CU3", Motion, 2, "m", Deps::Pose),
    comp(214, "CUR1", Motion, 3, "rad", Deps::Pose),
    comp(215, "CUR2", Motion, 4, "rad", Deps::Pose),
    comp(216, "CUR3", Motion, 5, "rad", Deps::Pose),
    comp(221, "CV1", Velocity, 0, "m/s", Deps::All),
    comp(222, "CV2", Velocity, 1, "m/s", Deps::All),
    comp(223, "CV3", Velocity, 2, "m/s", Deps::All),
    comp(224, "CVR1", Velocity, 3, "rad/s", Deps::All),
    comp(225, "CVR2", Velocity, 4, "rad/s", Deps::All),
    comp(226, "CVR3", Velocity, 5, "rad/s", Deps::All),
    comp(231, "CTF1", Total, 0, "N", Deps::All),
    comp(232, "CTF2", Total, 1, "N", Deps::All),
    comp(233, "CTF3", Total, 2, "N", Deps::All),
    comp(234, "CTM1", Total, 3, "N.m", Deps::All),
    comp(235, "CTM2", Total, 4, "N.m", Deps::All),
    comp(236, "CTM3", Total, 5, "N.m", Deps::All),
    comp(241, "CEF1", Elastic, 0, "N", Deps::Pose),
    comp(242, "CEF2", Elastic, 1, "N", Deps::Pose),
    comp(243, "CEF3", Elastic, 2, "N", Deps::Pose),
    comp(244, "CEM1", Elastic, 3, "N.m", Deps::Pose),
    comp(245, "CEM2", Elastic, 4, "N.m", Deps::Pose),
    comp(246, "CEM3", Elastic, 5, "N.m", Deps::Pose),
    comp(251, "CVF1", Viscous, 0, "N", Deps::All),
    comp(252, "CVF2", Viscous, 1, "N", Deps::All),
    comp(253, "CVF3", Viscous, 2, "N", Deps::All),
    comp(254, "CVM1", Viscous, 3, "N.m", Deps::All),
    comp(255, "CVM2", Viscous, 4, "N.m", Deps::All),
    comp(256, "CVM3", Viscous, 5, "N.m", Deps::All),
    comp(261, "CSF1", Friction, 0, "N", Deps::All),
    comp(262, "CSF2", Friction, 1, "N", Deps::All),
    comp(263, "CSF3", Friction, 2, "N", Deps::All),
    comp(264, "CSM1", Friction, 3, "N.m", Deps::All),
    comp(265, "CSM2", Friction, 4, "N.m", Deps::All),
    comp(266, "CSM3", Friction, 5, "N.m", Deps::All),
    comp(271, "CRF1", Reaction, 0, "N", Deps::All),
    comp(272, "CRF2", Reaction, 1, "N", Deps::All),
    comp(273, "CRF3", Reaction, 2, "N", Deps::All),
    comp(274, "CRM1", Reaction, 3, "N.m", Deps::All),
    comp(275, "CRM2", Reaction, 4, "N.m", Deps::All),
    comp(276, "CRM3", Reaction, 5, "N.m", Deps::All),
    stop_status(281, "CSLST1", 0),
    stop_status(282, "CSLST2", 1),
    stop_status(283, "CSLST3", 2),
    stop_status(284, "CSLST4", 3),
    stop_status(285, "CSLST5", 4),
    stop_status(286, "CSLST6", 5),
    // ---- outputs: PLANAR friction
    friction(301, "CNF", Cnf, "N", "friction-producing normal force F_NC = |F_C + friction.Fint|, F_C = |CRF1| + |(CRM2, CRM3)|/R (|CRF1| when R = 0). The plane passes through b's initial position, so an initial offset normal to the plane gives no normal force: preload with friction.Fint"),
    friction(302, "CNM1", Cnm1, "N.m", "friction-producing normal moment M_NR1 = |(2/3)·R·|CRF1| + |(CRM2, CRM3)| + friction.Mint|"),
    friction(303, "CSFC", Csfc, "N", "magnitude of the sliding friction force |(CSF2, CSF3)|"),
    friction(304, "CSMC1", Csmc1, "N.m", "magnitude of the spin friction moment |CSM1|"),
    friction(305, "friction.slip", Slip, "m", "accumulated sliding slip (path length in the 2-3 plane)"),
    friction(306, "friction.slipR1", SlipR1, "rad", "accumulated spin slip"),
    friction(307, "friction.status", Status, "", "sliding: 0 no normal force, 1 stick, 2 slip"),
    friction(308, "friction.statusR1", StatusR1, "", "spin: 0 no normal force, 1 stick, 2 slip"),
    // ---- outputs: energy
    energy(401, "energy.stored", 0, Deps::Pose, "energy stored in springs, penalties, stops and stick springs"),
    energy(402, "energy.damping", 1, Deps::None, "energy dissipated by dampers since initialization"),
    energy(403, "energy.friction", 2, Deps::None, "energy dissipated by friction since initialization"),
    energy(404, "energy.stops", 3, Deps::None, "energy dissipated by stops since initialization"),
    // ---- outputs: events located in the last step
    event(411, "event.time", Start::Real(None), "s", "time of the first event located in the last step: a stop engaging or letting go (CSLST changes), friction stick -> slip or slip -> stick, the normal force of friction passing through zero; the end of the step when none (the start time before the first step). A master that can roll back re-steps to it"),
    event(412, "event.count", Start::Integer(None), "", "number of events located in the last step (0: none; at an FMI 3.0 early return, the events at lastSuccessfulTime)"),
    // ---- parameters per component slot k = 1..6 (VR 501 + 10·kind + k − 1); described per variant
    comp_param(501, "elasticity.k1", Stiffness, 0, Tunable, Start::Real(Some(0.0)), "N/m", NONNEG),
    comp_param(502, "elasticity.k2", Stiffness, 1, Tunable, Start::Real(Some(0.0)), "N/m", NONNEG),
    comp_param(503, "elasticity.k3", Stiffness, 2, Tunable, Start::Real(Some(0.0)), "N/m", NONNEG),
    comp_param(504, "elasticity.k4", Stiffness, 3, Tunable, Start::Real(Some(0.0)), "N.m/rad", NONNEG),
    comp_param(505, "elasticity.k5", Stiffness, 4, Tunable, Start::Real(Some(0.0)), "N.m/rad", NONNEG),
    comp_param(506, "elasticity.k6", Stiffness, 5, Tunable, Start::Real(Some(0.0)), "N.m/rad", NONNEG),
    comp_param(511, "damping.c1", Damping, 0, Tunable, Start::Real(Some(0.0)), "N.s/m", NONNEG),
    comp_param(512, "damping.c2", Damping, 1, Tunable, Start::Real(Some(0.0)), "N.s/m", NONNEG),
    comp_param(513, "damping.c3", Damping, 2, Tunable, Start::Real(Some(0.0)), "N.s/m", NONNEG),
    comp_param(514, "damping.c4", Damping, 3, Tunable, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG),
    comp_param(515, "damping.c5", Damping, 4, Tunable, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG),
    comp_param(516, "damping.c6", Damping, 5, Tunable, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG),
    comp_param(521, "reference.given1", RefGiven, 0, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(522, "reference.given2", RefGiven, 1, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(523, "reference.given3", RefGiven, 2, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(524, "reference.given4", RefGiven, 3, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(525, "reference.given5", RefGiven, 4, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(526, "reference.given6", RefGiven, 5, Fixed, Start::Boolean(Some(false)), "", ANY),
    comp_param(531, "reference.value1", RefValue, 0, Fixed, Start::Real(Some(0.0)), "m", ANY),
    comp_param(532, "reference.value2", RefValue, 1, Fixed, Start::Real(Some(0.0)), "m", ANY),
    comp_param(533, "reference.value3", RefValue, 2, Fixed, Start::Real(Some(0.0)), "m", ANY),
    comp_param(534, "reference.value4", RefValue, 3, Fixed, Start::Real(Some(0.0)), "rad", ANY),
    comp_param(535, "reference.value5", RefValue, 4, Fixed, Start::Real(Some(0.0)), "rad", ANY),
    comp_param(536, "reference.value6", RefValue, 5, Fixed, Start::Real(Some(0.0)), "rad", ANY),
    comp_param(541, "stop.lower1", StopLower, 0, Tunable, Start::Real(Some(-INF)), "m", ANY),
    comp_param(542, "stop.lower2", StopLower, 1, Tunable, Start::Real(Some(-INF)), "m", ANY),
    comp_param(543, "stop.lower3", StopLower, 2, Tunable, Start::Real(Some(-INF)), "m", ANY),
    comp_param(544, "stop.lower4", StopLower, 3, Tunable, Start::Real(Some(-INF)), "rad", ANY),
    comp_param(545, "stop.lower5", StopLower, 4, Tunable, Start::Real(Some(-INF)), "rad", ANY),
    comp_param(546, "stop.lower6", StopLower, 5, Tunable, Start::Real(Some(-INF)), "rad", ANY),
    comp_param(551, "stop.upper1", StopUpper, 0, Tunable, Start::Real(Some(INF)), "m", ANY),
    comp_param(552, "stop.upper2", StopUpper, 1, Tunable, Start::Real(Some(INF)), "m", ANY),
    comp_param(553, "stop.upper3", StopUpper, 2, Tunable, Start::Real(Some(INF)), "m", ANY),
    comp_param(554, "stop.upper4", StopUpper, 3, Tunable, Start::Real(Some(INF)), "rad", ANY),
    comp_param(555, "stop.upper5", StopUpper, 4, Tunable, Start::Real(Some(INF)), "rad", ANY),
    comp_param(556, "stop.upper6", StopUpper, 5, Tunable, Start::Real(Some(INF)), "rad", ANY),

    // ---- scalar parameters (VR 601..; appended ones keep the earlier value references)
    scalar(601, "stop.stiffness", ScalarPar::StopK, Start::Real(Some(1e7)), "N/m", NONNEG, "translational stop penalty stiffness, ≥ 0"),
    scalar(602, "stop.damping", ScalarPar::StopC, Start::Real(Some(0.0)), "N.s/m", NONNEG, "translational stop penalty damping, ≥ 0 (the stop force never pulls)"),
    scalar(603, "stop.rotStiffness", ScalarPar::StopKr, Start::Real(Some(1e5)), "N.m/rad", NONNEG, "rotational stop penalty stiffness, ≥ 0"),
    scalar(604, "stop.rotDamping", ScalarPar::StopCr, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG, "rotational stop penalty damping, ≥ 0 (the stop moment never pulls)"),
    scalar(605, "constraint.stiffness", ScalarPar::ConK, Start::Real(Some(1e7)), "N/m", NONNEG, "SLIDE-PLANE penalty stiffness holding the normal distance x (CP1) at its initial value, ≥ 0. The plane passes through node b's initial position, so an initial offset normal to the plane gives no normal force; preload the friction with friction.Fint"),
    scalar(606, "constraint.damping", ScalarPar::ConC, Start::Real(Some(0.0)), "N.s/m", NONNEG, "SLIDE-PLANE penalty damping on the normal rate dx/dt, ≥ 0"),
    scalar(607, "constraint.rotStiffness", ScalarPar::ConKr, Start::Real(Some(1e5)), "N.m/rad", NONNEG, "REVOLUTE penalty stiffness holding e1 of node b along e1 of node a (φ2 = φ3 = 0), ≥ 0"),
    scalar(608, "constraint.rotDamping", ScalarPar::ConCr, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG, "REVOLUTE penalty damping on dφ2/dt, dφ3/dt, ≥ 0"),
    scalar(609, "friction.muStatic", ScalarPar::MuS, Start::Real(Some(0.0)), "1", NONNEG, "static friction coefficient μ_s, ≥ 0 and ≥ friction.muKinetic (μ_s = μ_k = 0: no friction)"),
    scalar(610, "friction.muKinetic", ScalarPar::MuK, Start::Real(Some(0.0)), "1", NONNEG, "kinetic friction coefficient μ_k, ≥ 0 and ≤ friction.muStatic; acts only with friction.decay > 0: μ = μ_k + (μ_s - μ_k)·exp(-decay·slip rate) while slipping; with decay = 0, μ = μ_s throughout"),
    scalar(611, "friction.decay", ScalarPar::Decay, Start::Real(Some(0.0)), "s/m", NONNEG, "decay d_c of μ with the slip rate, ≥ 0 (0: μ = friction.muStatic, friction.muKinetic unused)"),
    scalar(612, "friction.R", ScalarPar::Radius, Start::Real(Some(0.0)), "m", NONNEG, "characteristic puck radius R, ≥ 0 (0: the bending moments and the spin term from CRF1 are ignored; friction.coupling = 1 needs R > 0)"),
    scalar(613, "friction.Fint", ScalarPar::Fint, Start::Real(Some(0.0)), "N", ANY, "internal contact force F_C^int added to F_C in CNF (any finite sign): the preload of the sliding friction. The plane passes through node b's initial position, so an initial offset normal to the plane gives no normal force; set friction.Fint = F_int to preload"),
    scalar(614, "friction.Mint", ScalarPar::Mint, Start::Real(Some(0.0)), "N.m", ANY, "internal contact moment M_R1^int added in CNM1 (any finite sign): the preload of the spin friction"),
    scalar(615, "friction.stickStiffness", ScalarPar::StickK, Start::Real(Some(1e6)), "N/m", POSITIVE, "elastic stick stiffness of sliding, > 0 (0 is refused)"),
    scalar(616, "friction.stickStiffnessR1", ScalarPar::StickKr, Start::Real(Some(1e4)), "N.m/rad", POSITIVE, "elastic stick stiffness of spin, > 0 (0 is refused)"),
    scalar(617, "friction.maxForce", ScalarPar::MaxForce, Start::Real(Some(INF)), "N", NONNEG, "cap on the sliding friction force, ≥ 0 (+INF = none)"),
    scalar(618, "friction.coupling", ScalarPar::Coupling, Start::Integer(Some(0)), "", ZERO_ONE, "0 separate sliding and spin (Abaqus), 1 coupled: ellipsoidal limit, disc flow (needs friction.R > 0)"),
    scalar(619, "cosim.extrapolation", ScalarPar::Extrapolation, Start::Integer(Some(1)), "", ZERO_THREE, "input extrapolation over a step: 0 hold, 1 linear (positions and orientations along the velocities; velocities along their FMI 2.0 input derivatives where set), 2 second order (positions and orientations also along the accelerations; accelerations from the input derivatives of the velocities where set, otherwise from the velocity inputs of the previous communication point), 3 second order along the acceleration inputs a.dv, a.dw, b.dv, b.dw (the path the importer's bodies follow; FMI 3.0 has no input derivatives)"),
    scalar(620, "cosim.maxSubstep", ScalarPar::MaxSubstep, Start::Real(Some(0.0)), "s", NONNEG, "largest internal substep, ≥ 0 (0: from the path alone)"),
    scalar(621, "friction.stickDamping", ScalarPar::StickC, Start::Real(Some(0.0)), "N.s/m", NONNEG, "stick damping of sliding, parallel to the stick spring, ≥ 0 (0: Abaqus)"),
    scalar(622, "friction.stickDampingR1", ScalarPar::StickCr, Start::Real(Some(0.0)), "N.m.s/rad", NONNEG, "stick damping of spin, parallel to the stick spring, ≥ 0 (0: Abaqus)"),
];

/// Whether a variant of connection type `ct` has the variable stored in `field`.
fn present(ct: ConnectionType, field: &Field) -> bool {
    let roles = ct.roles();
    let planar = ct.rot == Rotational::Revolute;
    let has_trans = roles[..3].contains(&Role::Available);
    let has_rot = roles[3..].contains(&Role::Available);
    match *field {
        Field::Input { node, idx } => match idx {
            0..=2 | 7..=9 | 13..=15 => ct.uses_positions(),
            _ if node == 0 => ct.uses_orientation_a(),
            _ => ct.uses_orientation_b(),
        },
        Field::Load { which, .. } => match which {
            0 | 2 => ct.uses_positions(),
            1 => true,
            _ => ct.uses_orientation_b(),
        },
        Field::Comp { out, k } => match roles[k as usize] {
            Role::Available => out != CompOut::Friction || planar,
            Role::Constrained => matches!(out, CompOut::Reaction | CompOut::Total),
            Role::Absent => false,
        },
        Field::StopStatus(k) | Field::CompParam { k, .. } => roles[k as usize] == Role::Available,
        Field::Friction(_) => planar,
        Field::Energy(i) => i != 2 || planar,
        Field::Event(_) => true,
        Field::Param(p) => {
            use ScalarPar::*;
            match p {
                StopK | StopC => has_trans,
                StopKr | StopCr => has_rot,
                Extrapolation | MaxSubstep => true,
                ConK | ConC | ConKr | ConCr | MuS | MuK | Decay | Radius | Fint | Mint | StickK
                | StickKr | StickC | StickCr | MaxForce | Coupling => planar,
            }
        }
    }
}

/// What slot k (0..5) is in connection type `ct`: the Abaqus component label, the symbol
/// of its position and what that position measures.
fn slot(ct: ConnectionType, k: usize) -> (&'static str, &'static str, &'static str) {
    const LABEL: [&str; 6] = ["u1", "u2", "u3", "ur1", "ur2", "ur3"];
    let (sym, meaning) = if k < 3 {
        match (ct.trans, k) {
            (Translational::ProjectionCartesian, 0) => {
                ("x", "projected distance x = e1·(x_b - x_a) along e1 of the centred projection triad")
            }
            (Translational::ProjectionCartesian, 1) => {
                ("y", "projected distance y = e2·(x_b - x_a) along e2 of the centred projection triad")
            }
            (Translational::ProjectionCartesian, _) => {
                ("z", "projected distance z = e3·(x_b - x_a) along e3 of the centred projection triad")
            }
            (Translational::SlidePlane, 0) => (
                "x",
                "normal distance x = e1a·(x_b - x_a) to the sliding plane (SLIDE-PLANE constraint: held at its initial value x0, so the plane passes through node b's initial position)",
            ),
            (Translational::SlidePlane, 1) => {
                ("y", "in-plane position y = e2a·(x_b - x_a) (SLIDE-PLANE)")
            }
            (Translational::SlidePlane, _) => {
                ("z", "in-plane position z = e3a·(x_b - x_a) (SLIDE-PLANE)")
            }
            (Translational::RadialThrust, 0) => {
                ("r", "radial distance r of node b from the axis e3a through node a")
            }
            (Translational::RadialThrust, _) => {
                ("l", "thrust (axial) distance l = e3a·(x_b - x_a) along the axis e3a")
            }
            (Translational::None, _) => ("", ""),
        }
    } else {
        match (ct.rot, k) {
            (Rotational::ProjectionFlexionTorsion, 3) => (
                "α1",
                "flexion angle α1 = α e1·q about e1 of the centred triad (α total flexion, q flexion axis)",
            ),
            (Rotational::ProjectionFlexionTorsion, 4) => (
                "α2",
                "flexion angle α2 = α e2·q about e2 of the centred triad (α total flexion, q flexion axis)",
            ),
            (Rotational::ProjectionFlexionTorsion, _) => {
                ("β", "torsion angle β about e3 of the centred triad")
            }
            (Rotational::Revolute, 3) => (
                "α",
                "rotation angle α about e1a (REVOLUTE), on its continuous branch",
            ),
            (Rotational::Revolute, 4) => (
                "φ2",
                "misalignment rotation φ2 = -e3a·e1b about e2a (REVOLUTE constraint, held at 0)",
            ),
            (Rotational::Revolute, _) => (
                "φ3",
                "misalignment rotation φ3 = e2a·e1b about e3a (REVOLUTE constraint, held at 0)",
            ),
            (Rotational::None, _) => ("", ""),
        }
    };
    (LABEL[k], sym, meaning)
}

/// A short name of slot k's component in connection type `ct` ("radial distance r").
fn short_name(ct: ConnectionType, k: usize) -> &'static str {
    match (ct.trans, ct.rot, k) {
        (Translational::ProjectionCartesian, _, 0) => "projection x",
        (Translational::ProjectionCartesian, _, 1) => "projection y",
        (Translational::ProjectionCartesian, _, 2) => "projection z",
        (Translational::SlidePlane, _, 0) => "normal distance x",
        (Translational::SlidePlane, _, 1) => "in-plane y",
        (Translational::SlidePlane, _, 2) => "in-plane z",
        (Translational::RadialThrust, _, 0) => "radial distance r",
        (Translational::RadialThrust, _, 2) => "thrust distance l",
        (_, Rotational::ProjectionFlexionTorsion, 3) => "flexion angle α1",
        (_, Rotational::ProjectionFlexionTorsion, 4) => "flexion angle α2",
        (_, Rotational::ProjectionFlexionTorsion, 5) => "torsion angle β",
        (_, Rotational::Revolute, 3) => "rotation angle α",
        (_, Rotational::Revolute, 4) => "misalignment φ2",
        (_, Rotational::Revolute, 5) => "misalignment φ3",
        _ => "",
    }
}

/// Name of a per-component output in slot k (CP1, CPR1, ...).
fn comp_name(out: CompOut, k: usize) -> String {
    let (t, r) = match out {
        CompOut::Position => ("CP", "CPR"),
        CompOut::Motion => ("CU", "CUR"),
        CompOut::Velocity => ("CV", "CVR"),
        CompOut::Total => ("CTF", "CTM"),
        CompOut::Elastic => ("CEF", "CEM"),
        CompOut::Viscous => ("CVF", "CVM"),
        CompOut::Friction => ("CSF", "CSM"),
        CompOut::Reaction => ("CRF", "CRM"),
    };
    if k < 3 {
        format!("{t}{}", k + 1)
    } else {
        format!("{r}{}", k - 2)
    }
}

/// The description of a row in a variant: per-component variables name the variant's
/// component in that slot, forces as forces and moments as moments.
fn describe(ct: ConnectionType, row: &Row) -> String {
    let roles = ct.roles();
    let planar = ct.rot == Rotational::Revolute;
    let k = match row.field {
        Field::Comp { k, .. } | Field::StopStatus(k) | Field::CompParam { k, .. } => k as usize,
        _ => return row.what.to_string(),
    };
    let (lab, sym, meaning) = slot(ct, k);
    let short = short_name(ct, k);
    let n = k + 1;
    let (fm, unit_of_pos) = if k < 3 {
        ("force", "m")
    } else {
        ("moment", "rad")
    };
    let constrained = roles[k] == Role::Constrained;
    match row.field {
        Field::Comp { out, .. } => match out {
            CompOut::Position => format!("{meaning} (component {lab})"),
            CompOut::Motion => {
                format!("motion of the {short} ({lab}): {sym} minus its value at the end of initialization")
            }
            CompOut::Velocity => format!("rate of the {short} ({lab}): d{sym}/dt"),
            CompOut::Total if constrained => format!(
                "total {fm} in {lab} ({short}): the constraint reaction {}",
                comp_name(CompOut::Reaction, k)
            ),
            CompOut::Total => {
                let mut terms = vec![
                    comp_name(CompOut::Elastic, k),
                    comp_name(CompOut::Viscous, k),
                ];
                if planar {
                    terms.push(comp_name(CompOut::Friction, k));
                }
                terms.push(comp_name(CompOut::Reaction, k));
                format!("total {fm} in {lab} ({short}): {}", terms.join(" + "))
            }
            CompOut::Elastic => format!(
                "elastic {fm} in {lab} ({short}): elasticity.k{n}·({sym} - reference), the reference being the initial {sym} or reference.value{n}"
            ),
            CompOut::Viscous => format!("viscous {fm} in {lab} ({short}): damping.c{n}·d{sym}/dt"),
            CompOut::Friction if k < 3 => {
                format!("sliding friction force in {lab} (along the {short})")
            }
            CompOut::Friction => format!("spin friction moment in {lab} (about the {short})"),
            CompOut::Reaction if constrained && k < 3 => format!(
                "constraint reaction force f1 normal to the sliding plane: constraint.stiffness·({sym} - x0) + constraint.damping·d{sym}/dt; drives the friction (CNF). The plane passes through node b's initial position, so it is 0 at the start: preload the friction with friction.Fint"
            ),
            CompOut::Reaction if constrained => format!(
                "constraint reaction moment m{n_rot} holding {sym} at 0 (REVOLUTE): constraint.rotStiffness·{sym} + constraint.rotDamping·d{sym}/dt; enters CNF (through R) and CNM1",
                n_rot = k - 2
            ),
            CompOut::Reaction => format!(
                "stop reaction {fm} on the {short} ({lab}): one-sided penalty beyond stop.lower{n} or stop.upper{n}, 0 between the stops"
            ),
        },
        Field::StopStatus(_) => format!(
            "stop status of the {short} ({lab}): -1 at stop.lower{n}, 0 free, +1 at stop.upper{n}"
        ),
        Field::CompParam { par, .. } => match par {
            CompPar::Stiffness => format!(
                "stiffness of {lab} ({short}), ≥ 0: {} = elasticity.k{n}·({sym} - reference)",
                comp_name(CompOut::Elastic, k)
            ),
            CompPar::Damping => format!(
                "damping of {lab} ({short}), ≥ 0: {} = damping.c{n}·d{sym}/dt",
                comp_name(CompOut::Viscous, k)
            ),
            CompPar::RefGiven => format!(
                "true: reference.value{n} is the elastic reference of the {short} ({lab}); false: its initial value"
            ),
            CompPar::RefValue => format!(
                "elastic reference of the {short} ({lab}, {unit_of_pos}) when reference.given{n} is true"
            ),
            CompPar::StopLower => format!(
                "lower stop on the {short} ({lab}), -INF = none; must not exceed stop.upper{n}"
            ),
            CompPar::StopUpper => format!(
                "upper stop on the {short} ({lab}), +INF = none; must not be below stop.lower{n}"
            ),
        },
        _ => row.what.to_string(),
    }
}

/// Builds the table of one variant: the rows present in its connection type.
fn build(spec: &'static VariantSpec) -> Table {
    let ct = spec.connection;
    let vars: Vec<VarSpec> = ROWS
        .iter()
        .filter(|r| present(ct, &r.field))
        .map(|r| VarSpec {
            vr: r.vr,
            name: r.name.to_string(),
            field: r.field,
            causality: r.causality,
            variability: r.variability,
            start: r.start,
            unit: r.unit,
            description: describe(ct, r),
            deps: r.deps,
            min: r.range.0,
            max: r.range.1,
        })
        .collect();
    let max_vr = vars.iter().map(|v| v.vr).max().unwrap_or(0) as usize;
    let mut index = vec![None; max_vr + 1];
    for (i, v) in vars.iter().enumerate() {
        index[v.vr as usize] = Some(i as u16);
    }
    let mut t = Table {
        spec,
        vars,
        index,
        guid: String::new(),
    };
    t.guid = guid_of(&interface_text(&t));
    t
}

impl VarSpec {
    /// The FMI type element's name.
    pub fn type_name(&self) -> &'static str {
        match self.start {
            Start::Real(_) => "Real",
            Start::Integer(_) => "Integer",
            Start::Boolean(_) => "Boolean",
        }
    }

    /// The `start` attribute as the model description writes it.
    pub fn start_text(&self) -> Option<String> {
        match self.start {
            Start::Real(s) => s.map(xml_real),
            Start::Integer(s) => s.map(|x| x.to_string()),
            Start::Boolean(s) => s.map(|x| x.to_string()),
        }
    }

    /// The `unit` attribute as the model description writes it (Real only; "1" is no unit).
    pub fn unit_text(&self) -> Option<&'static str> {
        match self.start {
            Start::Real(_) if !self.unit.is_empty() && self.unit != "1" => Some(self.unit),
            _ => None,
        }
    }

    /// The `min` and `max` attributes as the model description writes them.
    pub fn range_text(&self) -> (Option<String>, Option<String>) {
        let text = |x: Option<f64>| {
            x.map(|x| match self.start {
                Start::Integer(_) => (x as i32).to_string(),
                _ => xml_real(x),
            })
        };
        (text(self.min), text(self.max))
    }
}

/// The interface as the model description shows it, one line per item, from which the GUID is
/// hashed: the model identifier and version; per variable (in order) its name, value
/// reference, causality, variability, type, start, unit, min and max as the XML spells them;
/// the ModelStructure's Outputs and InitialUnknowns with their dependencies. Descriptions are
/// not part of it: rewording one is not an interface change. `tests/model_description.rs`
/// rebuilds this text from the committed XML alone.
pub fn interface_text(t: &Table) -> String {
    let mut s = format!(
        "{} {}\n",
        t.spec.model_identifier,
        env!("CARGO_PKG_VERSION")
    );
    for v in &t.vars {
        let (min, max) = v.range_text();
        s.push_str(&format!(
            "{}|{}|{}|{}|{}|{}|{}|{}|{}\n",
            v.name,
            v.vr,
            v.causality.name(),
            v.variability.name(),
            v.type_name(),
            v.start_text().unwrap_or_default(),
            v.unit_text().unwrap_or_default(),
            min.unwrap_or_default(),
            max.unwrap_or_default(),
        ));
    }
    let join = |ix: &[usize]| {
        ix.iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    for (tag, initial) in [("O", false), ("I", true)] {
        for i in 0..t.vars.len() {
            if let Some((out, init)) = t.dependencies(i) {
                let d = if initial { init } else { out };
                s.push_str(&format!("{tag}{}:{}\n", i + 1, join(&d)));
            }
        }
    }
    s
}

/// A GUID from a text (FNV-1a, 128 bits as two 64-bit lanes); `tests/model_description.rs`
/// repeats this hash on the text it rebuilds from the XML.
pub fn guid_of(text: &str) -> String {
    let fnv = |seed: u64| {
        text.bytes().fold(seed, |h, b| {
            (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let (h1, h2) = (fnv(0xcbf2_9ce4_8422_2325), fnv(0x6c62_272e_07bb_0142));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        h1 >> 32,
        (h1 >> 16) & 0xffff,
        h1 & 0xffff,
        h2 >> 48,
        h2 & 0xffff_ffff_ffff
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_vrs_are_unique_and_indexed() {
        for s in VARIANTS {
            let t = table(s.variant);
            let mut names: Vec<&str> = t.vars.iter().map(|v| v.name.as_str()).collect();
            names.sort();
            names.dedup();
            assert_eq!(names.len(), t.vars.len(), "{}", s.model_identifier);
            for v in &t.vars {
                assert_eq!(t.get(v.vr).map(|x| &x.name), Some(&v.name));
            }
            assert_eq!(variant_by_guid(&t.guid), Some(s.variant));
        }
    }

    #[test]
    fn variants_expose_only_what_they_need() {
        let names =
            |v: Variant| -> Vec<String> { table(v).vars.iter().map(|x| x.name.clone()).collect() };
        let rt = names(Variant::RadialThrust);
        assert!(rt.contains(&"a.q.w".to_string()));
        assert!(!rt
            .iter()
            .any(|n| n.starts_with("b.q") || n.starts_with("b.w") || n.starts_with("b.m")));
        let ft = names(Variant::ProjectionFlexionTorsion);
        assert!(!ft
            .iter()
            .any(|n| n.starts_with("a.r") || n.starts_with("a.f")));
        assert!(
            ft.contains(&"elasticity.k6".to_string()) && !ft.contains(&"elasticity.k1".to_string())
        );
        let pl = names(Variant::Planar);
        for n in [
            "CRF1",
            "CRM2",
            "CRM3",
            "CTF1",
            "CTM2",
            "CTM3",
            "CP2",
            "CPR1",
            "CNF",
            "friction.status",
        ] {
            assert!(pl.contains(&n.to_string()), "{n}");
        }
        assert!(!pl.contains(&"CP1".to_string()) && !pl.contains(&"elasticity.k1".to_string()));
    }

    #[test]
    fn starts_are_the_physics_defaults() {
        // every parameter's start, written out in ROWS, is what Params::default holds
        use crate::physics::connector::{Extrapolation, Params};
        let d = Params::default();
        let f = d.friction;
        let t = table(Variant::Planar);
        let real = |name: &str| match t.vars.iter().find(|v| v.name == name).map(|v| v.start) {
            Some(Start::Real(Some(x))) => x,
            other => panic!("{name}: {other:?}"),
        };
        let int = |name: &str| match t.vars.iter().find(|v| v.name == name).map(|v| v.start) {
            Some(Start::Integer(Some(x))) => x,
            other => panic!("{name}: {other:?}"),
        };
        let want = [
            ("stop.stiffness", d.stop.k),
            ("stop.damping", d.stop.c),
            ("stop.rotStiffness", d.stop.k_rot),
            ("stop.rotDamping", d.stop.c_rot),
            ("constraint.stiffness", d.constraint.k),
            ("constraint.damping", d.constraint.c),
            ("constraint.rotStiffness", d.constraint.k_rot),
            ("constraint.rotDamping", d.constraint.c_rot),
            ("friction.muStatic", f.mu_static),
            ("friction.muKinetic", f.mu_kinetic),
            ("friction.decay", f.decay),
            ("friction.R", f.radius),
            ("friction.Fint", f.f_int),
            ("friction.Mint", f.m_int),
            ("friction.stickStiffness", f.k_stick),
            ("friction.stickStiffnessR1", f.k_stick_r1),
            ("friction.stickDamping", f.c_stick),
            ("friction.stickDampingR1", f.c_stick_r1),
            ("friction.maxForce", f.max_force),
            ("cosim.maxSubstep", d.max_substep),
            ("elasticity.k2", d.k[1]),
            ("damping.c4", d.c[3]),
            ("reference.value3", d.ref_value[2]),
            ("stop.lower2", d.stop_lower[1]),
            ("stop.upper4", d.stop_upper[3]),
        ];
        for (name, x) in want {
            assert_eq!(real(name).to_bits(), x.to_bits(), "{name}");
        }
        assert_eq!(int("friction.coupling"), f.coupling);
        let linear = d.extrapolation == Extrapolation::Linear;
        assert_eq!(int("cosim.extrapolation"), i32::from(linear));
    }

    #[test]
    fn rows_are_in_value_reference_order_and_unique() {
        assert!(ROWS.windows(2).all(|w| w[0].vr < w[1].vr));
        for r in ROWS {
            let (min, max) = r.range;
            if let (Some(lo), Some(hi)) = (min, max) {
                assert!(lo <= hi, "{}", r.name);
            }
            if r.causality != Causality::Parameter {
                assert_eq!(r.range, ANY, "{}: only parameters have ranges", r.name);
            }
        }
    }
}
