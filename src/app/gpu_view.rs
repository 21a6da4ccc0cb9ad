//! The editor's one bridge to the GPU (`egui_wgpu::CallbackTrait`): the map view's wind,
//! drawn by [`crate::gpu::mapview::MapRenderer`] straight from the live solver's buffers on
//! the device eframe draws the UI with. Everything GPU-side lives in `crate::gpu`; this file
//! only hands it egui's encoder and render pass.

use super::live::Snapshot;
use crate::gpu::mapview::{FieldBuffers, Frame, MapRenderer};
use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};
use eframe::wgpu;

/// Makes the map renderer for eframe's device and target format.
pub fn install(rs: &egui_wgpu::RenderState) {
    let renderer = MapRenderer::new(&rs.device, rs.target_format);
    rs.renderer.write().callback_resources.insert(renderer);
}

/// Copies of a CPU-run field on the GPU, so the map view draws it with the same passes as a
/// GPU-run one (no per-segment tessellation on the CPU); rewritten when a new snapshot arrives.
#[derive(Default)]
pub struct Uploaded {
    field: Option<(u64, FieldBuffers)>,
}

impl Uploaded {
    /// The buffers holding `snap`'s field, uploaded if it is newer than the last.
    pub fn field(&mut self, rs: &egui_wgpu::RenderState, snap: &Snapshot) -> Option<FieldBuffers> {
        let (nx, ny) = (snap.nx as u32, snap.ny as u32);
        if nx == 0
            || snap.u.len() != (snap.nx + 1) * snap.ny
            || snap.v.len() != snap.nx * (snap.ny + 1)
        {
            return None;
        }
        let data = (&snap.u[..], &snap.v[..], &snap.pressure[..]);
        let cell = [snap.size[0] / snap.nx as f32, snap.size[1] / snap.ny as f32];
        match &mut self.field {
            Some((serial, f)) if f.nx == nx && f.ny == ny => {
                if *serial != snap.serial {
                    f.write(&rs.queue, data);
                    *serial = snap.serial;
                }
                f.origin = snap.origin;
                f.cell = cell;
            }
            _ => {
                let f = FieldBuffers::upload(&rs.device, (nx, ny), snap.origin, cell, data);
                self.field = Some((snap.serial, f));
            }
        }
        self.field.as_ref().map(|(_, f)| f.clone())
    }
}

/// The wind over the map view's `rect` this frame.
pub fn map_wind(rect: egui::Rect, field: FieldBuffers, frame: Frame) -> egui::Shape {
    egui::Shape::Callback(egui_wgpu::Callback::new_paint_callback(
        rect,
        MapCallback { field, frame },
    ))
}

struct MapCallback {
    field: FieldBuffers,
    frame: Frame,
}

impl CallbackTrait for MapCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(r) = resources.get_mut::<MapRenderer>() {
            r.prepare(device, queue, encoder, &self.field, &self.frame);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(r) = resources.get::<MapRenderer>() {
            r.paint(pass);
        }
    }
}
