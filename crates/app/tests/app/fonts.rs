//! The browser app's cut-down fonts (`accelviz_app::fonts`) hold every character accelviz
//! writes that the desktop's fonts (egui's full ones) hold, so the browser shows the lessons
//! in the same glyphs as the desktop.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use egui::{FontFamily, FontId};

/// The files accelviz's words come from: the sources of the crates the app shows text from,
/// and the lesson and lecture files.
fn text_files() -> Vec<PathBuf> {
    fn walk(directory: &Path, files: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(directory).expect("a readable directory") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                walk(&path, files);
            } else if path
                .extension()
                .is_some_and(|extension| extension == "rs" || extension == "ron")
            {
                files.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![root.join("assets/lecture.txt")];
    for directory in [
        "crates/app/src",
        "crates/quiz/src",
        "crates/scene/src",
        "crates/core/src",
        "assets/lessons",
    ] {
        walk(&root.join(directory), &mut files);
    }
    files
}

#[test]
fn the_web_fonts_cover_every_character_the_app_writes() {
    let mut written = BTreeSet::new();
    let files = text_files();
    assert!(files.len() > 100, "found {} files", files.len());
    for file in &files {
        let text = std::fs::read_to_string(file).expect("a text file");
        written.extend(text.chars().filter(|c| !c.is_control()));
    }
    // The characters that make the test worth its name are there.
    for expected in ['×', '≤', '→', 'α', '…', '²'] {
        assert!(written.contains(&expected), "{expected}");
    }
    let web = egui::Context::default();
    web.set_fonts(accelviz_app::fonts::web_fonts());
    let desktop = egui::Context::default();
    desktop.set_fonts(egui::FontDefinitions::default());
    for context in [&web, &desktop] {
        // A pass takes the fonts in; its font atlas, meant for a renderer, is dropped.
        let mut output = context.run_ui(egui::RawInput::default(), |_| {});
        output.textures_delta.clear();
    }
    for family in [FontFamily::Proportional, FontFamily::Monospace] {
        let font = FontId::new(14.0, family.clone());
        let on_desktop: Vec<char> = desktop.fonts_mut(|fonts| {
            written
                .iter()
                .copied()
                .filter(|&c| fonts.has_glyph(&font, c))
                .collect()
        });
        assert!(on_desktop.contains(&'×') && on_desktop.contains(&'α'));
        let missing: String = web.fonts_mut(|fonts| {
            on_desktop
                .iter()
                .filter(|&&c| !fonts.has_glyph(&font, c))
                .collect()
        });
        assert!(
            missing.is_empty(),
            "the browser's {family:?} font lacks {missing:?}, which the desktop's has: add them to scripts/subset-fonts and run it"
        );
    }
}
