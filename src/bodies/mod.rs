//! Cloth nodes as Rapier particle bodies: the one module that knows how.
//!
//! Each node is a small dynamic rigid body (rotations locked) with a ball collider; warp and weft
//! neighbours are linked by rope joints when stretch is a constraint. Why rigid-body nodes and
//! not Rapier's soft-body particles is measured and explained in `docs/rapier.md`: on the
//! drapemeter rim the soft body's trimesh contacts creep and slide off, ball contacts hold.
//! Everything else in kes-cloth talks to nodes through [`ClothBodies`], so the choice can change
//! here alone.

mod carriers;
mod cloth_bodies;
mod link_contacts;
mod sheet_contacts;
mod world_colliders;
mod world_settings;

pub use carriers::CarrierMemory;
pub use cloth_bodies::{ClothBodies, NodeOptions, TOUCH_DISTANCE};
pub use sheet_contacts::SheetContacts;
pub(crate) use sheet_contacts::{encode_normal, encode_surface_depth, sheet_normals};
pub use world_colliders::{ThrownBody, WorldShape, add_world_collider};
pub use world_settings::{ContactStiffness, configure_world};
