//! Where a [`ClothBuilder`]'s nodes lie: the woven lattice inside the outline, each node's flat
//! position, shift against the outline and mass.

use glam::DVec3;

use super::{ClothBuilder, ClothOutline};
use crate::forces::{ClothTopology, NodeMass};

impl ClothBuilder {
    /// Nodes per side of the bounding grid.
    pub(super) fn grid_size(&self) -> (usize, usize) {
        match self.outline {
            ClothOutline::Circle(d) => {
                // A shifted lattice can reach one node further on one side.
                let extra = usize::from(self.lattice_offset != [0.0; 2]);
                let n = 2 * ((d / 2.0 / self.spacing + 1e-9).floor() as usize + extra) + 1;
                (n, n)
            }
            ClothOutline::Rectangle { warp, weft } => (
                (warp / self.spacing).round() as usize + 1,
                (weft / self.spacing).round() as usize + 1,
            ),
        }
    }

    /// The woven grid and its flat node positions (m), before any perturbation.
    pub fn grid(&self) -> (ClothTopology, Vec<DVec3>) {
        let sigma = self.spacing;
        let (nu, nv) = self.grid_size();
        let (hu, hv) = ((nu - 1) as f64 / 2.0, (nv - 1) as f64 / 2.0);
        let [ou, ov] = self.outline_offset();
        let radius = match self.outline {
            ClothOutline::Circle(d) => Some(d / 2.0),
            ClothOutline::Rectangle { .. } => None,
        };
        let topology = ClothTopology::from_mask(nu, nv, sigma, |i, j| {
            let [x, z] = self.flat_position(i, j);
            radius.is_none_or(|r| x * x + z * z <= r * r * (1.0 + 1e-9))
        });
        let angle = self.warp_angle_deg.to_radians();
        let warp = DVec3::new(angle.cos(), 0.0, -angle.sin());
        let weft = DVec3::new(angle.sin(), 0.0, angle.cos());
        let shear = self.initial_shear_deg.to_radians();
        let weft = shear.cos() * weft + shear.sin() * warp;
        let origin = self.centre + (ou - hu * sigma) * warp + (ov - hv * sigma) * weft;
        let mut positions = topology.rest_positions(origin, warp, weft);
        if let Some(gap) = self.fold_gap {
            // Crossings beyond the middle of the warp go onto their mirror images, `gap` above.
            let fold = (nu - 1) / 2;
            let up = weft.cross(warp).normalize();
            for (p, &(i, _)) in positions.iter_mut().zip(&topology.grid_coords) {
                let i = i as usize;
                if i > fold {
                    let back = 2.0 * (i - fold) as f64 * sigma;
                    *p += gap * up - back * warp;
                }
            }
        }
        (topology, positions)
    }

    /// Each node's flat position in the cloth's own frame (m: along the warp and the weft, from
    /// the outline's centre), whatever the lattice's offset against the outline.
    pub(super) fn flat_coordinates(&self, topology: &ClothTopology) -> Vec<[f64; 2]> {
        topology
            .grid_coords
            .iter()
            .map(|&(i, j)| self.flat_position(i as usize, j as usize))
            .collect()
    }

    /// The flat position of grid crossing (`i`, `j`) in the cloth's own frame (m: along the warp
    /// and the weft, from the outline's centre).
    fn flat_position(&self, i: usize, j: usize) -> [f64; 2] {
        self.crossing_position(i as i64, j as i64)
    }

    /// The flat position (m, as [`Self::flat_position`]) of lattice crossing (`i`, `j`), inside
    /// the bounding grid or beyond it.
    fn crossing_position(&self, i: i64, j: i64) -> [f64; 2] {
        let sigma = self.spacing;
        let (nu, nv) = self.grid_size();
        let [ou, ov] = self.outline_offset();
        [
            (i as f64 - (nu - 1) as f64 / 2.0) * sigma + ou,
            (j as f64 - (nv - 1) as f64 / 2.0) * sigma + ov,
        ]
    }

    /// Each node's mass (kg) under the builder's [`NodeMass`] rule, in the order of
    /// [`Self::grid`]'s nodes.
    pub fn node_masses(&self) -> Vec<f64> {
        self.masses_of(&self.grid().0)
    }

    /// Each node's mass (kg) of `topology` (the builder's grid) under the builder's rule.
    pub(super) fn masses_of(&self, topology: &ClothTopology) -> Vec<f64> {
        let density = self.fabric.areal_density;
        match (self.node_mass, self.outline) {
            (NodeMass::TrueArea, ClothOutline::Circle(d)) => crate::embed::outline_areas::circle_node_areas(
                &topology.grid_coords,
                |i, j| self.crossing_position(i, j),
                self.spacing,
                d / 2.0,
            )
            .into_iter()
            .map(|a| density * a)
            .collect(),
            (rule, _) => topology.node_masses(density, rule),
        }
    }

    /// The lattice's shift against the outline (m, along warp and weft): a circle's
    /// [`Self::lattice_offset`], none on a rectangle.
    fn outline_offset(&self) -> [f64; 2] {
        match self.outline {
            ClothOutline::Circle(_) => self.lattice_offset,
            ClothOutline::Rectangle { .. } => [0.0; 2],
        }
    }
}
