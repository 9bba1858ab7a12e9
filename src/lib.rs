//! # kes-cloth
//!
//! Woven cloth simulated from Kawabata (KES-F) measurements, after the particle model of
//! Horiba & Shimizu (after Breen et al.).
//!
//! Data flows one way:
//!
//! ```text
//!  assets/fabrics/*.ron ──► material::KesFabric ──► material::Fabric (SI) ──┐
//!  (KES units)              (schema)        kes_units: the one conversion     │
//!                                                                            ▼
//!  grid of crossings ──► forces::ClothTopology ──► forces::{Bending, Trellising,
//!                                                   SeedSeparation, KesTensile}
//!                        positions ──► forces::ClothGeometry ──► forces (N) per particle
//! ```
//!
//! - [`material`]: KES data, its conversion to SI, the elastic curves.
//! - [`forces`]: one force generator per effect, behind [`forces::ForceGenerator`].
//!
//! All quantities are SI (N, m, kg, s, rad) unless a name or doc says otherwise.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod bodies;
pub mod forces;
pub mod material;
pub mod measure;
pub mod output;
pub mod repeat;
mod ron_file;
pub mod run;
pub mod scene;
pub mod schedule;

pub use ron_file::RonError;
