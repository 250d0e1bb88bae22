//! The child side of [`super`]: one process, one GPU family. It opens Mesa's RADV driver on
//! its null device (no GPU needed: `RADV_FORCE_FAMILY` names the chip the compiler targets),
//! builds each job's pipeline with `VK_KHR_pipeline_executable_properties` and returns the
//! compiler's statistics and, on request, its disassembly.
//!
//! Why a Vulkan program of relief's own (`ash`) rather than wgpu: the null device can create
//! shader modules and pipelines but no fence or timeline semaphore, which wgpu needs to open
//! a device, and wgpu does not enable the statistics extension.

use std::ffi::{c_char, CStr};

use ash::vk;
use serde::{Deserialize, Serialize};

/// What a descriptor binding holds, as the shader declares it.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
pub(crate) enum Descriptor {
    Uniform,
    Storage,
    SampledImage,
    StorageImage,
    Sampler,
}

/// The shaders of one pipeline to compile.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum Shaders {
    /// A vertex and fragment pair, drawn into one colour attachment (and a depth attachment
    /// when the fragment writes depth): the entries `entries` (vertex, fragment), the vertex
    /// shader reading `vertex_attributes` `vec4<f32>` attributes at locations 0, 1, … from one
    /// interleaved buffer (0 for relief's quad, which reads none; 7 for a mesh module's
    /// `MeshVertex`).
    Graphics { vert: Vec<u32>, frag: Vec<u32>, depth: bool, entries: [String; 2], vertex_attributes: u32 },
    /// A compute shader.
    Compute { comp: Vec<u32> },
}

/// One pipeline to compile.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Job {
    pub name: String,
    pub shaders: Shaders,
    /// Set 0's bindings.
    pub bindings: Vec<(u32, Descriptor)>,
}

/// One compiled shader of a pipeline: the executable's name as the driver gives it
/// ("Fragment Shader", "Compute Shader", …), its subgroup size, the statistics by name and
/// the disassembly.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Executable {
    pub name: String,
    pub subgroup_size: u32,
    pub stats: Vec<(String, f64)>,
    pub isa: String,
}

/// What the child answers: the device and driver once, then per job its executables or why
/// it failed.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Answer {
    pub device: String,
    pub driver: String,
    pub results: Vec<Result<Vec<Executable>, String>>,
}

fn text(chars: &[c_char]) -> String {
    // SAFETY: the driver's strings are NUL-terminated within their fixed arrays.
    unsafe { CStr::from_ptr(chars.as_ptr()) }.to_string_lossy().trim().to_string()
}

fn vkerr(what: &str) -> impl Fn(vk::Result) -> String + '_ {
    move |e| format!("{what}: {e}")
}

/// The driver's device: RADV on its null device, with the statistics extension enabled.
struct Radv {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    exec: ash::khr::pipeline_executable_properties::Device,
    name: String,
    driver: String,
}

impl Drop for Radv {
    fn drop(&mut self) {
        // SAFETY: every object made from the device was destroyed by its maker.
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

impl Radv {
    fn open() -> Result<Radv, String> {
        // SAFETY: loading the system's Vulkan loader.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| format!("the Vulkan loader (libvulkan.so.1) cannot be loaded: {e}"))?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: valid create info.
        let instance = unsafe { entry.create_instance(&info, None) }.map_err(vkerr("vkCreateInstance"))?;
        let close = |instance: &ash::Instance, e: String| {
            // SAFETY: nothing else was made from the instance.
            unsafe { instance.destroy_instance(None) };
            e
        };
        // SAFETY: a live instance.
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(|e| close(&instance, format!("vkEnumeratePhysicalDevices: {e}")))?;
        let mut found = None;
        for pd in devices {
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            let mut props = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
            // SAFETY: a device of this instance.
            unsafe { instance.get_physical_device_properties2(pd, &mut props) };
            let name = text(&props.properties.device_name);
            if driver.driver_id == vk::DriverId::MESA_RADV {
                found = Some((pd, name, format!("{} {}", text(&driver.driver_name), text(&driver.driver_info))));
                break;
            }
        }
        let Some((pd, name, driver)) = found else {
            return Err(close(
                &instance,
                "RADV offers no device (is mesa-vulkan-drivers installed, and the family one this Mesa knows?)".into(),
            ));
        };
        let queue_priority = [1.0f32];
        let queue = [vk::DeviceQueueCreateInfo::default().queue_family_index(0).queue_priorities(&queue_priority)];
        let extensions = [ash::khr::pipeline_executable_properties::NAME.as_ptr()];
        let mut exec_features =
            vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default().pipeline_executable_info(true);
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true);
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue)
            .enabled_extension_names(&extensions)
            .push_next(&mut exec_features)
            .push_next(&mut v13);
        // SAFETY: a device of this instance, valid create info.
        let device = unsafe { instance.create_device(pd, &info, None) }
            .map_err(|e| close(&instance, format!("vkCreateDevice on RADV: {e}")))?;
        let exec = ash::khr::pipeline_executable_properties::Device::new(&instance, &device);
        Ok(Radv { _entry: entry, instance, device, exec, name, driver })
    }

    fn module(&self, words: &[u32]) -> Result<vk::ShaderModule, String> {
        let info = vk::ShaderModuleCreateInfo::default().code(words);
        // SAFETY: valid create info; the driver checks the SPIR-V.
        unsafe { self.device.create_shader_module(&info, None) }.map_err(vkerr("vkCreateShaderModule"))
    }

    /// Compiles one job and reads its executables.
    fn compile(&self, job: &Job) -> Result<Vec<Executable>, String> {
        let d = &self.device;
        let mut stages = vec![];
        let layout_bindings: Vec<_> = job
            .bindings
            .iter()
            .map(|&(b, kind)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::ALL)
                    .descriptor_type(match kind {
                        Descriptor::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
                        Descriptor::Storage => vk::DescriptorType::STORAGE_BUFFER,
                        Descriptor::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
                        Descriptor::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
                        Descriptor::Sampler => vk::DescriptorType::SAMPLER,
                    })
            })
            .collect();
        let set_info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: valid create infos throughout; every object is destroyed before return.
        unsafe {
            let set = d.create_descriptor_set_layout(&set_info, None).map_err(vkerr("vkCreateDescriptorSetLayout"))?;
            let sets = [set];
            let layout = d.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().set_layouts(&sets), None);
            let layout = match layout {
                Ok(l) => l,
                Err(e) => {
                    d.destroy_descriptor_set_layout(set, None);
                    return Err(format!("vkCreatePipelineLayout: {e}"));
                }
            };
            let flags = vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR
                | vk::PipelineCreateFlags::CAPTURE_INTERNAL_REPRESENTATIONS_KHR;
            let result = (|| -> Result<vk::Pipeline, String> {
                match &job.shaders {
                    Shaders::Graphics { vert, frag, depth, entries, vertex_attributes } => {
                        stages.push(self.module(vert)?);
                        stages.push(self.module(frag)?);
                        let name = |n: &str| {
                            std::ffi::CString::new(n).map_err(|_| format!("entry point name {n:?} holds a NUL"))
                        };
                        let (vs, fs) = (name(&entries[0])?, name(&entries[1])?);
                        let infos = [
                            vk::PipelineShaderStageCreateInfo::default()
                                .stage(vk::ShaderStageFlags::VERTEX)
                                .module(stages[0])
                                .name(&vs),
                            vk::PipelineShaderStageCreateInfo::default()
                                .stage(vk::ShaderStageFlags::FRAGMENT)
                                .module(stages[1])
                                .name(&fs),
                        ];
                        let n = *vertex_attributes;
                        let buffers = [vk::VertexInputBindingDescription::default()
                            .binding(0)
                            .stride(16 * n)
                            .input_rate(vk::VertexInputRate::VERTEX)];
                        let attributes: Vec<vk::VertexInputAttributeDescription> = (0..n)
                            .map(|k| {
                                vk::VertexInputAttributeDescription::default()
                                    .location(k)
                                    .binding(0)
                                    .format(vk::Format::R32G32B32A32_SFLOAT)
                                    .offset(16 * k)
                            })
                            .collect();
                        let vertex_input = if n == 0 {
                            vk::PipelineVertexInputStateCreateInfo::default()
                        } else {
                            vk::PipelineVertexInputStateCreateInfo::default()
                                .vertex_binding_descriptions(&buffers)
                                .vertex_attribute_descriptions(&attributes)
                        };
                        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
                            .topology(vk::PrimitiveTopology::TRIANGLE_STRIP);
                        let viewport =
                            vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
                        let raster = vk::PipelineRasterizationStateCreateInfo::default()
                            .polygon_mode(vk::PolygonMode::FILL)
                            .cull_mode(vk::CullModeFlags::NONE)
                            .line_width(1.0);
                        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
                            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
                        let depth_state = vk::PipelineDepthStencilStateCreateInfo::default()
                            .depth_test_enable(*depth)
                            .depth_write_enable(*depth)
                            .depth_compare_op(vk::CompareOp::ALWAYS);
                        let blend_attachment = [vk::PipelineColorBlendAttachmentState::default()
                            .color_write_mask(vk::ColorComponentFlags::RGBA)];
                        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachment);
                        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
                        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
                        let colour = [vk::Format::R8G8B8A8_SRGB];
                        let mut rendering = vk::PipelineRenderingCreateInfo::default()
                            .color_attachment_formats(&colour)
                            .depth_attachment_format(if *depth {
                                vk::Format::D32_SFLOAT
                            } else {
                                vk::Format::UNDEFINED
                            });
                        let info = vk::GraphicsPipelineCreateInfo::default()
                            .flags(flags)
                            .stages(&infos)
                            .vertex_input_state(&vertex_input)
                            .input_assembly_state(&assembly)
                            .viewport_state(&viewport)
                            .rasterization_state(&raster)
                            .multisample_state(&multisample)
                            .depth_stencil_state(&depth_state)
                            .color_blend_state(&blend)
                            .dynamic_state(&dynamic)
                            .layout(layout)
                            .push_next(&mut rendering);
                        d.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
                            .map(|p| p[0])
                            .map_err(|(_, e)| format!("vkCreateGraphicsPipelines: {e}"))
                    }
                    Shaders::Compute { comp } => {
                        stages.push(self.module(comp)?);
                        let stage = vk::PipelineShaderStageCreateInfo::default()
                            .stage(vk::ShaderStageFlags::COMPUTE)
                            .module(stages[0])
                            .name(c"probe");
                        let info = vk::ComputePipelineCreateInfo::default().flags(flags).stage(stage).layout(layout);
                        d.create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
                            .map(|p| p[0])
                            .map_err(|(_, e)| format!("vkCreateComputePipelines: {e}"))
                    }
                }
            })();
            let out = result.and_then(|pipeline| {
                let read = self.executables(pipeline);
                d.destroy_pipeline(pipeline, None);
                read
            });
            for m in stages {
                d.destroy_shader_module(m, None);
            }
            d.destroy_pipeline_layout(layout, None);
            d.destroy_descriptor_set_layout(set, None);
            out
        }
    }

    /// The executables of a pipeline made with the capture flags.
    ///
    /// # Safety
    /// `pipeline` is a live pipeline of this device created with the capture flags.
    unsafe fn executables(&self, pipeline: vk::Pipeline) -> Result<Vec<Executable>, String> {
        let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
        let props = self
            .exec
            .get_pipeline_executable_properties(&info)
            .map_err(vkerr("vkGetPipelineExecutablePropertiesKHR"))?;
        let mut out = vec![];
        for (i, p) in props.iter().enumerate() {
            let ex = vk::PipelineExecutableInfoKHR::default().pipeline(pipeline).executable_index(i as u32);
            let stats = self
                .exec
                .get_pipeline_executable_statistics(&ex)
                .map_err(vkerr("vkGetPipelineExecutableStatisticsKHR"))?
                .iter()
                .map(|s| {
                    let value = match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => s.value.b32 as f64,
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64 as f64,
                        vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64 as f64,
                        _ => s.value.f64,
                    };
                    (text(&s.name), value)
                })
                .collect();
            out.push(Executable {
                name: text(&p.name),
                subgroup_size: p.subgroup_size,
                stats,
                isa: self.disassembly(&ex)?,
            });
        }
        Ok(out)
    }

    /// The executable's internal representation the driver calls its assembly (the last text
    /// representation whose name says "Assembly", else the last text one).
    ///
    /// # Safety
    /// `ex` names an executable of a live pipeline created with the capture flags.
    unsafe fn disassembly(&self, ex: &vk::PipelineExecutableInfoKHR<'_>) -> Result<String, String> {
        let fp = self.exec.fp().get_pipeline_executable_internal_representations_khr;
        let handle = self.device.handle();
        let mut count = 0u32;
        fp(handle, ex, &mut count, std::ptr::null_mut())
            .result()
            .map_err(vkerr("vkGetPipelineExecutableInternalRepresentationsKHR"))?;
        let mut reps = vec![vk::PipelineExecutableInternalRepresentationKHR::default(); count as usize];
        fp(handle, ex, &mut count, reps.as_mut_ptr())
            .result()
            .map_err(vkerr("vkGetPipelineExecutableInternalRepresentationsKHR"))?;
        let mut buffers: Vec<Vec<u8>> = reps.iter().map(|r| vec![0u8; r.data_size]).collect();
        for (r, b) in reps.iter_mut().zip(buffers.iter_mut()) {
            r.p_data = b.as_mut_ptr().cast();
        }
        fp(handle, ex, &mut count, reps.as_mut_ptr())
            .result()
            .map_err(vkerr("vkGetPipelineExecutableInternalRepresentationsKHR"))?;
        let mut best = None;
        for (r, b) in reps.iter().zip(&buffers) {
            if r.is_text == vk::FALSE {
                continue;
            }
            let name = text(&r.name);
            let body = String::from_utf8_lossy(b.split(|&c| c == 0).next().unwrap_or(&[])).into_owned();
            if name.contains("Assembly") || best.is_none() {
                best = Some(body);
            }
        }
        Ok(best.unwrap_or_default())
    }
}

/// Compiles every job on the RADV device this process sees (the family is the process's
/// `RADV_FORCE_FAMILY`). An error opening the driver fails the whole answer; a job that
/// fails to compile fails alone.
pub(crate) fn compile_jobs(jobs: &[Job]) -> Result<Answer, String> {
    let radv = Radv::open()?;
    let results = jobs.iter().map(|j| radv.compile(j).map_err(|e| format!("{}: {e}", j.name))).collect();
    Ok(Answer { device: radv.name.clone(), driver: radv.driver.clone(), results })
}
