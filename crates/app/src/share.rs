//! A view as a link: the lesson, its step, its scene (the 2D scene with its ray and settings,
//! or the built-in mesh) and what the lesson lets you choose (the structure, the camera),
//! written as `lesson=4&step=12&structure=bvh:sah-sweep&scene=…`. In the browser it is the
//! page's URL fragment (`#lesson=4&…`); on the desktop a string to copy and paste, or a file.
//! Opening it restores exactly that view; text that is not such a state is refused with a
//! reason (and the app stays on its default lesson).

use crate::app::{AccelvizApp, Mode};

/// The key of a named ray or preset of the lesson file (`show=r2`).
pub const SHOW: &str = "show";

/// The name of the lesson file's named ray or preset that makes `scene`, if one does: the
/// lesson's scene with that ray, or that preset's scene.
pub fn named_scene(
    text: &crate::lesson_file::LessonText,
    scene: &accelviz_scene::document::Scene2d,
) -> Option<String> {
    let ray = text.file.named_rays.iter().find(|named| {
        let mut with_ray = text.scene.clone();
        with_ray.ray_origin = glam::DVec2::new(named.ray.origin.0, named.ray.origin.1);
        with_ray.ray_toward = glam::DVec2::new(named.ray.toward.0, named.ray.toward.1);
        with_ray == *scene
    });
    if let Some(named) = ray {
        return Some(named.name.clone());
    }
    text.file
        .presets
        .iter()
        .find(|preset| {
            accelviz_scene::document::Scene2d::from_document(preset.scene.clone(), &preset.name)
                .is_ok_and(|preset_scene| preset_scene == *scene)
        })
        .map(|preset| preset.name.clone())
}

/// The state string's version; a link of another version is refused, not misread.
pub const VERSION: &str = "1";

/// The longest state accepted (a scene of a few thousand shapes; larger ones are saved as
/// files).
pub const MOST_BYTES: usize = 256 * 1024;

/// A view, as shared.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewState {
    /// The lesson's number in the list, from 0.
    pub lesson: usize,
    /// The animation's step.
    pub step: usize,
    /// The lesson's own choices (structure, camera, mesh, …), in order.
    pub values: Vec<(String, String)>,
    /// A 2D scene document (RON), when it is not the lesson's own.
    pub scene: Option<String>,
}

impl ViewState {
    /// The state as a string (safe in a URL fragment: words, `=` and `&`).
    pub fn encode(&self) -> String {
        let mut text = format!("v={VERSION}&lesson={}&step={}", self.lesson + 1, self.step);
        for (key, value) in &self.values {
            text.push_str(&format!("&{key}={}", escape(value)));
        }
        if let Some(scene) = &self.scene {
            text.push_str("&scene=");
            text.push_str(&base64url(compact(scene).as_bytes()));
        }
        text
    }

    /// Reads a state string (a leading `#` or a whole link is allowed).
    pub fn decode(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let text = text.rsplit_once('#').map_or(text, |(_, fragment)| fragment);
        if text.len() > MOST_BYTES {
            return Err(format!(
                "it is {} bytes; a link holds at most {MOST_BYTES}",
                text.len()
            ));
        }
        let mut state = ViewState::default();
        let mut version = None;
        let mut lesson = None;
        for pair in text.split('&').filter(|pair| !pair.is_empty()) {
            let (key, value) = pair
                .split_once('=')
                .ok_or_else(|| format!("'{}' is not key=value", shorten(pair)))?;
            let value = unescape(value).ok_or_else(|| format!("{key}: a broken %-escape"))?;
            match key {
                "v" => version = Some(value),
                "lesson" => {
                    lesson = Some(
                        value
                            .parse::<usize>()
                            .ok()
                            .filter(|number| *number >= 1)
                            .ok_or_else(|| {
                                format!(
                                    "lesson '{}' is not a lesson number (1, 2, 3, …)",
                                    shorten(&value)
                                )
                            })?
                            - 1,
                    );
                }
                "step" => {
                    state.step = value
                        .parse()
                        .map_err(|_| format!("step '{}' is not a whole number", shorten(&value)))?;
                }
                "scene" => {
                    let bytes = unbase64url(&value).ok_or("the scene is not base64url")?;
                    let scene =
                        String::from_utf8(bytes).map_err(|_| "the scene is not text".to_owned())?;
                    state.scene = Some(scene);
                }
                _ if key.chars().all(|c| c.is_ascii_alphanumeric() || c == '-') => {
                    state.values.push((key.to_owned(), value));
                }
                _ => return Err(format!("'{}' is not a key of a view", shorten(key))),
            }
        }
        match version.as_deref() {
            Some(VERSION) => {}
            Some(other) => {
                return Err(format!(
                    "it is version {}; this accelviz reads version {VERSION}",
                    shorten(other)
                ));
            }
            None => return Err("it has no version (v=1): it is not an accelviz view".into()),
        }
        state.lesson = lesson.ok_or("it names no lesson")?;
        Ok(state)
    }
}

/// The app's side of sharing: a view made into a state, a state opened, and the Share window.
impl AccelvizApp {
    /// The view as a shared state: the lesson, its step, its scene when it is not the
    /// lesson's own, and the lesson's choices. An error says what cannot go in a link (a mesh
    /// opened from a file).
    pub fn share_state(&self) -> Result<ViewState, String> {
        let lesson = self.lesson().ok_or("this lesson did not load")?;
        let stage = lesson.stage();
        let mut state = ViewState {
            lesson: self.selected,
            step: stage.timeline.shown,
            values: lesson.share(),
            scene: None,
        };
        if let Some(flat) = stage.scene.flat()
            && flat.scene != lesson.text().scene
        {
            // A named ray or preset of the lesson file goes by its name, not as a scene.
            match named_scene(lesson.text(), &flat.scene) {
                Some(name) => state.values.insert(0, (SHOW.to_owned(), name)),
                None => state.scene = Some(flat.scene.to_ron()),
            }
        }
        // A 2D view the user moved (zoomed or panned): where it is, as they see it.
        if let Some(flat) = stage.scene.flat()
            && flat.view.placed
            && flat.view.fitted_size.is_none()
        {
            state.values.push(view_value(&flat.view));
        }
        let is_3d = stage.scene.flat().is_none() && stage.scene.noun() == "mesh";
        if is_3d && !state.values.iter().any(|(key, _)| key == "mesh") {
            return Err(
                "a mesh opened from a file cannot go in a link: share the file, or pick a built-in mesh. A clicked ray can be shared as a line of a ray file: its button is under the ray in the inspector (\"copy as a ray-file line\").".into(),
            );
        }
        if state.encode().len() > MOST_BYTES {
            return Err("the scene is too large for a link: save it as a file instead".into());
        }
        Ok(state)
    }

    /// Opens a shared view (a state string, a link, or a file holding one): exactly that
    /// lesson, scene, choices and step. On any problem the app shows its first lesson and the
    /// error says why.
    pub fn open_state(&mut self, text: &str) -> Result<(), String> {
        let result = self.apply_state(text);
        if let Err(problem) = &result {
            log::warn!("accelviz: the shared view could not be opened: {problem}");
            // Nothing half-opened: back to the first lesson, as it starts.
            if let Some(lesson) = self.lesson_mut() {
                lesson.stage_mut().reset_scene();
            }
            self.selected = 0;
            self.pending_step = None;
            self.status = Some((
                format!(
                    "The shared view could not be opened ({problem}); this is the first lesson."
                ),
                true,
            ));
        }
        result
    }

    fn apply_state(&mut self, text: &str) -> Result<(), String> {
        let state = ViewState::decode(text)?;
        if state.lesson >= self.lessons.len() {
            return Err(format!(
                "lesson {} does not exist; there are {}",
                state.lesson + 1,
                self.lessons.len()
            ));
        }
        self.mode = Mode::Lessons;
        self.lecture = None;
        self.selected = state.lesson;
        let lesson = self.lesson_mut().ok_or("that lesson did not load")?;
        lesson.stage_mut().reset_scene();
        if let Some(scene) = &state.scene {
            lesson.stage_mut().scene.open("the link's scene", scene)?;
        }
        for (key, value) in &state.values {
            if key == SHOW {
                if !lesson.show_named(value) {
                    return Err(format!(
                        "this lesson has no ray or preset \"{value}\"; it has: {}",
                        lesson.named().join(", ")
                    ));
                }
            } else if key == VIEW {
                let view = parse_view(value)?;
                if let Some(flat) = lesson.stage_mut().scene.as_flat() {
                    flat.view = view;
                }
            } else {
                lesson.restore(key, value)?;
            }
        }
        lesson.stage_mut().timeline.playing = false;
        self.pending_step = Some(state.step);
        self.status = Some(("Opened a shared view.".into(), false));
        log::info!(
            "accelviz: opened a shared view of lesson {}",
            state.lesson + 1
        );
        Ok(())
    }

    /// Applies a shared view's step once the lesson's animation knows its steps.
    pub(crate) fn apply_pending_step(&mut self) {
        let Some(step) = self.pending_step else {
            return;
        };
        let Some(lesson) = self.lesson_mut() else {
            return;
        };
        // A lesson still building what it animates (a 3D lesson's tree, in a Web Worker in the
        // browser) has no caption yet: the step waits for it.
        if lesson.building().is_some() {
            return;
        }
        let animated = lesson.caption().is_some();
        let timeline = &mut lesson.stage_mut().timeline;
        if !animated {
            self.pending_step = None;
        } else if timeline.len > 0 {
            timeline.shown = step.min(timeline.len);
            self.pending_step = None;
        }
    }

    /// The share window: the view's link to copy, and a field to open one.
    pub(crate) fn share_window_ui(&mut self, ctx: &egui::Context) {
        let Some(mut typed) = self.share_window.take() else {
            return;
        };
        // Escape closes it, as it closes a menu.
        let mut open = !ctx.input(|input| input.key_pressed(egui::Key::Escape));
        let mut opened = None;
        let state = self.share_state().map(|state| state.encode());
        egui::Window::new("Share this view")
            .open(&mut open)
            .collapsible(false)
            .default_width(520.0)
            .show(ctx, |ui| {
                match &state {
                    Ok(encoded) => {
                        let link = crate::files::page_link(encoded);
                        let about = ui.label("This link opens exactly this view: the lesson, its scene and ray, its choices, its zoom and the step.");
                        let mut shown = link.clone();
                        ui.add(
                            egui::TextEdit::multiline(&mut shown)
                                .desired_rows(3)
                                .desired_width(f32::INFINITY),
                        )
                        .labelled_by(about.id);
                        if ui.button("Copy").clicked() {
                            ui.ctx().copy_text(link);
                        }
                    }
                    Err(problem) => {
                        ui.colored_label(crate::canvas::readable(ui, crate::canvas::palette::MISS), problem);
                    }
                }
                ui.separator();
                let label = ui.label("Open a shared view (paste a link or its text):");
                let field = ui
                    .add(egui::TextEdit::singleline(&mut typed).desired_width(f32::INFINITY))
                    .labelled_by(label.id);
                let enter = field.lost_focus() && ui.input(|input| input.key_pressed(egui::Key::Enter));
                if ui.button("Open").clicked() || enter {
                    opened = Some(typed.clone());
                }
            });
        if let Some(text) = opened
            && self.open_state(&text).is_ok()
        {
            return;
        }
        if open {
            self.share_window = Some(typed);
        }
    }
}

/// The key of a traversal order.
pub const ORDER: &str = "order";

/// A traversal order as a value: its name (`near-first`, `file-order`).
pub fn order_value(order: accelviz_core::Order) -> (String, String) {
    (ORDER.into(), order.name().into())
}

/// An order from its value.
pub fn parse_order(value: &str) -> Result<accelviz_core::Order, String> {
    accelviz_core::Order::from_name(value).ok_or_else(|| {
        let names: Vec<&str> = accelviz_core::Order::ALL
            .iter()
            .map(|order| order.name())
            .collect();
        format!(
            "order '{}' is not one of {}",
            shorten(value),
            names.join(", ")
        )
    })
}

/// A structure as a value: its catalogue name.
pub fn structure_value(structure: &accelviz_core::Structure) -> (String, String) {
    ("structure".into(), structure.name())
}

/// A structure from its value.
pub fn parse_structure(value: &str) -> Result<accelviz_core::Structure, String> {
    accelviz_core::Structure::parse(value).map_err(|error| error.to_string())
}

/// A 3D view's camera as a value: yaw, pitch, distance, pan x y z, `p`erspective or
/// `o`rthographic (numbers as Rust prints them, so they read back exactly).
pub fn camera_value(orbit: &crate::view3d::Orbit) -> (String, String) {
    let kind = if orbit.orthographic { "o" } else { "p" };
    let numbers = [
        orbit.yaw,
        orbit.pitch,
        orbit.distance,
        orbit.pan.x,
        orbit.pan.y,
        orbit.pan.z,
    ]
    .map(tidy);
    ("camera".into(), format!("{},{kind}", numbers.join(",")))
}

/// `value` in at most [`TIDY_DIGITS`] significant digits, without trailing zeros: a dragged
/// camera's `34.00000000000001` degrees is `34` (the view the same to a millionth).
pub fn tidy(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{}", if value == 0.0 { 0.0 } else { value });
    }
    let magnitude = value.abs().log10().floor() as i32;
    let decimals = (TIDY_DIGITS - 1 - magnitude).max(0) as usize;
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    };
    if text == "-0" { "0".to_owned() } else { text }
}

/// Significant digits [`tidy`] keeps.
const TIDY_DIGITS: i32 = 10;

/// The key of a moved 2D view.
pub const VIEW: &str = "view";

/// A 2D view as a value: its centre and its zoom (screen points per world unit).
pub fn view_value(view: &crate::canvas::View2d) -> (String, String) {
    (
        VIEW.into(),
        format!(
            "{},{},{}",
            tidy(view.center.x),
            tidy(view.center.y),
            tidy(view.points_per_unit)
        ),
    )
}

/// A 2D view from its value: placed where it says, as a view the user moved.
pub fn parse_view(value: &str) -> Result<crate::canvas::View2d, String> {
    let bad = || format!("view '{}' is not x,y,zoom", shorten(value));
    let numbers: Vec<f64> = value
        .split(',')
        .map(|part| part.parse::<f64>().ok().filter(|number| number.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    let [x, y, zoom] = numbers[..] else {
        return Err(bad());
    };
    if zoom <= 0.0 {
        return Err(bad());
    }
    Ok(crate::canvas::View2d {
        center: glam::DVec2::new(x, y),
        points_per_unit: zoom,
        placed: true,
        fitted_size: None,
        ..crate::canvas::View2d::default()
    })
}

/// A camera from its value.
pub fn parse_camera(value: &str) -> Result<crate::view3d::Orbit, String> {
    let parts: Vec<&str> = value.split(',').collect();
    let bad = || {
        format!(
            "camera '{}' is not yaw,pitch,distance,x,y,z,p|o",
            shorten(value)
        )
    };
    let [yaw, pitch, distance, x, y, z, kind] = parts[..] else {
        return Err(bad());
    };
    let number = |text: &str| {
        text.parse::<f64>()
            .ok()
            .filter(|number| number.is_finite())
            .ok_or_else(bad)
    };
    let orthographic = match kind {
        "o" => true,
        "p" => false,
        _ => return Err(bad()),
    };
    let distance = number(distance)?;
    if distance <= 0.0 {
        return Err(bad());
    }
    Ok(crate::view3d::Orbit {
        yaw: number(yaw)?,
        pitch: number(pitch)?.clamp(-89.0, 89.0),
        distance,
        pan: glam::DVec3::new(number(x)?, number(y)?, number(z)?),
        orthographic,
    })
}

/// A 3D scene's mesh as a value, if it can go in a link (a built-in mesh; a file opened
/// cannot).
pub fn mesh_value(scene: &crate::mesh::MeshScene) -> Option<(String, String)> {
    scene
        .name
        .starts_with("builtin:")
        .then(|| ("mesh".into(), scene.name.clone()))
}

/// Shows the built-in mesh a value names, unless it is shown already.
pub fn restore_mesh(scene: &mut crate::mesh::MeshScene, value: &str) -> Result<(), String> {
    if scene.name != value {
        let named = crate::mesh::MeshScene::named(value)?;
        scene.replace((*named.mesh).clone());
        scene.name = named.name;
    }
    Ok(())
}

/// What a mesh lesson keeps (its built-in mesh, structure and camera).
pub fn mesh_view_values(
    scene: &crate::mesh::MeshScene,
    structure: &accelviz_core::Structure,
    orbit: &crate::view3d::Orbit,
) -> Vec<(String, String)> {
    let mut values = Vec::from_iter(mesh_value(scene));
    values.push(structure_value(structure));
    values.push(camera_value(orbit));
    values
}

/// Restores one of [`mesh_view_values`]'s pairs.
pub fn restore_mesh_view(
    scene: &mut crate::mesh::MeshScene,
    structure: &mut accelviz_core::Structure,
    orbit: &mut crate::view3d::Orbit,
    key: &str,
    value: &str,
) -> Result<(), String> {
    match key {
        "mesh" => restore_mesh(scene, value)?,
        "structure" => *structure = parse_structure(value)?,
        "camera" => *orbit = parse_camera(value)?,
        _ => return Err(format!("this lesson keeps no '{key}'")),
    }
    Ok(())
}

fn shorten(text: &str) -> String {
    let short: String = text.chars().take(40).collect();
    if short.len() < text.len() {
        format!("{short}…")
    } else {
        short
    }
}

/// A value with `%`, `&`, `=`, `#` and spaces escaped as `%XX`.
fn escape(value: &str) -> String {
    let mut text = String::with_capacity(value.len());
    for byte in value.bytes() {
        if byte.is_ascii_alphanumeric() || b"-_.:,+!*()~".contains(&byte) {
            text.push(byte as char);
        } else {
            text.push_str(&format!("%{byte:02X}"));
        }
    }
    text
}

fn unescape(value: &str) -> Option<String> {
    let bytes = value.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut index = 0;
    while index < bytes.len() {
        if bytes[index] == b'%' {
            let hex = std::str::from_utf8(bytes.get(index + 1..index + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            index += 3;
        } else {
            out.push(bytes[index]);
            index += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// RON without the whitespace between tokens (a scene document holds no strings).
fn compact(ron: &str) -> String {
    ron.chars().filter(|c| !c.is_whitespace()).collect()
}

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";

/// Base64 with the URL alphabet and no padding (RFC 4648 §5).
pub fn base64url(bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let word = chunk.iter().enumerate().fold(0u32, |word, (at, byte)| {
            word | (u32::from(*byte) << (16 - 8 * at))
        });
        for at in 0..=chunk.len() {
            text.push(ALPHABET[((word >> (18 - 6 * at)) & 63) as usize] as char);
        }
    }
    text
}

/// The bytes of [`base64url`] text, or `None` for anything else.
pub fn unbase64url(text: &str) -> Option<Vec<u8>> {
    let values: Vec<u32> = text
        .bytes()
        .map(|byte| ALPHABET.iter().position(|a| *a == byte).map(|v| v as u32))
        .collect::<Option<_>>()?;
    if values.len() % 4 == 1 {
        return None;
    }
    let mut bytes = Vec::with_capacity(values.len() * 3 / 4);
    for chunk in values.chunks(4) {
        let word = chunk
            .iter()
            .enumerate()
            .fold(0u32, |word, (at, value)| word | (value << (18 - 6 * at)));
        for at in 0..chunk.len() - 1 {
            bytes.push((word >> (16 - 8 * at)) as u8);
        }
    }
    Some(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64url_round_trips_every_length() {
        for length in 0..40 {
            let bytes: Vec<u8> = (0..length).map(|i| (i * 37 + 11) as u8).collect();
            let text = base64url(&bytes);
            assert!(!text.contains(['+', '/', '=']));
            assert_eq!(unbase64url(&text), Some(bytes));
        }
        // "Man" is "TWFu" in RFC 4648's example.
        assert_eq!(base64url(b"Man"), "TWFu");
        assert_eq!(unbase64url("T"), None);
        assert_eq!(unbase64url("TW+u"), None);
    }

    #[test]
    fn a_state_round_trips_and_garbage_is_refused() {
        let state = ViewState {
            lesson: 11,
            step: 7,
            values: vec![
                ("structure".into(), "bvh:sah-binned:16".into()),
                ("camera".into(), "20,22.5,2.8,0,0,0,p".into()),
                ("mesh".into(), "builtin:teapot stadium & more".into()),
            ],
            scene: Some("(shapes: [Disc(center: (1.0, 2.0), radius: 3.0)])".into()),
        };
        let text = state.encode();
        assert!(!text.contains([' ', '#']));
        let back = ViewState::decode(&format!("https://x.invalid/#{text}")).unwrap();
        assert_eq!(back.lesson, 11);
        assert_eq!(back.step, 7);
        assert_eq!(back.values, state.values);
        assert_eq!(
            back.scene.as_deref(),
            Some("(shapes:[Disc(center:(1.0,2.0),radius:3.0)])")
        );
        for garbage in [
            "",
            "hello",
            "lesson=3",
            "v=1",
            "v=2&lesson=1",
            "v=1&lesson=0",
            "v=1&lesson=x",
            "v=1&lesson=1&step=-1",
            "v=1&lesson=1&scene=!!",
            "v=1&lesson=1&<b>=1",
            "v=1&lesson=1&camera=%zz",
        ] {
            assert!(ViewState::decode(garbage).is_err(), "{garbage:?}");
        }
    }
}
