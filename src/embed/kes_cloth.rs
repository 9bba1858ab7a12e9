//! A KES cloth driven from a plain Rapier loop.

use glam::DVec3;
use rapier3d::prelude::PhysicsWorld;

use super::{ClothParts, StepError};
use crate::bodies::{CarrierMemory, SheetContacts};
use crate::measure::{
    Motion, is_runaway, non_finite_force, non_finite_solve_message, non_finite_state,
    non_finite_state_message, runaway_message,
};

/// A cloth in a user's Rapier world. Each frame: [`KesCloth::step`], or
/// [`KesCloth::apply_forces`], your own `world.step_with_events(&SheetContacts, &())` (or
/// `world.step()` if no dynamic body touches the cloth), then [`KesCloth::after_step`].
///
/// [`SheetContacts`]: super::SheetContacts
///
/// Every step runs the scenes' divergence checks (`docs/model.md` §11) and returns a
/// [`StepError`] naming the step, the node and the effect instead of letting a diverging cloth
/// run on; after one, the cloth refuses further steps with the same error.
pub struct KesCloth {
    parts: ClothParts,
    /// Steps taken.
    steps: u64,
    /// Simulated time (s).
    time: f64,
    /// The failure that stopped the cloth.
    failure: Option<StepError>,
    /// The motion of the latest step.
    motion: Motion,
    /// Force (N) on each node from the host's dynamic bodies over the latest step.
    body_loads: Vec<DVec3>,
    /// Scratch space for the nodes' surface normals.
    normals: Vec<DVec3>,
    /// The host's dynamic bodies solved with the cloth in the last step.
    carriers: CarrierMemory,
}

impl KesCloth {
    /// Wraps built parts.
    pub fn from_parts(parts: ClothParts) -> Self {
        Self {
            parts,
            steps: 0,
            time: 0.0,
            failure: None,
            motion: Motion::default(),
            body_loads: Vec::new(),
            normals: Vec::new(),
            carriers: CarrierMemory::default(),
        }
    }

    /// Reads the nodes from `world`, computes every KES force (and, for an implicit cloth, solves
    /// for its velocity change over the world's step), and hands them to Rapier for the next step
    /// as a velocity kick F·dt/m on each node: call `world.step()` right after, then
    /// [`Self::after_step`]. Fails on a non-finite force, naming the effect.
    pub fn apply_forces(&mut self, world: &mut PhysicsWorld) -> Result<(), StepError> {
        if let Some(failure) = &self.failure {
            return Err(failure.clone());
        }
        let p = &mut self.parts;
        let state = &mut p.state;
        p.bodies.read(world, &mut state.positions, &mut state.velocities);
        state.geometry.update(&state.positions);
        state.forces.clear();
        p.effects.advance_state(&state.geometry);
        p.effects
            .add_forces(&state.geometry, &state.velocities, &mut state.forces);
        state.forces.resolve(&state.topology);
        for (f, load) in state.forces.particle.iter_mut().zip(&self.body_loads) {
            *f += *load;
        }
        if let Some(node) = non_finite_force(&state.forces.particle) {
            let effect = p
                .effects
                .first_non_finite(&state.topology, &state.positions, &state.velocities)
                .unwrap_or("unknown");
            let message = format!("non-finite force {:?} N", state.forces.particle[node]);
            return Err(self.fail(node, effect, message));
        }
        if let Some(implicit) = &mut p.implicit {
            p.bodies.read_supports(world, &mut implicit.supports);
            let links = &state.topology.links;
            p.bodies
                .read_link_supports(world, links, &state.positions, &mut implicit.supports);
            p.bodies.back_supported_nodes(world, &implicit.supports);
            let h = world.integration_parameters.dt as f64;
            p.bodies
                .read_pin_velocities(world, h, &mut implicit.pin_velocities);
            p.bodies.read_carriers(world, implicit, &mut self.carriers);
            let forces = &mut state.forces.particle;
            let g = p.bodies.gravity(world);
            let generators: Vec<_> = p.effects.iter().map(Some).collect();
            implicit.solve(&generators, &state.geometry, &state.velocities, forces, (h, g));
            if let Some(node) = non_finite_force(forces) {
                let message = non_finite_solve_message(forces[node]);
                return Err(self.fail(node, "implicit_solve", message));
            }
        }
        let p = &mut self.parts;
        p.bodies.write_forces(world, &p.state.forces.particle);
        if let Some(implicit) = &p.implicit {
            p.bodies.move_carriers(world, &implicit.carriers, &self.carriers);
        }
        p.bodies
            .write_sheet_normals(world, &p.state.topology, &p.state.positions, &mut self.normals);
        Ok(())
    }

    /// Reads the stepped nodes from `world` (call it after your `world.step()`) and checks them:
    /// a non-finite position or velocity, or a runaway (a node faster than
    /// [`crate::measure::RUNAWAY_SPEED`] or a link strained beyond
    /// [`crate::measure::RUNAWAY_STRAIN`]), is an error naming the effect pushing hardest on the
    /// node at fault. Before the checks, an implicit cloth's links are brought within the
    /// strain limit ([`crate::implicit::limit_strain`]; the moved nodes are written back into
    /// `world`).
    pub fn after_step(&mut self, world: &mut PhysicsWorld) -> Result<(), StepError> {
        if let Some(failure) = &self.failure {
            return Err(failure.clone());
        }
        let dt = world.integration_parameters.dt as f64;
        let p = &mut self.parts;
        let state = &mut p.state;
        std::mem::swap(&mut state.positions, &mut state.previous_positions);
        p.bodies.read(world, &mut state.positions, &mut state.velocities);
        p.bodies.read_body_loads(world, dt, &mut self.body_loads);
        let limited = p.implicit.as_ref().map_or(0, |solver| {
            p.bodies.limit_strain(
                world,
                (&state.topology, solver.held()),
                &mut state.positions,
                &mut state.velocities,
            )
        });
        if let Some(node) = non_finite_state(&state.positions, &state.velocities) {
            let message = non_finite_state_message(state.positions[node], state.velocities[node], dt);
            return Err(self.fail(node, "rapier_step", message));
        }
        let motion = Motion::of(
            &state.topology,
            &p.bodies.masses,
            (&state.positions, &state.previous_positions, &state.velocities),
            dt,
        );
        if is_runaway(&motion) {
            let node = motion.fastest_node;
            let effect = p
                .effects
                .strongest_at(node, &state.topology, &state.positions, &state.velocities)
                .unwrap_or("rapier_step");
            let message = runaway_message(
                &motion,
                p.implicit.is_some(),
                !p.bodies.joints.is_empty(),
                (dt, state.topology.spacing),
            );
            return Err(self.fail(node, effect, message));
        }
        let limited_steps = self.motion.strain_limited_steps + u64::from(limited > 0);
        self.motion = motion;
        self.motion.strain_limited_steps = limited_steps;
        self.steps += 1;
        self.time += dt;
        Ok(())
    }

    /// [`Self::apply_forces`], Rapier's step with [`super::SheetContacts`], [`Self::after_step`]; afterwards
    /// [`Self::positions`] is current.
    pub fn step(&mut self, world: &mut PhysicsWorld) -> Result<(), StepError> {
        self.apply_forces(world)?;
        world.step_with_events(&SheetContacts, &());
        self.after_step(world)
    }

    /// Records and returns the failure of the current step.
    fn fail(&mut self, node: usize, effect: &str, message: String) -> StepError {
        let error = StepError::Diverged {
            step: self.steps,
            time_s: self.time,
            node,
            effect: effect.to_string(),
            message,
        };
        self.failure = Some(error.clone());
        error
    }

    /// Node positions (m) as of the last read.
    pub fn positions(&self) -> &[DVec3] {
        &self.parts.state.positions
    }

    /// Node velocities (m/s) as of the last read.
    pub fn velocities(&self) -> &[DVec3] {
        &self.parts.state.velocities
    }

    /// The motion over the latest step: fastest node (m/s), how far nodes actually moved per
    /// second, largest link strain, kinetic energy (J).
    pub fn motion(&self) -> &Motion {
        &self.motion
    }

    /// Steps taken, and the simulated time they cover (s).
    pub fn clock(&self) -> (u64, f64) {
        (self.steps, self.time)
    }

    /// The lowest node's height (m).
    pub fn lowest_point(&self) -> f64 {
        self.positions().iter().map(|p| p.y).fold(f64::INFINITY, f64::min)
    }

    /// The cloth's parts (state, bodies, generators).
    pub fn parts(&self) -> &ClothParts {
        &self.parts
    }

    /// Gives the parts back, e.g. to move the cloth into a bevy_ecs world.
    pub fn into_parts(self) -> ClothParts {
        self.parts
    }
}
