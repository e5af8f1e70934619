//! Every output read at initialization, with each behaviour on, through the C ABI: nothing
//! has moved and no time has passed, so motions, accumulated slip and dissipated energies are
//! exactly zero, friction forces lie within their limits (zero without normal force), and the
//! outputs read in Initialization Mode are those read right after fmi2ExitInitializationMode.
//!
//! Regression: with a stick damper, the outputs after fmi2ExitInitializationMode showed the
//! damper's overload at the initial rates as plastic slip (friction.slip = c·v/k, negative
//! friction dissipation, a friction force without normal force), as if a substep had been
//! taken.

mod common;
use common::Fmu;
use connector_fmu::variables::{table, VARIANTS};

/// One behaviour switched on by its parameters (those the variant has).
struct Behaviour {
    name: &'static str,
    params: &'static [(&'static str, f64)],
}

const BEHAVIOURS: &[Behaviour] = &[
    Behaviour {
        name: "elasticity",
        params: &[
            ("elasticity.k1", 1e3),
            ("elasticity.k2", 2e3),
            ("elasticity.k3", 3e3),
            ("elasticity.k4", 40.0),
            ("elasticity.k5", 50.0),
            ("elasticity.k6", 60.0),
        ],
    },
    Behaviour {
        name: "damping",
        params: &[
            ("damping.c1", 10.0),
            ("damping.c2", 20.0),
            ("damping.c3", 30.0),
            ("damping.c4", 0.4),
            ("damping.c5", 0.5),
            ("damping.c6", 0.6),
        ],
    },
    // the nodes start inside the stops: the stop springs are loaded from the start
    Behaviour {
        name: "stops",
        params: &[
            ("stop.upper1", 0.05),
            ("stop.upper2", 0.01),
            ("stop.lower3", 0.04),
            ("stop.upper4", 0.05),
            ("stop.lower5", -0.01),
            ("stop.upper6", 0.01),
            ("stop.stiffness", 1e4),
            ("stop.damping", 10.0),
            ("stop.rotStiffness", 100.0),
            ("stop.rotDamping", 1.0),
        ],
    },
    // the case: no normal force, a stick damper and a sliding velocity
    Behaviour {
        name: "friction, stick damper, no normal force",
        params: &[
            ("friction.muStatic", 0.3),
            ("friction.stickDamping", 100.0),
            ("friction.stickDampingR1", 1.0),
        ],
    },
    // normal force from F_int: the damper force c·v exceeds μ_s·F_NC, so the start is on the
    // limit (slipping), with no slip taken
    Behaviour {
        name: "friction, stick damper overloaded",
        params: &[
            ("friction.muStatic", 0.3),
            ("friction.muKinetic", 0.2),
            ("friction.decay", 5.0),
            ("friction.R", 0.05),
            ("friction.Fint", 2.0),
            ("friction.Mint", 0.1),
            ("friction.stickDamping", 100.0),
            ("friction.stickDampingR1", 1.0),
        ],
    },
    Behaviour {
        name: "friction, stick damper within the limit",
        params: &[
            ("friction.muStatic", 0.5),
            ("friction.R", 0.05),
            ("friction.Fint", 1e3),
            ("friction.Mint", 10.0),
            ("friction.stickDamping", 10.0),
            ("friction.stickDampingR1", 0.1),
        ],
    },
    Behaviour {
        name: "friction coupled, stick damper overloaded",
        params: &[
            ("friction.muStatic", 0.3),
            ("friction.R", 0.05),
            ("friction.Fint", 2.0),
            ("friction.stickDamping", 100.0),
            ("friction.stickDampingR1", 1.0),
        ],
    },
];

/// Nodes off the origin, b turned, both moving, so that every component has a position and a
/// rate (positions within the stops' reach above).
const INPUTS: &[(&str, f64)] = &[
    ("a.r[1]", 0.01),
    ("a.r[2]", -0.02),
    ("a.r[3]", 0.005),
    ("b.r[1]", 0.1),
    ("b.r[2]", 0.02),
    ("b.r[3]", 0.03),
    // turned by 0.1 rad about x, the revolute axis of PLANAR (no constraint violation, so its
    // penalty springs store nothing); a flexion and a torsion for the projection types
    ("b.q.w", 0.998_750_260_394_966),
    ("b.q.x", 0.049_979_169_270_678),
    ("a.v[1]", 0.05),
    ("b.v[1]", 0.3),
    ("b.v[2]", 0.1 * std::f64::consts::PI),
    ("b.v[3]", -0.2),
    ("a.w[3]", 0.1),
    ("b.w[1]", 0.5),
    ("b.w[2]", 0.2),
    ("b.w[3]", -0.4),
];

struct Read {
    reals: Vec<(String, f64)>,
    ints: Vec<(String, i32)>,
}

impl Read {
    fn real(&self, name: &str) -> Option<f64> {
        self.reals.iter().find(|(n, _)| n == name).map(|&(_, x)| x)
    }
    fn int(&self, name: &str) -> Option<i32> {
        self.ints.iter().find(|(n, _)| n == name).map(|&(_, x)| x)
    }
}

fn read_all(f: &Fmu) -> Read {
    let names = |vrs: &[u32]| -> Vec<String> {
        let t = table(f.variant);
        vrs.iter()
            .map(|&vr| t.get(vr).map(|v| v.name.clone()).unwrap_or_default())
            .collect()
    };
    let (rv, iv) = (f.outputs(false), f.outputs(true));
    Read {
        reals: names(&rv).into_iter().zip(f.get_reals(&rv)).collect(),
        ints: names(&iv).into_iter().zip(f.get_integers(&iv)).collect(),
    }
}

fn check(variant: &str, b: &Behaviour, r: &Read) {
    let ctx = format!("{variant}, {}", b.name);
    for (n, x) in &r.reals {
        assert!(x.is_finite(), "{ctx}: {n} = {x}");
        // nothing has moved: motions from the initial state are zero
        if n.starts_with("CU") {
            assert_eq!(*x, 0.0, "{ctx}: {n}");
        }
    }
    // no time has passed: nothing accumulated, nothing dissipated
    for n in [
        "energy.damping",
        "energy.friction",
        "energy.stops",
        "friction.slip",
        "friction.slipR1",
    ] {
        if let Some(x) = r.real(n) {
            assert_eq!(x, 0.0, "{ctx}: {n}");
        }
    }
    // friction forces within their limits; none without normal force
    let param = |n: &str| b.params.iter().find(|(p, _)| *p == n).map(|&(_, x)| x);
    if let (Some(cnf), Some(csfc)) = (r.real("CNF"), r.real("CSFC")) {
        let mu = param("friction.muStatic").unwrap_or(0.0);
        let (cnm1, csmc1) = (
            r.real("CNM1").unwrap_or(0.0),
            r.real("CSMC1").unwrap_or(0.0),
        );
        let coupled = b.name.contains("coupled");
        if coupled {
            let rho = 2.0 / 3.0 * param("friction.R").unwrap_or(0.0);
            let n = (csfc * csfc + (csmc1 / rho).powi(2)).sqrt();
            assert!(n <= mu * cnf * (1.0 + 1e-12), "{ctx}: {n} > μ·{cnf}");
        } else {
            // 1e-12: the return puts the force on the limit to round-off
            assert!(
                csfc <= mu * cnf * (1.0 + 1e-12),
                "{ctx}: CSFC {csfc} > μ·{cnf}"
            );
            assert!(
                csmc1 <= mu * cnm1 * (1.0 + 1e-12),
                "{ctx}: CSMC1 {csmc1} > μ·{cnm1}"
            );
        }
        if cnf == 0.0 {
            assert_eq!(csfc, 0.0, "{ctx}: friction force without normal force");
            assert_eq!(r.real("CSF2"), Some(0.0), "{ctx}");
            assert_eq!(r.real("CSF3"), Some(0.0), "{ctx}");
            assert_eq!(r.int("friction.status"), Some(0), "{ctx}");
        }
        if param("friction.stickDamping").is_some() && cnf > 0.0 {
            // the damper force at the initial rate, c·|v|, where it is within the limit (μ_s);
            // beyond it the contact slips from the start at the speed v, on the limit with μ
            // at that speed (μ_k + (μ_s − μ_k) exp(−d_c v) with a decay)
            let c = param("friction.stickDamping").unwrap_or(0.0);
            let v = (r.real("CV2").unwrap_or(0.0)).hypot(r.real("CV3").unwrap_or(0.0));
            let mu_k = param("friction.muKinetic").unwrap_or(mu);
            let decay = param("friction.decay").unwrap_or(0.0);
            let mu_v = if decay > 0.0 {
                mu_k + (mu - mu_k) * (-decay * v).exp()
            } else {
                mu
            };
            let expect = if c * v > mu * cnf { mu_v * cnf } else { c * v };
            if !coupled {
                assert!(
                    (csfc - expect).abs() <= 1e-12 * expect,
                    "{ctx}: CSFC {csfc}, expected {expect}"
                );
                let status = if c * v > mu * cnf { 2 } else { 1 };
                assert_eq!(r.int("friction.status"), Some(status), "{ctx}");
            }
        }
    }
    // the stops' springs hold what the start penetration stores; the rest stores nothing
    // (references are the initial positions, the stick springs start unstretched)
    let mut stored = 0.0;
    for k in 1..=6 {
        let pos = if k <= 3 {
            r.real(&format!("CP{k}"))
        } else {
            r.real(&format!("CPR{}", k - 3))
        };
        let Some(c) = pos else { continue };
        let ks = if k <= 3 {
            param("stop.stiffness")
        } else {
            param("stop.rotStiffness")
        };
        let lower = param(&format!("stop.lower{k}")).unwrap_or(f64::NEG_INFINITY);
        let upper = param(&format!("stop.upper{k}")).unwrap_or(f64::INFINITY);
        let pen = (c - upper).max(lower - c).max(0.0);
        stored += 0.5 * ks.unwrap_or(0.0) * pen * pen;
    }
    let e = r.real("energy.stored").unwrap_or(0.0);
    assert!(
        (e - stored).abs() <= 1e-12 * stored.max(1e-300),
        "{ctx}: energy.stored {e}, expected {stored}"
    );
}

#[test]
fn every_output_at_initialization_with_each_behaviour_on() {
    let mut checked = 0;
    for spec in VARIANTS.iter() {
        for b in BEHAVIOURS {
            let f = Fmu::new(spec.variant);
            if !b.params.iter().any(|(n, _)| f.has(n)) {
                continue;
            }
            for &(n, x) in b.params {
                f.set_real_if(n, x);
            }
            f.enter_init();
            for &(n, x) in INPUTS {
                f.set_real_if(n, x);
            }
            let during = read_all(&f);
            check(spec.model_identifier, b, &during);
            f.exit_init();
            let after = read_all(&f);
            check(spec.model_identifier, b, &after);
            // outputs follow the inputs in Initialization Mode: the same values after it
            for ((n, x), (_, y)) in during.reals.iter().zip(&after.reals) {
                assert_eq!(x.to_bits(), y.to_bits(), "{}: {n}", spec.model_identifier);
            }
            assert_eq!(during.ints, after.ints, "{}", spec.model_identifier);
            checked += 1;
        }
    }
    // elasticity, damping, stops on every variant, four friction cases on Planar
    assert_eq!(checked, 5 * 3 + 4);
}
