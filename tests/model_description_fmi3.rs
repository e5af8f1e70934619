//! Golden-file test of the FMI 3.0 model descriptions: the committed
//! `modelDescription/fmi3/<Variant>.xml` equal what the generator writes from the variable
//! tables, and each describes the same model as the committed FMI 2.0 description: the same
//! variables (name, value reference, causality, variability, start, unit, min, max, description;
//! the model's author, version, copyright and license; Real →
//! Float64, Integer → Int32, Boolean → Boolean), the GUID as instantiationToken, the same unit
//! definitions and the same model structure (FMI 2.0 indices translated to value references).
//! After changing a table: `cargo run --bin gen_model_description` and commit the diff.

use connector_fmu::model_description::fmi3::{model_description, TIME_VR};
use connector_fmu::variables::VARIANTS;
use quick_xml::events::Event;
use quick_xml::reader::Reader;
use std::collections::BTreeMap;

fn committed(path: &str) -> String {
    let path = format!("{}/modelDescription/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Every element of a document as (tag, attributes, enclosing tags), in document order.
type Element = (String, BTreeMap<String, String>, Vec<String>);

fn elements(xml: &str) -> Vec<Element> {
    let mut reader = Reader::from_str(xml);
    let mut out = Vec::new();
    let mut stack: Vec<String> = Vec::new();
    loop {
        let (e, empty) = match reader.read_event().expect("well-formed XML") {
            Event::Eof => break,
            Event::End(_) => {
                stack.pop();
                continue;
            }
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            _ => continue,
        };
        let tag = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        let attrs = e
            .attributes()
            .flatten()
            .map(|a| {
                (
                    String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                    a.unescape_value().unwrap().into_owned(),
                )
            })
            .collect();
        out.push((tag.clone(), attrs, stack.clone()));
        if !empty {
            stack.push(tag);
        }
    }
    out
}

fn root(els: &[Element]) -> &BTreeMap<String, String> {
    &els.iter().find(|e| e.0 == "fmiModelDescription").unwrap().1
}

#[test]
fn committed_files_equal_the_generator() {
    for v in VARIANTS {
        assert!(
            committed(&format!("fmi3/{}.xml", v.model_identifier)) == model_description(v.variant),
            "modelDescription/fmi3/{}.xml drifted from the variable table: run `cargo run --bin gen_model_description`",
            v.model_identifier
        );
    }
}

#[test]
fn fmi3_describes_the_same_model_as_fmi2() {
    for v in VARIANTS {
        let id = v.model_identifier;
        let e2 = elements(&committed(&format!("{id}.xml")));
        let e3 = elements(&committed(&format!("fmi3/{id}.xml")));
        let (r2, r3) = (root(&e2), root(&e3));
        assert_eq!(r3["fmiVersion"], "3.0");
        assert_eq!(r3["instantiationToken"], r2["guid"], "{id}");
        for key in ["modelName", "author", "version", "copyright", "license"] {
            assert_eq!(r3.get(key), r2.get(key), "{id} {key}");
        }

        // variables: FMI 2.0 ScalarVariable + type child, against the FMI 3.0 typed element
        let mut vars2 = Vec::new();
        for (i, (tag, attrs, _)) in e2.iter().enumerate() {
            if tag == "ScalarVariable" {
                let (ty, ty_attrs, _) = &e2[i + 1];
                vars2.push((attrs.clone(), ty.clone(), ty_attrs.clone()));
            }
        }
        let vars3: Vec<_> = e3
            .iter()
            .filter(|e| e.2.last().map(String::as_str) == Some("ModelVariables"))
            .collect();
        let (time, vars3) = vars3.split_first().expect("variables");
        assert_eq!(time.0, "Float64");
        assert_eq!(time.1["causality"], "independent");
        assert_eq!(time.1["valueReference"], TIME_VR.to_string());
        assert_eq!(vars3.len(), vars2.len(), "{id}");
        for ((a2, ty2, t2), (ty3, a3, _)) in vars2.iter().zip(vars3) {
            let want_ty = match ty2.as_str() {
                "Real" => "Float64",
                "Integer" => "Int32",
                "Boolean" => "Boolean",
                other => panic!("unexpected FMI 2.0 type {other}"),
            };
            assert_eq!(ty3, want_ty, "{id} {}", a2["name"]);
            for key in [
                "name",
                "valueReference",
                "causality",
                "variability",
                "description",
            ] {
                assert_eq!(a3.get(key), a2.get(key), "{id} {} {key}", a2["name"]);
            }
            for key in ["start", "unit", "min", "max"] {
                assert_eq!(a3.get(key), t2.get(key), "{id} {} {key}", a2["name"]);
            }
            assert_ne!(a3["valueReference"], TIME_VR.to_string());
        }

        // unit definitions: the same units with the same base units
        let units = |els: &[Element]| -> Vec<(String, BTreeMap<String, String>)> {
            els.iter()
                .enumerate()
                .filter(|(_, e)| e.0 == "Unit")
                .map(|(i, e)| (e.1["name"].clone(), els[i + 1].1.clone()))
                .collect()
        };
        assert_eq!(units(&e3), units(&e2), "{id}");

        // model structure: FMI 2.0 indices (1-based over ScalarVariable) to value references
        let vr_of = |i: &str| vars2[i.parse::<usize>().unwrap() - 1].0["valueReference"].clone();
        let structure2 = |section: &str| -> Vec<(String, Vec<String>)> {
            e2.iter()
                .filter(|e| e.0 == "Unknown" && e.2.last().map(String::as_str) == Some(section))
                .map(|e| {
                    let mut deps: Vec<String> =
                        e.1["dependencies"].split_whitespace().map(vr_of).collect();
                    deps.sort_by_key(|d| d.parse::<u32>().unwrap());
                    (vr_of(&e.1["index"]), deps)
                })
                .collect()
        };
        let structure3 = |tag: &str| -> Vec<(String, Vec<String>)> {
            e3.iter()
                .filter(|e| e.0 == tag)
                .map(|e| {
                    let deps = e.1["dependencies"]
                        .split_whitespace()
                        .map(String::from)
                        .collect();
                    (e.1["valueReference"].clone(), deps)
                })
                .collect()
        };
        assert_eq!(structure3("Output"), structure2("Outputs"), "{id}");
        assert_eq!(
            structure3("InitialUnknown"),
            structure2("InitialUnknowns"),
            "{id}"
        );

        // capabilities: what works is declared: early return at the FMU's own events, no
        // Event Mode and no intermediate update
        let cs = &e3.iter().find(|e| e.0 == "CoSimulation").unwrap().1;
        assert_eq!(cs["modelIdentifier"], id);
        for (key, want) in [
            ("canHandleVariableCommunicationStepSize", "true"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "true"),
            ("providesAdjointDerivatives", "true"),
            ("providesIntermediateUpdate", "false"),
            ("mightReturnEarlyFromDoStep", "true"),
            ("canReturnEarlyAfterIntermediateUpdate", "false"),
            ("hasEventMode", "false"),
        ] {
            assert_eq!(cs[key], want, "{id} {key}");
        }
    }
}
