//! The behaviour sets of a case: `Case` (a variant, behaviours off or on, compared with the
//! floor or not), `params_on` (springs and dampers of tests/data/parameter_sets.json, or PLANAR's
//! friction, and stops placed from a pre-pass over one period), the components that get a stop
//! and their status outputs. Uses `scenes`, `instances`, `fmus` and `timing` (the pre-pass), and
//! the test support module.

use crate::fmus::REAL;
use crate::instances::{ok, real_instance};
use crate::scenes::{shared, PERIOD};
use crate::support;
use crate::timing::rounds;
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::variables::{table, Variant};

/// One benchmark configuration.
pub struct Case {
    pub variant: Variant,
    pub on: bool,
    /// Compared with the floor (Bushing and Planar "on").
    pub direct: bool,
    pub label: &'static str,
}

/// The Abaqus components (1..6) the variant makes available.
pub fn components(v: Variant) -> Vec<usize> {
    table(v)
        .vars
        .iter()
        .filter_map(|x| x.name.strip_prefix("elasticity.k"))
        .filter_map(|k| k.parse().ok())
        .collect()
}

/// Components that get a stop in the "on" configuration (hit twice per period).
pub fn stop_components(v: Variant) -> &'static [usize] {
    match v {
        Variant::Bushing => &[1, 4],
        Variant::Planar => &[2],
        Variant::ProjectionCartesian => &[1],
        Variant::ProjectionFlexionTorsion => &[4],
        Variant::RadialThrust => &[1],
    }
}

/// CP<i> / CPR<i> of Abaqus component k.
pub fn position_name(k: usize) -> String {
    if k <= 3 {
        format!("CP{k}")
    } else {
        format!("CPR{}", k - 3)
    }
}

/// The "on" parameters of a variant (stops placed from a pre-pass over one period).
pub fn params_on(v: Variant) -> Vec<(String, f64)> {
    let mut p: Vec<(String, f64)> = vec![];
    if v == Variant::Planar {
        // `planar_friction` of tests/data/parameter_sets.json (tests/python PLANAR_FRICTION)
        p.extend(shared().planar_friction.values.iter().cloned());
    } else {
        // `spring_damper` of tests/data/parameter_sets.json (tests/python spring_damper_params)
        let sd = &shared().spring_damper;
        for k in components(v) {
            let (kk, cc) = if k <= 3 {
                (sd.k_translational[k - 1], sd.c_translational[k - 1])
            } else {
                (sd.k_rotational[k - 4], sd.c_rotational[k - 4])
            };
            p.push((format!("elasticity.k{k}"), kk));
            p.push((format!("damping.c{k}"), cc));
        }
    }
    // stops at 70 % of each component's excursion along the path (positions are kinematic, so
    // a pre-pass with the defaults gives them)
    let stops = stop_components(v);
    let mut pre = real_instance(v, &[]);
    let vrs: Vec<u32> = stops
        .iter()
        .map(|&k| support::vr(v, &position_name(k)))
        .collect();
    let mut lo = vec![f64::INFINITY; stops.len()];
    let mut hi = vec![f64::NEG_INFINITY; stops.len()];
    let mut x = vec![0.0; stops.len()];
    for _ in 0..PERIOD {
        rounds(&REAL, &mut pre, 1);
        ok(
            pre.env,
            fmi::fmi2GetReal(pre.c, vrs.as_ptr(), vrs.len(), x.as_mut_ptr()),
            "positions",
        );
        for i in 0..x.len() {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    for (i, &k) in stops.iter().enumerate() {
        p.push((format!("stop.upper{k}"), lo[i] + 0.7 * (hi[i] - lo[i])));
    }
    p.extend([
        ("stop.stiffness".into(), 1.0e5),
        ("stop.damping".into(), 10.0),
        ("stop.rotStiffness".into(), 500.0),
        ("stop.rotDamping".into(), 1.0),
    ]);
    p.retain(|(n, _)| table(v).vars.iter().any(|x| &x.name == n));
    p
}

pub fn stop_status_vrs(v: Variant) -> Vec<u32> {
    stop_components(v)
        .iter()
        .map(|k| support::vr(v, &format!("CSLST{k}")))
        .collect()
}
