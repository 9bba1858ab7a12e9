//! Which particles a woven grid connects: thread links, bending springs and trellis corners.
//!
//! Particles sit at the warp/weft crossings of a square grid of spacing σ. Grid index `i` runs
//! along the warp, `j` along the weft. A grid may leave crossings out (a circular sample cut
//! from a square); every spring whose particles all exist is kept. Topology is built once; the
//! per-step force loops only read these flat index arrays.

use crate::material::Thread;

/// How the cloth's mass is shared among its nodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum NodeMass {
    /// Every node carries ρ_A·σ², a whole cell, outline nodes included (the seed's lumping;
    /// default): a free edge is heavier than the cloth by half a row of cells.
    #[default]
    Uniform,
    /// Each node carries the cell area it stands for ([`ClothTopology::cell_areas`]): ½σ² on an
    /// edge, ¼σ² at a corner, so the cloth weighs what its outline holds; each bending spring
    /// likewise the width it stands for ([`ClothTopology::share_outline_widths`]).
    CellArea,
    /// As `CellArea`, with each node of a circle carrying the part of the specimen it stands
    /// for: its cell clipped to the circle, plus a share of the clipped cells of the crossings
    /// just outside it, so the nodes weigh what the cut circle weighs (`embed/outline_areas.rs`;
    /// on a rectangle the same as `CellArea`).
    TrueArea,
}

impl NodeMass {
    /// Whether outline nodes carry less than a whole cell, and bending springs on the outline
    /// the width they stand for.
    pub fn shares_outline(self) -> bool {
        self != NodeMass::Uniform
    }
}

/// The springs of a woven particle grid, as flat index arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct ClothTopology {
    /// σ, rest spacing between neighbouring crossings (m).
    pub spacing: f64,
    /// Number of particles.
    pub particle_count: usize,
    /// Grid coordinates `(i, j)` of each particle.
    pub grid_coords: Vec<(u32, u32)>,
    /// Thread links `[p, q]` between neighbours, oriented along increasing grid index; warp
    /// links first (`..warp_link_count`), then weft links.
    pub links: Vec<[u32; 2]>,
    /// How many of `links` are warp links.
    pub warp_link_count: usize,
    /// Bending springs `[a, b, c]` with `b` in the middle, along one thread; warp first.
    pub bend_particles: Vec<[u32; 3]>,
    /// For each bending spring, the links `[a→b, b→c]` (both oriented along the grid).
    pub bend_links: Vec<[u32; 2]>,
    /// How many bending springs lie along the warp.
    pub warp_bend_count: usize,
    /// For each bending spring, the patch of cloth it stands for as fractions of σ,
    /// `[across, along]` its thread: `[1, 1]` inside the cloth (a σ × σ patch). Across is ½ on an
    /// outline the thread runs along ([`Self::share_outline_widths`]); along is ½ where the thread
    /// leaves a held segment at the spring's middle node ([`Self::hold_rigidly`]).
    pub bend_patch: Vec<[f64; 2]>,
    /// Crossings with all four neighbours, as their links `[+warp, +weft, −warp, −weft]`: the
    /// first two leave the crossing, the last two arrive at it. Each holds four trellis corners,
    /// which the trellis loop evaluates together so that each link is read and written once.
    pub full_crossings: Vec<[u32; 4]>,
    /// The trellis corners of all other crossings (at the cloth's edge), as `[a, b, c]`: `b`
    /// the crossing, `a` its warp neighbour, `c` its weft neighbour.
    pub corner_particles: Vec<[u32; 3]>,
    /// Surface triangles (two per complete grid cell, one where a cell lacks a corner),
    /// counter-clockwise seen from +weft × +warp; for meshes, pictures and projected areas.
    pub triangles: Vec<[u32; 3]>,
    /// For each corner, the warp link b–a and the weft link b–c, each as a [`SignedLink`]:
    /// the link index, with [`SignedLink::REVERSED`] set when the neighbour is the link's
    /// first particle (so `sign · unit[link]` points from `b` to the neighbour). Packing the
    /// sign into the index keeps the hot loop's memory traffic at 8 bytes per corner.
    pub corner_links: Vec<[SignedLink; 2]>,
}

/// A link index with a direction bit (see [`ClothTopology::corner_links`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SignedLink(pub u32);

impl SignedLink {
    /// The bit marking a link traversed from its second particle to its first.
    pub const REVERSED: u32 = 1 << 31;

    fn new(link: u32, reversed: bool) -> Self {
        Self(link | if reversed { Self::REVERSED } else { 0 })
    }

    /// The link's index into `links`.
    #[inline(always)]
    pub fn index(self) -> usize {
        (self.0 & !Self::REVERSED) as usize
    }

    /// +1 along the link's orientation, −1 against it.
    #[inline(always)]
    pub fn sign(self) -> f64 {
        if self.0 & Self::REVERSED == 0 { 1.0 } else { -1.0 }
    }
}

impl ClothTopology {
    /// A full `nu × nv` grid (nu crossings along the warp, nv along the weft).
    pub fn rectangle(nu: usize, nv: usize, spacing: f64) -> Self {
        Self::from_mask(nu, nv, spacing, |_, _| true)
    }

    /// The crossings `(i, j)` of an `nu × nv` grid for which `keep(i, j)` holds, numbered in
    /// row-major order (i slowest).
    pub fn from_mask(nu: usize, nv: usize, spacing: f64, keep: impl Fn(usize, usize) -> bool) -> Self {
        const NONE: u32 = u32::MAX;
        let mut index = vec![NONE; nu * nv];
        let mut grid_coords = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                if keep(i, j) {
                    index[i * nv + j] = grid_coords.len() as u32;
                    grid_coords.push((i as u32, j as u32));
                }
            }
        }
        let at = |i: isize, j: isize| -> Option<u32> {
            if i < 0 || j < 0 || i >= nu as isize || j >= nv as isize {
                return None;
            }
            let p = index[i as usize * nv + j as usize];
            (p != NONE).then_some(p)
        };

        // Links, oriented from (i, j) to (i+1, j) [warp] or (i, j+1) [weft].
        let mut links = Vec::new();
        let mut link_index = std::collections::HashMap::new();
        for (thread, (di, dj)) in [(Thread::Warp, (1, 0)), (Thread::Weft, (0, 1))] {
            for &(i, j) in &grid_coords {
                let (i, j) = (i as isize, j as isize);
                if let (Some(p), Some(q)) = (at(i, j), at(i + di, j + dj)) {
                    link_index.insert((thread, p), links.len() as u32);
                    links.push([p, q]);
                }
            }
        }
        let warp_link_count = link_index.keys().filter(|(t, _)| *t == Thread::Warp).count();
        // The link leaving particle p in the + direction of `thread`.
        let link_from = |thread: Thread, p: u32| link_index.get(&(thread, p)).copied();

        let mut bend_particles = Vec::new();
        let mut bend_links = Vec::new();
        let mut warp_bend_count = 0;
        for (thread, (di, dj)) in [(Thread::Warp, (1, 0)), (Thread::Weft, (0, 1))] {
            for &(i, j) in &grid_coords {
                let (i, j) = (i as isize, j as isize);
                if let (Some(a), Some(b), Some(c)) = (at(i - di, j - dj), at(i, j), at(i + di, j + dj)) {
                    if let (Some(l1), Some(l2)) = (link_from(thread, a), link_from(thread, b)) {
                        bend_particles.push([a, b, c]);
                        bend_links.push([l1, l2]);
                        if thread == Thread::Warp {
                            warp_bend_count += 1;
                        }
                    }
                }
            }
        }

        let mut full_crossings = Vec::new();
        let mut corner_particles = Vec::new();
        let mut corner_links = Vec::new();
        for &(i, j) in &grid_coords {
            let (i, j) = (i as isize, j as isize);
            let Some(b) = at(i, j) else { continue };
            let around = (at(i - 1, j), at(i, j - 1));
            let full = [
                link_from(Thread::Warp, b),
                link_from(Thread::Weft, b),
                around.0.and_then(|a| link_from(Thread::Warp, a)),
                around.1.and_then(|c| link_from(Thread::Weft, c)),
            ];
            if let [Some(up), Some(wp), Some(um), Some(wm)] = full {
                full_crossings.push([up, wp, um, wm]);
                continue;
            }
            for (si, sj) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
                let (Some(a), Some(c)) = (at(i + si, j), at(i, j + sj)) else {
                    continue;
                };
                // The warp link between b and a starts at whichever has the lower i.
                let lu = link_from(Thread::Warp, if si > 0 { b } else { a });
                let lw = link_from(Thread::Weft, if sj > 0 { b } else { c });
                if let (Some(lu), Some(lw)) = (lu, lw) {
                    corner_particles.push([a, b, c]);
                    corner_links.push([SignedLink::new(lu, si < 0), SignedLink::new(lw, sj < 0)]);
                }
            }
        }

        let mut triangles = Vec::new();
        for i in 0..nu as isize - 1 {
            for j in 0..nv as isize - 1 {
                let quad = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                match quad {
                    // Alternate the diagonal so the mesh has no preferred direction.
                    [Some(a), Some(b), Some(c), Some(d)] if (i + j) % 2 == 0 => {
                        triangles.extend([[a, b, c], [a, c, d]]);
                    }
                    [Some(a), Some(b), Some(c), Some(d)] => triangles.extend([[a, b, d], [b, c, d]]),
                    [None, Some(b), Some(c), Some(d)] => triangles.push([b, c, d]),
                    [Some(a), None, Some(c), Some(d)] => triangles.push([a, c, d]),
                    [Some(a), Some(b), None, Some(d)] => triangles.push([a, b, d]),
                    [Some(a), Some(b), Some(c), None] => triangles.push([a, b, c]),
                    _ => {}
                }
            }
        }

        Self {
            spacing,
            particle_count: grid_coords.len(),
            bend_patch: vec![[1.0, 1.0]; bend_particles.len()],
            triangles,
            grid_coords,
            links,
            warp_link_count,
            bend_particles,
            bend_links,
            warp_bend_count,
            full_crossings,
            corner_particles,
            corner_links,
        }
    }

    /// Number of trellis corners: four per full crossing plus the edge corners.
    pub fn corner_count(&self) -> usize {
        4 * self.full_crossings.len() + self.corner_links.len()
    }

    /// The thread a link runs along.
    pub fn link_thread(&self, link: usize) -> Thread {
        if link < self.warp_link_count {
            Thread::Warp
        } else {
            Thread::Weft
        }
    }

    /// The thread a bending spring runs along.
    pub fn bend_thread(&self, bend: usize) -> Thread {
        if bend < self.warp_bend_count {
            Thread::Warp
        } else {
            Thread::Weft
        }
    }

    /// Per node, how many links it has along the warp and along the weft (0, 1 or 2 each).
    fn thread_link_counts(&self) -> (Vec<u8>, Vec<u8>) {
        let mut warp = vec![0u8; self.particle_count];
        let mut weft = vec![0u8; self.particle_count];
        for (k, &[p, q]) in self.links.iter().enumerate() {
            let count = if k < self.warp_link_count {
                &mut warp
            } else {
                &mut weft
            };
            count[p as usize] += 1;
            count[q as usize] += 1;
        }
        (warp, weft)
    }

    /// The share of a cell's side a node stands for along a thread on which it has `links`
    /// links: ½ at the end of the thread, 1 inside (a lone node keeps ½).
    fn side_share(links: u8) -> f64 {
        f64::from(links.clamp(1, 2)) / 2.0
    }

    /// The area (m²) each node stands for: its cell of σ × σ around it, halved along a thread
    /// for each side on which it has no neighbour along that thread (an edge node ½σ², a
    /// corner ¼σ²). They sum to the area the lattice's links enclose (for a rectangle, the
    /// specimen's own area), so mass ρ_A·area puts on a free edge the half cell it carries.
    pub fn cell_areas(&self) -> Vec<f64> {
        let (warp, weft) = self.thread_link_counts();
        warp.iter()
            .zip(&weft)
            .map(|(&u, &v)| self.spacing * self.spacing * Self::side_share(u) * Self::side_share(v))
            .collect()
    }

    /// Gives each bending spring the width of cloth its middle node stands for across its
    /// thread, as [`Self::cell_areas`] does for mass: half a spacing for a thread running along
    /// the outline, so that a strip of n threads bends with the rigidity of its true width
    /// (n − 1)·σ, not n·σ.
    pub fn share_outline_widths(&mut self) {
        let (warp, weft) = self.thread_link_counts();
        for (s, &[_, b, _]) in self.bend_particles.iter().enumerate() {
            let across = if s < self.warp_bend_count { &weft } else { &warp };
            self.bend_patch[s][0] = Self::side_share(across[b as usize]);
        }
    }

    /// Declares the nodes `held` (indices) held in place, as a clamp holds them. A bending
    /// spring whose middle node and one end are held is where the thread leaves the clamp: the
    /// held link is straight, so the spring's curvature lies on the half spacing beyond the
    /// middle node, and the spring stands for that half (`along` = ½, twice the stiffness of a
    /// whole spacing for a linear M(K)). This is the clamped end θ = 0 of the continuum
    /// discretised consistently; with a whole spacing the first free link turns by twice the
    /// angle the continuum gives it, an error of first order in σ.
    pub fn hold_rigidly(&mut self, held: &[usize]) {
        let mut is_held = vec![false; self.particle_count];
        for &k in held {
            if let Some(h) = is_held.get_mut(k) {
                *h = true;
            }
        }
        for (s, &[a, b, c]) in self.bend_particles.iter().enumerate() {
            let [a, b, c] = [a, b, c].map(|p| is_held[p as usize]);
            if b && (a != c) {
                self.bend_patch[s][1] = 0.5;
            }
        }
    }

    /// Each node's mass (kg) for a fabric of `areal_density` (kg/m²) under `rule` (a circle's
    /// `TrueArea` needs its outline: `ClothBuilder` computes it).
    pub fn node_masses(&self, areal_density: f64, rule: NodeMass) -> Vec<f64> {
        match rule {
            NodeMass::Uniform => vec![areal_density * self.spacing * self.spacing; self.particle_count],
            NodeMass::CellArea | NodeMass::TrueArea => {
                self.cell_areas().iter().map(|a| areal_density * a).collect()
            }
        }
    }

    /// Rest positions (m): particle (i, j) at `origin + i·σ·warp + j·σ·weft`.
    /// `warp` and `weft` are unit vectors (orthogonal for an unsheared cloth).
    pub fn rest_positions(
        &self,
        origin: glam::DVec3,
        warp: glam::DVec3,
        weft: glam::DVec3,
    ) -> Vec<glam::DVec3> {
        self.grid_coords
            .iter()
            .map(|&(i, j)| origin + (i as f64 * self.spacing) * warp + (j as f64 * self.spacing) * weft)
            .collect()
    }
}
