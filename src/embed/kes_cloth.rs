//! A KES cloth driven from a plain Rapier loop.

use glam::DVec3;
use rapier3d::prelude::PhysicsWorld;

use super::ClothParts;

/// A cloth in a user's Rapier world. Each frame: [`KesCloth::step`], or
/// [`KesCloth::apply_forces`] followed by your own `world.step()`.
pub struct KesCloth {
    parts: ClothParts,
}

impl KesCloth {
    /// Wraps built parts.
    pub fn from_parts(parts: ClothParts) -> Self {
        Self { parts }
    }

    /// Reads the nodes from `world`, computes every KES force, and hands them to Rapier for
    /// the next step as a velocity kick F·dt/m on each node: call `world.step()` right after.
    pub fn apply_forces(&mut self, world: &mut PhysicsWorld) {
        let p = &mut self.parts;
        let state = &mut p.state;
        p.bodies.read(world, &mut state.positions, &mut state.velocities);
        state.geometry.update(&state.positions);
        state.forces.clear();
        p.effects.advance_state(&state.geometry);
        p.effects
            .add_forces(&state.geometry, &state.velocities, &mut state.forces);
        state.forces.resolve(&state.topology);
        if let Some(implicit) = &mut p.implicit {
            p.bodies.read_supports(world, &mut implicit.supports);
            let h = world.integration_parameters.dt as f64;
            let forces = &mut state.forces.particle;
            let g = p.bodies.gravity(world);
            let generators: Vec<_> = p.effects.iter().map(Some).collect();
            implicit.solve(&generators, &state.geometry, &state.velocities, forces, (h, g));
        }
        p.bodies.write_forces(world, &state.forces.particle);
    }

    /// [`Self::apply_forces`] then `world.step()`; afterwards [`Self::positions`] is current.
    pub fn step(&mut self, world: &mut PhysicsWorld) {
        self.apply_forces(world);
        world.step();
        let state = &mut self.parts.state;
        self.parts
            .bodies
            .read(world, &mut state.positions, &mut state.velocities);
    }

    /// Node positions (m) as of the last read.
    pub fn positions(&self) -> &[DVec3] {
        &self.parts.state.positions
    }

    /// Node velocities (m/s) as of the last read.
    pub fn velocities(&self) -> &[DVec3] {
        &self.parts.state.velocities
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
