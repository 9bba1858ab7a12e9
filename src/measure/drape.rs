//! The drape test's numbers, measured as a drape laboratory does (BS 5058 / ISO 9073-9):
//! the drape coefficient from the shadow's area, and the folds (nodes) from its outline.
//!
//! **Shadow area.** The shadow is the union of the draped triangles projected on the
//! horizontal plane. It is integrated exactly along x and by the midpoint rule in z: for rows
//! Δz apart, each triangle cut by the row contributes an exact x-interval, the intervals are
//! merged, and their total length times Δz is the row's area. With Δz = σ/50 the rule's error
//! is far below the error of representing the cloth by flat triangles (tested on a polygonal
//! disk: relative error < 1e-4).
//!
//! **Drape coefficient.** DC = (A_s − A_d)/(A_D − A_d): A_s the shadow area, A_d the disk's area,
//! A_D the flat specimen's area (the area of the same triangles before draping, so a flat
//! specimen measures exactly 1).
//!
//! **Nodes.** The outline radius R(α) around the disk centre is the largest radius of the
//! shadow's boundary points (the merged intervals' ends) in 1° bins, empty bins filled by
//! circular interpolation, smoothed by a circular moving average over an arc of twice the node spacing (at least ±2°: features narrower than two nodes are below the mesh's resolution). A node is
//! a local maximum of the smoothed R(α) whose topographic prominence is at least
//! [`NODE_PROMINENCE`]; prominence, not height, so that ripples on a broad lobe do not count.

use glam::{DVec2, DVec3};

/// Smallest prominence of an outline peak counted as a node (m). 3 mm: well above the outline
/// noise of a cm-spaced mesh, well below the 1–5 cm lobes of a real drape.
pub const NODE_PROMINENCE: f64 = 0.003;

/// Gap (m) below which two row intervals are one: far below any mesh feature, far above
/// rounding.
const MERGE_TOLERANCE: f64 = 1e-9;

/// Angular bins of the outline profile.
const BINS: usize = 360;
/// Half-width of the circular smoothing window, in bins.
const SMOOTH_HALF_WIDTH: usize = 2;

/// What the drape test reports.
#[derive(Clone, Debug, PartialEq)]
pub struct DrapeMeasurement {
    /// A_s, projected (shadow) area of the draped cloth (m²).
    pub shadow_area: f64,
    /// DC (dimensionless; 1 = flat, 0 = hanging straight down).
    pub drape_coefficient: f64,
    /// Number of folds (nodes) of the outline.
    pub nodes: u32,
    /// Angles of the nodes around the disk centre (rad, from +x towards +z).
    pub node_angles: Vec<f64>,
    /// Outline radius at each node (m).
    pub node_radii: Vec<f64>,
    /// Smallest and largest outline radius, smoothed (m).
    pub min_radius: f64,
    /// See `min_radius`.
    pub max_radius: f64,
    /// Fold amplitude (max − min)/2 of the smoothed outline radius (m).
    pub fold_amplitude: f64,
}

/// Area (m²) of the union of triangles in the plane, rows `dz` (m) apart.
pub fn union_area(triangles: &[[DVec2; 3]], dz: f64) -> f64 {
    let mut total = 0.0;
    for_each_row(triangles, dz, |_, intervals| {
        total += intervals.iter().map(|(a, b)| b - a).sum::<f64>() * dz
    });
    total
}

/// Calls `f(z, merged intervals)` for every row z = z_min + (k + ½)·dz crossing the triangles.
fn for_each_row(triangles: &[[DVec2; 3]], dz: f64, mut f: impl FnMut(f64, &[(f64, f64)])) {
    if triangles.is_empty() {
        return;
    }
    let z_min = triangles
        .iter()
        .flatten()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min);
    let z_max = triangles
        .iter()
        .flatten()
        .map(|p| p.y)
        .fold(f64::NEG_INFINITY, f64::max);
    let rows = ((z_max - z_min) / dz).ceil() as usize;
    let mut per_row: Vec<Vec<(f64, f64)>> = vec![Vec::new(); rows];
    for t in triangles {
        let lo = t.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        let hi = t.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
        let first = (((lo - z_min) / dz) - 0.5).ceil().max(0.0) as usize;
        let last = ((((hi - z_min) / dz) - 0.5).floor() as isize).min(rows as isize - 1);
        for k in first as isize..=last {
            let z = z_min + (k as f64 + 0.5) * dz;
            let mut xs = [f64::NAN; 3];
            let mut n = 0;
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                if (a.y <= z && b.y > z) || (b.y <= z && a.y > z) {
                    xs[n] = a.x + (z - a.y) / (b.y - a.y) * (b.x - a.x);
                    n += 1;
                }
            }
            if n == 2 {
                per_row[k as usize].push((xs[0].min(xs[1]), xs[0].max(xs[1])));
            }
        }
    }
    for (k, mut intervals) in per_row.into_iter().enumerate() {
        if intervals.is_empty() {
            continue;
        }
        intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut merged: Vec<(f64, f64)> = Vec::with_capacity(intervals.len());
        for (a, b) in intervals {
            match merged.last_mut() {
                // Neighbouring triangles meet on a shared edge; rounding may leave a gap of a
                // few ulps there, which must not split the shadow.
                Some(last) if a <= last.1 + MERGE_TOLERANCE => last.1 = last.1.max(b),
                _ => merged.push((a, b)),
            }
        }
        f(z_min + (k as f64 + 0.5) * dz, &merged);
    }
}

/// Projects triangles of a mesh onto the horizontal (x, z) plane.
pub fn project(triangles: &[[u32; 3]], positions: &[DVec3]) -> Vec<[DVec2; 3]> {
    triangles
        .iter()
        .map(|t| t.map(|i| DVec2::new(positions[i as usize].x, positions[i as usize].z)))
        .collect()
}

/// Measures a draped cloth: `draped` and `flat` are its projected triangles now and before
/// draping, `centre` the disk centre (x, z) (m), `disk_radius` (m), `dz` the row spacing (m).
///
/// `resolution` (m) is the shortest outline feature the mesh can represent (twice the node
/// spacing): the outline is smoothed over that arc length, so ripples one or two nodes wide,
/// which a cm-spaced mesh makes when a stiff skirt buckles, are not counted as folds.
pub fn measure_drape(
    draped: &[[DVec2; 3]],
    flat: &[[DVec2; 3]],
    centre: DVec2,
    disk_radius: f64,
    dz: f64,
    resolution: f64,
) -> DrapeMeasurement {
    let disk_area = std::f64::consts::PI * disk_radius * disk_radius;
    let flat_area: f64 = flat
        .iter()
        .map(|t| 0.5 * (t[1] - t[0]).perp_dot(t[2] - t[0]).abs())
        .sum();
    let (shadow_area, raw) = outline_profile(draped, centre, dz, |d| d.length());
    let mean_radius = raw.iter().sum::<f64>() / raw.len() as f64;
    let half_width = smoothing_half_width(resolution, mean_radius);
    let profile = smooth(&raw, half_width);
    let (nodes_at, min_radius, max_radius) = peaks(&profile, NODE_PROMINENCE);
    DrapeMeasurement {
        shadow_area,
        drape_coefficient: (shadow_area - disk_area) / (flat_area - disk_area),
        nodes: nodes_at.len() as u32,
        node_angles: nodes_at.iter().map(|&b| bin_angle(b)).collect(),
        node_radii: nodes_at.iter().map(|&b| profile[b]).collect(),
        min_radius,
        max_radius,
        fold_amplitude: 0.5 * (max_radius - min_radius),
    }
}

/// Centre angle of an outline bin (rad).
fn bin_angle(bin: usize) -> f64 {
    (bin as f64 + 0.5) / BINS as f64 * std::f64::consts::TAU
}

/// Bins on each side of the smoothing window: half the arc `resolution` (m) at `radius` (m),
/// at least [`SMOOTH_HALF_WIDTH`].
fn smoothing_half_width(resolution: f64, radius: f64) -> usize {
    let bins = (0.5 * resolution / radius.max(1e-9)).to_degrees() * (BINS as f64 / 360.0);
    (bins.round() as usize).clamp(SMOOTH_HALF_WIDTH, 30)
}

/// The shadow's area (m²) and its outline profile (gaps filled, not smoothed): in each 1° bin around `centre`,
/// the largest `measure(point − centre)` over the shadow's boundary points.
fn outline_profile(
    draped: &[[DVec2; 3]],
    centre: DVec2,
    dz: f64,
    measure: impl Fn(DVec2) -> f64,
) -> (f64, Vec<f64>) {
    let mut shadow_area = 0.0;
    let mut profile = vec![f64::NAN; BINS];
    for_each_row(draped, dz, |z, intervals| {
        shadow_area += intervals.iter().map(|(a, b)| b - a).sum::<f64>() * dz;
        for &(a, b) in intervals {
            for x in [a, b] {
                let d = DVec2::new(x, z) - centre;
                let bin = ((d.y.atan2(d.x).rem_euclid(std::f64::consts::TAU)) / std::f64::consts::TAU
                    * BINS as f64) as usize
                    % BINS;
                let r = measure(d);
                if profile[bin].is_nan() || r > profile[bin] {
                    profile[bin] = r;
                }
            }
        }
    });
    (shadow_area, fill_gaps(&profile))
}

/// The tablecloth's skirt seen from above.
#[derive(Clone, Debug, PartialEq)]
pub struct SkirtMeasurement {
    /// Folds of the skirt: peaks (prominence ≥ [`NODE_PROMINENCE`]) of how far the shadow
    /// reaches beyond the table's edge, going round the table.
    pub folds: u32,
    /// Angles of the folds around the table centre (rad).
    pub fold_angles: Vec<f64>,
    /// Largest reach of the shadow beyond the table edge (m).
    pub max_reach: f64,
}

/// Measures the skirt of a cloth on a rectangular table of half extents (x, z) (m).
/// `resolution` (m) as for [`measure_drape`].
pub fn measure_skirt(
    draped: &[[DVec2; 3]],
    centre: DVec2,
    half: DVec2,
    dz: f64,
    resolution: f64,
) -> SkirtMeasurement {
    // Distance outside the rectangle (0 on or inside it).
    let beyond = |d: DVec2| (d.abs() - half).max(DVec2::ZERO).length();
    let (_, raw) = outline_profile(draped, centre, dz, beyond);
    let profile = smooth(&raw, smoothing_half_width(resolution, half.length()));
    let (at, _, max) = peaks(&profile, NODE_PROMINENCE);
    SkirtMeasurement {
        folds: at.len() as u32,
        fold_angles: at.iter().map(|&b| bin_angle(b)).collect(),
        max_reach: max,
    }
}

/// Fills empty (NaN) bins by linear interpolation around the circle.
fn fill_gaps(r: &[f64]) -> Vec<f64> {
    let n = r.len();
    let known: Vec<usize> = (0..n).filter(|&i| !r[i].is_nan()).collect();
    if known.is_empty() {
        return vec![0.0; n];
    }
    let mut out = r.to_vec();
    for (k, &i) in known.iter().enumerate() {
        let j = known[(k + 1) % known.len()];
        let gap = (j + n - i) % n;
        let gap = if gap == 0 { n } else { gap };
        for s in 1..gap {
            out[(i + s) % n] = r[i] + (r[j] - r[i]) * s as f64 / gap as f64;
        }
    }
    out
}

/// Circular moving average over 2·half_width + 1 bins.
fn smooth(r: &[f64], half_width: usize) -> Vec<f64> {
    let n = r.len() as isize;
    let w = half_width as isize;
    (0..n)
        .map(|i| (-w..=w).map(|d| r[((i + d).rem_euclid(n)) as usize]).sum::<f64>() / (2 * w + 1) as f64)
        .collect()
}

/// Bins of the peaks of a circular profile with prominence ≥ `min_prominence`, and the
/// profile's minimum and maximum.
pub fn peaks(profile: &[f64], min_prominence: f64) -> (Vec<usize>, f64, f64) {
    let n = profile.len();
    let max = profile.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = profile.iter().copied().fold(f64::INFINITY, f64::min);
    let at = |i: isize| profile[i.rem_euclid(n as isize) as usize];
    let mut found = Vec::new();
    for i in 0..n as isize {
        // A plateau counts once, at its first bin.
        let v = at(i);
        if v <= at(i - 1) {
            continue;
        }
        let mut j = i + 1;
        while j < i + n as isize && at(j) == v {
            j += 1;
        }
        if at(j) > v {
            continue;
        }
        // Walk each way until a higher point (or all the way round); the prominence is the
        // height above the higher of the two lowest points passed.
        let mut left_min = v;
        let mut k = i - 1;
        while k > i - n as isize && at(k) <= v {
            left_min = left_min.min(at(k));
            k -= 1;
        }
        let mut right_min = v;
        let mut k = j;
        while k < i + n as isize && at(k) <= v {
            right_min = right_min.min(at(k));
            k += 1;
        }
        let prominence = if v >= max {
            v - min
        } else {
            v - left_min.max(right_min)
        };
        if prominence >= min_prominence {
            found.push(i as usize);
        }
    }
    (found, min, max)
}
