//! A headless wgpu device for the CLI and the tests. (The editor will hand in eframe's device
//! instead, so that one device serves the UI and the wind; not wired yet.)

/// A device and queue with what the fluid passes need.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: wgpu::AdapterInfo,
}

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found ({0}); on Linux install a Vulkan driver (for software rendering: apt-get install mesa-vulkan-drivers libvulkan1)"
    )]
    NoAdapter(String),
    #[error("the GPU adapter {adapter} cannot {what}")]
    Unsupported { adapter: String, what: String },
    #[error("could not open the GPU device on {adapter}: {message}")]
    Device { adapter: String, message: String },
    #[error("the GPU reported an error in {what}: {message}")]
    Runtime { what: String, message: String },
}

impl GpuContext {
    /// Opens the default adapter (a high-performance one when there is a choice) without a
    /// window, asking for the adapter's own limits, which the largest grids need.
    pub fn headless() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let name = format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend);
        let limits = adapter.limits();
        if !adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
        {
            return Err(GpuError::Unsupported {
                adapter: name,
                what: "run compute shaders".into(),
            });
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("windloom headless device"),
            // Optional: per-pass times in `bench --backend gpu` where the adapter has them.
            required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device {
            adapter: name.clone(),
            message: e.to_string(),
        })?;
        Ok(Self {
            device,
            queue,
            adapter: info,
        })
    }

    /// `name (type, backend)`, as logs and benchmarks print it.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.adapter.name, self.adapter.device_type, self.adapter.backend
        )
    }
}
