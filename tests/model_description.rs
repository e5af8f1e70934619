//! Golden-file test: the committed `modelDescription/<Variant>.xml` equal what the generator
//! writes from the variable tables, and every committed variable matches its table entry.
//! After changing a table: `cargo run --bin gen_model_description` and commit the diff.

use connector_fmu::model_description::fmi2::model_description;
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

// ------------------------------------------------------------------------------------------
// What the committed XML shows, read back from the XML text alone
// ------------------------------------------------------------------------------------------

mod common;

use common::Fmu;
use connector_fmu::fmi2::exports::{fmi2SetInteger, fmi2SetReal};
use connector_fmu::fmi2::types::fmi2Status;
use std::collections::BTreeMap;

/// One ScalarVariable as the XML writes it.
#[derive(Debug, Default, Clone)]
struct XmlVar {
    attrs: BTreeMap<String, String>,
    ty: String,
    ty_attrs: BTreeMap<String, String>,
}

/// The parts of a committed model description the tests below read.
#[derive(Debug, Default)]
struct Xml {
    root: BTreeMap<String, String>,
    vars: Vec<XmlVar>,
    /// (section, index, dependencies) for Outputs and InitialUnknowns, in order.
    unknowns: Vec<(String, String, String)>,
}

fn parse(xml: &str) -> Xml {
    let mut reader = Reader::from_str(xml);
    let mut out = Xml::default();
    let mut section = String::new();
    let mut in_var = false;
    loop {
        let (e, empty) = match reader.read_event().expect("well-formed XML") {
            Event::Eof => break,
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(e) => {
                if e.name().as_ref() == b"ScalarVariable" {
                    in_var = false;
                }
                continue;
            }
            _ => continue,
        };
        let attrs: BTreeMap<String, String> = e
            .attributes()
            .flatten()
            .map(|a| {
                (
                    String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                    a.unescape_value().expect("attribute").into_owned(),
                )
            })
            .collect();
        let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        match name.as_str() {
            "fmiModelDescription" => out.root = attrs,
            "ScalarVariable" => {
                out.vars.push(XmlVar {
                    attrs,
                    ..XmlVar::default()
                });
                in_var = !empty;
            }
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" if in_var => {
                let v = out.vars.last_mut().expect("inside a ScalarVariable");
                v.ty = name;
                v.ty_attrs = attrs;
            }
            "Outputs" | "InitialUnknowns" | "Derivatives" => section = name,
            "Unknown" => out.unknowns.push((
                section.clone(),
                attrs.get("index").cloned().unwrap_or_default(),
                attrs.get("dependencies").cloned().unwrap_or_default(),
            )),
            _ => {}
        }
    }
    out
}

/// FNV-1a over the text with two seeds, formatted as a GUID: written here again so that the
/// test does not call the code it checks.
fn fnv_guid(text: &str) -> String {
    let fnv = |seed: u64| {
        text.bytes().fold(seed, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
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

#[test]
fn guid_is_a_hash_of_the_interface_the_xml_shows() {
    // The interface text is rebuilt from the committed XML only (no Rust enum or type name
    // enters it), so renaming code cannot move the GUID; changing a name, VR, causality,
    // variability, type, start, unit, range or dependency does.
    let mut guids = Vec::new();
    for v in VARIANTS {
        let x = parse(&committed(v.model_identifier));
        let mut text = format!("{} {}\n", x.root["modelName"], x.root["version"]);
        for s in &x.vars {
            let a = |k: &str| s.attrs.get(k).cloned().unwrap_or_default();
            let t = |k: &str| s.ty_attrs.get(k).cloned().unwrap_or_default();
            text.push_str(&format!(
                "{}|{}|{}|{}|{}|{}|{}|{}|{}\n",
                a("name"),
                a("valueReference"),
                a("causality"),
                a("variability"),
                s.ty,
                t("start"),
                t("unit"),
                t("min"),
                t("max")
            ));
        }
        for (section, tag) in [("Outputs", "O"), ("InitialUnknowns", "I")] {
            for (_, i, d) in x.unknowns.iter().filter(|u| u.0 == section) {
                text.push_str(&format!("{tag}{i}:{d}\n"));
            }
        }
        let guid = &x.root["guid"];
        assert_eq!(&fnv_guid(&text), guid, "{}", v.model_identifier);
        // and the binary accepts exactly that GUID
        assert_eq!(
            connector_fmu::variables::variant_by_guid(guid),
            Some(v.variant)
        );
        // a description is not interface: the text above has none
        assert!(!text.contains(&x.vars[0].attrs["description"]));
        guids.push(guid.clone());
    }
    guids.sort();
    guids.dedup();
    assert_eq!(guids.len(), VARIANTS.len());
}

#[test]
fn model_attributes_are_present_and_stable() {
    for v in VARIANTS {
        let x = parse(&committed(v.model_identifier));
        assert_eq!(x.root["version"], env!("CARGO_PKG_VERSION"));
        assert_eq!(x.root["license"], "MIT");
        assert!(x.root["author"].contains("connector_fmu"));
        assert!(x.root["copyright"].starts_with("Copyright (c) "));
        // the packaging step adds the date from the commit; the committed file stays stable
        assert!(!x.root.contains_key("generationDateAndTime"));
    }
    let license = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/LICENSE"))
        .expect("LICENSE at the repository's top");
    assert!(license.starts_with("MIT License"));
}

/// The double just below x.
fn below(x: f64) -> f64 {
    if x == 0.0 {
        -f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() - 1)
    } else {
        f64::from_bits(x.to_bits() + 1)
    }
}

/// The double just above x.
fn above(x: f64) -> f64 {
    -below(-x)
}

fn set_real(variant: connector_fmu::variables::Variant, vr: u32, x: f64) -> fmi2Status {
    let f = Fmu::new(variant);
    fmi2SetReal(f.c, &vr, 1, &x)
}

fn set_int(variant: connector_fmu::variables::Variant, vr: u32, x: i32) -> fmi2Status {
    let f = Fmu::new(variant);
    fmi2SetInteger(f.c, &vr, 1, &x)
}

#[test]
fn ranges_are_what_the_setters_accept() {
    // For every parameter of every variant, through the C ABI on a fresh instance: −1 is
    // refused exactly when the committed min is above it; the min and max themselves are
    // accepted (FMI ranges are inclusive) and the doubles (integers) just outside refused.
    // So min="0" sits on exactly the parameters the code requires to be ≥ 0.
    let mut checked = [0usize; 3];
    for v in VARIANTS {
        let x = parse(&committed(v.model_identifier));
        for s in x
            .vars
            .iter()
            .filter(|s| s.attrs["causality"] == "parameter")
        {
            let name = &s.attrs["name"];
            let vr: u32 = s.attrs["valueReference"].parse().expect("VR");
            let num = |k: &str| s.ty_attrs.get(k).map(|t| t.parse::<f64>().expect("number"));
            let (min, max) = (num("min"), num("max"));
            match s.ty.as_str() {
                "Real" => {
                    let refused = min.is_some_and(|m| m > -1.0);
                    let want = if refused {
                        fmi2Status::Error
                    } else {
                        fmi2Status::OK
                    };
                    assert_eq!(set_real(v.variant, vr, -1.0), want, "{name} = -1");
                    if let Some(m) = min {
                        assert_eq!(set_real(v.variant, vr, m), fmi2Status::OK, "{name} = min");
                        let b = below(m);
                        assert_eq!(
                            set_real(v.variant, vr, b),
                            fmi2Status::Error,
                            "{name} = {b:e}"
                        );
                        checked[0] += 1;
                    }
                    if let Some(m) = max {
                        assert_eq!(set_real(v.variant, vr, m), fmi2Status::OK, "{name} = max");
                        let a = above(m);
                        assert_eq!(
                            set_real(v.variant, vr, a),
                            fmi2Status::Error,
                            "{name} = {a:e}"
                        );
                    }
                    if refused {
                        checked[1] += 1;
                    }
                }
                "Integer" => {
                    let (lo, hi) = (
                        min.expect("Integer min") as i32,
                        max.expect("Integer max") as i32,
                    );
                    assert_eq!(set_int(v.variant, vr, lo), fmi2Status::OK, "{name} = min");
                    assert_eq!(set_int(v.variant, vr, hi), fmi2Status::OK, "{name} = max");
                    assert_eq!(
                        set_int(v.variant, vr, lo - 1),
                        fmi2Status::Error,
                        "{name} < min"
                    );
                    assert_eq!(
                        set_int(v.variant, vr, hi + 1),
                        fmi2Status::Error,
                        "{name} > max"
                    );
                    checked[2] += 1;
                }
                _ => assert!(min.is_none() && max.is_none(), "{name}"),
            }
        }
    }
    // the Planar table alone has 3 + 3 + 4 + 4 + 12 ranged Real parameters
    assert!(
        checked[0] >= 26 && checked[1] == checked[0] && checked[2] >= 6,
        "{checked:?}"
    );
}

/// Slot k = 0..5 of a per-component variable name, None for the others.
fn slot_of(name: &str) -> Option<usize> {
    let digit = name.chars().last()?.to_digit(10)? as usize;
    let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let per_k = [
        "elasticity.k",
        "damping.c",
        "reference.given",
        "reference.value",
        "stop.lower",
        "stop.upper",
        "CSLST",
    ];
    if per_k.contains(&stem) {
        return Some(digit - 1);
    }
    let trans = ["CP", "CU", "CV", "CTF", "CEF", "CVF", "CSF", "CRF"];
    let rot = ["CPR", "CUR", "CVR", "CTM", "CEM", "CVM", "CSM", "CRM"];
    if trans.contains(&stem) {
        Some(digit - 1)
    } else if rot.contains(&stem) {
        Some(digit + 2)
    } else {
        None
    }
}

fn descriptions(id: &str) -> BTreeMap<String, String> {
    parse(&committed(id))
        .vars
        .into_iter()
        .map(|s| (s.attrs["name"].clone(), s.attrs["description"].clone()))
        .collect()
}

#[test]
fn descriptions_name_each_variants_component() {
    let d: BTreeMap<&str, BTreeMap<String, String>> = VARIANTS
        .iter()
        .map(|v| (v.model_identifier, descriptions(v.model_identifier)))
        .collect();
    // per-component variables: the same description exactly where two variants have the same
    // part (translational for slots 1–3, rotational for 4–6) in that slot
    let mut compared = 0;
    for a in VARIANTS {
        for b in VARIANTS {
            if a.model_identifier >= b.model_identifier {
                continue;
            }
            for (name, da) in &d[a.model_identifier] {
                let (Some(k), Some(db)) = (slot_of(name), d[b.model_identifier].get(name)) else {
                    continue;
                };
                let same_part = if k < 3 {
                    a.connection.trans == b.connection.trans
                } else {
                    a.connection.rot == b.connection.rot
                };
                assert_eq!(
                    da == db,
                    same_part,
                    "{name}: {} {da:?} vs {} {db:?}",
                    a.model_identifier,
                    b.model_identifier
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 50, "{compared}");
    let has = |v: &str, name: &str, part: &str| {
        let text = &d[v][name];
        assert!(text.contains(part), "{v} {name}: {text:?} lacks {part:?}");
    };
    has("RadialThrust", "CP1", "radial distance r");
    has("RadialThrust", "CP3", "thrust (axial) distance l");
    has("RadialThrust", "elasticity.k1", "u1 (radial distance r)");
    has("ProjectionCartesian", "CP1", "x = e1·(x_b - x_a)");
    has("Bushing", "CPR1", "flexion angle α1");
    has("Bushing", "CPR3", "torsion angle β");
    has(
        "Bushing",
        "elasticity.k4",
        "stiffness of ur1 (flexion angle α1)",
    );
    has("Planar", "CPR1", "rotation angle α about e1a (REVOLUTE)");
    has(
        "Planar",
        "friction.muKinetic",
        "only with friction.decay > 0",
    );
    for name in ["constraint.stiffness", "CNF", "friction.Fint", "CRF1"] {
        has("Planar", name, "initial position");
        has("Planar", name, "friction.Fint");
    }
    // moments are moments, forces are forces
    for (v, ds) in &d {
        for (name, text) in ds {
            let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
            if ["CTM", "CEM", "CVM", "CSM", "CRM"].contains(&stem) {
                assert!(
                    text.contains("moment") && !text.contains("force"),
                    "{v} {name}: {text}"
                );
            }
            if ["CTF", "CEF", "CVF", "CSF"].contains(&stem) {
                assert!(
                    text.contains("force") && !text.contains("moment"),
                    "{v} {name}: {text}"
                );
            }
            assert!(
                !text.contains("component 1 position"),
                "{v} {name}: the old generic text"
            );
        }
    }
}
