//! The settle criterion: the cloth is at rest once no node has travelled further than
//! `max_speed × hold` over the last `hold` seconds (after an initial grace period), and, with a
//! confirmation watch, no node then travels further than that same `max_speed × hold` over
//! the next `confirm` seconds either.
//!
//! Displacement over a window, not the instantaneous speed, because contacts and constraints
//! leave micrometre-sized step-to-step oscillations (a node can report 1 cm/s while moving
//! 2 µm back and forth); a drape laboratory would call that cloth at rest. The instantaneous
//! fastest node speed is still reported in the metrics.
//!
//! The confirmation watch exists because a quiet window can be a slow passage, not rest: a
//! light skirt can come almost to rest on a shape that is not stable (a fold about to open) and
//! leave it along a slowly growing mode, nodes accelerating from a fraction of a mm/s to several
//! mm/s over seconds (thin wool on the Cusick tester, `docs/model.md` §1, "Rest"). A quiet window the watch
//! undoes is counted in [`SettleState::restarts`] and the windows start again from that moment.

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
    /// Confirmation watch after a quiet window (s; 0: none).
    #[serde(default)]
    pub confirm: f64,
    /// Quiet windows the confirmation watch undid.
    #[serde(default)]
    pub restarts: u32,
    /// A quiet window being confirmed: its start (s), the time the watch began (s) and the node
    /// positions then (m).
    #[serde(default)]
    candidate: Option<(f64, f64, Vec<DVec3>)>,
    /// Largest node displacement over the latest full window divided by its length (m/s).
    pub window_speed: Option<f64>,
    /// When the criterion was first met (s): the start of the quiet window.
    pub settled_at: Option<f64>,
    snapshots: VecDeque<(f64, Vec<DVec3>)>,
}

impl SettleState {
    /// A tracker for the given threshold (m/s), window (s), grace period (s) and confirmation
    /// watch (s; 0 for none).
    pub fn new(max_speed: f64, hold: f64, min_time: f64, confirm: f64) -> Self {
        Self {
            max_speed,
            hold,
            min_time,
            confirm,
            restarts: 0,
            candidate: None,
            window_speed: None,
            settled_at: None,
            snapshots: VecDeque::new(),
        }
    }

    /// Whether the cloth is quiet: a quiet window is being confirmed, or the cloth has settled.
    pub fn quiet(&self) -> bool {
        self.candidate.is_some() || self.settled_at.is_some()
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
        if let Some((start, watched_from, at)) = &self.candidate {
            self.snapshots.clear();
            self.snapshots.push_back((t, Vec::new()));
            let travel = farthest(at, positions);
            if travel > self.max_speed * self.hold {
                self.restarts += 1;
                self.candidate = None;
                self.snapshots.clear();
                self.snapshots.push_back((t, positions.to_vec()));
            } else if t - watched_from >= self.confirm - 1e-9 {
                self.settled_at = Some(*start);
            }
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
        let speed = farthest(first, positions) / span;
        self.window_speed = Some(speed);
        if speed < self.max_speed {
            if self.confirm > 0.0 {
                self.candidate = Some((*t0, t, positions.to_vec()));
                self.snapshots.clear();
            } else {
                self.settled_at = Some(*t0);
            }
        }
    }
}

/// The farthest any node moved from `from` to `to` (m).
fn farthest(from: &[DVec3], to: &[DVec3]) -> f64 {
    from.iter()
        .zip(to)
        .map(|(a, b)| (*b - *a).length())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One node that relaxes (speed 2 mm/s halving every 0.5 s), comes almost to rest at 1.5 s,
    /// then leaves along a growing mode (0.05 mm/s doubling every 0.5 s) until 4.5 s and stops:
    /// the shape of a slow passage through an unstable drape. Position (m) along x at `t` (s).
    fn passage(t: f64) -> f64 {
        let relax = 2e-3 * 0.5 / std::f64::consts::LN_2 * (1.0 - 0.5f64.powf(t / 0.5));
        let grow = |t: f64| 5e-5 * 0.5 / std::f64::consts::LN_2 * (2f64.powf((t - 1.5) / 0.5) - 1.0);
        relax + if t <= 1.5 { 0.0 } else { grow(t.min(4.5)) }
    }

    fn run(confirm: f64) -> SettleState {
        let mut s = SettleState::new(5e-4, 0.5, 0.2, confirm);
        let dt = 1.0 / 240.0;
        for k in 0..(12.0 / dt) as usize {
            let t = k as f64 * dt;
            s.observe(t, &[DVec3::new(passage(t), 0.0, 0.0)]);
        }
        s
    }

    /// Without a watch the quiet window before the passage (mean speed below 0.5 mm/s from
    /// 1 s) counts as rest; the node then moves 2.3 mm (the growing mode's 2^6 − 1 times
    /// 0.036 mm). A 2 s watch sees the node leave (it may travel 0.25 mm, as far as in a quiet
    /// window), undoes that window and settles only once the passage has stopped at 4.5 s.
    #[test]
    fn a_slow_passage_is_not_rest_under_a_confirmation_watch() {
        let hasty = run(0.0);
        let early = hasty.settled_at.unwrap();
        assert!(early < 1.5, "without a watch: settled at {early} s");
        assert!(passage(4.5) - passage(early + 0.5) > 2e-3);
        let watched = run(2.0);
        let late = watched.settled_at.unwrap();
        assert!(watched.restarts >= 1, "no window undone");
        assert!(
            late >= 4.5 - 0.5,
            "with a watch: settled at {late} s, before the passage ended"
        );
    }

    /// The run takes its rest step while [`SettleState::quiet`]: from the quiet window before
    /// the passage, until the watch undoes it (the step is then the moving one again), and
    /// again once the passage has stopped.
    #[test]
    fn the_cloth_stops_being_quiet_when_the_watch_undoes_its_window() {
        let mut s = SettleState::new(5e-4, 0.5, 0.2, 2.0);
        let dt = 1.0 / 240.0;
        let mut changes = Vec::new();
        let mut quiet = false;
        for k in 0..(12.0 / dt) as usize {
            let t = k as f64 * dt;
            s.observe(t, &[DVec3::new(passage(t), 0.0, 0.0)]);
            if s.quiet() != quiet {
                quiet = s.quiet();
                changes.push((t, quiet));
            }
        }
        assert!(changes.len() >= 3, "quiet changed at {changes:?}");
        let (first, undone, last) = (changes[0], changes[1], changes[changes.len() - 1]);
        assert!(first.1 && first.0 < 2.0, "first quiet at {first:?}");
        assert!(!undone.1 && undone.0 < 4.5, "window undone at {undone:?}");
        assert!(last.1 && quiet && last.0 >= 4.5, "quiet again at {last:?}");
    }
}
