//! Wavefront OBJ meshes, read with tobj.
//!
//! Triangle numbering (the CLI's contract): triangles are numbered from 0 in file order:
//! models in order, faces in order, each polygon fan-triangulated in order (tobj's
//! `triangulate`). Before tobj reads the file, a line scan checks what tobj would accept
//! silently or report without a place: malformed or non-finite coordinates and face indices
//! out of range, each reported with its line.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::BufRead;

use crate::Mesh;
use crate::error::{LoadError, read_text};

/// Reads an OBJ file.
pub fn load_obj(path: &str) -> Result<Mesh, LoadError> {
    let text = read_text(path)?;
    parse_obj(&text, path)
}

/// Parses OBJ text; `path` names it in errors.
pub fn parse_obj(text: &str, path: &str) -> Result<Mesh, LoadError> {
    parse_obj_with_progress(text, path, &|_| {})
}

/// Parses OBJ text like [`parse_obj`], telling `progress` how far it got (per mille) now and
/// then: half for the line check, half for tobj's pass, so a large file's reading can be shown.
pub fn parse_obj_with_progress(
    text: &str,
    path: &str,
    progress: &dyn Fn(u32),
) -> Result<Mesh, LoadError> {
    let total = text.len().max(1) as u64;
    let face_count = check_lines(text, path, &|done| {
        progress((done as u64 * 500 / total) as u32);
    })?;
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are irrelevant here; `mtllib` lines are answered with "no such file". tobj
    // names no line in its errors, but it stops at the line it cannot read: the reader
    // counts the lines tobj took.
    let mut reader = LineCounter::new(text.as_bytes());
    reader.progress = Some((progress, total));
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|error| {
        LoadError::at_line(
            path,
            reader.current_line(),
            format!("not a valid OBJ line: {error}"),
        )
    })?;
    let mut triangles = Vec::new();
    for model in &models {
        let positions = &model.mesh.positions;
        let corner = |index: u32| {
            let at = index as usize * 3;
            [positions[at], positions[at + 1], positions[at + 2]]
        };
        for face in model.mesh.indices.chunks_exact(3) {
            triangles.push([corner(face[0]), corner(face[1]), corner(face[2])]);
        }
    }
    if face_count == 0 || triangles.is_empty() {
        return Err(LoadError::in_file(path, "the file has no faces"));
    }
    Ok(Mesh {
        name: path.to_owned(),
        triangles,
    })
}

/// Checks every `v` and `f` line; returns the number of faces. `done` hears how many bytes
/// are checked, now and then.
fn check_lines(text: &str, path: &str, done: &dyn Fn(usize)) -> Result<usize, LoadError> {
    let total_positions = text
        .lines()
        .filter(|line| line.split_whitespace().next() == Some("v"))
        .count();
    let mut counts = [0usize; 3]; // positions, texture coordinates, normals so far
    let mut faces = 0;
    let mut checked = 0;
    for (line_index, line) in text.lines().enumerate() {
        let line_number = line_index + 1;
        checked += line.len() + 1;
        if line_index.is_multiple_of(65_536) {
            done(checked);
        }
        let fail = |problem: String| LoadError::at_line(path, line_number, problem);
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let values: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                counts[0] += 1;
                if !matches!(values.len(), 3 | 4 | 6) {
                    return Err(fail(format!(
                        "a vertex needs 3 coordinates (optionally w, or r g b), found {}",
                        accelviz_core::format::counted(values.len(), "value", "values")
                    )));
                }
                let numbers = parse_numbers(&values, &fail)?;
                let w = if values.len() == 4 { numbers[3] } else { 1.0 };
                if w == 0.0 {
                    return Err(fail("the vertex weight w is zero".into()));
                }
                if numbers[..3].iter().any(|x| !(x / w).is_finite()) {
                    return Err(fail(format!(
                        "vertex coordinate is not finite (NaN or infinity): {}",
                        values[..3].join(" ")
                    )));
                }
            }
            "vt" => {
                counts[1] += 1;
                // tobj reads u and v; w is optional.
                if !matches!(values.len(), 2 | 3) {
                    return Err(fail(format!(
                        "a texture coordinate needs 2 numbers (u v, optionally w), found {}",
                        values.len()
                    )));
                }
                parse_numbers(&values, &fail)?;
            }
            "vn" => {
                counts[2] += 1;
                if values.len() != 3 {
                    return Err(fail(format!(
                        "a normal needs 3 numbers, found {}",
                        values.len()
                    )));
                }
                parse_numbers(&values, &fail)?;
            }
            "f" => {
                faces += 1;
                if values.len() < 3 {
                    return Err(fail(format!(
                        "a face needs at least 3 vertices, found {}",
                        values.len()
                    )));
                }
                for vertex in &values {
                    check_face_vertex(vertex, &counts, total_positions, &fail)?;
                }
            }
            _ => {}
        }
    }
    Ok(faces)
}

/// A reader that counts the lines its user has consumed, to name the line a parser that
/// reports no place stopped at.
struct LineCounter<'a> {
    rest: &'a [u8],
    complete_lines: usize,
    inside_line: bool,
    /// Where to report how far tobj has read (per mille, the second half), and the text's size.
    progress: Option<(&'a dyn Fn(u32), u64)>,
}

impl<'a> LineCounter<'a> {
    fn new(text: &'a [u8]) -> Self {
        Self {
            rest: text,
            complete_lines: 0,
            inside_line: false,
            progress: None,
        }
    }

    /// The number (from 1) of the line the last byte consumed belongs to.
    fn current_line(&self) -> usize {
        self.complete_lines + usize::from(self.inside_line || self.complete_lines == 0)
    }
}

impl std::io::Read for LineCounter<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let count = out.len().min(self.rest.len());
        out[..count].copy_from_slice(&self.rest[..count]);
        self.consume(count);
        Ok(count)
    }
}

impl BufRead for LineCounter<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        Ok(self.rest)
    }

    fn consume(&mut self, amount: usize) {
        let (taken, rest) = self.rest.split_at(amount.min(self.rest.len()));
        self.complete_lines += taken.iter().filter(|&&byte| byte == b'\n').count();
        if let Some(&last) = taken.last() {
            self.inside_line = last != b'\n';
        }
        self.rest = rest;
        if let Some((progress, total)) = self.progress
            && self.complete_lines.is_multiple_of(65_536)
        {
            let done = total - self.rest.len() as u64;
            progress(500 + (done * 500 / total) as u32);
        }
    }
}

fn parse_numbers(
    values: &[&str],
    fail: &impl Fn(String) -> LoadError,
) -> Result<Vec<f64>, LoadError> {
    values
        .iter()
        .map(|value| {
            value
                .parse::<f64>()
                .map_err(|_| fail(format!("'{value}' is not a number")))
        })
        .collect()
}

/// Checks `v`, `v/vt`, `v//vn` or `v/vt/vn`. Negative indices count back from the last
/// element read so far; positive ones may refer to any vertex in the file.
fn check_face_vertex(
    vertex: &str,
    counts: &[usize; 3],
    total_positions: usize,
    fail: &impl Fn(String) -> LoadError,
) -> Result<(), LoadError> {
    let names = [
        ("vertex", "vertices"),
        ("texture coordinate", "texture coordinates"),
        ("normal", "normals"),
    ];
    for (slot, part) in vertex.split('/').enumerate() {
        if slot > 2 {
            return Err(fail(format!("'{vertex}' has more than three indices")));
        }
        if part.is_empty() && slot > 0 {
            continue;
        }
        let index: i64 = part
            .parse()
            .map_err(|_| fail(format!("'{vertex}' is not a face vertex (index '{part}')")))?;
        let available = if slot == 0 {
            total_positions
        } else {
            counts[slot]
        };
        let in_range = match index {
            0 => false,
            index if index > 0 => index as usize <= available,
            index => index.unsigned_abs() as usize <= counts[slot],
        };
        if !in_range {
            return Err(fail(format!(
                "{} index {index} is out of range (the file has {})",
                names[slot].0,
                accelviz_core::format::counted(available, names[slot].0, names[slot].1)
            )));
        }
    }
    Ok(())
}

/// `mesh` as OBJ text: each distinct corner one `v` line, each triangle one `f` line, in
/// order, so [`parse_obj`] reads the same triangles back.
pub fn obj_text(mesh: &Mesh) -> String {
    let mut text = String::with_capacity(mesh.triangles.len() * 60);
    let mut numbers: HashMap<[u64; 3], usize> = HashMap::new();
    let mut faces = String::with_capacity(mesh.triangles.len() * 30);
    for triangle in &mesh.triangles {
        faces.push('f');
        for corner in triangle {
            let next = numbers.len() + 1;
            let number = *numbers.entry(corner.map(f64::to_bits)).or_insert_with(|| {
                let [x, y, z] = corner;
                let _ = writeln!(text, "v {x} {y} {z}");
                next
            });
            let _ = write!(faces, " {number}");
        }
        faces.push('\n');
    }
    text.push_str(&faces);
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_are_fan_triangulated_in_order() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3\n";
        let mesh = parse_obj(text, "quad.obj").unwrap();
        assert_eq!(mesh.triangles.len(), 3);
        assert_eq!(
            mesh.triangles[0],
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
        );
        assert_eq!(
            mesh.triangles[1],
            [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
        );
    }

    #[test]
    fn written_meshes_read_back_the_same() {
        let mesh = crate::builtin::icosphere(2);
        let text = obj_text(&mesh);
        assert_eq!(
            text.lines().filter(|line| line.starts_with("v ")).count(),
            162
        );
        let read = parse_obj(&text, &mesh.name).unwrap();
        assert_eq!(read.triangles, mesh.triangles);
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            ("v 0 0 0\nv 1 0\n", "x.obj:2: a vertex needs 3 coordinates"),
            (
                "v 0 0 0\nv 1 nan 0\n",
                "x.obj:2: vertex coordinate is not finite",
            ),
            (
                "v 0 0 0\nv 1 inf 0\n",
                "x.obj:2: vertex coordinate is not finite",
            ),
            ("v 0 0 0\nv 1 x 0\n", "x.obj:2: 'x' is not a number"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n",
                "x.obj:5: vertex index 4 is out of range",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
                "x.obj:4: vertex index -4 is out of range",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
                "x.obj:4: a face needs at least 3 vertices",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1\n",
                "x.obj:4: texture coordinate index 1",
            ),
            ("v 0 0 0\n", "x.obj: the file has no faces"),
            (
                "v 0 0 0\nvn 0 1\nv 1 0 0\n",
                "x.obj:2: a normal needs 3 numbers, found 2",
            ),
            ("v 0 0 0\nvt 0.5\n", "x.obj:2: a texture coordinate needs 2"),
            ("v 0 0 0\nvn 0 1 x\n", "x.obj:2: 'x' is not a number"),
            // What only tobj rejects still names its line.
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\n# ok\nusemtl\nf 1 2 3\n",
                "x.obj:5: not a valid OBJ line",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl",
                "x.obj:4: not a valid OBJ line",
            ),
        ];
        for (text, expected) in cases {
            let message = parse_obj(text, "x.obj").unwrap_err().to_string();
            assert!(
                message.starts_with(expected),
                "{message:?} should start with {expected:?}"
            );
        }
    }
}
