//! A bake replaces its output folder as a whole.
//!
//! Every file is written into a fresh staging folder beside the output folder
//! (`.windloom-bake-ID`, a short fixed-length name, so an output name as long as the file
//! system allows still works). When everything is written and flushed, what the user (or an
//! engine: Unity's `.meta`, Godot's `.import`) put in the old folder is hard-linked into the
//! staging folder, and the two folders are exchanged with one `renameat2(RENAME_EXCHANGE)`:
//! a reader sees the whole old bake or the whole new one, never a mixture. The old bake, now
//! under the staging name, is then deleted. Where the exchange is not available (another
//! system, or a file system without it) the old folder is renamed aside and the new one
//! renamed in, which leaves a moment with no folder rather than a mixed one.
//!
//! **A mount point** (a Docker volume, a bind mount, a share's root) cannot be renamed, and
//! neither can a folder whose parent this user may not write: there the staging folder is
//! made inside the output folder, and the commit moves the new files in one by one (each
//! replaced whole by a rename), the old manifest removed first and the new one renamed in
//! last, after a commit plan was flushed to disk. A reader that goes by `manifest.json` sees
//! the old bake, no manifest, or the whole new bake; a bake killed while it moves files is
//! finished by the next bake into that folder (it rolls the plan forward).
//!
//! **Ownership** holds across processes, containers and machines that share the folder: each
//! staging folder has a lock file beside it (`.windloom-bake-ID.lock`, naming its host and
//! process) that its bake holds locked (`flock`) until it ends. The kernel, or the file
//! server, releases the lock when the process dies however it dies, so a bake removes (or
//! rolls forward) exactly the staging folders whose lock it can take, and never one whose
//! bake still runs, wherever that runs.

use super::error::BakeError;
use super::manifest::MANIFEST;
use crate::io::{parent_dir, resolve_links, sync_dir};
use std::collections::BTreeSet;
use std::fs::File;
use std::path::{Path, PathBuf};

/// How every staging folder's (and its lock file's) name starts.
pub(super) const MARK: &str = ".windloom-bake-";
/// The commit plan inside a staging folder that commits in place: the old bake's names to
/// remove once the new files are in.
const PLAN: &str = ".windloom-commit";
/// The file a folder's commit lock is taken on where a folder cannot be locked itself
/// (Windows: `platform::fs::lock_folder`). It starts with [`MARK`], so it is no one's output
/// and no one's file; the sweep leaves it be.
const FOLDER_LOCK: &str = ".windloom-bake-folder";
/// How long a half-made lock file (`.lock-new`) is left alone: it is locked and renamed
/// within microseconds of its making, so one this old belongs to a bake that died then.
const HALF_MADE_GRACE: std::time::Duration = std::time::Duration::from_secs(60);

/// A staging folder for one bake into `out`; removed on drop unless committed.
pub(crate) struct Staging {
    /// The output folder (symbolic links resolved).
    out: PathBuf,
    /// The staging folder: beside `out`, or inside it when committing in place.
    dir: PathBuf,
    /// Its lock file, held locked by `_lock` while the bake runs.
    lock: PathBuf,
    _lock: File,
    /// Names an earlier bake in `out` wrote: those its manifest lists whose content is still
    /// what it wrote (size and CRC-32), `manifest.json` included. Everything else in `out` is
    /// the user's and is carried over (a manifest's word alone removes nothing).
    previous: Option<BTreeSet<String>>,
    /// The earlier bake's manifest `sequence` (0: none, or a version 1 manifest).
    previous_sequence: u64,
    /// The output folder cannot be renamed (a mount point), or its parent not written.
    in_place: bool,
    committed: bool,
}

fn output_error(path: &Path, source: std::io::Error) -> BakeError {
    BakeError::Output {
        path: path.to_path_buf(),
        source: crate::io::plain(source),
    }
}

fn other(message: String) -> std::io::Error {
    std::io::Error::other(message)
}

/// Who holds a staging folder, for a person reading the lock file.
fn owner_record() -> String {
    let (host, boot) = crate::platform::process::host_and_boot();
    format!(
        "windloom bake\nhost {host}\nboot {boot}\npid {}\n",
        std::process::id()
    )
}

/// Makes a locked lock file and its staging folder in `home`: the lock file is made and
/// locked under a temporary name, then renamed, so a sweeping bake never finds it unlocked.
fn make_staging(home: &Path) -> std::io::Result<(PathBuf, PathBuf, File)> {
    use std::io::Write;
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let base = format!("{MARK}{}-{stamp:x}", std::process::id());
    let half = home.join(format!("{base}.lock-new"));
    let lock = home.join(format!("{base}.lock"));
    let dir = home.join(&base);
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&half)?;
    let made = (|| {
        file.lock()?;
        file.write_all(owner_record().as_bytes())?;
        std::fs::rename(&half, &lock)?;
        // create_dir applies the umask: the new folder gets the user's usual mode.
        std::fs::create_dir(&dir)
    })();
    if let Err(e) = made {
        let _ = std::fs::remove_file(&half);
        let _ = std::fs::remove_file(&lock);
        return Err(e);
    }
    Ok((dir, lock, file))
}

impl Staging {
    /// Checks `out` and creates the staging folder (beside it, or inside it where it cannot
    /// be renamed).
    pub(crate) fn new(out: &Path) -> Result<Self, BakeError> {
        Self::open(out, false)
    }

    /// [`Self::new`]; `force_in_place` commits in place into an existing folder that could be
    /// renamed (the tests' stand-in for a mount point).
    fn open(out: &Path, force_in_place: bool) -> Result<Self, BakeError> {
        let out = resolve_links(out).map_err(|e| output_error(out, e))?;
        let exists = match std::fs::symlink_metadata(&out) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => false,
            Err(e) => return Err(output_error(&out, e)),
            Ok(m) if !m.is_dir() => {
                return Err(output_error(
                    &out,
                    other(format!(
                        "it is {}, not a folder; a bake writes a folder",
                        crate::io::kind_of(&m)
                    )),
                ));
            }
            Ok(_) => true,
        };
        let parent = parent_dir(&out).to_path_buf();
        std::fs::create_dir_all(&parent).map_err(|e| output_error(&parent, e))?;
        if out.file_name().is_none() {
            return Err(output_error(&out, other("it has no folder name".into())));
        }
        // What killed bakes left, here or (committing in place) inside the folder, goes
        // before the folder is read: a plan half carried out is finished first.
        sweep(&parent);
        let previous = if exists {
            // Read while no in-place commit is halfway through the folder (it removes the
            // manifest first and renames it in last).
            let _commit = lock_folder(&out).map_err(|e| output_error(&out, e))?;
            sweep_holding(&out, true);
            Some(previous_bake(&out)?)
        } else {
            None
        };
        let previous_sequence = previous.as_ref().map_or(0, |_| previous_sequence(&out));
        let mut in_place = exists && (force_in_place || crate::platform::fs::is_mount_root(&out));
        let made = if in_place {
            make_staging(&out)
        } else {
            match make_staging(&parent) {
                Err(e)
                    if exists
                        && matches!(
                            e.kind(),
                            std::io::ErrorKind::PermissionDenied
                                | std::io::ErrorKind::ReadOnlyFilesystem
                        ) =>
                {
                    in_place = true;
                    make_staging(&out)
                }
                other => other,
            }
        };
        let (dir, lock, file) = made.map_err(|e| {
            let home = if in_place { &out } else { &parent };
            output_error(
                &out,
                other(format!(
                    "cannot make a staging folder in {}: {}",
                    home.display(),
                    crate::io::plain(e)
                )),
            )
        })?;
        let staging = Self {
            out,
            dir,
            lock,
            _lock: file,
            previous,
            previous_sequence,
            in_place,
            committed: false,
        };
        if staging.previous.is_some() && !staging.in_place {
            // The new folder keeps the old one's permissions.
            let perms = std::fs::metadata(&staging.out)
                .map_err(|e| output_error(&staging.out, e))?
                .permissions();
            std::fs::set_permissions(&staging.dir, perms)
                .map_err(|e| output_error(&staging.out, e))?;
        }
        Ok(staging)
    }

    pub(crate) fn path(&self) -> &Path {
        &self.dir
    }

    /// The `sequence` this bake's manifest carries: one more than the bake it replaces (1
    /// into a new folder), so a reader polling the folder reloads when it changes.
    pub(crate) fn next_sequence(&self) -> u64 {
        self.previous_sequence + 1
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
        sync_dir(&self.dir).map_err(|e| output_error(&self.out, e))?;
        // Windows will neither rename a folder with a file in it held open nor replace that
        // file: found before anything moves, so the previous bake stays whole.
        if self.previous.is_some()
            && let Some(file) = held_file(&self.out)
        {
            return Err(held_error(&self.out, &file));
        }
        if self.in_place {
            // One in-place commit at a time into a folder, from any process or machine (a
            // lock on the folder itself), and against the bake there now: another may have
            // committed since this one began, or died halfway (rolled forward first).
            let _commit = lock_folder(&self.out).map_err(|e| output_error(&self.out, e))?;
            sweep_holding(&self.out, true);
            let previous = previous_bake(&self.out)?;
            let new: BTreeSet<String> = entry_names(&self.dir)?.into_iter().collect();
            let remove: Vec<&String> = previous.difference(&new).collect();
            let plan = serde_json::json!({ "remove": remove }).to_string();
            crate::io::write_atomic(&self.dir.join(PLAN), plan.as_bytes())
                .map_err(|e| output_error(&self.out, e))?;
            self.committed = true;
            return roll_forward(&self.dir, &self.out).map_err(|e| output_error(&self.out, e));
        }
        let Some(previous) = self.previous.clone() else {
            std::fs::rename(&self.dir, &self.out).map_err(|e| output_error(&self.out, e))?;
            self.committed = true;
            return sync_dir(&parent).map_err(|e| output_error(&parent, e));
        };
        let theirs = |name: &str| !previous.contains(name) && !name.starts_with(MARK);
        for name in entry_names(&self.out)?.into_iter().filter(|n| theirs(n)) {
            let to = self.dir.join(&name);
            if std::fs::symlink_metadata(&to).is_err() {
                link_tree(&self.out.join(&name), &to)
                    .map_err(|e| output_error(&self.out.join(&name), e))?;
            }
        }
        exchange(&self.dir, &self.out).map_err(|e| match held_file(&self.out) {
            // Opened between the check and the swap.
            Some(file) => held_error(&self.out, &file),
            None => output_error(&self.out, e),
        })?;
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
        // The folder goes before its lock file: a folder whose lock file is gone is dead.
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Carries out an in-place commit's plan (idempotent: a bake killed halfway through it is
/// finished by the next): the old manifest goes, the new files move in (each replacing its
/// namesake whole), the old bake's other files go, and the new manifest comes last.
fn roll_forward(dir: &Path, out: &Path) -> std::io::Result<()> {
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join(PLAN))?).map_err(std::io::Error::other)?;
    match std::fs::remove_file(out.join(MANIFEST)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    for e in std::fs::read_dir(dir)? {
        let name = e?.file_name();
        if name != PLAN && name != MANIFEST {
            std::fs::rename(dir.join(&name), out.join(&name))?;
        }
    }
    for name in plan["remove"].as_array().into_iter().flatten() {
        if let Some(name) = name
            .as_str()
            .filter(|n| !n.contains(['/', '\\']) && *n != MANIFEST)
        {
            match std::fs::remove_file(out.join(name)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
        }
    }
    if dir.join(MANIFEST).exists() {
        std::fs::rename(dir.join(MANIFEST), out.join(MANIFEST))?;
    }
    sync_dir(out)?;
    std::fs::remove_dir_all(dir)
}

/// Removes (or, for an in-place commit cut short, finishes) the staging folders in `home`
/// whose bake is gone: those whose lock this process can take. A staging folder whose lock
/// file is gone is dead too (its bake removes the folder before the lock file).
fn sweep(home: &Path) {
    sweep_holding(home, false);
}

/// [`sweep`], where `held` says this process already holds `home`'s commit lock.
fn sweep_holding(home: &Path, held: bool) {
    let Ok(read) = std::fs::read_dir(home) else {
        return;
    };
    let names: Vec<String> = read
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    for name in &names {
        if !name.starts_with(MARK) {
            legacy_stale(home, name);
            continue;
        }
        if name == FOLDER_LOCK {
            continue;
        }
        let path = home.join(name);
        if let Some(base) = name.strip_suffix(".lock-new") {
            let old = std::fs::metadata(&path)
                .and_then(|m| m.modified())
                .is_ok_and(|t| t.elapsed().is_ok_and(|a| a > HALF_MADE_GRACE));
            if old && !names.iter().any(|n| n == base) && lock_free(&path).is_some() {
                let _ = std::fs::remove_file(&path);
            }
        } else if let Some(base) = name.strip_suffix(".lock") {
            if let Some(_held) = lock_free(&path) {
                finish(&home.join(base), home, held);
                let _ = std::fs::remove_file(&path);
            }
        } else if !names.iter().any(|n| n == &format!("{name}.lock")) {
            finish(&path, home, held);
        }
    }
}

/// A dead bake's staging folder: rolled forward where its in-place commit had begun, else
/// removed.
fn finish(dir: &Path, home: &Path, held: bool) {
    if dir.join(PLAN).exists() {
        let commit = if held { None } else { lock_folder(home).ok() };
        if (held || commit.is_some()) && roll_forward(dir, home).is_ok() {
            return;
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Waits for, and holds, the lock on a folder that in-place commits into it share.
fn lock_folder(dir: &Path) -> std::io::Result<File> {
    crate::platform::fs::lock_folder(dir, FOLDER_LOCK)
}

/// The first file under `dir` that another program holds open where that stops the folder
/// being replaced (Windows: an engine importing a texture, a viewer showing one); `None`
/// elsewhere, where a file held open is renamed and removed under its holder.
fn held_file(dir: &Path) -> Option<PathBuf> {
    if !crate::platform::fs::OPEN_FILES_PIN {
        return None;
    }
    for e in std::fs::read_dir(dir).ok()?.flatten() {
        if e.file_name().to_string_lossy().starts_with(MARK) {
            continue;
        }
        let path = e.path();
        let found = match e.file_type() {
            Ok(t) if t.is_dir() => held_file(&path),
            Ok(_) => crate::platform::fs::held_open(&path).then_some(path),
            Err(_) => None,
        };
        if found.is_some() {
            return found;
        }
    }
    None
}

/// The error of a bake that cannot replace its folder because `file` in it is held open:
/// the previous bake is left as it was.
fn held_error(out: &Path, file: &Path) -> BakeError {
    output_error(
        out,
        other(format!(
            "{} is open in another program (an engine importing it, a viewer showing it), and \
             Windows cannot replace a folder while a file in it is open; the previous bake is \
             left as it was: close the file there, or wait for the import, and bake again",
            file.display()
        )),
    )
}

/// The lock file at `path`, locked by this process, if no one else holds it.
fn lock_free(path: &Path) -> Option<File> {
    let f = File::open(path).ok()?;
    f.try_lock().ok().map(|()| f)
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

/// The most bytes an earlier bake's `manifest.json` is read to (a bake of a thousand frame
/// files writes about 0.5 MB).
const MANIFEST_MAX: u64 = 16 << 20;

/// The earlier bake's manifest: a regular file of at most [`MANIFEST_MAX`] bytes, read
/// without waiting (a FIFO in its place is refused, never waited on).
fn read_manifest(out: &Path) -> std::io::Result<String> {
    let bytes = crate::io::read_regular(&out.join(MANIFEST), MANIFEST_MAX, "a bake's manifest")?;
    String::from_utf8(bytes).map_err(|_| other("it is not UTF-8 text".into()))
}

/// The `sequence` of the bake in `out` (0 where it has none).
fn previous_sequence(out: &Path) -> u64 {
    read_manifest(out)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["sequence"].as_u64())
        .unwrap_or(0)
}

/// The size and CRC-32 of the regular file at `path`, read in blocks (a FIFO, a device or a
/// folder is refused without waiting on it).
fn size_and_crc(path: &Path) -> std::io::Result<(u64, u32)> {
    use std::io::Read;
    let (mut file, _) = crate::io::open_regular(path, "a bake's file")?;
    let mut hasher = crc32fast::Hasher::new();
    let mut buf = vec![0u8; 1 << 20];
    let mut size = 0u64;
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            return Ok((size, hasher.finalize()));
        }
        size += n as u64;
        hasher.update(&buf[..n]);
    }
}

/// The CRC-32 of a file this bake wrote, for its manifest entry.
pub(super) fn crc32_of(path: &Path) -> Result<u32, BakeError> {
    size_and_crc(path)
        .map(|(_, crc)| crc)
        .map_err(|source| BakeError::Write {
            path: path.to_path_buf(),
            source,
        })
}

/// Whether the file an earlier manifest lists as `entry` is still the one that bake wrote:
/// its size, and its CRC-32 where the manifest has one. A manifest from before the CRCs
/// (windloom 0.1's first bakes) is taken at its size and the format's first bytes.
fn written_by_bake(path: &Path, entry: &serde_json::Value) -> bool {
    let Some(bytes) = entry["bytes"].as_u64() else {
        return false;
    };
    match entry["crc32"].as_u64() {
        Some(crc) => size_and_crc(path).is_ok_and(|(n, c)| n == bytes && u64::from(c) == crc),
        None => {
            let Ok(meta) = std::fs::symlink_metadata(path) else {
                return false;
            };
            meta.is_file() && meta.len() == bytes && starts_as_its_format(path)
        }
    }
}

/// Whether a file begins as windloom writes its format (by its name's extension).
fn starts_as_its_format(path: &Path) -> bool {
    use std::io::Read;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let magic: &[u8] = match ext.as_deref() {
        Some("png") => b"\x89PNG\r\n\x1a\n",
        Some("exr") => &[0x76, 0x2f, 0x31, 0x01],
        Some("dds") => b"DDS ",
        Some("vf") => b"VF_V",
        Some("fga") => b"",
        // Raw floats have no header: their size, checked above, is their shape.
        Some("f32") => b"",
        _ => return false,
    };
    let mut head = vec![0u8; magic.len()];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|()| head == magic)
}

/// The names an earlier bake wrote into `out`. An empty folder has none; a folder that holds
/// files but no windloom manifest is not a bake folder, and replacing it whole could take
/// more than a bake with it, so it is refused.
fn previous_bake(out: &Path) -> Result<BTreeSet<String>, BakeError> {
    let mut names = entry_names(out)?;
    names.retain(|n| !n.starts_with(MARK));
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
    let text = match read_manifest(out) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(refuse("no manifest.json"));
        }
        Err(e) => {
            return Err(output_error(
                &manifest,
                other(format!(
                    "{} (a bake reads the manifest of the bake it replaces)",
                    crate::io::plain(e)
                )),
            ));
        }
    };
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|_| refuse("its manifest.json is not a windloom bake manifest"))?;
    if value["format"] != super::manifest::FORMAT {
        return Err(refuse("its manifest.json is not a windloom bake manifest"));
    }
    let mut set = BTreeSet::from([MANIFEST.to_string()]);
    // The bake's files, and the terrain's heightmap (`terrain.file`), which it wrote too:
    // each only while it holds what the bake wrote (a manifest listing the user's files
    // claims nothing).
    let entries = (value["files"].as_array().into_iter().flatten())
        .map(|f| (&f["name"], f))
        .chain([(&value["terrain"]["file"], &value["terrain"])]);
    for (name, entry) in entries {
        if let Some(name) = name.as_str() {
            // Only plain names: a manifest cannot make a bake claim files elsewhere.
            if !name.contains(['/', '\\'])
                && name != "."
                && name != ".."
                && written_by_bake(&out.join(name), entry)
            {
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
        crate::platform::fs::copy_symlink(from, to)
    } else if kind.is_dir() {
        std::fs::create_dir(to)?;
        for e in std::fs::read_dir(from)? {
            let e = e?;
            link_tree(&e.path(), &to.join(e.file_name()))?;
        }
        std::fs::set_permissions(to, meta.permissions())
    } else {
        std::fs::hard_link(from, to).or_else(|_| copy_keeping(from, to, &meta))
    }
}

/// Copies a file where it cannot be linked (a file system without hard links, or a file of
/// another user's where the kernel refuses to link it), keeping its modification time and,
/// as a save does, its mode and, where this user may, its owner and group.
fn copy_keeping(from: &Path, to: &Path, meta: &std::fs::Metadata) -> std::io::Result<()> {
    std::fs::copy(from, to)?;
    let f = std::fs::OpenOptions::new().write(true).open(to)?;
    if let Ok(t) = meta.modified() {
        f.set_modified(t)?;
    }
    crate::io::keep_owner_and_mode(&f, meta)
}

/// Swaps two folders' names in one step where the system can; else renames `to` aside and
/// `from` into its place, then the old one to `from`'s name.
fn exchange(from: &Path, to: &Path) -> std::io::Result<()> {
    if crate::platform::fs::exchange_folders(from, to)? {
        return Ok(());
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

/// A staging folder that an earlier windloom (one that named them `.NAME.windloom-bake-PID-N`
/// and knew its owner by a local process id) left beside its output: removed when that
/// process is gone from this machine.
fn legacy_stale(home: &Path, name: &str) {
    let Some((_, rest)) = name.split_once(MARK) else {
        return;
    };
    let pid = rest
        .split(['-', '.'])
        .next()
        .and_then(|p| p.parse::<u32>().ok());
    if let Some(pid) = pid
        && pid != std::process::id()
        // Where the system cannot tell, it lives: a leftover folder beats a lost bake.
        && !crate::platform::process::alive(pid).unwrap_or(true)
    {
        let _ = std::fs::remove_dir_all(home.join(name));
    }
}

/// The error naming the file of the output folder rather than its namesake in the hidden
/// staging folder, which the user never sees.
pub(super) fn outside_staging(e: BakeError, out: &Path) -> BakeError {
    let fix = |path: PathBuf| {
        let parts: Vec<_> = path.components().collect();
        match parts
            .iter()
            .position(|c| c.as_os_str().to_string_lossy().starts_with(MARK))
        {
            Some(i) => parts[i + 1..]
                .iter()
                .fold(out.to_path_buf(), |p, c| p.join(c)),
            None => path,
        }
    };
    match e {
        BakeError::Output { path, source } => BakeError::Output {
            path: fix(path),
            source,
        },
        BakeError::Write { path, source } => BakeError::Write {
            path: fix(path),
            source: crate::io::plain(source),
        },
        other => other,
    }
}

/// Writes a file and flushes it to disk before the folder swap can make it visible.
pub(crate) fn write_file(dir: &Path, name: &str, bytes: &[u8]) -> Result<u64, BakeError> {
    use std::io::Write;
    let path = dir.join(name);
    let err = |source| BakeError::Write {
        path: path.clone(),
        source,
    };
    let mut f = std::fs::File::create(&path).map_err(err)?;
    f.write_all(bytes).map_err(err)?;
    f.sync_all().map_err(err)?;
    Ok(bytes.len() as u64)
}

pub(crate) fn sync_file(path: &Path) -> Result<u64, BakeError> {
    let err = |source| BakeError::Write {
        path: path.to_path_buf(),
        source,
    };
    let f = crate::platform::fs::flush_file(path).map_err(err)?;
    Ok(f.metadata().map_err(err)?.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A staging folder as another machine's bake makes it beside a shared folder: its lock
    /// file held by a process this machine cannot see (here, another open file holding the
    /// lock, under a process id that does not exist here).
    fn foreign_staging(home: &Path) -> (PathBuf, File) {
        let base = format!("{MARK}4000000-1");
        let dir = home.join(&base);
        std::fs::create_dir(&dir).unwrap();
        std::fs::write(dir.join("wind.vf"), "half").unwrap();
        let lock = File::create(home.join(format!("{base}.lock"))).unwrap();
        lock.lock().unwrap();
        (dir, lock)
    }

    /// The ownership check holds across machines: a staging folder whose owner holds its
    /// lock survives other bakes beside it, whatever its process id says; once the owner is
    /// gone (its lock released) the next bake removes it.
    #[test]
    fn a_staging_folder_is_removed_only_when_its_owner_is_gone() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("wind");
        let (theirs, held) = foreign_staging(root.path());
        let mine = Staging::new(&out).unwrap();
        assert!(
            theirs.join("wind.vf").exists(),
            "a live bake's folder was removed"
        );
        // Two bakes of this machine at once: neither removes the other's.
        let second = Staging::new(&out).unwrap();
        assert!(mine.path().exists() && second.path().exists());
        drop(second);
        drop(mine);
        assert!(theirs.exists());
        drop(held);
        let next = Staging::new(&out).unwrap();
        assert!(!theirs.exists(), "a dead bake's folder was left");
        drop(next);
        let left: Vec<String> = entry_names(root.path()).unwrap();
        assert!(left.is_empty(), "{left:?}");
    }

    /// In-place commits into one folder from several bakes at once (two machines baking into
    /// one shared volume) never leave a mixture: after each, the folder holds exactly the
    /// files its manifest lists and the user's file.
    #[test]
    fn concurrent_in_place_commits_leave_one_whole_bake() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("volume");
        std::fs::create_dir(&out).unwrap();
        let bake = |who: usize, frames: usize| {
            let s = Staging::open(&out, true).unwrap();
            assert!(s.in_place);
            let mut files = Vec::new();
            for k in 0..frames {
                let name = format!("wind_{k:04}.vf");
                let content = format!("{who}");
                std::fs::write(s.path().join(&name), &content).unwrap();
                files.push(serde_json::json!({
                    "name": name,
                    "bytes": content.len(),
                    "crc32": crc32fast::hash(content.as_bytes()),
                }));
            }
            let m = serde_json::json!({ "format": "windloom-bake", "who": who, "files": files });
            std::fs::write(s.path().join(MANIFEST), m.to_string()).unwrap();
            s.commit().unwrap();
        };
        bake(9, 2);
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        std::thread::scope(|scope| {
            for who in 0..4 {
                let bake = &bake;
                scope.spawn(move || {
                    for round in 0..15 {
                        bake(who, 1 + (who + round) % 4);
                    }
                });
            }
        });
        let m: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join(MANIFEST)).unwrap()).unwrap();
        let who = m["who"].to_string();
        let mut want: Vec<String> = m["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap().to_string())
            .collect();
        for n in &want {
            assert_eq!(std::fs::read_to_string(out.join(n)).unwrap(), who, "{n}");
        }
        want.extend([MANIFEST.to_string(), "notes.txt".to_string()]);
        want.sort();
        let mut have = entry_names(&out).unwrap();
        have.sort();
        assert_eq!(have, want);
        assert!(entry_names(root.path()).unwrap() == ["volume"]);
    }

    /// An in-place commit cut short (the bake killed while moving files into a mount point)
    /// is finished by the next bake: the folder then holds the whole new bake and the user's
    /// files, and no staging folder.
    #[test]
    fn an_in_place_commit_cut_short_is_rolled_forward() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("volume");
        std::fs::create_dir(&out).unwrap();
        // The old bake: two frames; and a file of the user's.
        let listed = |name: &str, content: &str| {
            serde_json::json!({
                "name": name,
                "bytes": content.len(),
                "crc32": crc32fast::hash(content.as_bytes()),
            })
        };
        let old = serde_json::json!({
            "format": "windloom-bake",
            "files": [listed("a_0000.vf", "old0"), listed("a_0001.vf", "old1")],
        });
        std::fs::write(out.join(MANIFEST), old.to_string()).unwrap();
        std::fs::write(out.join("a_0000.vf"), "old0").unwrap();
        std::fs::write(out.join("a_0001.vf"), "old1").unwrap();
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        // The new bake, one frame, staged inside, its plan written and half carried out: the
        // old manifest gone, the new frame moved in, then the bake died (its lock free).
        let dir = out.join(format!("{MARK}4000001-2"));
        std::fs::create_dir(&dir).unwrap();
        let new =
            serde_json::json!({ "format": "windloom-bake", "files": [listed("a.vf", "new")] });
        std::fs::write(dir.join(MANIFEST), new.to_string()).unwrap();
        std::fs::write(
            dir.join(PLAN),
            r#"{"remove":["a_0000.vf","a_0001.vf","manifest.json"]}"#,
        )
        .unwrap();
        std::fs::remove_file(out.join(MANIFEST)).unwrap();
        std::fs::write(out.join("a.vf"), "new").unwrap();
        File::create(out.join(format!("{MARK}4000001-2.lock"))).unwrap();

        let next = Staging::new(&out).unwrap();
        assert_eq!(
            next.previous,
            Some(BTreeSet::from([MANIFEST.into(), "a.vf".into()]))
        );
        drop(next);
        let mut names = entry_names(&out).unwrap();
        names.sort();
        assert_eq!(names, ["a.vf", "manifest.json", "notes.txt"]);
    }
}
