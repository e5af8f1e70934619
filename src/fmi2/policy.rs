//! The FMI rules that need no pointer: how fmi2Boolean (and fmi3Boolean) values map to `bool`,
//! copying a serialized state into the importer's buffer (both versions use these), and the answers for status kinds and output
//! derivatives this FMU does not provide. Safe code, called by `exports` after `boundary` has
//! turned the pointers into slices.
#![forbid(unsafe_code)]

use super::types::fmi2StatusKind;
use crate::error::{FmuError, FmuResult};
use crate::instance::{Call, ModelInstance};
use crate::model::snapshot::Snapshot;

/// fmi2GetBoolean / fmi3GetBoolean through a `bool` buffer: `value[]` is written (0 or 1) only
/// on success.
pub(crate) fn get_booleans<T: From<bool>>(
    inst: &mut ModelInstance,
    vrs: &[u32],
    out: &mut [T],
) -> FmuResult<()> {
    let mut b = vec![false; vrs.len()];
    inst.get_boolean(vrs, &mut b)?;
    for (o, x) in out.iter_mut().zip(b) {
        *o = T::from(x);
    }
    Ok(())
}

/// fmi2SetBoolean / fmi3SetBoolean: any non-zero value is true (never a cast to `bool`).
pub(crate) fn set_booleans<T: Copy + Default + PartialEq>(
    inst: &mut ModelInstance,
    vrs: &[u32],
    values: &[T],
) -> FmuResult<()> {
    let b: Vec<bool> = values.iter().map(|&x| x != T::default()).collect();
    inst.set_boolean(vrs, &b)
}

/// fmi2SerializeFMUstate / fmi3SerializeFMUState into the caller's buffer (which must be large
/// enough; `size_fn` names the function that tells the size).
pub(crate) fn copy_serialized(
    inst: &ModelInstance,
    s: &Snapshot,
    buf: &mut [u8],
    size_fn: &str,
) -> FmuResult<()> {
    inst.own_state(s)?;
    let bytes = inst.serialize(s);
    let size = buf.len();
    let dst = buf.get_mut(..bytes.len()).ok_or_else(|| {
        FmuError::error(format!(
            "size {size} is smaller than the serialized state ({} bytes, see {size_fn})",
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
