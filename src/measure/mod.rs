//! Measurements of the cloth: motion, strain and height each step, the settle criterion, the
//! creep check after settling, and per-step progress.

mod creep;
mod drape;
mod motion;
mod penetration;
mod progress;
mod settle;

pub use creep::{Creep, CreepWatch};
pub use drape::{
    DrapeMeasurement, NODE_PROMINENCE, SkirtMeasurement, measure_drape, measure_skirt, peaks, project,
    union_area,
};
pub use motion::{
    Motion, MovingColliders, RUNAWAY_SPEED, RUNAWAY_STRAIN, WorldColliders, link_strains, runaway_causes,
};
pub use penetration::{depth_inside, max_penetration};
pub use progress::Progress;
pub use settle::SettleState;
