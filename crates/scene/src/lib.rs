//! # accelviz-scene
//!
//! Everything that turns the outside world into what `accelviz-core` takes: OBJ meshes read with
//! tobj ([`obj`]), ray files and seeded ray generators ([`rays`]), built-in procedural meshes
//! ([`builtin`]), 2D scenes ([`scene2d`]) and 2D scene documents in RON ([`document`]); PNG images and files
//! written whole or not at all ([`output`]). Errors name the file, the line and the problem.

pub mod builtin;
pub mod document;
pub mod error;
pub mod obj;
pub mod output;
pub mod rays;
pub mod rng;
pub mod scene2d;

pub use error::LoadError;

/// A triangle mesh as loaded: triangles numbered from 0 in file order, corners in f64.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Where it came from (a path, or `builtin:NAME`).
    pub name: String,
    /// The triangles' corners.
    pub triangles: Vec<[[f64; 3]; 3]>,
}

impl Mesh {
    /// The box around every corner.
    pub fn bounds(&self) -> accelviz_core::Aabb<glam::DVec3> {
        accelviz_core::Aabb::from_points(
            self.triangles
                .iter()
                .flatten()
                .map(|&corner| glam::DVec3::from_array(corner)),
        )
    }

    /// The same mesh moved by `offset`.
    pub fn translated(&self, offset: [f64; 3]) -> Self {
        Self {
            name: format!("{} moved by {offset:?}", self.name),
            triangles: self
                .triangles
                .iter()
                .map(|triangle| {
                    triangle.map(|c| [c[0] + offset[0], c[1] + offset[1], c[2] + offset[2]])
                })
                .collect(),
        }
    }
}
