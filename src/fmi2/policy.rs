//! The FMI 2.0 rules that need no pointer: how fmi2Boolean values map to `bool`, copying a
//! serialized state into the importer's buffer, and the answers for status kinds and output
//! derivatives this FMU does not provide. Safe code, called by `exports` after `boundary` has
//! turned the pointers into slices.
#![forbid(unsafe_code)]

use super::types::fmi2StatusKind;
use crate::error::{FmuError, FmuResult};
use crate::instance::{Call, ModelInstance};
use crate::model::snapshot::Snapshot;

/// fmi2GetBoolean through a `bool` buffer: `value[]` is written only on success.
pub(crate) fn get_booleans(
    inst: &mut ModelInstance,
    vrs: &[u32],
    out: &mut [libc::c_int],
) -> FmuResult<()> {
    let mut b = vec![false; vrs.len()];
    inst.get_boolean(vrs, &mut b)?;
    for (o, x) in out.iter_mut().zip(b) {
        *o = libc::c_int::from(x);
    }
    Ok(())
}

/// fmi2SetBoolean: any non-zero fmi2Boolean is true (never a cast to `bool`).
pub(crate) fn set_booleans(
    inst: &mut ModelInstance,
    vrs: &[u32],
    values: &[libc::c_int],
) -> FmuResult<()> {
    let b: Vec<bool> = values.iter().map(|&x| x != 0).collect();
    inst.set_boolean(vrs, &b)
}

/// fmi2SerializeFMUstate into the caller's buffer (which must be large enough).
pub(crate) fn copy_serialized(inst: &ModelInstance, s: &Snapshot, buf: &mut [u8]) -> FmuResult<()> {
    inst.own_state(s)?;
    let bytes = inst.serialize(s);
    let size = buf.len();
    let dst = buf.get_mut(..bytes.len()).ok_or_else(|| {
        FmuError::error(format!(
            "size {size} is smaller than the serialized state ({} bytes, see fmi2SerializedFMUstateSize)",
            bytes.len()
        ))
    })?;
    dst.copy_from_slice(&bytes);
    Ok(())
}

/// The answer for status kinds this FMU does not provide (or that do not exist).
pub(crate) fn unsupported_status(kind: libc::c_int) -> FmuResult<()> {
    match fmi2StatusKind::try_from(kind) {
        Ok(k) => Err(FmuError::discard(format!(
            "status kind {} is not provided (fmi2DoStep is synchronous; only fmi2LastSuccessfulTime \
             through fmi2GetRealStatus and fmi2Terminated through fmi2GetBooleanStatus are)",
            k.name()
        ))),
        Err(k) => Err(FmuError::error(format!("unknown fmi2StatusKind {k}"))),
    }
}

/// Ok when `kind` is the one kind a fmi2Get*Status function provides (its instance method
/// checks the state); otherwise the state check and the answer for an unprovided kind.
pub(crate) fn provided_kind(
    inst: &ModelInstance,
    kind: libc::c_int,
    provided: fmi2StatusKind,
) -> FmuResult<()> {
    if fmi2StatusKind::try_from(kind) == Ok(provided) {
        return Ok(());
    }
    inst.allowed(Call::Status)?;
    unsupported_status(kind)
}

/// fmi2GetRealOutputDerivatives: nothing to provide (MaxOutputDerivativeOrder = 0); an empty
/// request is answered with OK.
pub(crate) fn no_output_derivatives(vrs: &[u32]) -> FmuResult<()> {
    match vrs.first() {
        None => Ok(()),
        Some(vr) => Err(FmuError::error(format!(
            "no output derivatives (MaxOutputDerivativeOrder = 0), asked for vr {vr}"
        ))),
    }
}
