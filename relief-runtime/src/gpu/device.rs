//! A headless wgpu device on any adapter.

/// Why no device could be had.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// wgpu found no adapter; holds wgpu's reason.
    #[error(
        "no GPU adapter found ({0}). relief needs a Vulkan, Metal, DX12 or GL device; on Linux \
         without a GPU, install Mesa's software Vulkan device: `apt-get install mesa-vulkan-drivers libvulkan1`"
    )]
    NoAdapter(String),
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

impl Gpu {
    /// The first adapter wgpu finds (high performance preferred), headless.
    pub fn new() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
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
