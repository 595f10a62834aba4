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

/// A built-in mesh: its name (`--mesh builtin:NAME` in the CLI, the mesh list in the app),
/// what it is for, and how to make it.
pub struct Builtin {
    /// The name after `builtin:`.
    pub name: &'static str,
    /// One line saying what the mesh is and why it is there.
    pub about: &'static str,
    /// Makes the mesh.
    pub make: fn() -> Mesh,
}

/// Every built-in mesh of a fixed size, once. [`by_name`] also knows `lumpy-sphere:N`.
pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "lumpy-sphere",
        about: "20,480 triangles of varying size: the default mesh of the benchmarks",
        make: lumpy_sphere,
    },
    Builtin {
        name: "icosphere",
        about: "5,120 equal triangles on a unit sphere",
        make: || icosphere(4),
    },
    Builtin {
        name: "cube",
        about: "a cube of 3,072 triangles on an axis-aligned grid (flat boxes, planes on slabs)",
        make: || subdivided_cube(16),
    },
    Builtin {
        name: "box-room",
        about: "an open room with two blocks and a ball: large flat walls beside small parts",
        make: box_room,
    },
    Builtin {
        name: "teapot",
        about: "a teapot of 3,648 triangles (body, lid, spout and handle)",
        make: teapot,
    },
    Builtin {
        name: "teapot-stadium",
        about: "the teapot in a stadium (Haines): a small detailed object in a large sparse scene",
        make: teapot_in_stadium,
    },
    Builtin {
        name: "soup",
        about: "20,000 small triangles spread evenly through a cube: a uniform grid at its best",
        make: soup,
    },
    Builtin {
        name: "icosphere-far",
        about: "the icosphere moved far from the origin, where f32 keeps three decimal digits",
        make: || icosphere(4).translated(FAR_AWAY),
    },
    Builtin {
        name: "cube-far",
        about: "the cube moved far from the origin",
        make: || subdivided_cube(16).translated(FAR_AWAY),
    },
];

/// The built-in meshes by name, for the CLI's `--mesh builtin:NAME`: an entry of
/// [`BUILTINS`], or `lumpy-sphere:N` (about N triangles).
pub fn by_name(name: &str) -> Option<Mesh> {
    if let Some(count) = name.strip_prefix("lumpy-sphere:") {
        let count = count.parse::<usize>().ok()?;
        return (100..=20_000_000)
            .contains(&count)
            .then(|| lumpy_grid_sphere(count));
    }
    BUILTINS
        .iter()
        .find(|builtin| builtin.name == name)
        .map(|builtin| (builtin.make)())
}

/// The mesh `spec` names as the command line names one: `builtin:NAME` (see [`by_name`]),
/// or the path of an OBJ file.
pub fn load_mesh(spec: &str) -> Result<Mesh, crate::LoadError> {
    match spec.strip_prefix("builtin:") {
        Some(name) => by_name(name).ok_or_else(|| crate::LoadError::UnknownBuiltin {
            name: name.to_owned(),
        }),
        None => crate::obj::load_obj(spec),
    }
}

/// The entry of [`BUILTINS`] that `spec` (`builtin:NAME`) names, or why there is none (the
/// message lists them).
pub fn named(spec: &str) -> Result<&'static Builtin, String> {
    spec.strip_prefix("builtin:")
        .and_then(|name| BUILTINS.iter().find(|builtin| builtin.name == name))
        .ok_or_else(|| {
            format!(
                "'{spec}' is not a built-in mesh (builtin:{})",
                BUILTINS
                    .iter()
                    .map(|builtin| builtin.name)
                    .collect::<Vec<_>>()
                    .join(", builtin:")
            )
        })
}

/// The names [`by_name`] knows, for messages.
pub fn names() -> Vec<String> {
    let mut names: Vec<String> = BUILTINS.iter().map(|b| b.name.to_owned()).collect();
    names.insert(
        1,
        "lumpy-sphere:N (about N triangles, 100 to 20000000)".to_owned(),
    );
    names
}

/// Where the `-far` meshes are moved: far enough from the origin that f32 keeps only about
/// three decimal digits of a unit-sized mesh's coordinates.
pub const FAR_AWAY: [f64; 3] = [1.0e4, -3.0e4, 2.0e4];

impl Indexed {
    fn new() -> Self {
        Self {
            vertices: Vec::new(),
            faces: Vec::new(),
        }
    }

    fn vertex(&mut self, point: [f64; 3]) -> usize {
        self.vertices.push(point);
        self.vertices.len() - 1
    }

    /// The quad `a b c d` (in order around it) as two triangles.
    fn quad(&mut self, [a, b, c, d]: [usize; 4]) {
        self.faces.extend([[a, b, c], [a, c, d]]);
    }

    /// Rings of points joined band by band: `rings[k]` and `rings[k + 1]` have the same
    /// length (closed loops), or one of them is a single point (a pole, joined as a fan).
    fn join_rings(&mut self, rings: &[Vec<usize>]) {
        for pair in rings.windows(2) {
            let (lower, upper) = (&pair[0], &pair[1]);
            let count = lower.len().max(upper.len());
            let at =
                |ring: &Vec<usize>, k: usize| ring[if ring.len() == 1 { 0 } else { k % count }];
            for k in 0..count {
                let (a, b) = (at(lower, k), at(lower, k + 1));
                let (c, d) = (at(upper, k + 1), at(upper, k));
                if lower.len() == 1 {
                    self.faces.push([a, c, d]);
                } else if upper.len() == 1 {
                    self.faces.push([a, b, c]);
                } else {
                    self.quad([a, b, c, d]);
                }
            }
        }
    }

    /// A surface of revolution about the y axis through `centre`: `profile` is
    /// (radius, height) from bottom to top; a radius of 0 is a pole.
    fn revolve(&mut self, profile: &[[f64; 2]], segments: usize, centre: [f64; 3]) {
        let rings: Vec<Vec<usize>> = profile
            .iter()
            .map(|&[radius, height]| {
                if radius == 0.0 {
                    return vec![self.vertex([centre[0], centre[1] + height, centre[2]])];
                }
                (0..segments)
                    .map(|k| {
                        let angle = std::f64::consts::TAU * k as f64 / segments as f64;
                        self.vertex([
                            centre[0] + radius * angle.cos(),
                            centre[1] + height,
                            centre[2] - radius * angle.sin(),
                        ])
                    })
                    .collect()
            })
            .collect();
        self.join_rings(&rings);
    }

    /// A tube around a curve in the xy plane: `centre(s)` and `radius(s)` for s in [0, 1],
    /// open at both ends.
    fn tube(
        &mut self,
        centre: impl Fn(f64) -> [f64; 3],
        radius: impl Fn(f64) -> f64,
        rings: usize,
        segments: usize,
    ) {
        let ring_list: Vec<Vec<usize>> = (0..=rings)
            .map(|ring| {
                let s = ring as f64 / rings as f64;
                let here = centre(s);
                let (before, after) = (centre((s - 1e-3).max(0.0)), centre((s + 1e-3).min(1.0)));
                let tangent = normalized([after[0] - before[0], after[1] - before[1], 0.0]);
                // The curve lies in the xy plane: z and the in-plane normal span each ring.
                let normal = [-tangent[1], tangent[0], 0.0];
                let r = radius(s);
                (0..segments)
                    .map(|k| {
                        let angle = std::f64::consts::TAU * k as f64 / segments as f64;
                        let (cos, sin) = (angle.cos() * r, angle.sin() * r);
                        self.vertex([
                            here[0] + normal[0] * cos,
                            here[1] + normal[1] * cos,
                            here[2] + sin,
                        ])
                    })
                    .collect()
            })
            .collect();
        self.join_rings(&ring_list);
    }

    /// The box `min`..`max` turned by `angle` about the vertical line through its centre,
    /// 12 triangles.
    fn block(&mut self, min: [f64; 3], max: [f64; 3], angle: f64) {
        let (cx, cz) = ((min[0] + max[0]) / 2.0, (min[2] + max[2]) / 2.0);
        let (cos, sin) = (angle.cos(), angle.sin());
        let corner = |bits: usize| {
            let x = if bits & 1 == 0 { min[0] } else { max[0] } - cx;
            let y = if bits & 2 == 0 { min[1] } else { max[1] };
            let z = if bits & 4 == 0 { min[2] } else { max[2] } - cz;
            [cx + cos * x - sin * z, y, cz + sin * x + cos * z]
        };
        let ids: Vec<usize> = (0..8).map(|bits| self.vertex(corner(bits))).collect();
        for [a, b, c, d] in [
            // The six faces, each with its corners in order around it.
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            self.quad([ids[a], ids[b], ids[c], ids[d]]);
        }
    }

    /// A flat rectangle `corner + u·i/cells + v·j/cells`, cut into `cells × cells` squares.
    fn grid(&mut self, corner: [f64; 3], u: [f64; 3], v: [f64; 3], cells: usize) {
        let point = |i: usize, j: usize| {
            let (a, b) = (i as f64 / cells as f64, j as f64 / cells as f64);
            [0, 1, 2].map(|k| corner[k] + u[k] * a + v[k] * b)
        };
        let first = self.vertices.len();
        for j in 0..=cells {
            for i in 0..=cells {
                self.vertices.push(point(i, j));
            }
        }
        let id = |i: usize, j: usize| first + j * (cells + 1) + i;
        for j in 0..cells {
            for i in 0..cells {
                self.quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
}

/// A teapot standing on y = 0 at `base`, about 1.7 high and 3.5 wide (spout to handle):
/// a body and lid turned about the vertical axis, a spout and a handle swept along curves.
/// Made here (not the Utah teapot's patches) so that it needs no data file.
fn add_teapot(mesh: &mut Indexed, base: [f64; 3]) {
    // The body bulges out and narrows to the rim; the lid rises to a knob.
    let mut profile = vec![[0.0, 0.0]];
    for k in 0..=16 {
        let s = k as f64 / 16.0;
        let radius = 0.7 + 0.5 * (std::f64::consts::PI * (0.1 + 0.8 * s)).sin() - 0.12 * s;
        profile.push([radius, 1.3 * s]);
    }
    profile.extend([
        [0.68, 1.33],
        [0.55, 1.42],
        [0.35, 1.47],
        [0.14, 1.49],
        [0.11, 1.56],
        [0.17, 1.63],
        [0.12, 1.69],
        [0.0, 1.71],
    ]);
    mesh.revolve(&profile, 48, base);
    let at = |[x, y]: [f64; 2]| [base[0] + x, base[1] + y, base[2]];
    let bezier = |points: &[[f64; 2]], s: f64| {
        // de Casteljau: repeated interpolation of the control polygon.
        let mut points = points.to_vec();
        while points.len() > 1 {
            points = points
                .windows(2)
                .map(|pair| [0, 1].map(|k| pair[0][k] + (pair[1][k] - pair[0][k]) * s))
                .collect();
        }
        points[0]
    };
    let spout = [[0.75, 0.45], [1.55, 0.5], [1.75, 1.3]];
    mesh.tube(|s| at(bezier(&spout, s)), |s| 0.22 - 0.13 * s, 12, 24);
    let handle = [[-0.95, 1.05], [-1.85, 1.2], [-1.65, 0.3], [-0.98, 0.38]];
    mesh.tube(|s| at(bezier(&handle, s)), |_| 0.075, 24, 16);
}

/// The teapot alone.
pub fn teapot() -> Mesh {
    let mut mesh = Indexed::new();
    add_teapot(&mut mesh, [0.0, 0.0, 0.0]);
    mesh.into_mesh("builtin:teapot".into())
}

/// Haines' "teapot in a stadium": the teapot (1.7 high) on the centre spot of a field
/// 120 × 80 wide, ringed by 16 tiers of stands. Most of the space is empty and most of the
/// triangles are small: a uniform grid fails here, and a good hierarchy must not.
pub fn teapot_in_stadium() -> Mesh {
    let mut mesh = Indexed::new();
    add_teapot(&mut mesh, [0.0, 0.0, 0.0]);
    mesh.grid([-70.0, 0.0, 50.0], [140.0, 0.0, 0.0], [0.0, 0.0, -100.0], 4);
    let segments = 128;
    let tiers = 16;
    let point = |tier: f64, height: f64, k: usize| {
        let angle = std::f64::consts::TAU * k as f64 / segments as f64;
        [
            (62.0 + 1.5 * tier) * angle.cos(),
            height,
            -(42.0 + 1.5 * tier) * angle.sin(),
        ]
    };
    for tier in 0..tiers {
        let (inner, outer) = (tier as f64, tier as f64 + 1.0);
        let (low, high) = (tier as f64, tier as f64 + 1.0);
        // Each tier: a riser up from the step below, then a tread out to the next riser.
        let rings: Vec<Vec<usize>> = [(inner, low), (inner, high), (outer, high)]
            .iter()
            .map(|&(radius, height)| {
                (0..segments)
                    .map(|k| mesh.vertex(point(radius, height, k)))
                    .collect()
            })
            .collect();
        mesh.join_rings(&rings);
    }
    // Four floodlight masts at the corners.
    for [x, z] in [[-80.0, -60.0], [80.0, -60.0], [-80.0, 60.0], [80.0, 60.0]] {
        mesh.block([x - 1.0, 0.0, z - 1.0], [x + 1.0, 40.0, z + 1.0], 0.0);
        mesh.block([x - 4.0, 40.0, z - 1.0], [x + 4.0, 44.0, z + 1.0], 0.0);
    }
    mesh.into_mesh("builtin:teapot-stadium".into())
}

/// An open room (floor, ceiling, back and side walls; the front is open towards +z, like
/// the Cornell box) holding a tall block, a short block with a ball on it and a lamp.
pub fn box_room() -> Mesh {
    let mut mesh = Indexed::new();
    let cells = 10;
    mesh.grid([-5.0, 0.0, 5.0], [10.0, 0.0, 0.0], [0.0, 0.0, -10.0], cells); // floor
    mesh.grid([-5.0, 6.0, -5.0], [10.0, 0.0, 0.0], [0.0, 0.0, 10.0], cells); // ceiling
    mesh.grid([-5.0, 0.0, -5.0], [10.0, 0.0, 0.0], [0.0, 6.0, 0.0], cells); // back
    mesh.grid([-5.0, 0.0, 5.0], [0.0, 0.0, -10.0], [0.0, 6.0, 0.0], cells); // left
    mesh.grid([5.0, 0.0, -5.0], [0.0, 0.0, 10.0], [0.0, 6.0, 0.0], cells); // right
    mesh.block([-3.2, 0.0, -3.0], [-0.8, 3.6, -0.6], 0.3);
    mesh.block([0.8, 0.0, -0.5], [3.2, 1.6, 1.9], -0.3);
    mesh.block([-1.0, 5.9, -1.0], [1.0, 6.0, 1.0], 0.0);
    let ball = icosphere_indexed(3);
    let first = mesh.vertices.len();
    mesh.vertices.extend(
        ball.vertices
            .iter()
            .map(|&[x, y, z]| [2.0 + 0.9 * x, 2.5 + 0.9 * y, 0.7 + 0.9 * z]),
    );
    mesh.faces.extend(
        ball.faces
            .iter()
            .map(|face| face.map(|corner| first + corner)),
    );
    mesh.into_mesh("builtin:box-room".into())
}

/// 20,000 small triangles, each within 0.02 of a point drawn evenly from the unit cube
/// (seeded): every part of the box holds about as much as every other, the scene a uniform
/// grid suits best (Cleary & Wyvill 1988's analysis assumes it), against the teapot in a
/// stadium, where it suits worst.
pub fn soup() -> Mesh {
    let mut rng = crate::rng::SplitMix64::new(0x50_0b);
    let triangles = (0..20_000)
        .map(|_| {
            let center = [rng.next_f64(), rng.next_f64(), rng.next_f64()];
            std::array::from_fn(|_| {
                let offset = rng.unit_vector();
                std::array::from_fn(|axis| center[axis] + 0.02 * offset[axis])
            })
        })
        .collect();
    Mesh {
        name: "builtin:soup".to_owned(),
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_is_named_by_builtin_name_or_path_and_an_unknown_one_is_listed() {
        assert_eq!(load_mesh("builtin:cube").ok(), by_name("cube"));
        let unknown = load_mesh("builtin:nope").unwrap_err().to_string();
        assert!(
            unknown.starts_with("unknown built-in mesh 'nope'; built-in meshes are: ")
                && unknown.contains("teapot"),
            "{unknown}"
        );
        let missing = load_mesh("/no/such.obj").unwrap_err().to_string();
        assert!(
            missing.starts_with("/no/such.obj: cannot read"),
            "{missing}"
        );
    }

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
        assert_eq!(teapot().triangles.len(), 3648);
    }

    #[test]
    fn every_builtin_is_made_finite_and_named() {
        for builtin in BUILTINS {
            let mesh = by_name(builtin.name).expect(builtin.name);
            assert!(!mesh.triangles.is_empty(), "{}", builtin.name);
            assert!(
                mesh.triangles
                    .iter()
                    .flatten()
                    .flatten()
                    .all(|x| x.is_finite()),
                "{}",
                builtin.name
            );
            // No triangle without area: each would be a primitive no ray can hit.
            let degenerate = mesh
                .triangles
                .iter()
                .filter(|[a, b, c]| {
                    let (u, v) = (
                        [0, 1, 2].map(|k| b[k] - a[k]),
                        [0, 1, 2].map(|k| c[k] - a[k]),
                    );
                    let cross = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    cross.iter().map(|x| x * x).sum::<f64>() < 1e-20
                })
                .count();
            assert_eq!(degenerate, 0, "{}", builtin.name);
        }
        assert!(
            names()
                .iter()
                .any(|name| name.starts_with("lumpy-sphere:N"))
        );
    }
}
