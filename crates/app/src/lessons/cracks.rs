//! Lesson 17, "Cracks and extremes": the numbers behind the speed/accuracy trade, live. Every
//! number shown is what the core's own tests computed (`accelviz_core::crack`,
//! `TriangleSet::explain`, the slab test's `axis_interval` and `slab_record`):
//!
//! - a ray aimed at the edge two triangles share, in 3D and seen along the ray, zoomed until
//!   the floats show, in f32 beside f64: Möller–Trumbore's barycentric coordinates can put the
//!   point just outside both triangles (the ray slips through), the watertight test's edge
//!   functions cannot (Woop, Benthin & Wald 2013);
//! - the same far from the origin, where the numbers near the mesh grow apart;
//! - a ray lying on a slab's plane, where `0 × ∞` gives NaN and the test must ignore it
//!   (Williams et al. 2005);
//! - a ray exactly through a box's corner, which the plain slab test misses and Ize's (2013)
//!   widened `t_far` keeps.

use accelviz_core::crack::{
    CornerGraze, EdgeTest, SharedEdge, corner_graze, corner_ray, slip_count,
};
use accelviz_core::format::{count, number};
use accelviz_core::primitive::clipped_polygon;
use accelviz_core::slab::{SlabRay, axis_interval};
use accelviz_core::trade::Precision;
use accelviz_core::{Aabb, HitTest, Ray, slab_record};
use accelviz_scene::rng::SplitMix64;
use egui::{Color32, Rect, RichText, Stroke, Vec2};
use glam::{DVec2, DVec3, Vec3};

use crate::canvas::{Canvas, View2d, faded, palette, readable};
use crate::files::FileFilter;
use crate::lesson::{Lesson, Part as InspectorPart, Parts};
use crate::lesson_file::LessonText;
use crate::stage::{SceneFile, Stage};
use crate::view3d::{Content, DrawTriangle, HiddenEdges, Instance, View3d, relative, revision_of};

/// The lesson's parts, each a case the numbers go wrong in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// A ray aimed at a shared edge.
    SharedEdge,
    /// The same far from the origin.
    FarAway,
    /// A ray lying on a slab's plane.
    SlabPlane,
    /// A ray exactly through a box's corner.
    Corner,
}

impl Part {
    /// Every part, in the lesson's order.
    pub const ALL: [Part; 4] = [
        Part::SharedEdge,
        Part::FarAway,
        Part::SlabPlane,
        Part::Corner,
    ];

    /// Its name on its tab and in a lecture script's `show NAME`.
    pub fn name(self) -> &'static str {
        match self {
            Part::SharedEdge => "shared-edge",
            Part::FarAway => "far-away",
            Part::SlabPlane => "slab-plane",
            Part::Corner => "corner",
        }
    }

    /// Its tab's words.
    fn title(self) -> &'static str {
        match self {
            Part::SharedEdge => "a shared edge",
            Part::FarAway => "far from the origin",
            Part::SlabPlane => "on a slab plane",
            Part::Corner => "through a corner",
        }
    }
}

/// The box of the slab parts: corners a few bits long, so a ray through one is exact.
fn slab_box() -> Aabb<DVec2> {
    Aabb::new(DVec2::new(0.25, 0.25), DVec2::new(1.75, 1.125))
}

/// The ray lying on the box's bottom plane, y = 0.25: its y slab gives `(0.25 − 0.25) · ∞`.
const PLANE_RAY: ([f64; 2], [f64; 2]) = ([-0.5, 0.25], [1.0, 0.0]);

/// How many cases the far-away part's slip rates count over, at each offset.
const SLIP_CASES: usize = 2_000;

/// The offsets the far-away part offers, as powers of ten.
const OFFSET_POWERS: std::ops::RangeInclusive<i32> = 0..=6;

/// What the lesson shows: which part, which case, which test, how far away, how zoomed.
pub struct CrackScene {
    /// The part shown.
    pub part: Part,
    /// The shared-edge case's seed (the lesson opens on the first whose ray slips through the
    /// fast f32 test).
    pub seed: u64,
    /// The test of the shared-edge parts.
    pub test: HitTest,
    /// The far-away part's offset, as a power of ten.
    pub offset_power: i32,
    /// How far the views seen along the ray and at the corner are zoomed in, as a power of ten.
    pub zoom_power: f64,
    /// The slab parts' test: widened (Ize 2013) or plain.
    pub robust: bool,
}

impl CrackScene {
    fn of_lesson(_text: &LessonText) -> Self {
        Self {
            part: Part::SharedEdge,
            seed: 0,
            test: HitTest::Fast,
            offset_power: 3,
            zoom_power: 0.0,
            robust: false,
        }
    }

    /// The shared-edge case of this seed, moved as far as the part says.
    pub fn case(&self) -> SharedEdge {
        let mut numbers = SplitMix64::new(self.seed);
        let case = SharedEdge::draw(|| numbers.next_f64());
        match self.part {
            Part::FarAway => case.moved(DVec3::splat(10f64.powi(self.offset_power))),
            _ => case,
        }
    }

    /// The case tested in f32 and in f64.
    pub fn tested(&self) -> Option<[EdgeTest; 2]> {
        let case = self.case();
        Some([
            case.test::<Vec3>(self.test)?,
            case.test::<DVec3>(self.test)?,
        ])
    }
}

impl SceneFile for CrackScene {
    fn noun(&self) -> &'static str {
        "case"
    }

    fn filter(&self) -> Option<FileFilter> {
        None
    }

    fn open(&mut self, _name: &str, _text: &str) -> Result<(), String> {
        Err("this lesson opens no files: draw another ray, or pick a part".to_owned())
    }

    fn save(&self) -> Option<(String, String)> {
        None
    }

    fn can_save(&self) -> bool {
        false
    }

    fn reset(&mut self, text: &LessonText) {
        *self = Self::of_lesson(text);
    }
}

/// The far-away part's slip columns: a test in a precision, with the ray aimed so far beside
/// the shared edge (into B, which the exact ray then hits).
pub const SLIP_COLUMNS: [(Precision, HitTest, f64); 5] = [
    (Precision::F32, HitTest::Fast, 0.0),
    (Precision::F32, HitTest::Fast, 1e-6),
    (Precision::F64, HitTest::Fast, 0.0),
    (Precision::F32, HitTest::Watertight, 0.0),
    (Precision::F64, HitTest::Watertight, 0.0),
];

/// How many of the cases the far-away part's hit points are measured over.
const HIT_POINT_CASES: usize = 200;

/// The far-away part's measurements at one offset.
#[derive(Clone, Debug, PartialEq)]
pub struct FarRow {
    /// The offset, as a power of ten.
    pub power: i32,
    /// How far apart the numbers near the mesh are: f32, f64.
    pub spacing: [f64; 2],
    /// The farthest a hit point `o + t·d` (watertight test) landed off its triangle's plane:
    /// f32, f64.
    pub hit_point_off: [f64; 2],
    /// Rays slipped through, per [`SLIP_COLUMNS`] column.
    pub slipped: [usize; SLIP_COLUMNS.len()],
    /// Out of how many.
    pub tested: usize,
}

/// The lesson.
pub struct CracksLesson {
    stage: Stage<CrackScene>,
    /// The 3D view of the shared-edge parts.
    pub view: View3d,
    /// The views seen along the ray, f32 and f64.
    along: [View2d; 2],
    /// The slab parts' view.
    slab_view: View2d,
    /// The far-away part's measurements, made when first shown.
    far: Option<Vec<FarRow>>,
    /// Whether the first case's answers were logged (the browser test reads them).
    logged: bool,
}

/// The inspector's parts a slide can show alone.
const PARTS: [InspectorPart; 2] = [
    InspectorPart::new("numbers", "what the tests computed, in f32 and f64"),
    InspectorPart::new(
        "rates",
        "how often the fast test slips, by distance from the origin",
    ),
];

/// `value` with every digit its precision holds (the shortest text that reads back exactly).
pub fn digits(value: f64, precision: Precision) -> String {
    if !value.is_finite() {
        return number(value);
    }
    let text = match precision {
        Precision::F32 => format!("{:e}", value as f32),
        Precision::F64 => format!("{value:e}"),
    };
    text.replace('-', "−")
}

/// The names of the values a test computes for a triangle.
fn value_names(test: HitTest) -> [&'static str; 3] {
    match test {
        HitTest::Fast => ["u", "v", "u + v"],
        HitTest::Watertight => ["U", "V", "W"],
    }
}

/// A DVec2 from an array's first two values.
fn flat(values: [f64; 3]) -> DVec2 {
    DVec2::new(values[0], values[1])
}

impl CracksLesson {
    /// The lesson on its first part, a ray that slips through.
    pub fn new(text: LessonText) -> Self {
        let scene = CrackScene::of_lesson(&text);
        let mut lesson = Self {
            stage: Stage::with_scene(text, scene),
            view: View3d::default(),
            along: [View2d::default(), View2d::default()],
            slab_view: View2d::default(),
            far: None,
            logged: false,
        };
        lesson.next_slip();
        lesson
    }

    /// What is shown.
    pub fn scene(&self) -> &CrackScene {
        &self.stage.scene
    }

    /// Shows `part`.
    pub fn show_part(&mut self, part: Part) {
        self.stage.scene.part = part;
        self.stage.scene.zoom_power = 0.0;
        self.refit();
    }

    /// Picks the test of the shared-edge parts.
    pub fn set_test(&mut self, test: HitTest) {
        self.stage.scene.test = test;
    }

    /// Sets how far the views are zoomed in, as a power of ten.
    pub fn set_zoom(&mut self, power: f64) {
        self.stage.scene.zoom_power = power.clamp(0.0, 9.0);
    }

    /// Draws the next case whose ray the fast f32 test lets slip through.
    pub fn next_slip(&mut self) {
        let scene = &mut self.stage.scene;
        for _ in 0..10_000 {
            scene.seed += 1;
            let slipped = scene
                .case()
                .test::<Vec3>(HitTest::Fast)
                .is_some_and(|tested| tested.hit.is_none());
            if slipped {
                break;
            }
        }
    }

    fn refit(&mut self) {
        self.along = [View2d::default(), View2d::default()];
        self.slab_view = View2d::default();
    }

    /// The far-away part's measurements at every offset, made once.
    pub fn far_rows(&mut self) -> &[FarRow] {
        self.far.get_or_insert_with(|| {
            let mut numbers = SplitMix64::new(2026);
            let near: Vec<SharedEdge> = (0..SLIP_CASES)
                .map(|_| SharedEdge::draw(|| numbers.next_f64()))
                .collect();
            OFFSET_POWERS
                .map(|power| {
                    let offset = DVec3::splat(10f64.powi(power));
                    let cases: Vec<SharedEdge> =
                        near.iter().map(|case| case.moved(offset)).collect();
                    let mut tested = 0;
                    let slipped = SLIP_COLUMNS.map(|(precision, test, aside)| {
                        let aimed: Vec<SharedEdge> =
                            cases.iter().map(|case| case.aimed_aside(aside)).collect();
                        let (slipped, count) = match precision {
                            Precision::F32 => slip_count::<Vec3>(&aimed, test),
                            Precision::F64 => slip_count::<DVec3>(&aimed, test),
                        };
                        tested = tested.max(count);
                        slipped
                    });
                    let measured = |tested: Option<EdgeTest>| {
                        tested.map(|t| (t.coordinate_ulp, t.hit_point_off.unwrap_or(0.0)))
                    };
                    let mut spacing = [0.0; 2];
                    let mut hit_point_off = [0.0f64; 2];
                    for case in cases.iter().take(HIT_POINT_CASES) {
                        let both = [
                            measured(case.test::<Vec3>(HitTest::Watertight)),
                            measured(case.test::<DVec3>(HitTest::Watertight)),
                        ];
                        for (index, values) in both.into_iter().enumerate() {
                            if let Some((ulp, off)) = values {
                                spacing[index] = f64::max(spacing[index], ulp);
                                hit_point_off[index] = hit_point_off[index].max(off);
                            }
                        }
                    }
                    FarRow {
                        power,
                        spacing,
                        hit_point_off,
                        slipped,
                        tested,
                    }
                })
                .collect()
        })
    }

    /// The controls above the canvas.
    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            for part in Part::ALL {
                if ui
                    .selectable_label(self.stage.scene.part == part, part.title())
                    .clicked()
                {
                    self.show_part(part);
                }
            }
        });
        let mut find_slip = false;
        let scene = &mut self.stage.scene;
        ui.horizontal_wrapped(|ui| match scene.part {
            Part::SharedEdge | Part::FarAway => {
                ui.label("test:");
                ui.selectable_value(&mut scene.test, HitTest::Fast, "fast (Möller–Trumbore)");
                ui.selectable_value(&mut scene.test, HitTest::Watertight, "watertight");
                if ui.button("next ray").clicked() {
                    scene.seed += 1;
                }
                if ui
                    .button("next that slips")
                    .on_hover_text("draws rays until the fast f32 test lets one through")
                    .clicked()
                {
                    find_slip = true;
                }
                if scene.part == Part::FarAway {
                    ui.add(
                        egui::DragValue::new(&mut scene.offset_power)
                            .range(OFFSET_POWERS)
                            .prefix("mesh at 10^"),
                    );
                }
            }
            Part::SlabPlane | Part::Corner => {
                ui.checkbox(&mut scene.robust, "conservative (Ize 2013)");
            }
        });
        if scene.part != Part::SlabPlane {
            // On its own row, as wide as there is room for: at lecture scale a fixed slider
            // and its words would push the inspector off.
            ui.horizontal(|ui| {
                ui.spacing_mut().slider_width = (ui.available_width() - 140.0).clamp(40.0, 240.0);
                let most = if scene.part == Part::Corner { 8.0 } else { 9.0 };
                ui.add(
                    egui::Slider::new(&mut scene.zoom_power, 0.0..=most)
                        .step_by(0.5)
                        .text("zoom 10^x"),
                );
            });
        }
        if find_slip {
            self.next_slip();
        }
    }

    /// The two triangles and the ray in 3D.
    fn view3d_ui(&mut self, ui: &mut egui::Ui, size: Vec2, tested: &EdgeTest) {
        let target = tested.origin + tested.direction;
        let all = Aabb::from_points(tested.corners.iter().flatten().copied()).grown(tested.origin);
        let sphere = accelviz_core::camera::bounding_sphere_of_box(&all);
        let colours = [palette::BOX, palette::SPHERE];
        let triangles: Vec<DrawTriangle> = tested
            .corners
            .iter()
            .zip(colours)
            .map(|(corners, colour)| DrawTriangle {
                corners: corners.map(|corner| relative(corner, sphere)),
                color: [colour.r(), colour.g(), colour.b(), 255],
            })
            .collect();
        let ray_colour = if tested.hit.is_some() {
            palette::HIT
        } else {
            palette::MISS
        };
        let beyond = tested.origin + tested.direction * 1.4;
        let segments = [
            Instance {
                a: relative(tested.origin, sphere),
                b: relative(target, sphere),
                color: [ray_colour.r(), ray_colour.g(), ray_colour.b(), 255],
            },
            Instance {
                a: relative(target, sphere),
                b: relative(beyond, sphere),
                color: [ray_colour.r(), ray_colour.g(), ray_colour.b(), 120],
            },
            // The shared edge.
            Instance {
                a: relative(tested.corners[0][0], sphere),
                b: relative(tested.corners[0][2], sphere),
                color: [255, 255, 255, 255],
            },
        ];
        let half = DVec3::splat(sphere.1 * 0.02);
        let boxes = [Instance {
            a: relative(target - half, sphere),
            b: relative(target + half, sphere),
            color: [ray_colour.r(), ray_colour.g(), ray_colour.b(), 255],
        }];
        let key = revision_of((
            tested
                .corners
                .map(|t| t.map(|c| c.to_array().map(f64::to_bits))),
            tested.origin.to_array().map(f64::to_bits),
            tested.hit.is_some(),
        ));
        self.view.ui(
            ui,
            size.max(Vec2::splat(60.0)),
            &Content {
                sphere,
                mesh: (key, &triangles),
                highlights: (0, &[]),
                boxes: (key, &boxes),
                segments: (key, &segments),
                quads: (0, &[]),
                hidden_edges: HiddenEdges::Dimmed,
                wireframe: true,
            },
        );
    }

    /// The triangles seen along the ray, zoomed about the point it aims at: the shared edge,
    /// the ray (a point), and where each triangle's test put the ray's point across the edge.
    fn along_ui(ui: &mut egui::Ui, view: &mut View2d, size: Vec2, tested: &EdgeTest, zoom: f64) {
        let direction = tested.direction.normalize();
        let (across, up) = direction.any_orthonormal_pair();
        let aim = tested.origin + tested.direction;
        let project = |point: DVec3| {
            let relative = point - aim;
            DVec2::new(relative.dot(across), relative.dot(up))
        };
        let seen = tested.corners.map(|triangle| triangle.map(project));
        let extent = seen.iter().flatten().fold(0.0f64, |widest, point| {
            widest.max(point.abs().max_element())
        });
        let fit = Aabb::new(DVec2::splat(-extent), DVec2::splat(extent));
        // What the view shows, under it rather than on it: a caption on the view covered
        // a third of it at a lecture's text size. The view's width in world units, and so
        // the caption, depends on the view's size, which the caption's height decides:
        // laid out once for the whole height, the caption's rows hardly change after.
        let caption = |canvas_size: Vec2| {
            let (fitted, _) = View2d::fitted_scale(fit.extent(), canvas_size, Vec2::ZERO, 0.0);
            let width = f64::from(canvas_size.x) / (fitted * 10f64.powf(zoom));
            format!(
                "{} · {} test · seen along the ray · {} across = {} of the coordinates' ulp ({})",
                tested.precision.name(),
                tested.test.name(),
                number(width),
                number(width / tested.coordinate_ulp),
                number(tested.coordinate_ulp),
            )
        };
        let caption_font = egui::TextStyle::Small.resolve(ui.style());
        let caption_height = ui
            .painter()
            .layout(caption(size), caption_font, Color32::WHITE, size.x)
            .size()
            .y;
        let size = Vec2::new(
            size.x,
            (size.y - caption_height - ui.spacing().item_spacing.y).max(40.0),
        );
        ui.vertical(|ui| {
            ui.set_max_width(size.x);
            Self::along_canvas_ui(ui, view, size, &fit, &seen, tested, zoom);
            ui.label(RichText::new(caption(size)).small());
        });
    }

    /// The view along the ray of [`Self::along_ui`]: the triangles as seen, the edge, where
    /// each test put the ray and the exact ray's dot.
    fn along_canvas_ui(
        ui: &mut egui::Ui,
        view: &mut View2d,
        size: Vec2,
        fit: &Aabb<DVec2>,
        seen: &[[DVec2; 3]; 2],
        tested: &EdgeTest,
        zoom: f64,
    ) {
        let mut canvas = Canvas::allocate(ui, size, view, fit, false);
        // The zoom is the slider's: about the aimed point, whatever the wheel did.
        let fitted = View2d::fitted(fit, canvas.rect);
        let mut shown = canvas.view;
        shown.center = DVec2::ZERO;
        shown.points_per_unit = fitted.points_per_unit * 10f64.powf(zoom);
        *view = shown;
        canvas.set_view(shown);
        let half = DVec2::new(
            f64::from(canvas.rect.width()),
            f64::from(canvas.rect.height()),
        ) / shown.points_per_unit
            * 0.6;
        let window = Aabb::new(-half, half);
        let colours = [palette::BOX, palette::SPHERE];
        for (index, (corners, colour)) in seen.iter().zip(colours).enumerate() {
            // Zoomed a billion times, only the part on screen is drawn: its corners stay
            // within screen coordinates.
            let clipped = clipped_polygon(corners, &window);
            if clipped.len() >= 3 {
                let points = clipped.iter().map(|&p| canvas.to_screen(p)).collect();
                canvas.painter.add(egui::Shape::convex_polygon(
                    points,
                    faded(colour, 50),
                    Stroke::new(1.5, colour),
                ));
            }
            let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
            if window.contains_point(centroid) {
                canvas.label(centroid, ["A", "B"][index], colour);
            }
        }
        // The shared edge, a–c.
        let (edge_a, edge_c) = (seen[0][0], seen[0][2]);
        let along_edge = (edge_c - edge_a).normalize();
        let normal = DVec2::new(-along_edge.y, along_edge.x);
        let foot = edge_a + along_edge * (-edge_a).dot(along_edge);
        canvas.painter.line_segment(
            [
                canvas.to_screen(foot - along_edge * half.length() * 2.0),
                canvas.to_screen(foot + along_edge * half.length() * 2.0),
            ],
            Stroke::new(2.0, Color32::WHITE),
        );
        // Where each triangle's test put the ray's point: the weight of its corner facing the
        // edge times that corner's height above it. The rings and the ray's dot are kept
        // clear first, so that no name covers them.
        let ring_at = |index: usize| {
            let weight = tested.across(index)?;
            let facing = seen[index][accelviz_core::crack::OPPOSITE[index]];
            let height = (facing - foot).dot(normal);
            Some(foot + normal * (weight * height))
        };
        canvas.keep_clear(Rect::from_center_size(
            canvas.to_screen(DVec2::ZERO),
            Vec2::splat(10.0),
        ));
        for index in 0..2 {
            if let Some(at) = ring_at(index) {
                canvas.keep_clear(Rect::from_center_size(
                    canvas.to_screen(at),
                    Vec2::splat(20.0),
                ));
            }
        }
        for (index, colour) in colours.iter().enumerate() {
            let (Some(weight), Some(at)) = (tested.across(index), ring_at(index)) else {
                continue;
            };
            let inside = weight >= 0.0;
            let screen = canvas.to_screen(at);
            canvas
                .painter
                .circle_stroke(screen, 7.0, Stroke::new(2.5, *colour));
            if !inside {
                canvas
                    .painter
                    .line_segment([screen, canvas.to_screen(foot)], Stroke::new(1.0, *colour));
            }
            canvas.label_beside(
                at,
                &format!(
                    "{}'s test puts it {}",
                    ["A", "B"][index],
                    if inside { "inside" } else { "outside" }
                ),
                *colour,
                12.0,
            );
        }
        let ray_colour = if tested.hit.is_some() {
            palette::HIT
        } else {
            palette::MISS
        };
        canvas
            .painter
            .circle_filled(canvas.to_screen(DVec2::ZERO), 4.0, ray_colour);
        canvas.finish();
    }

    /// The slab parts: the box, the ray, and, through a corner, the zoom on it.
    fn slab_ui(&mut self, ui: &mut egui::Ui) {
        let scene = &self.stage.scene;
        let bounds = slab_box();
        let (origin, direction, zoom_at) = match scene.part {
            Part::SlabPlane => (flat_pair(PLANE_RAY.0), flat_pair(PLANE_RAY.1), None),
            _ => match corner_case() {
                Some(graze) => (
                    flat(graze.origin),
                    flat(graze.direction),
                    Some(DVec2::new(bounds.min.x, bounds.max.y)),
                ),
                None => return,
            },
        };
        let shown_bounds = bounds.grown(origin);
        let size = ui.available_size();
        let mut canvas = Canvas::allocate(ui, size, &mut self.slab_view, &shown_bounds, false);
        let mut view = canvas.view;
        if let Some(corner) = zoom_at {
            let fitted = View2d::fitted(&shown_bounds, canvas.rect);
            let zoom = 10f64.powf(scene.zoom_power);
            // Zooming moves towards the corner.
            view.center = corner + (fitted.center - corner) / zoom;
            view.points_per_unit = fitted.points_per_unit * zoom;
            self.slab_view = view;
        }
        canvas.set_view(view);
        canvas.box_outline(
            &bounds,
            Stroke::new(2.0, palette::BOX),
            Some(faded(palette::BOX, 30)),
        );
        let Ok(ray) = Ray::try_new(origin, direction) else {
            return;
        };
        // The test as f32 runs it (the corner's ray was found in f32).
        let Ok(ray_f32) = Ray::try_new(origin.as_vec2(), direction.as_vec2()) else {
            return;
        };
        let record = slab_record(
            &Aabb::new(bounds.min.as_vec2(), bounds.max.as_vec2()),
            &ray_f32,
            scene.robust,
        );
        // Zoomed a millionfold, only the part of the ray on screen is drawn: the screen's
        // box clips it, by the slab test itself.
        let window = Aabb::from_points([
            canvas.to_world(canvas.rect.left_top()),
            canvas.to_world(canvas.rect.right_bottom()),
        ]);
        let drawn = |from: f64, to: f64, stroke: Stroke| {
            let clipped = slab_record(&window, &ray, false);
            let (start, end) = (from.max(clipped.t_enter), to.min(clipped.t_exit));
            if clipped.hit && start < end {
                canvas.painter.line_segment(
                    [
                        canvas.to_screen(ray.at(start)),
                        canvas.to_screen(ray.at(end)),
                    ],
                    stroke,
                );
            }
        };
        drawn(0.0, 4.0, Stroke::new(2.0, palette::RAY));
        if record.hit {
            drawn(
                f64::from(record.t_enter.max(0.0)),
                f64::from(record.t_exit),
                Stroke::new(5.0, palette::HIT),
            );
        }
        canvas.note(&format!(
            "f32 {} slab test: {}",
            if scene.robust {
                "conservative"
            } else {
                "plain"
            },
            if record.hit { "hit" } else { "miss" }
        ));
        canvas.finish();
    }

    /// What one precision's test computed for A and B, every digit: under its view.
    fn values_ui(ui: &mut egui::Ui, tested: &EdgeTest) {
        let names = value_names(tested.test);
        egui::Grid::new(("crack values", tested.precision.name()))
            .striped(true)
            .min_col_width(48.0)
            .show(ui, |ui| {
                ui.strong(tested.precision.name());
                ui.strong("A");
                ui.strong("B");
                ui.end_row();
                for (value, label) in names.iter().enumerate() {
                    ui.label(*label);
                    for values in &tested.values {
                        ui.monospace(
                            values.coordinates[value].map_or("(stopped before)".to_owned(), |v| {
                                digits(v, tested.precision)
                            }),
                        );
                    }
                    ui.end_row();
                }
                ui.label("t");
                for values in &tested.values {
                    ui.monospace(
                        values
                            .t
                            .map_or("—".to_owned(), |t| digits(t, tested.precision)),
                    );
                }
                ui.end_row();
                ui.label("hit");
                for values in &tested.values {
                    ui.colored_label(
                        readable(
                            ui,
                            if values.hit {
                                palette::HIT
                            } else {
                                palette::MISS
                            },
                        ),
                        if values.hit { "yes" } else { "no" },
                    );
                }
                ui.end_row();
            });
    }

    /// The numbers of the shared-edge parts, f32 beside f64.
    fn edge_numbers_ui(ui: &mut egui::Ui, tested: &[EdgeTest; 2]) {
        let test = tested[0].test;
        ui.label(RichText::new(format!("{} test, f32 beside f64", tested[0].test.name())).strong());
        for tested in tested {
            let (answer, colour) = match tested.hit {
                Some(hit) if tested.both_hit() => (
                    format!("both hit; {} kept", ["A", "B"][hit.primitive as usize]),
                    palette::HIT,
                ),
                Some(hit) => (
                    format!("{} hit", ["A", "B"][hit.primitive as usize]),
                    palette::HIT,
                ),
                None => ("slips through".to_owned(), palette::MISS),
            };
            ui.horizontal_wrapped(|ui| {
                ui.strong(format!("{}:", tested.precision.name()));
                ui.colored_label(readable(ui, colour), answer);
                ui.label(format!("({})", tested.outcome.name().replace('_', " ")));
            });
            ui.label(format!(
                "numbers {} apart here",
                number(tested.coordinate_ulp)
            ));
            if let Some((_, ulp, error)) = tested.t_error() {
                ui.label(format!(
                    "t's ulp {}; t is {} ulp from the reference's",
                    number(ulp),
                    number(error)
                ));
            }
            if let Some(off) = tested.hit_point_off {
                ui.label(format!("hit point {} off the plane", number(off)));
            }
        }
        let f32_test = &tested[0];
        let why = match (test, f32_test.hit) {
            (HitTest::Fast, None) => {
                "In f32 rounding put the point outside A and outside B, across the edge they share: the ray slips through a closed surface. Each triangle computes its u and v on its own, so nothing makes the two agree."
            }
            (HitTest::Fast, Some(_)) if f32_test.both_hit() => {
                "Here rounding put the point inside both: each triangle computed its own coordinates."
            }
            (HitTest::Fast, Some(_)) => {
                "Here rounding left the point inside one triangle; try \"next ray that slips\"."
            }
            (HitTest::Watertight, _) => {
                "The watertight test computes the shared edge's function from the same products for both triangles, subtracted the other way round: one is exactly the other's negative, so the point is inside at least one of them. If it is exactly 0, both hit, and the closest hit is kept (equal t: the lower number)."
            }
        };
        ui.label(why);
    }

    /// The numbers of the slab parts.
    fn slab_numbers_ui(&self, ui: &mut egui::Ui) {
        let scene = &self.stage.scene;
        let bounds = slab_box();
        match scene.part {
            Part::SlabPlane => {
                let (origin, direction) = (flat_pair(PLANE_RAY.0), flat_pair(PLANE_RAY.1));
                let Ok(ray) = Ray::try_new(origin, direction) else {
                    return;
                };
                let slab_ray = SlabRay::new(&ray, scene.robust);
                ui.label(
                    RichText::new("The ray runs along the box's bottom plane, y = 0.25").strong(),
                );
                egui::Grid::new("slab plane numbers")
                    .striped(true)
                    .show(ui, |ui| {
                        for label in ["axis", "1/d", "near plane − p", "t near", "t far"] {
                            ui.strong(label);
                        }
                        ui.end_row();
                        for axis in 0..2 {
                            let (t_near, t_far) = axis_interval(&bounds, &slab_ray, axis);
                            let near_plane = if slab_ray.negative[axis] {
                                bounds.max[axis]
                            } else {
                                bounds.min[axis]
                            };
                            ui.label(["x", "y"][axis]);
                            ui.monospace(number(slab_ray.inv_direction[axis]));
                            ui.monospace(number(near_plane - origin[axis]));
                            ui.monospace(number(t_near));
                            ui.monospace(number(t_far));
                            ui.end_row();
                        }
                    });
                let record = slab_record(&bounds, &ray, scene.robust);
                ui.label("On the y axis (0.25 − 0.25) × ∞ = 0 × ∞ = NaN. A comparison with NaN is false, so the max of the t_near and the min of the t_far skip it: the y slab does not constrain a ray that runs inside it, which is the exact answer for a closed box (Williams et al. 2005).");
                ui.monospace(format!(
                    "max t_near = {}, min t_far = {}: {}",
                    number(record.t_enter),
                    number(record.t_exit),
                    if record.hit { "hit" } else { "miss" }
                ));
            }
            _ => {
                let graze = corner_case();
                // The same ray in f64: the columns compare the precisions, not two rays.
                let graze_f64 = graze.and_then(|g| {
                    let (p, q) = sixty_fourths(g.direction);
                    corner_ray(&bounds, p, q)
                });
                ui.label(
                    RichText::new(format!(
                        "A ray exactly through the corner (0.25, 1.125), direction {}, in f32 and in f64",
                        graze.map_or("—".into(), |g| direction_text(g.direction))
                    ))
                    .strong(),
                );
                egui::Grid::new("corner numbers")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.label("");
                        ui.strong("f32");
                        ui.strong("f64");
                        ui.end_row();
                        let rows: [CornerRow; 3] = [
                            ("max t_near", |g| g.t_enter, |g| g.t_enter),
                            ("min t_far", |g| g.t_exit, |g| g.t_exit),
                            ("× (1 + 2γ(3))", |g| g.t_exit_widened, |g| g.t_exit_widened),
                        ];
                        for (label, in_f32, in_f64) in rows {
                            ui.label(label);
                            ui.monospace(graze.map_or("—".into(), |g| {
                                digits(f64::from(in_f32(&g)), Precision::F32)
                            }));
                            ui.monospace(
                                graze_f64
                                    .map_or("—".into(), |g| digits(in_f64(&g), Precision::F64)),
                            );
                            ui.end_row();
                        }
                    });
                ui.label("Both would be exactly 1: the ray only touches the box at its corner. Rounded in f32, max t_near came out above min t_far, so the plain test misses the box, and every triangle in it. Multiplying t_far by 1 + 2γ(3), the bound on three roundings, makes the test conservative: it never misses a box the exact ray touches (Ize 2013).");
                if let Some(own) = graze_f64 {
                    let said = if own.t_enter > own.t_exit {
                        "In f64 this ray is missed too.".to_owned()
                    } else {
                        match corner_graze(&bounds) {
                            Some(other) => format!(
                                "In f64 this ray is met; f64 misses others, first the ray of direction {}: rounding is smaller, not gone.",
                                direction_text(other.direction)
                            ),
                            None => "In f64 this ray is met, and so is every ray of the search."
                                .to_owned(),
                        }
                    };
                    ui.label(said);
                }
                if let Some(graze) = graze {
                    float_line_ui(ui, &graze);
                }
            }
        }
    }
}

/// A row of the corner's table: its label, and the number in f32 and in f64.
type CornerRow = (
    &'static str,
    fn(&CornerGraze<f32>) -> f32,
    fn(&CornerGraze<f64>) -> f64,
);

/// The corner case in f32 for the lesson's box.
fn corner_case() -> Option<CornerGraze<f32>> {
    let bounds = slab_box();
    corner_graze(&Aabb::new(bounds.min.as_vec2(), bounds.max.as_vec2()))
}

/// How far beside the edge a column's rays are aimed.
fn aside_text(aside: f64) -> String {
    if aside == 0.0 {
        "at the edge".to_owned()
    } else {
        format!("{} aside", number(aside))
    }
}

fn flat_pair(values: [f64; 2]) -> DVec2 {
    DVec2::from_array(values)
}

/// A corner ray's direction as the whole sixty-fourths it was built of.
fn sixty_fourths(direction: [f64; 3]) -> (u32, u32) {
    (
        (direction[0] * 64.0).round() as u32,
        (direction[1] * 64.0).round() as u32,
    )
}

fn direction_text(direction: [f64; 3]) -> String {
    format!(
        "({}, {})/64",
        (direction[0] * 64.0).round(),
        (direction[1] * 64.0).round()
    )
}

/// The f32 numbers either side of 1, one tick each, with the corner's t_near, t_far and
/// widened t_far marked: the floats themselves.
fn float_line_ui(ui: &mut egui::Ui, graze: &CornerGraze<f32>) {
    let (response, painter) =
        ui.allocate_painter(Vec2::new(ui.available_width(), 86.0), egui::Sense::hover());
    let rect = response.rect.shrink2(Vec2::new(16.0, 10.0));
    let mut ticks = vec![1.0f32];
    for _ in 0..6 {
        let low = ticks[0].next_down();
        let high = ticks[ticks.len() - 1].next_up();
        ticks.insert(0, low);
        ticks.push(high);
    }
    let to_x = |value: f32| {
        let position = ticks.iter().position(|&tick| tick >= value).unwrap_or(0) as f32;
        rect.left() + position / (ticks.len() - 1) as f32 * rect.width()
    };
    let y = rect.top() + 24.0;
    let text_colour = ui.visuals().text_color();
    painter.line_segment(
        [egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
        Stroke::new(1.0, text_colour),
    );
    for &tick in &ticks {
        painter.line_segment(
            [
                egui::pos2(to_x(tick), y - 5.0),
                egui::pos2(to_x(tick), y + 5.0),
            ],
            Stroke::new(1.0, text_colour),
        );
    }
    painter.text(
        egui::pos2(to_x(1.0), y + 8.0),
        egui::Align2::CENTER_TOP,
        "1 (exact)",
        egui::FontId::proportional(12.0),
        text_colour,
    );
    let marks = [
        (graze.t_enter, "max t_near", palette::CURRENT, -1.0),
        (graze.t_exit, "min t_far", palette::MISS, 1.0),
        (graze.t_exit_widened, "widened", palette::HIT, 1.0),
    ];
    for (value, name, colour, side) in marks {
        let x = to_x(value);
        let colour = readable(ui, colour);
        painter.circle_filled(egui::pos2(x, y), 4.0, colour);
        let at = if side < 0.0 {
            y - 9.0
        } else {
            y + 24.0 + if name == "widened" { 16.0 } else { 0.0 }
        };
        painter.text(
            egui::pos2(x, at),
            if side < 0.0 {
                egui::Align2::CENTER_BOTTOM
            } else {
                egui::Align2::CENTER_TOP
            },
            name,
            egui::FontId::proportional(12.0),
            colour,
        );
    }
    ui.label(format!(
        "Each tick is one f32 number: they are {} apart above 1 and half that below.",
        number(f64::from(f32::EPSILON))
    ));
}

impl Lesson for CracksLesson {
    crate::staged!();

    fn named(&self) -> Vec<String> {
        Part::ALL
            .iter()
            .map(|part| part.name().to_owned())
            .collect()
    }

    fn show_named(&mut self, name: &str) -> bool {
        match Part::ALL.iter().find(|part| part.name() == name) {
            Some(&part) => {
                self.show_part(part);
                true
            }
            None => false,
        }
    }

    fn share(&self) -> Vec<(String, String)> {
        let scene = &self.stage.scene;
        vec![
            ("part".to_owned(), scene.part.name().to_owned()),
            ("seed".to_owned(), scene.seed.to_string()),
            ("test".to_owned(), scene.test.name().to_owned()),
            ("offset".to_owned(), scene.offset_power.to_string()),
        ]
    }

    fn restore(&mut self, key: &str, value: &str) -> Result<(), String> {
        let scene = &mut self.stage.scene;
        match key {
            "part" => {
                scene.part = *Part::ALL
                    .iter()
                    .find(|part| part.name() == value)
                    .ok_or_else(|| format!("no part '{value}'"))?;
            }
            "seed" => scene.seed = value.parse().map_err(|_| format!("bad seed '{value}'"))?,
            "test" => {
                scene.test = HitTest::from_name(value)
                    .ok_or_else(|| format!("no test '{value}' (fast or watertight)"))?;
            }
            "offset" => {
                let power: i32 = value.parse().map_err(|_| format!("bad offset '{value}'"))?;
                if !OFFSET_POWERS.contains(&power) {
                    return Err(format!("offset 10^{power} is outside 10^0 to 10^6"));
                }
                scene.offset_power = power;
            }
            _ => return Err(format!("this lesson keeps no '{key}'")),
        }
        Ok(())
    }

    fn take_export(&mut self) -> Option<crate::view3d::Export> {
        self.view.take_export()
    }

    fn parts(&self) -> &'static [InspectorPart] {
        &PARTS
    }

    fn inspector_ui(&mut self, ui: &mut egui::Ui, parts: Parts<'_>) {
        let part = self.stage.scene.part;
        if parts.show(&PARTS[0]) {
            match part {
                Part::SharedEdge | Part::FarAway => match self.stage.scene.tested() {
                    Some(tested) => Self::edge_numbers_ui(ui, &tested),
                    None => {
                        ui.label("This ray has no direction once rounded: draw the next.");
                    }
                },
                Part::SlabPlane | Part::Corner => self.slab_numbers_ui(ui),
            }
        }
        if part == Part::FarAway && parts.show(&PARTS[1]) {
            ui.separator();
            let shown_power = self.stage.scene.offset_power;
            ui.label(
                RichText::new(format!(
                    "Far from the origin: {} rays at the shared edge, at each distance",
                    count(SLIP_CASES)
                ))
                .strong(),
            );
            let rows = self.far_rows().to_vec();
            // Two narrow tables, the lesson's point first: how many slipped at each distance
            // (five columns of short headings fit the inspector; in one wide table they sat
            // off to the right, behind a scroll bar nobody saw), then what does grow.
            let distance = |ui: &mut egui::Ui, power: i32| {
                let label = format!("10^{power}");
                if power == shown_power {
                    ui.strong(label);
                } else {
                    ui.label(label);
                }
            };
            ui.label(format!("Slipped through, of {} rays:", count(SLIP_CASES)));
            egui::Grid::new("far rows slipped")
                .striped(true)
                .show(ui, |ui| {
                    ui.strong("mesh\nat");
                    for (precision, test, aside) in SLIP_COLUMNS {
                        let heading = format!("{}\n{}", test.name(), precision.name());
                        let heading = if aside == 0.0 {
                            heading
                        } else {
                            format!("{heading}\n{}", aside_text(aside))
                        };
                        ui.strong(heading).on_hover_text(format!(
                            "the {} test in {}, rays aimed {}",
                            test.name(),
                            precision.name(),
                            aside_text(aside)
                        ));
                    }
                    ui.end_row();
                    for row in &rows {
                        distance(ui, row.power);
                        for value in row.slipped {
                            let colour = if value > 0 {
                                palette::MISS
                            } else {
                                palette::HIT
                            };
                            ui.colored_label(readable(ui, colour), count(value));
                        }
                        ui.end_row();
                    }
                });
            ui.add_space(6.0);
            ui.label("What grows: the spacing of the numbers, and how far off the surface the hit point o + t·d can be placed.");
            egui::Grid::new("far rows spacing")
                .striped(true)
                .show(ui, |ui| {
                    for heading in [
                        "mesh at",
                        "f32 spacing",
                        "f32 point off",
                        "f64 spacing",
                        "f64 point off",
                    ] {
                        ui.strong(heading);
                    }
                    ui.end_row();
                    for row in &rows {
                        distance(ui, row.power);
                        for index in 0..2 {
                            ui.label(number(row.spacing[index]));
                            ui.label(number(row.hit_point_off[index]));
                        }
                        ui.end_row();
                    }
                });
            ui.label("The tests work on differences (a corner minus the ray's start), which stay exact when the ray starts near the mesh: far from the origin the crack does not widen. At the edge itself rounding decides at every distance, and a ray 1e-6 beside it never slips. What grows is the spacing of the numbers themselves: the corners snap to it, and the hit point o + t·d can only be placed to within it, off the surface by up to about that spacing. A shadow or bounce ray from it must start at least that far off the surface.");
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui) {
        self.controls_ui(ui);
        let scene = &self.stage.scene;
        match scene.part {
            Part::SharedEdge | Part::FarAway => {
                let Some(tested) = scene.tested() else {
                    ui.label("This ray has no direction once rounded: draw the next.");
                    return;
                };
                let zoom = scene.zoom_power;
                if !self.logged {
                    self.logged = true;
                    let said = |tested: &EdgeTest| match tested.hit {
                        Some(_) => "hits",
                        None => "slips through",
                    };
                    log::info!(
                        "accelviz: cracks: the {} test in f32 {}, in f64 {}",
                        tested[0].test.name(),
                        said(&tested[0]),
                        said(&tested[1])
                    );
                }
                // What the marks are, once for both views: the dot is the exact ray,
                // the triangles and edge are drawn at their stored corners, and each
                // ring is what that triangle's test computed, so the dot may sit on
                // one side of the drawn edge while a test puts it on the other.
                ui.label(
                    RichText::new("Seen along the ray: the dot is where the exact ray meets the plane (green: the test hits); each ring is where A's or B's test put it, rounding and all; the edge is drawn at the stored corners.")
                        .small(),
                );
                let available = ui.available_size();
                // Each precision: its view seen along the ray, and under it the numbers.
                let values_height =
                    6.0 * (ui.text_style_height(&egui::TextStyle::Monospace) + 8.0) + 6.0;
                let row_height = (available.y - 12.0) / 2.0;
                // The numbers under each view, or, where that would leave the view a strip
                // its caption covers (a lecture slide's large text), beside it, the 3D view
                // narrower to make room for every digit.
                let beside = row_height - values_height < 150.0;
                let left_share = if beside { 0.3 } else { 0.4 };
                let left = Vec2::new((available.x * left_share).max(60.0), available.y);
                let right_width = available.x - left.x - 2.0 * ui.spacing().item_spacing.x - 4.0;
                let view_size = if beside {
                    Vec2::new(right_width * 0.45, row_height - 4.0)
                } else {
                    Vec2::new(right_width, row_height - values_height)
                }
                .max(Vec2::splat(60.0));
                ui.horizontal(|ui| {
                    self.view3d_ui(ui, left, &tested[0]);
                    ui.vertical(|ui| {
                        for (view, tested) in self.along.iter_mut().zip(&tested) {
                            let mut view_and_values = |ui: &mut egui::Ui| {
                                Self::along_ui(ui, view, view_size, tested, zoom);
                                // Every digit of f64 is wide: at lecture scale the numbers
                                // scroll sideways rather than push the inspector off.
                                egui::ScrollArea::horizontal()
                                    .id_salt(("crack values scroll", tested.precision.name()))
                                    .max_width(ui.available_width().max(60.0))
                                    .show(ui, |ui| Self::values_ui(ui, tested));
                            };
                            if beside {
                                ui.horizontal_top(view_and_values);
                            } else {
                                ui.scope(|ui| {
                                    ui.set_max_width(right_width.max(60.0));
                                    view_and_values(ui)
                                });
                            }
                        }
                    });
                });
            }
            Part::SlabPlane | Part::Corner => self.slab_ui(ui),
        }
    }
}
