//! The settle criterion: the cloth is at rest once no node has travelled further than
//! `max_speed × hold` over the last `hold` seconds (after an initial grace period).
//!
//! Displacement over a window, not the instantaneous speed, because contacts and constraints
//! leave micrometre-sized step-to-step oscillations (a node can report 1 cm/s while moving
//! 2 µm back and forth); a drape laboratory would call that cloth at rest. The instantaneous
//! fastest node speed is still reported in the metrics.

use std::collections::VecDeque;

use bevy_ecs::prelude::*;
use glam::DVec3;

/// Snapshots per hold window: the window is resolved to a fifth of its length.
const SNAPSHOTS_PER_WINDOW: usize = 5;

/// Tracks the settle criterion through the run.
#[derive(Resource, Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SettleState {
    /// Mean speed threshold over the window (m/s).
    pub max_speed: f64,
    /// Window length (s).
    pub hold: f64,
    /// Grace period before the criterion applies (s).
    pub min_time: f64,
    /// Largest node displacement over the latest full window divided by its length (m/s).
    pub window_speed: Option<f64>,
    /// When the criterion was first met (s): the start of the quiet window.
    pub settled_at: Option<f64>,
    snapshots: VecDeque<(f64, Vec<DVec3>)>,
}

impl SettleState {
    /// A tracker for the given threshold (m/s), window (s) and grace period (s).
    pub fn new(max_speed: f64, hold: f64, min_time: f64) -> Self {
        Self {
            max_speed,
            hold,
            min_time,
            window_speed: None,
            settled_at: None,
            snapshots: VecDeque::new(),
        }
    }

    /// Feeds the node positions (m) at time `t` (s); call every step.
    pub fn observe(&mut self, t: f64, positions: &[DVec3]) {
        if self.settled_at.is_some() {
            return;
        }
        let interval = self.hold / SNAPSHOTS_PER_WINDOW as f64;
        let due = self
            .snapshots
            .back()
            .is_none_or(|(last, _)| t - last >= interval - 1e-12);
        if !due {
            return;
        }
        self.snapshots.push_back((t, positions.to_vec()));
        while self.snapshots.len() > SNAPSHOTS_PER_WINDOW + 1 {
            self.snapshots.pop_front();
        }
        let (t0, first) = &self.snapshots[0];
        let span = t - t0;
        if span < self.hold - 1e-9 || *t0 < self.min_time {
            return;
        }
        let travel = first
            .iter()
            .zip(positions)
            .map(|(a, b)| (*b - *a).length())
            .fold(0.0, f64::max);
        let speed = travel / span;
        self.window_speed = Some(speed);
        if speed < self.max_speed {
            self.settled_at = Some(*t0);
        }
    }
}
