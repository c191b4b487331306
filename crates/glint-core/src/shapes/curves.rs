//! Curves: tubes around polylines and cubic splines, for hair, fur, grass and wires (Mitsuba's
//! `linearcurve` and `bsplinecurve`, pbrt's `curve`).
//!
//! A curve is a list of control points, each with a radius. Its surface is the one a sphere
//! sweeps out as it moves along the curve, growing and shrinking with the radius:
//! - `Linear`: straight segments between the points, with a sphere at every point (the
//!   joints and the two ends are round), as Mitsuba's `linearcurve` (Embree's round linear
//!   curves);
//! - `BSpline`: a uniform cubic B-spline through the points (n points, n − 3 segments), the
//!   radius the same spline of the radii, open at its two ends, as Mitsuba's `bsplinecurve`;
//! - `Bezier`: cubic Bézier segments (points 0–3, 3–6, …), as pbrt's `curve`.
//!
//! Each straight segment is intersected exactly: the swept sphere of a segment whose radius
//! changes linearly is a cone tangent to its two end spheres, a quadric, so the ray meets it
//! at the roots of a quadratic. A cubic segment is cut into straight pieces fine enough that
//! the tube's axis strays from the cubic by at most 2 % of the segment's largest radius (the
//! chord's distance from a cubic over a parameter step h is at most max|c″| h² / 8; at most 64
//! pieces), joined by spheres, and shaded with the normal of the sphere swept along the cubic
//! itself, so that neither silhouette nor shading shows the pieces. Every piece is a
//! primitive of the BVH.
//!
//! Only the outside is a surface: a ray that starts inside a tube leaves it unseen (Embree's
//! round curves, and so Mitsuba's, do the same), so a ray leaving the surface never meets it
//! again from within. A piece's entry point that lies within its neighbours on the curve is
//! inside the tube, so the joints and bends are not seen from within either.
//!
//! Parameterisation (Mitsuba's): v runs along the curves, from 0 at the start of the first
//! segment to 1 at the end of the last (all curves of the shape in order), u around the tube,
//! from the frame that the tangent and +z make. The surface is in world space: control points
//! are placed by the object's transform when the scene is built, radii are not scaled by it
//! (as Mitsuba).

use glam::{Vec2, Vec3};

use super::{solve_quadratic, PrimHit, SurfaceGeometry};
use crate::geometry::{gamma, Aabb, Ray};
use crate::Named;

/// How the control points make the curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurveBasis {
    /// Straight segments, round joints and ends.
    #[default]
    Linear,
    /// Uniform cubic B-spline, open ends.
    BSpline,
    /// Cubic Bézier segments sharing their end points, open ends.
    Bezier,
}

impl Named for CurveBasis {
    const ALL: &'static [Self] = &[CurveBasis::Linear, CurveBasis::BSpline, CurveBasis::Bezier];

    fn name(self) -> &'static str {
        match self {
            CurveBasis::Linear => "linear",
            CurveBasis::BSpline => "bspline",
            CurveBasis::Bezier => "bezier",
        }
    }
}

/// A segment as a cubic Bézier of positions and of radii (a straight one too: its inner
/// control points at thirds), for shading.
#[derive(Clone, Debug, PartialEq)]
struct Segment {
    points: [Vec3; 4],
    radii: [f32; 4],
}

impl Segment {
    fn point(&self, v: f32) -> Vec3 {
        let [a, b, c, d] = bernstein(v);
        a * self.points[0] + b * self.points[1] + c * self.points[2] + d * self.points[3]
    }

    fn radius(&self, v: f32) -> f32 {
        let [a, b, c, d] = bernstein(v);
        a * self.radii[0] + b * self.radii[1] + c * self.radii[2] + d * self.radii[3]
    }

    /// c′(v), c″(v) and r′(v).
    fn derivatives(&self, v: f32) -> (Vec3, Vec3, f32) {
        let [p0, p1, p2, p3] = self.points;
        let [r0, r1, r2, r3] = self.radii;
        let s = 1.0 - v;
        let first = 3.0 * (s * s * (p1 - p0) + 2.0 * s * v * (p2 - p1) + v * v * (p3 - p2));
        let second = 6.0 * (s * (p2 - 2.0 * p1 + p0) + v * (p3 - 2.0 * p2 + p1));
        let radius = 3.0 * (s * s * (r1 - r0) + 2.0 * s * v * (r2 - r1) + v * v * (r3 - r2));
        (first, second, radius)
    }
}

fn bernstein(v: f32) -> [f32; 4] {
    let s = 1.0 - v;
    [s * s * s, 3.0 * s * s * v, 3.0 * s * v * v, v * v * v]
}

/// A straight piece of tube: the swept sphere from (p0, r0) to (p1, r1), with the end spheres
/// where `caps` says, covering parameters `v0` to `v1` of its segment.
#[derive(Clone, Debug, PartialEq)]
struct Piece {
    p0: Vec3,
    p1: Vec3,
    r0: f32,
    r1: f32,
    /// Bit 0: the sphere at p0 is part of the surface; bit 1: the one at p1.
    caps: u8,
    /// Whether the pieces before and after this one (in `Curves::pieces`) belong to the same
    /// curve: a point within them is inside the tube, not on its surface.
    joined: [bool; 2],
    segment: u32,
    v0: f32,
    v1: f32,
}

/// The chord of a piece may stray from its cubic by this fraction of the radius.
const CHORD_TOLERANCE: f32 = 0.02;
/// At most this many pieces per cubic segment.
const MAX_PIECES: usize = 64;

#[derive(Clone, Debug, PartialEq)]
pub struct Curves {
    basis: CurveBasis,
    segments: Vec<Segment>,
    pieces: Vec<Piece>,
}

impl Curves {
    /// The curves through `curves` (each a list of control points (x, y, z, radius), already
    /// in world space), or what is wrong with them.
    pub fn new(basis: CurveBasis, curves: &[Vec<[f32; 4]>]) -> Result<Self, String> {
        let mut segments = Vec::new();
        let mut first_segments = Vec::new();
        for (c, points) in curves.iter().enumerate() {
            if let Some(i) = points.iter().position(|p| !p.iter().all(|x| x.is_finite()) || p[3] < 0.0) {
                return Err(format!("curve {c}, point {i}: {:?} is not finite or has a negative radius", points[i]));
            }
            let at = |i: usize| (Vec3::new(points[i][0], points[i][1], points[i][2]), points[i][3]);
            first_segments.push(segments.len());
            match basis {
                CurveBasis::Linear => {
                    if points.len() < 2 {
                        return Err(format!("curve {c} has {} point(s); a linear curve needs 2", points.len()));
                    }
                    for i in 0..points.len() - 1 {
                        let ((p0, r0), (p1, r1)) = (at(i), at(i + 1));
                        let third = |a: f32| (p0.lerp(p1, a), r0 + (r1 - r0) * a);
                        let ((q1, s1), (q2, s2)) = (third(1.0 / 3.0), third(2.0 / 3.0));
                        segments.push(Segment { points: [p0, q1, q2, p1], radii: [r0, s1, s2, r1] });
                    }
                }
                CurveBasis::BSpline => {
                    if points.len() < 4 {
                        return Err(format!("curve {c} has {} point(s); a B-spline needs 4", points.len()));
                    }
                    for i in 0..points.len() - 3 {
                        let [(p0, r0), (p1, r1), (p2, r2), (p3, r3)] = [at(i), at(i + 1), at(i + 2), at(i + 3)];
                        segments.push(Segment {
                            points: [
                                (p0 + 4.0 * p1 + p2) / 6.0,
                                (2.0 * p1 + p2) / 3.0,
                                (p1 + 2.0 * p2) / 3.0,
                                (p1 + 4.0 * p2 + p3) / 6.0,
                            ],
                            radii: [
                                (r0 + 4.0 * r1 + r2) / 6.0,
                                (2.0 * r1 + r2) / 3.0,
                                (r1 + 2.0 * r2) / 3.0,
                                (r1 + 4.0 * r2 + r3) / 6.0,
                            ],
                        });
                    }
                }
                CurveBasis::Bezier => {
                    if points.len() < 4 || (points.len() - 1) % 3 != 0 {
                        return Err(format!(
                            "curve {c} has {} points; cubic Bézier segments need 3k + 1 (k ≥ 1)",
                            points.len()
                        ));
                    }
                    for i in (0..points.len() - 1).step_by(3) {
                        let [(p0, r0), (p1, r1), (p2, r2), (p3, r3)] = [at(i), at(i + 1), at(i + 2), at(i + 3)];
                        segments.push(Segment { points: [p0, p1, p2, p3], radii: [r0, r1, r2, r3] });
                    }
                }
            }
        }
        if segments.is_empty() {
            return Err("no curves".into());
        }
        first_segments.push(segments.len());
        let mut pieces = Vec::new();
        for curve in first_segments.windows(2) {
            let (first, end) = (curve[0], curve[1]);
            let first_piece = pieces.len();
            for (s, segment) in segments.iter().enumerate().take(end).skip(first) {
                let n = pieces_for(segment, basis);
                for k in 0..n {
                    let (v0, v1) = (k as f32 / n as f32, (k + 1) as f32 / n as f32);
                    let (p0, p1) = (segment.point(v0), segment.point(v1));
                    let (r0, r1) = (segment.radius(v0).max(0.0), segment.radius(v1).max(0.0));
                    // Linear curves are round at every point; cubic ones join their pieces
                    // with spheres (one per joint, at the start of the later piece) and stay
                    // open at their ends.
                    let caps = match basis {
                        CurveBasis::Linear => 0b11,
                        _ => u8::from(pieces.len() > first_piece),
                    };
                    let joined = [pieces.len() > first_piece, true];
                    pieces.push(Piece { p0, p1, r0, r1, caps, joined, segment: s as u32, v0, v1 });
                }
            }
            if let Some(last) = pieces.last_mut() {
                last.joined[1] = false;
            }
        }
        Ok(Self { basis, segments, pieces })
    }

    pub fn basis(&self) -> CurveBasis {
        self.basis
    }

    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    pub fn primitive_count(&self) -> u32 {
        self.pieces.len() as u32
    }

    pub fn bounds(&self, prim: u32) -> Aabb {
        let p = &self.pieces[prim as usize];
        let (r0, r1) = (Vec3::splat(p.r0), Vec3::splat(p.r1));
        let lo = (p.p0 - r0).min(p.p1 - r1);
        let hi = (p.p0 + r0).max(p.p1 + r1);
        // Widened by the rounding of the intersection's arithmetic.
        let margin = (lo.abs().max(hi.abs()) + Vec3::splat(p.r0.max(p.r1))) * gamma(4);
        Aabb { min: lo - margin, max: hi + margin }
    }

    /// The nearest point where the ray enters piece `prim` from outside: its distance, and in
    /// `u` the parameter along the piece (0 at p0, 1 at p1) of the point's foot on the axis.
    pub fn intersect(&self, prim: u32, ray: &Ray) -> Option<PrimHit> {
        let p = &self.pieces[prim as usize];
        let mut best: Option<f32> = None;
        // A point within the neighbouring pieces is inside the tube (a ray from inside, at a
        // joint or a bend), not on its surface.
        let mut consider = |t: f32| {
            if ray.contains(t) && best.is_none_or(|b| t < b) && !self.within_neighbours(prim as usize, ray.at(t)) {
                best = Some(t);
            }
        };
        for (cap, centre, radius) in [(1, p.p0, p.r0), (2, p.p1, p.r1)] {
            if p.caps & cap != 0 {
                // Entering a sphere is entering the piece unless the point is already within
                // the rest of it (a ray from inside the tube).
                if let Some(t) = sphere_entry(ray, centre, radius).filter(|&t| !p.holds(ray.at(t), cap)) {
                    consider(t);
                }
            }
        }
        if let Some(t) = cone_entry(ray, p) {
            consider(t);
        }
        let t = best?;
        Some(PrimHit { t, u: p.foot(ray.at(t)), v: 0.0, inner: 0 })
    }

    /// `point` lies strictly within the piece before or after piece `i` on its curve.
    fn within_neighbours(&self, i: usize, point: Vec3) -> bool {
        let piece = &self.pieces[i];
        (piece.joined[0] && self.pieces[i - 1].holds(point, 0))
            || (piece.joined[1] && self.pieces[i + 1].holds(point, 0))
    }

    /// The surface where the ray hit piece `prim`.
    pub fn surface(&self, prim: u32, ray: &Ray, hit: &PrimHit) -> SurfaceGeometry {
        self.surface_at_point(prim, ray.at(hit.t), hit.u)
    }

    fn surface_at_point(&self, prim: u32, point: Vec3, along: f32) -> SurfaceGeometry {
        let piece = &self.pieces[prim as usize];
        let axis_point = piece.p0.lerp(piece.p1, along);
        let geometric = (point - axis_point).normalize_or(Vec3::Z);
        let segment = &self.segments[piece.segment as usize];
        let v = piece.v0 + (piece.v1 - piece.v0) * along;
        let shading = self.shading_normal(segment, v, point, geometric);
        let tangent = segment.derivatives(v).0.normalize_or(piece.p1 - piece.p0);
        let (around, radial) = frame(tangent);
        let mut u = around.dot(shading).atan2(radial.dot(shading)) / std::f32::consts::TAU;
        if u < 0.0 {
            u += 1.0;
        }
        let global_v = (piece.segment as f32 + v) / self.segments.len() as f32;
        let radius = piece.r0.max(piece.r1);
        SurfaceGeometry {
            point,
            geometric_normal: geometric,
            shading_normal: shading,
            uv: Vec2::new(u, global_v),
            error: (point.abs() + Vec3::splat(radius)) * gamma(8),
        }
    }

    /// The swept sphere's normal over the cubic itself: from the cubic's point at parameter
    /// v (the touching sphere's centre, where the pieces' chords stray from it) to `point`,
    /// on `geometric`'s side; `geometric` where it degenerates. Continuous across the pieces,
    /// and on a straight segment the geometric normal.
    fn shading_normal(&self, segment: &Segment, v: f32, point: Vec3, geometric: Vec3) -> Vec3 {
        let n = (point - segment.point(v)).normalize_or(geometric);
        if n.dot(geometric) > 0.0 {
            n
        } else {
            geometric
        }
    }

    /// (∂p/∂u, ∂p/∂v) at `point` on piece `prim`: around the tube and along the curves (v
    /// over every segment of the shape).
    pub fn tangents(&self, prim: u32, point: Vec3) -> (Vec3, Vec3) {
        let piece = &self.pieces[prim as usize];
        let along = piece.foot(point);
        let segment = &self.segments[piece.segment as usize];
        let v = piece.v0 + (piece.v1 - piece.v0) * along;
        let (d1, _, dr) = segment.derivatives(v);
        let centre = segment.point(v);
        let normal = (point - centre).normalize_or(Vec3::Z);
        let dpdu = std::f32::consts::TAU * d1.normalize_or(Vec3::X).cross(point - centre);
        let dpdv = self.segments.len() as f32 * (d1 + dr * normal);
        (dpdu, dpdv)
    }
}

impl Piece {
    /// `point` lies strictly within the piece's cone or within one of its caps other than
    /// `cap` (a bit of `caps`; 0: any of them).
    fn holds(&self, point: Vec3, cap: u8) -> bool {
        let within = |distance: f32, radius: f32| distance < radius * (1.0 - 1e-4);
        let tau = self.foot(point);
        let in_cone = tau > 0.0
            && tau < 1.0
            && within((point - self.p0.lerp(self.p1, tau)).length(), self.r0 + (self.r1 - self.r0) * tau);
        let in_cap = |bit: u8, centre: Vec3, radius: f32| {
            bit != cap && self.caps & bit != 0 && within((point - centre).length(), radius)
        };
        in_cone || in_cap(1, self.p0, self.r0) || in_cap(2, self.p1, self.r1)
    }

    /// The parameter along the axis (clamped to [0, 1]) of the sphere whose surface holds
    /// `point`: where ∂/∂t |point − c(t)|² − r(t)² vanishes.
    fn foot(&self, point: Vec3) -> f32 {
        let d = self.p1 - self.p0;
        let dr = self.r1 - self.r0;
        let denominator = d.length_squared() - dr * dr;
        if denominator <= 0.0 {
            return if self.r0 >= self.r1 { 0.0 } else { 1.0 };
        }
        (((point - self.p0).dot(d) + self.r0 * dr) / denominator).clamp(0.0, 1.0)
    }
}

/// The distance at which the ray enters the sphere from outside, if it does.
fn sphere_entry(ray: &Ray, centre: Vec3, radius: f32) -> Option<f32> {
    let oc = ray.origin - centre;
    let a = ray.direction.length_squared();
    let (t0, _) = solve_quadratic(a, oc.dot(ray.direction), oc.length_squared() - radius * radius)?;
    // The first root enters; a ray from inside has it behind its origin.
    ((oc + t0 * ray.direction).dot(ray.direction) < 0.0).then_some(t0)
}

/// The distance at which the ray enters the side of the cone between the piece's end spheres
/// (their tangent cone), from outside.
///
/// With d = p1 − p0 and dr = r1 − r0, the sphere at parameter τ(q) = (q·d + r0 dr) / (|d|² −
/// dr²) touches the surface at q (q from p0), so the surface is |q − τ d|² = (r0 + τ dr)²
/// for τ in [0, 1]: along the ray q = o′ + s w, τ is linear in s, q − τ d = P + s Q and
/// r = R + s S, and the surface a quadratic |Q|² − S², 2(P·Q − R S), |P|² − R².
fn cone_entry(ray: &Ray, piece: &Piece) -> Option<f32> {
    let d = piece.p1 - piece.p0;
    let dr = piece.r1 - piece.r0;
    let e = d.length_squared() - dr * dr;
    if e <= 0.0 {
        return None; // one end sphere holds the other: no side
    }
    let oa = ray.origin - piece.p0;
    let (alpha, beta) = ((oa.dot(d) + piece.r0 * dr) / e, ray.direction.dot(d) / e);
    let (big_p, big_q) = (oa - alpha * d, ray.direction - beta * d);
    let (big_r, big_s) = (piece.r0 + alpha * dr, beta * dr);
    let a = big_q.length_squared() - big_s * big_s;
    let half_b = big_p.dot(big_q) - big_r * big_s;
    let c = big_p.length_squared() - big_r * big_r;
    let (s0, s1) = if a.abs() <= f32::EPSILON * big_q.length_squared() {
        // Along the cone's slant: one root.
        if half_b == 0.0 {
            return None;
        }
        let s = -c / (2.0 * half_b);
        (s, s)
    } else {
        solve_quadratic(a, half_b, c)?
    };
    for s in [s0, s1] {
        let tau = alpha + beta * s;
        if !(0.0..=1.0).contains(&tau) || !ray.contains(s) {
            continue;
        }
        // Entering: the surface's outward normal P + s Q faces against the ray.
        if (big_p + s * big_q).dot(ray.direction) < 0.0 {
            return Some(s);
        }
    }
    None
}

/// The pieces a segment is cut into: one for a straight segment; for a cubic, enough that each
/// chord strays at most `CHORD_TOLERANCE` of the radius from the curve.
fn pieces_for(segment: &Segment, basis: CurveBasis) -> usize {
    if basis == CurveBasis::Linear {
        return 1;
    }
    let [p0, p1, p2, p3] = segment.points;
    // |c″| ≤ 6 max |b_i − 2 b_{i+1} + b_{i+2}|, and a chord over a step h strays at most
    // |c″| h² / 8.
    let bend = (p0 - 2.0 * p1 + p2).length().max((p1 - 2.0 * p2 + p3).length());
    let radius = segment.radii.iter().fold(0.0f32, |m, &r| m.max(r));
    let tolerance = CHORD_TOLERANCE * radius.max(1e-3 * (p3 - p0).length()).max(f32::MIN_POSITIVE);
    let n = (6.0 * bend / (8.0 * tolerance)).sqrt().ceil();
    if n.is_finite() {
        (n as usize).clamp(1, MAX_PIECES)
    } else {
        MAX_PIECES
    }
}

/// The frame around a tube's tangent that its u is measured in (Mitsuba's): the direction
/// toward +z square to the tangent (+y where the tangent is along z), and that × the tangent.
fn frame(tangent: Vec3) -> (Vec3, Vec3) {
    let up = (Vec3::Z - tangent * tangent.dot(Vec3::Z)).try_normalize().unwrap_or(Vec3::Y);
    (up, up.cross(tangent))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(curves: &Curves, ray: &Ray) -> Option<(u32, PrimHit)> {
        let mut best: Option<(u32, PrimHit)> = None;
        for prim in 0..curves.primitive_count() {
            let mut narrowed = *ray;
            if let Some((_, b)) = best {
                narrowed.t_max = b.t;
            }
            if let Some(h) = curves.intersect(prim, &narrowed) {
                best = Some((prim, h));
            }
        }
        best
    }

    /// A straight linear curve of constant radius is a capsule: a cylinder of radius ½ from
    /// x = −1 to 1 with round ends. Rays across it hit at distance (distance to axis − ½), along
    /// the axis the cap's pole; the normal points away from the axis.
    #[test]
    fn a_straight_linear_curve_is_a_capsule() {
        let curves = Curves::new(CurveBasis::Linear, &[vec![[-1.0, 0.0, 0.0, 0.5], [1.0, 0.0, 0.0, 0.5]]]).unwrap();
        for x in [-0.9f32, 0.0, 0.4] {
            let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
            let (prim, h) = hit(&curves, &ray).expect("across the side");
            assert!((h.t - 4.5).abs() < 1e-5, "{x}: {}", h.t);
            let s = curves.surface(prim, &ray, &h);
            assert!((s.geometric_normal - Vec3::Z).length() < 1e-5);
        }
        let along = Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X);
        let (_, h) = hit(&curves, &along).expect("the cap");
        assert!((h.t - 3.5).abs() < 1e-5, "{}", h.t);
        // Past the cap's edge (x = 1.3: within the cap's sphere, y = 0.4 < √(0.25 − 0.09)).
        let grazing = Ray::new(Vec3::new(1.3, 0.3, 5.0), -Vec3::Z);
        let (_, h) = hit(&curves, &grazing).expect("the cap's side");
        assert!((h.t - (5.0 - (0.25f32 - 0.09 - 0.09).sqrt())).abs() < 1e-5, "{}", h.t);
        assert!(hit(&curves, &Ray::new(Vec3::new(1.6, 0.0, 5.0), -Vec3::Z)).is_none());
    }

    /// A tapered linear segment (radius 1 at x = 0 to 0.5 at x = 4): its side is the cone
    /// tangent to the two spheres. Rays straight down meet it where the tangent line of the
    /// two circles (in the xz plane) is: z = r(x′) / cos(φ) geometry, checked against the
    /// distance from the hit point to the nearest sphere of the sweep, which must be its radius.
    #[test]
    fn a_tapered_segment_is_the_spheres_tangent_cone() {
        let curves = Curves::new(CurveBasis::Linear, &[vec![[0.0, 0.0, 0.0, 1.0], [4.0, 0.0, 0.0, 0.5]]]).unwrap();
        for x in [0.5f32, 1.5, 2.5, 3.5] {
            let ray = Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
            let (_, h) = hit(&curves, &ray).expect("the side");
            let p = ray.at(h.t);
            // On the surface: the least over τ of |p − c(τ)| − r(τ) is zero.
            let gap = (0..=4000)
                .map(|i| {
                    let tau = i as f32 / 4000.0;
                    (p - Vec3::new(4.0 * tau, 0.0, 0.0)).length() - (1.0 - 0.5 * tau)
                })
                .fold(f32::INFINITY, f32::min);
            assert!(gap.abs() < 1e-4, "{x}: {gap}");
        }
    }

    /// Rays from inside a tube leave it unseen (only the outside is a surface): through one
    /// segment, past the joints of a straight and a bent polyline, and along a bent B-spline.
    #[test]
    fn rays_from_inside_pass_out() {
        let curves = Curves::new(CurveBasis::Linear, &[vec![[-1.0, 0.0, 0.0, 0.5], [1.0, 0.0, 0.0, 0.5]]]).unwrap();
        for direction in [Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            assert!(hit(&curves, &Ray::new(Vec3::ZERO, direction)).is_none(), "{direction}");
        }
        let straight = vec![[-1.0, 0.0, 0.0, 0.5], [0.0, 0.0, 0.0, 0.5], [1.0, 0.0, 0.0, 0.5], [2.0, 0.0, 0.0, 0.5]];
        let curves = Curves::new(CurveBasis::Linear, &[straight]).unwrap();
        assert!(hit(&curves, &Ray::new(Vec3::new(-0.9, 0.3, 0.0), Vec3::X)).is_none(), "past the joints");
        let bent = vec![[0.0, 0.0, 0.0, 0.3], [1.0, 0.0, 0.0, 0.3], [1.5, 0.8, 0.0, 0.3]];
        let curves = Curves::new(CurveBasis::Linear, &[bent]).unwrap();
        assert!(hit(&curves, &Ray::new(Vec3::new(0.2, 0.1, 0.0), Vec3::X)).is_none(), "through the bend");
        let spline = vec![[0.0, 0.0, 0.0, 0.3], [1.0, 0.0, 0.0, 0.3], [2.0, 0.5, 0.0, 0.3], [3.0, 1.5, 0.0, 0.3]];
        let curves = Curves::new(CurveBasis::BSpline, &[spline]).unwrap();
        assert!(curves.primitive_count() > 1);
        let start = curves.segments[0].point(0.1);
        let along = curves.segments[0].point(0.9) - start;
        assert!(hit(&curves, &Ray::new(start, along.normalize())).is_none(), "along the spline");
    }

    /// A B-spline through collinear, evenly spaced points is a straight tube open at its ends:
    /// points x = −1, −0.3, 0.3, 1 (radius 1) give one segment from x = −0.317 to 0.317 (the
    /// spline's ends are (p0 + 4p1 + p2) / 6 and (p1 + 4p2 + p3) / 6); rays straight down hit
    /// within it and miss beyond, where a linear curve would have a cap. A bent B-spline's
    /// surface stays within the tolerance of the swept sphere of the true cubic.
    #[test]
    fn b_splines_are_open_tubes_close_to_their_cubic() {
        let straight = [[-1.0, 0.0, 0.0, 1.0], [-0.3, 0.0, 0.0, 1.0], [0.3, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]];
        let curves = Curves::new(CurveBasis::BSpline, &[straight.to_vec()]).unwrap();
        assert_eq!(curves.segment_count(), 1);
        let down = |x: f32| Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z);
        let (_, h) = hit(&curves, &down(0.3)).expect("within the segment");
        assert!((h.t - 4.0).abs() < 1e-4, "{}", h.t);
        assert!(hit(&curves, &down(0.33)).is_none(), "open past the spline's end");

        let bent = vec![[0.0, 0.0, 0.0, 0.1], [1.0, 2.0, 0.0, 0.1], [2.0, -1.0, 0.0, 0.1], [3.0, 1.0, 0.0, 0.1]];
        let curves = Curves::new(CurveBasis::BSpline, std::slice::from_ref(&bent)).unwrap();
        assert!(curves.primitive_count() > 4, "cut into pieces: {}", curves.primitive_count());
        let segment = &curves.segments[0];
        let mut hits = 0;
        for i in 0..200 {
            let x = 0.8 + 1.4 * i as f32 / 200.0;
            let Some((prim, h)) = hit(&curves, &down(x)) else { continue };
            hits += 1;
            let p = down(x).at(h.t);
            let gap = (0..=2000)
                .map(|k| {
                    let v = k as f32 / 2000.0;
                    (p - segment.point(v)).length() - segment.radius(v)
                })
                .fold(f32::INFINITY, f32::min);
            assert!(gap.abs() < CHORD_TOLERANCE * 0.1 + 1e-4, "x {x}: {gap}");
            let s = curves.surface(prim, &down(x), &h);
            assert!(s.shading_normal.dot(s.geometric_normal) > 0.99, "{:?}", s);
            assert!((0.0..=1.0).contains(&s.uv.x) && (0.0..=1.0).contains(&s.uv.y));
        }
        assert!(hits > 20, "{hits}");
    }

    /// Bézier and B-spline describe the same cubic when the points convert: the B-spline
    /// segment's Bézier form, given as a Bézier curve, is hit at the same distances.
    #[test]
    fn bezier_and_b_spline_forms_agree() {
        let spline = vec![[0.0, 0.0, 0.0, 0.2], [1.0, 1.0, 0.0, 0.3], [2.0, -1.0, 0.5, 0.1], [3.0, 0.5, 0.0, 0.2]];
        let as_spline = Curves::new(CurveBasis::BSpline, std::slice::from_ref(&spline)).unwrap();
        let s = &as_spline.segments[0];
        let bezier: Vec<[f32; 4]> = (0..4).map(|i| [s.points[i].x, s.points[i].y, s.points[i].z, s.radii[i]]).collect();
        let as_bezier = Curves::new(CurveBasis::Bezier, &[bezier]).unwrap();
        for i in 0..50 {
            let ray = Ray::new(Vec3::new(0.8 + i as f32 * 0.03, 0.2, 5.0), Vec3::new(0.0, -0.05, -1.0).normalize());
            let (a, b) = (hit(&as_spline, &ray), hit(&as_bezier, &ray));
            assert_eq!(a.is_some(), b.is_some(), "{i}");
            if let (Some((_, a)), Some((_, b))) = (a, b) {
                assert!((a.t - b.t).abs() < 1e-4, "{i}: {} {}", a.t, b.t);
            }
        }
    }

    /// Curves refuse what cannot be one: too few points, a negative radius, no curves.
    #[test]
    fn bad_curves_are_refused() {
        assert!(Curves::new(CurveBasis::Linear, &[vec![[0.0; 4]]]).unwrap_err().contains("needs 2"));
        assert!(Curves::new(CurveBasis::BSpline, &[vec![[0.0; 4]; 3]]).unwrap_err().contains("needs 4"));
        assert!(Curves::new(CurveBasis::Bezier, &[vec![[0.0; 4]; 5]]).unwrap_err().contains("3k + 1"));
        let negative = vec![[0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, -1.0]];
        assert!(Curves::new(CurveBasis::Linear, &[negative]).unwrap_err().contains("negative radius"));
        assert!(Curves::new(CurveBasis::Linear, &[]).is_err());
    }
}
