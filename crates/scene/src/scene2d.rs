//! Seeded 2D scenes of segments, discs and boxes.

use accelviz_core::{Aabb, Shape, ShapeSet, Sphere};
use glam::DVec2;

use crate::rng::SplitMix64;

/// How the shapes of a generated scene are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Uniformly over the square `[0, 100]²`.
    Uniform,
    /// In a few tight clusters.
    Clustered,
    /// "Teapot in a stadium": a dense cluster in a corner of a large, nearly empty scene,
    /// where middle splits waste levels and SAH cuts the empty space off.
    TeapotInStadium,
}

/// `count` shapes (segments, discs and boxes in turn) placed by `layout`.
pub fn generate(layout: Layout, count: usize, seed: u64) -> ShapeSet<DVec2> {
    let mut rng = SplitMix64::new(seed);
    let clusters: Vec<DVec2> = (0..4)
        .map(|_| DVec2::new(rng.range(10.0, 90.0), rng.range(10.0, 90.0)))
        .collect();
    let mut shapes = Vec::with_capacity(count);
    for index in 0..count {
        let (center, size) = match layout {
            Layout::Uniform => (
                DVec2::new(rng.range(0.0, 100.0), rng.range(0.0, 100.0)),
                2.0,
            ),
            Layout::Clustered => {
                let cluster = clusters[index % clusters.len()];
                (
                    cluster + DVec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)),
                    0.8,
                )
            }
            Layout::TeapotInStadium => {
                if index < 4 {
                    // The stadium's walls, far apart.
                    let corner = [
                        DVec2::ZERO,
                        DVec2::new(100.0, 0.0),
                        DVec2::new(100.0, 100.0),
                        DVec2::new(0.0, 100.0),
                    ];
                    shapes.push(Shape::Segment([corner[index], corner[(index + 1) % 4]]));
                    continue;
                }
                (
                    DVec2::new(rng.range(80.0, 86.0), rng.range(10.0, 16.0)),
                    0.3,
                )
            }
        };
        let radius = rng.range(0.2, 1.0) * size;
        shapes.push(match index % 3 {
            0 => {
                let angle = rng.range(0.0, std::f64::consts::TAU);
                let half = DVec2::new(angle.cos(), angle.sin()) * radius;
                Shape::Segment([center - half, center + half])
            }
            1 => Shape::Sphere(Sphere { center, radius }),
            _ => {
                let half = DVec2::new(rng.range(0.3, 1.0), rng.range(0.3, 1.0)) * radius;
                Shape::Box(Aabb::new(center - half, center + half))
            }
        });
    }
    ShapeSet { shapes }
}
