//! A fabric as a table people read: every KES value in its instrument unit beside the SI value
//! the engine uses, and the bending lengths.

use crate::material::{Fabric, KesFabric, Thread};

/// One line of the sheet: symbol, meaning, warp and weft (or one) values in KES units, the KES
/// unit, and the SI values with their unit.
struct Line {
    symbol: &'static str,
    meaning: &'static str,
    kes: [f64; 2],
    kes_unit: &'static str,
    si: [f64; 2],
    si_unit: &'static str,
    per_thread: bool,
}

/// `value` with four significant digits, plain where that reads well (trailing zeros dropped:
/// 1.25, 2.5, 3.333, 10).
pub fn number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-3..1e5).contains(&magnitude) {
        let decimals = (3 - magnitude.log10().floor() as i32).clamp(0, 6) as usize;
        let text = format!("{value:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{value:.3e}")
    }
}

/// The sheet of `fabric` (validated and in SI) as read from `kes` (its KES values).
pub fn fabric_sheet(kes: &KesFabric, fabric: &Fabric) -> String {
    let both = |x: f64| [x, x];
    let b = |t: Thread| fabric.bending(t);
    let tensile = |t: Thread| fabric.tensile(t);
    let lines = [
        Line {
            symbol: "W",
            meaning: "areal weight",
            kes: both(kes.weight_mg_per_cm2),
            kes_unit: "mg/cm²",
            si: both(fabric.areal_density),
            si_unit: "kg/m²",
            per_thread: false,
        },
        Line {
            symbol: "T",
            meaning: "thickness",
            kes: both(kes.thickness_mm),
            kes_unit: "mm",
            si: both(fabric.thickness),
            si_unit: "m",
            per_thread: false,
        },
        Line {
            symbol: "B",
            meaning: "bending rigidity",
            kes: [kes.bending.warp.b, kes.bending.weft.b],
            kes_unit: "gf·cm²/cm",
            si: [b(Thread::Warp).rigidity, b(Thread::Weft).rigidity],
            si_unit: "N·m",
            per_thread: true,
        },
        Line {
            symbol: "2HB",
            meaning: "bending hysteresis",
            kes: [kes.bending.warp.two_hb, kes.bending.weft.two_hb],
            kes_unit: "gf·cm/cm",
            si: [b(Thread::Warp).hysteresis_width, b(Thread::Weft).hysteresis_width],
            si_unit: "N",
            per_thread: true,
        },
        Line {
            symbol: "G",
            meaning: "shear rigidity",
            kes: both(kes.shear.g),
            kes_unit: "gf/(cm·deg)",
            si: both(fabric.shear.rigidity),
            si_unit: "N/m/rad",
            per_thread: false,
        },
        Line {
            symbol: "2HG",
            meaning: "shear hysteresis at 0.5°",
            kes: both(kes.shear.two_hg),
            kes_unit: "gf/cm",
            si: both(fabric.shear.hysteresis_width_small),
            si_unit: "N/m",
            per_thread: false,
        },
        Line {
            symbol: "2HG5",
            meaning: "shear hysteresis at 5°",
            kes: both(kes.shear.two_hg5),
            kes_unit: "gf/cm",
            si: both(fabric.shear.hysteresis_width_large),
            si_unit: "N/m",
            per_thread: false,
        },
        Line {
            symbol: "LT",
            meaning: "tensile linearity",
            kes: [kes.tensile.warp.lt, kes.tensile.weft.lt],
            kes_unit: "–",
            si: [tensile(Thread::Warp).linearity, tensile(Thread::Weft).linearity],
            si_unit: "–",
            per_thread: true,
        },
        Line {
            symbol: "WT",
            meaning: "tensile energy",
            kes: [kes.tensile.warp.wt, kes.tensile.weft.wt],
            kes_unit: "gf·cm/cm²",
            si: [tensile(Thread::Warp).energy, tensile(Thread::Weft).energy],
            si_unit: "J/m²",
            per_thread: true,
        },
        Line {
            symbol: "RT",
            meaning: "tensile resilience",
            kes: [kes.tensile.warp.rt, kes.tensile.weft.rt],
            kes_unit: "%",
            si: [tensile(Thread::Warp).resilience, tensile(Thread::Weft).resilience],
            si_unit: "–",
            per_thread: true,
        },
        Line {
            symbol: "EMT",
            meaning: "strain at T_m",
            kes: [kes.tensile.warp.emt, kes.tensile.weft.emt],
            kes_unit: "%",
            si: [
                tensile(Thread::Warp).law.strain_at_max_load,
                tensile(Thread::Weft).law.strain_at_max_load,
            ],
            si_unit: "–",
            per_thread: true,
        },
    ];
    let mut out = format!("{}\nsource: {}\n\n", fabric.name, fabric.source);
    out.push_str(&format!(
        "{:<5} {:<26} {:>10} {:>10}  {:<12} {:>11} {:>11}  {}\n",
        "", "", "warp", "weft", "KES unit", "SI warp", "SI weft", "SI unit"
    ));
    for l in &lines {
        let (kes_weft, si_weft) = if l.per_thread {
            (number(l.kes[1]), number(l.si[1]))
        } else {
            ("".into(), "".into())
        };
        out.push_str(&format!(
            "{:<5} {:<26} {:>10} {:>10}  {:<12} {:>11} {:>11}  {}\n",
            l.symbol,
            l.meaning,
            number(l.kes[0]),
            kes_weft,
            l.kes_unit,
            number(l.si[0]),
            si_weft,
            l.si_unit
        ));
    }
    out.push_str(&format!(
        "\nT_m, tensile test's maximum load: {} gf/cm\nbending length c = (B/W)^(1/3): warp {:.2} cm, weft {:.2} cm (BS 3356 / ASTM D1388: a strip overhanging 2c bends down to 41.5°)\n",
        number(kes.tensile_max_load_gf_per_cm),
        fabric.bending_length(Thread::Warp) * 100.0,
        fabric.bending_length(Thread::Weft) * 100.0,
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::number;

    /// Numbers keep four significant digits and drop trailing zeros.
    #[test]
    fn numbers_read_plainly() {
        assert_eq!(number(12.5), "12.5");
        assert_eq!(number(0.055), "0.055");
        assert_eq!(number(500.0), "500");
        assert_eq!(number(5.393e-6), "5.393e-6");
        assert_eq!(number(0.0), "0");
    }

    /// A run's summary gives its spacing in millimetres through [`number`]: to one decimal,
    /// 1.25 mm would read as 1.2 mm.
    #[test]
    fn a_spacing_of_one_and_a_quarter_millimetres_reads_as_it_is() {
        assert_eq!(number(0.00125 * 1e3), "1.25");
        assert_eq!(number(0.001875 * 1e3), "1.875");
        assert_eq!(number(0.01 / 3.0 * 1e3), "3.333");
        assert_eq!(number(0.0025 * 1e3), "2.5");
    }
}
