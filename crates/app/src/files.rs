//! Opening and saving scene files.
//!
//! On the desktop the system's file dialog is asked first (rfd: the XDG desktop portal, or
//! zenity). Where neither exists (a Linux desktop without a portal, a lecture-hall PC set up
//! by hand) rfd only logs why and returns nothing, so the app listens to rfd's log: a dialog
//! that failed opens the in-app file panel ([`FilePanel`]) with rfd's reason, and the panel's
//! path field and listing always work. In the browser, opening is an upload and saving a
//! download; opening is asynchronous there, so results arrive as events on the next frame.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A finished file operation.
#[derive(Clone, Debug, PartialEq)]
pub enum FileEvent {
    /// A file was read: its name and text.
    Opened {
        /// The file's name or path.
        name: String,
        /// Its contents.
        text: String,
        /// What it was opened as (a scene, a mesh, a lecture script).
        filter: FileFilter,
    },
    /// Reading failed; the message says which file and why.
    Failed(String),
}

/// What rfd logged at warning level or above while a dialog was open: why it failed.
static DIALOG_LOG: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// A logger that passes every record on to `inner` and keeps rfd's warnings and errors, so a
/// dialog that fails can say why in the app instead of only on stderr.
struct DialogLogCapture {
    inner: Option<Box<dyn log::Log>>,
}

impl log::Log for DialogLogCapture {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.target().starts_with("rfd")
            || self
                .inner
                .as_ref()
                .is_some_and(|inner| inner.enabled(metadata))
    }

    fn log(&self, record: &log::Record) {
        if record.target().starts_with("rfd")
            && record.level() <= log::Level::Warn
            && let Ok(mut messages) = DIALOG_LOG.lock()
        {
            messages.push(record.args().to_string());
        }
        if let Some(inner) = &self.inner
            && inner.enabled(record.metadata())
        {
            inner.log(record);
        }
    }

    fn flush(&self) {
        if let Some(inner) = &self.inner {
            inner.flush();
        }
    }
}

/// Installs the process's logger: `inner` (the desktop app's env_logger), with rfd's
/// complaints kept for the app. Does nothing if a logger is already installed.
pub fn install_logger(inner: Option<Box<dyn log::Log>>, max_level: log::LevelFilter) {
    if log::set_boxed_logger(Box::new(DialogLogCapture { inner })).is_ok() {
        log::set_max_level(max_level.max(log::LevelFilter::Warn));
    }
}

/// Runs a dialog and returns its answer, or why it could not open (what rfd logged).
#[cfg(not(target_arch = "wasm32"))]
fn run_dialog<T>(dialog: impl FnOnce() -> Option<T>) -> Result<Option<T>, String> {
    if let Ok(mut messages) = DIALOG_LOG.lock() {
        messages.clear();
    }
    let answer = dialog();
    let complaints = DIALOG_LOG
        .lock()
        .map(|mut messages| std::mem::take(&mut *messages))
        .unwrap_or_default();
    match answer {
        Some(answer) => Ok(Some(answer)),
        // Nothing chosen and nothing said: the user cancelled.
        None if complaints.is_empty() => Ok(None),
        None => Err(complaints.join("; ")),
    }
}

/// Reads a file opened as `filter` says, refusing one larger than its `max_bytes` before
/// reading it.
pub fn read_text_file(path: &Path, filter: FileFilter) -> FileEvent {
    let max_bytes = filter.max_bytes;
    let name = path.display().to_string();
    let size = std::fs::metadata(path)
        .map(|metadata| metadata.len())
        .unwrap_or(0);
    if size > max_bytes {
        return too_large(&name, size, max_bytes);
    }
    match std::fs::read(path) {
        Ok(bytes) => text_event(name, bytes, filter),
        Err(error) => FileEvent::Failed(format!("{name}: cannot read the file: {error}")),
    }
}

/// The refusal of a file of `size` bytes over `max_bytes`.
fn too_large(name: &str, size: u64, max_bytes: u64) -> FileEvent {
    FileEvent::Failed(format!(
        "{name}: the file is {} MB; these files are limited to {} MB",
        size >> 20,
        max_bytes >> 20
    ))
}

/// A file's bytes as text, or why they are not.
fn text_event(name: String, bytes: Vec<u8>, filter: FileFilter) -> FileEvent {
    match String::from_utf8(bytes) {
        Ok(text) => FileEvent::Opened { name, text, filter },
        Err(_) => FileEvent::Failed(format!("{name}: the file is not UTF-8 text")),
    }
}

/// Writes `bytes` to `path` through a file beside it and a rename, so a failed write never
/// leaves half a file where the old one was.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<String, String> {
    accelviz_scene::output::write_all_or_nothing(&[(path, bytes)])
        .map(|()| format!("saved {}", path.display()))
        .map_err(|error| error.to_string())
}

/// What the in-app file panel is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanelMode {
    /// Choose a scene file to open.
    Open,
    /// Choose where to save the scene.
    Save,
}

/// The in-app file panel: a path field, the scene files in its folder, and Open or Save. It
/// needs nothing of the desktop, so it always works.
#[derive(Clone, Debug)]
pub struct FilePanel {
    /// Open or save.
    pub mode: PanelMode,
    /// The path typed or picked.
    pub path: String,
    /// Why the panel is shown instead of the system dialog, if it failed.
    pub reason: Option<String>,
    /// Which files it lists.
    pub filter: FileFilter,
    /// What a save panel writes (its suggested name is in the path).
    pub content: Vec<u8>,
}

/// What the panel asks the app to do.
pub enum PanelAction {
    /// Nothing yet.
    None,
    /// Close the panel.
    Close,
    /// Open this file.
    Open(PathBuf),
    /// Save to this file.
    Save(PathBuf),
}

/// The folder the file panel was last used in: the next panel starts there.
static LAST_FOLDER: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Where a new panel starts: the folder last used, or the current one.
fn start_folder() -> PathBuf {
    LAST_FOLDER
        .lock()
        .ok()
        .and_then(|folder| folder.clone())
        .filter(|folder| folder.is_dir())
        .unwrap_or_else(|| std::env::current_dir().unwrap_or_default())
}

impl FilePanel {
    /// A panel for `mode`, starting in the folder last used (and with `file_name` to save).
    pub fn new(mode: PanelMode, filter: FileFilter, reason: Option<String>) -> Self {
        let folder = start_folder();
        Self {
            mode,
            path: folder.display().to_string(),
            reason,
            filter,
            content: Vec::new(),
        }
    }

    /// A panel that saves `content`, suggesting `name` in the current folder.
    pub fn saving(filter: FileFilter, name: &str, content: Vec<u8>, reason: String) -> Self {
        let folder = start_folder();
        Self {
            mode: PanelMode::Save,
            path: folder.join(name).display().to_string(),
            reason: Some(reason),
            filter,
            content,
        }
    }

    /// The folder the path is in (or is).
    fn folder(&self) -> PathBuf {
        let path = PathBuf::from(&self.path);
        if path.is_dir() {
            path
        } else {
            path.parent().map(Path::to_path_buf).unwrap_or_default()
        }
    }

    /// The files the filter accepts and the folders in the path's folder, folders first.
    fn listing(&self) -> Vec<(PathBuf, bool)> {
        let Ok(entries) = std::fs::read_dir(self.folder()) else {
            return Vec::new();
        };
        let mut listing: Vec<(PathBuf, bool)> = entries
            .filter_map(Result::ok)
            .map(|entry| entry.path())
            .filter_map(|path| {
                let is_dir = path.is_dir();
                let hidden = path
                    .file_name()
                    .is_some_and(|name| name.to_string_lossy().starts_with('.'));
                let scene = path.extension().is_some_and(|extension| {
                    self.filter
                        .extensions
                        .iter()
                        .any(|wanted| extension.eq_ignore_ascii_case(wanted))
                });
                (!hidden && (is_dir || scene)).then_some((path, is_dir))
            })
            .collect();
        listing.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        listing.truncate(200);
        listing
    }

    /// The panel's window. Returns what the user asked for.
    pub fn ui(&mut self, ctx: &egui::Context) -> PanelAction {
        let mut action = PanelAction::None;
        let title = match self.mode {
            PanelMode::Open => format!("Open a file ({})", self.filter.name),
            PanelMode::Save => format!("Save ({})", self.filter.name),
        };
        let mut open = true;
        egui::Window::new(title)
            .collapsible(false)
            .resizable(true)
            .default_width(520.0)
            .open(&mut open)
            .show(ctx, |ui| {
                if let Some(reason) = &self.reason {
                    // What the dialog library logged is for a bug report, not the message.
                    ui.label(
                        "The system's file dialog could not open here. Type or pick a path instead.",
                    )
                    .on_hover_text(format!("What the dialog reported: {reason}"));
                }
                let mut entered = false;
                ui.horizontal(|ui| {
                    let label = ui.label("path");
                    let field = ui
                        .add(
                            egui::TextEdit::singleline(&mut self.path)
                                .desired_width(ui.available_width() - 8.0),
                        )
                        .labelled_by(label.id);
                    entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                });
                let folder = self.folder();
                ui.horizontal(|ui| {
                    if let Some(parent) = folder.parent()
                        && ui.button("up a folder").clicked()
                    {
                        self.path = parent.display().to_string();
                    }
                    ui.label(
                        egui::RichText::new(format!("in {}", folder.display()))
                            .small()
                            .weak(),
                    );
                });
                // Always as tall, so the buttons below stay put while a path is typed.
                egui::ScrollArea::vertical()
                    .auto_shrink([false, false])
                    .max_height(220.0)
                    .show(ui, |ui| {
                        for (path, is_dir) in self.listing() {
                            let name = path
                                .file_name()
                                .map(|name| name.to_string_lossy().into_owned())
                                .unwrap_or_default();
                            let shown = if is_dir { format!("{name}/") } else { name };
                            if ui.selectable_label(false, shown).clicked() {
                                self.path = path.display().to_string();
                            }
                        }
                    });
                ui.separator();
                ui.horizontal(|ui| {
                    let path = PathBuf::from(&self.path);
                    let verb = match self.mode {
                        PanelMode::Open => "Open",
                        PanelMode::Save => "Save",
                    };
                    // Enter in the path field presses the button, unless the path is a folder
                    // (whose files the list then shows).
                    let entered = entered && !path.is_dir();
                    if ui.button(verb).clicked() || entered {
                        if let Some(folder) = path.parent().filter(|_| !path.is_dir())
                            && let Ok(mut last) = LAST_FOLDER.lock()
                        {
                            *last = Some(folder.to_path_buf());
                        }
                        action = match self.mode {
                            PanelMode::Open => PanelAction::Open(path),
                            PanelMode::Save => PanelAction::Save(path),
                        };
                    }
                    if ui.button("Cancel").clicked() {
                        action = PanelAction::Close;
                    }
                });
            });
        if !open {
            action = PanelAction::Close;
        }
        action
    }
}

/// Where file results wait for the next frame, and how dialogs are shown.
#[derive(Clone, Default)]
pub struct FileChannel {
    events: Arc<Mutex<Vec<FileEvent>>>,
}

/// Which files a dialog offers: a name for the kind and its extensions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileFilter {
    /// What the files are ("accelviz scene", "OBJ mesh").
    pub name: &'static str,
    /// Their extensions, without the dot.
    pub extensions: &'static [&'static str],
    /// The largest file opened: larger ones are refused before they are read.
    pub max_bytes: u64,
}

/// What asking for a file led to.
pub enum DialogOutcome {
    /// The answer will come as an event (a file read) or came already.
    Done,
    /// The user cancelled.
    Cancelled,
    /// No dialog could open; the in-app panel should, with this reason.
    Unavailable(String),
}

impl FileChannel {
    /// Results that arrived since the last call.
    pub fn take_events(&self) -> Vec<FileEvent> {
        self.events
            .lock()
            .map(|mut events| std::mem::take(&mut *events))
            .unwrap_or_default()
    }

    /// Reads a file dropped onto the window or the page (at once on the desktop; in the
    /// browser asynchronously, arriving as an event).
    pub fn dropped(&self, ctx: &egui::Context, file: egui::DroppedFileHandle, filter: FileFilter) {
        let max_bytes = filter.max_bytes;
        let name = file.path().file_name().map_or_else(
            || file.path().display().to_string(),
            |name| name.to_string_lossy().into_owned(),
        );
        #[cfg(not(target_arch = "wasm32"))]
        {
            let size = std::fs::metadata(file.path()).map_or(0, |metadata| metadata.len());
            let event = if size > max_bytes {
                too_large(&name, size, max_bytes)
            } else {
                match file.bytes() {
                    Ok(bytes) => text_event(name, bytes, filter),
                    Err(error) => {
                        FileEvent::Failed(format!("{name}: cannot read the file: {error}"))
                    }
                }
            };
            self.push(ctx, event);
        }
        #[cfg(target_arch = "wasm32")]
        {
            let channel = self.clone();
            let ctx = ctx.clone();
            wasm_bindgen_futures::spawn_local(async move {
                let event = match file.bytes_async().await {
                    Ok(bytes) if bytes.len() as u64 > max_bytes => {
                        too_large(&name, bytes.len() as u64, max_bytes)
                    }
                    Ok(bytes) => text_event(name, bytes, filter),
                    Err(error) => {
                        FileEvent::Failed(format!("{name}: cannot read the file: {error}"))
                    }
                };
                channel.push(&ctx, event);
            });
        }
    }

    /// Leaves `event` for the next frame, and asks `ctx` for that frame: egui draws only
    /// when something happens, and a file read in the background is not an input event.
    fn push(&self, ctx: &egui::Context, event: FileEvent) {
        if let Ok(mut events) = self.events.lock() {
            events.push(event);
        }
        ctx.request_repaint();
    }

    /// Asks the system's dialog for a scene file to open.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn open(&self, ctx: &egui::Context, filter: FileFilter) -> DialogOutcome {
        let picked = run_dialog(|| {
            rfd::FileDialog::new()
                .add_filter(filter.name, filter.extensions)
                .pick_file()
        });
        match picked {
            Ok(Some(path)) => {
                self.push(ctx, read_text_file(&path, filter));
                DialogOutcome::Done
            }
            Ok(None) => DialogOutcome::Cancelled,
            Err(reason) => DialogOutcome::Unavailable(reason),
        }
    }

    /// Asks the browser for a scene file to upload.
    #[cfg(target_arch = "wasm32")]
    pub fn open(&self, ctx: &egui::Context, filter: FileFilter) -> DialogOutcome {
        let channel = self.clone();
        let ctx = ctx.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let Some(file) = rfd::AsyncFileDialog::new()
                .add_filter(filter.name, filter.extensions)
                .pick_file()
                .await
            else {
                log::info!("accelviz: no file chosen");
                return;
            };
            let name = file.file_name();
            let bytes = file.read().await;
            let event = if bytes.len() as u64 > filter.max_bytes {
                too_large(&name, bytes.len() as u64, filter.max_bytes)
            } else {
                text_event(name, bytes, filter)
            };
            channel.push(&ctx, event);
        });
        DialogOutcome::Done
    }

    /// Saves `bytes` through the system's save dialog. `Ok(Some(message))` when saved,
    /// `Ok(None)` if the user cancelled, `Err(reason)` if no dialog could open.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn save(
        &self,
        suggested_name: &str,
        bytes: &[u8],
        filter: FileFilter,
    ) -> Result<Option<Result<String, String>>, String> {
        let chosen = run_dialog(|| {
            rfd::FileDialog::new()
                .add_filter(filter.name, filter.extensions)
                .set_file_name(suggested_name)
                .save_file()
        })?;
        Ok(chosen.map(|path| write_file(&path, bytes)))
    }

    /// Downloads `bytes` as a file.
    #[cfg(target_arch = "wasm32")]
    pub fn save(
        &self,
        suggested_name: &str,
        bytes: &[u8],
        _filter: FileFilter,
    ) -> Result<Option<Result<String, String>>, String> {
        Ok(Some(
            web::download(suggested_name, bytes)
                .map(|()| format!("downloaded {suggested_name}"))
                .map_err(|error| format!("cannot download {suggested_name}: {error:?}")),
        ))
    }
}

/// A link to the view `state` encodes: the page's address with it as the fragment in the
/// browser; on the desktop the state itself (it opens with `accelviz STATE` or the share
/// window).
pub fn page_link(state: &str) -> String {
    #[cfg(target_arch = "wasm32")]
    if let Some(location) = web_sys::window().map(|window| window.location()) {
        let base = location.href().unwrap_or_default();
        let base = base.split('#').next().unwrap_or_default().to_owned();
        return format!("{base}#{state}");
    }
    format!("#{state}")
}

/// The page's URL fragment, without the `#` (browser only).
pub fn page_fragment() -> Option<String> {
    #[cfg(target_arch = "wasm32")]
    {
        let hash = web_sys::window()?.location().hash().ok()?;
        let hash = hash.trim_start_matches('#');
        (!hash.is_empty()).then(|| hash.to_owned())
    }
    #[cfg(not(target_arch = "wasm32"))]
    None
}

/// Puts the page full screen, or back (the browser's full screen; on the desktop the window
/// is asked through the viewport instead).
pub fn web_full_screen(on: bool) {
    #[cfg(target_arch = "wasm32")]
    if let Some(document) = web_sys::window().and_then(|window| window.document()) {
        if on {
            if let Some(element) = document.document_element() {
                let _ = element.request_fullscreen();
            }
        } else {
            document.exit_fullscreen();
        }
    }
    #[cfg(not(target_arch = "wasm32"))]
    let _ = on;
}

/// Sets the browser page's title (nothing on the desktop, where the window title is set
/// through the viewport).
pub fn set_page_title(title: &str) {
    #[cfg(target_arch = "wasm32")]
    if let Some(document) = web_sys::window().and_then(|window| window.document()) {
        document.set_title(title);
    }
    #[cfg(not(target_arch = "wasm32"))]
    let _ = title;
}

#[cfg(target_arch = "wasm32")]
mod web {
    use wasm_bindgen::{JsCast, JsValue};

    /// Offers `text` as a download named `name`.
    pub fn download(name: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let array = js_sys::Uint8Array::from(bytes);
        let parts = js_sys::Array::of1(&array);
        let options = web_sys::BlobPropertyBag::new();
        let kind = if name.ends_with(".png") {
            "image/png"
        } else {
            "text/plain"
        };
        options.set_type(kind);
        let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)?;
        let url = web_sys::Url::create_object_url_with_blob(&blob)?;
        let document = web_sys::window()
            .and_then(|window| window.document())
            .ok_or_else(|| JsValue::from_str("no document"))?;
        let anchor: web_sys::HtmlAnchorElement = document.create_element("a")?.dyn_into()?;
        anchor.set_href(&url);
        anchor.set_download(name);
        anchor.click();
        web_sys::Url::revoke_object_url(&url)
    }
}
