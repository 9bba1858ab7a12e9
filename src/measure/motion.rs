//! Per-step motion statistics and the runaway limits.

use bevy_ecs::prelude::*;
use glam::DVec3;

use crate::forces::ClothTopology;

/// Motion of the cloth after the latest step.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Motion {
    /// Speed of the fastest node (m/s), as Rapier stores it.
    pub max_speed: f64,
    /// Largest distance a node moved over the latest step, divided by the step (m/s): how fast
    /// the nodes actually move. It differs from `max_speed` at a node resting on a contact,
    /// whose stored velocity Rapier's contact solve can leave at millimetres per second while
    /// its position stays put (`docs/model.md` §12).
    #[serde(default)]
    pub max_step_speed: f64,
    /// Index of the fastest node.
    pub fastest_node: usize,
    /// Kinetic energy of all nodes (J).
    pub kinetic_energy: f64,
    /// Height of the lowest node centre (m).
    pub min_height: f64,
    /// Largest |link length/σ − 1| now (dimensionless).
    pub max_strain: f64,
    /// Largest `max_strain` seen so far in the run.
    pub peak_strain: f64,
    /// Deepest node centre inside a world collider at the end of any step so far (m); measured
    /// only where a [`WorldColliders`] resource lists the colliders.
    pub peak_penetration: f64,
    /// Steps so far after which the strain limit moved nodes (an implicit cloth's links held
    /// within [`crate::implicit::STRAIN_LIMIT`]; 0 at the shipped scenes' steps, `docs/model.md`
    /// §12, "The longest step").
    #[serde(default)]
    pub strain_limited_steps: u64,
}

/// The world's colliders as true shapes with their centres (m), for the per-step penetration
/// check (inserted by the scene runner; optional for embedders).
#[derive(Resource, Clone, Debug, Default)]
pub struct WorldColliders(pub Vec<(crate::bodies::WorldShape, DVec3)>);

/// Which of [`WorldColliders`] ride on Rapier bodies: (index, body). Their centres are read
/// from Rapier each step before the penetration check.
#[derive(Resource, Clone, Debug, Default)]
pub struct MovingColliders(pub Vec<(usize, rapier3d::prelude::RigidBodyHandle)>);

/// |l/σ − 1| of every link.
pub fn link_strains<'a>(
    topology: &'a ClothTopology,
    positions: &'a [DVec3],
) -> impl Iterator<Item = f64> + 'a {
    let sigma = topology.spacing;
    topology
        .links
        .iter()
        .map(move |&[p, q]| ((positions[q as usize] - positions[p as usize]).length() / sigma - 1.0).abs())
}

impl Motion {
    /// The motion of nodes of `masses` (kg) at `positions` (m) with `velocities` (m/s), which
    /// were at `previous` (m) one step `dt` (s) earlier, on the grid `topology`.
    pub fn of(
        topology: &ClothTopology,
        masses: &[f64],
        (positions, previous, velocities): (&[DVec3], &[DVec3], &[DVec3]),
        dt: f64,
    ) -> Self {
        let mut m = Motion {
            min_height: f64::INFINITY,
            ..Default::default()
        };
        for (i, ((x, v), mass)) in positions.iter().zip(velocities).zip(masses).enumerate() {
            let speed = v.length();
            if speed > m.max_speed {
                m.max_speed = speed;
                m.fastest_node = i;
            }
            m.kinetic_energy += 0.5 * mass * speed * speed;
            m.min_height = m.min_height.min(x.y);
        }
        m.max_step_speed = positions
            .iter()
            .zip(previous)
            .map(|(x, before)| (*x - *before).length())
            .fold(0.0, f64::max)
            / dt;
        m.max_strain = link_strains(topology, positions).fold(0.0, f64::max);
        m
    }
}

/// What to suspect when a run runs away: with the implicit solve our forces are stable at any
/// step, so there it is the rope joints (solved by Rapier, after our solve), a step that carries
/// nodes too far for one linear solve, or the load. `stride` is how far the fastest node moves
/// in a step, in spacings (its speed times `dt` (s) over the spacing `spacing_m` (m)).
pub fn runaway_causes(implicit: bool, rope_joints: bool, dt: f64, (stride, spacing_m): (f64, f64)) -> String {
    let load = "a load the links cannot carry, such as a body much heavier than the nodes \
                pressing on the cloth (scenes/hard/ball_impact.ron)";
    match (implicit, rope_joints) {
        (true, true) => format!(
            "likely causes: links Rapier's rope joints cannot hold at dt = {dt} s (measured: a \
             wool tablecloth at 7.5 mm and 1/240 s; try more integration.solver_iterations, a \
             smaller integration.dt_s, or effects.stretch: Kes, which the implicit solve \
             integrates itself, docs/model.md §12), or {load}"
        ),
        (true, false) if stride > LONG_STRIDE => format!(
            "likely cause: a step too long for the lattice: the fastest node moves {stride:.1} \
             spacings a step (dt = {dt} s, spacing {:.2} mm). The solve knows only the contacts \
             of the last step, so where a surface stops nodes within the step their neighbours \
             swing about them by more than a spacing and the links stretch (docs/model.md §12, \
             \"The longest step\"); try integration.dt_s ≤ {:.4} s (half a spacing a step) or a \
             coarser cloth.spacing_m; else {load}",
            spacing_m * 1e3,
            dt * LONG_STRIDE / stride
        ),
        (true, false) => format!("likely cause: {load}"),
        (false, _) => format!(
            "likely causes: dt = {dt} s is too large for this effect's stiffness when applied \
             explicitly (docs/model.md §10; try a smaller integration.dt_s, or \
             integration.integrator: Implicit), or {load}"
        ),
    }
}

/// A node moving more than this many spacings a step can leave a link far outside what one
/// linear solve followed (`docs/model.md` §12, "The longest step"): 2.5 mm lattices run away
/// on landing at 1.4–2.8 spacings a step, and come through at 0.7.
pub const LONG_STRIDE: f64 = 0.5;

/// Link strain beyond which a run has diverged: no woven fabric survives 50 % stretch, and a
/// link shortened by half has folded through its neighbour.
pub const RUNAWAY_STRAIN: f64 = 0.5;

/// Node speed beyond which a run has diverged (m/s): ten times the speed of a cloth dropped
/// from 5 m, far above anything a drape or a hanging cloth reaches.
pub const RUNAWAY_SPEED: f64 = 100.0;
