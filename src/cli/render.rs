//! `windloom render LAYOUT -o PNG`: a top-down picture of the wind (tiny-skia), or the grass
//! in 3D (on the GPU).

use super::{CliError, Command, MESSAGE_SHOWN, RenderView, camera_from, warn_advice};
use crate::{doc, io};
use std::process::ExitCode;

/// Runs a `Command::Render`.
pub fn run(command: Command) -> Result<ExitCode, CliError> {
    let Command::Render {
        layout,
        output,
        size,
        time,
        view,
        camera,
        paper_literal,
        model,
        push,
        wind_colours,
        no_arrows,
        speed_scale,
    } = command
    else {
        unreachable!("render::run is called with a render command");
    };
    if view == RenderView::Map {
        // Said rather than ignored: a map picture with its arrows, say, after `--no-arrows`,
        // would look like a bug.
        let grass_only = [
            ("--camera", camera.is_some()),
            ("--paper-literal", paper_literal),
            ("--model", model.is_some()),
            ("--push", push.is_some()),
            ("--wind-colours", wind_colours.is_some()),
            ("--no-arrows", no_arrows),
        ];
        if let Some((flag, _)) = grass_only.iter().find(|(_, given)| *given) {
            return Err(CliError::Message(format!(
                "{flag} is for the 3D grass picture: add --view grass"
            )));
        }
    }
    let cannot_write = |e| CliError::failed(format!("cannot write {}", output.display()), e);
    io::check_target(&output).map_err(cannot_write)?;
    let mut l = io::load(&layout)?;
    if let Some(m) = model {
        l.grass.model = m;
    }
    let base = io::layout_base(Some(&layout));
    let backdrop = match io::layout_backdrop(&l, &base) {
        Some(Ok(img)) => Some(img),
        Some(Err(e)) => {
            eprintln!(
                "warning: {}; drawn without it",
                doc::printable(&e.to_string(), MESSAGE_SHOWN)
            );
            None
        }
        None => None,
    };
    warn_advice(&l, &layout);
    let png = match view {
        RenderView::Map => crate::render::render_png(&l, &base, size, time, speed_scale)?,
        RenderView::Grass => {
            if !((16..=16384).contains(&size[0]) && (16..=16384).contains(&size[1])) {
                return Err(CliError::Message(
                    "--size: each side must be 16 to 16384 pixels".into(),
                ));
            }
            let ctx = crate::gpu::GpuContext::headless()?;
            let options = crate::gpu::grass::PictureOptions {
                size,
                time,
                camera: camera.map(camera_from),
                paper_literal,
                push: push.map(|p| crate::gpu::grass::PushPath {
                    from: [p[0], p[1]],
                    to: [p[2], p[3]],
                    radius: p[4],
                }),
                wind_colours,
                speed_scale,
                arrows: !no_arrows,
            };
            let pixels = crate::gpu::grass::picture(&ctx, &l, backdrop.as_ref(), &options)?;
            let mut png = Vec::new();
            image::RgbaImage::from_raw(size[0], size[1], pixels)
                .ok_or_else(|| CliError::Message("picture size".into()))?
                .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                .map_err(|e| CliError::failed("encoding the picture".into(), e))?;
            png
        }
    };
    io::write_atomic(&output, &png)
        .map_err(|e| CliError::failed(format!("could not write {}", output.display()), e))?;
    println!("wrote {}", output.display());
    Ok(ExitCode::SUCCESS)
}
