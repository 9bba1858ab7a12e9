//! The solver's state that a checkpoint saves and restores: what carries from one step to the
//! next (the warm start, the supports' release rule, sliding friction, BDF2's history).

use glam::DVec3;

use super::ImplicitSolver;
use crate::implicit::Bdf2History;

impl ImplicitSolver {
    /// The last step's Δv (m/s), the next solve's warm start (for checkpoints).
    pub fn warm_start(&self) -> &[DVec3] {
        &self.dv
    }

    /// Restores a warm start saved by [`Self::warm_start`]; `false` (and nothing changed) if it
    /// does not fit this cloth.
    pub fn restore_warm_start(&mut self, dv: &[DVec3]) -> bool {
        copy_if_same_length(&mut self.dv, dv)
    }

    /// Which nodes the last solve's surface pushed (for checkpoints).
    pub fn pressed(&self) -> &[bool] {
        &self.pressed
    }

    /// Restores what [`Self::pressed`] returned; `false` (and nothing changed) if it does not fit
    /// this cloth.
    pub fn restore_pressed(&mut self, pressed: &[bool]) -> bool {
        copy_if_same_length(&mut self.pressed, pressed)
    }

    /// Each node's kinetic friction impulse from the last solve (N·s), and the system step h'
    /// (s) it was taken over (for checkpoints).
    pub fn sliding_impulses(&self) -> (&[f64], f64) {
        (&self.sliding_impulse, self.sliding_step_s)
    }

    /// Which holds gave way in the last solve and slide from the next step
    /// ([`crate::implicit::FrictionRelease::NextStep`]; for checkpoints).
    pub fn releases_due(&self) -> &[bool] {
        &self.release_next
    }

    /// Restores what [`Self::releases_due`] returned; an empty list (a checkpoint without them)
    /// leaves none due; `false` (and nothing changed) if it does not fit this cloth.
    pub fn restore_releases_due(&mut self, due: &[bool]) -> bool {
        if due.is_empty() {
            self.release_next.fill(false);
            return true;
        }
        copy_if_same_length(&mut self.release_next, due)
    }

    /// BDF2's history (for checkpoints; `None` before its first step or with backward Euler).
    pub fn bdf2_history(&self) -> Option<&Bdf2History> {
        self.bdf2.as_ref()
    }

    /// Restores what [`Self::bdf2_history`] returned; `false` (and nothing changed) if it does
    /// not fit this cloth.
    pub fn restore_bdf2_history(&mut self, history: Option<Bdf2History>) -> bool {
        let n = self.masses.len();
        let fits = history
            .as_ref()
            .is_none_or(|h| h.lag.len() == n && h.previous.len() == n);
        if fits {
            self.bdf2 = history;
        }
        fits
    }

    /// Restores what [`Self::sliding_impulses`] returned (a step of 0: unknown, the next step's
    /// taken); `false` (and nothing changed) if it does not fit this cloth.
    pub fn restore_sliding_impulses(&mut self, impulses: &[f64], step_s: f64) -> bool {
        let fits = copy_if_same_length(&mut self.sliding_impulse, impulses);
        if fits {
            self.sliding_step_s = step_s;
        }
        fits
    }
}

/// Copies `from` into `to` if they have the same length (a checkpoint of this cloth).
fn copy_if_same_length<T: Copy>(to: &mut [T], from: &[T]) -> bool {
    let fits = to.len() == from.len();
    if fits {
        to.copy_from_slice(from);
    }
    fits
}
