//! Fabric data: KES-F measurements as files, their one conversion to SI, and the elastic laws
//! (bending M(K), shear F(φ), tensile T(ε)) that the force generators read.
//!
//! - [`kes_units`]: KES units → SI, the only place where units change.
//! - [`KesFabric`]: the fabric file schema, in KES units.
//! - [`Fabric`]: the validated fabric in SI.
//! - [`ElasticCurve`], [`TensileLaw`]: the curves.

mod elastic_curve;
mod fabric;
mod fabric_error;
mod kes_fabric;
pub mod kes_units;
mod tensile_law;

pub use elastic_curve::{CurveSampleError, ElasticCurve};
pub use fabric::{BendingLaw, Fabric, ShearLaw, TensileProperties, Thread};
pub use fabric_error::{Allowed, FabricLoadError, InvalidFabric};
pub use kes_fabric::{KesBending, KesCurves, KesFabric, KesLoop, KesShear, KesTensile, PerThread};
pub use kes_units::{GRAM_FORCE, KesUnit, STANDARD_GRAVITY};
pub use tensile_law::TensileLaw;
