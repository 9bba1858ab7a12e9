//! The measurements a scene declares (`measure:`), taken on its settled cloth.

use glam::{DVec2, DVec3};

use crate::forces::ClothTopology;
use crate::measure::{DrapeMeasurement, measure_drape, measure_skirt, project};
use crate::scene::{ColliderShape, MeasureSpec, Scene};

/// A rectangular cloth's hang on its table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableHang {
    /// Mean hang of the four corners below the table top (m).
    pub corners: f64,
    /// Mean hang of the four mid-sides below the table top (m).
    pub mid_sides: f64,
    /// Folds of the skirt around the table.
    pub folds: u32,
}

/// A cantilever strip's bend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CantileverBend {
    /// The chord from the clamp's edge to the free end, from the clamp's direction (rad).
    pub chord: f64,
    /// The heavy elastica's exact chord for the same fabric, weight and overhang (rad).
    pub exact: f64,
}

/// What a settled run measured, as its scene declared.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Measured {
    /// The drape test, for `measure: Drape(..)`.
    pub drape: Option<DrapeMeasurement>,
    /// The tablecloth's hang, for `measure: Tablecloth(..)`.
    pub table: Option<TableHang>,
    /// The cantilever test, for `measure: Cantilever`.
    pub cantilever: Option<CantileverBend>,
}

/// Centre (x, z) (m) and radius (m) of the drapemeter disk `measure: Drape(disk: ..)` names.
pub fn declared_disk(scene: &Scene) -> Option<(DVec2, f64)> {
    let MeasureSpec::Drape { disk } = &scene.spec.measure else {
        return None;
    };
    scene.spec.world.colliders.iter().find_map(|c| match c.shape {
        ColliderShape::Cylinder { radius_m, .. } if &c.name == disk => {
            Some((DVec2::new(c.centre_m[0], c.centre_m[2]), radius_m))
        }
        _ => None,
    })
}

/// Centre (m) and half extents (m) of the table `measure: Tablecloth(table: ..)` names.
fn declared_table(scene: &Scene) -> Option<([f64; 3], [f64; 3])> {
    let MeasureSpec::Tablecloth { table } = &scene.spec.measure else {
        return None;
    };
    scene.spec.world.colliders.iter().find_map(|c| match c.shape {
        ColliderShape::Cuboid { half_extents_m } if &c.name == table => Some((c.centre_m, half_extents_m)),
        _ => None,
    })
}

/// Takes the scene's declared measurement of the cloth `topology` at `positions` (m).
pub fn measure_declared(scene: &Scene, topology: &ClothTopology, positions: &[DVec3]) -> Measured {
    Measured {
        drape: measure_scene_drape(scene, topology, positions),
        table: measure_scene_table(scene, topology, positions),
        cantilever: measure_cantilever(scene, positions),
    }
}

/// The chord angle of a strip held by `cloth.clamp_m`, from the clamp's edge (the flat layout's
/// −warp end plus the clamp length, at the held nodes' height) to the mean of the free end's
/// nodes (those farthest along the warp in the flat layout), and the heavy elastica's.
fn measure_cantilever(scene: &Scene, positions: &[DVec3]) -> Option<CantileverBend> {
    if scene.spec.measure != MeasureSpec::Cantilever {
        return None;
    }
    let (_, flat) = crate::scene::spawn::cloth_grid(scene);
    let warp = scene.warp_direction();
    let along: Vec<f64> = flat.iter().map(|p| p.dot(warp)).collect();
    let start = along.iter().copied().fold(f64::INFINITY, f64::min);
    let end = along.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let tolerance = 1e-6 * scene.spec.cloth.spacing_m;
    let tip: Vec<usize> = (0..flat.len()).filter(|&k| along[k] >= end - tolerance).collect();
    let held = scene.clamped_nodes();
    let mean =
        |nodes: &[usize], of: &[DVec3]| nodes.iter().map(|&k| of[k]).sum::<DVec3>() / nodes.len() as f64;
    let (root, free) = (mean(&held, positions), mean(&tip, positions));
    let edge = start + scene.spec.cloth.clamp_m;
    let reach = free.dot(warp) - edge;
    let overhang = end - edge;
    // The clamp's angle above the horizontal, from gravity's direction in the strip's plane
    // (warp and +y): 0 for gravity along −y, 90° for gravity back along the strip (an upright
    // column). Gravity across the strip (along the weft) has no planar elastica.
    let g = DVec3::from_array(scene.spec.world.gravity_m_per_s2);
    let gravity = g.length();
    let weft = DVec3::Y.cross(warp);
    if gravity == 0.0 || g.dot(weft).abs() > 1e-9 * gravity {
        return None;
    }
    let clamp_angle = (-g.dot(warp)).atan2(-g.y);
    let drop = root.y - free.y;
    // Upright, the column bends to either side alike.
    let drop = if g.y == 0.0 { drop.abs() } else { drop };
    let chord = drop.atan2(reach);
    let rigidity = scene.fabric.bending(crate::material::Thread::Warp).rigidity;
    let c = (rigidity / (scene.fabric.areal_density * gravity)).cbrt();
    let exact = crate::study::heavy_elastica::heavy_elastica(overhang / c, clamp_angle)?.chord_angle();
    Some(CantileverBend { chord, exact })
}

/// The drape around the declared disk.
fn measure_scene_drape(
    scene: &Scene,
    topology: &ClothTopology,
    positions: &[DVec3],
) -> Option<DrapeMeasurement> {
    let (centre, radius) = declared_disk(scene)?;
    let (_, flat) = crate::scene::spawn::cloth_grid(scene);
    // Rows σ/50 apart: the row rule's error is then far below the mesh's (docs/validation.md).
    let dz = topology.spacing / 50.0;
    Some(measure_drape(
        &project(&topology.triangles, positions),
        &project(&topology.triangles, &flat),
        centre,
        radius,
        dz,
        2.0 * topology.spacing,
    ))
}

/// The hang of the corners and mid-sides below the declared table's top, and the skirt's folds.
fn measure_scene_table(scene: &Scene, topology: &ClothTopology, positions: &[DVec3]) -> Option<TableHang> {
    let (centre, half) = declared_table(scene)?;
    let top = centre[1] + half[1];
    let nu = topology.grid_coords.iter().map(|&(i, _)| i).max()?;
    let nv = topology.grid_coords.iter().map(|&(_, j)| j).max()?;
    let (mu, mv) = (nu / 2, nv / 2);
    let at = |i: u32, j: u32| {
        topology
            .grid_coords
            .iter()
            .position(|&c| c == (i, j))
            .map(|p| top - positions[p].y)
    };
    let mean = |pts: [(u32, u32); 4]| -> Option<f64> {
        let hangs: Option<Vec<f64>> = pts.iter().map(|&(i, j)| at(i, j)).collect();
        hangs.map(|h| h.iter().sum::<f64>() / 4.0)
    };
    let corners = mean([(0, 0), (nu, 0), (0, nv), (nu, nv)])?;
    let mid_sides = mean([(mu, 0), (0, mv), (nu, mv), (mu, nv)])?;
    let skirt = measure_skirt(
        &project(&topology.triangles, positions),
        DVec2::new(centre[0], centre[2]),
        DVec2::new(half[0], half[2]),
        topology.spacing / 50.0,
        2.0 * topology.spacing,
    );
    Some(TableHang {
        corners,
        mid_sides,
        folds: skirt.folds,
    })
}
