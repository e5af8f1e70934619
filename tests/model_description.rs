//! Golden-file test: the committed `modelDescription/<Variant>.xml` equal what the generator
//! writes from the variable tables, and every committed variable matches its table entry.
//! After changing a table: `cargo run --bin gen_model_description` and commit the diff.

use connector_fmu::model_description::model_description;
use connector_fmu::variables::{table, Causality, VARIANTS};
use quick_xml::events::Event;
use quick_xml::reader::Reader;

fn committed(id: &str) -> String {
    let path = format!("{}/modelDescription/{id}.xml", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn committed_files_equal_the_generator() {
    for v in VARIANTS {
        assert!(
            committed(v.model_identifier) == model_description(v.variant),
            "modelDescription/{}.xml drifted from the variable table: run `cargo run --bin gen_model_description`",
            v.model_identifier
        );
    }
}

#[test]
fn committed_variables_match_the_table() {
    for v in VARIANTS {
        let xml = committed(v.model_identifier);
        let t = table(v.variant);
        let mut reader = Reader::from_str(&xml);
        let mut seen = Vec::new();
        let mut guid = None;
        loop {
            match reader.read_event().expect("well-formed XML") {
                Event::Eof => break,
                Event::Start(e) | Event::Empty(e) => {
                    let attr = |name: &[u8]| {
                        e.attributes()
                            .flatten()
                            .find(|a| a.key.as_ref() == name)
                            .map(|a| String::from_utf8_lossy(&a.value).into_owned())
                    };
                    match e.name().as_ref() {
                        b"fmiModelDescription" => guid = attr(b"guid"),
                        b"ScalarVariable" => seen.push((
                            attr(b"valueReference").and_then(|s| s.parse::<u32>().ok()),
                            attr(b"name"),
                            attr(b"causality"),
                        )),
                        _ => {}
                    }
                }
                _ => {}
            }
        }
        assert_eq!(guid.as_deref(), Some(t.guid.as_str()));
        assert_eq!(seen.len(), t.vars.len(), "{}", v.model_identifier);
        for ((vr, name, causality), spec) in seen.iter().zip(&t.vars) {
            assert_eq!(*vr, Some(spec.vr));
            assert_eq!(name.as_deref(), Some(spec.name.as_str()));
            let c = match spec.causality {
                Causality::Parameter => "parameter",
                Causality::Input => "input",
                Causality::Output => "output",
            };
            assert_eq!(causality.as_deref(), Some(c));
        }
    }
}
