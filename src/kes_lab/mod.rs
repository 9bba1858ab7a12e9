//! The virtual KES laboratory: a simulated KES-FB2 pure-bending test and KES-FB1 shear test on a
//! small strip of a fabric, using the same force generators as every scene, read the way the
//! instruments read a sample (B, 2HB, G, 2HG, 2HG5).
//!
//! It proves that what a scene simulates is the fabric the file describes: run on a fabric, the
//! laboratory must give back the file's values (within the discretisation of the strip and the
//! sweep), and with hysteresis off it must find no loop at all.
//!
//! - [`bending_test`]: curvature swept 0 → +2.5 → −2.5 → +2.5 cm⁻¹, moment per width M(K).
//! - [`shear_test`]: shear angle swept 0 → +8° → −8° → +8°, shear force per length F(φ).
//! - [`KesLoop`]: slopes and loop widths read off a swept cycle.
//! - [`write_loop_plots`]: the loops as `kes_bending.png` and `kes_shear.png`.

pub mod bending_test;
mod kes_plot;
mod loop_reading;
pub mod shear_test;
mod strip;

pub use kes_plot::write_loop_plots;
pub use loop_reading::KesLoop;
pub use strip::{Reading, Strip, kes_cycle};

use crate::material::{Fabric, KesUnit, Thread};

/// B is the mean branch slope between these curvatures (m⁻¹): 0.5 and 1.5 cm⁻¹.
pub const B_RANGE: (f64, f64) = (50.0, 150.0);
/// 2HB is the loop width at this curvature (m⁻¹): ±1 cm⁻¹.
pub const HB_AT: f64 = 100.0;
/// G is the mean branch slope between these shear angles (degrees).
pub const G_RANGE_DEG: (f64, f64) = (0.5, 5.0);

/// A fabric's KES bending and shear summary, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KesSummary {
    /// B along [warp, weft] (N·m).
    pub bending_rigidity: [f64; 2],
    /// 2HB along [warp, weft] (N·m/m).
    pub bending_hysteresis: [f64; 2],
    /// G (N/m per radian).
    pub shear_rigidity: f64,
    /// 2HG, loop width at ±0.5° (N/m).
    pub shear_hysteresis_small: f64,
    /// 2HG5, loop width at ±5° (N/m).
    pub shear_hysteresis_large: f64,
}

impl KesSummary {
    /// The values a fabric was built from.
    pub fn of_fabric(fabric: &Fabric) -> Self {
        let b = |t| fabric.bending(t);
        Self {
            bending_rigidity: [b(Thread::Warp).rigidity, b(Thread::Weft).rigidity],
            bending_hysteresis: [b(Thread::Warp).hysteresis_width, b(Thread::Weft).hysteresis_width],
            shear_rigidity: fabric.shear.rigidity,
            shear_hysteresis_small: fabric.shear.hysteresis_width_small,
            shear_hysteresis_large: fabric.shear.hysteresis_width_large,
        }
    }

    /// Each value with its KES name and unit, in the instrument's order (SI values).
    pub fn entries(&self) -> [(&'static str, KesUnit, f64); 7] {
        [
            ("B_warp", KesUnit::BendingRigidity, self.bending_rigidity[0]),
            ("B_weft", KesUnit::BendingRigidity, self.bending_rigidity[1]),
            ("2HB_warp", KesUnit::MomentPerWidth, self.bending_hysteresis[0]),
            ("2HB_weft", KesUnit::MomentPerWidth, self.bending_hysteresis[1]),
            ("G", KesUnit::ShearRigidity, self.shear_rigidity),
            ("2HG", KesUnit::ForcePerLength, self.shear_hysteresis_small),
            ("2HG5", KesUnit::ForcePerLength, self.shear_hysteresis_large),
        ]
    }
}

/// One line of the laboratory's report, in KES units.
#[derive(Clone, Debug, PartialEq)]
pub struct KesRow {
    /// KES name, e.g. `B_warp`.
    pub name: &'static str,
    /// The KES unit of both values.
    pub unit: KesUnit,
    /// The fabric file's value (KES unit).
    pub file: f64,
    /// The laboratory's reading (KES unit).
    pub recovered: f64,
}

impl KesRow {
    /// (recovered − file)/file; `None` when the file's value is 0.
    pub fn relative_error(&self) -> Option<f64> {
        (self.file != 0.0).then(|| (self.recovered - self.file) / self.file)
    }
}

/// What the laboratory measured on one fabric.
#[derive(Clone, Debug, PartialEq)]
pub struct KesLabReport {
    /// The fabric's name.
    pub fabric: String,
    /// Node spacing of the strips (m).
    pub spacing: f64,
    /// Whether the strips carried the hysteresis effect.
    pub hysteresis: bool,
    /// The bending cycles along [warp, weft]: K (m⁻¹) against M (N·m/m).
    pub bending: [KesLoop; 2],
    /// The shear cycle: φ (rad) against F (N/m).
    pub shear: KesLoop,
    /// The file's values.
    pub file: KesSummary,
    /// The readings.
    pub recovered: KesSummary,
}

/// Runs both tests on `fabric` with strips of node spacing `spacing` (m), with or without the
/// hysteresis effect, and reads them.
pub fn run_kes_lab(fabric: &Fabric, spacing: f64, hysteresis: bool) -> KesLabReport {
    let cycle = |t| KesLoop {
        legs: bending_test::bending_cycle(fabric, t, spacing, hysteresis),
    };
    let bending = [cycle(Thread::Warp), cycle(Thread::Weft)];
    let shear = KesLoop {
        legs: shear_test::shear_cycle(fabric, spacing, hysteresis),
    };
    let (g0, g1) = (G_RANGE_DEG.0.to_radians(), G_RANGE_DEG.1.to_radians());
    let recovered = KesSummary {
        bending_rigidity: [0, 1].map(|t| bending[t].rigidity(B_RANGE.0, B_RANGE.1)),
        bending_hysteresis: [0, 1].map(|t| bending[t].width(HB_AT)),
        shear_rigidity: shear.rigidity(g0, g1),
        shear_hysteresis_small: shear.width(g0),
        shear_hysteresis_large: shear.width(g1),
    };
    KesLabReport {
        fabric: fabric.name.clone(),
        spacing,
        hysteresis,
        bending,
        shear,
        file: KesSummary::of_fabric(fabric),
        recovered,
    }
}

impl KesLabReport {
    /// File and recovered values side by side, in KES units.
    pub fn rows(&self) -> Vec<KesRow> {
        self.file
            .entries()
            .iter()
            .zip(self.recovered.entries())
            .map(|(&(name, unit, file), (_, _, recovered))| KesRow {
                name,
                unit,
                file: unit.from_si(file),
                recovered: unit.from_si(recovered),
            })
            .collect()
    }

    /// The report as a text table, as a KES instrument would print it.
    pub fn table(&self) -> String {
        let mut out = format!(
            "virtual KES-FB2 (bending, ±2.5 cm⁻¹) and KES-FB1 (shear, ±8°) on {}\nstrip spacing σ = {} mm, hysteresis {}\n\n{:<10} {:>10} {:>10} {:>8}  unit\n",
            self.fabric,
            self.spacing * 1e3,
            if self.hysteresis { "on" } else { "off" },
            "value",
            "file",
            "recovered",
            "error"
        );
        for row in self.rows() {
            let error = row
                .relative_error()
                .map_or("-".to_string(), |e| format!("{:+.1} %", 100.0 * e));
            out += &format!(
                "{:<10} {:>10.4} {:>10.4} {:>8}  {}\n",
                row.name,
                row.file,
                row.recovered,
                error,
                row.unit.symbol()
            );
        }
        out
    }

    /// The report as one JSON object keyed by KES name, each `{"file": v, "recovered": v}` in
    /// KES units.
    pub fn json(&self) -> serde_json::Value {
        let map = self
            .rows()
            .into_iter()
            .map(|r| {
                (
                    r.name.to_string(),
                    serde_json::json!({ "file": r.file, "recovered": r.recovered }),
                )
            })
            .collect::<serde_json::Map<_, _>>();
        serde_json::Value::Object(map)
    }
}
