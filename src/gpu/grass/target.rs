//! The colour and depth target the grass draws into, and whole frames into it.

use super::draw::SAMPLES;
use super::{Camera, DEPTH_FORMAT, GrassRenderer};
use crate::gpu::GpuError;

/// The colour the frame is cleared to before the sky pass paints over it (linear).
const SKY: wgpu::Color = wgpu::Color {
    r: 0.50,
    g: 0.66,
    b: 0.85,
    a: 1.0,
};

/// A colour and depth target the grass draws into: offscreen pictures, and the editor's 3D view
/// (which shows the colour texture as an image).
pub struct Target {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// The colour texture viewed as plain `Rgba8Unorm`: sampling gives the sRGB-encoded bytes,
    /// which is what egui's painter expects of an image.
    pub encoded_view: wgpu::TextureView,
    /// On an adapter that cannot view a texture in another format (a GL adapter lacks
    /// `DownlevelFlags::VIEW_FORMATS`), a plain `Rgba8Unorm` copy of the colour texture that
    /// each frame ends by filling, and `encoded_view` views that instead.
    encoded_copy: Option<wgpu::Texture>,
    /// The multisampled colour the pass draws into, resolved into `texture` at its end.
    msaa_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    pub size: [u32; 2],
}

impl Target {
    /// The colour format (sRGB: pictures and egui both read it as such).
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
    /// The format egui reads the frame in (the same bytes, not decoded from sRGB).
    const ENCODED: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

    /// A target of `[w, h]` pixels on a device with the `downlevel` flags of its adapter
    /// ([`GpuContext::downlevel`](crate::gpu::GpuContext::downlevel)).
    pub fn new(device: &wgpu::Device, [w, h]: [u32; 2], downlevel: wgpu::DownlevelFlags) -> Self {
        let views = downlevel.contains(wgpu::DownlevelFlags::VIEW_FORMATS);
        let extent = wgpu::Extent3d {
            width: w.max(1),
            height: h.max(1),
            depth_or_array_layers: 1,
        };
        let sampled = |samples, format, usage, view_formats: &'static [wgpu::TextureFormat]| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("grass target"),
                size: extent,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats,
            })
        };
        let texture = |format, usage, view_formats| sampled(1, format, usage, view_formats);
        let colour = texture(
            Self::FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
            if views { &[Self::ENCODED] } else { &[] },
        );
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let depth = sampled(SAMPLES, DEPTH_FORMAT, attachment, &[]);
        let msaa = sampled(SAMPLES, Self::FORMAT, attachment, &[]);
        let encoded_copy = (!views).then(|| {
            texture(
                Self::ENCODED,
                wgpu::TextureUsages::COPY_DST
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                &[],
            )
        });
        let encoded_view = match &encoded_copy {
            Some(copy) => copy.create_view(&Default::default()),
            None => colour.create_view(&wgpu::TextureViewDescriptor {
                format: Some(Self::ENCODED),
                ..Default::default()
            }),
        };
        Self {
            view: colour.create_view(&Default::default()),
            encoded_view,
            encoded_copy,
            msaa_view: msaa.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            texture: colour,
            size: [extent.width, extent.height],
        }
    }

    /// The texture `encoded_view` views: the colour texture itself, or its plain copy.
    pub fn encoded_texture(&self) -> &wgpu::Texture {
        self.encoded_copy.as_ref().unwrap_or(&self.texture)
    }

    /// Copies the finished frame to the plain copy, where there is one (the formats differ
    /// only in sRGB-ness, so the bytes copy as they are).
    fn publish(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some(copy) = &self.encoded_copy {
            enc.copy_texture_to_texture(
                self.texture.as_image_copy(),
                copy.as_image_copy(),
                self.texture.size(),
            );
        }
    }
}

impl GrassRenderer {
    /// Records a whole frame into `target`, `dt` seconds after the last: the compute passes,
    /// then sky, ground and blades.
    pub fn record(
        &mut self,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        target: &Target,
        camera: &Camera,
        time: f32,
        dt: f32,
    ) {
        let [w, h] = target.size;
        self.prepare(queue, enc, camera, w as f32 / h as f32, time, dt);
        self.record_draw(enc, target);
    }

    /// Records the frame's render pass alone into `target` (sky, ground and blades), drawing
    /// the blades the last [`GrassRenderer::prepare`] posed and kept.
    pub fn record_draw(&self, enc: &mut wgpu::CommandEncoder, target: &Target) {
        self.record_draw_counted(enc, target, None);
    }

    /// [`GrassRenderer::record_draw`], the samples its draws write counted by query 0 of
    /// `written` (an occlusion query set) where one is given: what `bench --grass` reports of
    /// the pixels' side of a frame.
    pub fn record_draw_counted(
        &self,
        enc: &mut wgpu::CommandEncoder,
        target: &Target,
        written: Option<&wgpu::QuerySet>,
    ) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("grass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.msaa_view,
                depth_slice: None,
                resolve_target: Some(&target.view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(SKY),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: written,
            multiview_mask: None,
        });
        if written.is_some() {
            pass.begin_occlusion_query(0);
        }
        self.paint(&mut pass);
        if written.is_some() {
            pass.end_occlusion_query();
        }
        drop(pass);
        target.publish(enc);
    }
}

/// One offscreen picture of the grass, `dt` seconds after the last frame: RGBA8 (sRGB) pixels,
/// `size` wide and high, and the time the frame took in milliseconds (wall clock, submitted
/// and waited for).
pub fn render_offscreen(
    ctx: &crate::gpu::GpuContext,
    grass: &mut GrassRenderer,
    camera: &Camera,
    (time, dt): (f32, f32),
    [w, h]: [u32; 2],
) -> Result<(Vec<u8>, f64), GpuError> {
    let (device, queue) = (&ctx.device, &ctx.queue);
    let target = Target::new(device, [w, h], ctx.downlevel);
    let whole = FramePart::Whole;
    let ms = render_into(device, queue, grass, camera, (time, dt), &target, whole)?;
    let pixels = crate::gpu::read_texture(device, queue, &target.texture, 4)?;
    // A picture drawn on a faulted device is not the picture: say so instead.
    ctx.check("drawing the grass")?;
    Ok((pixels, ms))
}

/// A frame, or half of one, into an existing target, submitted and waited for: its
/// wall-clock milliseconds (the benchmark times these and reads nothing back). `Compute`
/// records the compute passes alone ([`GrassRenderer::prepare`]), `Draw` the render pass
/// alone over the blades the last compute passes kept; `bench --grass` times all three to say
/// where a frame's time goes.
pub fn render_into(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    grass: &mut GrassRenderer,
    camera: &Camera,
    (time, dt): (f32, f32),
    target: &Target,
    part: FramePart,
) -> Result<f64, GpuError> {
    let started = std::time::Instant::now();
    let mut enc = device.create_command_encoder(&Default::default());
    match part {
        FramePart::Whole => grass.record(queue, &mut enc, target, camera, time, dt),
        FramePart::Compute => {
            let [w, h] = target.size;
            grass.prepare(queue, &mut enc, camera, w as f32 / h as f32, time, dt);
        }
        FramePart::Draw => grass.record_draw(&mut enc, target),
    }
    queue.submit([enc.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Runtime {
            what: "drawing the grass".into(),
            message: e.to_string(),
        })?;
    Ok(started.elapsed().as_secs_f64() * 1e3)
}

/// What of a frame [`render_into`] records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramePart {
    Whole,
    Compute,
    Draw,
}
