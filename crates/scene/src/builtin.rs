//! Built-in procedural meshes: closed meshes whose shared vertices are bit-identical, for
//! watertightness tests, and the default mesh that `accelviz-cli bench` runs on.

use std::collections::HashMap;

use crate::Mesh;

/// An indexed mesh: shared corners are stored once, so neighbours share them exactly.
struct Indexed {
    vertices: Vec<[f64; 3]>,
    faces: Vec<[usize; 3]>,
}

impl Indexed {
    fn into_mesh(self, name: String) -> Mesh {
        Mesh {
            name,
            triangles: self
                .faces
                .iter()
                .map(|face| face.map(|corner| self.vertices[corner]))
                .collect(),
        }
    }
}

fn normalized([x, y, z]: [f64; 3]) -> [f64; 3] {
    let length = (x * x + y * y + z * z).sqrt();
    [x / length, y / length, z / length]
}

fn icosphere_indexed(subdivisions: u32) -> Indexed {
    // The icosahedron: three golden rectangles.
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<[f64; 3]> = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .into_iter()
    .map(normalized)
    .collect();
    let mut faces = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        // Split every triangle in four; each edge's midpoint is made once and shared.
        let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
        let mut midpoint = |a: usize, b: usize, vertices: &mut Vec<[f64; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (vertices[a], vertices[b]);
                vertices.push(normalized([
                    (p[0] + q[0]) / 2.0,
                    (p[1] + q[1]) / 2.0,
                    (p[2] + q[2]) / 2.0,
                ]));
                vertices.len() - 1
            })
        };
        let mut finer = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = finer;
    }
    Indexed { vertices, faces }
}

/// A unit sphere made of `20 · 4^subdivisions` triangles (a subdivided icosahedron).
pub fn icosphere(subdivisions: u32) -> Mesh {
    icosphere_indexed(subdivisions).into_mesh(format!("builtin:icosphere-{subdivisions}"))
}

/// The cube `[-1, 1]³` with each face cut into `cells × cells` squares of two triangles.
pub fn subdivided_cube(cells: usize) -> Mesh {
    let cells = cells.max(1);
    let coordinate = |step: usize| -1.0 + 2.0 * step as f64 / cells as f64;
    let mut indexed = Indexed {
        vertices: Vec::new(),
        faces: Vec::new(),
    };
    let mut index_of: HashMap<[usize; 3], usize> = HashMap::new();
    // For each axis and side, the two in-face axes (ordered so the face points outwards).
    for axis in 0..3 {
        for side in [0, cells] {
            let (u_axis, v_axis) = if side == 0 {
                ((axis + 2) % 3, (axis + 1) % 3)
            } else {
                ((axis + 1) % 3, (axis + 2) % 3)
            };
            let mut vertex = |u: usize, v: usize, vertices: &mut Vec<[f64; 3]>| {
                let mut grid = [0; 3];
                grid[axis] = side;
                grid[u_axis] = u;
                grid[v_axis] = v;
                *index_of.entry(grid).or_insert_with(|| {
                    vertices.push(grid.map(coordinate));
                    vertices.len() - 1
                })
            };
            for u in 0..cells {
                for v in 0..cells {
                    let a = vertex(u, v, &mut indexed.vertices);
                    let b = vertex(u + 1, v, &mut indexed.vertices);
                    let c = vertex(u + 1, v + 1, &mut indexed.vertices);
                    let d = vertex(u, v + 1, &mut indexed.vertices);
                    indexed.faces.extend([[a, b, c], [a, c, d]]);
                }
            }
        }
    }
    indexed.into_mesh(format!("builtin:cube-{cells}"))
}

/// The default mesh: a lumpy sphere of 20,480 triangles (an icosphere of 5 subdivisions with
/// every vertex pushed in or out by a smooth pattern), so that triangle sizes and densities
/// vary as in a scanned model.
pub fn lumpy_sphere() -> Mesh {
    let mut indexed = icosphere_indexed(5);
    for vertex in &mut indexed.vertices {
        *vertex = lump(*vertex);
    }
    indexed.into_mesh("builtin:lumpy-sphere".into())
}

/// The lumpy sphere's displacement: smooth bumps in and out.
fn lump([x, y, z]: [f64; 3]) -> [f64; 3] {
    let bump = 1.0
        + 0.25 * (5.0 * x).sin() * (4.0 * y).sin() * (3.0 * z + 1.0).sin()
        + 0.1 * (11.0 * x + 7.0 * z).sin();
    [x * bump, y * bump, z * bump]
}

/// A lumpy sphere of about `triangles` triangles, for scaling benchmarks: a latitude-longitude
/// grid (`w` segments around, `h` bands; `2·w·(h − 1)` triangles, fans at the poles) with the
/// lumpy sphere's bumps. Unlike the icosphere its size can be any number, and its triangles
/// are long near the poles and square at the equator.
pub fn lumpy_grid_sphere(triangles: usize) -> Mesh {
    let segments = ((triangles as f64).sqrt().round() as usize).max(3);
    let bands = (triangles / (2 * segments) + 1).max(2);
    let mut indexed = Indexed {
        vertices: vec![lump([0.0, 0.0, 1.0])],
        faces: Vec::with_capacity(2 * segments * (bands - 1)),
    };
    for band in 1..bands {
        let polar = std::f64::consts::PI * band as f64 / bands as f64;
        for segment in 0..segments {
            let azimuth = std::f64::consts::TAU * segment as f64 / segments as f64;
            let point = [
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            ];
            indexed.vertices.push(lump(point));
        }
    }
    indexed.vertices.push(lump([0.0, 0.0, -1.0]));
    let south = indexed.vertices.len() - 1;
    let ring = |band: usize, segment: usize| 1 + (band - 1) * segments + segment % segments;
    for segment in 0..segments {
        indexed
            .faces
            .push([0, ring(1, segment), ring(1, segment + 1)]);
        indexed.faces.push([
            south,
            ring(bands - 1, segment + 1),
            ring(bands - 1, segment),
        ]);
    }
    for band in 1..bands - 1 {
        for segment in 0..segments {
            let (a, b) = (ring(band, segment), ring(band, segment + 1));
            let (c, d) = (ring(band + 1, segment + 1), ring(band + 1, segment));
            indexed.faces.extend([[a, d, c], [a, c, b]]);
        }
    }
    indexed.into_mesh(format!("builtin:lumpy-sphere:{triangles}"))
}

/// The built-in meshes by name, for the CLI's `--mesh builtin:NAME`.
pub fn by_name(name: &str) -> Option<Mesh> {
    if let Some(count) = name.strip_prefix("lumpy-sphere:") {
        let count = count.parse::<usize>().ok()?;
        return (100..=20_000_000)
            .contains(&count)
            .then(|| lumpy_grid_sphere(count));
    }
    match name {
        "lumpy-sphere" => Some(lumpy_sphere()),
        "icosphere" => Some(icosphere(4)),
        "cube" => Some(subdivided_cube(16)),
        "icosphere-far" => Some(icosphere(4).translated(FAR_AWAY)),
        "cube-far" => Some(subdivided_cube(16).translated(FAR_AWAY)),
        _ => None,
    }
}

/// Where the `-far` meshes are moved: far enough from the origin that f32 keeps only about
/// three decimal digits of a unit-sized mesh's coordinates.
pub const FAR_AWAY: [f64; 3] = [1.0e4, -3.0e4, 2.0e4];

/// The names [`by_name`] knows.
pub const BUILTIN_NAMES: [&str; 6] = [
    "lumpy-sphere",
    "lumpy-sphere:N (about N triangles, 100 to 20000000)",
    "icosphere",
    "cube",
    "icosphere-far",
    "cube-far",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(icosphere(2).triangles.len(), 320);
        assert_eq!(subdivided_cube(3).triangles.len(), 6 * 9 * 2);
        assert_eq!(lumpy_sphere().triangles.len(), 20_480);
        for target in [100, 10_000, 100_000, 1_000_000] {
            let count = lumpy_grid_sphere(target).triangles.len();
            assert!(count.abs_diff(target) * 100 <= target, "{target}: {count}");
        }
        assert!(by_name("lumpy-sphere:99").is_none());
        assert!(by_name("lumpy-sphere:x").is_none());
    }
}
