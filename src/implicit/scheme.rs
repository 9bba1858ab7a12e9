//! The implicit time-stepping scheme: backward Euler, or the two-step BDF2, and the history
//! BDF2 carries from step to step.
//!
//! Both are linearly implicit (one linear solve a step) and hand Rapier a velocity that it
//! integrates as x ← x + h·w. Backward Euler's w is its new velocity. BDF2,
//!
//!   x₊ = (4x − x₋)/3 + (2h/3)·v₊,  v₊ = (4v − v₋)/3 + (2h/3)·a(x₊, v₊),
//!
//! moves each node by h·(w/3 + 2v₊/3), w = (x − x₋)/h being the velocity Rapier moved it with
//! last step, so the node's velocity v (the scheme's state) and Rapier's w differ by a lag
//! d = v − w that the scheme keeps per node. Linearised about the step's start, with
//! h' = 2h/3 and Δv = v₊ − v:
//!
//!   (M + h'·C + h'²·H)·Δv = h'·(F + M·g) − h'²·H·(3w/2 + d) − h'·C·d + M·(v − v₋)/3,
//!
//! the backward-Euler system at the step h' plus the history M·(v − v₋)/3; Rapier is then
//! handed w₊ = w/3 + 2v₊/3, a kick of (2/3)·(d + Δv), and the lag becomes (d + Δv)/3.
//! The numerical damping of both, mode by mode, is in `docs/model.md` §12, "BDF2".

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// How the implicit solve steps our forces in time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Scheme {
    /// Linearly implicit backward Euler (default): first order; a mode of period T loses a
    /// fraction of its amplitude each step that grows as (2π·h/T)²/2, so long steps damp
    /// slow motion (folds forming) as well as stiff jitter.
    #[default]
    BackwardEuler,
    /// The two-step backward differentiation formula, linearly implicit: second order, the
    /// same one solve a step at 2/3 of the step; it damps stiff modes (2π·h/T ≫ 1) almost
    /// as strongly as backward Euler, but slow ones by (2π·h/T)⁴/4 a step.
    Bdf2,
}

impl Scheme {
    /// The step h' (s) the linear system is assembled at for a Rapier step `h` (s).
    pub fn system_step(self, h: f64) -> f64 {
        match self {
            Scheme::BackwardEuler => h,
            Scheme::Bdf2 => 2.0 * h / 3.0,
        }
    }
}

/// What BDF2 carries between steps, per node.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Bdf2History {
    /// The lag d = v − w (m/s): the scheme's velocity less the one Rapier moved the node with.
    pub lag: Vec<DVec3>,
    /// The scheme's velocity one step back, v₋ (m/s).
    pub previous: Vec<DVec3>,
    /// Whether a step has been taken (the first is backward Euler's, which needs no history).
    pub started: bool,
    /// The Rapier step the history was taken at (s; 0 before the first step).
    #[serde(default)]
    pub step_s: f64,
}

impl Bdf2History {
    /// Empty history for `n` nodes.
    pub fn new(n: usize) -> Self {
        Self {
            lag: vec![DVec3::ZERO; n],
            previous: vec![DVec3::ZERO; n],
            started: false,
            step_s: 0.0,
        }
    }

    /// Starts the scheme again, from a backward-Euler step, when the step `h` (s) differs from
    /// the history's: the formula above holds at a constant step, and the lag d is dropped
    /// with the history (Rapier's velocity becomes the scheme's). A run changes its step only
    /// at rest ([`crate::scene::IntegrationSpec::rest_dt_s`]), where d nearly vanishes; a host
    /// that changes its step every step gets backward Euler.
    pub fn restart_if_step_changed(&mut self, h: f64) {
        if self.started && self.step_s != 0.0 && self.step_s != h {
            self.started = false;
        }
        self.step_s = h;
    }

    /// The scheme's velocities v = w + d (m/s) from Rapier's `w`, into `out`; nodes in `held`
    /// have no lag, nor any before the first step.
    pub fn velocities(&mut self, w: &[DVec3], held: &[bool], out: &mut [DVec3]) {
        for (((o, w), d), held) in out.iter_mut().zip(w).zip(&mut self.lag).zip(held) {
            if *held || !self.started {
                *d = DVec3::ZERO;
            }
            *o = *w + *d;
        }
    }

    /// The history term M·(v − v₋)/3 (N·s) of node `i`, for the scheme's velocity `v` (m/s) and
    /// mass `m` (kg).
    pub fn history(&self, i: usize, m: f64, v: DVec3) -> DVec3 {
        (m / 3.0) * (v - self.previous[i])
    }

    /// The velocity kick w₊ − w (m/s) that Rapier is handed for node `i` whose solved
    /// velocity change is `dv` (m/s): (2/3)·(d + Δv).
    pub fn kick(&self, i: usize, dv: DVec3) -> DVec3 {
        (self.lag[i] + dv) * (2.0 / 3.0)
    }

    /// Ends a first step taken by backward Euler from the velocities `v` (m/s): Rapier then
    /// moved each node with its new velocity (no lag), and v is v₋.
    pub fn start(&mut self, v: &[DVec3]) {
        self.lag.fill(DVec3::ZERO);
        self.previous.copy_from_slice(v);
        self.started = true;
    }

    /// Ends the step, given the scheme's velocities `v` (m/s) at its start and the solved
    /// velocity changes `dv` (m/s): keeps v as v₋ and the new lag (d + Δv)/3.
    pub fn advance(&mut self, v: &[DVec3], dv: &[DVec3]) {
        for (((d, previous), v), dv) in self.lag.iter_mut().zip(&mut self.previous).zip(v).zip(dv) {
            *d = (*d + *dv) / 3.0;
            *previous = *v;
        }
        self.started = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The history holds at one step only: a changed step starts the scheme again from
    /// backward Euler (dropping the lag), the same step keeps it.
    #[test]
    fn a_changed_step_starts_bdf2_again() {
        let mut history = Bdf2History::new(2);
        history.restart_if_step_changed(1.0 / 240.0);
        history.start(&[DVec3::X, DVec3::Y]);
        history.restart_if_step_changed(1.0 / 240.0);
        assert!(history.started, "the same step restarted the scheme");
        history.restart_if_step_changed(1.0 / 30.0);
        assert!(!history.started, "a step eight times longer kept the history");
        let mut v = [DVec3::ZERO; 2];
        history.lag = vec![DVec3::Z; 2];
        history.velocities(&[DVec3::X, DVec3::Y], &[false, false], &mut v);
        assert_eq!(v, [DVec3::X, DVec3::Y], "the lag survived the restart");
    }
}
