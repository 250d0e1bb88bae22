//! A headless wgpu device on any adapter.

/// Why no device could be had.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// wgpu found no adapter; holds wgpu's reason.
    #[error(
        "no GPU adapter ({0}). relief needs a Vulkan, Metal, DX12 or GL device (`relief adapters` lists \
         what wgpu sees); on Linux without a GPU, install Mesa's software Vulkan device: \
         `apt-get install mesa-vulkan-drivers libvulkan1`"
    )]
    NoAdapter(String),
    /// No adapter's name contains the one asked for (`--adapter`, `RELIEF_ADAPTER`).
    #[error("no adapter matches `{wanted}` (--adapter / RELIEF_ADAPTER); wgpu sees: {seen}")]
    NoMatch {
        /// What was asked for.
        wanted: String,
        /// The adapters wgpu sees, with backend and device type.
        seen: String,
    },
    /// The adapter would not create a device with the features and limits asked for.
    #[error("the adapter {adapter} refused a device: {message}")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        message: String,
    },
    /// Work on the device failed or cannot be done: a wait that failed or timed out, a
    /// buffer that could not be read back, missing timestamp queries, or more probe rays
    /// than one dispatch takes.
    #[error("the device failed: {0}")]
    Device(String),
    /// The device reported a validation error for a shader or pipeline, or the shader reads
    /// a binding the runtime has nothing for (a map that was not built).
    #[error("shader or pipeline rejected by the device: {0}")]
    Pipeline(String),
}

/// A device and queue, with what every result records about them.
pub struct Gpu {
    /// The device, with timestamp queries and 32-bit float filtering when the adapter has them.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub adapter: String,
    /// Driver and its version.
    pub driver: String,
    /// Whether render-pass timestamp queries are available.
    pub timestamps: bool,
    /// Whether 32-bit float textures can be filtered (else heights are uploaded as f16).
    pub float32_filterable: bool,
}

/// The environment variable that names the adapter (a substring of its name, any case) when
/// `--adapter` is not given.
pub const ADAPTER_VAR: &str = "RELIEF_ADAPTER";

fn instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

/// Every adapter wgpu sees, on every backend this build has (Vulkan; Metal on Apple systems;
/// DX12 and GL on Windows), in wgpu's order.
pub fn adapters() -> Vec<wgpu::AdapterInfo> {
    pollster::block_on(instance().enumerate_adapters(wgpu::Backends::all())).iter().map(|a| a.get_info()).collect()
}

/// How much a device type is preferred when no adapter is named: a discrete GPU first, then
/// an integrated one, a virtual one, anything else, and a CPU (software) device last.
fn preference(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

/// The index of the adapter to use among `infos`: with `wanted`, the first whose name contains
/// it (any case; an error listing them all when none does); without, the most preferred device
/// type (a discrete GPU, an integrated one, a virtual one, any other, a CPU device last), the
/// first of equals (wgpu lists Vulkan before GL).
pub fn choose(infos: &[wgpu::AdapterInfo], wanted: Option<&str>) -> Result<usize, GpuError> {
    let list = || {
        infos
            .iter()
            .map(|i| format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type))
            .collect::<Vec<_>>()
            .join("; ")
    };
    match wanted {
        Some(w) => {
            let lower = w.to_lowercase();
            infos.iter().position(|i| i.name.to_lowercase().contains(&lower)).ok_or_else(|| GpuError::NoMatch {
                wanted: w.to_string(),
                seen: if infos.is_empty() { "none".into() } else { list() },
            })
        }
        None => (0..infos.len())
            .min_by_key(|&i| preference(infos[i].device_type))
            .ok_or_else(|| GpuError::NoAdapter("wgpu sees none".into())),
    }
}

impl Gpu {
    /// The adapter [`ADAPTER_VAR`] names, or else the one [`choose`] prefers, headless.
    pub fn new() -> Result<Gpu, GpuError> {
        let wanted = std::env::var(ADAPTER_VAR).ok().filter(|w| !w.trim().is_empty());
        Gpu::on(wanted.as_deref())
    }

    /// The adapter whose name contains `wanted` (any case), or the preferred one when `None`.
    pub fn on(wanted: Option<&str>) -> Result<Gpu, GpuError> {
        let mut all = pollster::block_on(instance().enumerate_adapters(wgpu::Backends::all()));
        let infos: Vec<wgpu::AdapterInfo> = all.iter().map(|a| a.get_info()).collect();
        let adapter = all.swap_remove(choose(&infos, wanted)?);
        let info = adapter.get_info();
        let available = adapter.features();
        let wanted = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::FLOAT32_FILTERABLE;
        let features = available & wanted;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("relief"),
            required_features: features,
            required_limits: wgpu::Limits {
                // A room module binds every wall's maps (five of each kind): as many sampled
                // textures as the adapter allows.
                max_sampled_textures_per_shader_stage: adapter.limits().max_sampled_textures_per_shader_stage,
                ..wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits())
            },
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice { adapter: info.name.clone(), message: e.to_string() })?;
        Ok(Gpu {
            device,
            queue,
            adapter: info.name.clone(),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            float32_filterable: features.contains(wgpu::Features::FLOAT32_FILTERABLE),
        })
    }

    /// Waits for all submitted work.
    pub fn wait(&self) -> Result<(), GpuError> {
        // On the GL backend a poll can time out after ~2 s while work is still running: retry.
        for _ in 0..30 {
            match self.device.poll(wgpu::PollType::wait_indefinitely()) {
                Ok(_) => return Ok(()),
                Err(wgpu::PollError::Timeout) => continue,
                Err(e) => return Err(GpuError::Device(e.to_string())),
            }
        }
        Err(GpuError::Device("timed out waiting for the device".into()))
    }

    /// Reads a mappable buffer back.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let slice = buffer.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv().map_err(|e| GpuError::Device(e.to_string()))?.map_err(|e| GpuError::Device(e.to_string()))?;
        let data = slice.get_mapped_range().map_err(|e| GpuError::Device(e.to_string()))?.to_vec();
        buffer.unmap();
        Ok(data)
    }

    /// Runs `f` and turns any validation error the device reports into a [`GpuError`].
    pub fn checked<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Pipeline(e.to_string())),
            None => Ok(out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(name: &str, backend: wgpu::Backend, device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.into(),
            vendor: 0,
            device: 0,
            device_type,
            device_pci_bus_id: String::new(),
            driver: String::new(),
            driver_info: String::new(),
            backend,
            subgroup_min_size: 0,
            subgroup_max_size: 0,
            transient_saves_memory: None,
            limit_bucket: None,
        }
    }

    #[test]
    fn a_named_adapter_is_found_by_substring_and_hardware_is_preferred() {
        use wgpu::{Backend as B, DeviceType as D};
        let seen = [
            info("llvmpipe (LLVM 19)", B::Vulkan, D::Cpu),
            info("Intel(R) UHD 630", B::Vulkan, D::IntegratedGpu),
            info("llvmpipe GL", B::Gl, D::Cpu),
            info("NVIDIA GeForce RTX 4070", B::Vulkan, D::DiscreteGpu),
        ];
        assert_eq!(choose(&seen, None).unwrap(), 3, "a discrete GPU first");
        assert_eq!(choose(&seen[..3], None).unwrap(), 1, "then an integrated one");
        assert_eq!(
            choose(&[seen[0].clone(), seen[2].clone()], None).unwrap(),
            0,
            "the first of equals: Vulkan before GL"
        );
        assert_eq!(choose(&seen, Some("LLVMPIPE")).unwrap(), 0, "any case, the first match");
        assert_eq!(choose(&seen, Some("uhd")).unwrap(), 1);
        let e = choose(&seen, Some("radeon")).unwrap_err().to_string();
        assert!(
            e.contains("no adapter matches `radeon`")
                && e.contains("NVIDIA GeForce RTX 4070 (Vulkan, DiscreteGpu)")
                && !e.contains('\n'),
            "{e}"
        );
        assert!(choose(&[], None).is_err());
    }
}
