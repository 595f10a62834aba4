//! Three trees of one scene side by side, built by the lecture's three rules (middle, median,
//! SAH), each pane with its statistics and counters measured on the same seeded rays. Lessons 7
//! and 8 show it.

use accelviz_core::{Counters, Ray, TraceOptions, TreeStats};
use accelviz_scene::rng::SplitMix64;
use egui::{Color32, Stroke, Vec2};
use glam::DVec2;

use super::bvh::BuiltBvh;
use super::common::{self, BvhRule, KdRule};
use super::kd::BuiltKd;
use crate::canvas::{Canvas, View2d, depth_color, faded, palette};
use crate::editor::EditableScene;

/// Which kind of tree is compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Structure {
    /// Bounding volume hierarchies.
    Bvh,
    /// kD-trees.
    Kd,
}

/// The three rules in pane order.
pub const RULE_NAMES: [&str; 3] = ["middle", "median", "SAH"];

/// One built tree.
pub enum BuiltTree {
    /// A BVH.
    Bvh(BuiltBvh),
    /// A kD-tree.
    Kd(BuiltKd),
}

/// Rays the panes are measured with: seeded, from outside the scene through it.
const MEASURED_RAYS: usize = 256;

/// Three trees with their statistics and measured counters.
pub struct Comparison {
    /// What was built.
    pub structure: Structure,
    /// Middle, median, SAH.
    pub trees: Vec<BuiltTree>,
    /// Their statistics under the scene's cost model.
    pub stats: Vec<TreeStats>,
    /// Counters summed over the measured rays.
    pub counters: Vec<Counters>,
    /// How many rays were measured.
    pub ray_count: usize,
}

impl Comparison {
    /// Builds the three trees of `structure` over the scene and measures them.
    pub fn new(scene: &EditableScene, structure: Structure) -> Self {
        let shapes = &scene.scene.shapes;
        let settings = &scene.scene.settings;
        let cost = settings.cost();
        let trees: Vec<BuiltTree> = match structure {
            Structure::Bvh => [BvhRule::Middle, BvhRule::Median, BvhRule::Sah]
                .into_iter()
                .map(|rule| BuiltTree::Bvh(BuiltBvh::new(scene, rule)))
                .collect(),
            Structure::Kd => [KdRule::Middle, KdRule::Median, KdRule::Sah]
                .into_iter()
                .map(|rule| BuiltTree::Kd(BuiltKd::new(scene, rule)))
                .collect(),
        };
        let stats = trees
            .iter()
            .map(|tree| match tree {
                BuiltTree::Bvh(built) => TreeStats::of(&built.bvh, &cost),
                BuiltTree::Kd(built) => TreeStats::of(&built.tree, &cost),
            })
            .collect();
        let rays = measured_rays(scene);
        let options = TraceOptions::default();
        let counters = trees
            .iter()
            .map(|tree| {
                let mut counters = Counters::default();
                for ray in &rays {
                    match tree {
                        BuiltTree::Bvh(built) => {
                            accelviz_core::bvh::traverse(
                                &built.bvh,
                                shapes,
                                ray,
                                &options,
                                &mut accelviz_core::bvh::TraversalStack::new(),
                                &mut counters,
                            );
                        }
                        BuiltTree::Kd(built) => {
                            accelviz_core::kd::traverse(
                                &built.tree,
                                shapes,
                                ray,
                                &options,
                                &mut accelviz_core::kd::KdTraversalStack::new(),
                                &mut counters,
                            );
                        }
                    }
                }
                counters
            })
            .collect();
        Self {
            structure,
            trees,
            stats,
            counters,
            ray_count: rays.len(),
        }
    }

    /// Short lines of statistics per pane.
    pub fn summary(&self, pane: usize) -> [String; 3] {
        let stats = &self.stats[pane];
        let counters = &self.counters[pane];
        let per_ray = |value: u64| value as f64 / self.ray_count.max(1) as f64;
        [
            format!("SAH cost {:.2}, depth {}", stats.sah_cost, stats.max_depth),
            format!(
                "{} leaves of {}..{} (mean {:.1})",
                stats.leaf_count, stats.min_leaf_size, stats.max_leaf_size, stats.mean_leaf_size
            ),
            format!(
                "per ray: {:.1} nodes, {:.1} tests",
                per_ray(counters.nodes_visited),
                per_ray(counters.primitive_tests)
            ),
        ]
    }

    /// Draws pane `pane`: the scene and the tree's boxes or split lines.
    pub fn draw_pane(&self, ui: &egui::Ui, canvas: &Canvas, scene: &EditableScene, pane: usize) {
        common::draw_shapes(ui, canvas, &scene.scene.shapes, |_| None);
        match &self.trees[pane] {
            BuiltTree::Bvh(built) => {
                canvas.box_outlines(built.bvh.nodes.iter().enumerate().map(|(node, entry)| {
                    let color = depth_color(built.shape.depth[node]);
                    (entry.bounds, Stroke::new(1.2, faded(color, 220)))
                }))
            }
            BuiltTree::Kd(built) => built.draw_splits(canvas, None),
        }
        let [first, second, third] = self.summary(pane);
        canvas.caption(&[
            (RULE_NAMES[pane].to_owned(), rule_color(pane)),
            (first, Color32::WHITE),
            (second, Color32::WHITE),
            (third, Color32::WHITE),
        ]);
    }

    /// Three panes side by side, sharing one view; returns their canvases for editing.
    pub fn panes_ui(
        &self,
        ui: &mut egui::Ui,
        scene: &mut EditableScene,
        height: f32,
    ) -> Vec<Canvas> {
        let width = (ui.available_width() - 12.0) / 3.0;
        let bounds = scene.bounds();
        let mut view: View2d = scene.view;
        let canvases = ui
            .horizontal(|ui| {
                (0..3)
                    .map(|pane| {
                        let canvas = Canvas::allocate(
                            ui,
                            Vec2::new(width, height),
                            &mut view,
                            &bounds,
                            false,
                        );
                        self.draw_pane(ui, &canvas, scene, pane);
                        canvas
                    })
                    .collect::<Vec<_>>()
            })
            .inner;
        scene.view = view;
        canvases
    }
}

/// Seeded rays from a circle around the scene to random points in it.
fn measured_rays(scene: &EditableScene) -> Vec<Ray<DVec2>> {
    let bounds = scene
        .scene
        .shapes
        .shapes
        .iter()
        .fold(accelviz_core::Aabb::empty(), |bounds, shape| {
            bounds.union(shape.bounds())
        });
    if bounds.is_empty() {
        return Vec::new();
    }
    let mut rng = SplitMix64::new(27);
    let center = bounds.center();
    let reach = bounds.extent().length() * 0.75 + 1e-9;
    (0..MEASURED_RAYS)
        .filter_map(|_| {
            let angle = rng.range(0.0, std::f64::consts::TAU);
            let origin = center + DVec2::new(angle.cos(), angle.sin()) * reach;
            let target = DVec2::new(
                rng.range(bounds.min.x, bounds.max.x),
                rng.range(bounds.min.y, bounds.max.y),
            );
            Ray::try_new(origin, target - origin).ok()
        })
        .collect()
}

/// The colour of a rule's pane marks (curves, ghost splits).
pub fn rule_color(pane: usize) -> Color32 {
    [palette::X_AXIS, palette::Y_AXIS, palette::CURRENT][pane.min(2)]
}
