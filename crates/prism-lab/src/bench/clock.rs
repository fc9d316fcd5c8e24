//! The clock measurements read. Wall time counts every moment another process held the
//! core; on a shared machine that noise swamps a 10 % difference. The process's CPU time
//! counts only the cycles spent here, so single-threaded measurements stay comparable
//! while other work runs (it still sees cache and memory-bandwidth contention).

use std::time::{Duration, Instant};

/// What a benchmark's times are read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// Elapsed real time.
    Wall,
    /// CPU time of the whole process (all threads); falls back to wall time where the
    /// platform does not offer it.
    ProcessCpu,
}

impl Clock {
    /// What the clock measures, for report headers.
    pub fn describe(self) -> &'static str {
        match (self, process_cpu_time().is_some()) {
            (Clock::ProcessCpu, true) => "process CPU time",
            _ => "wall-clock time",
        }
    }

    /// Starts a stopwatch on this clock.
    pub fn start(self) -> Stopwatch {
        Stopwatch {
            clock: self,
            wall: Instant::now(),
            cpu: match self {
                Clock::ProcessCpu => process_cpu_time(),
                Clock::Wall => None,
            },
        }
    }
}

/// A running measurement on one clock, from the moment `Clock::start` made it.
pub struct Stopwatch {
    clock: Clock,
    wall: Instant,
    cpu: Option<Duration>,
}

impl Stopwatch {
    /// Time since the start on the stopwatch's clock.
    pub fn elapsed(&self) -> Duration {
        match (self.clock, self.cpu, process_cpu_time()) {
            (Clock::ProcessCpu, Some(start), Some(now)) => now.saturating_sub(start),
            _ => self.wall.elapsed(),
        }
    }
}

/// CPU time consumed by this process so far.
#[cfg(unix)]
#[allow(unsafe_code)] // the libc call; std has no process CPU clock
fn process_cpu_time() -> Option<Duration> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes into it.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    (status == 0).then(|| Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32))
}

#[cfg(not(unix))]
fn process_cpu_time() -> Option<Duration> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Work advances the CPU clock. (Other tests run in the same process at the same
    /// time and advance it too, so nothing is asserted about sleeping.)
    #[test]
    fn cpu_time_advances_with_work() {
        if process_cpu_time().is_none() {
            return;
        }
        let watch = Clock::ProcessCpu.start();
        let wall = Instant::now();
        let mut x = 0u64;
        while watch.elapsed() < Duration::from_millis(20) {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
            assert!(
                wall.elapsed() < Duration::from_secs(20),
                "20 s of busy work did not show as 20 ms of CPU time"
            );
        }
        let wall = Clock::Wall.start();
        std::thread::sleep(Duration::from_millis(5));
        assert!(wall.elapsed() >= Duration::from_millis(5));
    }
}
