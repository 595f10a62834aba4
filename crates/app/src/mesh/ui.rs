//! What every 3D lesson with a mesh shows above its view: the mesh and structure choosers, and
//! the progress of a large mesh read or built aside, with its cancel button.

use accelviz_core::Structure;
use accelviz_core::trade::Precision;
use accelviz_scene::builtin::BUILTINS;

use super::scene::MeshScene;
use super::tree::MeshTree;
use crate::background::Derived;

/// The mesh and structure choosers every 3D lesson with a mesh shows. Returns whether the
/// mesh was replaced (a traced ray then no longer fits it).
pub fn mesh_and_structure_ui(
    ui: &mut egui::Ui,
    scene: &mut MeshScene,
    structure: &mut Structure,
) -> bool {
    let replaced = mesh_ui(ui, scene);
    ui.separator();
    egui::ComboBox::from_label("structure")
        .selected_text(structure.name())
        .show_ui(ui, |ui| {
            for entry in accelviz_core::CATALOGUE {
                let chosen = structure.entry().name == entry.name;
                if ui
                    // The name the lesson texts, links and CLI use, then what it is.
                    .selectable_label(
                        chosen,
                        format!("{}: {}", entry.name, entry.structure.title()),
                    )
                    .on_hover_text(entry.about)
                    .clicked()
                {
                    *structure = entry.structure.with_width(structure.width());
                }
            }
        });
    crate::views::width_ui(ui, structure);
    replaced
}

/// The built-in meshes to choose from (an opened OBJ is shown by its name); true when the
/// mesh was replaced.
pub fn mesh_ui(ui: &mut egui::Ui, scene: &mut MeshScene) -> bool {
    let mut replaced = false;
    let current = scene.name.clone();
    egui::ComboBox::from_label("mesh")
        .selected_text(current.trim_start_matches("builtin:").to_owned())
        .show_ui(ui, |ui| {
            for builtin in BUILTINS {
                let name = format!("builtin:{}", builtin.name);
                if ui
                    // The name links and lesson texts use, then what it is.
                    .selectable_label(
                        current == name,
                        format!("{}: {}", builtin.name, builtin.about),
                    )
                    .on_hover_text(builtin.about)
                    .clicked()
                {
                    scene.replace((builtin.make)());
                    scene.name = name;
                    replaced = true;
                }
            }
        });
    replaced
}

/// While a large mesh is read: its progress with a cancel button that keeps the mesh shown,
/// and a repaint asked for each frame, so the mesh comes in when the read ends (a lesson that
/// asked for none sat on "reading…" until the mouse moved). True while reading.
pub fn reading_ui(ui: &mut egui::Ui, scene: &mut MeshScene) -> bool {
    let Some(loading) = &scene.loading else {
        return false;
    };
    let (name, progress) = (loading.name.clone(), loading.progress());
    ui.horizontal(|ui| {
        if ui
            .button("cancel")
            .on_hover_text("Stop reading, and keep the mesh on screen")
            .clicked()
        {
            scene.loading = None;
        }
        ui.add(
            egui::ProgressBar::new(progress)
                .desired_width(260.0)
                .text(format!("reading {name}: {:.0} %", progress * 100.0)),
        );
    });
    ui.ctx().request_repaint();
    true
}

/// While a large mesh is read or its structure built: a progress line with a cancel button
/// that goes back to exactly what is on screen (the UI keeps drawing meanwhile): a read
/// stops and the mesh shown stays; a build stops and the mesh, `structure` and `precision`
/// go back to the tree shown.
pub fn loading_ui(
    ui: &mut egui::Ui,
    scene: &mut MeshScene,
    tree: &mut Derived<crate::mesh::scene::TreeKey, MeshTree>,
    (structure, precision): (&mut Structure, &mut Precision),
) {
    let building = tree.working_for();
    let line = match (&scene.loading, building) {
        (Some(loading), _) => Some((
            format!("reading {}", loading.name),
            Some(loading.progress()),
        )),
        (None, Some(working)) => Some((
            format!(
                "building the structure over {} triangles… {:.1} s",
                scene.mesh.triangles.len(),
                working.as_secs_f64()
            ),
            None,
        )),
        (None, None) => None,
    };
    let Some((text, progress)) = line else { return };
    ui.horizontal(|ui| {
        // The button first, so it stays where it is when reading turns into building.
        if ui
            .button("cancel")
            .on_hover_text("Stop, and keep what is on screen: its mesh and its structure")
            .clicked()
        {
            tree.cancel();
            if scene.loading.is_some() {
                // A file being read: the mesh on screen is still the one before it.
                scene.loading = None;
            } else if let Some(&(revision, shown, shown_precision)) = tree.key() {
                // A build: back to the tree on screen, over its mesh.
                if revision != scene.revision {
                    scene.go_back();
                }
                *structure = shown;
                *precision = shown_precision;
            }
        }
        match progress {
            Some(progress) => ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(260.0)
                    .text(format!("{text}: {:.0} %", progress * 100.0)),
            ),
            None => {
                ui.add(egui::Spinner::new());
                ui.label(text)
            }
        };
    });
    ui.ctx().request_repaint();
}
