//! [`SceneSpec`]: one scene of a `POST /scorecard`, a `/simulate` body without `methods` and
//! `points`.

use crate::request::scene_body;

scene_body! {
    /// One scene of a `POST /scorecard`: a `/simulate` body without `methods` and `points`.
    pub struct SceneSpec {}
}
