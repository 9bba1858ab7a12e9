//! Contacts of moving bodies with the cloth's sheet, not with its beads.
//!
//! Each node is a ball, so a body resting on the cloth meets a carpet of balls: a ball or a box
//! corner settles into the hollows between them, and the contact normals lean by up to 45°
//! towards the hollow's centre. The lean pushes the nodes apart with a share of the body's
//! weight; a body a thousand times heavier than a node tears a lattice apart that way, which a
//! woven sheet (whose surface normal is the only direction its contact can push) never does.
//! [`SheetContacts`] turns the normal of every contact between a node and a dynamic body into
//! the cloth's own surface normal at that node, on the side of the sheet where the body's centre
//! is (a ball's contact moves to its point nearest the sheet); a body whose centre lies
//! nearly in the sheet's plane (meeting a cut edge edge-on) keeps its own normal. Contacts with
//! fixed and kinematic colliders are left alone: they are the
//! supports the implicit solve reads.
//!
//! A node may also carry a surface depth (its collider's `user_data`, from
//! [`crate::embed::ClothBuilder::rest_on_lower_face`]): its contacts with fixed and kinematic colliders
//! are then read that much deeper than Rapier measures its ball, so that the cloth's lower face,
//! not the ball around its mid-surface, rests on the host's own shapes.
//!
//! The surface normals travel in the node bodies' `user_data`, written by
//! [`ClothBodies::write_sheet_normals`](super::ClothBodies::write_sheet_normals) before each
//! step, so one [`SheetContacts`] serves every cloth in a world.

use glam::{DVec3, Vec3};
use rapier3d::prelude::*;

use crate::forces::ClothTopology;

/// Marks a node body's `user_data` as holding a surface normal (the high 32 bits).
const NORMAL_TAG: u128 = 0x4B45_5343;

/// Marks a node collider's `user_data` as holding its surface depth (the high 32 bits).
const DEPTH_TAG: u128 = 0x4B45_5344;

/// Sine of the angle (about 11.5°) between the sheet and the line from a node to a body's
/// centre below which the body meets the sheet edge-on and its contact keeps its own normal.
const EDGE_ON: f32 = 0.2;

/// `user_data` carrying the unit surface normal `n`.
pub(crate) fn encode_normal(n: Vec3) -> u128 {
    (NORMAL_TAG << 96)
        | ((n.x.to_bits() as u128) << 64)
        | ((n.y.to_bits() as u128) << 32)
        | n.z.to_bits() as u128
}

/// The surface normal in a node body's `user_data`, if it carries one.
fn decode_normal(data: u128) -> Option<Vec3> {
    if data >> 96 != NORMAL_TAG {
        return None;
    }
    let part = |shift: u32| f32::from_bits((data >> shift) as u32);
    let n = Vec3::new(part(64), part(32), part(0));
    (n.length_squared() > 0.5).then_some(n)
}

/// A node collider's `user_data` carrying its surface depth `depth` (m): how much deeper than
/// Rapier measures its ball the node's contacts with fixed and kinematic colliders are read.
pub(crate) fn encode_surface_depth(depth: f32) -> u128 {
    (DEPTH_TAG << 96) | depth.to_bits() as u128
}

/// The surface depth (m) in a node collider's `user_data`, if it carries one.
fn surface_depth(data: u128) -> Option<f32> {
    (data >> 96 == DEPTH_TAG).then(|| f32::from_bits(data as u32))
}

/// Whether `body` is a cloth node: its `user_data` carries a surface normal.
pub(crate) fn is_node(body: &RigidBody) -> bool {
    body.user_data >> 96 == NORMAL_TAG
}

/// Unit surface normal at every node (sign arbitrary but consistent over the sheet): the sum of
/// the normals of the triangles around the node, each weighted by its area. A node whose
/// triangles cancel (folded flat on itself) gets zero.
pub(crate) fn sheet_normals(topology: &ClothTopology, positions: &[DVec3], out: &mut Vec<DVec3>) {
    out.clear();
    out.resize(positions.len(), DVec3::ZERO);
    for &[a, b, c] in &topology.triangles {
        let (a, b, c) = (a as usize, b as usize, c as usize);
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        out[a] += n;
        out[b] += n;
        out[c] += n;
    }
    for n in out.iter_mut() {
        *n = n.try_normalize().unwrap_or(DVec3::ZERO);
    }
}

/// Rapier physics hooks that make a dynamic body's contacts with cloth nodes act along the
/// cloth's surface normal (module docs). Step the world with
/// `world.step_with_events(&SheetContacts, &())`, or call
/// [`SheetContacts::modify`] from your own hooks' `modify_solver_contacts`.
#[derive(Clone, Copy, Debug, Default)]
pub struct SheetContacts;

impl SheetContacts {
    /// Makes a node–dynamic body contact act along the node's surface normal (module docs);
    /// leaves every other pair alone.
    pub fn modify(context: &mut ContactModificationContext) {
        let body = |handle: Option<RigidBodyHandle>| handle.and_then(|h| context.bodies.get(h));
        let (b1, b2) = (body(context.rigid_body1), body(context.rigid_body2));
        let sheet1 = b1.and_then(|b| decode_normal(b.user_data));
        let sheet2 = b2.and_then(|b| decode_normal(b.user_data));
        // A node without a normal (folded flat) is no body landing on the sheet.
        let dynamic = |b: Option<&RigidBody>| b.is_some_and(|b| b.is_dynamic() && !is_node(b));
        // A node resting on a fixed or kinematic collider with a surface depth: its contact is
        // read that much deeper, so that the sheet, not the node's ball, meets the surface.
        let depth = |node: ColliderHandle, other: Option<&RigidBody>| {
            let depth = context
                .colliders
                .get(node)
                .and_then(|c| surface_depth(c.user_data));
            depth.filter(|_| other.is_none_or(|b| !b.is_dynamic()))
        };
        if let Some(depth) = depth(context.collider1, b2).or_else(|| depth(context.collider2, b1)) {
            if let Some(manifold) = context.rigid_mut() {
                for contact in manifold.solver_contacts.iter_mut() {
                    contact.dist += depth;
                }
            }
            return;
        }
        // The manifold normal points from collider 1 to collider 2.
        let (sheet, node_first, node_collider, other_collider) = match (sheet1, sheet2) {
            (Some(n), None) if dynamic(b2) => (n, true, context.collider1, context.collider2),
            (None, Some(n)) if dynamic(b1) => (n, false, context.collider2, context.collider1),
            _ => return,
        };
        let (Some(node), Some(other)) = (
            context.colliders.get(node_collider),
            context.colliders.get(other_collider),
        ) else {
            return;
        };
        let node_centre = node.position().translation;
        let node_radius = node.shape().as_ball().map_or(0.0, |b| b.radius);
        let other_pose = *other.position();
        let ball_radius = other.shape().as_ball().map(|b| b.radius);
        let Some(manifold) = context.rigid_mut() else {
            return;
        };
        let towards_other = if node_first { 1.0 } else { -1.0 };
        // The side of the sheet the body is on, judged from its centre, which stays on its side
        // however deep a fast body has sunk between the nodes within one step.
        let to_centre = other_pose.translation - node_centre;
        let height = to_centre.dot(sheet);
        if height.abs() < EDGE_ON * to_centre.length() {
            return;
        }
        // Unit normal from the sheet towards the body.
        let n = sheet * height.signum();
        // A ball meets the sheet at its point nearest the sheet, under its centre, not where it
        // meets a node's ball off its axis (which, pushed along the sheet's normal, would spin
        // it); other shapes keep their contact points (a face lying on the sheet, an edge or a
        // corner meeting it).
        let lowest = ball_radius.map(|r| other_pose.translation - r * n);
        for contact in manifold.solver_contacts.iter_mut() {
            let on_other = if node_first {
                &mut contact.anchor2
            } else {
                &mut contact.anchor1
            };
            if let Some(lowest) = lowest {
                *on_other = lowest;
            }
            let other_point = *on_other;
            // The separation along the sheet's normal, or the contact's own if deeper: a node
            // that a fast body has swallowed within one step meets the body's far side, where
            // the separation along the normal would read as a gap.
            let gap = ((other_point - node_centre).dot(n) - node_radius).min(contact.dist);
            let on_node = other_point - gap * n;
            if node_first {
                contact.anchor1 = on_node;
            } else {
                contact.anchor2 = on_node;
            }
            contact.dist = gap;
        }
        *manifold.normal = n * towards_other;
    }
}

impl PhysicsHooks for SheetContacts {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        Self::modify(context);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A surface depth survives the trip through a collider's `user_data`, and other data reads
    /// as none (a normal included).
    #[test]
    fn surface_depths_round_trip_through_user_data() {
        assert_eq!(surface_depth(encode_surface_depth(0.004_75)), Some(0.004_75));
        assert_eq!(surface_depth(0), None);
        assert_eq!(surface_depth(encode_normal(Vec3::Y)), None);
    }

    /// A normal survives the trip through `user_data` bit for bit, and data not written by us
    /// reads as no normal.
    #[test]
    fn normals_round_trip_through_user_data() {
        let n = Vec3::new(0.6, -0.0, 0.8);
        assert_eq!(decode_normal(encode_normal(n)), Some(n));
        assert_eq!(decode_normal(0), None);
        assert_eq!(decode_normal(12345), None);
    }
}
