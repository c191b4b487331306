//! BVH heat map (`--integrator bvh-heat`): how much work the acceleration structure does for
//! each camera ray. The "radiance" is (nodes visited + primitives tested, nodes, primitives),
//! where the primitives of a leaf block (up to four, tested together) count one by one,
//! averaged over the pixel's samples; the CLI turns the first channel into a false-colour PNG
//! with a colour bar, and EXR/PFM keep the raw counts. It shows students what the hierarchy
//! does, and us where it is slow. (Counts are of the scene's top-level BVH; an instance's own
//! traversal is counted as one primitive test.)

use super::{Integrator, SampleContext};
use crate::geometry::Ray;
use crate::scene::Scene;
use crate::Rgb;

pub struct BvhHeat;

impl Integrator for BvhHeat {
    fn radiance(&self, scene: &Scene, ray: &Ray, context: &mut SampleContext) -> Rgb {
        context.rays.camera += 1;
        let counts = scene.geometry().traversal_counts(ray);
        let (nodes, primitives) = (counts.nodes as f32, counts.primitives as f32);
        Rgb::new(nodes + primitives, nodes, primitives)
    }
}

/// A false colour for `t` in [0, 1]: dark blue, blue, cyan, green, yellow, red.
pub fn heat_colour(t: f32) -> Rgb {
    const STOPS: [Rgb; 6] = [
        Rgb::new(0.0, 0.0, 0.15),
        Rgb::new(0.0, 0.15, 0.9),
        Rgb::new(0.0, 0.8, 0.9),
        Rgb::new(0.1, 0.85, 0.1),
        Rgb::new(1.0, 0.9, 0.0),
        Rgb::new(0.95, 0.05, 0.0),
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    STOPS[i].lerp(STOPS[i + 1], x - i as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_ramp_ends() {
        assert_eq!(heat_colour(0.0), Rgb::new(0.0, 0.0, 0.15));
        assert_eq!(heat_colour(1.0), Rgb::new(0.95, 0.05, 0.0));
        assert_eq!(heat_colour(7.0), heat_colour(1.0));
    }
}
