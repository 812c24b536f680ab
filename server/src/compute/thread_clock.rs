//! [`ThreadClock`]: the CPU time of the calling thread, which is what a run's computation
//! cost. A run's wall time also counts the time it waited for a core (runs beyond the
//! server's cores share them, and a browser drawing the live plots on the same machine takes
//! its share); its thread's CPU time does not, so steps per second of it measure the method,
//! not the load.

use std::time::Duration;

/// A stopwatch of the calling thread's CPU time.
#[derive(Debug, Clone, Copy)]
pub struct ThreadClock(Option<Duration>);

impl ThreadClock {
    /// Starts it on the calling thread (stop it on the same thread).
    pub fn start() -> Self {
        Self(thread_cpu_time())
    }

    /// The CPU time the thread has used since [`ThreadClock::start`], in milliseconds
    /// rounded to the microsecond; `None` where the platform does not measure it.
    pub fn elapsed_ms(&self) -> Option<f64> {
        let used = thread_cpu_time()?.checked_sub(self.0?)?;
        Some(millis(used))
    }
}

/// A duration in milliseconds rounded to the microsecond, as the API reports times.
pub fn millis(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1e3
}

#[cfg(target_os = "linux")]
fn thread_cpu_time() -> Option<Duration> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable timespec owned by this frame; the call only writes it.
    #[allow(unsafe_code, reason = "clock_gettime has no safe wrapper in libc or std")]
    let result = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if result != 0 {
        return None;
    }
    Some(Duration::new(u64::try_from(ts.tv_sec).ok()?, u32::try_from(ts.tv_nsec).ok()?))
}

#[cfg(not(target_os = "linux"))]
fn thread_cpu_time() -> Option<Duration> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn counts_this_threads_work_and_not_its_sleep() {
        let clock = ThreadClock::start();
        let wall = std::time::Instant::now();
        std::thread::sleep(Duration::from_millis(30));
        let mut x = 0u64;
        while wall.elapsed() < Duration::from_millis(60) {
            x = std::hint::black_box(x.wrapping_add(1));
        }
        let cpu = clock.elapsed_ms().expect("Linux measures thread CPU time");
        // ~30 ms of spinning, none of the 30 ms asleep (wall 60 ms).
        assert!(cpu > 1.0 && cpu < 55.0, "cpu {cpu} ms");
    }
}
