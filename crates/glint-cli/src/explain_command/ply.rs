//! `glint explain --ply FILE`: the paths as an ASCII PLY line set, to look at beside the
//! scene in a 3D viewer.

use std::fmt::Write;

use glint_core::geometry::Ray;
use glint_core::integrators::path_record::{ParticleEvent, PathEvent, PathLog};
use glint_core::integrators::ParticleExplanation;
use glint_core::scene::Scene;
use glint_core::{Rgb, Vec3};

/// The particles' paths as a PLY line set: from each particle's start through its surfaces,
/// and from each surface that splats into the pixel to the camera.
pub(super) fn particles_ply(scene: &Scene, e: &ParticleExplanation, x: u32, y: u32) -> String {
    let camera = scene.camera().generate_ray(x as f32 + 0.5, y as f32 + 0.5).origin;
    let mut points = Vec::new();
    let mut edges = Vec::new();
    for (_, log) in &e.particles {
        let mut previous = None;
        for event in &log.events {
            match event {
                ParticleEvent::Start { origin: p, .. } | ParticleEvent::Surface { point: p, .. } => {
                    points.push(*p);
                    if let Some(q) = previous {
                        edges.push((q, points.len() - 1));
                    }
                    previous = Some(points.len() - 1);
                }
                ParticleEvent::Splat { x: sx, y: sy, .. } if (*sx, *sy) == (x, y) => {
                    if let Some(q) = previous {
                        points.push(camera);
                        edges.push((q, points.len() - 1));
                    }
                }
                _ => {}
            }
        }
    }
    line_set(&points, &edges, &format!("glint explain --integrator light: pixel {x},{y}"))
}

/// The path as an ASCII PLY line set: vertices, then edges from the camera through each path
/// vertex (to a point 1 scene radius past the last one where the path leaves the scene), and
/// from each vertex to its light sample's point (a unit-length stub toward a light at infinity).
pub(super) fn path_ply(scene: &Scene, (ray, _, log): &(Ray, Rgb, PathLog), x: u32, y: u32) -> String {
    let mut points = vec![ray.origin];
    let mut edges = Vec::new();
    let (mut previous, mut last_direction) = (0usize, ray.direction.normalize());
    let bounds = scene.geometry().bounds();
    let reach = if bounds.is_empty() { 1.0 } else { bounds.extent().length().clamp(1.0, 1e6) };
    for event in &log.events {
        match event {
            PathEvent::Vertex { point, .. } | PathEvent::Medium { point, .. } => {
                points.push(*point);
                edges.push((previous, points.len() - 1));
                previous = points.len() - 1;
            }
            PathEvent::Light(l) => {
                points.push(l.point.unwrap_or(points[previous] + l.direction));
                edges.push((previous, points.len() - 1));
            }
            PathEvent::Scatter { direction, .. } | PathEvent::Phase { direction, .. } => last_direction = *direction,
            PathEvent::Escape { .. } => {
                points.push(points[previous] + last_direction * reach);
                edges.push((previous, points.len() - 1));
            }
            _ => {}
        }
    }
    line_set(&points, &edges, &format!("glint explain: pixel {x},{y}"))
}

/// Points and the edges between them as an ASCII PLY line set.
pub(super) fn line_set(points: &[Vec3], edges: &[(usize, usize)], comment: &str) -> String {
    let mut out = format!(
        "ply\nformat ascii 1.0\ncomment {comment}\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement edge {}\nproperty int vertex1\nproperty int vertex2\nend_header\n",
        points.len(),
        edges.len()
    );
    for p in points {
        let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
    }
    for (a, b) in edges {
        let _ = writeln!(out, "{a} {b}");
    }
    out
}
