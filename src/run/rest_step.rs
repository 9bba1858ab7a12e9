//! The step at rest (`integration.rest_dt_s`; `docs/model.md` §12, "The step at rest"): the
//! step each run of the schedule takes, `rest_dt_s` while the cloth is quiet and `dt_s`
//! otherwise.
//!
//! It applies only where a cloth at rest is at rest at any step: the implicit solve holds the
//! cloth's stretch and the supports' friction. Rapier's rope joints and Rapier's own friction
//! hold a resting cloth as well as their step lets them (thick cotton at 1 cm with rope joints,
//! stepped at 1/30 s once quiet, never came to rest), so there it does not apply. And a quiet
//! window the confirmation watch undoes while the cloth was at the rest step ends the rest step
//! for the rest of the run: the motion that undid it may be the long step's own.

use bevy_ecs::prelude::*;

use crate::measure::SettleState;
use crate::scene::Scene;
use crate::schedule::{Clock, Physics};

/// The steps a run chooses from.
pub(super) struct RestStep {
    /// The step in motion, `dt_s` (s).
    moving: f64,
    /// The step at rest (s), where it applies.
    rest: Option<f64>,
    /// Quiet windows undone before the step being taken, and whether it is taken at rest.
    current: (u32, bool),
}

impl RestStep {
    /// The steps of `scene` ([`crate::scene::SceneFile::rest_step_s`] says where the rest step
    /// applies).
    pub fn new(scene: &Scene) -> Self {
        Self {
            moving: scene.spec.integration.dt_s,
            rest: scene.spec.rest_step_s(),
            current: (0, false),
        }
    }

    /// Before a step: sets it on the clock and in Rapier, the rest step while the cloth is
    /// quiet and the run has not given it up.
    pub fn choose(&mut self, world: &mut World) {
        let settle = world.resource::<SettleState>();
        let (restarts, quiet) = (settle.restarts, settle.quiet());
        let mut clock = world.resource_mut::<Clock>();
        let at_rest = self.rest.is_some() && quiet && !clock.rest_given_up;
        let dt = match self.rest {
            Some(rest) if at_rest => rest,
            _ => self.moving,
        };
        clock.dt = dt;
        clock.rest_steps += u64::from(at_rest);
        self.current = (restarts, at_rest);
        world.resource_mut::<Physics>().0.integration_parameters.dt = dt as f32;
    }

    /// After the step: if the watch undid a quiet window during a step at rest, the run goes on
    /// at `dt_s` (kept on the clock, so that a checkpoint carries it).
    pub fn judge(&self, world: &mut World) {
        let (before, at_rest) = self.current;
        if at_rest && world.resource::<SettleState>().restarts > before {
            world.resource_mut::<Clock>().rest_given_up = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use rapier3d::prelude::PhysicsWorld;

    use super::*;

    /// A node at rest, then moving 1 mm between 1.5 and 1.6 s, then at rest again, under a 0.5 s
    /// window and a 2 s watch: the step grows to the rest step once the window is quiet, falls
    /// back when the watch undoes the window, and stays at `dt_s` from then on, in Rapier too.
    #[test]
    fn a_window_undone_at_the_rest_step_ends_it() {
        let (moving, rest) = (1.0 / 240.0, 1.0 / 30.0);
        let mut world = World::new();
        crate::scene::spawn::insert_resources(
            &mut world,
            PhysicsWorld::default(),
            moving,
            &crate::scene::SettleSpec {
                max_speed_m_per_s: 5e-4,
                hold_s: 0.5,
                confirm_s: 2.0,
                ..Default::default()
            },
        );
        let mut steps = RestStep {
            moving,
            rest: Some(rest),
            current: (0, false),
        };
        let mut log = Vec::new();
        while world.resource::<Clock>().time < 8.0 {
            steps.choose(&mut world);
            let mut clock = world.resource_mut::<Clock>();
            clock.time += clock.dt;
            let (t, dt) = (clock.time, clock.dt);
            let x = 1e-3 * ((t - 1.5) / 0.1).clamp(0.0, 1.0);
            let mut settle = world.resource_mut::<SettleState>();
            settle.observe(t, &[DVec3::new(x, 0.0, 0.0)]);
            let restarts = settle.restarts;
            steps.judge(&mut world);
            log.push((t, dt, restarts));
        }
        let rapier_dt = world.resource::<Physics>().0.integration_parameters.dt as f64;
        let step_at = |t: f64| log.iter().find(|(time, ..)| *time >= t).unwrap().1;
        assert_eq!(step_at(0.2), moving, "moving at the start");
        assert_eq!(step_at(1.2), rest, "at rest once quiet");
        assert_eq!(log.last().unwrap().2, 1, "one window undone");
        assert_eq!(step_at(1.9), moving, "back to dt_s once undone");
        assert_eq!(step_at(7.9), moving, "the rest step given up");
        assert!(world.resource::<Clock>().rest_given_up);
        assert!((rapier_dt - moving).abs() < 1e-9, "Rapier at {rapier_dt} s");
    }
}
