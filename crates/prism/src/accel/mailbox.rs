//! Per-query mailbox for spatial subdivisions: remembers which primitives a ray has already
//! been tested against, so one that straddles several cells is tested once per ray.
//!
//! The classic mailbox stamps a ray id into every primitive, which needs shared mutable
//! state (locks or atomics) once rays run on several threads. Here the mailbox lives on the
//! stack of the query instead: a small direct-mapped table of recently tested ids, indexed
//! by the id's low bits. It needs no synchronisation and no clearing between rays beyond
//! its 256-byte initialisation. A collision evicts an older id, which only costs a repeated
//! test later, never a wrong answer: re-testing a primitive against a `t_max` that has only
//! shrunk since cannot produce a different nearest hit. Neighbouring cells hold mostly
//! consecutive ids, so the low bits spread them well.

const SLOTS: usize = 64;

pub(crate) struct Mailbox {
    ids: [u32; SLOTS],
}

impl Mailbox {
    pub(crate) fn new() -> Self {
        Mailbox {
            ids: [u32::MAX; SLOTS],
        }
    }

    /// True the first time `prim` is seen (and records it), false if it was just tested.
    #[inline(always)]
    pub(crate) fn first_visit(&mut self, prim: u32) -> bool {
        let slot = &mut self.ids[prim as usize % SLOTS];
        if *slot == prim {
            false
        } else {
            *slot = prim;
            true
        }
    }
}
