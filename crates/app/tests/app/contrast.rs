//! Text contrast, computed from the themes' own colours: every text colour the app uses on
//! every background it uses it on reads at 4.5:1 or better (WCAG AA), in every theme; canvas
//! labels on their plate over anything, white included; the 3D view's depth colours stand
//! out of its background (3:1, WCAG's figure for lines).

use accelviz_app::canvas::{PLATE, contrast_ratio, depth_color, over, palette, readable_on};
use accelviz_app::lecture::Theme;
use egui::Color32;

/// Every pair that fails, as "what: ratio": the text (translucent, as egui's weak text is)
/// as it is seen, blended over its background.
fn failures(pairs: &[(String, Color32, Color32)], least: f32) -> Vec<String> {
    pairs
        .iter()
        .filter_map(|(what, text, background)| {
            let ratio = contrast_ratio(over(*text, *background), *background);
            (ratio < least).then(|| format!("{what}: {ratio:.2}:1 ({text:?} on {background:?})"))
        })
        .collect()
}

/// The text colour a widget in these visuals draws: the theme's override, else its own.
fn text_of(visuals: &egui::Visuals, own: Color32) -> Color32 {
    visuals.override_text_color.unwrap_or(own)
}

#[test]
fn every_text_reads_at_4_5_to_1_in_every_theme() {
    let palette_colours = [
        ("ray", palette::RAY),
        ("hit", palette::HIT),
        ("miss", palette::MISS),
        ("current", palette::CURRENT),
        ("box", palette::BOX),
        ("sphere", palette::SPHERE),
        ("x axis", palette::X_AXIS),
        ("y axis", palette::Y_AXIS),
        ("z axis", palette::Z_AXIS),
    ];
    let mut problems = Vec::new();
    for theme in Theme::ALL {
        let v = theme.visuals();
        let name = theme.name();
        let mut pairs = Vec::new();
        for (surface, background) in [
            ("panel", v.panel_fill),
            ("window", v.window_fill),
            ("text field", v.extreme_bg_color),
            ("grid stripe", over(v.faint_bg_color, v.panel_fill)),
        ] {
            pairs.push((
                format!("{name}: text on {surface}"),
                v.text_color(),
                background,
            ));
            pairs.push((
                format!("{name}: weak text on {surface}"),
                v.weak_text_color(),
                background,
            ));
            for (role, colour) in palette_colours {
                pairs.push((
                    format!("{name}: {role} text on {surface}"),
                    readable_on(colour, background),
                    background,
                ));
            }
        }
        for (state, widget) in [
            ("inactive", &v.widgets.inactive),
            ("hovered", &v.widgets.hovered),
            ("active", &v.widgets.active),
        ] {
            pairs.push((
                format!("{name}: {state} button text"),
                text_of(&v, widget.fg_stroke.color),
                over(widget.weak_bg_fill, v.panel_fill),
            ));
        }
        pairs.push((
            format!("{name}: selected button text"),
            text_of(&v, v.selection.stroke.color),
            v.selection.bg_fill,
        ));
        // Canvas labels sit on the plate, over whatever is drawn there: the canvas, a shape
        // of the label's own colour (green on a green hit), black or white.
        for (role, colour) in palette_colours
            .into_iter()
            .chain([
                ("note", Color32::from_gray(220)),
                ("caption", Color32::WHITE),
            ])
            .chain((0..12).map(|depth| ("depth label", depth_color(depth, true))))
        {
            for (under, below) in [
                ("the canvas", v.extreme_bg_color),
                ("white", Color32::WHITE),
                ("black", Color32::BLACK),
                ("its own colour", colour),
            ] {
                pairs.push((
                    format!("{name}: {role} label on its plate over {under}"),
                    colour,
                    over(PLATE, below),
                ));
            }
        }
        problems.extend(failures(&pairs, 4.5));
        // Lines and boxes (not text): the depth colours against the 3D view's background.
        let lines: Vec<(String, Color32, Color32)> = (0..12)
            .map(|depth| {
                (
                    format!("{name}: depth {depth}'s boxes on the 3D view"),
                    depth_color(depth, v.dark_mode),
                    v.extreme_bg_color,
                )
            })
            .collect();
        problems.extend(failures(&lines, 3.0));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_contrast_ratio_is_wcag_s() {
    assert!((contrast_ratio(Color32::BLACK, Color32::WHITE) - 21.0).abs() < 0.01);
    assert!((contrast_ratio(Color32::WHITE, Color32::WHITE) - 1.0).abs() < 1e-6);
    // Two values WCAG's examples give: #767676 on white is 4.54:1, #777777 4.48:1.
    assert!((contrast_ratio(Color32::from_gray(0x76), Color32::WHITE) - 4.54).abs() < 0.01);
    assert!((contrast_ratio(Color32::from_gray(0x77), Color32::WHITE) - 4.48).abs() < 0.01);
}

/// Lines and shapes on the 2D canvas, computed from each theme's own canvas colour: every
/// palette colour as a view draws it (the canvas's `ink`: the ray, a hit shape, the shape
/// looked at now, a missed one), opaque, as a shape's fill (faded to 200) and as the ray beyond
/// the closest hit (faded to 70), stands out of the canvas at 3:1 (WCAG's figure for
/// graphical objects) in every theme. On the high-contrast theme's white the ray was 1.9:1,
/// a hit shape 1.6:1, the ray beyond the hit 1.2:1.
#[test]
fn every_line_and_shape_stands_out_at_3_to_1_in_every_theme() {
    use accelviz_app::canvas::{faded, ink_on};
    let palette_colours = [
        ("ray", palette::RAY),
        ("hit", palette::HIT),
        ("miss", palette::MISS),
        ("current", palette::CURRENT),
        ("box", palette::BOX),
        ("sphere", palette::SPHERE),
        ("x axis", palette::X_AXIS),
        ("y axis", palette::Y_AXIS),
        ("z axis", palette::Z_AXIS),
    ];
    let mut lines = Vec::new();
    for theme in Theme::ALL {
        let canvas = theme.visuals().extreme_bg_color;
        for (role, colour) in palette_colours {
            for (how, alpha) in [("line", 255), ("shape fill", 200), ("faded line", 70)] {
                lines.push((
                    format!("{}: {role} {how} on the canvas", theme.name()),
                    ink_on(faded(colour, alpha), canvas),
                    canvas,
                ));
            }
        }
    }
    let problems = failures(&lines, 3.0);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The theme for lit rooms, seen: lesson 1 (the ray, the shapes hit, missed and looked at
/// now, the ray beyond the closest hit) and lesson 18 (a grid's current cell and its label)
/// part-way, on the high-contrast theme's white.
#[test]
fn the_high_contrast_theme_draws_the_canvas_to_be_seen() {
    let mut harness = crate::common::app_harness();
    harness.state_mut().theme = Theme::HighContrast;
    for (lesson, name) in [
        (0usize, "lesson_01_high_contrast"),
        (17, "lesson_18_high_contrast"),
    ] {
        harness.state_mut().selected = lesson;
        harness.run();
        let frames = harness
            .state()
            .lesson()
            .expect("a lesson")
            .stage()
            .timeline
            .len;
        harness
            .state_mut()
            .lesson_mut()
            .expect("a lesson")
            .stage_mut()
            .timeline
            .shown = frames * 2 / 3;
        harness.run();
        harness.snapshot(name);
    }
}
