//! Lesson 2, "Bounding Volume" and "Pros and Cons": a box and a sphere around the same object,
//! the reject test, the void shaded with its share, and the rays that pass the volume's test
//! only to miss the object (wasted work).

use std::sync::Arc;

use accelviz_core::bounding::BoundingVolumes;
use accelviz_core::format::{number, point};
use accelviz_core::{Ray, ShapeSet, TraceOptions, brute_force};
use egui::{Color32, Stroke};
use glam::DVec2;

use crate::background::Derived;
use crate::canvas::{faded, palette};
use crate::editor::Editing;
use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::stage::Stage;
use crate::views::scene_view::{building_note, draw_shapes};

/// Which bounding volume the rays are tested against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Volume {
    Aabb,
    Sphere,
}

/// How one ray of the fan fares.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fate {
    /// Missed the volume: rejected at the cost of one cheap test.
    Rejected,
    /// Hit the volume and the object, first at `t`.
    Hit(f64),
    /// Hit the volume but missed the object: every primitive tested for nothing.
    Wasted,
}

/// The lesson.
pub struct BoundingVolumesLesson {
    stage: Stage,
    volume: Volume,
    fan_size: usize,
    /// The volumes and both fans, for the scene revision and fan size they were made for:
    /// the fans test every shape per ray, so they are not redone every frame.
    measured: Derived<(u64, usize), Measured>,
}

/// The volumes around the scene, and each ray of the fan with its fate under each volume.
struct Measured {
    volumes: BoundingVolumes<DVec2>,
    fans: [Vec<(Ray<DVec2>, Fate)>; 2],
}

impl Volume {
    fn index(self) -> usize {
        match self {
            Volume::Aabb => 0,
            Volume::Sphere => 1,
        }
    }
}

impl BoundingVolumesLesson {
    /// The lesson with its file's scene.
    pub fn new(text: LessonText) -> Self {
        Self {
            stage: Stage::new(text, Editing::BY_HAND),
            volume: Volume::Aabb,
            fan_size: 31,
            measured: Derived::default(),
        }
    }
}

/// The volumes around the shapes (taken as one object), and both fans from `origin`.
fn measure(shapes: &ShapeSet<DVec2>, origin: DVec2, fan_size: usize) -> Measured {
    let volumes = BoundingVolumes::around_shapes(shapes);
    let fans = [Volume::Aabb, Volume::Sphere]
        .map(|volume| fan(shapes, &volumes, volume, origin, fan_size));
    Measured { volumes, fans }
}

/// A fan of rays from `origin` spanning the bounding sphere (and a little more), with each
/// ray's fate under `volume`.
fn fan(
    shapes: &ShapeSet<DVec2>,
    volumes: &BoundingVolumes<DVec2>,
    volume: Volume,
    origin: DVec2,
    fan_size: usize,
) -> Vec<(Ray<DVec2>, Fate)> {
    let to_center = volumes.sphere.center - origin;
    let distance = to_center.length();
    if distance <= volumes.sphere.radius * 1.05 || fan_size == 0 {
        return Vec::new();
    }
    let half_angle = (volumes.sphere.radius / distance).asin() * 1.35;
    let center_angle = to_center.y.atan2(to_center.x);
    (0..fan_size)
        .filter_map(|index| {
            let share = index as f64 / (fan_size - 1).max(1) as f64;
            let angle = center_angle - half_angle + 2.0 * half_angle * share;
            let ray = Ray::try_new(origin, DVec2::new(angle.cos(), angle.sin())).ok()?;
            let (box_hit, sphere_hit) = volumes.reject_tests(&ray);
            let volume_hit = match volume {
                Volume::Aabb => box_hit,
                Volume::Sphere => sphere_hit,
            };
            let fate = if !volume_hit {
                Fate::Rejected
            } else {
                match brute_force(
                    shapes,
                    &ray,
                    &TraceOptions::default(),
                    &mut accelviz_core::NoObserver,
                ) {
                    Some(hit) => Fate::Hit(hit.t),
                    None => Fate::Wasted,
                }
            };
            Some((ray, fate))
        })
        .collect()
}

impl Lesson for BoundingVolumesLesson {
    crate::staged!(measured);

    fn update(&mut self) {
        let scene = &self.stage.scene;
        let key = (scene.revision, self.fan_size);
        let fan_size = self.fan_size;
        self.measured
            .request(&key, scene.scene.shapes.shapes.len(), || {
                let shapes = Arc::new(scene.scene.shapes.clone());
                let origin = scene.scene.ray_origin;
                move || measure(&shapes, origin, fan_size)
            });
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, _parts: crate::lesson::Parts<'_>) {
        ui.horizontal(|ui| {
            ui.label("Test rays against");
            ui.selectable_value(&mut self.volume, Volume::Aabb, "the box (AABB)");
            ui.selectable_value(&mut self.volume, Volume::Sphere, "the sphere");
        });
        ui.add(egui::Slider::new(&mut self.fan_size, 2..=101).text("rays in the fan"));
        ui.separator();
        let Some(measured) = self.measured.get().cloned() else {
            ui.label("Measuring…");
            return;
        };
        let volumes = measured.volumes;
        let mut rows = Vec::new();
        for volume in [Volume::Aabb, Volume::Sphere] {
            let fan = &measured.fans[volume.index()];
            let count =
                |wanted: fn(&Fate) -> bool| fan.iter().filter(|(_, fate)| wanted(fate)).count();
            rows.push((
                volume,
                count(|fate| *fate == Fate::Rejected),
                count(|fate| matches!(fate, Fate::Hit(_))),
                count(|fate| *fate == Fate::Wasted),
            ));
        }
        // A table keeps its columns: in a narrow panel (the app scaled up) it scrolls
        // sideways rather than widen the panel.
        egui::ScrollArea::horizontal()
            .id_salt("volumes table columns")
            .show(ui, |ui| {
                egui::Grid::new("volumes table")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.strong("volume");
                        ui.strong("void");
                        ui.strong("rejected");
                        ui.strong("hit object");
                        ui.strong("wasted");
                        ui.end_row();
                        for (volume, rejected, hit, wasted) in rows {
                            let (name, void) = match volume {
                                Volume::Aabb => ("box", volumes.aabb_void),
                                Volume::Sphere => ("sphere", volumes.sphere_void),
                            };
                            ui.label(name);
                            ui.label(format!("{:.0} %", void * 100.0));
                            ui.label(rejected.to_string());
                            ui.label(hit.to_string());
                            ui.colored_label(
                                crate::canvas::readable(ui, palette::RAY),
                                wasted.to_string(),
                            );
                            ui.end_row();
                        }
                    });
            });
        ui.label(
            "Void: the share of the volume the object does not fill. A ray through the void passes \
             the cheap reject test and then tests every primitive for nothing: the wasted rays.",
        );
        ui.label(format!(
            "Box: from {} to {}. Sphere: centre {}, radius {} (Ritter 1990). The object covers {} (overlaps counted once).",
            point(&[volumes.aabb.min.x, volumes.aabb.min.y]),
            point(&[volumes.aabb.max.x, volumes.aabb.max.y]),
            point(&[volumes.sphere.center.x, volumes.sphere.center.y]),
            number(volumes.sphere.radius),
            number(volumes.aabb.measure() * (1.0 - volumes.aabb_void)),
        ));
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        let measured = self.measured.get().cloned();
        let sphere_bounds = measured
            .as_ref()
            .map(|measured| measured.volumes.sphere.bounds());
        let canvas = self.stage.scene.canvas_ui(ui, sphere_bounds);
        let Some(measured) = measured else { return };
        let volume = self.volume;
        let volumes = measured.volumes;
        let fan = measured.fans[volume.index()].clone();
        // The volumes, filled: what the object leaves uncovered is the void.
        let sphere_center = canvas.to_screen(volumes.sphere.center);
        let sphere_radius = (volumes.sphere.radius * canvas.view.points_per_unit) as f32;
        let (box_alpha, sphere_alpha) = match self.volume {
            Volume::Aabb => (70, 18),
            Volume::Sphere => (18, 70),
        };
        canvas.painter.circle_filled(
            sphere_center,
            sphere_radius,
            faded(palette::SPHERE, sphere_alpha),
        );
        canvas.painter.circle_stroke(
            sphere_center,
            sphere_radius,
            Stroke::new(2.0, palette::SPHERE),
        );
        canvas.box_outline(
            &volumes.aabb,
            Stroke::new(2.0, palette::BOX),
            Some(faded(palette::BOX, box_alpha)),
        );
        for (ray, fate) in &fan {
            let color = match fate {
                Fate::Rejected => faded(ui.visuals().weak_text_color(), 90),
                Fate::Hit(_) => faded(palette::HIT, 170),
                Fate::Wasted => palette::RAY,
            };
            // A ray that hits the object stops there.
            let t_stop = match fate {
                Fate::Hit(t) => *t,
                _ => f64::INFINITY,
            };
            let t_end = canvas.clip_t(ray.origin, ray.direction, t_stop);
            canvas.painter.line_segment(
                [
                    canvas.to_screen(ray.origin),
                    canvas.to_screen(ray.at(t_end)),
                ],
                Stroke::new(if *fate == Fate::Wasted { 2.0 } else { 1.0 }, color),
            );
        }
        draw_shapes(ui, &canvas, &self.stage.scene.scene.shapes, |_| None);
        canvas.label(
            DVec2::new(volumes.aabb.min.x, volumes.aabb.max.y),
            " AABB",
            palette::BOX,
        );
        canvas.label(
            volumes.sphere.center + DVec2::new(0.0, volumes.sphere.radius),
            " bounding sphere",
            palette::SPHERE,
        );
        canvas.painter.circle_filled(
            canvas.to_screen(self.stage.scene.scene.ray_origin),
            5.0,
            palette::RAY,
        );
        self.stage.scene.draw_handles(&canvas);
        let volume_name = match self.volume {
            Volume::Aabb => "box",
            Volume::Sphere => "sphere",
        };
        let wasted = fan.iter().filter(|(_, fate)| *fate == Fate::Wasted).count();
        canvas.caption(&[
            (
                format!(
                    "void: box {:.0} %, sphere {:.0} % of their area",
                    volumes.aabb_void * 100.0,
                    volumes.sphere_void * 100.0
                ),
                Color32::WHITE,
            ),
            (
                format!(
                    "{wasted} of {} rays hit the {volume_name} but miss the object (orange)",
                    fan.len()
                ),
                palette::RAY,
            ),
        ]);
        building_note(
            ui,
            &canvas,
            self.measured.working_for(),
            "the volumes and the fan",
        );
        self.stage.scene.draw_footer(&canvas);
        canvas.finish();
    }
}
