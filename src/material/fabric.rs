//! A fabric in SI: the laws every force generator reads.

use std::path::Path;

use super::elastic_curve::ElasticCurve;
use super::fabric_error::{Allowed, FabricLoadError, InvalidFabric};
use super::kes_fabric::{KesBending, KesFabric, KesLoop, KesTensile};
use super::kes_units::KesUnit;
use super::tensile_law::TensileLaw;

/// A thread direction of a woven fabric.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Thread {
    /// The warp (lengthwise threads).
    Warp = 0,
    /// The weft (crosswise threads).
    Weft = 1,
}

/// Bending along one thread direction (KES-FB2), SI.
#[derive(Clone, Debug, PartialEq)]
pub struct BendingLaw {
    /// B, bending rigidity per unit width (N·m, i.e. N·m²/m).
    pub rigidity: f64,
    /// 2HB, hysteresis width at K = ±1 cm⁻¹ (N·m/m = N).
    pub hysteresis_width: f64,
    /// Elastic mean curve M(K): moment per unit width (N·m/m) of curvature K (m⁻¹).
    pub moment: ElasticCurve,
}

/// Shear (trellising) of the fabric (KES-FB1), SI.
#[derive(Clone, Debug, PartialEq)]
pub struct ShearLaw {
    /// G, shear rigidity (N/m per radian).
    pub rigidity: f64,
    /// 2HG, hysteresis width at φ = ±0.5° (N/m).
    pub hysteresis_width_small: f64,
    /// 2HG5, hysteresis width at φ = ±5° (N/m).
    pub hysteresis_width_large: f64,
    /// Elastic mean curve of shear force per unit length F (N/m) against the trellis shear
    /// measure γ = sin φ (dimensionless; φ the shear angle). γ = sin φ is the sideways travel
    /// per unit height of a trellis of inextensible threads, so F·dγ is the work per unit area.
    pub force: ElasticCurve,
}

/// Tensile behaviour along one thread direction (KES-FB1), SI.
#[derive(Clone, Debug, PartialEq)]
pub struct TensileProperties {
    /// The load–strain law T(ε) built from EMT, LT and T_m.
    pub law: TensileLaw,
    /// LT, linearity (dimensionless).
    pub linearity: f64,
    /// WT, tensile energy to T_m (J/m²).
    pub energy: f64,
    /// RT, resilience (fraction in [0, 1]).
    pub resilience: f64,
}

/// A validated fabric in SI units.
#[derive(Clone, Debug, PartialEq)]
pub struct Fabric {
    /// Human name.
    pub name: String,
    /// Provenance of the numbers, as written in the fabric file.
    pub source: String,
    /// Areal density ρ_A (kg/m²).
    pub areal_density: f64,
    /// Thickness (m).
    pub thickness: f64,
    /// Bending, indexed by [`Thread`] (`[warp, weft]`).
    pub bending: [BendingLaw; 2],
    /// Shear (trellising).
    pub shear: ShearLaw,
    /// Tensile, indexed by [`Thread`] (`[warp, weft]`).
    pub tensile: [TensileProperties; 2],
}

/// Largest relative mismatch accepted between WT and LT·T_m·EMT/2 (KES defines LT that way;
/// 5 % leaves room for rounding in published tables but catches a wrong unit).
const WT_CONSISTENCY: f64 = 0.05;

impl Fabric {
    /// Reads, validates and converts a fabric file (RON, KES units).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, FabricLoadError> {
        Self::load_with_kes(path).map(|(_, fabric)| fabric)
    }

    /// Reads, validates and converts a fabric file, returning its KES values as written too.
    pub fn load_with_kes(path: impl AsRef<Path>) -> Result<(KesFabric, Self), FabricLoadError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| FabricLoadError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let kes: KesFabric = crate::ron_file::parse(&text).map_err(|e| FabricLoadError::Syntax {
            path: path.to_path_buf(),
            line: e.line,
            column: e.column,
            message: e.message,
        })?;
        let fabric = Self::from_kes(&kes).map_err(|source| FabricLoadError::Invalid {
            path: path.to_path_buf(),
            source,
        })?;
        Ok((kes, fabric))
    }

    /// Validates KES values and converts them to SI.
    pub fn from_kes(kes: &KesFabric) -> Result<Self, InvalidFabric> {
        use KesUnit as U;
        if kes.source.trim().is_empty() {
            return Err(InvalidFabric {
                field: "source".into(),
                value: "\"\"".into(),
                reason: "must say where the numbers come from".into(),
            });
        }
        check(
            "weight_mg_per_cm2",
            kes.weight_mg_per_cm2,
            Allowed::positive(200.0, "mg/cm²"),
            "W, areal weight",
        )?;
        check(
            "thickness_mm",
            kes.thickness_mm,
            Allowed::positive(20.0, "mm"),
            "T, thickness",
        )?;
        let max_load = kes.tensile_max_load_gf_per_cm;
        check(
            "tensile_max_load_gf_per_cm",
            max_load,
            Allowed::positive(5000.0, "gf/cm"),
            "T_m, tensile maximum load",
        )?;

        let bending = [
            bending_law("warp", &kes.bending.warp, &kes.curves.bending_warp)?,
            bending_law("weft", &kes.bending.weft, &kes.curves.bending_weft)?,
        ];

        let s = &kes.shear;
        check(
            "shear.g",
            s.g,
            Allowed::positive(100.0, "gf/(cm·deg)"),
            "G, shear rigidity",
        )?;
        check(
            "shear.two_hg",
            s.two_hg,
            Allowed::non_negative(200.0, "gf/cm"),
            "2HG, shear hysteresis at 0.5°",
        )?;
        check(
            "shear.two_hg5",
            s.two_hg5,
            Allowed::non_negative(200.0, "gf/cm"),
            "2HG5, shear hysteresis at 5°",
        )?;
        let shear_rigidity = U::ShearRigidity.to_si(s.g);
        let force = match &kes.curves.shear {
            Some(lp) => sampled_curve(
                "curves.shear",
                lp,
                |deg| U::Degree.to_si(deg).sin(),
                U::ForcePerLength,
            )?,
            // F = G·sin φ: slope G at φ = 0, and 0.1 % below G·φ at 5°.
            None => ElasticCurve::linear(shear_rigidity),
        };
        let shear = ShearLaw {
            rigidity: shear_rigidity,
            hysteresis_width_small: U::ForcePerLength.to_si(s.two_hg),
            hysteresis_width_large: U::ForcePerLength.to_si(s.two_hg5),
            force,
        };

        let tensile = [
            tensile_properties("warp", &kes.tensile.warp, max_load)?,
            tensile_properties("weft", &kes.tensile.weft, max_load)?,
        ];
        Ok(Self {
            name: kes.name.clone(),
            source: kes.source.clone(),
            areal_density: U::ArealWeight.to_si(kes.weight_mg_per_cm2),
            thickness: U::Thickness.to_si(kes.thickness_mm),
            bending,
            shear,
            tensile,
        })
    }

    /// Bending along `thread`.
    pub fn bending(&self, thread: Thread) -> &BendingLaw {
        &self.bending[thread as usize]
    }

    /// Shear force per unit length F (N/m) at shear angle φ (rad), from the elastic curve.
    pub fn shear_force_at_angle(&self, phi: f64) -> f64 {
        self.shear.force.value(phi.sin())
    }

    /// Tensile behaviour along `thread`.
    pub fn tensile(&self, thread: Thread) -> &TensileProperties {
        &self.tensile[thread as usize]
    }

    /// Bending length c = (B/W)^(1/3) along `thread` (m), with W the weight per area in N/m².
    /// The textile measure of how far a strip overhangs before it bends down (Peirce).
    pub fn bending_length(&self, thread: Thread) -> f64 {
        let weight = self.areal_density * crate::material::STANDARD_GRAVITY;
        (self.bending(thread).rigidity / weight).cbrt()
    }
}

fn bending_law(
    dir: &str,
    values: &KesBending,
    samples: &Option<KesLoop>,
) -> Result<BendingLaw, InvalidFabric> {
    use KesUnit as U;
    check(
        &format!("bending.{dir}.b"),
        values.b,
        Allowed::positive(100.0, "gf·cm²/cm"),
        "B, bending rigidity",
    )?;
    check(
        &format!("bending.{dir}.two_hb"),
        values.two_hb,
        Allowed::non_negative(100.0, "gf·cm/cm"),
        "2HB, bending hysteresis",
    )?;
    let rigidity = U::BendingRigidity.to_si(values.b);
    let moment = match samples {
        Some(lp) => sampled_curve(
            &format!("curves.bending_{dir}"),
            lp,
            |k| U::Curvature.to_si(k),
            U::MomentPerWidth,
        )?,
        None => ElasticCurve::linear(rigidity),
    };
    Ok(BendingLaw {
        rigidity,
        hysteresis_width: U::MomentPerWidth.to_si(values.two_hb),
        moment,
    })
}

fn tensile_properties(dir: &str, t: &KesTensile, max_load: f64) -> Result<TensileProperties, InvalidFabric> {
    use KesUnit as U;
    check(
        &format!("tensile.{dir}.lt"),
        t.lt,
        Allowed::positive(1.0, ""),
        "LT, tensile linearity (the power-law model needs LT ≤ 1)",
    )?;
    check(
        &format!("tensile.{dir}.emt"),
        t.emt,
        Allowed::positive(100.0, "%"),
        "EMT, strain at T_m",
    )?;
    check(
        &format!("tensile.{dir}.rt"),
        t.rt,
        Allowed::non_negative(100.0, "%"),
        "RT, tensile resilience",
    )?;
    check(
        &format!("tensile.{dir}.wt"),
        t.wt,
        Allowed::positive(1000.0, "gf·cm/cm²"),
        "WT, tensile energy",
    )?;
    let expected_wt = t.lt * max_load * (t.emt / 100.0) / 2.0;
    if ((t.wt - expected_wt) / expected_wt).abs() > WT_CONSISTENCY {
        return Err(InvalidFabric {
            field: format!("tensile.{dir}.wt"),
            value: t.wt.to_string(),
            reason: format!(
                "must equal LT·T_m·EMT/2 = {expected_wt:.3} gf·cm/cm² within {:.0} % (KES defines LT = WT/(T_m·EMT/2)); check the units of WT and EMT",
                WT_CONSISTENCY * 100.0
            ),
        });
    }
    Ok(TensileProperties {
        law: TensileLaw::from_kes(U::ForcePerLength.to_si(max_load), U::Percent.to_si(t.emt), t.lt),
        linearity: t.lt,
        energy: U::TensileEnergy.to_si(t.wt),
        resilience: U::Percent.to_si(t.rt),
    })
}

fn check(field: &str, value: f64, allowed: Allowed, meaning: &str) -> Result<(), InvalidFabric> {
    if allowed.contains(value) {
        Ok(())
    } else {
        Err(InvalidFabric {
            field: field.to_string(),
            value: value.to_string(),
            reason: format!("must lie in {allowed} ({meaning})"),
        })
    }
}

/// Builds the elastic curve of a sampled KES loop, converting both axes to SI.
/// `x_to_si` maps the file's abscissa to the curve's SI abscissa (monotone increasing).
fn sampled_curve(
    field: &str,
    lp: &KesLoop,
    x_to_si: impl Fn(f64) -> f64,
    y_unit: KesUnit,
) -> Result<ElasticCurve, InvalidFabric> {
    let to_si = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        pts.iter().map(|&(x, y)| (x_to_si(x), y_unit.to_si(y))).collect()
    };
    let units = format!("y in {}", y_unit.symbol());
    for (name, branch) in [("loading", &lp.loading), ("unloading", &lp.unloading)] {
        if let Some(pts) = branch {
            if let Some(bad) = pts.iter().position(|(x, y)| !x.is_finite() || !y.is_finite()) {
                return Err(InvalidFabric {
                    field: format!("{field}.{name}[{bad}]"),
                    value: format!("{:?}", pts[bad]),
                    reason: format!("must be finite numbers ({units})"),
                });
            }
            if let Some(bad) = (1..pts.len()).find(|&i| pts[i].0 <= pts[i - 1].0) {
                return Err(InvalidFabric {
                    field: format!("{field}.{name}[{bad}]"),
                    value: format!("{:?}", pts[bad]),
                    reason: format!("x must be strictly increasing ({units})"),
                });
            }
        }
    }
    let Some(mean) = &lp.mean else {
        return Err(InvalidFabric {
            field: format!("{field}.mean"),
            value: "None".into(),
            reason: "a sampled curve needs its elastic mean branch `mean` (the loading and unloading branches are kept for hysteresis)".into(),
        });
    };
    ElasticCurve::from_samples(&to_si(mean)).map_err(|e| InvalidFabric {
        field: format!("{field}.mean"),
        value: format!("{} samples", mean.len()),
        reason: format!("{e} ({units})"),
    })
}
