//! The file system: the kinds of special file, opening without blocking, hard links,
//! ownership, flushing a folder, locking a folder, files held open, symbolic links, mount
//! points, the atomic folder swap and free space.

use std::path::Path;

/// What a special file is, in words ("a FIFO (named pipe)"), or `None` for a file, folder or
/// link. Only Unix has FIFOs, devices and sockets in the file system.
pub fn special_kind(t: &std::fs::FileType) -> Option<&'static str> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    let _ = t;
    None
}

/// Makes `options` open without waiting: on Unix, opening a FIFO for reading otherwise
/// waits for a writer, for ever. Elsewhere nothing waits.
pub fn open_without_waiting(options: &mut std::fs::OpenOptions) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let _ = options;
}

/// How many names the file has (hard links). Windows: 1 (std does not tell; a save there
/// replaces the file by rename, as for a file of one name).
pub fn link_count(meta: &std::fs::Metadata) -> u64 {
    #[cfg(unix)]
    {
        std::os::unix::fs::MetadataExt::nlink(meta)
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        1
    }
}

/// Makes a temporary file get the mode a new file gets (Unix: 0666 less the umask, as
/// open(2) does, not tempfile's 0600); elsewhere the system's default.
pub fn new_file_mode(builder: &mut tempfile::Builder<'_, '_>) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let _ = builder;
}

/// Gives `file` the owner and group of `old` where this user may (Unix; only root may give a
/// file away, a member of the group may still keep the group). Elsewhere a new file belongs
/// to its writer.
pub fn keep_owner(file: &std::fs::File, old: &std::fs::Metadata) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let mine = file.metadata()?;
        if (mine.uid(), mine.gid()) != (old.uid(), old.gid()) {
            let _ = std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()))
                .or_else(|_| std::os::unix::fs::fchown(file, None, Some(old.gid())));
        }
    }
    let _ = (file, old);
    Ok(())
}

/// Flushes the file at `path` to disk; returns it, open. Opened to write: Windows flushes
/// only through a handle that may write (`FlushFileBuffers` needs `GENERIC_WRITE`; a
/// read-only handle is refused, "permission denied"). Nothing is written or truncated.
pub fn flush_file(path: &Path) -> std::io::Result<std::fs::File> {
    let f = std::fs::OpenOptions::new().write(true).open(path)?;
    f.sync_all()?;
    Ok(f)
}

/// Flushes a folder's entries to disk, so a rename inside it survives a power cut (Unix;
/// Windows flushes the entries with the files and cannot open a folder as a file).
pub fn sync_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)?.sync_all()?;
    let _ = dir;
    Ok(())
}

/// Whether file names such as `CON`, `NUL` or `COM1.png` name devices here, in any folder
/// (Windows), so that opening one opens the console or a port instead of a file.
pub const DEVICE_NAMES: bool = cfg!(windows);

/// Waits for, and holds (until the returned file is dropped), an exclusive lock on the folder
/// `dir`. Unix locks the folder itself (`flock`). Windows cannot open a folder as a file, so
/// it locks the file `stand_in` inside it, made if missing and left there (a name the caller
/// keeps out of its listings).
pub fn lock_folder(dir: &Path, stand_in: &str) -> std::io::Result<std::fs::File> {
    #[cfg(unix)]
    let f = {
        let _ = stand_in;
        std::fs::File::open(dir)?
    };
    #[cfg(not(unix))]
    let f = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(dir.join(stand_in))?;
    f.lock()?;
    Ok(f)
}

/// Whether a file held open by another program stops its folder being renamed or the file
/// being replaced (Windows); elsewhere such a file is renamed and removed under its holder.
pub const OPEN_FILES_PIN: bool = cfg!(windows);

/// Whether another program holds the file at `path` open, so that Windows refuses to rename
/// or remove it, or the folder it is in. Windows: an exclusive open is refused with a
/// sharing violation. Unix renames and removes files held open (their holder keeps the old
/// file): always `false`.
pub fn held_open(path: &Path) -> bool {
    #[cfg(windows)]
    {
        use std::os::windows::fs::OpenOptionsExt;
        /// `ERROR_SHARING_VIOLATION`.
        const SHARING_VIOLATION: i32 = 32;
        let open = std::fs::OpenOptions::new()
            .read(true)
            .share_mode(0)
            .open(path);
        matches!(open, Err(e) if e.raw_os_error() == Some(SHARING_VIOLATION))
    }
    #[cfg(not(windows))]
    {
        let _ = path;
        false
    }
}

/// Makes `to` a symbolic link like `from` (Unix); elsewhere a copy of what it points to.
pub fn copy_symlink(from: &Path, to: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(std::fs::read_link(from)?, to)
    }
    #[cfg(not(unix))]
    {
        std::fs::copy(from, to).map(|_| ())
    }
}

/// Whether `dir` is the root of a mounted file system (it cannot be renamed). Linux asks
/// statx; other Unix compares devices with the parent folder; elsewhere `false`.
pub fn is_mount_root(dir: &Path) -> bool {
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{AtFlags, CWD, StatxAttributes, StatxFlags, statx};
        if let Ok(st) = statx(CWD, dir, AtFlags::empty(), StatxFlags::BASIC_STATS)
            && st.stx_attributes_mask.contains(StatxAttributes::MOUNT_ROOT)
        {
            return st.stx_attributes.contains(StatxAttributes::MOUNT_ROOT);
        }
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let parent = dir.join("..");
        match (std::fs::metadata(dir), std::fs::metadata(parent)) {
            (Ok(a), Ok(b)) => a.dev() != b.dev() || a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        false
    }
}

/// Swaps the names of the folders `from` and `to` in one atomic step where the system can:
/// `Ok(true)`. Linux has `renameat2(RENAME_EXCHANGE)`, macOS `renameatx_np(RENAME_SWAP)`
/// (APFS; not HFS+). `Ok(false)` where it cannot (Windows, an old kernel, a file system
/// without it): the caller renames in two steps.
pub fn exchange_folders(from: &Path, to: &Path) -> std::io::Result<bool> {
    #[cfg(any(target_os = "linux", target_os = "android", target_vendor = "apple"))]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, from, CWD, to, RenameFlags::EXCHANGE) {
            Ok(()) => return Ok(true),
            // Not supported here (an old kernel or macOS, or a file system without it, such
            // as overlayfs for folders of a lower layer, or HFS+).
            Err(e)
                if e == rustix::io::Errno::INVAL
                    || e == rustix::io::Errno::NOSYS
                    || e == rustix::io::Errno::XDEV
                    || e == rustix::io::Errno::NOTSUP => {}
            Err(e) => return Err(e.into()),
        }
    }
    let _ = (from, to);
    Ok(false)
}

/// Bytes free to this user on the file system holding `dir`, where the system says (Unix's
/// statvfs); `None` elsewhere.
pub fn free_space(dir: &Path) -> Option<u64> {
    #[cfg(unix)]
    {
        rustix::fs::statvfs(dir)
            .ok()
            .map(|s| s.f_bavail.saturating_mul(s.f_frsize))
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        None
    }
}
