//! Where a quiz's progress is kept between runs: a file on the desktop, written whole or not
//! at all (a temporary file beside it, then a rename, which replaces the old one atomically on
//! every platform we run on), and `localStorage` in the browser. What is there but is not
//! progress (damaged, foreign, from another version) is set aside under another name and
//! reported, never overwritten unseen.

use accelviz_quiz::{Progress, Session};

/// What a store found when asked for the saved quiz.
#[derive(Debug)]
pub enum Loaded {
    /// Nothing saved.
    Nothing,
    /// A quiz to carry on with.
    Quiz(Box<Session>),
    /// Something that is not progress, set aside: what it was, and where it went.
    SetAside(String),
}

/// A place for progress.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgressStore {
    /// Not kept (tests, or nowhere to keep it).
    Nowhere,
    /// A file (desktop).
    File(std::path::PathBuf),
    /// A `localStorage` key (browser).
    Browser(String),
}

/// The `localStorage` key, and the file name.
pub const PROGRESS_NAME: &str = "accelviz-quiz-progress";

impl ProgressStore {
    /// The platform's place: `ACCELVIZ_QUIZ_PROGRESS` if set, else the user's data folder
    /// on the desktop; `localStorage` in the browser.
    pub fn platform() -> Self {
        #[cfg(target_arch = "wasm32")]
        {
            Self::Browser(PROGRESS_NAME.to_owned())
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            if let Some(path) = std::env::var_os("ACCELVIZ_QUIZ_PROGRESS") {
                return Self::File(path.into());
            }
            let data = std::env::var_os("XDG_DATA_HOME")
                .map(std::path::PathBuf::from)
                .or_else(|| {
                    std::env::var_os("HOME")
                        .map(|home| std::path::PathBuf::from(home).join(".local/share"))
                })
                .or_else(|| std::env::var_os("APPDATA").map(std::path::PathBuf::from));
            match data {
                Some(folder) => Self::File(
                    folder
                        .join("accelviz")
                        .join(format!("{PROGRESS_NAME}.json")),
                ),
                None => Self::Nowhere,
            }
        }
    }

    /// Where progress goes, for messages.
    pub fn describe(&self) -> String {
        match self {
            Self::Nowhere => "nowhere".into(),
            Self::File(path) => path.display().to_string(),
            Self::Browser(key) => format!("this browser's storage ({key})"),
        }
    }

    /// Saves `progress`, whole or not at all. The error says what failed.
    pub fn save(&self, progress: &Progress) -> Result<(), String> {
        let text = progress.to_text();
        match self {
            Self::Nowhere => Ok(()),
            Self::File(path) => write_whole(path, &text),
            Self::Browser(key) => browser::set(key, &text),
        }
    }

    /// Forgets the saved quiz (a new quiz was started).
    pub fn clear(&self) {
        match self {
            Self::Nowhere => {}
            Self::File(path) => {
                let _ = std::fs::remove_file(path);
            }
            Self::Browser(key) => browser::remove(key),
        }
    }

    /// The saved quiz, if any; anything else there is set aside and reported.
    pub fn load(&self) -> Loaded {
        let text = match self {
            Self::Nowhere => return Loaded::Nothing,
            Self::File(path) => match std::fs::read(path) {
                Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
                Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
                    return Loaded::Nothing;
                }
                Err(error) => {
                    return Loaded::SetAside(format!(
                        "The saved quiz at {} could not be read ({error}); a new quiz starts.",
                        path.display()
                    ));
                }
            },
            Self::Browser(key) => match browser::get(key) {
                Some(text) => text,
                None => return Loaded::Nothing,
            },
        };
        let problem = match Progress::parse(&text) {
            Ok(progress) => match Session::restore(&progress) {
                Ok(session) => return Loaded::Quiz(Box::new(session)),
                Err(error) => error.to_string(),
            },
            Err(error) => error.to_string(),
        };
        Loaded::SetAside(format!(
            "The saved quiz could not be used ({problem}). It was kept as {}; a new quiz starts.",
            self.set_aside(&text)
        ))
    }

    /// Moves what is stored out of the way, keeping it; returns where it went.
    fn set_aside(&self, text: &str) -> String {
        match self {
            Self::Nowhere => "nothing".into(),
            Self::File(path) => {
                let stamp = web_time::SystemTime::now()
                    .duration_since(web_time::UNIX_EPOCH)
                    .map_or(0, |elapsed| elapsed.as_secs());
                let aside = path.with_extension(format!("json.unreadable-{stamp}"));
                match std::fs::rename(path, &aside) {
                    Ok(()) => aside.display().to_string(),
                    Err(error) => format!("{} (it could not be renamed: {error})", path.display()),
                }
            }
            Self::Browser(key) => {
                let aside = format!("{key}.unreadable");
                match browser::set(&aside, text) {
                    Ok(()) => {
                        browser::remove(key);
                        format!("this browser's storage under {aside}")
                    }
                    Err(error) => format!("{key} (it could not be copied: {error})"),
                }
            }
        }
    }
}

/// Writes `text` to a temporary file beside `path`, then renames it over `path`: a crash
/// leaves the old file or the new one, never half of one.
fn write_whole(path: &std::path::Path, text: &str) -> Result<(), String> {
    use std::io::Write;
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)
            .map_err(|error| format!("{}: {error}", folder.display()))?;
    }
    let temporary = path.with_extension("json.saving");
    let written = std::fs::File::create(&temporary).and_then(|mut file| {
        file.write_all(text.as_bytes())?;
        file.sync_all()
    });
    if let Err(error) = written.and_then(|()| std::fs::rename(&temporary, path)) {
        let _ = std::fs::remove_file(&temporary);
        return Err(format!("{}: {error}", path.display()));
    }
    Ok(())
}

#[cfg(target_arch = "wasm32")]
mod browser {
    fn storage() -> Option<web_sys::Storage> {
        web_sys::window()?.local_storage().ok().flatten()
    }

    pub fn get(key: &str) -> Option<String> {
        storage()?.get_item(key).ok().flatten()
    }

    pub fn set(key: &str, text: &str) -> Result<(), String> {
        let storage = storage().ok_or("this browser keeps no local storage")?;
        storage
            .set_item(key, text)
            .map_err(|error| format!("the browser refused to store it: {error:?}"))
    }

    pub fn remove(key: &str) {
        if let Some(storage) = storage() {
            let _ = storage.remove_item(key);
        }
    }
}

/// Outside the browser there is no `localStorage`; a browser store keeps nothing.
#[cfg(not(target_arch = "wasm32"))]
mod browser {
    pub fn get(_key: &str) -> Option<String> {
        None
    }

    pub fn set(_key: &str, _text: &str) -> Result<(), String> {
        Err("there is no browser storage here".into())
    }

    pub fn remove(_key: &str) {}
}
