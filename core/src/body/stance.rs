//! Standing on the ground: the body's supports, the pitch of the trunk
//! that keeps the fore and hind supports both on the ground, and the lift
//! that puts them there (growth paper, Sec. 7 joint rotations; Fig. 5, the
//! young horse stands).
//!
//! Fore and hind legs grow at their own rates (Table 1: elbow-to-ground
//! 25.0 → 35.8 in, hind leg 18.1 → 23.3 in), so a body whose hooves stand
//! level in the model cannot stand level at another age: the trunk must
//! slope. Sec. 7 lets a joint rotation R (measured from the rest pose)
//! enter the chain `T_AB·G_A⁻¹·R_AB·R·S·G_B` as long as it does not change
//! the measured distances. The pitch is such a rotation: R = R_z(φ) at the
//! root, about the hind support's joint, and the inverse rotation at the
//! joints of the supporting limbs (shoulders, hips), which therefore keep
//! their world orientation and are only carried by their joint. Every
//! cylinder moves rigidly, no feature changes, and the legs stay upright,
//! so the vertical heights the table measures (elbow → ground, hock →
//! ground) remain vertical.
//!
//! A **support** is a leaf cylinder whose lower axis end lies within its
//! radius of the lowest axis end of the model; its **sole** is the row of
//! mesh vertices on the model's ground inside it (its heel and toe, the
//! least and greatest x), and it is a **fore** or **hind** support by the
//! side of the supports' mid-x its lower end lies on. At every pose the
//! lowest sole of each end is found, the trunk pitches until they are
//! level, and the body is lifted so that they touch the ground. A gait
//! with footfall timing ([`super::gait::Footfall`]) names the supports on
//! the ground at each phase (a trot's diagonal pair) and only they count;
//! without it the lower hoof of each pair is the support. A body without
//! both fore and hind supports (a tail, a biped) keeps the plain lift of
//! [`super::skeleton`].

use heapless::Vec;
use nalgebra::Vector3;

use super::BodyModel;
use super::chain::Affine;
use super::cylinder::{Rest, norm};
use super::solve::Growth;
use crate::fx::Real;

/// Which end of the body a support carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// Behind the supports' mid-x (the hind legs).
    Hind = 0,
    /// Ahead of it (the fore legs).
    Fore = 1,
}

/// How one cylinder takes part in standing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part<R: Real> {
    /// Its limb: the ancestor hanging from the root (itself for a child of
    /// the root; 0 for the root).
    pub limb: u8,
    /// Whether its limb holds a support (it keeps its orientation when the
    /// trunk pitches).
    pub carried: bool,
    /// The end it supports, if it is a support.
    pub end: Option<End>,
    /// Its sole's heel and toe x in model space (at the ground, at the z of
    /// its lower axis end).
    pub sole: [R; 2],
}

/// The lower axis end of a cylinder, in model space.
fn lower_end<R: Real>(rest: &Rest<R>) -> Vector3<R> {
    let tip = rest.origin + rest.rotation.column(0) * rest.length;
    if tip.y < rest.origin.y {
        tip
    } else {
        rest.origin
    }
}

/// The roles of `model`'s cylinders and the model's ground (its lowest
/// vertex), or `None` when the body has no fore and hind supports.
///
/// `axis_ground` is the lowest axis end of the model.
pub fn parts<R: Real, const C: usize>(
    model: &BodyModel<'_>,
    rests: &[Rest<R>],
    axis_ground: R,
) -> Option<(Vec<Part<R>, C>, R)> {
    let cylinders = model.cylinders;
    let mut parts: Vec<Part<R>, C> = Vec::new();
    // Limbs and supports; the supports' x range.
    let mut span: Option<(R, R)> = None;
    for (i, (c, rest)) in cylinders.iter().zip(rests).enumerate() {
        let mut limb = i;
        // Parents come before children: at most `i` steps up.
        for _ in 0..=i {
            match cylinders.get(limb).and_then(|c| c.parent) {
                Some(p)
                    if cylinders
                        .get(usize::from(p))
                        .is_some_and(|a| a.parent.is_some()) =>
                {
                    limb = usize::from(p);
                }
                Some(_) => break,
                None => {
                    limb = 0;
                    break;
                }
            }
        }
        let leaf = !cylinders.iter().any(|d| d.parent == u8::try_from(i).ok());
        let end = lower_end(rest);
        let support = leaf && c.parent.is_some() && end.y - axis_ground <= rest.radius;
        if support {
            span = Some(match span {
                None => (end.x, end.x),
                Some((lo, hi)) => (
                    if end.x < lo { end.x } else { lo },
                    if end.x > hi { end.x } else { hi },
                ),
            });
        }
        let part = Part {
            limb: u8::try_from(limb).ok()?,
            carried: false,
            end: support.then_some(End::Hind),
            sole: [end.x, end.x],
        };
        parts.push(part).ok()?;
    }
    let (lo, hi) = span?;
    // Half each first: no overflow near the range's ends.
    let half = R::from_ratio(1, 2);
    let mid = lo * half + hi * half;
    let (mut fore, mut hind) = (false, false);
    for (part, rest) in parts.iter_mut().zip(rests) {
        if part.end.is_some() {
            let x = lower_end(rest).x;
            part.end = if x > mid {
                fore = true;
                Some(End::Fore)
            } else if x < mid {
                hind = true;
                Some(End::Hind)
            } else {
                None
            };
        }
    }
    if !(fore && hind) {
        return None;
    }
    for i in 0..parts.len() {
        let Some(limb) = parts.get(i).map(|p| p.limb) else {
            break;
        };
        let carried = limb != 0 && parts.iter().any(|p| p.end.is_some() && p.limb == limb);
        if let Some(p) = parts.get_mut(i) {
            p.carried = carried;
        }
    }
    // The ground: the lowest vertex (first pass); a sole: the vertices on
    // it inside the support (second pass). Heel and toe start as an empty
    // range (heel > toe); a support without such vertices stands on the
    // point under its lower axis end.
    for part in &mut parts {
        part.sole = [
            R::from_int(i32::from(i16::MAX)),
            R::from_int(i32::from(i16::MIN)),
        ];
    }
    let mesh = &model.mesh;
    let mut ground: Option<R> = None;
    for pass in 0..2 {
        for p in (0..mesh.vertex_count()).filter_map(|i| mesh.vertex::<R>(i)) {
            let Some(g) = ground.filter(|_| pass == 1) else {
                if ground.is_none_or(|g| p.y < g) {
                    ground = Some(p.y);
                }
                continue;
            };
            for (part, rest) in parts.iter_mut().zip(rests) {
                let q = rest.to_local(&p);
                if part.end.is_some()
                    && p.y - g <= rest.radius * R::from_ratio(1, 8)
                    && q.x >= R::zero()
                    && q.x <= rest.length
                    && norm(&Vector3::new(R::zero(), q.y, q.z)) <= rest.radius
                {
                    if p.x < part.sole[0] {
                        part.sole[0] = p.x;
                    }
                    if p.x > part.sole[1] {
                        part.sole[1] = p.x;
                    }
                }
            }
        }
    }
    for (part, rest) in parts.iter_mut().zip(rests) {
        if part.sole[0] > part.sole[1] {
            let x = lower_end(rest).x;
            part.sole = [x, x];
        }
    }
    let ground = ground?;
    Some((parts, ground))
}

/// The lowest sole of each end (hind, fore) under the chain maps `maps`
/// (before growth): its height and its limb. Only the supports `on(i)`
/// count, unless an end has none on the ground: then all of that end's.
fn lowest<R: Real>(
    parts: &[Part<R>],
    rests: &[Rest<R>],
    growth: &[Growth<R>],
    maps: &[Affine<R>],
    ground: R,
    on: &dyn Fn(usize) -> bool,
) -> Option<[(R, usize); 2]> {
    let mut best: [Option<(R, usize)>; 2] = [None, None];
    let down = |end: End| {
        parts
            .iter()
            .enumerate()
            .any(|(i, p)| p.end == Some(end) && on(i))
    };
    let counted = [down(End::Hind), down(End::Fore)];
    for (i, (((part, rest), g), w)) in parts.iter().zip(rests).zip(growth).zip(maps).enumerate() {
        let Some(end) = part.end else { continue };
        if counted[end as usize] && !on(i) {
            continue;
        }
        let z = lower_end(rest).z;
        for x in part.sole {
            // The sole point's local frame at model size, grown, to the world.
            let q = rest.to_local(&Vector3::new(x, ground, z));
            let y = w
                .apply(&Vector3::new(
                    q.x * g.length,
                    q.y * g.radius,
                    q.z * g.radius,
                ))
                .y;
            let slot = &mut best[end as usize];
            if slot.is_none_or(|(b, _)| y < b) {
                *slot = Some((y, usize::from(part.limb)));
            }
        }
    }
    Some([best[0]?, best[1]?])
}

/// Pitches the chain maps `maps` (before growth) so that the lowest fore
/// and hind soles of the supports on the ground (`on(i)` for cylinder i)
/// are level, and returns the lift that puts the lowest sole of all on
/// `ground`: the supports on the ground touch it unless a lifted hoof
/// hangs lower, and no hoof goes below it (`None` when a map is missing).
pub fn stand<R: Real>(
    parts: &[Part<R>],
    rests: &[Rest<R>],
    growth: &[Growth<R>],
    maps: &mut [Affine<R>],
    ground: R,
    on: &dyn Fn(usize) -> bool,
) -> Option<R> {
    let [(hind_y, hind_limb), (fore_y, fore_limb)] =
        lowest(parts, rests, growth, maps, ground, on)?;
    let pivot = maps.get(hind_limb)?.translation;
    let joint = maps.get(fore_limb)?.translation;
    // The fore joint seen from the hind one, in the side plane: turn it
    // about the pivot until it is `fore_y − hind_y` lower. All ratios to r:
    // of order one.
    let (dx, dy) = (joint.x - pivot.x, joint.y - pivot.y);
    let r = norm(&Vector3::new(dx, dy, R::zero()));
    if r > R::zero() {
        let (ux, uy) = (dx.div(r), dy.div(r));
        let vy = (dy - (fore_y - hind_y)).div(r);
        let across = R::one() - vy * vy;
        if across > R::zero() {
            let vx = if ux < R::zero() {
                -across.sqrt()
            } else {
                across.sqrt()
            };
            let (c, s) = (ux * vx + uy * vy, ux * vy - uy * vx);
            // The pitch R_z(φ) about the pivot, on x and y only.
            let turn = |x: R, y: R| (c * x - s * y, s * x + c * y);
            // Children after parents: backwards, a limb's map is still
            // unpitched while its cylinders are carried by its joint.
            for i in (0..maps.len()).rev() {
                let Some(part) = parts.get(i) else { continue };
                let joint = maps.get(usize::from(part.limb))?.translation;
                let w = maps.get_mut(i)?;
                let moved = if part.carried { joint } else { w.translation };
                let (x, y) = turn(moved.x - pivot.x, moved.y - pivot.y);
                w.translation.x += x + pivot.x - moved.x;
                w.translation.y += y + pivot.y - moved.y;
                if !part.carried {
                    for mut column in w.linear.column_iter_mut() {
                        (column[0], column[1]) = turn(column[0], column[1]);
                    }
                }
            }
        }
    }
    let [(hind, _), (fore, _)] = lowest(parts, rests, growth, maps, ground, &|_| true)?;
    Some(ground - if fore < hind { fore } else { hind })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::mesh::Mesh;
    use crate::body::quadruped::{COW, HORSE};
    use crate::body::{Cylinder, Label};
    use crate::fx::Fx;

    fn roles(model: &BodyModel<'_>) -> Option<(Vec<Part<Fx>, 24>, Fx)> {
        let rests: Vec<Rest<Fx>, 24> = model
            .cylinders
            .iter()
            .map(|c| Rest::of(c).unwrap())
            .collect();
        let axis_ground = rests
            .iter()
            .map(|r| lower_end(r).y)
            .fold(Fx::MAX, |a, b| if b < a { b } else { a });
        parts::<Fx, 24>(model, &rests, axis_ground)
    }

    #[test]
    fn the_quadrupeds_stand_on_their_four_pasterns_and_carry_their_legs() {
        for model in [&HORSE, &COW] {
            let (parts, ground) = roles(model).unwrap();
            assert_eq!(ground, Fx::ZERO);
            for (c, p) in model.cylinders.iter().zip(&parts) {
                let name = c.name.as_str();
                let leg = name.contains("-fore-") || name.contains("-hind-");
                let want = match (name.ends_with("pastern"), name.contains("-fore-")) {
                    (true, true) => Some(End::Fore),
                    (true, false) => Some(End::Hind),
                    _ => None,
                };
                assert_eq!(p.end, want, "{name}");
                assert_eq!(p.carried, leg, "{name}");
                if p.end.is_some() {
                    // A sole a few units long, heel behind toe.
                    let length = p.sole[1] - p.sole[0];
                    assert!(length > Fx::from_int(3), "{name}: {length}");
                }
            }
        }
    }

    #[test]
    fn a_body_without_fore_and_hind_supports_has_no_stance() {
        let c = |name: &str, parent: Option<u8>, x0: i32, x1: i32| {
            let mut c: Cylinder = HORSE.cylinders[0];
            c.name = Label::new(name);
            c.parent = parent;
            c.base = [Fx::from_int(x0), Fx::ZERO, Fx::ZERO];
            c.tip = [Fx::from_int(x1), Fx::ZERO, Fx::ZERO];
            c
        };
        let cylinders = [c("base", None, 0, 10), c("tip", Some(0), 10, 20)];
        let vertices = [[Fx::ZERO; 3], [Fx::from_int(20), Fx::ZERO, Fx::ZERO]];
        let tail = BodyModel {
            cylinders: &cylinders,
            mesh: Mesh::Indexed {
                vertices: &vertices,
                triangles: &[],
            },
            model_age: Fx::ZERO,
        };
        assert!(roles(&tail).is_none());
    }
}
