//! Names a layout and a bake can carry to every platform our users work on: a file or folder
//! name Windows, macOS and Linux all accept, and the relative paths a layout stores (its
//! images), written with `/` and read with `/` or `\`.

/// Why `name` (one file or folder name, no separators) cannot be a file's name on every
/// platform, or `None` when it can. Windows is the strictest: it reserves the device names
/// (`CON`, `PRN`, `AUX`, `NUL`, `COM1`–`COM9`, `LPT1`–`LPT9`, with any extension and in any
/// case), the characters `< > : " / \ | ? *` and control characters, and drops a trailing
/// dot or space; macOS's Finder shows `:` as `/`.
pub fn name_problem(name: &str) -> Option<String> {
    if name.is_empty() {
        return Some("it is empty".into());
    }
    if name == "." || name == ".." {
        return Some(format!("{name:?} names a folder, not a file"));
    }
    if let Some(c) = name.chars().find(|c| {
        c.is_control() || matches!(c, '<' | '>' | ':' | '"' | '/' | '\\' | '|' | '?' | '*')
    }) {
        let shown: String = c.escape_default().collect();
        return Some(format!(
            "Windows does not allow the character '{shown}' in a file name"
        ));
    }
    if name.ends_with(['.', ' ']) {
        return Some("Windows drops a trailing dot or space from a file name".into());
    }
    let stem = name.split('.').next().unwrap_or(name).trim_end();
    let upper = stem.to_ascii_uppercase();
    let reserved = matches!(upper.as_str(), "CON" | "PRN" | "AUX" | "NUL")
        || ((upper.starts_with("COM") || upper.starts_with("LPT"))
            && upper.len() == 4
            && upper.as_bytes()[3].is_ascii_digit()
            && upper.as_bytes()[3] != b'0');
    reserved.then(|| format!("Windows reserves the name {stem} (a device), with any extension"))
}

/// The folders and file of a relative path as a layout stores it: `/` and `\` both separate
/// (a path typed on Windows reads everywhere); empty and `.` parts are dropped.
pub fn path_parts(stored: &str) -> impl Iterator<Item = &str> {
    stored
        .split(['/', '\\'])
        .filter(|part| !part.is_empty() && *part != ".")
}

/// Why the relative path `stored` (a layout's image) cannot be carried to every platform:
/// the first part that is no portable name, or `None`. `..` is allowed (an image beside the
/// layout's folder).
pub fn path_problem(stored: &str) -> Option<String> {
    path_parts(stored)
        .filter(|part| *part != "..")
        .find_map(|part| name_problem(part).map(|why| format!("{part:?}: {why}")))
}

/// A grey image a layout reads (a mask obstacle's image, the terrain's heightmap, the grass's
/// density map): its pixels as read, and what it is, for messages ("mask image").
pub type Grey<'a> = (&'a super::MaskPixels, &'static str);

/// Every file `layout` names, in one order: the field that names it (`world.map.image`,
/// `obstacles[3].shape.image`, `world.terrain.heightmap`, `grass.density_map.image`), the
/// path as stored, and for a grey image its pixels. The one list of a layout's files: a new
/// image field is added here and in [`for_each_file_mut`], and every reader of files sees it.
pub fn files(layout: &super::Layout) -> Vec<(String, &str, Option<Grey<'_>>)> {
    let mut files = Vec::new();
    if let Some(m) = &layout.world.map {
        files.push(("world.map.image".to_owned(), m.image.as_str(), None));
    }
    for (k, o) in layout.obstacles.iter().enumerate() {
        if let super::Shape::Mask { image, pixels, .. } = &o.shape {
            let field = format!("obstacles[{k}].shape.image");
            files.push((field, image.as_str(), Some((pixels, "mask image"))));
        }
    }
    if let Some(t) = &layout.world.terrain {
        let grey = Some((&t.pixels, "heightmap"));
        files.push((
            "world.terrain.heightmap".to_owned(),
            t.heightmap.as_str(),
            grey,
        ));
    }
    if let Some(m) = &layout.grass.density_map {
        let grey = Some((&m.pixels, "density map"));
        files.push(("grass.density_map.image".to_owned(), m.image.as_str(), grey));
    }
    files
}

/// [`files`] to change: `f` gets each path and, for a grey image, its pixels and what it is.
pub fn for_each_file_mut(
    layout: &mut super::Layout,
    mut f: impl FnMut(&mut String, Option<(&mut super::MaskPixels, &'static str)>),
) {
    if let Some(m) = &mut layout.world.map {
        f(&mut m.image, None);
    }
    for o in &mut layout.obstacles {
        if let super::Shape::Mask { image, pixels, .. } = &mut o.shape {
            f(image, Some((pixels, "mask image")));
        }
    }
    if let Some(t) = &mut layout.world.terrain {
        f(&mut t.heightmap, Some((&mut t.pixels, "heightmap")));
    }
    if let Some(m) = &mut layout.grass.density_map {
        f(&mut m.image, Some((&mut m.pixels, "density map")));
    }
}

/// The layout's relative file paths written with `/` (a path typed on Windows, `maps\grass.png`,
/// becomes `maps/grass.png`), so a layout saved anywhere opens everywhere. Absolute paths
/// (`/…`, `\\server\…`, `C:\…`) stay as they are: they name one machine's files.
pub fn normalize_paths(layout: &mut super::Layout) {
    for_each_file_mut(layout, |path, _| {
        let b = path.as_bytes();
        let absolute = b.first().is_some_and(|c| matches!(c, b'/' | b'\\'))
            || (b.len() >= 2 && b[0].is_ascii_alphabetic() && b[1] == b':');
        if !absolute && path.contains('\\') {
            *path = path.replace('\\', "/");
        }
    });
}

/// One line for each file `layout` names that some platform cannot hold: the field, the
/// part of its path and why.
pub fn layout_problems(layout: &super::Layout) -> Vec<String> {
    files(layout)
        .into_iter()
        .filter_map(|(field, path, _)| path_problem(path).map(|why| format!("{field}: {why}")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_device_names_are_refused_with_any_extension_and_case() {
        for name in [
            "CON", "con.json", "Aux.png", "nul", "COM1.exr", "lpt9", "NUL .txt",
        ] {
            assert!(name_problem(name).is_some(), "{name}");
        }
        for name in [
            "CONSOLE.json",
            "com0.png",
            "COM10",
            "lpt",
            "icon.png",
            "nullable",
            "level.json",
        ] {
            assert_eq!(name_problem(name), None, "{name}");
        }
    }

    #[test]
    fn characters_and_endings_windows_refuses_are_named() {
        assert!(name_problem("a:b.png").unwrap().contains("':'"));
        assert!(name_problem("what?.json").unwrap().contains("'?'"));
        assert!(name_problem("tab\there").unwrap().contains("'\\t'"));
        assert!(name_problem("level.").unwrap().contains("trailing"));
        assert!(name_problem("level ").unwrap().contains("trailing"));
        assert!(name_problem("").is_some() && name_problem("..").is_some());
    }

    #[test]
    fn stored_paths_split_on_both_separators() {
        let parts: Vec<_> = path_parts("maps\\level/./grass.png").collect();
        assert_eq!(parts, ["maps", "level", "grass.png"]);
        assert_eq!(path_problem("../shared\\maps/level.png"), None);
        assert!(
            path_problem("maps\\aux\\grass.png")
                .unwrap()
                .starts_with("\"aux\"")
        );
    }

    #[test]
    fn relative_paths_are_normalized_to_slashes_and_absolute_ones_kept() {
        let mut l = crate::doc::Layout::new("t", [50.0, 40.0], [50, 40]);
        for (stored, kept) in [
            ("maps\\grass.png", "maps/grass.png"),
            ("C:\\levels\\grass.png", "C:\\levels\\grass.png"),
            ("\\\\server\\share\\g.png", "\\\\server\\share\\g.png"),
            ("../maps/g.png", "../maps/g.png"),
        ] {
            l.world.map = Some(crate::doc::MapBackdrop {
                image: stored.into(),
                opacity: 1.0,
                rect: None,
            });
            normalize_paths(&mut l);
            assert_eq!(l.world.map.as_ref().unwrap().image, kept);
        }
    }
}
