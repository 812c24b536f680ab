//! [`WorkPrecisionRequest`]: the body of `POST /work-precision`, a scene, methods and the step
//! sizes to measure.

use crate::request::{MethodRequest, ObservablesRequest, scene_body, schemas};

scene_body! {
    /// The body of `POST /work-precision`: a `/simulate` scene and methods (without
    /// `points`), and the step sizes to measure. The scene's `step` is the largest of the
    /// `levels` (when `steps` is given and `step` is not, the largest of `steps` stands for
    /// it); `t_end` is where the final error is measured; `integrals` are those whose largest
    /// error is reported.
    pub struct WorkPrecisionRequest {
        /// Methods, as in `/simulate` (default: the paper's five).
        #[serde(default)]
        #[schema(schema_with = schemas::methods)]
        pub methods: Option<Vec<MethodRequest>>,
        /// Step sizes, each in (0, t_end]; each is rounded to t_end / n so the run ends at
        /// t_end. Not together with `levels`.
        #[serde(default)]
        #[schema(min_items = 1, max_items = 12)]
        pub steps: Option<Vec<f64>>,
        /// Step sizes h, h/2, …, h/2^(levels−1) from the scene's step (default 4 when `steps`
        /// is not given).
        #[serde(default)]
        #[schema(minimum = 1, maximum = 12)]
        pub levels: Option<i64>,
        /// Timing repetitions per run; the fastest counts (default 3).
        #[serde(default)]
        #[schema(minimum = 1, maximum = 10)]
        pub repeats: Option<i64>,
        /// Quantities to take at t_end, by name, as in `/simulate`: each row and the
        /// reference get their values there (`observables`).
        #[serde(default)]
        #[schema(schema_with = schemas::observables)]
        pub observables: Option<ObservablesRequest>,
    }
}
