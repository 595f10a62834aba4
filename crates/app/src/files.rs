//! Opening and saving scene files: a file dialog on the desktop (rfd), upload and download in
//! the browser. Opening is asynchronous in the browser, so results arrive as events the app
//! picks up on its next frame.

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
    },
    /// Reading failed; the message says which file and why.
    Failed(String),
}

/// The largest scene file opened (bytes), checked before reading it all.
const MAX_OPEN_BYTES: u64 = accelviz_scene::document::MAX_DOCUMENT_BYTES as u64;

/// Where file results wait for the next frame.
#[derive(Clone, Default)]
pub struct FileChannel {
    events: Arc<Mutex<Vec<FileEvent>>>,
}

impl FileChannel {
    /// Results that arrived since the last call.
    pub fn take_events(&self) -> Vec<FileEvent> {
        self.events
            .lock()
            .map(|mut events| std::mem::take(&mut *events))
            .unwrap_or_default()
    }

    fn push(&self, event: FileEvent) {
        if let Ok(mut events) = self.events.lock() {
            events.push(event);
        }
    }

    /// Asks the user for a scene file to open.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn open(&self) {
        let Some(path) = rfd::FileDialog::new()
            .add_filter("accelviz scene", &["ron"])
            .pick_file()
        else {
            return;
        };
        let name = path.display().to_string();
        let size = std::fs::metadata(&path)
            .map(|metadata| metadata.len())
            .unwrap_or(0);
        let event = if size > MAX_OPEN_BYTES {
            FileEvent::Failed(format!(
                "{name}: the file is {} MB; scene files are limited to {} MB",
                size >> 20,
                MAX_OPEN_BYTES >> 20
            ))
        } else {
            match std::fs::read_to_string(&path) {
                Ok(text) => FileEvent::Opened { name, text },
                Err(error) => FileEvent::Failed(format!("{name}: cannot read the file: {error}")),
            }
        };
        self.push(event);
    }

    /// Asks the user for a scene file to upload.
    #[cfg(target_arch = "wasm32")]
    pub fn open(&self) {
        let channel = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let Some(file) = rfd::AsyncFileDialog::new()
                .add_filter("accelviz scene", &["ron"])
                .pick_file()
                .await
            else {
                return;
            };
            let name = file.file_name();
            let bytes = file.read().await;
            let event = if bytes.len() as u64 > MAX_OPEN_BYTES {
                FileEvent::Failed(format!(
                    "{name}: the file is {} MB; scene files are limited to {} MB",
                    bytes.len() >> 20,
                    MAX_OPEN_BYTES >> 20
                ))
            } else {
                match String::from_utf8(bytes) {
                    Ok(text) => FileEvent::Opened { name, text },
                    Err(_) => FileEvent::Failed(format!("{name}: the file is not UTF-8 text")),
                }
            };
            channel.push(event);
        });
    }

    /// Saves `text` through a save dialog. `Ok(Some(message))` on success, `Ok(None)` if the
    /// user cancelled.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn save(&self, suggested_name: &str, text: String) -> Result<Option<String>, String> {
        let Some(path) = rfd::FileDialog::new()
            .add_filter("accelviz scene", &["ron"])
            .set_file_name(suggested_name)
            .save_file()
        else {
            return Ok(None);
        };
        // Write beside the target and rename, so a failed write never leaves half a file.
        let partial = path.with_extension("ron.partial");
        std::fs::write(&partial, text)
            .and_then(|()| std::fs::rename(&partial, &path))
            .map(|()| Some(format!("saved {}", path.display())))
            .map_err(|error| format!("{}: cannot save: {error}", path.display()))
    }

    /// Downloads `text` as a file.
    #[cfg(target_arch = "wasm32")]
    pub fn save(&self, suggested_name: &str, text: String) -> Result<Option<String>, String> {
        web::download(suggested_name, &text)
            .map(|()| Some(format!("downloaded {suggested_name}")))
            .map_err(|error| format!("cannot download {suggested_name}: {error:?}"))
    }
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
    pub fn download(name: &str, text: &str) -> Result<(), JsValue> {
        let parts = js_sys::Array::of1(&JsValue::from_str(text));
        let options = web_sys::BlobPropertyBag::new();
        options.set_type("text/plain");
        let blob = web_sys::Blob::new_with_str_sequence_and_options(&parts, &options)?;
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
