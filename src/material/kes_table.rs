//! Fabrics from a spreadsheet: one fabric per row of a CSV table, under the column names KES-F
//! reports use, read into [`KesFabric`] and validated as a fabric file would be.
//!
//! Columns (case, spaces, `-` and `_` ignored; `-1` or `warp` marks the warp, `-2` or `weft` the
//! weft, and a column without a direction applies to both):
//!
//! | column | quantity | unit |
//! |---|---|---|
//! | `name`, `source` | the fabric's name; where its numbers come from | text |
//! | `W` | areal weight | mg/cm² (or g/m²) |
//! | `T` | thickness | mm |
//! | `B-1`, `B-2` or `B` | bending rigidity | gf·cm²/cm |
//! | `2HB-1`, `2HB-2` or `2HB` | bending hysteresis | gf·cm/cm |
//! | `G` | shear rigidity | gf/(cm·deg) |
//! | `2HG`, `2HG5` | shear hysteresis at 0.5° and 5° | gf/cm |
//! | `LT-1`, `LT-2` or `LT` | tensile linearity | – |
//! | `WT-1`, `WT-2` or `WT` | tensile energy | gf·cm/cm² |
//! | `RT-1`, `RT-2` or `RT` | tensile resilience | % |
//! | `EMT-1`, `EMT-2` or `EMT` | strain at 500 gf/cm | % |
//!
//! The units are these unless a units row follows the header (its `name` cell reads `unit` or
//! `units`); a unit there must be the column's own (W also takes g/m²).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::{Fabric, KesBending, KesCurves, KesFabric, KesShear, KesTensile, PerThread};

/// Reading a KES table failed; every case names the file, and the row and column where it can.
#[derive(Debug, thiserror::Error)]
pub enum FabricImportError {
    /// The file could not be read.
    #[error("{}: cannot read the table: {source}", path.display())]
    Io {
        /// The table.
        path: PathBuf,
        /// The I/O failure.
        source: std::io::Error,
    },
    /// The file is not well-formed CSV.
    #[error("{}: row {row}: {message}", path.display())]
    Csv {
        /// The table.
        path: PathBuf,
        /// 1-based row (the header is row 1).
        row: u64,
        /// The parser's description.
        message: String,
    },
    /// A column the fabric needs is not in the header.
    #[error("{}: row 1 (the header): no column `{column}` ({meaning}); the header has: {header}", path.display())]
    MissingColumn {
        /// The table.
        path: PathBuf,
        /// The missing column, as KES reports name it.
        column: String,
        /// What it holds, with its unit.
        meaning: String,
        /// The columns the header has.
        header: String,
    },
    /// A cell is not what its column holds.
    #[error("{}: row {row}, column {column} (`{header}`): {message}", path.display())]
    Cell {
        /// The table.
        path: PathBuf,
        /// 1-based row (the header is row 1).
        row: u64,
        /// 1-based column.
        column: usize,
        /// The column's header.
        header: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// One quantity of the fabric: how to find its column and where its value goes.
struct Quantity {
    /// The column name in KES reports, without a direction.
    key: &'static str,
    /// Meaning and unit, for messages.
    meaning: &'static str,
    /// Per thread direction (warp `-1`, weft `-2`).
    per_thread: bool,
    /// Accepted unit spellings (normalised) and the factor to the KES unit.
    units: &'static [(&'static str, f64)],
    /// The field path in a fabric file (with `{dir}` for the direction).
    field: &'static str,
}

const QUANTITIES: &[Quantity] = &[
    Quantity {
        key: "W",
        meaning: "areal weight, mg/cm²",
        per_thread: false,
        units: &[("mg/cm2", 1.0), ("g/m2", 0.1)],
        field: "weight_mg_per_cm2",
    },
    Quantity {
        key: "T",
        meaning: "thickness, mm",
        per_thread: false,
        units: &[("mm", 1.0)],
        field: "thickness_mm",
    },
    Quantity {
        key: "B",
        meaning: "bending rigidity, gf·cm²/cm",
        per_thread: true,
        units: &[("gfcm2/cm", 1.0)],
        field: "bending.{dir}.b",
    },
    Quantity {
        key: "2HB",
        meaning: "bending hysteresis, gf·cm/cm",
        per_thread: true,
        units: &[("gfcm/cm", 1.0)],
        field: "bending.{dir}.two_hb",
    },
    Quantity {
        key: "G",
        meaning: "shear rigidity, gf/(cm·deg)",
        per_thread: false,
        units: &[("gf/cmdeg", 1.0), ("gf/cm/deg", 1.0)],
        field: "shear.g",
    },
    Quantity {
        key: "2HG",
        meaning: "shear hysteresis at 0.5°, gf/cm",
        per_thread: false,
        units: &[("gf/cm", 1.0)],
        field: "shear.two_hg",
    },
    Quantity {
        key: "2HG5",
        meaning: "shear hysteresis at 5°, gf/cm",
        per_thread: false,
        units: &[("gf/cm", 1.0)],
        field: "shear.two_hg5",
    },
    Quantity {
        key: "LT",
        meaning: "tensile linearity, dimensionless",
        per_thread: true,
        units: &[("", 1.0), ("-", 1.0), ("none", 1.0), ("dimensionless", 1.0)],
        field: "tensile.{dir}.lt",
    },
    Quantity {
        key: "WT",
        meaning: "tensile energy, gf·cm/cm²",
        per_thread: true,
        units: &[("gfcm/cm2", 1.0)],
        field: "tensile.{dir}.wt",
    },
    Quantity {
        key: "RT",
        meaning: "tensile resilience, %",
        per_thread: true,
        units: &[("%", 1.0)],
        field: "tensile.{dir}.rt",
    },
    Quantity {
        key: "EMT",
        meaning: "strain at 500 gf/cm, %",
        per_thread: true,
        units: &[("%", 1.0)],
        field: "tensile.{dir}.emt",
    },
];

/// A column name or unit reduced to compare: lower case, without spaces, `-`, `_`, `·`, `.`,
/// `*`, `(`, `)`, and with `²` as `2`.
fn normalise(text: &str) -> String {
    text.trim()
        .to_lowercase()
        .replace('²', "2")
        .chars()
        .filter(|c| !matches!(c, ' ' | '-' | '_' | '·' | '.' | '*' | '(' | ')'))
        .collect()
}

/// One fabric read from a row, with the row it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedFabric {
    /// 1-based row of the table (the header is row 1).
    pub row: u64,
    /// The fabric in KES units, validated.
    pub kes: KesFabric,
}

/// Reads every fabric of the CSV table at `path` and validates each as a fabric file.
pub fn read_kes_table(path: &Path) -> Result<Vec<ImportedFabric>, FabricImportError> {
    let text = std::fs::read_to_string(path).map_err(|source| FabricImportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut reader = csv::ReaderBuilder::new()
        .flexible(false)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let csv_error = |e: csv::Error| FabricImportError::Csv {
        path: path.to_path_buf(),
        row: e.position().map_or(1, |p| p.line()),
        message: e.to_string(),
    };
    let header: Vec<String> = reader
        .headers()
        .map_err(csv_error)?
        .iter()
        .map(str::to_string)
        .collect();
    let columns: HashMap<String, usize> = header
        .iter()
        .enumerate()
        .map(|(i, h)| (normalise(h), i))
        .collect();
    let find = |names: &[String]| names.iter().find_map(|n| columns.get(n).copied());
    let missing = |column: &str, meaning: &str| FabricImportError::MissingColumn {
        path: path.to_path_buf(),
        column: column.to_string(),
        meaning: meaning.to_string(),
        header: header.join(", "),
    };
    let name_column = find(&["name".into()]).ok_or_else(|| missing("name", "the fabric's name"))?;
    let source_column =
        find(&["source".into()]).ok_or_else(|| missing("source", "where the fabric's numbers come from"))?;
    // field path → column, for every quantity and direction.
    let mut fields: Vec<(String, &Quantity, usize)> = Vec::new();
    for q in QUANTITIES {
        let key = normalise(q.key);
        if q.per_thread {
            for (dir, marks) in [("warp", ["1", "warp"]), ("weft", ["2", "weft"])] {
                let names: Vec<String> = marks
                    .iter()
                    .map(|m| format!("{key}{m}"))
                    .chain([key.clone()])
                    .collect();
                let column = find(&names).ok_or_else(|| {
                    missing(
                        &format!("{}-{}", q.key, if dir == "warp" { 1 } else { 2 }),
                        &format!("{} along the {dir}; or `{}` for both", q.meaning, q.key),
                    )
                })?;
                fields.push((q.field.replace("{dir}", dir), q, column));
            }
        } else {
            let column = find(&[key]).ok_or_else(|| missing(q.key, q.meaning))?;
            fields.push((q.field.to_string(), q, column));
        }
    }
    let cell_error = |row: u64, column: usize, message: String| FabricImportError::Cell {
        path: path.to_path_buf(),
        row,
        column: column + 1,
        header: header.get(column).cloned().unwrap_or_default(),
        message,
    };
    let mut units: HashMap<usize, f64> = HashMap::new();
    let mut fabrics: Vec<ImportedFabric> = Vec::new();
    let mut names: HashMap<String, u64> = HashMap::new();
    for (index, record) in reader.records().enumerate() {
        let record = record.map_err(csv_error)?;
        let row = record.position().map_or(index as u64 + 2, |p| p.line());
        let cell = |column: usize| record.get(column).unwrap_or("");
        if index == 0 && matches!(normalise(cell(name_column)).as_str(), "unit" | "units") {
            for (_, q, column) in &fields {
                let written = normalise(cell(*column));
                let Some(&(_, factor)) = q.units.iter().find(|(u, _)| *u == written) else {
                    return Err(cell_error(
                        row,
                        *column,
                        format!(
                            "unit `{}`: column {} holds the {}; units accepted: {}",
                            cell(*column),
                            q.key,
                            q.meaning,
                            q.units
                                .iter()
                                .map(|(u, _)| if u.is_empty() { "(none)" } else { u })
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                };
                units.insert(*column, factor);
            }
            continue;
        }
        let name = cell(name_column).to_string();
        if name.is_empty() {
            return Err(cell_error(row, name_column, "a fabric needs a name".into()));
        }
        if let Some(first) = names.get(&name) {
            return Err(cell_error(
                row,
                name_column,
                format!("`{name}` is already the name of row {first}: names must differ"),
            ));
        }
        names.insert(name.clone(), row);
        let mut values: HashMap<&str, (f64, usize)> = HashMap::new();
        for (field, _, column) in &fields {
            let text = cell(*column);
            let value: f64 = text
                .parse()
                .map_err(|_| cell_error(row, *column, format!("`{text}` is not a number ({field})")))?;
            let factor = units.get(column).copied().unwrap_or(1.0);
            values.insert(field.as_str(), (value * factor, *column));
        }
        let v = |field: &str| values[field].0;
        let kes = KesFabric {
            name: name.clone(),
            source: cell(source_column).to_string(),
            weight_mg_per_cm2: v("weight_mg_per_cm2"),
            thickness_mm: v("thickness_mm"),
            bending: PerThread {
                warp: KesBending {
                    b: v("bending.warp.b"),
                    two_hb: v("bending.warp.two_hb"),
                },
                weft: KesBending {
                    b: v("bending.weft.b"),
                    two_hb: v("bending.weft.two_hb"),
                },
            },
            shear: KesShear {
                g: v("shear.g"),
                two_hg: v("shear.two_hg"),
                two_hg5: v("shear.two_hg5"),
            },
            tensile: PerThread {
                warp: tensile(&v, "warp"),
                weft: tensile(&v, "weft"),
            },
            tensile_max_load_gf_per_cm: 500.0,
            curves: KesCurves::default(),
        };
        if let Err(invalid) = Fabric::from_kes(&kes) {
            let column = match invalid.field.as_str() {
                "source" => source_column,
                field => values.get(field).map_or(name_column, |v| v.1),
            };
            return Err(cell_error(row, column, invalid.to_string()));
        }
        fabrics.push(ImportedFabric { row, kes });
    }
    Ok(fabrics)
}

/// The tensile values along `dir` ("warp" or "weft").
fn tensile(v: &impl Fn(&str) -> f64, dir: &str) -> KesTensile {
    KesTensile {
        lt: v(&format!("tensile.{dir}.lt")),
        wt: v(&format!("tensile.{dir}.wt")),
        rt: v(&format!("tensile.{dir}.rt")),
        emt: v(&format!("tensile.{dir}.emt")),
    }
}

/// A file name for a fabric: its name in lower case, letters and digits, words joined by `_`.
pub fn fabric_file_stem(name: &str) -> String {
    let mut stem = String::new();
    for word in name
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
    {
        if !stem.is_empty() {
            stem.push('_');
        }
        stem.push_str(&word.to_lowercase());
    }
    if stem.is_empty() { "fabric".into() } else { stem }
}

/// The fabric file text of `fabric` (RON, KES units), with a header naming its origin.
pub fn fabric_file_text(fabric: &ImportedFabric, table: &Path) -> String {
    let body = ron::ser::to_string_pretty(&fabric.kes, ron::ser::PrettyConfig::default())
        .expect("a KES fabric always serialises");
    format!(
        "// {}: imported from {} row {}.\n// Units: W mg/cm², T mm, B gf·cm²/cm, 2HB gf·cm/cm, G gf/(cm·deg), 2HG and 2HG5 gf/cm,\n// LT dimensionless, WT gf·cm/cm², RT %, EMT %.\n{body}\n",
        fabric.kes.name,
        table.display(),
        fabric.row
    )
}
