//! Where the time goes: the cost of every pixel's ray.
//!
//! Each pixel's ray ([`Camera::pixel_ray`], the rays `bench --camera` traces) is traced by a
//! structure's own traversal with the [`Counters`] observer, and the counts are kept per
//! pixel: nodes visited, box tests, primitive tests. Rays go one at a time, or in packets of
//! square tiles of pixels (what a renderer does with camera rays; each ray's counters hear
//! what the packet traversal did for that ray). Nothing here is a second traversal:
//! the caller passes the one it measures, so a heat map's totals are the benchmark's counts.
//! RRA (AMD's Radeon Raytracing Analyzer) shows the same counters per pixel; the palettes
//! here are sequential (viridis-like: dark to light, colour-blind safe) and diverging (blue,
//! near-white, orange) for differences.

use std::ops::Range;
use std::sync::Mutex;

use crate::camera::Camera;
use crate::math::Vector3;
use crate::observer::Counters;
use crate::ray::Ray;

/// What one pixel's ray cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelCost {
    /// Nodes entered.
    pub nodes: u32,
    /// Ray/box slab tests.
    pub boxes: u32,
    /// Ray/primitive tests.
    pub prims: u32,
}

impl PixelCost {
    fn of(counters: &Counters) -> Self {
        let narrow = |count: u64| u32::try_from(count).unwrap_or(u32::MAX);
        Self {
            nodes: narrow(counters.nodes_visited),
            boxes: narrow(counters.box_tests),
            prims: narrow(counters.primitive_tests),
        }
    }
}

/// Which count a heat map shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Counter {
    /// Nodes entered.
    #[default]
    Nodes,
    /// Ray/box slab tests.
    Boxes,
    /// Ray/primitive tests.
    Prims,
}

impl Counter {
    /// Every counter, in the order the CLI's CSV writes them.
    pub const ALL: [Counter; 3] = [Counter::Nodes, Counter::Boxes, Counter::Prims];

    /// The name the CLI uses (`--counter nodes|boxes|prims`).
    pub fn name(self) -> &'static str {
        match self {
            Counter::Nodes => "nodes",
            Counter::Boxes => "boxes",
            Counter::Prims => "prims",
        }
    }

    /// What it counts, for people.
    pub fn label(self) -> &'static str {
        match self {
            Counter::Nodes => "nodes visited",
            Counter::Boxes => "box tests",
            Counter::Prims => "primitive tests",
        }
    }

    /// Its value in `cost`.
    pub fn of(self, cost: &PixelCost) -> u32 {
        match self {
            Counter::Nodes => cost.nodes,
            Counter::Boxes => cost.boxes,
            Counter::Prims => cost.prims,
        }
    }
}

/// The sum, largest value and mean of one counter over a heat map.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// Sum over all pixels.
    pub total: u64,
    /// The largest pixel.
    pub max: u32,
    /// `total / pixels`.
    pub mean: f64,
}

/// The cost of every pixel of a `width × height` image, row by row from the top left.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HeatMap {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// `width × height` costs, row by row from the top left.
    pub pixels: Vec<PixelCost>,
}

/// Rows traced per piece of work: small enough to share the image fairly between threads
/// (its costly middle and its empty edges), large enough to make the sharing cheap.
const ROWS_PER_PIECE: usize = 4;

impl HeatMap {
    /// A map of zeros.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            pixels: vec![PixelCost::default(); width * height],
        }
    }

    /// Traces every pixel of the image with `trace` (a structure's traversal, given a ray,
    /// the thread's scratch `S`, e.g. its traversal stacks, and the counters to add to) on
    /// `threads` threads (1: on this one, which is what the browser can do).
    pub fn compute<V: Vector3, S: Default>(
        camera: &Camera,
        width: usize,
        height: usize,
        threads: usize,
        trace: &(impl Fn(&Ray<V>, &mut S, &mut Counters) + Sync),
    ) -> Self {
        Self::compute_in_packets(
            camera,
            width,
            height,
            threads,
            1,
            &|rays: &[Ray<V>], scratch: &mut S, counters: &mut [Counters]| {
                trace(&rays[0], scratch, &mut counters[0]);
            },
        )
    }

    /// [`HeatMap::compute`] with the rays of each `tile × tile` block of pixels traced
    /// together by `trace` (a packet traversal, given the rays row by row and one set of
    /// counters each); `tile` 1 gives one ray at a time. (A packet traversal takes at most
    /// [`MAX_PACKET`](crate::bvh::MAX_PACKET) rays: tiles of 8 × 8.)
    pub fn compute_in_packets<V: Vector3, S: Default>(
        camera: &Camera,
        width: usize,
        height: usize,
        threads: usize,
        tile: usize,
        trace: &(impl Fn(&[Ray<V>], &mut S, &mut [Counters]) + Sync),
    ) -> Self {
        let mut map = Self::new(width, height);
        if width == 0 || height == 0 {
            return map;
        }
        // Pieces of whole tiles.
        let tile = tile.max(1);
        let rows_per_piece = tile * ROWS_PER_PIECE.div_ceil(tile);
        let pieces = Mutex::new(map.pixels.chunks_mut(width * rows_per_piece).enumerate());
        let work = || {
            let mut scratch = S::default();
            loop {
                let next = match pieces.lock() {
                    Ok(mut pieces) => pieces.next(),
                    Err(_) => None,
                };
                let Some((piece, out)) = next else { break };
                trace_rows_in_packets(
                    camera,
                    width,
                    height,
                    piece * rows_per_piece,
                    out,
                    tile,
                    |rays, counters| trace(rays, &mut scratch, counters),
                );
            }
        };
        if threads <= 1 {
            work();
        } else {
            std::thread::scope(|scope| {
                for _ in 0..threads {
                    scope.spawn(work);
                }
            });
        }
        map
    }

    /// Traces the rows `rows` into this map (the browser does a few rows a frame).
    pub fn trace_rows<V: Vector3>(
        &mut self,
        camera: &Camera,
        rows: Range<usize>,
        trace: impl FnMut(&Ray<V>, &mut Counters),
    ) {
        let rows = rows.start.min(self.height)..rows.end.min(self.height);
        let out = &mut self.pixels[rows.start * self.width..rows.end * self.width];
        trace_rows(camera, self.width, self.height, rows.start, out, trace);
    }

    /// One counter's sum, maximum and mean.
    pub fn summary(&self, counter: Counter) -> Summary {
        let values = self.pixels.iter().map(|cost| counter.of(cost));
        let total: u64 = values.clone().map(u64::from).sum();
        Summary {
            total,
            max: values.max().unwrap_or(0),
            mean: total as f64 / self.pixels.len().max(1) as f64,
        }
    }

    /// The cost at pixel `(column, row)`, if it is in the image.
    pub fn at(&self, column: usize, row: usize) -> Option<PixelCost> {
        (column < self.width && row < self.height).then(|| self.pixels[row * self.width + column])
    }

    /// One counter as colours (RGBA, row by row): 0 is the palette's darkest colour and
    /// `scale_max` (and above) its lightest.
    pub fn colors(&self, counter: Counter, scale_max: u32) -> Vec<[u8; 4]> {
        let scale = f64::from(scale_max.max(1));
        self.pixels
            .iter()
            .map(|cost| {
                let [r, g, b] = sequential(f64::from(counter.of(cost)) / scale);
                [r, g, b, 255]
            })
            .collect()
    }

    /// This map minus `other`, one counter, per pixel (the maps must be the same size).
    pub fn difference(&self, other: &HeatMap, counter: Counter) -> Vec<i64> {
        self.pixels
            .iter()
            .zip(&other.pixels)
            .map(|(a, b)| i64::from(counter.of(a)) - i64::from(counter.of(b)))
            .collect()
    }
}

/// Differences as colours (RGBA): negative blue, zero near-white, positive orange, full
/// colour at `±scale` (and beyond).
pub fn difference_colors(differences: &[i64], scale: u64) -> Vec<[u8; 4]> {
    difference_colors_on(differences, scale, false)
}

/// [`difference_colors`] for a view on a dark background (`dark`): the no-difference middle
/// dark too ([`diverging_on`]), so a map that mostly does not differ is no glaring white panel.
pub fn difference_colors_on(differences: &[i64], scale: u64, dark: bool) -> Vec<[u8; 4]> {
    let scale = scale.max(1) as f64;
    differences
        .iter()
        .map(|&difference| {
            let [r, g, b] = diverging_on(difference as f64 / scale, dark);
            [r, g, b, 255]
        })
        .collect()
}

/// Traces the pixels of rows `first_row..` of a `width × height` image into `out` (whole
/// rows of `width`), with `trace` adding each ray's steps to its counters: a piece of a heat
/// map, for callers that share the rows out themselves (the app, a band at a time).
pub fn trace_rows<V: Vector3>(
    camera: &Camera,
    width: usize,
    height: usize,
    first_row: usize,
    out: &mut [PixelCost],
    mut trace: impl FnMut(&Ray<V>, &mut Counters),
) {
    trace_rows_in_packets(
        camera,
        width,
        height,
        first_row,
        out,
        1,
        |rays, counters| trace(&rays[0], &mut counters[0]),
    );
}

/// [`trace_rows`] with the rays of each `tile × tile` block of pixels given to `trace`
/// together (row by row, one set of counters each); blocks are cut at the image's right
/// edge and at the end of `out`, so give whole tiles of rows where it matters.
pub fn trace_rows_in_packets<V: Vector3>(
    camera: &Camera,
    width: usize,
    height: usize,
    first_row: usize,
    out: &mut [PixelCost],
    tile: usize,
    mut trace: impl FnMut(&[Ray<V>], &mut [Counters]),
) {
    let tile = tile.max(1);
    let rows = out.len().checked_div(width).unwrap_or(0);
    let mut rays = Vec::with_capacity(tile * tile);
    let mut pixels = Vec::with_capacity(tile * tile);
    let mut counters = Vec::with_capacity(tile * tile);
    for tile_row in (0..rows).step_by(tile) {
        for tile_column in (0..width).step_by(tile) {
            rays.clear();
            pixels.clear();
            for row in tile_row..(tile_row + tile).min(rows) {
                for column in tile_column..(tile_column + tile).min(width) {
                    let index = row * width + column;
                    // A camera gives a valid ray for every pixel unless it is itself broken
                    // (a zero view direction); such a pixel costs nothing.
                    out[index] = PixelCost::default();
                    if let Ok(ray) = camera.pixel_ray::<V>(column, first_row + row, width, height) {
                        rays.push(ray);
                        pixels.push(index);
                    }
                }
            }
            if rays.is_empty() {
                continue;
            }
            counters.clear();
            counters.resize(rays.len(), Counters::default());
            trace(&rays, &mut counters);
            for (&index, counters) in pixels.iter().zip(&counters) {
                out[index] = PixelCost::of(counters);
            }
        }
    }
}

/// Linear interpolation through evenly spaced colour stops, `t` clamped to [0, 1].
fn through_stops(stops: &[[f64; 3]], t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let position = t * (stops.len() - 1) as f64;
    let index = (position.floor() as usize).min(stops.len() - 2);
    let within = position - index as f64;
    let (low, high) = (stops[index], stops[index + 1]);
    [0, 1, 2].map(|k| ((low[k] + (high[k] - low[k]) * within) * 255.0).round() as u8)
}

/// The sequential palette, `t` in [0, 1]: dark purple, blue, teal, green, yellow, with
/// lightness rising throughout (readable in grey and by colour-blind viewers, like viridis).
pub fn sequential(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [0.267, 0.005, 0.329],
        [0.231, 0.322, 0.545],
        [0.129, 0.569, 0.549],
        [0.369, 0.788, 0.384],
        [0.992, 0.906, 0.145],
    ];
    through_stops(&STOPS, t)
}

/// [`diverging`] for a view on a light background, or on a dark one (`dark`): there the
/// middle is dark and the ends light, the same two hues.
pub fn diverging_on(t: f64, dark: bool) -> [u8; 3] {
    // The same two hues, from a dark middle out to light ends: on a dark background the
    // colour's distance from the background tells the size, as the light map's does on white.
    const DARK_STOPS: [[f64; 3]; 5] = [
        [0.573, 0.773, 0.871],
        [0.200, 0.420, 0.620],
        [0.120, 0.120, 0.120],
        [0.640, 0.360, 0.090],
        [0.992, 0.722, 0.388],
    ];
    if dark {
        through_stops(&DARK_STOPS, (t + 1.0) / 2.0)
    } else {
        diverging(t)
    }
}

/// The diverging palette, `t` in [-1, 1]: blue below zero, near-white at zero, orange above
/// (a blue/orange pair stays distinct for red-green colour-blind viewers).
pub fn diverging(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [0.129, 0.400, 0.675],
        [0.573, 0.773, 0.871],
        [0.969, 0.969, 0.969],
        [0.992, 0.722, 0.388],
        [0.702, 0.345, 0.024],
    ];
    through_stops(&STOPS, (t + 1.0) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palettes_get_lighter_and_meet_their_ends() {
        let lightness =
            |[r, g, b]: [u8; 3]| 0.2126 * r as f64 + 0.7152 * g as f64 + 0.0722 * b as f64;
        let mut previous = -1.0;
        for step in 0..=100 {
            let here = lightness(sequential(step as f64 / 100.0));
            assert!(here > previous, "lightness falls at {step}");
            previous = here;
        }
        assert_eq!(sequential(-3.0), sequential(0.0));
        assert_eq!(sequential(f64::NAN), sequential(0.0));
        assert_eq!(sequential(7.0), [253, 231, 37]);
        assert_eq!(diverging(0.0), [247, 247, 247]);
        assert!(diverging(-1.0)[2] > diverging(-1.0)[0], "negative is blue");
        assert!(diverging(1.0)[0] > diverging(1.0)[2], "positive is orange");
    }
}
