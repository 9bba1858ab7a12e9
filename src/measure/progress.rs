//! Progress of a long run on the terminal (indicatif), updated from the schedule's output phase.

use bevy_ecs::prelude::*;
use indicatif::{ProgressBar, ProgressStyle};

use super::Motion;

/// A terminal progress bar over simulated time; present only for interactive runs.
#[derive(Resource)]
pub struct Progress {
    bar: ProgressBar,
    /// Update the bar every this many steps.
    every: u64,
}

impl Progress {
    /// A bar up to `max_time` (s), refreshed every `every` steps.
    pub fn new(max_time: f64, every: u64) -> Self {
        let bar = ProgressBar::new((max_time * 1000.0).round() as u64);
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:30} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self {
            bar,
            every: every.max(1),
        }
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// Shows simulated time `time` (s), the fastest node and the largest strain, every
    /// `every`-th `step`.
    pub fn show(&self, step: u64, time: f64, motion: &Motion) {
        if step % self.every == 0 {
            self.bar.set_position((time * 1000.0).round() as u64);
            self.bar.set_message(format!(
                "t = {:.2} s, fastest node {:.1} mm/s, max strain {:.2} %",
                time,
                motion.max_speed * 1000.0,
                motion.max_strain * 100.0
            ));
        }
    }
}
