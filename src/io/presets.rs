//! The user's own presets, in their config folder (`~/.config/windloom/presets` on Linux):
//! `wind/NAME.json` and `grass/NAME.json`, each a layout (`doc::presets` says what of it a
//! preset uses), written atomically and never over another.

use super::{LoadError, load, plain, write_atomic};
use crate::doc::{self, Layout};
use std::path::{Path, PathBuf};

/// A preset's kind: its sub-folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    Wind,
    Grass,
}

impl Kind {
    pub fn folder(self) -> &'static str {
        match self {
            Self::Wind => "wind",
            Self::Grass => "grass",
        }
    }
}

/// The longest preset name, in characters.
pub const NAME_MAX: usize = 64;

/// Why a preset could not be saved or read.
#[derive(Debug, thiserror::Error)]
pub enum PresetError {
    #[error(
        "a preset's name is 1 to {NAME_MAX} letters, digits, spaces, '-' or '_' (not {})",
        doc::quote(.0)
    )]
    Name(String),
    #[error("a {} preset named {} exists already: pick another name", .kind.folder(), doc::quote(.name))]
    Exists { kind: Kind, name: String },
    #[error("{}: {source}", .path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Load(#[from] LoadError),
}

/// The presets folder in the user's config folder, if the system names one.
pub fn folder() -> Option<PathBuf> {
    directories::ProjectDirs::from("", "", "windloom").map(|d| d.config_dir().join("presets"))
}

/// Whether `name` may name a preset file: no path, no hidden file, nothing a file system
/// reads otherwise.
fn check_name(name: &str) -> Result<(), PresetError> {
    let ok = !name.trim().is_empty()
        && name.chars().count() <= NAME_MAX
        && name == name.trim()
        && (name.chars()).all(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'));
    if ok {
        Ok(())
    } else {
        Err(PresetError::Name(name.into()))
    }
}

/// The user's presets of `kind` under `folder`, by name (sorted), with their files. A folder
/// that does not exist has none.
pub fn list(folder: &Path, kind: Kind) -> Vec<(String, PathBuf)> {
    let Ok(entries) = std::fs::read_dir(folder.join(kind.folder())) else {
        return Vec::new();
    };
    let mut out: Vec<(String, PathBuf)> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json") && p.is_file())
        .filter_map(|p| {
            let name = p.file_stem()?.to_str()?.to_string();
            check_name(&name).ok().map(|_| (name, p))
        })
        .collect();
    out.sort_by_key(|a| a.0.to_lowercase());
    out
}

/// Saves `preset` as the user's preset `name` of `kind` under `folder` (made if need be);
/// refuses a bad name and a name in use.
pub fn save(
    folder: &Path,
    kind: Kind,
    name: &str,
    preset: &Layout,
) -> Result<PathBuf, PresetError> {
    check_name(name)?;
    let dir = folder.join(kind.folder());
    let path = dir.join(format!("{name}.json"));
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PresetError::Io {
            path,
            source: plain(source),
        }
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    if list(folder, kind)
        .iter()
        .any(|(n, _)| n.to_lowercase() == name.to_lowercase())
    {
        return Err(PresetError::Exists {
            kind,
            name: name.into(),
        });
    }
    let mut preset = preset.clone();
    preset.name = name.into();
    write_atomic(&path, doc::to_json(&preset).as_bytes()).map_err(io(&path))?;
    Ok(path)
}

/// Reads a user's preset file.
pub fn read(path: &Path) -> Result<Layout, PresetError> {
    Ok(load(path)?)
}

/// Deletes a user's preset file.
pub fn delete(path: &Path) -> Result<(), PresetError> {
    std::fs::remove_file(path).map_err(|source| PresetError::Io {
        path: path.to_path_buf(),
        source: plain(source),
    })
}
