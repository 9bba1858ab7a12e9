//! The one place where Kawabata (KES-F) units become SI.
//!
//! KES instruments report in gram-force, centimetres and degrees. Everything inside kes-cloth is
//! SI (N, m, kg, rad, s); a KES number crosses into the engine only through [`KesUnit::to_si`],
//! and leaves (for reports in the instrument's units) only through [`KesUnit::from_si`].
//! The factors are exact, built from the standard acceleration of gravity g_n = 9.80665 m/s².

/// Standard acceleration of gravity g_n (m/s²), exact by definition (CGPM 1901).
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// One gram-force in newtons: 1 gf = 1e-3 kg × g_n = 9.80665e-3 N.
pub const GRAM_FORCE: f64 = 1e-3 * STANDARD_GRAVITY;

/// One centimetre in metres.
const CENTIMETRE: f64 = 1e-2;

/// The KES quantities kes-cloth reads, each with its instrument unit.
///
/// `factor()` is the number of SI units in one KES unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KesUnit {
    /// B, bending rigidity per unit width: gf·cm²/cm → N·m (per metre of width: N·m²/m).
    BendingRigidity,
    /// 2HB and M(K), bending moment per unit width: gf·cm/cm → N·m/m (= N).
    MomentPerWidth,
    /// K, curvature: cm⁻¹ → m⁻¹.
    Curvature,
    /// G, shear rigidity: gf/(cm·degree) → N/m per radian.
    ShearRigidity,
    /// 2HG, 2HG5, F(φ), tensile load: force per unit length gf/cm → N/m.
    ForcePerLength,
    /// WT, tensile energy per unit area: gf·cm/cm² → J/m².
    TensileEnergy,
    /// W, areal weight: mg/cm² → kg/m².
    ArealWeight,
    /// T, thickness: mm → m.
    Thickness,
    /// EMT and RT: % → fraction (dimensionless).
    Percent,
    /// Shear angle φ: degree → radian.
    Degree,
}

impl KesUnit {
    /// SI units per KES unit (multiply a KES value by this to get SI).
    pub fn factor(self) -> f64 {
        match self {
            KesUnit::BendingRigidity => GRAM_FORCE * CENTIMETRE * CENTIMETRE / CENTIMETRE,
            KesUnit::MomentPerWidth => GRAM_FORCE * CENTIMETRE / CENTIMETRE,
            KesUnit::Curvature => 1.0 / CENTIMETRE,
            KesUnit::ShearRigidity => GRAM_FORCE / CENTIMETRE * (180.0 / std::f64::consts::PI),
            KesUnit::ForcePerLength => GRAM_FORCE / CENTIMETRE,
            KesUnit::TensileEnergy => GRAM_FORCE * CENTIMETRE / (CENTIMETRE * CENTIMETRE),
            KesUnit::ArealWeight => 1e-6 / (CENTIMETRE * CENTIMETRE),
            KesUnit::Thickness => 1e-3,
            KesUnit::Percent => 1e-2,
            KesUnit::Degree => std::f64::consts::PI / 180.0,
        }
    }

    /// Converts a value in this KES unit to SI.
    pub fn to_si(self, kes_value: f64) -> f64 {
        kes_value * self.factor()
    }

    /// Converts an SI value back to this KES unit (for reports in the instrument's units).
    pub fn from_si(self, si_value: f64) -> f64 {
        si_value / self.factor()
    }

    /// The KES unit as printed by the instrument, e.g. `gf·cm²/cm`.
    pub fn symbol(self) -> &'static str {
        match self {
            KesUnit::BendingRigidity => "gf·cm²/cm",
            KesUnit::MomentPerWidth => "gf·cm/cm",
            KesUnit::Curvature => "cm⁻¹",
            KesUnit::ShearRigidity => "gf/(cm·deg)",
            KesUnit::ForcePerLength => "gf/cm",
            KesUnit::TensileEnergy => "gf·cm/cm²",
            KesUnit::ArealWeight => "mg/cm²",
            KesUnit::Thickness => "mm",
            KesUnit::Percent => "%",
            KesUnit::Degree => "deg",
        }
    }
}
