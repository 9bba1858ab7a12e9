//! Fabric data: KES-F measurements as files, their one conversion to SI, and the elastic laws
//! (bending M(K), shear F(φ), tensile T(ε)) that the force generators read.
//!
//! - [`kes_units`]: KES units → SI, the only place where units change.
//! - [`KesFabric`]: the fabric file schema, in KES units.
//! - [`Fabric`]: the validated fabric in SI.
//! - [`ElasticCurve`], [`TensileLaw`]: the curves.
//! - [`HysteresisLaw`]: the friction elements behind the KES loop widths 2HB, 2HG, 2HG5.

mod elastic_curve;
mod fabric;
mod fabric_error;
mod hysteresis_law;
mod kes_fabric;
mod kes_table;
pub mod kes_units;
mod tensile_law;

pub use elastic_curve::{CurveSampleError, ElasticCurve};
pub use fabric::{BendingLaw, Fabric, ShearLaw, TensileProperties, Thread};
pub use fabric_error::{Allowed, FabricLoadError, InvalidFabric};
pub use hysteresis_law::{BENDING_REVERSAL_SPAN, FrictionResponse, HysteresisLaw, SHEAR_REVERSAL_SPAN_DEG};
pub use kes_fabric::{KesBending, KesCurves, KesFabric, KesLoop, KesShear, KesTensile, PerThread};
pub use kes_table::{FabricImportError, ImportedFabric, fabric_file_stem, fabric_file_text, read_kes_table};
pub use kes_units::{GRAM_FORCE, KesUnit, STANDARD_GRAVITY};
pub use tensile_law::TensileLaw;
