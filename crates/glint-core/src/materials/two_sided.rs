//! Two sides, Mitsuba's `twosided`: a one-sided material (diffuse, conductor, plastic) made to
//! answer from both sides, the same material on both or one per side. A wrapper: the side the
//! viewer is on picks the material, which is then evaluated as if seen from its front.
//!
//! Scene parameters: `front`, and optionally `back` (material names; default: `front`).
//! ```toml
//! [materials.card]
//! type = "two-sided"
//! front = "red"
//! back = "blue"
//! ```

use super::Material;

#[derive(Clone, Debug, PartialEq)]
pub struct TwoSided {
    pub front: Material,
    pub back: Material,
}
