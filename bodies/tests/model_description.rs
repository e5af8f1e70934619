//! The committed model descriptions (bodies/modelDescription/Body.xml and fmi3/Body.xml) equal
//! what the generator writes from the variable table today, and read back with quick-xml they
//! declare every row of the table (name, value reference, causality, variability, type) and the
//! GUID the binary accepts. Regenerate with `cargo run --bin gen_body_model_description`.
//! Uses the crate's model_description and variables modules.

use body_fmu::model_description::{fmi2, fmi3};
use body_fmu::variables::{guid, Causality, Variability, VARS};
use quick_xml::events::Event;
use std::collections::BTreeMap;
use std::path::Path;

fn committed(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn assert_same(rel: &str, generated: &str) {
    let text = committed(rel);
    if text != generated {
        let line = text
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .map_or_else(|| "(length)".to_string(), |i| format!("line {}", i + 1));
        panic!("{rel} differs from the generator's output at {line}; run cargo run --bin gen_body_model_description");
    }
}

#[test]
fn committed_model_descriptions_equal_the_generator() {
    assert_same("modelDescription/Body.xml", &fmi2::model_description());
    assert_same("modelDescription/fmi3/Body.xml", &fmi3::model_description());
}

/// (element name, attributes) of every element of an XML text.
fn elements(text: &str) -> Vec<(String, BTreeMap<String, String>)> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut out = Vec::new();
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Start(e) | Event::Empty(e) => {
                let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                let attrs = e
                    .attributes()
                    .map(|a| {
                        let a = a.expect("attribute");
                        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
                        (key, a.unescape_value().expect("value").into_owned())
                    })
                    .collect();
                out.push((name, attrs));
            }
            Event::Eof => return out,
            _ => {}
        }
    }
}

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Fixed => "fixed",
        Variability::Continuous => "continuous",
        // not in the Body's table (the enum is the connector's too)
        Variability::Tunable | Variability::Discrete => "none of the Body's",
    }
}

#[test]
fn the_committed_fmi2_description_declares_every_row_of_the_table() {
    let els = elements(&committed("modelDescription/Body.xml"));
    assert_eq!(els[0].1["guid"], guid());
    let vars: Vec<_> = els.iter().filter(|(n, _)| n == "ScalarVariable").collect();
    let types: Vec<_> = els
        .iter()
        .filter(|(n, _)| n == "Real" || n == "Integer")
        .collect();
    assert_eq!(vars.len(), VARS.len());
    assert_eq!(types.len(), VARS.len());
    for ((v, (_, a)), (ty, t)) in VARS.iter().zip(&vars).zip(&types) {
        assert_eq!(a["name"], v.name);
        assert_eq!(a["valueReference"], v.vr.to_string());
        assert_eq!(a["causality"], causality(v.causality));
        assert_eq!(a["variability"], variability(v.variability));
        assert_eq!(ty, if v.is_integer() { "Integer" } else { "Real" });
        assert_eq!(t.get("start").is_some(), v.start.is_some(), "{}", v.name);
    }
    let outputs = VARS
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .count();
    let unknowns: Vec<_> = els.iter().filter(|(n, _)| n == "Unknown").collect();
    assert_eq!(unknowns.len(), 2 * outputs);
    assert!(unknowns[..outputs]
        .iter()
        .all(|(_, a)| a["dependencies"].is_empty()));
}

#[test]
fn the_committed_fmi3_description_declares_time_and_every_row() {
    let els = elements(&committed("modelDescription/fmi3/Body.xml"));
    assert_eq!(els[0].1["instantiationToken"], guid());
    let vars: Vec<_> = els
        .iter()
        .filter(|(n, _)| n == "Float64" || n == "Int32")
        .collect();
    assert_eq!(vars.len(), VARS.len() + 1);
    assert_eq!(
        (
            vars[0].1["name"].as_str(),
            vars[0].1["valueReference"].as_str()
        ),
        ("time", "0")
    );
    for (v, (ty, a)) in VARS.iter().zip(&vars[1..]) {
        assert_eq!(a["name"], v.name);
        assert_eq!(a["valueReference"], v.vr.to_string());
        assert_eq!(a["causality"], causality(v.causality));
        assert_eq!(ty, if v.is_integer() { "Int32" } else { "Float64" });
    }
    let cs = els
        .iter()
        .find(|(n, _)| n == "CoSimulation")
        .expect("CoSimulation");
    for (flag, want) in [
        ("canGetAndSetFMUState", "true"),
        ("canSerializeFMUState", "true"),
        ("providesDirectionalDerivatives", "false"),
        ("mightReturnEarlyFromDoStep", "false"),
        ("hasEventMode", "false"),
    ] {
        assert_eq!(cs.1[flag], want, "{flag}");
    }
}
