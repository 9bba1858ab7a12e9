//! The fabric as the KES-F instruments report it: the schema of `assets/fabrics/*.ron`.
//!
//! Every number here is in the instrument's own unit (named in each field doc); nothing in the
//! engine reads this type. [`crate::material::Fabric::from_kes`] validates it and converts it to
//! SI through [`crate::material::KesUnit`], the one place where units change.

use serde::{Deserialize, Serialize};

/// One fabric's KES-F measurements (or honest estimates), in KES units.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesFabric {
    /// A short human name, e.g. "thick cotton drill".
    pub name: String,
    /// Where the numbers come from: a publication, or "representative values within the
    /// published ranges for ...". Never present an estimate as a measurement.
    pub source: String,
    /// W, areal weight (mg/cm²; 1 mg/cm² = 10 g/m²). Must be > 0.
    pub weight_mg_per_cm2: f64,
    /// T, thickness at 0.5 gf/cm² (mm). Must be > 0.
    pub thickness_mm: f64,
    /// KES-FB2 pure bending, per thread direction.
    pub bending: PerThread<KesBending>,
    /// KES-FB1 shear (mean of the warp and weft directions, as KES summaries report it).
    pub shear: KesShear,
    /// KES-FB1 tensile, per thread direction.
    pub tensile: PerThread<KesTensile>,
    /// T_m, the tensile test's maximum load (gf/cm). Default 500 (the standard for wovens).
    #[serde(default = "default_max_load")]
    pub tensile_max_load_gf_per_cm: f64,
    /// Optional sampled curves; where absent, curves are generated from the summary values.
    #[serde(default)]
    pub curves: KesCurves,
}

fn default_max_load() -> f64 {
    500.0
}

/// A value for each thread direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerThread<T> {
    /// Along the warp (the warp threads are the ones bent or stretched).
    pub warp: T,
    /// Along the weft.
    pub weft: T,
}

impl<T> PerThread<T> {
    /// The two values in the order [warp, weft].
    pub fn as_array(&self) -> [&T; 2] {
        [&self.warp, &self.weft]
    }
}

/// KES-FB2 bending summary values for one direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesBending {
    /// B, bending rigidity: slope of M(K) between 0.5 and 1.5 cm⁻¹ (gf·cm²/cm). Must be > 0.
    pub b: f64,
    /// 2HB, hysteresis width of M(K) at K = ±1 cm⁻¹ (gf·cm/cm). Must be ≥ 0.
    pub two_hb: f64,
}

/// KES-FB1 shear summary values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesShear {
    /// G, shear rigidity: slope of F(φ) between 0.5° and 5° (gf/(cm·degree)). Must be > 0.
    pub g: f64,
    /// 2HG, hysteresis width of F(φ) at φ = ±0.5° (gf/cm). Must be ≥ 0.
    pub two_hg: f64,
    /// 2HG5, hysteresis width of F(φ) at φ = ±5° (gf/cm). Must be ≥ 0.
    pub two_hg5: f64,
}

/// KES-FB1 tensile summary values for one direction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesTensile {
    /// LT, linearity of the load–strain curve (dimensionless, in (0, 1]).
    pub lt: f64,
    /// WT, tensile energy to T_m (gf·cm/cm²). Must equal LT·T_m·EMT/2 within 5 %.
    pub wt: f64,
    /// RT, tensile resilience (%, in [0, 100]).
    pub rt: f64,
    /// EMT, strain at T_m (%, in (0, 100]).
    pub emt: f64,
}

/// Optional sampled curves, positive branch only (the curves are odd).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesCurves {
    /// M(K) along the warp: K in cm⁻¹, M in gf·cm/cm.
    #[serde(default)]
    pub bending_warp: Option<KesLoop>,
    /// M(K) along the weft: K in cm⁻¹, M in gf·cm/cm.
    #[serde(default)]
    pub bending_weft: Option<KesLoop>,
    /// F(φ): φ in degrees, F in gf/cm.
    #[serde(default)]
    pub shear: Option<KesLoop>,
}

/// A sampled KES curve: the elastic mean and, optionally, the loading and unloading branches
/// that hysteresis will use. `(x, y)` pairs with x ≥ 0 strictly increasing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KesLoop {
    /// Mean (elastic) curve; if absent, the average of `loading` and `unloading`.
    #[serde(default)]
    pub mean: Option<Vec<(f64, f64)>>,
    /// Loading branch (|x| increasing).
    #[serde(default)]
    pub loading: Option<Vec<(f64, f64)>>,
    /// Unloading branch (|x| decreasing), sampled at increasing x.
    #[serde(default)]
    pub unloading: Option<Vec<(f64, f64)>>,
}
