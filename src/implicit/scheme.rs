//! The implicit time-stepping scheme: backward Euler, or the two-step BDF2, and the history
//! BDF2 carries from step to step.
//!
//! Both are linearly implicit (one linear solve a step) and hand Rapier a velocity that it
//! integrates as x ← x + h·w. Backward Euler's w is its new velocity. BDF2 at a step h that
//! follows a step h₋, with the ratio ω = h/h₋ (1 at a constant step),
//!
//!   x₊ = x + b·(x − x₋) + β·h·v₊,  v₊ = v + b·(v − v₋) + β·h·a(x₊, v₊),
//!   β = (1 + ω)/(1 + 2ω),  b = ω²/(1 + 2ω)   (2/3 and 1/3 at a constant step),
//!
//! moves each node by h·((1 − β)·w + β·v₊), w = (x − x₋)/h₋ being the velocity Rapier moved
//! it with last step, so the node's velocity v (the scheme's state) and Rapier's w differ by a
//! lag d = v − w that the scheme keeps per node. Linearised about the step's start, with
//! h' = β·h and Δv = v₊ − v:
//!
//!   (M + h'·C + h'²·H)·Δv = h'·(F + M·g) − h'²·H·(k·w + d) − h'·C·d + b·M·(v − v₋),
//!
//! k = (1 + 2ω)/(1 + ω) (3/2 at a constant step): the backward-Euler system at the step h'
//! plus the history b·M·(v − v₋); Rapier is then handed w₊ = (1 − β)·w + β·v₊, a kick of
//! β·(d + Δv), and the lag becomes (1 − β)·(d + Δv). A step more than [`MAX_STEP_GROWTH`]
//! times the last starts the scheme again from backward Euler.
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
    /// same one solve a step at 2/3 of the step (at a constant step); it damps stiff modes (2π·h/T ≫ 1) almost
    /// as strongly as backward Euler, but slow ones by (2π·h/T)⁴/4 a step.
    Bdf2,
}

/// The largest ratio h/h₋ of a step to the one before that BDF2 carries its history across: the
/// variable-step formula stays stable on a dissipative problem for ratios up to
/// (2 + √13)/3 ≈ 1.87 (Becker 1998; zero-stable up to 1 + √2, Grigorieff 1983); a step that
/// grows more (the step at rest after the moving step, eight times longer) starts the scheme
/// again from backward Euler. Shorter steps keep it at any ratio.
pub const MAX_STEP_GROWTH: f64 = 1.8;

/// What BDF2 carries between steps, per node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// This step's ratio ω = h/h₋ to the step the history was taken at (1 at a constant step;
    /// set by [`Self::prepare`]).
    #[serde(skip, default = "unit_ratio")]
    pub ratio: f64,
}

fn unit_ratio() -> f64 {
    1.0
}

impl Bdf2History {
    /// Empty history for `n` nodes.
    pub fn new(n: usize) -> Self {
        Self {
            lag: vec![DVec3::ZERO; n],
            previous: vec![DVec3::ZERO; n],
            started: false,
            step_s: 0.0,
            ratio: 1.0,
        }
    }

    /// Prepares a step of `h` (s): the ratio ω to the step the history was taken at, or, where
    /// the step grew by more than [`MAX_STEP_GROWTH`], the scheme started again from a
    /// backward-Euler step, the lag d dropped with the history (Rapier's velocity becomes the
    /// scheme's). A run grows its step that much only on coming to rest
    /// ([`crate::scene::IntegrationSpec::rest_dt_s`]), where d nearly vanishes; a host whose
    /// step varies from frame to frame keeps second order.
    pub fn prepare(&mut self, h: f64) {
        self.ratio = if self.step_s > 0.0 { h / self.step_s } else { 1.0 };
        if self.started && self.ratio > MAX_STEP_GROWTH {
            self.started = false;
        }
        self.step_s = h;
    }

    /// β = (1 + ω)/(1 + 2ω): the share of the new velocity in Rapier's (2/3 at a constant
    /// step).
    fn beta(&self) -> f64 {
        (1.0 + self.ratio) / (1.0 + 2.0 * self.ratio)
    }

    /// The step h' = β·h (s) the linear system is assembled at for this step's `h` (s).
    pub fn system_step(&self, h: f64) -> f64 {
        self.beta() * h
    }

    /// k = (1 + 2ω)/(1 + ω): the weight of Rapier's last velocity w in the position the
    /// step's stiffness is taken about, x₊ − x = h'·(Δv + k·w + d) (3/2 at a constant step).
    pub fn velocity_weight(&self) -> f64 {
        (1.0 + 2.0 * self.ratio) / (1.0 + self.ratio)
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

    /// The history term b·M·(v − v₋) (N·s) of node `i`, b = ω²/(1 + 2ω), for the scheme's
    /// velocity `v` (m/s) and mass `m` (kg).
    pub fn history(&self, i: usize, m: f64, v: DVec3) -> DVec3 {
        let b = self.ratio * self.ratio / (1.0 + 2.0 * self.ratio);
        (b * m) * (v - self.previous[i])
    }

    /// The velocity kick w₊ − w (m/s) that Rapier is handed for node `i` whose solved
    /// velocity change is `dv` (m/s): β·(d + Δv).
    pub fn kick(&self, i: usize, dv: DVec3) -> DVec3 {
        (self.lag[i] + dv) * self.beta()
    }

    /// Ends a first step taken by backward Euler from the velocities `v` (m/s): Rapier then
    /// moved each node with its new velocity (no lag), and v is v₋.
    pub fn start(&mut self, v: &[DVec3]) {
        self.lag.fill(DVec3::ZERO);
        self.previous.copy_from_slice(v);
        self.started = true;
    }

    /// Ends the step, given the scheme's velocities `v` (m/s) at its start and the solved
    /// velocity changes `dv` (m/s): keeps v as v₋ and the new lag (1 − β)·(d + Δv).
    pub fn advance(&mut self, v: &[DVec3], dv: &[DVec3]) {
        let keep = 1.0 - self.beta();
        for (((d, previous), v), dv) in self.lag.iter_mut().zip(&mut self.previous).zip(v).zip(dv) {
            *d = (*d + *dv) * keep;
            *previous = *v;
        }
        self.started = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step up to [`MAX_STEP_GROWTH`] times the last, or any shorter one, keeps the history
    /// at its ratio; one that grows more (the step at rest) starts the scheme again from
    /// backward Euler, dropping the lag.
    #[test]
    fn a_step_grown_eightfold_starts_bdf2_again_and_a_varying_one_keeps_it() {
        let mut history = Bdf2History::new(2);
        history.prepare(1.0 / 240.0);
        history.start(&[DVec3::X, DVec3::Y]);
        history.prepare(1.0 / 240.0);
        assert!(
            history.started && history.ratio == 1.0,
            "the same step changed the scheme"
        );
        history.prepare(1.2 / 240.0);
        assert!(history.started, "a step 1.2 times longer restarted the scheme");
        assert!((history.ratio - 1.2).abs() < 1e-12, "ratio {}", history.ratio);
        history.prepare(0.1 / 240.0);
        assert!(history.started, "a shorter step restarted the scheme");
        history.prepare(0.8 / 240.0);
        assert!(!history.started, "a step eight times longer kept the history");
        let mut v = [DVec3::ZERO; 2];
        history.lag = vec![DVec3::Z; 2];
        history.velocities(&[DVec3::X, DVec3::Y], &[false, false], &mut v);
        assert_eq!(v, [DVec3::X, DVec3::Y], "the lag survived the restart");
    }

    /// At a constant step the coefficients are the textbook BDF2's: h' = 2h/3, the history
    /// M·(v − v₋)/3, the kick (2/3)·(d + Δv), the lag (d + Δv)/3 and 3w/2; at ω → 0 (a step
    /// far shorter than the last) they tend to backward Euler's: h' = h, no history, no lag.
    #[test]
    fn bdf2_coefficients_are_the_textbook_ones_at_a_constant_step_and_backward_eulers_at_a_vanishing_ratio() {
        let mut history = Bdf2History::new(1);
        history.prepare(0.01);
        history.start(&[DVec3::ZERO]);
        history.prepare(0.01);
        assert!((history.system_step(0.01) - 0.02 / 3.0).abs() < 1e-15);
        assert!((history.history(0, 3.0, DVec3::X) - DVec3::X).length() < 1e-15);
        assert!((history.kick(0, DVec3::X) - DVec3::X * (2.0 / 3.0)).length() < 1e-15);
        assert!((history.velocity_weight() - 1.5).abs() < 1e-15);
        history.advance(&[DVec3::ZERO], &[DVec3::X]);
        assert!((history.lag[0] - DVec3::X / 3.0).length() < 1e-15);
        history.prepare(1e-9);
        assert!((history.system_step(1e-9) - 1e-9).abs() < 1e-15);
        assert!(history.history(0, 1.0, DVec3::X).length() < 1e-6);
        assert!((history.kick(0, DVec3::ZERO) - history.lag[0]).length() < 1e-6);
    }
}
