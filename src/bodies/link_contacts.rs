//! Reading, from Rapier's world, the links a fixed surface's edge presses between their nodes.

use glam::DVec3;
use rapier3d::prelude::*;

use super::ClothBodies;
use super::cloth_bodies::{body_pairs, collider_body};
use crate::implicit::{LinkSupport, Supports};

/// A link pressed less deeply than this (m) beyond its ends gets no support: below the
/// contact queries' rounding on a link lying flat on a face.
const LEAST_DEPTH: f32 = 1e-7;

/// Supports nearer a node than this share of the link (by position along it) are the node's
/// own contact's, not the link's.
const END_SHARE: f32 = 1e-3;

impl ClothBodies {
    /// With [`super::NodeOptions::link_support_hz`], fills `supports.links` with every link
    /// (`links`, node pairs in topology order, at `positions`, m) whose centre line a fixed or
    /// kinematic collider presses closer than the nodes' contact clearance somewhere between its
    /// nodes, deeper than the straight line between its ends' own penetrations (a link lying on
    /// a face, as its nodes do, is not pressed; one crossing an edge's corner is). Candidates
    /// are the links with a node in contact with such a collider in Rapier's last step (within
    /// its prediction distance) whose ends do not rest on one face alike. Call it after
    /// [`Self::read_supports`], which clears the list.
    pub fn read_link_supports(
        &self,
        world: &PhysicsWorld,
        links: &[[u32; 2]],
        positions: &[DVec3],
        supports: &mut Supports,
    ) {
        supports.links.clear();
        let Some(hz) = self.link_support_hz else {
            return;
        };
        let clearance = (self.radius - self.surface_depth).max(0.0) as f32;
        let omega = std::f64::consts::TAU * hz;
        let mut near: Vec<(usize, ColliderHandle)> = Vec::new();
        for (node, h) in self.handles.iter().enumerate() {
            let Some(body) = world.bodies.get(*h) else {
                continue;
            };
            for (pair, other, _) in body_pairs(world, body) {
                let fixed = collider_body(world, other).is_none_or(|b| !b.is_dynamic());
                if fixed && pair.manifolds().iter().any(|m| !m.points.is_empty()) {
                    near.push((node, other));
                }
            }
        }
        near.sort_unstable_by_key(|(node, c)| (*node, c.into_raw_parts()));
        let colliders_of = |node: usize| {
            let start = near.partition_point(|(n, _)| *n < node);
            near[start..]
                .iter()
                .take_while(move |(n, _)| *n == node)
                .map(|(_, c)| *c)
        };
        let alike = |p: usize, q: usize| {
            let (np, nq) = (supports.pushed[p], supports.pushed[q]);
            let (tp, tq) = (supports.touching[p], supports.touching[q]);
            let on = |a: DVec3, b: DVec3| a != DVec3::ZERO && a.dot(b) > 0.999;
            on(np, nq) || on(tp, tq)
        };
        let previous = std::mem::take(&mut supports.anchors);
        let mut found = Vec::new();
        let mut anchors = crate::implicit::LinkAnchors::new();
        for (l, &[p, q]) in links.iter().enumerate() {
            let (p, q) = (p as usize, q as usize);
            if alike(p, q) {
                continue;
            }
            let (a, b) = (positions[p].as_vec3(), positions[q].as_vec3());
            let mut colliders: Vec<ColliderHandle> = colliders_of(p).chain(colliders_of(q)).collect();
            colliders.sort_unstable_by_key(|c| c.into_raw_parts());
            colliders.dedup();
            for handle in colliders {
                let Some(collider) = world.colliders.get(handle) else {
                    continue;
                };
                let Some(press) = link_press(collider, [a, b], clearance) else {
                    continue;
                };
                let (at, normal, depth) = (press.at as f64, press.normal.as_dvec3(), press.depth as f64);
                let point = |t: f64| (1.0 - t) * positions[p] + t * positions[q];
                // Static friction: the material point held since the contact began (or last
                // slipped) stays at its anchor while the friction spring pulls it back with at
                // most μ times the normal force; beyond, it slips, and the point pressed now is
                // held, that limit from its anchor.
                let (held_at, anchor) = previous.get(&l).copied().unwrap_or((at, point(at)));
                let across = |v: DVec3| v - v.dot(normal) * normal;
                let limit = collider.friction() as f64 * depth;
                let stretched = across(point(held_at) - anchor);
                let (held_at, anchor) = if stretched.length() <= limit {
                    (held_at, anchor)
                } else {
                    (at, point(at) - stretched.normalize_or_zero() * limit)
                };
                let shift = across(point(held_at) - anchor);
                anchors.insert(l, (held_at, anchor));
                let mass = 0.5 * (self.masses[p] + self.masses[q]);
                found.push(LinkSupport {
                    link: l,
                    nodes: [p, q],
                    at,
                    normal,
                    depth,
                    stiffness: mass * omega * omega,
                    held_at,
                    shift,
                });
                break;
            }
        }
        supports.anchors = anchors;
        supports.links = found;
    }
}

/// Where a collider presses a link's centre line `[a, b]` (m) closer than `clearance` beyond
/// its ends' own penetrations.
struct Press {
    at: f32,
    normal: Vec3,
    depth: f32,
}

/// Golden-section steps of [`link_press`]: they narrow the point pressed to 0.618^40 ≈ 4e-9 of
/// the link.
const SEARCH_STEPS: usize = 40;

/// The signed distance (m, negative inside) from `x` to `collider`, and the unit normal out of
/// it towards `x` (`None` on its surface).
fn signed_distance(collider: &Collider, x: Vec3) -> (f32, Option<Vec3>) {
    let projection = collider.shape().project_point(collider.position(), x, false);
    let out = x - projection.point;
    let distance = out.length();
    let sign = if projection.is_inside { -1.0 } else { 1.0 };
    (sign * distance, (distance > 0.0).then(|| sign * out / distance))
}

/// The deepest press of `collider` on the link `[a, b]`: the point where its penetration into
/// the nodes' `clearance` most exceeds the straight line between its ends' penetrations.
/// Along a line, the distance to a convex shape is convex, so that excess is concave and a
/// golden-section search finds its one maximum (for a composite shape, one local maximum).
fn link_press(collider: &Collider, [a, b]: [Vec3; 2], clearance: f32) -> Option<Press> {
    let penetration = |t: f32| clearance - signed_distance(collider, a + t * (b - a)).0;
    let (end_a, end_b) = (penetration(0.0).max(0.0), penetration(1.0).max(0.0));
    let excess = |t: f32| penetration(t) - ((1.0 - t) * end_a + t * end_b);
    let ratio = 0.5 * (5f32.sqrt() - 1.0);
    let (mut low, mut high) = (0.0f32, 1.0f32);
    let (mut x1, mut x2) = (high - ratio * (high - low), low + ratio * (high - low));
    let (mut f1, mut f2) = (excess(x1), excess(x2));
    for _ in 0..SEARCH_STEPS {
        if f1 < f2 {
            low = x1;
            (x1, f1) = (x2, f2);
            x2 = low + ratio * (high - low);
            f2 = excess(x2);
        } else {
            high = x2;
            (x2, f2) = (x1, f1);
            x1 = high - ratio * (high - low);
            f1 = excess(x1);
        }
    }
    let at = 0.5 * (low + high);
    if !(END_SHARE..=1.0 - END_SHARE).contains(&at) {
        return None;
    }
    let depth = excess(at);
    if depth <= LEAST_DEPTH {
        return None;
    }
    let (_, normal) = signed_distance(collider, a + at * (b - a));
    normal.map(|normal| Press { at, normal, depth })
}
