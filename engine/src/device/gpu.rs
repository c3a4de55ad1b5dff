//! The GPU: one wgpu instance, adapter, device and queue, shared by every
//! target and renderer made from it.
//!
//! Choosing an adapter is where rendering fails on a machine without a GPU
//! driver, so this is where the error says what was tried and what to
//! install, instead of a panic deep inside wgpu.

use std::fmt;

use super::RenderError;

/// A wgpu device and queue, with the adapter they came from (cloned
/// cheaply: each is a handle to the same device).
#[derive(Clone)]
pub struct Gpu {
    /// The instance the adapter was found on (needed to create surfaces).
    pub instance: wgpu::Instance,
    /// The adapter (physical or software device) in use.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its command queue.
    pub queue: wgpu::Queue,
}

impl fmt::Debug for Gpu {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.adapter.get_info())
            .finish_non_exhaustive()
    }
}

/// Turns off Mesa's Vulkan device-selection layer when it would complain:
/// with `XDG_RUNTIME_DIR` unset or not a directory (CI, `sudo`, a bare
/// container) the layer tries Wayland and prints "error: XDG_RUNTIME_DIR
/// is invalid or not set in the environment" twice on every run, though
/// nothing is wrong (wgpu picks the adapter itself, so the layer has no
/// work to do). Sets `NODEVICE_SELECT=1` then, unless the user set it.
///
/// Call it first thing in `main`, before any thread starts: the binaries
/// and [`run`](crate::app::run) do.
pub fn quiet_device_select_layer() {
    use crate::platform::env_var;
    // A page has no environment (and no Mesa layer).
    if crate::platform::IS_WEB {
        return;
    }
    let runtime_dir_ok = env_var("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if !runtime_dir_ok && env_var("NODEVICE_SELECT").is_none() {
        // SAFETY: called at the start of a program, before the engine starts
        // a thread (the docs say so), so no other thread reads the
        // environment while it changes.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

impl Gpu {
    /// A GPU for off-screen rendering (no window, no display), on the
    /// backends `WGPU_BACKEND` selects (default: all that are compiled in,
    /// Vulkan then GL on Linux).
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] naming the backends tried and, on Linux, the
    /// packages that provide a software adapter; [`RenderError::Device`] if
    /// the adapter refuses a device.
    pub fn headless() -> Result<Self, RenderError> {
        let descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        Self::with_instance(descriptor, None)
    }

    /// A GPU able to present to `surface`'s kind of window. `descriptor`
    /// must carry the display handle for the GL backend to find a
    /// compatible adapter.
    ///
    /// # Errors
    /// As [`Gpu::headless`].
    pub fn with_instance(
        descriptor: wgpu::InstanceDescriptor,
        compatible_surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, RenderError> {
        let backends = descriptor.backends;
        let instance = wgpu::Instance::new(descriptor);
        Self::from_instance(instance, backends, compatible_surface)
    }

    /// As [`Gpu::with_instance`], for an instance already made (a window
    /// creates its surface from the instance first). Natively it waits for
    /// the adapter and device; a page cannot wait (see [`Gpu::request`]).
    ///
    /// # Errors
    /// As [`Gpu::headless`]; in the browser, [`RenderError::Device`] saying
    /// to use [`Gpu::request`].
    pub fn from_instance(
        instance: wgpu::Instance,
        backends: wgpu::Backends,
        compatible_surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, RenderError> {
        crate::platform::ready_now(Self::request(instance, backends, compatible_surface)).unwrap_or_else(|| {
            Err(RenderError::Device(
                "the browser gives the adapter and device later: start the GPU with Gpu::request".into(),
            ))
        })
    }

    /// The adapter and device of `instance`, as futures resolve them: in a
    /// page the browser answers only after the script yields, so this is
    /// the one way to start a GPU there (natively [`Gpu::from_instance`]
    /// waits on it).
    ///
    /// # Errors
    /// As [`Gpu::headless`].
    pub async fn request(
        instance: wgpu::Instance,
        backends: wgpu::Backends,
        compatible_surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, RenderError> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
            force_fallback_adapter: false,
            compatible_surface,
            apply_limit_buckets: false,
        };
        let adapter = instance
            .request_adapter(&options)
            .await
            .map_err(|error| RenderError::NoAdapter {
                backends: backend_names(backends),
                reason: error.to_string(),
            })?;
        // WebGL2 has no compute or storage buffers: its own defaults (the
        // renderer then draws without the splat path).
        let base = if adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
        {
            wgpu::Limits::downlevel_defaults()
        } else {
            wgpu::Limits::downlevel_webgl2_defaults()
        };
        let limits = base.using_resolution(adapter.limits());
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("tickwork"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits {
                max_storage_buffer_binding_size: adapter.limits().max_storage_buffer_binding_size,
                max_buffer_size: adapter.limits().max_buffer_size,
                // The GPU step's row kernels bind six (downlevel: four).
                max_storage_buffers_per_shader_stage: adapter.limits().max_storage_buffers_per_shader_stage,
                ..limits
            },
            ..Default::default()
        };
        let (device, queue) = adapter
            .request_device(&descriptor)
            .await
            .map_err(|error| RenderError::Device(error.to_string()))?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// Runs `create` (which makes textures or buffers) inside an
    /// out-of-memory error scope: a size within the device's limits can
    /// still be past its memory (16384 x 16384 with MSAA is 4 GiB a
    /// buffer on a software adapter), which wgpu reports to its
    /// uncaptured-error handler, a panic. Here it is a
    /// [`RenderError::Device`] naming `what` and what to try.
    ///
    /// # Errors
    /// `create`'s own, or the out-of-memory error.
    pub fn allocate<T>(
        &self,
        what: &dyn Fn() -> String,
        create: impl FnOnce() -> Result<T, RenderError>,
    ) -> Result<T, RenderError> {
        // Views of a texture that failed to allocate are validation errors:
        // caught too, and reported as the memory error that caused them.
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let created = create();
        // A page cannot wait for the scopes' answers: there an error reaches
        // the console through wgpu's own handler instead.
        let invalid = crate::platform::ready_now(validation.pop()).flatten();
        if let Some(error) = crate::platform::ready_now(memory.pop()).flatten() {
            return Err(RenderError::Device(format!(
                "out of GPU memory for {}: {error}; draw a smaller size, or without MSAA",
                what()
            )));
        }
        if let Some(error) = invalid {
            return Err(RenderError::Device(format!("cannot create {}: {error}", what())));
        }
        created
    }

    /// What the adapter is: name, backend and device type, for logs and
    /// HUDs (e.g. `llvmpipe (LLVM 15.0.6, 256 bits) on Vulkan (Cpu)`).
    #[must_use]
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        // A browser's WebGPU adapter may keep its name to itself.
        if info.name.is_empty() {
            format!("{:?} ({:?})", info.backend, info.device_type)
        } else {
            format!("{} on {:?} ({:?})", info.name, info.backend, info.device_type)
        }
    }
}

/// The names of the backends in `backends`, for error messages.
fn backend_names(backends: wgpu::Backends) -> Vec<&'static str> {
    [
        (wgpu::Backends::VULKAN, "Vulkan"),
        (wgpu::Backends::GL, "GL"),
        (wgpu::Backends::METAL, "Metal"),
        (wgpu::Backends::DX12, "DX12"),
        (wgpu::Backends::BROWSER_WEBGPU, "WebGPU"),
    ]
    .into_iter()
    .filter(|(flag, _)| backends.contains(*flag))
    .map(|(_, name)| name)
    .collect()
}
