//! The one owner of the wgpu instance, adapter, device and queue; everything else borrows it.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::faults::{self, Asked, GpuFault, SharedFaults};

/// Why no GPU could be set up.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (backends tried: {backends}). shadowlab needs Vulkan, Metal, DX12 or GL. \
         On Linux without a GPU, install a software Vulkan driver (Debian/Ubuntu: \
         `apt-get install mesa-vulkan-drivers libvulkan1`) and set WGPU_BACKEND=vulkan"
    )]
    NoAdapter { backends: String },
    #[error("the GPU adapter {adapter} refused to create a device: {source}")]
    RequestDevice {
        adapter: String,
        #[source]
        source: wgpu::RequestDeviceError,
    },
    #[error("reading back {what} from the GPU failed: {reason}")]
    Readback { what: String, reason: String },
    /// Out of memory, beyond the device's limits, or the device lost.
    #[error(transparent)]
    Fault(#[from] GpuFault),
}

/// Device features shadowlab uses when the adapter has them; none is required.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::INDIRECT_FIRST_INSTANCE)
    .union(wgpu::Features::PIPELINE_STATISTICS_QUERY)
    .union(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
    .union(wgpu::Features::CONSERVATIVE_RASTERIZATION)
    .union(wgpu::Features::POLYGON_MODE_LINE)
    .union(wgpu::Features::DEPTH_CLIP_CONTROL)
    .union(wgpu::Features::DEPTH32FLOAT_STENCIL8)
    .union(wgpu::Features::CLIP_DISTANCES)
    .union(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT)
    .union(wgpu::Features::MULTIVIEW);

/// Instance, adapter, device and queue. Long-lived: one per process (or per window).
#[derive(Clone, Debug)]
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// How many times the CPU has waited for the GPU ([`Self::wait_idle`]): the window's
    /// frame log shows that its frames never do. Shared by the context's clones.
    waits: Arc<AtomicU64>,
    /// Compute pipelines compiled once per device ([`Self::compute_pipeline_once`]).
    compiled: Arc<Mutex<HashMap<String, wgpu::ComputePipeline>>>,
    /// The device's loss and failed allocations ([`Self::take_fault`]).
    faults: SharedFaults,
    /// What probes found out about the device ([`Self::probe_once`]).
    probed: Arc<Mutex<HashMap<&'static str, bool>>>,
}

impl GpuContext {
    /// A context without a window, on the adapter `WGPU_BACKEND` / `WGPU_ADAPTER_NAME` select.
    pub fn headless() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = Self::request_adapter(&instance, None)?;
        Self::with_adapter(instance, adapter)
    }

    /// The adapter for `surface` (or any, when `None`); a clear error when there is none.
    pub fn request_adapter(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<wgpu::Adapter, GpuError> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env()
                .unwrap_or(wgpu::PowerPreference::HighPerformance),
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        };
        pollster::block_on(instance.request_adapter(&options)).map_err(|_| GpuError::NoAdapter {
            backends: format!(
                "{:?}",
                wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all())
            ),
        })
    }

    /// Opens a device with the adapter's limits and whichever [`OPTIONAL_FEATURES`] it has.
    pub fn with_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, GpuError> {
        let features = adapter.features() & OPTIONAL_FEATURES;
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("shadowlab"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|source| {
                GpuError::RequestDevice {
                    adapter: adapter.get_info().name,
                    source,
                }
            })?;
        let faults = SharedFaults::default();
        faults::watch(&device, &faults);
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            waits: Arc::new(AtomicU64::new(0)),
            compiled: Arc::default(),
            faults,
            probed: Arc::default(),
        })
    }

    /// The device's loss (which stays), else the first allocation that failed since the last
    /// call (taken). Polls the device first, since wgpu reports a loss while polling.
    pub fn take_fault(&self) -> Option<GpuFault> {
        let _ = self.device.poll(wgpu::PollType::Poll);
        faults::take(&self.faults)
    }

    /// Runs `create` (an allocation of about `bytes`) with wgpu's errors captured: memory the
    /// device cannot give, or a size beyond its limits, becomes a [`GpuFault`] naming `asked`,
    /// which the frame reports ([`Self::take_fault`]) instead of a wgpu panic. What `create`
    /// returns is then invalid, and the frame must not use it.
    pub fn allocate<T>(
        &self,
        asked: &Asked,
        bytes: u64,
        create: impl FnOnce(&wgpu::Device) -> T,
    ) -> T {
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let created = create(&self.device);
        let over_limit = pollster::block_on(validation.pop());
        let out_of_memory = pollster::block_on(memory.pop());
        let fault = match (out_of_memory, over_limit) {
            (Some(_), _) => Some(GpuFault::OutOfMemory {
                what: asked.what.clone(),
                asked: bytes,
                remedy: asked.remedy.to_owned(),
            }),
            (None, Some(error)) => Some(GpuFault::OverLimit {
                what: asked.what.clone(),
                asked: bytes,
                detail: limit_detail(&error),
                remedy: asked.remedy.to_owned(),
            }),
            (None, None) => None,
        };
        if let Some(fault) = fault {
            faults::record(&self.faults, fault);
        }
        created
    }

    /// A texture made through [`Self::allocate`], its size from `descriptor`.
    pub fn texture(
        &self,
        asked: &Asked,
        descriptor: &wgpu::TextureDescriptor<'_>,
    ) -> wgpu::Texture {
        let mips = descriptor.mip_level_count.max(1);
        let bytes = descriptor
            .format
            .theoretical_memory_footprint(descriptor.size)
            * u64::from(descriptor.sample_count.max(1))
            * if mips > 1 { 4 } else { 3 }
            / 3;
        self.allocate(asked, bytes, |device| device.create_texture(descriptor))
    }

    /// A buffer made through [`Self::allocate`].
    pub fn buffer(&self, asked: &Asked, descriptor: &wgpu::BufferDescriptor<'_>) -> wgpu::Buffer {
        self.allocate(asked, descriptor.size, |device| {
            device.create_buffer(descriptor)
        })
    }

    pub fn features(&self) -> wgpu::Features {
        self.device.features()
    }

    /// The compute pipeline `key` names, compiled by `create` on its first use on this device
    /// and shared from then on by every renderer (a software adapter takes seconds to compile
    /// some). A key stands for one module, entry point and set of bind group layout entries:
    /// wgpu pools bind group layouts by their entries, so a pipeline compiled with one
    /// renderer's layouts binds another's groups of the same layouts.
    pub fn compute_pipeline_once(
        &self,
        key: &str,
        create: impl FnOnce() -> wgpu::ComputePipeline,
    ) -> wgpu::ComputePipeline {
        let mut compiled = self
            .compiled
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        compiled
            .entry(key.to_owned())
            .or_insert_with(create)
            .clone()
    }

    /// What `probe` (a blocking test of the device, such as whether multiview reaches every
    /// layer) answers, run on the first ask on this device and remembered for every renderer.
    pub fn probe_once(&self, key: &'static str, probe: impl FnOnce() -> bool) -> bool {
        let mut probed = self
            .probed
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        *probed.entry(key).or_insert_with(probe)
    }

    /// How many times the CPU has waited for the GPU so far.
    pub fn waits(&self) -> u64 {
        self.waits.load(Ordering::Relaxed)
    }

    /// "name (backend, device type)", for logs and reports.
    pub fn adapter_description(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.waits.fetch_add(1, Ordering::Relaxed);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback {
                what: "device poll".into(),
                reason: e.to_string(),
            })
    }
}

/// Shared handle for code that keeps the context alive (the window, the headless runner).
pub type SharedGpu = Arc<GpuContext>;

/// The part of a validation error that says which limit was passed (its innermost cause).
fn limit_detail(error: &wgpu::Error) -> String {
    let mut cause: &dyn std::error::Error = error;
    while let Some(next) = cause.source() {
        cause = next;
    }
    cause.to_string()
}
