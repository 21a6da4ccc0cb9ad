//! The file system edge: loading layouts with diagnostics and writing files atomically.

pub mod disk;
mod document;
pub mod images;
pub mod presets;
pub mod recovery;

pub use document::{AUTOSAVE_SECONDS, Document};

use crate::doc::{self, Diagnostics, Layout};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Every problem of the file, one per line, each prefixed with the file name.
    #[error("{}", .diagnostics.0.iter().map(|d| format!("{}:{d}", path.display())).collect::<Vec<_>>().join("\n"))]
    Invalid {
        path: PathBuf,
        diagnostics: Diagnostics,
    },
}

/// The largest map backdrop windloom reads: pixels along a side, pixels in all, bytes on disk.
pub const BACKDROP_MAX_SIDE: u32 = 16_384;
pub const BACKDROP_MAX_PIXELS: u64 = 64 << 20;
pub const BACKDROP_MAX_BYTES: u64 = 256 << 20;

/// Why an image the layout names — its map backdrop, a mask obstacle's image, the grass's
/// density map; `what` says which — could not be read. Never a reason to refuse the layout:
/// the editor, `render` and `validate` report it as a warning and go on without the image
/// (a bake refuses a mask it cannot read: `doc::mask_problems`).
#[derive(Debug, thiserror::Error)]
pub enum BackdropError {
    #[error("{what} {}: {source}", path.display())]
    Io {
        what: &'static str,
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{what} {}: {size} bytes, more than the {} MiB windloom reads", path.display(), BACKDROP_MAX_BYTES >> 20)]
    TooManyBytes {
        what: &'static str,
        path: PathBuf,
        size: u64,
    },
    #[error("{what} {}: {w}×{h} pixels, more than windloom reads ({BACKDROP_MAX_SIDE} a side, {} Mpixels)", path.display(), BACKDROP_MAX_PIXELS >> 20)]
    TooLarge {
        what: &'static str,
        path: PathBuf,
        w: u32,
        h: u32,
    },
    #[error("{what} {}: {message}", path.display())]
    Decode {
        what: &'static str,
        path: PathBuf,
        message: String,
    },
}

/// The folder a layout's relative paths (its map image) start from: the layout file's
/// folder ([`parent_dir`]), or the working folder (`.`) for a layout not yet saved.
pub fn layout_base(layout_path: Option<&Path>) -> PathBuf {
    layout_path.map_or(Path::new("."), parent_dir).to_path_buf()
}

/// `path` as the layout stores it: relative to `base` when inside it (with `/` separators, so
/// the layout moves between systems with its folder), else as it is.
pub fn relative_to(path: &Path, base: &Path) -> String {
    let abs = |p: &Path| {
        std::path::absolute(p)
            .map(|a| a.canonicalize().unwrap_or(a))
            .unwrap_or_else(|_| p.to_path_buf())
    };
    match abs(path).strip_prefix(abs(base)) {
        Ok(rel) => rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/"),
        Err(_) => path.display().to_string(),
    }
}

/// The file a path the layout stores names (`map.image`, a mask's, the heightmap's, the
/// density map's): relative to `base`, the layout's folder, with `/` or `\` between folders
/// (a layout written on Windows opens here, and back); an absolute path as it is.
pub fn layout_file(base: &Path, stored: &str) -> PathBuf {
    if Path::new(stored).is_absolute() {
        return PathBuf::from(stored);
    }
    doc::portable::path_parts(stored).fold(base.to_path_buf(), |p, part| p.join(part))
}

/// Why a layout cannot be saved as `path` so that it opens on every platform: its file name,
/// or a file it names, that Windows (the strictest) cannot hold. One line each.
pub fn portability_problems(path: &Path, layout: &Layout) -> Vec<String> {
    let mut problems = Vec::new();
    if let Some(name) = path.file_name() {
        let name = name.to_string_lossy();
        if let Some(why) = doc::portable::name_problem(&name) {
            problems.push(format!(
                "the file name {:?}: {why}",
                doc::printable(&name, 80)
            ));
        }
    }
    problems.extend(doc::portable::layout_problems(layout));
    problems
}

/// [`portability_problems`] as the error a save returns: nothing is written.
pub fn check_portable(path: &Path, layout: &Layout) -> std::io::Result<()> {
    match portability_problems(path, layout).first() {
        None => Ok(()),
        Some(p) => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("not saved, so that it opens on every platform: {p}"),
        )),
    }
}

/// The layout's map backdrop decoded ([`load_backdrop`]), if it has one.
pub fn layout_backdrop(
    layout: &Layout,
    base: &Path,
) -> Option<Result<image::RgbaImage, BackdropError>> {
    layout.world.map.as_ref().map(|m| load_backdrop(base, m))
}

/// The map backdrop's image (`map.image`, relative to the layout's folder `base`), as RGBA8:
/// its size checked on disk and in its header before any pixel is decoded.
pub fn load_backdrop(
    base: &Path,
    map: &doc::MapBackdrop,
) -> Result<image::RgbaImage, BackdropError> {
    load_picture(base, &map.image, "map image")
}

/// A picture (PNG, JPEG or EXR; `name` relative to the layout's folder `base`, `what` it is
/// for messages) as RGBA8, its size checked as the backdrop's.
pub fn load_picture(
    base: &Path,
    name: &str,
    what: &'static str,
) -> Result<image::RgbaImage, BackdropError> {
    let path = layout_file(base, name);
    let bytes = read_image_file(&path, what)?;
    if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        // An EXR: its luminance as grey (the grey images' reader).
        let m = load_mask(base, name, what)?;
        let grey = m.luminance.iter().flat_map(|&l| {
            let v = (f32::from(l) / 65535.0 * 255.0).round() as u8;
            [v, v, v, 255]
        });
        return image::RgbaImage::from_raw(m.width, m.height, grey.collect())
            .ok_or_else(|| decode_error(&path, what, "its pixels do not fill it"));
    }
    let (reader, _) = image_decoder(&path, what, &bytes)?;
    Ok(reader
        .decode()
        .map_err(|e| decode_error(&path, what, e))?
        .to_rgba8())
}

/// An image file the layout names (`what` it is, for the messages), read whole after its
/// size on disk is checked.
fn read_image_file(path: &Path, what: &'static str) -> Result<Vec<u8>, BackdropError> {
    let io = |source| BackdropError::Io {
        what,
        path: path.to_path_buf(),
        source: plain(source),
    };
    // Where a name such as CON or NUL opens a device (Windows: the console, the null
    // device), it is refused before it is opened; elsewhere the file is read, and a save or
    // a bake refuses the name as one Windows cannot hold.
    if let Some(why) = path
        .file_name()
        .filter(|_| crate::platform::fs::DEVICE_NAMES)
        .and_then(|n| doc::portable::name_problem(&n.to_string_lossy()))
    {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            why,
        )));
    }
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > BACKDROP_MAX_BYTES {
        return Err(BackdropError::TooManyBytes {
            what,
            path: path.to_path_buf(),
            size,
        });
    }
    read_regular(path, BACKDROP_MAX_BYTES, &format!("a {what}")).map_err(io)
}

fn decode_error(path: &Path, what: &'static str, e: impl std::fmt::Display) -> BackdropError {
    BackdropError::Decode {
        what,
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Refuses an image of more pixels than windloom reads.
fn check_pixels(path: &Path, what: &'static str, w: u32, h: u32) -> Result<(), BackdropError> {
    if w > BACKDROP_MAX_SIDE
        || h > BACKDROP_MAX_SIDE
        || u64::from(w) * u64::from(h) > BACKDROP_MAX_PIXELS
    {
        return Err(BackdropError::TooLarge {
            what,
            path: path.to_path_buf(),
            w,
            h,
        });
    }
    Ok(())
}

/// An image decoder over bytes in memory.
type ImageDecoder<'a> = image::ImageReader<std::io::Cursor<&'a [u8]>>;

/// A decoder of the image `bytes` (its format guessed) and its size, checked in its header,
/// limited so that decoding allocates no more than windloom reads.
fn image_decoder<'a>(
    path: &Path,
    what: &'static str,
    bytes: &'a [u8],
) -> Result<(ImageDecoder<'a>, [u32; 2]), BackdropError> {
    let open = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|source| BackdropError::Io {
                what,
                path: path.to_path_buf(),
                source: plain(source),
            })
    };
    let (w, h) = open()?
        .into_dimensions()
        .map_err(|e| decode_error(path, what, e))?;
    check_pixels(path, what, w, h)?;
    let mut reader = open()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(BACKDROP_MAX_SIDE);
    limits.max_image_height = Some(BACKDROP_MAX_SIDE);
    limits.max_alloc = Some(BACKDROP_MAX_PIXELS * 8);
    reader.limits(limits);
    Ok((reader, [w, h]))
}

/// An I/O error in plain words: the kinds a command meets on a hostile file system said as
/// a user reads them, and never the OS's "(os error 39)".
pub fn plain(e: std::io::Error) -> std::io::Error {
    use std::io::ErrorKind as K;
    // Messages windloom wrote itself (no OS code) are already in words.
    if e.raw_os_error().is_none() {
        return e;
    }
    let said = match e.kind() {
        K::DirectoryNotEmpty => {
            "a folder that had to be empty was not (another program writes there?)"
        }
        K::ResourceBusy => {
            "it is busy: a mount point (a Docker volume, a bind mount) or in use by another program"
        }
        K::CrossesDevices => "it is on another file system than its folder",
        K::ReadOnlyFilesystem => "the file system is read-only",
        K::StorageFull => "the disk is full",
        K::QuotaExceeded => "the disk quota is used up",
        K::PermissionDenied => "permission denied",
        K::InvalidFilename => "the name is too long, or not allowed here",
        K::NotADirectory => "a part of the path is a file, not a folder",
        K::IsADirectory => "it is a folder",
        K::NotFound => "it does not exist",
        K::TooManyLinks => "too many links",
        // Anything else: the OS's own words, without the number.
        _ => {
            let text = e.to_string();
            let text = text.rfind(" (os error ").map_or(&text[..], |i| &text[..i]);
            return std::io::Error::new(e.kind(), text.to_string());
        }
    };
    std::io::Error::new(e.kind(), said)
}

/// What a path is, in words, for a message that refuses it ("a FIFO (named pipe)").
pub fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if let Some(kind) = crate::platform::fs::special_kind(&t) {
        return kind;
    }
    if t.is_dir() {
        "a folder"
    } else if t.is_symlink() {
        "a symbolic link"
    } else if t.is_file() {
        "a file"
    } else {
        "not a file"
    }
}

/// Opens a regular file for reading (`what` names it in the refusal: "a layout"), with its
/// metadata. A FIFO, a device, a socket or a folder is refused without being read (a FIFO is
/// opened without waiting for a writer).
pub fn open_regular(
    path: &Path,
    what: &str,
) -> std::io::Result<(std::fs::File, std::fs::Metadata)> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    crate::platform::fs::open_without_waiting(&mut options);
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "it is {}, not a regular file; windloom reads {what} only from a regular file",
                kind_of(&meta)
            ),
        ));
    }
    Ok((file, meta))
}

/// Reads a whole regular file of at most `max` bytes (`what` names it in the refusal: "a
/// layout"). A FIFO, a device, a socket or a folder is refused without being read (a FIFO is
/// opened without waiting for a writer), and so is a file longer than `max`, before any of
/// it is read; a file that grows past `max` while it is read is refused too.
pub fn read_regular(path: &Path, max: u64, what: &str) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let (file, meta) = open_regular(path, what)?;
    let too_long = |size: u64| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "{size} bytes, more than the {} windloom reads as {what}",
                mib(max)
            ),
        )
    };
    if meta.len() > max {
        return Err(too_long(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(too_long(bytes.len() as u64));
    }
    Ok(bytes)
}

/// `bytes` in MiB for a message ("16 MiB").
fn mib(bytes: u64) -> String {
    format!("{} MiB", bytes >> 20)
}

/// Reads and validates a layout file: a regular file of at most [`doc::LAYOUT_MAX_BYTES`],
/// with its images read beside it.
pub fn load(path: &Path) -> Result<Layout, LoadError> {
    let mut layout = load_unread(path)?;
    load_masks(&mut layout, &layout_base(Some(path)));
    Ok(layout)
}

/// [`load`] without reading the images it names (a recovery copy, whose images live
/// elsewhere).
pub fn load_unread(path: &Path) -> Result<Layout, LoadError> {
    let bytes =
        read_regular(path, doc::LAYOUT_MAX_BYTES, "a layout").map_err(|source| LoadError::Io {
            path: path.to_path_buf(),
            source: plain(source),
        })?;
    doc::parse_bytes(&bytes).map_err(|diagnostics| LoadError::Invalid {
        path: path.to_path_buf(),
        diagnostics,
    })
}

/// Reads each mask obstacle's image, the terrain's heightmap and the grass's density map (relative to the layout's
/// folder `base`), into its `pixels`: loaded, or failed with the reason. Images already
/// loaded stay.
pub fn load_masks(layout: &mut Layout, base: &Path) {
    doc::portable::for_each_file_mut(layout, |image, grey| {
        if let Some((pixels, what)) = grey
            && !matches!(pixels, doc::MaskPixels::Loaded(_))
        {
            *pixels = grey_pixels(base, image, what);
        }
    });
}

/// [`load_mask`] as a layout keeps it: the pixels, or why they could not be read.
pub fn grey_pixels(base: &Path, image: &str, what: &'static str) -> doc::MaskPixels {
    match load_mask(base, image, what) {
        Ok(m) => doc::MaskPixels::Loaded(std::sync::Arc::new(m)),
        Err(e) => doc::MaskPixels::Failed(e.to_string().into()),
    }
}

/// A grey image the layout names (`image`, relative to `base`; `what` it is: a mask
/// obstacle's image, the density map) as luminance: PNG through `image` (8 or 16 bits, its
/// luma), EXR through `exr` (linear Rec. 709 luminance, clamped to 0–1); its size checked
/// before any pixel is decoded.
pub fn load_mask(
    base: &Path,
    image: &str,
    what: &'static str,
) -> Result<doc::MaskImage, BackdropError> {
    let path = layout_file(base, image);
    let bytes = read_image_file(&path, what)?;
    let decode = |e: &dyn std::fmt::Display| decode_error(&path, what, e);
    let has_pixels = |w: u32, h: u32| {
        if w == 0 || h == 0 {
            Err(decode(&"it has no pixels"))
        } else {
            Ok(())
        }
    };
    if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        use exr::prelude::*;
        let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(&bytes[..]), false)
            .map_err(|e| decode(&e))?;
        let s = meta.headers[0].layer_size;
        let (w, h) = (s.width() as u32, s.height() as u32);
        check_pixels(&path, what, w, h)?;
        has_pixels(w, h)?;
        let img = read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
                |res, _| (res.width(), vec![0u16; res.width() * res.height()]),
                |(w, px): &mut (usize, Vec<u16>),
                 p: Vec2<usize>,
                 (r, g, b, _a): (f32, f32, f32, f32)| {
                    let l = (0.2126 * r + 0.7152 * g + 0.0722 * b).clamp(0.0, 1.0);
                    px[p.y() * *w + p.x()] = (l * 65535.0).round() as u16;
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(std::io::Cursor::new(&bytes[..]))
            .map_err(|e| decode(&e))?;
        let (_, luminance) = img.layer_data.channel_data.pixels;
        return Ok(doc::MaskImage {
            width: w,
            height: h,
            luminance,
        });
    }
    let (reader, [w, h]) = image_decoder(&path, what, &bytes)?;
    has_pixels(w, h)?;
    let luma = reader.decode().map_err(|e| decode(&e))?.into_luma16();
    Ok(doc::MaskImage {
        width: w,
        height: h,
        luminance: luma.into_raw(),
    })
}

/// What the editor opens for `path`: the layout there (`false`), or, where no file is there
/// yet but its folder is, a new layout as File → New makes it, named after the file
/// (`true`), which Save then writes to `path`. Any other failure is the error [`load`] gives.
pub fn load_or_new(path: &Path) -> Result<(Layout, bool), LoadError> {
    match load(path) {
        Err(LoadError::Io { source, .. })
            if source.kind() == std::io::ErrorKind::NotFound && parent_dir(path).is_dir() =>
        {
            let name = path
                .file_stem()
                .map_or("Untitled".into(), |s| s.to_string_lossy());
            Ok((Layout::untitled(&name), true))
        }
        other => other.map(|l| (l, false)),
    }
}

/// Saves a layout atomically (see [`write_atomic`]).
pub fn save(path: &Path, layout: &Layout) -> std::io::Result<()> {
    check_portable(path, layout)?;
    write_atomic(path, doc::to_json(layout).as_bytes())
}

/// Symbolic links followed before a path is given up on (Linux's own limit).
const MAX_LINKS: usize = 40;

/// The file a write to `path` must replace: `path` itself, or, when `path` is a symbolic link
/// (to a file that may not exist yet), the file it finally points to. Replacing the link with
/// a plain file would cut it from the file it shared.
pub fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) => dir.join(target),
                    None => target,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(format!(
        "{}: more than {MAX_LINKS} levels of symbolic links",
        path.display()
    )))
}

/// The folder a file lives in (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Flushes a folder's entries to disk, so a rename inside it survives a power cut.
pub fn sync_dir(dir: &Path) -> std::io::Result<()> {
    crate::platform::fs::sync_dir(dir)
}

/// Writes `bytes` to `path` so that readers see either the old file or the whole new one:
/// the data goes to a temporary file in the same folder, is flushed to disk, and is then
/// renamed over `path`, and the folder is flushed so the new name is durable. On any failure
/// `path` is untouched and the temporary file removed.
///
/// The new file keeps the old one's permissions (and, where allowed, its owner and group); a
/// new file gets the user's usual mode (0666 less the umask). A symbolic link is written
/// through: its target is replaced and the link stays.
///
/// Only a regular file is replaced: a device node, FIFO, socket or folder at `path` is
/// refused (run as root, writing "into" `/dev/null` replaced the device with a file), and so
/// is a read-only file. A file with other hard links is rewritten in place, so every name
/// still shows the new text (its old text kept in a hidden backup beside it until then).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_raw(path, bytes).map_err(plain)
}

fn write_atomic_raw(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let path = resolve_links(path)?;
    let dir = parent_dir(&path);
    let old = match std::fs::metadata(&path) {
        Ok(m) => Some(m),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
    };
    if let Some(m) = &old {
        check_replaceable(m)?;
        if crate::platform::fs::link_count(m) > 1 {
            return write_in_place(&path, bytes);
        }
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(".windloom-").suffix(".tmp");
    crate::platform::fs::new_file_mode(&mut builder);
    // tempfile names its own temporary file in the error; the user wants the folder.
    let mut tmp = builder
        .tempfile_in(dir)
        .map_err(|e| folder_error(dir, e.kind()))?;
    if let Some(old) = &old {
        keep_owner_and_mode(tmp.as_file(), old)?;
    }
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(&path).map_err(|e| e.error)?;
    sync_dir(dir)
}

/// Checks, before any work, that [`write_atomic`] may write `path`: nothing there yet, or a
/// regular file it may replace.
pub fn check_target(path: &Path) -> std::io::Result<()> {
    match std::fs::metadata(resolve_links(path)?) {
        Ok(m) => check_replaceable(&m),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

/// Refuses to replace what is not a regular file, or a read-only one.
pub fn check_replaceable(meta: &std::fs::Metadata) -> std::io::Result<()> {
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "it is {}, not a regular file; windloom writes only regular files and \
                 folders it makes",
                kind_of(meta)
            ),
        ));
    }
    if meta.permissions().readonly() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            "it is read-only; make it writable (chmod u+w) to replace it",
        ));
    }
    Ok(())
}

/// Rewrites a file that has other hard links in place, so the other names keep sharing it.
/// An in-place write is not atomic, so the old text is first copied to a hidden backup
/// beside it (`.NAME.windloom-backup`), flushed, and removed only once the new text is
/// flushed: a write cut short leaves the old text there to restore.
fn write_in_place(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = parent_dir(path);
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let backup = dir.join(format!(".{name}.windloom-backup"));
    std::fs::copy(path, &backup).map_err(|e| folder_error(dir, e.kind()))?;
    crate::platform::fs::flush_file(&backup)?;
    let mut file = std::fs::OpenOptions::new().write(true).open(path)?;
    file.write_all(bytes)?;
    file.set_len(bytes.len() as u64)?;
    file.sync_all()?;
    std::fs::remove_file(&backup)?;
    sync_dir(dir)
}

/// Why a file cannot be created in `dir`, naming the folder.
fn folder_error(dir: &Path, kind: std::io::ErrorKind) -> std::io::Error {
    use std::io::ErrorKind as K;
    let why = match kind {
        K::NotFound => "does not exist".to_string(),
        K::PermissionDenied => "is not writable (permission denied)".to_string(),
        K::NotADirectory => "is not a folder".to_string(),
        other => format!("cannot hold a new file ({other})"),
    };
    std::io::Error::new(kind, format!("the folder {} {why}", dir.display()))
}

/// Gives `file` the permissions of `old`, and its owner and group where this user may.
pub(crate) fn keep_owner_and_mode(
    file: &std::fs::File,
    old: &std::fs::Metadata,
) -> std::io::Result<()> {
    crate::platform::fs::keep_owner(file, old)?;
    file.set_permissions(old.permissions())
}
