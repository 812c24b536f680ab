//! [`Pace`]: how often a long loop looks at the clock. A loop that must notice a stop (a
//! client gone, a server shutting down) or a time limit cannot read the clock every step:
//! a built-in step costs 20 ns to 2 µs, a read of the clock about 20 ns. Nor can it look
//! every fixed number of steps: a step of a system given as formulas may cost a millisecond,
//! and 1024 of them a second. So the loop looks every `k` steps and sizes `k` from what it
//! measures between two looks: doubled while they come less than half [`AIM`] apart (up to a
//! bound the loop sets: a run's observer may want to hear from it every so many steps),
//! scaled down at once to the steps that fit in [`AIM`] when they come later than that. `k`
//! starts at 1, so that the first look comes after one step, however long that step is.

use std::time::{Duration, Instant};

/// The time aimed at between two looks: short enough that a loop notices a stop within a
/// few of them (well within 50 ms), long enough that reading the clock costs nothing.
pub const AIM: Duration = Duration::from_millis(5);

/// Most steps between two looks by default, whatever a step costs (about 10 ms of 2.5 ns
/// steps).
pub const MAX_EVERY: u64 = 1 << 22;

/// The steps between a loop's looks at the clock, sized to take about [`AIM`]; see the
/// module's doc.
#[derive(Debug, Clone, Copy)]
pub struct Pace {
    every: u64,
    most: u64,
    left: u64,
    last: Instant,
}

impl Default for Pace {
    fn default() -> Self {
        Self::new(MAX_EVERY)
    }
}

impl Pace {
    /// A pace whose first look comes after one step, and never more than `most` steps after
    /// the one before.
    pub fn new(most: u64) -> Self {
        Self { every: 1, most: most.max(1), left: 1, last: Instant::now() }
    }

    /// Steps between two looks now.
    pub fn every(&self) -> u64 {
        self.every
    }

    /// Counts one step; the time now when it is time to look (about every [`AIM`]).
    #[inline]
    pub fn tick(&mut self) -> Option<Instant> {
        self.left -= 1;
        if self.left != 0 {
            return None;
        }
        Some(self.look())
    }

    /// Reads the clock and sizes the steps to the next look.
    #[cold]
    #[inline(never)]
    pub fn look(&mut self) -> Instant {
        let now = Instant::now();
        let took = now.saturating_duration_since(self.last);
        self.every = next_every(self.every, took).min(self.most);
        self.left = self.every;
        self.last = now;
        now
    }
}

/// The steps to take before the next look, `every` having taken `took`.
pub fn next_every(every: u64, took: Duration) -> u64 {
    if took > AIM {
        // As many as fit in AIM at the pace measured (at least one).
        let fit = every as f64 * AIM.as_secs_f64() / took.as_secs_f64();
        (fit as u64).max(1)
    } else if took < AIM / 2 {
        (every * 2).min(MAX_EVERY)
    } else {
        every
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_steps_between_looks_grow_while_fast_and_shrink_at_once_when_slow() {
        let ms = Duration::from_millis;
        // Fast steps: doubled up to the bound.
        assert_eq!(next_every(1, Duration::from_nanos(50)), 2);
        assert_eq!(next_every(MAX_EVERY, Duration::ZERO), MAX_EVERY);
        // Within [AIM/2, AIM]: kept.
        assert_eq!(next_every(1000, ms(3)), 1000);
        // Slow: as many as fit in AIM, at least one.
        assert_eq!(next_every(1000, ms(50)), 100);
        assert_eq!(next_every(1000, Duration::from_secs(60)), 1);
        assert_eq!(next_every(1, ms(14)), 1);
    }

    #[test]
    fn a_pace_looks_first_after_one_step_then_spaces_its_looks() {
        let mut bounded = Pace::new(4);
        for _ in 0..20 {
            bounded.tick();
        }
        assert!(bounded.every() <= 4, "at most the bound");
        let mut pace = Pace::default();
        assert!(pace.tick().is_some(), "the first step is looked at");
        // Nothing measurable between the looks: the count doubles, and the steps in between
        // are not looked at.
        let mut looks = 1;
        for _ in 0..1000 {
            looks += usize::from(pace.tick().is_some());
        }
        // Doubling gives 10; a preempted thread may see a long gap and start again from
        // fewer, never from every step.
        assert!(looks < 500, "{looks} looks in 1001 steps");
    }
}
