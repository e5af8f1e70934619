//! Regression 001 (found by the `fmi_calls` fuzz target): fmi2SerializedFMUstateSize and
//! fmi2SerializeFMUstate accepted an FMU state made by an instance of ANOTHER variant and wrote
//! it under the calling instance's model identifier, with that variant's parameter and input
//! layout. fmi2DeSerializeFMUstate then accepted the bytes and fmi2SetFMUstate restored a state
//! laundered from a foreign variant — the variant check of fmi2SetFMUstate was bypassed.
//! Fixed: both functions refuse a foreign state with fmi2Error and one message, as
//! fmi2SetFMUstate does.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::Variant;
use std::ptr::null_mut;

#[test]
fn serializing_a_state_of_another_variant_is_refused() {
    let bushing = Fmu::new(Variant::Bushing);
    let pft = Fmu::new(Variant::ProjectionFlexionTorsion);
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(bushing.c, &mut s), fmi2Status::OK);

    let n = pft.log_len();
    let mut size = 0usize;
    let status = fmi2SerializedFMUstateSize(pft.c, s, &mut size);
    assert_error_logged(&pft, n, status, "fmi2SerializedFMUstateSize");
    assert!(
        pft.log()[n].message.contains("Bushing"),
        "{:?}",
        pft.log()[n]
    );

    let mut buf = vec![0u8; 4096];
    let n = pft.log_len();
    let status = fmi2SerializeFMUstate(pft.c, s, buf.as_mut_ptr().cast(), buf.len());
    assert_error_logged(&pft, n, status, "fmi2SerializeFMUstate");
    assert!(buf.iter().all(|&b| b == 0), "nothing was written");

    // its own instance still serializes it
    assert_eq!(
        fmi2SerializedFMUstateSize(bushing.c, s, &mut size),
        fmi2Status::OK
    );
    assert!(size > 0);
    assert_eq!(fmi2FreeFMUstate(bushing.c, &mut s), fmi2Status::OK);
}
