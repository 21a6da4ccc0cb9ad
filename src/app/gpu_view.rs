//! The editor's one bridge to the GPU (`egui_wgpu::CallbackTrait`): the map view's wind,
//! drawn by [`crate::gpu::mapview::MapRenderer`] straight from the live solver's buffers on
//! the device eframe draws the UI with. Everything GPU-side lives in `crate::gpu`; this file
//! only hands it egui's encoder and render pass.

use crate::gpu::mapview::{FieldBuffers, Frame, MapRenderer};
use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};
use eframe::wgpu;

/// Makes the map renderer for eframe's device and target format.
pub fn install(rs: &egui_wgpu::RenderState) {
    let renderer = MapRenderer::new(&rs.device, rs.target_format);
    rs.renderer.write().callback_resources.insert(renderer);
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
