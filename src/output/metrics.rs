//! `metrics.json`: the numbers of one run, all SI, the unit in each key.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Deserializer, Serialize};

use super::OutputError;

/// Calls and time of one effect.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EffectCost {
    /// Number of times its system ran.
    pub calls: u64,
    /// Wall time spent in it (s).
    pub seconds: f64,
}

/// Why a run stopped early.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailureReport {
    /// Step at which the failure was detected.
    pub step: u64,
    /// Simulated time then (s).
    pub time_s: f64,
    /// Node index.
    pub particle: usize,
    /// The effect that produced the non-finite value.
    pub effect: String,
    /// Description and likely cause.
    pub message: String,
}

/// Everything `metrics.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Scene name.
    pub scene: String,
    /// Fabric name.
    pub fabric: String,
    /// Number of cloth nodes.
    pub particles: usize,
    /// Node spacing σ (m).
    pub spacing_m: f64,
    /// Shift of the node lattice against a circular outline, along warp and weft (m; the scene's
    /// `cloth.lattice_offset_m`).
    pub lattice_offset_m: [f64; 2],
    /// Time step (s).
    pub dt_s: f64,
    /// Steps run.
    pub steps: u64,
    /// The step taken while the cloth was quiet (s; `integration.rest_dt_s`), absent when the
    /// run took no step at it (none asked for, not applicable, or never quiet).
    #[serde(default)]
    pub rest_dt_s: Option<f64>,
    /// Of `steps`, those taken at `rest_dt_s` (0 without one).
    #[serde(default)]
    pub rest_steps: u64,
    /// Simulated time (s).
    #[serde(deserialize_with = "null_as_nan")]
    pub sim_time_s: f64,
    /// Wall-clock time of the simulation loop (s).
    #[serde(deserialize_with = "null_as_nan")]
    pub wall_time_s: f64,
    /// Whether the settle criterion was met before the time limit.
    pub settled: bool,
    /// Simulated time at which the cloth came to rest (s), if it did.
    pub settle_time_s: Option<f64>,
    /// Largest |link length/σ − 1| at the end (dimensionless).
    #[serde(deserialize_with = "null_as_nan")]
    pub max_strain: f64,
    /// Largest link strain at any step (dimensionless).
    #[serde(deserialize_with = "null_as_nan")]
    pub peak_strain: f64,
    /// Steps after which the strain limit moved nodes (`docs/model.md` §12, "The longest
    /// step"): a step long for the lattice. 0 at the shipped scenes' steps.
    #[serde(default)]
    pub strain_limited_steps: u64,
    /// Height of the lowest node centre at the end (m).
    #[serde(deserialize_with = "null_as_nan")]
    pub min_height_m: f64,
    /// Deepest node centre inside a collider at the end (m); 0 when none is inside.
    #[serde(deserialize_with = "null_as_nan")]
    pub max_penetration_m: f64,
    /// Deepest node centre inside a collider at the end of any step (m).
    #[serde(deserialize_with = "null_as_nan")]
    pub peak_penetration_m: f64,
    /// Speed of the fastest node at the end, as Rapier stores it (m/s).
    #[serde(deserialize_with = "null_as_nan")]
    pub max_speed_m_per_s: f64,
    /// Largest distance a node moved over the last step, divided by the step (m/s). Unlike
    /// `max_speed_m_per_s`, not raised by the velocity Rapier's contact solve leaves on a node
    /// resting on a surface.
    #[serde(default, deserialize_with = "null_as_nan")]
    pub max_step_speed_m_per_s: f64,
    /// Largest node travel over the last settle window divided by its length (m/s): the
    /// quantity the settle criterion tests.
    pub window_speed_m_per_s: Option<f64>,
    /// Kinetic energy at the end (J).
    #[serde(deserialize_with = "null_as_nan")]
    pub kinetic_energy_j: f64,
    /// Gravitational energy of the final shape, −Σ mᵢ g·xᵢ (J; zero with every node at the
    /// height of the origin, the support's top in the shipped scenes). With
    /// `elastic_energy_j`, the potential energy that ranks two rest shapes of one lattice
    /// ([`crate::measure::potential_energy`]). `None` for a failed run.
    #[serde(default)]
    pub gravitational_energy_j: Option<f64>,
    /// Energy stored in the cloth's elastic effects in the final shape (J): bending,
    /// trellising, stretch, compression, hysteresis's element springs. `None` for a failed run.
    #[serde(default)]
    pub elastic_energy_j: Option<f64>,
    /// Drape coefficient (dimensionless), for scenes with a drapemeter disk; provisional when
    /// `settled` is false.
    pub drape_coefficient: Option<f64>,
    /// Number of folds (nodes) of the drape's outline (see `measure/drape.rs`).
    pub nodes: Option<u32>,
    /// Smallest radius of the smoothed shadow outline around the disk centre (m).
    pub outline_min_radius_m: Option<f64>,
    /// Largest radius of the smoothed shadow outline (m).
    pub outline_max_radius_m: Option<f64>,
    /// Fold amplitude, (max − min)/2 of the outline radius (m).
    pub fold_amplitude_m: Option<f64>,
    /// Tablecloths: mean hang of the four corners below the table top (m).
    pub hang_corners_m: Option<f64>,
    /// Tablecloths: mean hang of the four mid-sides below the table top (m).
    pub hang_mid_sides_m: Option<f64>,
    /// Tablecloths: folds of the skirt around the table (see `measure/drape.rs`).
    pub skirt_folds: Option<u32>,
    /// Cantilever test: the chord from the clamp's edge to the free end, from the clamp's
    /// direction (degrees; below the horizontal when gravity is along −y).
    #[serde(default)]
    pub cantilever_chord_deg: Option<f64>,
    /// Cantilever test: the heavy elastica's exact chord angle for the fabric's warp bending
    /// rigidity, its weight and the same overhang (degrees).
    #[serde(default)]
    pub cantilever_exact_deg: Option<f64>,
    /// `"Explicit"` or `"Implicit"`: how our forces were integrated.
    pub integrator: String,
    /// Implicit runs: conjugate-gradient products per step, averaged over the run.
    pub cg_iterations_mean: Option<f64>,
    /// Implicit runs: steps whose solve stopped at the iteration limit above its tolerance.
    pub cg_unconverged_steps: Option<u64>,
    /// Implicit runs with friction in the solve: steps solved twice because a support's static
    /// friction gave way.
    pub cg_repeated_steps: Option<u64>,
    /// Implicit runs with the Cholesky preconditioner: numeric factorisations over the run (0
    /// with block Jacobi).
    #[serde(default)]
    pub cg_factorisations: Option<u64>,
    /// Implicit runs: where the solve's wall time went, summed over the run (s).
    #[serde(default)]
    pub solve_split: Option<SolveSplit>,
    /// Per effect: calls and seconds (0 calls for an effect the scene did not ask for).
    pub effects: BTreeMap<String, EffectCost>,
    /// Quiet windows that the settle criterion's confirmation watch (`settle.confirm_s`) undid:
    /// slow passages that were not rest.
    #[serde(default)]
    pub settle_restarts: u32,
    /// Creep check (scenes with `settle.creep_check_s`): how long the cloth was watched after
    /// settling (s).
    pub creep_window_s: Option<f64>,
    /// Largest node displacement over the creep check (m).
    pub creep_max_node_m: Option<f64>,
    /// Displacement of the nodes' centroid over the creep check (m).
    pub creep_centroid_m: Option<f64>,
    /// The numerical error of the measured values, estimated from a companion run on a
    /// coarser lattice (`kes-cloth run` without `--no-error-estimate`; see
    /// [`crate::run::ErrorEstimate`]). `None` when not estimated.
    pub numerical_error: Option<crate::run::ErrorEstimate>,
    /// Set when the run stopped on a non-finite value.
    pub failure: Option<FailureReport>,
    /// The run was interrupted (Ctrl-C) before it settled or reached its time limit: these are
    /// partial results; `kes-cloth resume` continues from the last checkpoint.
    pub interrupted: bool,
}

/// Where an implicit run's solve spent its wall time, summed over the run (s). The three parts
/// add up to a little less than the `implicit_solve` effect's seconds (the rest is the kick and
/// the supports' bookkeeping).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolveSplit {
    /// Assembling the system: every generator's stiffness and damping blocks, the right-hand
    /// side and the particle rows (s).
    pub assembly_s: f64,
    /// Setting up the preconditioner: block inverses, thread-line and coarse factorisations,
    /// the sparse Cholesky factor (s).
    pub preconditioner_s: f64,
    /// The conjugate gradients themselves: products, preconditioner applications, vector
    /// updates (s).
    pub cg_s: f64,
}

impl Metrics {
    /// Writes `metrics.json` into `dir`. Non-finite numbers are written as null, never NaN.
    pub fn write(&self, dir: &Path) -> Result<(), OutputError> {
        let path = dir.join("metrics.json");
        let text = serde_json::to_string_pretty(self).map_err(|e| OutputError::new(&path, e))?;
        std::fs::write(&path, text + "\n").map_err(|e| OutputError::new(&path, e))
    }
}

/// Reads a number `Metrics::write` may have written as null (a non-finite value of a failed
/// run) back as NaN.
fn null_as_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}
