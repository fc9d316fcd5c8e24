//! CPU time, which std has no clock for: the calling thread's (the wavefront's stage
//! clock) or the whole process's (the benchmark clock of prism-lab), each one libc call.

// The one libc call (the workspace's `unsafe_code = "deny"` lists this module as an
// exception).
#![allow(unsafe_code)]

use std::time::Duration;

/// Whose CPU time a reading counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuClock {
    /// The calling thread's.
    Thread,
    /// The whole process's (all threads).
    Process,
}

/// The CPU time `clock` has counted so far; `None` where the platform does not offer it.
#[cfg(unix)]
pub fn cpu_time(clock: CpuClock) -> Option<Duration> {
    let id = match clock {
        CpuClock::Thread => libc::CLOCK_THREAD_CPUTIME_ID,
        CpuClock::Process => libc::CLOCK_PROCESS_CPUTIME_ID,
    };
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes into it.
    let status = unsafe { libc::clock_gettime(id, &mut ts) };
    (status == 0).then(|| Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32))
}

/// The CPU time `clock` has counted so far; `None` where the platform does not offer it.
#[cfg(not(unix))]
pub fn cpu_time(_clock: CpuClock) -> Option<Duration> {
    None
}
