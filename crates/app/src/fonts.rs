//! The fonts: egui's own two, Ubuntu Light for text and Hack for code and numbers.
//!
//! The desktop app uses egui's bundled copies (eframe's `default_fonts`). The browser app,
//! which is downloaded, carries them cut down to the characters accelviz writes (Latin,
//! Greek, punctuation, arrows, operators: `fonts/`, made by `scripts/subset-fonts`): 0.22 MB
//! instead of 0.67 (0.11 MB gzipped instead of 0.32). Any other character (a mesh file's
//! name, say) the browser draws for it (eframe's canvas glyphs), so nothing shows as a box.

use std::sync::Arc;

use egui::{FontData, FontDefinitions, FontFamily};

/// Ubuntu Light, cut down (Ubuntu Font Licence 1.0; `fonts/UFL.txt`).
const TEXT_FONT: &[u8] = include_bytes!("../fonts/UbuntuLight-accelviz-subset.ttf");

/// Hack, cut down (MIT and Bitstream Vera licences; `fonts/Hack-Regular.txt`).
const CODE_FONT: &[u8] = include_bytes!("../fonts/Hack-accelviz-subset.ttf");

/// The browser app's fonts: the families egui's defaults make (text in Ubuntu Light; code in
/// Hack, falling back to Ubuntu Light for what Hack lacks), from the cut-down files.
pub fn web_fonts() -> FontDefinitions {
    let mut fonts = FontDefinitions::empty();
    fonts.font_data.insert(
        "text".to_owned(),
        Arc::new(FontData::from_static(TEXT_FONT)),
    );
    fonts.font_data.insert(
        "code".to_owned(),
        Arc::new(FontData::from_static(CODE_FONT)),
    );
    fonts
        .families
        .insert(FontFamily::Proportional, vec!["text".to_owned()]);
    fonts.families.insert(
        FontFamily::Monospace,
        vec!["code".to_owned(), "text".to_owned()],
    );
    fonts
}
