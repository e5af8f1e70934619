//! THE variable tables: every variable of every variant declared once, with its value
//! reference, name, causality, variability, type, start, unit and description. The model
//! descriptions (`modelDescription/<Variant>.xml`), the get/set dispatch, the allowed-set
//! checks and the start values all come from here.
//!
//! A variant composes a translational and a rotational part (`ConnectionType`); its table is
//! the families below filtered by the components and node quantities that the type uses, so a
//! new pairing costs one `VARIANTS` entry.
//!
//! Value references are stable across variants: the same variable has the same VR everywhere.

use crate::physics::kinematics::{ConnectionType, Role, Rotational, Translational};
use std::sync::OnceLock;

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

/// FMI causality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// parameter
    Parameter,
    /// input
    Input,
    /// output
    Output,
}

/// FMI variability.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// fixed: set before initialization ends
    Fixed,
    /// tunable: may change between steps
    Tunable,
    /// discrete (Integer outputs)
    Discrete,
    /// continuous
    Continuous,
}

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
    /// Node input: node 0 = a, 1 = b; idx 0..2 r, 3..6 q (w, x, y, z), 7..9 v, 10..12 ω.
    Input {
        /// node
        node: u8,
        /// index within the node's 13 inputs
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

/// One scalar variable.
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
    /// description
    pub description: String,
    /// input dependencies (outputs only)
    pub deps: Deps,
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
    /// GUID: a hash of the table, so any interface change changes it.
    pub guid: String,
}

impl Table {
    /// The variable with value reference `vr`.
    #[inline]
    pub fn get(&self, vr: u32) -> Option<&VarSpec> {
        let i = (*self.index.get(vr as usize)?)?;
        self.vars.get(i as usize)
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

const COMP_OUTS: [(CompOut, &str, &str, &str, Deps); 8] = [
    (
        CompOut::Position,
        "CP",
        "CPR",
        "position (x, y, z, r, l / α1, α2, β, α)",
        Deps::Pose,
    ),
    (
        CompOut::Motion,
        "CU",
        "CUR",
        "motion from the initial state",
        Deps::Pose,
    ),
    (
        CompOut::Velocity,
        "CV",
        "CVR",
        "relative velocity",
        Deps::All,
    ),
    (
        CompOut::Total,
        "CTF",
        "CTM",
        "total force in the connector",
        Deps::All,
    ),
    (CompOut::Elastic, "CEF", "CEM", "elastic force", Deps::Pose),
    (CompOut::Viscous, "CVF", "CVM", "viscous force", Deps::All),
    (CompOut::Friction, "CSF", "CSM", "friction force", Deps::All),
    (
        CompOut::Reaction,
        "CRF",
        "CRM",
        "constraint and stop reaction",
        Deps::All,
    ),
];

/// Builds the table of one variant from the families below.
fn build(spec: &'static VariantSpec) -> Table {
    let ct = spec.connection;
    let roles = ct.roles();
    let planar = ct.rot == Rotational::Revolute;
    let mut vars: Vec<VarSpec> = Vec::new();
    let mut push = |vr: u32,
                    name: String,
                    field: Field,
                    causality: Causality,
                    variability: Variability,
                    start: Start,
                    unit: &'static str,
                    description: String,
                    deps: Deps| {
        vars.push(VarSpec {
            vr,
            name,
            field,
            causality,
            variability,
            start,
            unit,
            description,
            deps,
        })
    };
    use Causality::*;
    use Variability::*;

    // ---- inputs: node poses and twists in W
    let node_quantities: [(&str, &str, u8, u8, &str); 4] = [
        ("r", "position", 0, 3, "m"),
        (
            "q",
            "orientation quaternion (scalar first, node-local to W)",
            3,
            4,
            "1",
        ),
        ("v", "velocity", 7, 3, "m/s"),
        ("w", "angular velocity in W", 10, 3, "rad/s"),
    ];
    for node in 0..2u8 {
        let n = ["a", "b"][node as usize];
        let uses_q = if node == 0 {
            ct.uses_orientation_a()
        } else {
            ct.uses_orientation_b()
        };
        for (q, what, first, count, unit) in node_quantities {
            let needed = match q {
                "r" | "v" => ct.uses_positions(),
                _ => uses_q,
            };
            if !needed {
                continue;
            }
            for j in 0..count {
                let idx = first + j;
                let name = if q == "q" {
                    format!("{n}.q.{}", ["w", "x", "y", "z"][j as usize])
                } else {
                    format!("{n}.{q}[{}]", j + 1)
                };
                let start = if q == "q" && j == 0 { 1.0 } else { 0.0 };
                push(
                    1 + 20 * node as u32 + idx as u32,
                    name,
                    Field::Input { node, idx },
                    Input,
                    Continuous,
                    Start::Real(Some(start)),
                    unit,
                    format!("node {n} {what}"),
                    Deps::None,
                );
            }
        }
    }

    // ---- outputs: node loads (what the connector exerts on the node, in W)
    let loads: [(&str, &str, &str, bool); 4] = [
        ("a.f", "force on node a", "N", ct.uses_positions()),
        ("a.m", "moment on node a about its position", "N.m", true),
        ("b.f", "force on node b", "N", ct.uses_positions()),
        (
            "b.m",
            "moment on node b about its position",
            "N.m",
            ct.uses_orientation_b(),
        ),
    ];
    for (w, (name, what, unit, present)) in loads.into_iter().enumerate() {
        if !present {
            continue;
        }
        for i in 0..3u8 {
            push(
                101 + 3 * w as u32 + i as u32,
                format!("{name}[{}]", i + 1),
                Field::Load { which: w as u8, i },
                Output,
                Continuous,
                Start::Real(None),
                unit,
                format!("{what}, W component {}", i + 1),
                Deps::All,
            );
        }
    }

    // ---- outputs: per component (available ones; PLANAR also its constrained reactions)
    for (o, (out, t_name, r_name, what, deps)) in COMP_OUTS.into_iter().enumerate() {
        for (k, role) in roles.iter().enumerate() {
            let present = match role {
                Role::Available => out != CompOut::Friction || planar,
                Role::Constrained => matches!(out, CompOut::Reaction | CompOut::Total),
                Role::Absent => false,
            };
            if !present {
                continue;
            }
            let rot = k >= 3;
            let (name, i) = if rot {
                (r_name, k - 2)
            } else {
                (t_name, k + 1)
            };
            let unit = match (out, rot) {
                (CompOut::Position | CompOut::Motion, false) => "m",
                (CompOut::Position | CompOut::Motion, true) => "rad",
                (CompOut::Velocity, false) => "m/s",
                (CompOut::Velocity, true) => "rad/s",
                (_, false) => "N",
                (_, true) => "N.m",
            };
            push(
                201 + 10 * o as u32 + k as u32,
                format!("{name}{i}"),
                Field::Comp { out, k: k as u8 },
                Output,
                Continuous,
                Start::Real(None),
                unit,
                format!("component {} {what}", k + 1),
                deps,
            );
        }
    }
    for (k, role) in roles.iter().enumerate() {
        if *role == Role::Available {
            push(
                281 + k as u32,
                format!("CSLST{}", k + 1),
                Field::StopStatus(k as u8),
                Output,
                Discrete,
                Start::Integer(None),
                "",
                format!(
                    "stop status of component {}: -1 lower, 0 free, +1 upper",
                    k + 1
                ),
                Deps::Pose,
            );
        }
    }

    // ---- outputs: PLANAR friction
    if planar {
        use FrictionField::*;
        let fr: [(FrictionField, &str, &str, &str); 8] = [
            (Cnf, "CNF", "N", "friction-producing normal force F_NC"),
            (
                Cnm1,
                "CNM1",
                "N.m",
                "friction-producing normal moment M_NR1",
            ),
            (Csfc, "CSFC", "N", "magnitude of the sliding friction force"),
            (
                Csmc1,
                "CSMC1",
                "N.m",
                "magnitude of the spin friction moment",
            ),
            (Slip, "friction.slip", "m", "accumulated sliding slip"),
            (SlipR1, "friction.slipR1", "rad", "accumulated spin slip"),
            (
                Status,
                "friction.status",
                "",
                "sliding: 0 no normal force, 1 stick, 2 slip",
            ),
            (
                StatusR1,
                "friction.statusR1",
                "",
                "spin: 0 no normal force, 1 stick, 2 slip",
            ),
        ];
        for (i, (f, name, unit, what)) in fr.into_iter().enumerate() {
            let int = matches!(f, Status | StatusR1);
            push(
                301 + i as u32,
                name.to_string(),
                Field::Friction(f),
                Output,
                if int { Discrete } else { Continuous },
                if int {
                    Start::Integer(None)
                } else {
                    Start::Real(None)
                },
                unit,
                what.to_string(),
                if matches!(f, Slip | SlipR1) {
                    Deps::None
                } else {
                    Deps::All
                },
            );
        }
    }

    // ---- outputs: energy
    let energies = [
        (
            "energy.stored",
            "energy stored in springs, penalties, stops and stick springs",
            Deps::Pose,
        ),
        (
            "energy.damping",
            "energy dissipated by dampers since initialization",
            Deps::None,
        ),
        (
            "energy.friction",
            "energy dissipated by friction since initialization",
            Deps::None,
        ),
        (
            "energy.stops",
            "energy dissipated by stops since initialization",
            Deps::None,
        ),
    ];
    for (i, (name, what, deps)) in energies.into_iter().enumerate() {
        if i == 2 && !planar {
            continue;
        }
        push(
            401 + i as u32,
            name.to_string(),
            Field::Energy(i as u8),
            Output,
            Continuous,
            Start::Real(None),
            "J",
            what.to_string(),
            deps,
        );
    }

    // ---- parameters per available component
    let comp_pars: [(CompPar, &str, Variability, &str); 6] = [
        (
            CompPar::Stiffness,
            "elasticity.k",
            Tunable,
            "linear stiffness",
        ),
        (CompPar::Damping, "damping.c", Tunable, "linear damping"),
        (
            CompPar::RefGiven,
            "reference.given",
            Fixed,
            "use reference.value as constitutive reference (else the initial position)",
        ),
        (
            CompPar::RefValue,
            "reference.value",
            Fixed,
            "constitutive reference length/angle",
        ),
        (
            CompPar::StopLower,
            "stop.lower",
            Tunable,
            "lower stop on the position (-INF = none)",
        ),
        (
            CompPar::StopUpper,
            "stop.upper",
            Tunable,
            "upper stop on the position (+INF = none)",
        ),
    ];
    for (p, (par, name, variability, what)) in comp_pars.into_iter().enumerate() {
        for (k, role) in roles.iter().enumerate() {
            if *role != Role::Available {
                continue;
            }
            let rot = k >= 3;
            let (start, unit) = match par {
                CompPar::Stiffness => (Start::Real(Some(0.0)), if rot { "N.m/rad" } else { "N/m" }),
                CompPar::Damping => (
                    Start::Real(Some(0.0)),
                    if rot { "N.m.s/rad" } else { "N.s/m" },
                ),
                CompPar::RefGiven => (Start::Boolean(Some(false)), ""),
                CompPar::RefValue => (Start::Real(Some(0.0)), if rot { "rad" } else { "m" }),
                CompPar::StopLower => (
                    Start::Real(Some(f64::NEG_INFINITY)),
                    if rot { "rad" } else { "m" },
                ),
                CompPar::StopUpper => (
                    Start::Real(Some(f64::INFINITY)),
                    if rot { "rad" } else { "m" },
                ),
            };
            push(
                501 + 10 * p as u32 + k as u32,
                format!("{name}{}", k + 1),
                Field::CompParam { par, k: k as u8 },
                Parameter,
                variability,
                start,
                unit,
                format!("component {}: {what}", k + 1),
                Deps::None,
            );
        }
    }

    // ---- scalar parameters
    let has_trans = roles[..3].contains(&Role::Available);
    let has_rot = roles[3..].contains(&Role::Available);
    let d = crate::physics::connector::Params::default();
    let f = d.friction;
    use ScalarPar::*;
    let scalars: [(ScalarPar, &str, Start, &str, &str, bool); 22] = [
        (
            StopK,
            "stop.stiffness",
            Start::Real(Some(d.stop.k)),
            "N/m",
            "translational stop penalty stiffness",
            has_trans,
        ),
        (
            StopC,
            "stop.damping",
            Start::Real(Some(d.stop.c)),
            "N.s/m",
            "translational stop penalty damping",
            has_trans,
        ),
        (
            StopKr,
            "stop.rotStiffness",
            Start::Real(Some(d.stop.k_rot)),
            "N.m/rad",
            "rotational stop penalty stiffness",
            has_rot,
        ),
        (
            StopCr,
            "stop.rotDamping",
            Start::Real(Some(d.stop.c_rot)),
            "N.m.s/rad",
            "rotational stop penalty damping",
            has_rot,
        ),
        (
            ConK,
            "constraint.stiffness",
            Start::Real(Some(d.constraint.k)),
            "N/m",
            "SLIDE-PLANE penalty stiffness",
            planar,
        ),
        (
            ConC,
            "constraint.damping",
            Start::Real(Some(d.constraint.c)),
            "N.s/m",
            "SLIDE-PLANE penalty damping",
            planar,
        ),
        (
            ConKr,
            "constraint.rotStiffness",
            Start::Real(Some(d.constraint.k_rot)),
            "N.m/rad",
            "REVOLUTE penalty stiffness",
            planar,
        ),
        (
            ConCr,
            "constraint.rotDamping",
            Start::Real(Some(d.constraint.c_rot)),
            "N.m.s/rad",
            "REVOLUTE penalty damping",
            planar,
        ),
        (
            MuS,
            "friction.muStatic",
            Start::Real(Some(f.mu_static)),
            "1",
            "static friction coefficient",
            planar,
        ),
        (
            MuK,
            "friction.muKinetic",
            Start::Real(Some(f.mu_kinetic)),
            "1",
            "kinetic friction coefficient",
            planar,
        ),
        (
            Decay,
            "friction.decay",
            Start::Real(Some(f.decay)),
            "s/m",
            "decay of mu with slip rate (0: mu = muStatic)",
            planar,
        ),
        (
            Radius,
            "friction.R",
            Start::Real(Some(f.radius)),
            "m",
            "characteristic puck radius R (0: bending terms ignored)",
            planar,
        ),
        (
            Fint,
            "friction.Fint",
            Start::Real(Some(f.f_int)),
            "N",
            "internal contact force F_C^int",
            planar,
        ),
        (
            Mint,
            "friction.Mint",
            Start::Real(Some(f.m_int)),
            "N.m",
            "internal contact moment M_R1^int",
            planar,
        ),
        (
            StickK,
            "friction.stickStiffness",
            Start::Real(Some(f.k_stick)),
            "N/m",
            "elastic stick stiffness of sliding",
            planar,
        ),
        (
            StickKr,
            "friction.stickStiffnessR1",
            Start::Real(Some(f.k_stick_r1)),
            "N.m/rad",
            "elastic stick stiffness of spin",
            planar,
        ),
        (
            MaxForce,
            "friction.maxForce",
            Start::Real(Some(f.max_force)),
            "N",
            "cap on the sliding friction force (+INF = none)",
            planar,
        ),
        (
            Coupling,
            "friction.coupling",
            Start::Integer(Some(f.coupling)),
            "",
            "0 separate sliding and spin (Abaqus), 1 coupled: ellipsoidal limit, disc flow",
            planar,
        ),
        (
            Extrapolation,
            "cosim.extrapolation",
            Start::Integer(Some(1)),
            "",
            "input extrapolation over a step: 0 hold, 1 linear",
            true,
        ),
        (
            MaxSubstep,
            "cosim.maxSubstep",
            Start::Real(Some(d.max_substep)),
            "s",
            "largest internal substep (0: from the path alone)",
            true,
        ),
        // added after the first release: appended so that earlier value references stay
        (
            StickC,
            "friction.stickDamping",
            Start::Real(Some(f.c_stick)),
            "N.s/m",
            "stick damping of sliding, parallel to the stick spring (0: Abaqus)",
            planar,
        ),
        (
            StickCr,
            "friction.stickDampingR1",
            Start::Real(Some(f.c_stick_r1)),
            "N.m.s/rad",
            "stick damping of spin, parallel to the stick spring (0: Abaqus)",
            planar,
        ),
    ];
    for (i, (par, name, start, unit, what, present)) in scalars.into_iter().enumerate() {
        if !present {
            continue;
        }
        let variability = if par == Coupling { Fixed } else { Tunable };
        push(
            601 + i as u32,
            name.to_string(),
            Field::Param(par),
            Parameter,
            variability,
            start,
            unit,
            what.to_string(),
            Deps::None,
        );
    }

    let max_vr = vars.iter().map(|v| v.vr).max().unwrap_or(0) as usize;
    let mut index = vec![None; max_vr + 1];
    for (i, v) in vars.iter().enumerate() {
        index[v.vr as usize] = Some(i as u16);
    }
    let guid = guid_of(spec, &vars);
    Table {
        spec,
        vars,
        index,
        guid,
    }
}

/// A GUID derived from the table (FNV-1a, 128 bits as two 64-bit lanes).
fn guid_of(spec: &VariantSpec, vars: &[VarSpec]) -> String {
    let mut text = format!("{}|{}", env!("CARGO_PKG_VERSION"), spec.model_identifier);
    for v in vars {
        text.push_str(&format!("|{:?}", v));
    }
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
}
