//! The state of one program and the interpreter's plumbing: `Program` (up to two instances,
//! four FMU-state slots, two serialized-state buffers, the trace), `call` (one call with the
//! checks of `invariants.rs`), the choice of value references, the instantiation header's GUID
//! and instance name, `run` with its clean-up, and lookups in the variable table. Uses `api`,
//! `bytes`, `support` (log keys, GUIDs) and the variable table.

use super::api::{Api, Handle, St, OK};
use super::bytes::Bytes;
use super::invariants::state_bytes;
use super::{support, trace_wanted};
use connector_fmu::variables::{table, Causality, Start, VarSpec, Variant, VARIANTS};
use std::ffi::CString;
use std::marker::PhantomData;
use std::ptr::null_mut;

/// Upper bound of DoStep calls per program (each can take up to MAX_SUBSTEPS substeps).
pub(super) const MAX_STEPS: usize = 24;
/// Upper bound of operations per program.
const MAX_OPS: usize = 400;

pub struct Inst {
    pub(super) c: Handle,
    pub(super) variant: Variant,
    /// Whether the instance has a logger (FMI 3.0 allows none: invariant 2 is then skipped).
    pub(super) logger: bool,
    /// earlyReturnAllowed at instantiation (FMI 3.0).
    pub(super) early_allowed: bool,
}

/// A state slot and the variant of the instance that produced it.
#[derive(Clone, Copy)]
pub(super) struct Slot {
    pub(super) s: Handle,
    pub(super) variant: Variant,
}

/// The componentEnvironment key a program's instances log under; its messages are dropped with it.
pub(super) struct Env(pub(super) usize);

impl Drop for Env {
    fn drop(&mut self) {
        support::forget_log(self.0);
    }
}

pub struct Program<'a, A: Api> {
    pub(super) env: Env,
    pub(super) b: Bytes<'a>,
    pub(super) inst: [Option<Inst>; 2],
    pub(super) slots: [Slot; 4],
    pub(super) bufs: Vec<(Vec<u8>, Variant)>,
    pub(super) steps: usize,
    pub(super) trace: Vec<String>,
    /// FMI 3.0 DoSteps that returned early at an event (what `run` returns).
    pub(super) early_returns: usize,
    api: PhantomData<A>,
}

pub(super) fn variant_of(i: usize) -> Variant {
    VARIANTS[i % VARIANTS.len()].variant
}

pub(super) fn reals_of(v: Variant, pred: impl Fn(&VarSpec) -> bool) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| matches!(x.start, Start::Real(_)) && pred(x))
        .map(|x| x.vr)
        .collect()
}

pub(super) fn is_real_output(v: Variant, vr: u32) -> bool {
    table(v)
        .get(vr)
        .is_some_and(|x| x.causality == Causality::Output && matches!(x.start, Start::Real(_)))
}

/// Value reference of the variant's output `name` when it has one.
pub(super) fn output_vr(v: Variant, name: &str) -> Option<u32> {
    table(v)
        .vars
        .iter()
        .find(|x| x.name == name && x.causality == Causality::Output)
        .map(|x| x.vr)
}

impl<'a, A: Api> Program<'a, A> {
    pub(super) fn new(data: &'a [u8]) -> Self {
        Program {
            env: Env(support::new_env()),
            b: Bytes::new(data),
            inst: [None, None],
            slots: [Slot {
                s: null_mut(),
                variant: Variant::Bushing,
            }; 4],
            bufs: Vec::new(),
            steps: 0,
            trace: Vec::new(),
            early_returns: 0,
            api: PhantomData,
        }
    }

    pub(super) fn fail(&self, what: String) -> ! {
        if trace_wanted() {
            eprintln!("full program trace: {:#?}", self.trace);
        }
        panic!(
            "invariant violated: {what}\nprogram trace (last 40 ops): {:#?}",
            &self.trace[self.trace.len().saturating_sub(40)..]
        );
    }

    /// Runs one call on instance i with invariant checks (state compared on Error).
    pub(super) fn call(&mut self, i: usize, fname: &str, f: impl FnOnce(Handle) -> St) -> St {
        let Some(inst) = self.inst[i].as_ref() else {
            return St::Error;
        };
        let c = inst.c;
        let before = state_bytes::<A>(inst);
        let n0 = support::log_len(self.env.0);
        let s = f(c);
        self.check(i, fname, n0, s, before);
        s
    }

    pub(super) fn variant(&self, i: usize) -> Option<Variant> {
        self.inst[i].as_ref().map(|x| x.variant)
    }

    /// A value reference: mostly one of the variant's variables of the wanted type, sometimes
    /// any variable of the variant, sometimes an arbitrary u32.
    pub(super) fn vr(&mut self, v: Variant, ty: u8) -> u32 {
        let t = table(v);
        match self.b.u8() % 8 {
            0 => match self.b.u8() % 4 {
                0 => 0,
                1 => u32::MAX,
                2 => self.b.u16() as u32 % 512,
                _ => self.b.u32(),
            },
            1 => {
                let k = self.b.u8() as usize % t.vars.len();
                t.vars[k].vr
            }
            _ => {
                let want: Vec<u32> = t
                    .vars
                    .iter()
                    .filter(|x| match ty {
                        0 => matches!(x.start, Start::Real(_)),
                        1 => matches!(x.start, Start::Integer(_)),
                        _ => matches!(x.start, Start::Boolean(_)),
                    })
                    .map(|x| x.vr)
                    .collect();
                if want.is_empty() {
                    self.b.u32()
                } else {
                    want[self.b.u8() as usize % want.len()]
                }
            }
        }
    }

    pub(super) fn free_instance(&mut self, i: usize) {
        if let Some(inst) = self.inst[i].take() {
            A::free_instance(inst.c);
        }
    }

    /// Runs the program to its end, then releases every state and instance.
    pub(super) fn run(mut self) -> usize {
        A::instantiate(&mut self, 0);
        let mut ops = 0;
        while !self.b.done() && ops < MAX_OPS {
            self.op();
            ops += 1;
        }
        // release every state through a live instance (making one when none is left), then the
        // instances: nothing may leak (LeakSanitizer checks under cargo fuzz)
        if self.slots.iter().any(|s| !s.s.is_null()) && self.inst.iter().all(Option::is_none) {
            let c = A::instantiate_valid(self.env.0, Variant::Bushing);
            assert!(!c.is_null(), "cleanup instance");
            self.inst[0] = Some(Inst {
                c,
                variant: Variant::Bushing,
                logger: true,
                early_allowed: false,
            });
        }
        let c = self.inst.iter().flatten().next().map(|x| x.c);
        for k in 0..4 {
            if let Some(c) = c {
                let mut s = self.slots[k].s;
                assert_eq!(A::free_state(c, &mut s), OK, "free state {k}");
                self.slots[k].s = s;
            }
        }
        self.free_instance(0);
        self.free_instance(1);
        if trace_wanted() {
            eprintln!("program trace: {:#?}", self.trace);
        }
        self.early_returns
    }

    /// The GUID (FMI 2.0) or instantiationToken (FMI 3.0) of a header's selector `sel`: the
    /// variant's, random bytes or NULL (the last two make the arguments invalid).
    pub(super) fn model_id(
        &mut self,
        sel: u8,
        variant: Variant,
        valid: &mut bool,
    ) -> Option<CString> {
        match sel % 16 {
            14 => {
                *valid = false;
                let n = self.b.u8() % 40;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                Some(CString::new(bytes).expect("no NUL"))
            }
            15 => {
                *valid = false;
                None
            }
            _ => Some(CString::new(support::guid(variant)).expect("no NUL")),
        }
    }

    /// The instance name of a header's `flags`: empty, NULL or random bytes (perhaps not
    /// UTF-8) make the arguments invalid.
    pub(super) fn instance_name(
        &mut self,
        i: usize,
        flags: u8,
        valid: &mut bool,
    ) -> Option<CString> {
        match flags % 16 {
            13 => {
                *valid = false;
                Some(CString::new("").expect("no NUL"))
            }
            14 => {
                *valid = false;
                None
            }
            15 => {
                let n = 1 + self.b.u8() % 12;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                *valid &= std::str::from_utf8(&bytes).is_ok();
                Some(CString::new(bytes).expect("no NUL"))
            }
            _ => Some(CString::new(format!("fuzz{i}")).expect("no NUL")),
        }
    }
}
