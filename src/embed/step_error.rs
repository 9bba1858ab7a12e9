//! Why a step of an embedded cloth failed.

/// A [`super::KesCloth`] step found the cloth diverging, the same checks scenes run
/// (`docs/model.md` §11): a non-finite force, velocity change or node state, a node faster than
/// [`crate::measure::RUNAWAY_SPEED`] or a link strained beyond [`crate::measure::RUNAWAY_STRAIN`].
/// The world has already taken the step when the state checks fail; the cloth refuses further
/// steps with the same error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// The cloth diverged.
    #[error(
        "the cloth diverged at its step {step} (t = {time_s:.4} s): node {node}, effect `{effect}`: {message}"
    )]
    Diverged {
        /// The cloth's step count when it happened (the first step is 0).
        step: u64,
        /// The cloth's simulated time then (s).
        time_s: f64,
        /// The node (index into [`super::KesCloth::positions`]).
        node: usize,
        /// The effect at fault (`rapier_step` for Rapier's own step, `implicit_solve` for the
        /// implicit solve).
        effect: String,
        /// What went wrong and what to try.
        message: String,
    },
}
