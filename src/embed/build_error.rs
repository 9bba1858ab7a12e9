//! Why a cloth could not be built into a Rapier world.

/// A [`super::ClothBuilder`] refused to build.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// Explicit forces were asked for, at a world step they cannot take
    /// (`docs/model.md` §10).
    #[error(
        "the world's step {dt_s:.3e} s is too long for explicit {effect} of this fabric at \
         σ = {spacing_m} m: it is stable only up to {max_step_s:.3e} s (docs/model.md §10). \
         Ways out: leave the integrator unset (the builder then integrates implicitly at any \
         step), `.integrator(Integrator::Implicit(..))`, a world step of at most {max_step_s:.3e} s, \
         or `.step_guard(false)` to build it anyway"
    )]
    StepTooLong {
        /// The world's step, `integration_parameters.dt` (s).
        dt_s: f64,
        /// The effect with the tightest limit, as scenes and metrics name it.
        effect: &'static str,
        /// That effect's largest stable explicit step (s).
        max_step_s: f64,
        /// Node spacing σ (m).
        spacing_m: f64,
    },
    /// A setting is out of its range.
    #[error("`{setting}` = {value}: {allowed}")]
    Invalid {
        /// The builder method or world parameter.
        setting: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, with its unit.
        allowed: String,
    },
    /// A pin names a grid node the cloth does not have.
    #[error(
        "`pin` at grid node ({}, {}): the cloth has no node there (its grid is {} × {} nodes, i \
         along the warp, j along the weft, counted from the (−warp, −weft) corner{})",
        node.0, node.1, grid.0, grid.1,
        if *circle { "; a circle keeps only the nodes inside its outline" } else { "" }
    )]
    PinOutsideCloth {
        /// The grid coordinates asked for.
        node: (u32, u32),
        /// Nodes along warp and weft of the bounding grid.
        grid: (usize, usize),
        /// Whether the outline is a circle.
        circle: bool,
    },
}
