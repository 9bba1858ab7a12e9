//! The KES tensile law along one thread direction, from EMT, LT and the maximum load.
//!
//! KES-FB1 loads a strip to T_m (500 gf/cm as standard) and reports the strain there (EMT), the
//! work done (WT) and the linearity LT = WT / (T_m·EMT/2). A power law T(ε) = T_m·(ε/EMT)ⁿ has
//! exactly that work when n = 2/LT − 1, so it is the simplest curve that reproduces all three
//! summary values: LT = 1 gives a straight line, LT < 1 the stiffening toe of a woven fabric.
//! Compression mirrors tension (T is odd in ε): in-plane buckling is the bending springs' job,
//! and the mirror keeps neighbouring particles from passing through each other.

/// Tension per unit width T(ε) (N/m) as a power law of the engineering strain ε.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TensileLaw {
    /// T_m, the instrument's maximum load (N/m). Default 500 gf/cm = 490.33 N/m.
    pub max_load: f64,
    /// EMT as a fraction: strain at `max_load` (dimensionless, > 0).
    pub strain_at_max_load: f64,
    /// n = 2/LT − 1 ≥ 1 (dimensionless).
    pub exponent: f64,
}

impl TensileLaw {
    /// Builds the law from T_m (N/m), EMT (fraction) and LT (dimensionless, in (0, 1]).
    pub fn from_kes(max_load: f64, emt: f64, lt: f64) -> Self {
        Self {
            max_load,
            strain_at_max_load: emt,
            exponent: 2.0 / lt - 1.0,
        }
    }

    /// Tension per unit width T(ε) (N/m); odd in ε.
    #[inline]
    pub fn tension(&self, strain: f64) -> f64 {
        strain.signum() * self.max_load * (strain.abs() / self.strain_at_max_load).powf(self.exponent)
    }

    /// dT/dε (N/m): the tangent stiffness per unit width.
    #[inline]
    pub fn stiffness(&self, strain: f64) -> f64 {
        let s = (strain.abs() / self.strain_at_max_load).max(0.0);
        self.max_load * self.exponent * s.powf(self.exponent - 1.0) / self.strain_at_max_load
    }

    /// Energy per unit area ∫₀^ε T dε' (J/m²); even in ε. At ε = EMT it equals WT.
    #[inline]
    pub fn energy_density(&self, strain: f64) -> f64 {
        let s = strain.abs() / self.strain_at_max_load;
        self.max_load * self.strain_at_max_load * s.powf(self.exponent + 1.0) / (self.exponent + 1.0)
    }
}
