//! `windloom [FILE]`: the editor's window.

use super::CliError;
use crate::app::{Central, Launch};
use crate::engine::Backend;
use crate::{doc, io};
use std::path::PathBuf;
use std::process::ExitCode;

/// Opens the editor on `file` (a new layout there when it does not exist yet), or on the
/// bundled default layout.
pub fn run(
    file: Option<PathBuf>,
    backend: Option<Backend>,
    view: Option<Central>,
) -> Result<ExitCode, CliError> {
    let (doc, note) = match &file {
        Some(path) => match io::load_or_new(path)? {
            (doc, false) => (doc, None),
            (doc, true) => (
                doc,
                // Short: the status bar is full in the 3D view.
                Some(format!(
                    "{} is new: Save creates it",
                    path.file_name().unwrap_or_default().to_string_lossy()
                )),
            ),
        },
        None => (doc::default_layout(), None),
    };
    let launch = Launch {
        path: file,
        backend,
        view,
        note,
    };
    crate::app::run(doc, launch).map_err(|e| {
        CliError::Message(format!(
            "could not open the editor window: {e}{}",
            window_hint(&e)
        ))
    })?;
    Ok(ExitCode::SUCCESS)
}

/// What to do when the editor's window cannot open: no display, or no graphics driver.
fn window_hint(e: &eframe::Error) -> &'static str {
    match e {
        eframe::Error::Winit(_) | eframe::Error::WinitEventLoop(_) => {
            " (on a machine without a display, run the editor under Xvfb: xvfb-run -a windloom; \
             `windloom bake` and `windloom render` need no display)"
        }
        eframe::Error::Wgpu(_) => {
            " (the editor draws with wgpu: Vulkan, Metal, DX12 or OpenGL; try another with \
             WGPU_BACKEND=vulkan, dx12 or gl; on Linux install a Vulkan driver, for software \
             rendering: apt-get install mesa-vulkan-drivers libvulkan1)"
        }
        _ => "",
    }
}
