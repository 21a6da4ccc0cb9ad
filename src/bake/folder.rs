//! A bake replaces its output folder as a whole.
//!
//! Every file is written into a fresh staging folder beside the output folder
//! (`.NAME.windloom-bake-PID-N`). When everything is written and flushed, what the user (or an
//! engine: Unity's `.meta`, Godot's `.import`) put in the old folder is hard-linked into the
//! staging folder, and the two folders are exchanged with one `renameat2(RENAME_EXCHANGE)`:
//! a reader sees the whole old bake or the whole new one, never a mixture. The old bake, now
//! under the staging name, is then deleted. Where the exchange is not available (another
//! system, or a file system without it) the old folder is renamed aside and the new one
//! renamed in, which leaves a moment with no folder rather than a mixed one.
//!
//! A killed bake leaves at most its staging folder; the next bake beside it removes staging
//! folders whose process is gone.

use super::{BakeError, MANIFEST};
use crate::io::{parent_dir, resolve_links, sync_dir};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

const MARK: &str = ".windloom-bake-";

/// A staging folder for one bake into `out`; removed on drop unless committed.
pub(crate) struct Staging {
    /// The output folder (symbolic links resolved).
    out: PathBuf,
    /// The staging folder beside it.
    dir: PathBuf,
    /// Names an earlier bake in `out` wrote (from its manifest), `manifest.json` included.
    /// Everything else in `out` is the user's and is carried over.
    previous: Option<BTreeSet<String>>,
    committed: bool,
}

fn output_error(path: &Path, source: std::io::Error) -> BakeError {
    BakeError::Output {
        path: path.to_path_buf(),
        source,
    }
}

fn other(message: String) -> std::io::Error {
    std::io::Error::other(message)
}

impl Staging {
    /// Checks `out` and creates the staging folder beside it.
    pub(crate) fn new(out: &Path) -> Result<Self, BakeError> {
        let out = resolve_links(out).map_err(|e| output_error(out, e))?;
        let previous = match std::fs::symlink_metadata(&out) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(output_error(&out, e)),
            Ok(m) if !m.is_dir() => {
                return Err(output_error(&out, other("it is not a folder".into())));
            }
            Ok(_) => Some(previous_bake(&out)?),
        };
        let parent = parent_dir(&out).to_path_buf();
        std::fs::create_dir_all(&parent).map_err(|e| output_error(&parent, e))?;
        let name = out
            .file_name()
            .ok_or_else(|| output_error(&out, other("it has no folder name".into())))?
            .to_string_lossy()
            .into_owned();
        remove_stale(&parent, &name);
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let dir = parent.join(format!(".{name}{MARK}{}-{stamp}", std::process::id()));
        // create_dir applies the umask: the new folder gets the user's usual mode.
        std::fs::create_dir(&dir).map_err(|e| {
            output_error(
                &out,
                other(format!(
                    "cannot create the staging folder {} beside it: {e}",
                    dir.display()
                )),
            )
        })?;
        let staging = Self {
            out,
            dir,
            previous,
            committed: false,
        };
        if staging.previous.is_some() {
            // The new folder keeps the old one's permissions.
            let perms = std::fs::metadata(&staging.out)
                .map_err(|e| output_error(&staging.out, e))?
                .permissions();
            std::fs::set_permissions(&staging.dir, perms)
                .map_err(|e| output_error(&staging.dir, e))?;
        }
        Ok(staging)
    }

    pub(crate) fn path(&self) -> &Path {
        &self.dir
    }

    /// Refuses to replace a file of the user's with an output of the same name.
    pub(crate) fn check_names<'a>(
        &self,
        names: impl IntoIterator<Item = &'a str>,
    ) -> Result<(), BakeError> {
        let Some(previous) = &self.previous else {
            return Ok(());
        };
        for name in names {
            let path = self.out.join(name);
            if !previous.contains(name) && std::fs::symlink_metadata(&path).is_ok() {
                return Err(output_error(
                    &path,
                    other(
                        "it was not written by an earlier bake, and this bake would replace \
                         it; move it away or bake into another folder"
                            .into(),
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Puts the staging folder in place of the output folder, carrying the user's files over.
    pub(crate) fn commit(mut self) -> Result<(), BakeError> {
        let parent = parent_dir(&self.out).to_path_buf();
        sync_dir(&self.dir).map_err(|e| output_error(&self.dir, e))?;
        let Some(previous) = self.previous.clone() else {
            std::fs::rename(&self.dir, &self.out).map_err(|e| output_error(&self.out, e))?;
            self.committed = true;
            return sync_dir(&parent).map_err(|e| output_error(&parent, e));
        };
        let theirs = |name: &str| !previous.contains(name);
        for name in entry_names(&self.out)?.into_iter().filter(|n| theirs(n)) {
            let to = self.dir.join(&name);
            if std::fs::symlink_metadata(&to).is_err() {
                link_tree(&self.out.join(&name), &to).map_err(|e| output_error(&to, e))?;
            }
        }
        exchange(&self.dir, &self.out).map_err(|e| output_error(&self.out, e))?;
        self.committed = true;
        // `self.dir` now holds the old bake. Anything of the user's that appeared in it
        // after the links were made moves across; the rest goes.
        for name in entry_names(&self.dir)?.into_iter().filter(|n| theirs(n)) {
            let to = self.out.join(&name);
            if std::fs::symlink_metadata(&to).is_err() {
                let _ = std::fs::rename(self.dir.join(&name), to);
            }
        }
        let _ = std::fs::remove_dir_all(&self.dir);
        sync_dir(&parent).map_err(|e| output_error(&parent, e))
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

fn entry_names(dir: &Path) -> Result<Vec<String>, BakeError> {
    let read = std::fs::read_dir(dir).map_err(|e| output_error(dir, e))?;
    let mut names = Vec::new();
    for e in read {
        let e = e.map_err(|e| output_error(dir, e))?;
        names.push(e.file_name().to_string_lossy().into_owned());
    }
    Ok(names)
}

/// The names an earlier bake wrote into `out`. An empty folder has none; a folder that holds
/// files but no windloom manifest is not a bake folder, and replacing it whole could take
/// more than a bake with it, so it is refused.
fn previous_bake(out: &Path) -> Result<BTreeSet<String>, BakeError> {
    let names = entry_names(out)?;
    if names.is_empty() {
        return Ok(BTreeSet::new());
    }
    let manifest = out.join(MANIFEST);
    let refuse = |why: &str| {
        output_error(
            out,
            other(format!(
                "it holds files but {why}; a bake replaces its folder as a whole, so bake \
                 into a new or empty folder, or into an earlier bake's folder"
            )),
        )
    };
    let text = std::fs::read_to_string(&manifest).map_err(|_| refuse("no manifest.json"))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|_| refuse("its manifest.json is not a windloom bake manifest"))?;
    if value["format"] != "windloom-bake" {
        return Err(refuse("its manifest.json is not a windloom bake manifest"));
    }
    let mut set = BTreeSet::from([MANIFEST.to_string()]);
    for f in value["files"].as_array().into_iter().flatten() {
        if let Some(name) = f["name"].as_str() {
            // Only plain names: a manifest cannot make a bake claim files elsewhere.
            if !name.contains(['/', '\\']) && name != "." && name != ".." {
                set.insert(name.to_string());
            }
        }
    }
    Ok(set)
}

/// Recreates `from` at `to`: folders rebuilt with their permissions, files hard-linked (copied
/// where the file system cannot link), symbolic links copied as links.
fn link_tree(from: &Path, to: &Path) -> std::io::Result<()> {
    let meta = std::fs::symlink_metadata(from)?;
    let kind = meta.file_type();
    if kind.is_symlink() {
        copy_symlink(from, to)
    } else if kind.is_dir() {
        std::fs::create_dir(to)?;
        for e in std::fs::read_dir(from)? {
            let e = e?;
            link_tree(&e.path(), &to.join(e.file_name()))?;
        }
        std::fs::set_permissions(to, meta.permissions())
    } else {
        std::fs::hard_link(from, to).or_else(|_| std::fs::copy(from, to).map(|_| ()))
    }
}

#[cfg(unix)]
fn copy_symlink(from: &Path, to: &Path) -> std::io::Result<()> {
    std::os::unix::fs::symlink(std::fs::read_link(from)?, to)
}

#[cfg(not(unix))]
fn copy_symlink(from: &Path, to: &Path) -> std::io::Result<()> {
    std::fs::copy(from, to).map(|_| ())
}

/// Swaps two folders' names in one step where the system can; else renames `to` aside and
/// `from` into its place, then the old one to `from`'s name.
fn exchange(from: &Path, to: &Path) -> std::io::Result<()> {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, from, CWD, to, RenameFlags::EXCHANGE) {
            Ok(()) => return Ok(()),
            // Not supported here (an old kernel, or a file system without it, such as
            // overlayfs for folders of a lower layer): fall back to two renames.
            Err(e)
                if e == rustix::io::Errno::INVAL
                    || e == rustix::io::Errno::NOSYS
                    || e == rustix::io::Errno::XDEV => {}
            Err(e) => return Err(e.into()),
        }
    }
    let mut aside = from.as_os_str().to_owned();
    aside.push("-old");
    let aside = PathBuf::from(aside);
    std::fs::rename(to, &aside)?;
    if let Err(e) = std::fs::rename(from, to) {
        let _ = std::fs::rename(&aside, to);
        return Err(e);
    }
    std::fs::rename(&aside, from)
}

/// Removes staging folders of `name` left by bakes whose process is gone (killed mid-bake).
fn remove_stale(parent: &Path, name: &str) {
    let prefix = format!(".{name}{MARK}");
    let Ok(read) = std::fs::read_dir(parent) else {
        return;
    };
    for e in read.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix) else {
            continue;
        };
        let pid = rest
            .split(['-', '.'])
            .next()
            .and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid
            && pid != std::process::id()
            && !process_alive(pid)
        {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        // Without /proc, assume it lives: a leftover folder is better than a lost bake.
        true
    }
}
