//! The response views: every type the API answers with, serialized as it is sent. They depend
//! on the core and on each other only; the handlers ([`routes`](crate::routes)) and the
//! observers ([`observers`](crate::observers)) fill them.
//!
//! A run is reported in three places, each with its [`RunSummary`] flattened into its own
//! fields: [`RunView`] (with its series, in the JSON response), [`RunEvent`] (with its
//! verdicts, in the stream) and [`ScorecardRun`] (with its verdicts, in the scorecard).

mod events;
mod gap;
mod health;
mod method;
mod observables;
mod run;
mod run_summary;
mod scene;
mod scorecard;
mod series;
mod simulate_response;
mod status;
mod sweep;
mod systems;
mod tableau;
mod verdict;
mod work_precision;

pub use events::{
    DoneEvent, ObservablesEvent, PointsEvent, ProgressEvent, RunEvent, SectionEvent, ShutdownEvent,
};
pub use gap::GapView;
pub use health::{CacheStats, CachesStats, FormulasHealth, Health};
pub use method::MethodView;
pub use observables::{ObservablesView, ValuesView};
pub use run::RunView;
pub use run_summary::RunSummary;
pub use scene::SceneView;
pub use scorecard::{
    PROPERTIES_TEST, PropertiesView, ScorecardResponse, ScorecardRun, ScorecardScene,
};
pub use series::SeriesView;
pub use simulate_response::SimulateResponse;
pub use status::Status;
pub use sweep::{
    AxisView, RowStatus, SimulateEcho, SweepCell, SweepDone, SweepHead, SweepProgress,
    SweepResponse, SweepRow,
};
pub use systems::{
    LimitsView, MethodInfoView, PaperClassView, PaperScene, ParamView, PresetView, SystemView,
    SystemsResponse,
};
pub use tableau::{ConstraintView, StoredTableauView, TableauEcho, TableauView};
pub use verdict::{CRITERION, VerdictView};
pub use work_precision::{ReferenceView, WorkPrecisionResponse, WorkPrecisionRow};
