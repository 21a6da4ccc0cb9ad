//! The grey images a document owns (mask obstacles' images, the heightmap, the density map)
//! against the files they come from and go to: which pixels each file held when this editor
//! last read or wrote it, which images are unsaved work (painted, newly made, pasted from
//! elsewhere, recovered after a crash), and how a save lays them out: names that keep
//! pointing at their files when the layout is saved into another folder, a free name for a
//! new image where a file this editor never read is in the way, nothing written over such a
//! file. No egui; the document ([`super::Document`]) keeps one.

use crate::doc::{self, Layout, MaskImage, MaskPixels};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// A grey image of a layout: the path it stores, the file that names in the layout's folder,
/// and its pixels.
#[derive(Debug, Clone)]
pub struct Grey {
    pub name: String,
    pub file: PathBuf,
    pub image: Arc<MaskImage>,
}

/// What this editor knows of the files of a document's grey images.
#[derive(Debug, Default)]
pub struct ImageFiles {
    /// The pixels each file held when this editor last read or wrote it.
    held: Vec<(PathBuf, Arc<MaskImage>)>,
    /// The files this document may write over: read or written by it, or named by a
    /// recovered copy as the images it was editing.
    own: Vec<PathBuf>,
}

/// The file `name` (a path the layout stores) names in the layout's folder `base`, as one
/// absolute path without `.` or `..` (two spellings of one file give one key). No file
/// system call but the working folder's.
pub fn file_key(base: &Path, name: &str) -> PathBuf {
    let p = super::layout_file(base, name);
    let abs = std::path::absolute(&p).unwrap_or(p);
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The loaded grey images of `layout` whose paths are relative to `base`, once each (two
/// items naming one file with the same pixels are one image).
pub fn greys(layout: &Layout, base: &Path) -> Vec<Grey> {
    let mut out: Vec<Grey> = Vec::new();
    for (_, name, grey) in doc::portable::files(layout) {
        if let Some((MaskPixels::Loaded(image), _)) = grey
            && !out
                .iter()
                .any(|g| g.name == name && Arc::ptr_eq(&g.image, image))
        {
            out.push(Grey {
                name: name.to_owned(),
                file: file_key(base, name),
                image: image.clone(),
            });
        }
    }
    out
}

/// Whether windloom writes a grey image under this name as it is (PNG or EXR): a painted
/// JPEG is saved as a PNG of its own, never as PNG bytes under a `.jpg` name.
fn writable_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".png") || lower.ends_with(".exr")
}

/// `name` with `-2`, `-3`… before its extension (and `.png` for a name windloom cannot write
/// as it is), the first that `free` accepts.
pub fn free_name(name: &str, free: impl Fn(&str) -> bool) -> String {
    let (stem, ext) = match name.rfind('.') {
        Some(dot) if dot > name.rfind(['/', '\\']).map_or(0, |s| s + 1) => {
            (&name[..dot], &name[dot..])
        }
        _ => (name, ""),
    };
    let writable = writable_name(name);
    let ext = if writable { ext } else { ".png" };
    // A JPEG's own name as a PNG, where that is free.
    let plain = format!("{stem}{ext}");
    if !writable && free(&plain) {
        return plain;
    }
    // A name that ends in "-N" already counts on from N.
    let (stem, first) = match stem.rsplit_once('-') {
        Some((s, n)) if !s.is_empty() && n.parse::<u32>().is_ok_and(|n| n < 100_000) => {
            (s, n.parse::<u32>().unwrap_or(1) + 1)
        }
        _ => (stem, 2),
    };
    (first..)
        .map(|k| format!("{stem}-{k}{ext}"))
        .find(|n| free(n))
        .expect("some numbered name is free")
}

/// `file` as a layout in `base` stores it: relative (with `/`, `..` where it lies beside the
/// folder) when the two share a root, else absolute.
pub fn stored_name(file: &Path, base: &Path) -> String {
    let base = file_key(base, ".");
    match pathdiff::diff_paths(file, &base) {
        Some(rel)
            if rel
                .components()
                .all(|c| matches!(c, Component::Normal(_) | Component::ParentDir)) =>
        {
            rel.components()
                .map(|c| c.as_os_str().to_string_lossy())
                .collect::<Vec<_>>()
                .join("/")
        }
        _ => file.display().to_string(),
    }
}

impl ImageFiles {
    /// Forgets every file (a new document).
    pub fn clear(&mut self) {
        self.held.clear();
        self.own.clear();
    }

    /// `image` is what `file` holds now (just read or written).
    pub fn note(&mut self, file: PathBuf, image: Arc<MaskImage>) {
        self.held.retain(|(f, _)| *f != file);
        if !self.own.contains(&file) {
            self.own.push(file.clone());
        }
        self.held.push((file, image));
    }

    /// Notes every loaded grey image of `layout` (read from its files, relative to `base`)
    /// as what its file holds.
    pub fn note_layout(&mut self, layout: &Layout, base: &Path) {
        for g in greys(layout, base) {
            self.note(g.file, g.image);
        }
    }

    /// The images `names` of `layout` are not their files' pixels (a recovered copy's
    /// painted images): unsaved, though their files stay this document's to write.
    pub fn unsave(&mut self, layout: &Layout, base: &Path, names: &[String]) {
        for g in greys(layout, base)
            .into_iter()
            .filter(|g| names.contains(&g.name))
        {
            self.held
                .retain(|(f, i)| !(*f == g.file && Arc::ptr_eq(i, &g.image)));
            if !self.own.contains(&g.file) {
                self.own.push(g.file);
            }
        }
    }

    /// Whether `file` holds `image` as far as this editor knows.
    fn holds(&self, file: &Path, image: &Arc<MaskImage>) -> bool {
        self.held
            .iter()
            .any(|(f, i)| f == file && Arc::ptr_eq(i, image))
    }

    /// The grey images of `layout` (relative to `base`) whose files do not hold them: painted,
    /// newly made, pasted from another folder or recovered. Unsaved work.
    pub fn unsaved(&self, layout: &Layout, base: &Path) -> Vec<Grey> {
        greys(layout, base)
            .into_iter()
            .filter(|g| !self.holds(&g.file, &g.image))
            .collect()
    }

    /// The renames a save of `layout` from folder `from` into folder `to` needs, so that
    /// nothing is lost and nothing of someone else's is replaced:
    /// - a file that exists (or that this editor read) keeps being named when the layout moves
    ///   to another folder (a relative path from there, as a moved Blender file's are);
    /// - a new image (never on disk), written beside the layout, takes a free name where a
    ///   file this editor never read is in the way;
    /// - a painted image read from a JPEG is written as a PNG of its own.
    pub fn plan_save(&self, layout: &Layout, from: &Path, to: &Path) -> Vec<(String, String)> {
        let mut pairs: Vec<(String, String)> = Vec::new();
        let named: Vec<String> = doc::portable::files(layout)
            .iter()
            .map(|(_, n, _)| (*n).to_owned())
            .collect();
        let unsaved = self.unsaved(layout, from);
        let taken = |n: &str, pairs: &[(String, String)]| {
            named.iter().any(|m| m == n) || pairs.iter().any(|(_, m)| m == n)
        };
        for (_, name, _) in doc::portable::files(layout) {
            if pairs.iter().any(|(n, _)| n == name) || Path::new(name).is_absolute() {
                continue;
            }
            let old = file_key(from, name);
            let new = file_key(to, name);
            let painted = unsaved.iter().find(|g| g.name == name);
            if old != new && (self.own.contains(&old) || old.exists()) {
                // The same file, named from the new folder (a painted one is written there).
                let mut kept = stored_name(&old, to);
                if painted.is_some() && !writable_name(name) {
                    kept = free_name(&kept, |n| !file_key(to, n).exists() && !taken(n, &pairs));
                }
                pairs.push((name.to_owned(), kept));
                continue;
            }
            let Some(_) = painted else { continue };
            let stranger = new.exists() && !self.own.contains(&new);
            if stranger || !writable_name(name) {
                let free = free_name(name, |n| {
                    let f = file_key(to, n);
                    !taken(n, &pairs) && (!f.exists() || self.own.contains(&f) && n == name)
                });
                if free != name {
                    pairs.push((name.to_owned(), free));
                }
            }
        }
        pairs
    }

    /// Writes every unsaved grey image of `layout` into its file (relative to `base`), each
    /// replaced atomically, and notes what each file holds now; returns how many. Refuses,
    /// writing nothing, when two items name one file with different pixels, or when an image
    /// would replace a file this editor never read (a save plans a free name first:
    /// [`Self::plan_save`]).
    pub fn write(&mut self, layout: &Layout, base: &Path) -> std::io::Result<usize> {
        let all = greys(layout, base);
        for (k, a) in all.iter().enumerate() {
            if let Some(b) = all[k + 1..]
                .iter()
                .find(|b| b.file == a.file && *b.image != *a.image)
            {
                return Err(std::io::Error::other(format!(
                    "{}: two items name this file with different pixels ({:?} and {:?}); \
                     give one of them a file of its own",
                    a.file.display(),
                    a.name,
                    b.name
                )));
            }
        }
        let unsaved: Vec<Grey> = all
            .into_iter()
            .filter(|g| !self.holds(&g.file, &g.image))
            .collect();
        for g in &unsaved {
            if g.file.exists() && !self.own.contains(&g.file) {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    format!(
                        "{}: a file this layout did not read is there; not replaced (name the \
                         image {:?} otherwise)",
                        g.file.display(),
                        g.name
                    ),
                ));
            }
        }
        let mut written = 0;
        for g in unsaved {
            let bytes = encode_grey(&g.file, &g.image, false)
                .map_err(|e| std::io::Error::other(format!("{}: {e}", g.file.display())))?;
            if let Some(dir) = g.file.parent() {
                std::fs::create_dir_all(dir).map_err(|e| {
                    std::io::Error::new(e.kind(), format!("{}: {e}", dir.display()))
                })?;
            }
            super::write_atomic(&g.file, &bytes)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", g.file.display())))?;
            self.note(g.file, g.image);
            written += 1;
        }
        Ok(written)
    }
}

/// A grey image's bytes for `file`: an EXR (grey in R, G and B, half floats) where its name
/// ends in `.exr`, else a 16-bit grey PNG (`fast`: least compression, for recovery copies
/// written while the designer works).
pub fn encode_grey(file: &Path, image: &MaskImage, fast: bool) -> Result<Vec<u8>, String> {
    let (w, h) = (image.width as usize, image.height as usize);
    if image.luminance.len() != w * h {
        return Err("the image's pixels do not fill it".into());
    }
    let exr = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr {
        use exr::prelude::*;
        let l = |p: Vec2<usize>| f32::from(image.luminance[p.y() * w + p.x()]) / 65535.0;
        let img = Image::from_channels((w, h), SpecificChannels::rgb(|p| (l(p), l(p), l(p))));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write()
            .to_buffered(&mut out)
            .map_err(|e| e.to_string())?;
        return Ok(out.into_inner());
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, image.width, image.height);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    if fast {
        enc.set_compression(png::Compression::Fastest);
    }
    let mut writer = enc.write_header().map_err(|e| e.to_string())?;
    let bytes: Vec<u8> = image
        .luminance
        .iter()
        .flat_map(|l| l.to_be_bytes())
        .collect();
    writer.write_image_data(&bytes).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(v: u16) -> Arc<MaskImage> {
        Arc::new(MaskImage {
            width: 4,
            height: 2,
            luminance: vec![v; 8],
        })
    }

    #[test]
    fn free_names_count_on_and_never_reuse_a_taken_one() {
        let taken = ["mask.png", "mask-2.png", "mask-3.png"];
        let free = |n: &str| !taken.contains(&n);
        assert_eq!(free_name("mask.png", free), "mask-4.png");
        assert_eq!(free_name("mask-2.png", free), "mask-4.png");
        assert_eq!(free_name("dir.v2/rocks", |_| true), "dir.v2/rocks.png");
        assert_eq!(free_name("photo.JPG", |_| true), "photo.png");
        assert_eq!(free_name("h.exr", |n| n != "h.exr"), "h-2.exr");
    }

    #[test]
    fn stored_names_reach_beside_the_folder_with_dot_dot() {
        let base = Path::new("/levels/forest");
        assert_eq!(
            stored_name(Path::new("/levels/forest/masks/a.png"), base),
            "masks/a.png"
        );
        assert_eq!(
            stored_name(Path::new("/levels/textures/a.png"), base),
            "../textures/a.png"
        );
        assert_eq!(file_key(base, "masks/../a.png"), file_key(base, "a.png"));
        assert_eq!(
            file_key(base, "masks\\a.png"),
            file_key(base, "masks/a.png")
        );
    }

    /// A painted image is unsaved until written; a read one is not; writing it makes it
    /// saved, and a file never read is not replaced.
    #[test]
    fn unsaved_images_are_the_ones_their_files_do_not_hold() {
        let dir = tempfile::tempdir().unwrap();
        let mut layout = doc::default_layout();
        layout.grass.density_map = Some(doc::DensityMap {
            image: "density.png".into(),
            rect: None,
            pixels: MaskPixels::Loaded(image(100)),
        });
        let mut files = ImageFiles::default();
        assert_eq!(files.unsaved(&layout, dir.path()).len(), 1, "new: unsaved");
        assert_eq!(files.write(&layout, dir.path()).unwrap(), 1);
        assert!(files.unsaved(&layout, dir.path()).is_empty());
        let read = super::super::load_mask(dir.path(), "density.png", "density map").unwrap();
        assert_eq!(read, *image(100));
        // Painted: unsaved again, and written over the file it was read from.
        layout.grass.density_map.as_mut().unwrap().pixels = MaskPixels::Loaded(image(7));
        assert_eq!(files.unsaved(&layout, dir.path()).len(), 1);
        assert_eq!(files.write(&layout, dir.path()).unwrap(), 1);
        // A stranger's file under a new image's name stays, and the save says so.
        std::fs::write(dir.path().join("theirs.png"), b"not ours").unwrap();
        layout.grass.density_map.as_mut().unwrap().image = "theirs.png".into();
        let e = files.write(&layout, dir.path()).unwrap_err();
        assert!(e.to_string().contains("theirs.png"), "{e}");
        assert_eq!(
            std::fs::read(dir.path().join("theirs.png")).unwrap(),
            b"not ours"
        );
        let plan = files.plan_save(&layout, dir.path(), dir.path());
        assert_eq!(
            plan,
            vec![("theirs.png".to_owned(), "theirs-2.png".to_owned())]
        );
    }
}
