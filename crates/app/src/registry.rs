//! Every lesson, listed once: its file (embedded in the binary) and the code that shows it,
//! in the lecture's order. Adding a lesson is one entry here, one RON file and one Rust file.

use std::path::Path;

use crate::lesson::Lesson;
use crate::lesson_file::LessonText;
use crate::lessons::{
    bounding_volumes, build_steps, bvh, cost_split, cracks, grid, hashing, heat, kd, mesh_tree,
    near_first, quadtree, recap, slab, slab3d, splits, trade, trivial,
};

/// One lesson: where its file lives, the file as embedded, and what shows it.
pub struct LessonEntry {
    /// The file's path in the repository.
    pub path: &'static str,
    /// Its text, embedded at build time.
    pub embedded: &'static str,
    /// Makes the lesson from its parsed file.
    pub make: fn(LessonText) -> Box<dyn Lesson>,
}

macro_rules! lesson {
    ($file:literal, $make:expr) => {
        LessonEntry {
            path: concat!("assets/lessons/", $file),
            embedded: include_str!(concat!("../../../assets/lessons/", $file)),
            make: $make,
        }
    };
}

/// The lessons, in the lecture's order.
pub const LESSONS: [LessonEntry; 20] = [
    lesson!("01-trivial.ron", |text| Box::new(
        trivial::TrivialLoop::new(text)
    )),
    lesson!("02-bounding-volumes.ron", |text| {
        Box::new(bounding_volumes::BoundingVolumesLesson::new(text))
    }),
    lesson!("03-slab-test.ron", |text| Box::new(slab::SlabLesson::new(
        text
    ))),
    lesson!("04-bvh.ron", |text| Box::new(bvh::BvhLesson::new(text))),
    lesson!("05-kd-tree.ron", |text| Box::new(kd::KdLesson::new(text))),
    lesson!("06-near-first.ron", |text| {
        Box::new(near_first::NearFirstLesson::new(text))
    }),
    lesson!("07-middle-median-sah.ron", |text| {
        Box::new(splits::SplitsLesson::new(text))
    }),
    lesson!("08-cost-optimised-split.ron", |text| {
        Box::new(cost_split::CostSplitLesson::new(text))
    }),
    lesson!("09-building-is-optimisation.ron", |text| {
        Box::new(build_steps::BuildStepsLesson::new(text))
    }),
    lesson!("10-recap.ron", |text| Box::new(recap::RecapLesson::new(
        text
    ))),
    lesson!("11-slab-3d.ron", |text| Box::new(
        slab3d::Slab3dLesson::new(text)
    )),
    lesson!("12-mesh-bvh.ron", |text| Box::new(
        mesh_tree::MeshTreeLesson::new(text)
    )),
    lesson!("13-kd-3d.ron", |text| Box::new(
        mesh_tree::MeshTreeLesson::new(text)
    )),
    lesson!("14-heat-maps.ron", |text| Box::new(heat::HeatLesson::new(
        text
    ))),
    // Lesson 4's lesson, on a wide BVH.
    lesson!("15-four-boxes.ron", |text| Box::new(bvh::BvhLesson::new(
        text
    ))),
    lesson!("16-trade-lab.ron", |text| Box::new(
        trade::TradeLesson::new(text)
    )),
    lesson!("17-cracks.ron", |text| Box::new(cracks::CracksLesson::new(
        text
    ))),
    lesson!("18-uniform-grid.ron", |text| Box::new(
        grid::GridLesson::new(text)
    )),
    lesson!("19-hashing.ron", |text| Box::new(hashing::HashLesson::new(
        text
    ))),
    lesson!("20-quadtree.ron", |text| Box::new(
        quadtree::QuadtreeLesson::new(text)
    )),
];

/// A lesson whose built-in file is broken too (a build of the app that its tests would have
/// refused): shown as an entry that says why.
#[derive(Clone, Debug)]
pub struct BrokenLesson {
    /// What to call it in the list.
    pub title: String,
    /// File, line and problem.
    pub message: String,
}

/// Every lesson from the embedded files.
pub fn registry() -> Vec<Result<Box<dyn Lesson>, BrokenLesson>> {
    registry_from(None)
}

/// Every lesson, reading each lesson file from `assets_dir` (the folder holding `lessons/`)
/// where it exists there, so a lecturer can edit a lesson's text or scene and restart the app
/// without rebuilding it. A file on disk that is broken keeps its lesson in the list: the
/// built-in copy is shown, with a notice naming the file, line and problem.
pub fn registry_from(assets_dir: Option<&Path>) -> Vec<Result<Box<dyn Lesson>, BrokenLesson>> {
    LESSONS
        .iter()
        .map(|entry| {
            let on_disk = assets_dir.and_then(|dir| {
                let file = dir.join(entry.path.trim_start_matches("assets/"));
                file.is_file().then(|| {
                    let shown = file.display().to_string();
                    accelviz_scene::error::read_text(&shown)
                        .and_then(|text| LessonText::parse(&text, &shown))
                })
            });
            let embedded = LessonText::parse(entry.embedded, entry.path);
            match (on_disk, embedded) {
                (Some(Ok(text)), _) | (None, Ok(text)) => Ok((entry.make)(text)),
                (Some(Err(problem)), Ok(text)) => {
                    let mut lesson = (entry.make)(text);
                    lesson.stage_mut().notice = Some(format!(
                        "{problem}. This is the built-in copy of the lesson; fix the file and restart to see yours."
                    ));
                    Ok(lesson)
                }
                (_, Err(problem)) => Err(BrokenLesson {
                    title: entry.path.to_owned(),
                    message: problem.to_string(),
                }),
            }
        })
        .collect()
}
