//! What runs the wind: the CPU solver or the GPU one, and the automatic choice between them.
//! The editor's live worker ([`live::LiveSim`]) and the bake's stepper ([`Stepper`]) both live
//! here, between `gpu`/`sim` below and `bake`/`app` above, so that both callers share one
//! notion of a backend.

pub mod live;
pub mod probe;
mod stepper;

pub use stepper::Stepper;

/// Where the wind should run, as the user asks for it (the CLI's `--backend`, the editor's
/// View menu). Stored in the editor's settings by its variant names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Backend {
    /// The GPU on a hardware adapter. Otherwise the editor runs whichever measures faster for
    /// the current grid ([`live::measure`]) and a bake runs on the CPU, with a note in the
    /// manifest saying why.
    Auto,
    /// The CPU solver (the reference).
    Cpu,
    /// The GPU solver (wgpu: Vulkan, Metal, DX12; lavapipe counts); an error for a bake when
    /// there is no adapter or it does not cover the layout.
    Gpu,
}

impl Backend {
    /// In the order the View menu lists them.
    pub const ALL: [Backend; 3] = [Backend::Auto, Backend::Cpu, Backend::Gpu];

    /// The name in the View menu.
    pub fn label(self) -> &'static str {
        match self {
            Backend::Auto => "Automatic (fastest)",
            Backend::Cpu => "CPU",
            Backend::Gpu => "GPU",
        }
    }

    /// The name on the command line (`--backend cpu|gpu|auto`).
    pub fn name(self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }
}

/// Where a field is running now: what [`Backend::Auto`] resolved to, or where a failing GPU
/// fell back to.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum RunsOn {
    #[default]
    Cpu,
    Gpu,
}

impl RunsOn {
    /// `CPU` or `GPU`, for the status bar.
    pub fn label(self) -> &'static str {
        match self {
            RunsOn::Cpu => "CPU",
            RunsOn::Gpu => "GPU",
        }
    }
}
