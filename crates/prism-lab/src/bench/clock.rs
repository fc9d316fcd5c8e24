//! The clock measurements read. Wall time counts every moment another process held the
//! core; on a shared machine that noise swamps a 10 % difference. The process's CPU time
//! counts only the cycles spent here, so single-threaded measurements stay comparable
//! while other work runs (it still sees cache and memory-bandwidth contention).

use prism::cpu_time::{cpu_time, CpuClock};
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
        match (self, cpu_time(CpuClock::Process).is_some()) {
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
                Clock::ProcessCpu => cpu_time(CpuClock::Process),
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
        match (self.clock, self.cpu, cpu_time(CpuClock::Process)) {
            (Clock::ProcessCpu, Some(start), Some(now)) => now.saturating_sub(start),
            _ => self.wall.elapsed(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Work advances the CPU clock. (Other tests run in the same process at the same
    /// time and advance it too, so nothing is asserted about sleeping.)
    #[test]
    fn cpu_time_advances_with_work() {
        if cpu_time(CpuClock::Process).is_none() {
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
