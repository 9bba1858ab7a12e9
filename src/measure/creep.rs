//! The creep check: after the cloth has settled, how far do its nodes and its centroid still move?
//!
//! The settle criterion looks at one window; a cloth that slides off a disk slowly, or sinks into
//! it, can pass it and still not be at rest. The check keeps simulating for a stated time after
//! settling and measures the largest node displacement and the centroid's displacement over it.

use bevy_ecs::prelude::*;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Node positions when the creep check started.
#[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CreepWatch {
    /// Simulated time at which the cloth was found settled (s).
    pub start_time: f64,
    /// Node positions then (m).
    pub positions: Vec<DVec3>,
}

/// What the creep check measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Creep {
    /// Length of the check (s): the scene's `creep_check_s`, or less if its time limit came first.
    pub window: f64,
    /// Largest displacement of any node over the check (m).
    pub max_node: f64,
    /// Displacement of the centroid of the nodes over the check (m).
    pub centroid: f64,
}

impl CreepWatch {
    /// The creep from the watch's start to `positions` (m) at time `now` (s).
    pub fn creep(&self, now: f64, positions: &[DVec3]) -> Creep {
        let n = positions.len().max(1) as f64;
        let max_node = self
            .positions
            .iter()
            .zip(positions)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        let shift: DVec3 = positions.iter().zip(&self.positions).map(|(b, a)| *b - *a).sum();
        Creep {
            window: now - self.start_time,
            max_node,
            centroid: (shift / n).length(),
        }
    }
}
