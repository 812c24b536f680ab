//! Where simulations compute, off the async runtime: a request checked into a [`Plan`] and
//! its work priced ([`check_price`]), its admission [`Slot`], the [`Runner`] that runs each
//! method on the blocking pool (timed by a [`ThreadClock`], counted in [`ActiveRuns`],
//! stopped through [`Cancel`] or by its time limit), the memory its answer may hold
//! ([`AnswerBudget`]), and the [`Caches`] of latitude axes and references kept across
//! requests. Nothing here knows the app's state or its handlers: they hand in what is
//! needed.

mod active_runs;
mod budget;
mod cache;
mod cancel;
mod plan;
mod price;
mod runner;
mod scorecard;
mod slot;
mod thread_clock;
mod work_precision;

pub use active_runs::{ActiveRuns, RunGuard};
pub use budget::{
    AnswerBudget, BudgetGuard, JSON_BYTES_PER_POINT, KEPT_BYTES_PER_POINT, answer_bytes, mib,
};
pub use cache::{CAPACITY, Cache, Caches, ReferenceKey, SceneKey};
pub use cancel::{Cancel, CancelOnDrop};
pub use plan::{
    ADVICE, Delivery, PROGRESS_EVERY, Plan, SectionPlan, check_answer_bytes, method, methods,
    observables_of, points, priced, run_config, steps_of, steps_text,
};
pub use price::{Priced, about, check_price, duration};
pub use runner::{Finished, Runner, lower_priority, off_runtime, time_limit};
pub use scorecard::{MAX_SCENES, PROPERTY_STEPS, plans as scorecard_plans};
pub use slot::Slot;
pub use thread_clock::{ThreadClock, millis};
pub use work_precision::{
    DEFAULT_LEVELS, DEFAULT_REPEATS, MAX_LEVELS, MAX_REPEATS, WorkPrecisionJob,
};
