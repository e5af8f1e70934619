//! Derivative information of the exported FMI 3.0 functions: the variable dependencies
//! (fmi3GetNumberOfVariableDependencies, fmi3GetVariableDependencies) against the FMI 2.0
//! description's model structure, and the directional derivatives, bit for bit those of the
//! FMI 2.0 twin, with adjoint derivatives that are their transpose.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `expect_error!`, `drive` of the FMI 2.0 twin) and
//! `modelDescription/<Variant>.xml` (read with quick_xml).

mod common;

use common::fmi3::*;
use connector_fmu::fmi2::exports as f2;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Causality, Start, Variability, Variant, VARIANTS};
use quick_xml::events::Event;
use quick_xml::reader::Reader;

// ------------------------------------------------------------------ dependencies

/// The FMI 2.0 description's ModelStructure as value references: (Outputs, InitialUnknowns),
/// each a list of (unknown vr, dependency vrs).
type Structure = Vec<(u32, Vec<u32>)>;

fn fmi2_structure(v: Variant) -> (Structure, Structure) {
    let id = v.spec().model_identifier;
    let path = format!("{}/modelDescription/{id}.xml", env!("CARGO_MANIFEST_DIR"));
    let xml = std::fs::read_to_string(path).unwrap();
    let mut reader = Reader::from_str(&xml);
    let mut vrs = Vec::new();
    let (mut outputs, mut initial) = (Vec::new(), Vec::new());
    let mut section = 0;
    loop {
        match reader.read_event().unwrap() {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => {
                let attr = |name: &[u8]| {
                    e.attributes()
                        .flatten()
                        .find(|a| a.key.as_ref() == name)
                        .map(|a| String::from_utf8_lossy(&a.value).into_owned())
                };
                match e.name().as_ref() {
                    b"ScalarVariable" => {
                        vrs.push(attr(b"valueReference").unwrap().parse::<u32>().unwrap())
                    }
                    b"Outputs" => section = 1,
                    b"InitialUnknowns" => section = 2,
                    b"Unknown" => {
                        let index: usize = attr(b"index").unwrap().parse().unwrap();
                        let deps: Vec<u32> = attr(b"dependencies")
                            .unwrap()
                            .split_whitespace()
                            .map(|i| vrs[i.parse::<usize>().unwrap() - 1])
                            .collect();
                        let entry = (vrs[index - 1], deps);
                        if section == 1 {
                            outputs.push(entry)
                        } else {
                            initial.push(entry)
                        }
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    (outputs, initial)
}

fn runtime_dependencies(f: &Fmu3, vr: u32) -> Vec<u32> {
    let mut n = usize::MAX;
    assert_eq!(
        fmi3GetNumberOfVariableDependencies(f.c, vr, &mut n),
        OK,
        "{:?}",
        f.log()
    );
    let (mut e_dep, mut indep, mut e_indep) = (vec![9; n], vec![0u32; n], vec![9; n]);
    let mut kinds = vec![fmi3DependencyKind::Independent; n];
    let s = fmi3GetVariableDependencies(
        f.c,
        vr,
        e_dep.as_mut_ptr(),
        indep.as_mut_ptr(),
        e_indep.as_mut_ptr(),
        kinds.as_mut_ptr(),
        n,
    );
    assert_eq!(s, OK, "{:?}", f.log());
    assert!(e_dep.iter().chain(&e_indep).all(|&i| i == 0), "scalars");
    assert!(kinds.iter().all(|&k| k == fmi3DependencyKind::Dependent));
    indep
}

#[test]
fn variable_dependencies_follow_the_fmi2_model_structure() {
    for spec in VARIANTS {
        let (outputs, initial) = fmi2_structure(spec.variant);
        let f = Fmu3::new(spec.variant);
        f.enter_init();
        for (vr, deps) in &initial {
            let mut want = deps.clone();
            want.sort_unstable();
            assert_eq!(
                runtime_dependencies(&f, *vr),
                want,
                "{:?} vr {vr}",
                spec.variant
            );
        }
        f.exit_init();
        for (vr, deps) in &outputs {
            let mut want = deps.clone();
            want.sort_unstable();
            assert_eq!(
                runtime_dependencies(&f, *vr),
                want,
                "{:?} vr {vr}",
                spec.variant
            );
        }
        let input = table(spec.variant)
            .vars
            .iter()
            .find(|x| x.causality == Causality::Input)
            .unwrap()
            .vr;
        let mut n = 0;
        expect_error!(
            f,
            "fmi3GetNumberOfVariableDependencies",
            fmi3GetNumberOfVariableDependencies(f.c, input, &mut n)
        );
        let out = outputs[0].0;
        let mut k = vec![fmi3DependencyKind::Independent; 1];
        let (mut a, mut b, mut c) = ([0usize; 1], [0u32; 1], [0usize; 1]);
        if outputs[0].1.len() != 1 {
            expect_error!(
                f,
                "fmi3GetVariableDependencies",
                fmi3GetVariableDependencies(
                    f.c,
                    out,
                    a.as_mut_ptr(),
                    b.as_mut_ptr(),
                    c.as_mut_ptr(),
                    k.as_mut_ptr(),
                    1
                )
            );
        }
    }
}

// ------------------------------------------------------------------ directional and adjoint derivatives

#[test]
fn directional_derivatives_equal_fmi2_and_adjoints_are_their_transpose() {
    for spec in VARIANTS {
        let v = spec.variant;
        let (a, b) = drive(v, &|set| {
            for k in 1..=6 {
                set(&format!("elasticity.k{k}"), 1e3 * k as f64);
                set(&format!("damping.c{k}"), 2.0);
            }
            set("friction.muStatic", 0.3);
            set("friction.Fint", 5.0);
            set("b.r[1]", 0.01);
            set("b.r[2]", -0.004);
            set("b.v[1]", 0.2);
        });
        let unknowns: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| {
                x.causality == Causality::Output && x.variability == Variability::Continuous
            })
            .filter(|x| matches!(x.start, Start::Real(_)))
            .map(|x| x.vr)
            .collect();
        let knowns: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Input)
            .map(|x| x.vr)
            .collect();
        let (nu, nk) = (unknowns.len(), knowns.len());
        // J column by column through both versions: bit for bit equal
        let mut jac = vec![vec![0.0; nk]; nu];
        for (j, &k) in knowns.iter().enumerate() {
            let (mut d2, mut d3) = (vec![0.0; nu], vec![0.0; nu]);
            let s2 = f2::fmi2GetDirectionalDerivative(
                a.0.c,
                unknowns.as_ptr(),
                nu,
                &k,
                1,
                &1.0,
                d2.as_mut_ptr(),
            );
            assert_eq!(s2, fmi2Status::OK);
            let s3 = fmi3GetDirectionalDerivative(
                b.c,
                unknowns.as_ptr(),
                nu,
                &k,
                1,
                &1.0,
                1,
                d3.as_mut_ptr(),
                nu,
            );
            assert_eq!(s3, OK, "{:?}", b.log());
            for i in 0..nu {
                assert_eq!(
                    d2[i].to_bits(),
                    d3[i].to_bits(),
                    "{v:?} ∂{}/∂{k}",
                    unknowns[i]
                );
                jac[i][j] = d3[i];
            }
        }
        // a seed direction with all entries non-zero
        let seed: Vec<f64> = (0..nu)
            .map(|i| 1.0 + 0.37 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let mut adj = vec![f64::NAN; nk];
        let s = fmi3GetAdjointDerivative(
            b.c,
            unknowns.as_ptr(),
            nu,
            knowns.as_ptr(),
            nk,
            seed.as_ptr(),
            nu,
            adj.as_mut_ptr(),
            nk,
        );
        assert_eq!(s, OK, "{:?}", b.log());
        let mut checked = 0;
        for j in 0..nk {
            let want: f64 = (0..nu).map(|i| jac[i][j] * seed[i]).sum();
            let scale: f64 = (0..nu).map(|i| (jac[i][j] * seed[i]).abs()).sum();
            assert!(
                (adj[j] - want).abs() <= 1e-12 * scale,
                "{v:?} known {}: adjoint {} vs Jᵀv {want}",
                knowns[j],
                adj[j]
            );
            checked += usize::from(want != 0.0);
        }
        assert!(checked > 0, "{v:?}: a non-trivial Jacobian");
    }
}
