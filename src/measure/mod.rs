//! Measurements of the cloth: motion, strain and height each step, the settle criterion, the
//! creep check after settling, per-step progress, and the final shape's potential energy.

mod creep;
mod divergence;
mod drape;
mod energy;
mod motion;
mod penetration;
mod progress;
mod settle;

pub use creep::{Creep, CreepWatch};
pub use divergence::{
    is_runaway, non_finite_force, non_finite_solve_message, non_finite_state, non_finite_state_message,
    runaway_message,
};
pub use drape::{
    DrapeMeasurement, NODE_PROMINENCE, SkirtMeasurement, measure_drape, measure_skirt, peaks, project,
    union_area,
};
pub use energy::{PotentialEnergy, potential_energy};
pub use motion::{
    Motion, MovingColliders, RUNAWAY_SPEED, RUNAWAY_STRAIN, WorldColliders, link_strains, runaway_causes,
};
pub use penetration::{depth_inside, max_penetration};
pub use progress::Progress;
pub use settle::SettleState;
