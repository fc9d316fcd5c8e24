//! The wavefront's stage clock: the calling thread's CPU time, so that the stage times
//! `--stats` reports are the work of each stage even on a machine where the render threads
//! wait for a core (wall time counted the waits too, inflating every stage alike). One
//! reading per stage per round of the queue (a thousand paths), so its cost, a system call
//! of well under a microsecond, is nothing per path.

use crate::cpu_time::{cpu_time, CpuClock};

/// Laps of the thread's CPU time (of wall time where the platform has no thread clock).
pub(super) struct StageClock {
    last: u64,
}

impl StageClock {
    /// A clock whose first lap starts now.
    pub(super) fn start() -> Self {
        StageClock { last: now_ns() }
    }

    /// Nanoseconds since the last lap (or the start).
    pub(super) fn lap(&mut self) -> u64 {
        let now = now_ns();
        let lap = now.saturating_sub(self.last);
        self.last = now;
        lap
    }
}

/// The calling thread's CPU time in nanoseconds (wall time where there is no thread clock).
fn now_ns() -> u64 {
    cpu_time(CpuClock::Thread).map_or_else(wall_ns, |t| t.as_nanos() as u64)
}

/// Wall time since the first reading of the process, in nanoseconds.
fn wall_ns() -> u64 {
    static EPOCH: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    EPOCH
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_nanos() as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Busy work shows in the laps; a wait for something else does not (it is the
    /// thread's CPU time, not wall time).
    #[test]
    #[cfg(unix)]
    fn laps_count_work_and_not_waits() {
        let mut clock = StageClock::start();
        let mut x = 1u64;
        for i in 0..20_000_000u64 {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(i));
        }
        std::hint::black_box(x);
        let busy = clock.lap();
        assert!(busy > 0, "twenty million multiplications took no CPU time");
        std::thread::sleep(std::time::Duration::from_millis(200));
        let waiting = clock.lap();
        assert!(
            waiting < 100_000_000,
            "a 200 ms sleep counted {waiting} ns of the thread's CPU time"
        );
    }
}
