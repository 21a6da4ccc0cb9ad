//! The wgpu device the wind runs on: a headless one for the CLI and the tests, or the
//! editor's own (eframe's), handed in with [`GpuContext::from_parts`] so that one device serves
//! the UI and the wind.

/// What the fluid passes and the map view ask of a device: the adapter's own limits (the
/// largest grids need its buffer sizes), timestamp queries where the adapter has them (per-pass
/// times), and the texture features the editor's drawing uses. The editor creates eframe's
/// device with this too.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    let wanted = wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
        | wgpu::Features::FLOAT32_FILTERABLE;
    wgpu::DeviceDescriptor {
        label: Some("windloom device"),
        required_features: adapter.features() & wanted,
        required_limits: adapter.limits(),
        ..Default::default()
    }
}

/// Whether an adapter is a software rasteriser (llvmpipe/lavapipe, WARP, SwiftShader).
pub fn is_software(info: &wgpu::AdapterInfo) -> bool {
    info.device_type == wgpu::DeviceType::Cpu
}

/// Submits command buffers on another thread's behalf (see [`GpuContext::submit`]).
pub type Submitter = std::sync::Arc<dyn Fn(wgpu::CommandBuffer) + Send + Sync>;

/// A device and queue with what the fluid passes need.
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: wgpu::AdapterInfo,
    /// Where the adapter falls short of WebGPU (a GL adapter: no texture views in another
    /// format, for one); what draws checks here rather than failing on the device.
    pub downlevel: wgpu::DownlevelFlags,
    /// Who submits this context's work: the queue directly, or — on the editor's device, whose
    /// surface wgpu reconfigures only while no other thread submits — the UI thread.
    submitter: Option<Submitter>,
    /// The first fault the device reported outside an error scope (see [`GpuContext::fault`]).
    fault: Fault,
}

/// Where a device's callbacks leave the first fault they saw: a lost device, or an error no
/// error scope caught (which wgpu's default handler would turn into a panic).
type Fault = std::sync::Arc<std::sync::Mutex<Option<String>>>;

/// Installs the device-lost callback and an uncaptured-error handler that log the fault and
/// keep the first one, instead of wgpu's default panic.
fn watch(device: &wgpu::Device) -> Fault {
    let fault: Fault = Default::default();
    let keep = |fault: &Fault, what: String| {
        log::error!("GPU fault: {what}");
        let mut f = fault.lock().unwrap_or_else(|p| p.into_inner());
        if f.is_none() {
            *f = Some(what);
        }
    };
    let lost = fault.clone();
    device.set_device_lost_callback(move |reason, message| {
        keep(
            &lost,
            format!("the device was lost ({reason:?}): {message}"),
        );
    });
    let uncaptured = fault.clone();
    device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
        keep(&uncaptured, e.to_string());
    }));
    fault
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

/// A wgpu instance without a window, on the backends `WGPU_BACKEND` names: every backend
/// when it is unset or empty (`WGPU_BACKEND= windloom …` is a common way to clear it, and
/// wgpu alone would read it as "no backend"), an error naming the variable when it names
/// none wgpu knows.
pub(crate) fn headless_instance() -> Result<wgpu::Instance, GpuError> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    if let Ok(value) = std::env::var("WGPU_BACKEND") {
        if value.trim().is_empty() {
            desc.backends = wgpu::InstanceDescriptor::new_without_display_handle().backends;
        } else if desc.backends.is_empty() {
            return Err(GpuError::NoAdapter(format!(
                "WGPU_BACKEND={value:?} names no backend wgpu knows (vulkan, gl, metal, dx12; \
                 unset it to try them all)"
            )));
        }
    }
    Ok(wgpu::Instance::new(desc))
}

impl GpuContext {
    /// Opens the default adapter (a high-performance one when there is a choice) without a
    /// window, asking for the adapter's own limits, which the largest grids need.
    pub fn headless() -> Result<Self, GpuError> {
        let instance = headless_instance()?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let name = format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend);
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
        let (device, queue) = pollster::block_on(
            adapter.request_device(&device_descriptor(&adapter)),
        )
        .map_err(|e| GpuError::Device {
            adapter: name.clone(),
            message: e.to_string(),
        })?;
        log::info!("GPU: {name}, driver {} {}", info.driver, info.driver_info);
        Ok(Self {
            fault: watch(&device),
            device,
            queue,
            adapter: info,
            downlevel: adapter.get_downlevel_capabilities().flags,
            submitter: None,
        })
    }

    /// A context on a device made elsewhere (the editor's, created by eframe with
    /// [`device_descriptor`]); fails when the adapter cannot run compute shaders.
    pub fn from_parts(
        adapter: &wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Result<Self, GpuError> {
        let info = adapter.get_info();
        if !adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS | wgpu::DownlevelFlags::VERTEX_STORAGE)
        {
            return Err(GpuError::Unsupported {
                adapter: format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend),
                what: "run compute shaders and read storage buffers in vertex shaders".into(),
            });
        }
        Ok(Self {
            fault: watch(&device),
            device,
            queue,
            adapter: info,
            downlevel: adapter.get_downlevel_capabilities().flags,
            submitter: None,
        })
    }

    /// This context with its submissions made by `submitter` (which must submit them, in
    /// order, before returning or soon after).
    pub fn with_submitter(mut self, submitter: Submitter) -> Self {
        self.submitter = Some(submitter);
        self
    }

    /// Submits `cb`: to the queue, or through the submitter when there is one.
    pub fn submit(&self, cb: wgpu::CommandBuffer) {
        match &self.submitter {
            Some(s) => s(cb),
            None => {
                self.queue.submit([cb]);
            }
        }
    }

    /// The first fault the device reported: lost, or an error outside any error scope (a
    /// failed allocation, an invalid dispatch). Once there is one, nothing the device computes
    /// can be trusted; the solvers' `finish` reports it as an error.
    pub fn fault(&self) -> Option<String> {
        self.fault.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    /// `Ok` while the device has reported no fault; else the fault, as an error in `what`.
    pub fn check(&self, what: &str) -> Result<(), GpuError> {
        match self.fault() {
            Some(message) => Err(GpuError::Runtime {
                what: what.into(),
                message,
            }),
            None => Ok(()),
        }
    }

    /// Whether the device is a software rasteriser.
    pub fn is_software(&self) -> bool {
        is_software(&self.adapter)
    }

    /// `name (type, backend)`, as logs and benchmarks print it.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.adapter.name, self.adapter.device_type, self.adapter.backend
        )
    }
}
