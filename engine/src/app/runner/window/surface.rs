//! What exists only while the window does: the GPU, the swap chain
//! configured for the window's size (none while minimised to 0x0), the
//! renderer and the panel's egui state; and screenshots drawn off-screen
//! at the window's size.

use std::path::PathBuf;
use std::sync::Arc;

use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::options::WindowOptions;
use super::panel::Panel;
use crate::app::api::error::RunError;
use crate::app::session::source::FrameSource;
use crate::render::{FrameBuffers, Gpu, OFFSCREEN_FORMAT, OffscreenTarget, RenderError, Renderer};

/// Everything that exists only while the window does.
pub(super) struct WindowState {
    pub(super) gpu: Gpu,
    pub(super) surface: wgpu::Surface<'static>,
    pub(super) config: wgpu::SurfaceConfiguration,
    /// The format drawn in: the surface's own, or an sRGB view of it
    /// where the surface has only a plain format (WebGPU in a browser).
    pub(super) format: wgpu::TextureFormat,
    pub(super) renderer: Renderer,
    pub(super) buffers: Option<FrameBuffers>,
    /// Where a frame is drawn first when the surface is drawn through an
    /// sRGB view ([`Relay`]); `None` where the surface is sRGB itself.
    pub(super) relay: Option<Relay>,
    // Dropped last: the surface refers to it.
    pub(super) window: Arc<Window>,
}

/// A frame's first stop on a surface drawn through an sRGB view of a
/// plain format (WebGPU canvases). Dawn (Chromium's WebGPU) resolves a
/// multisampled frame into such a view as if it were the plain format,
/// leaving linear values on the canvas (every colour too dark); drawing
/// through the view is right. So the frame is drawn and resolved into
/// this sRGB texture, which a full-screen pass then copies through the
/// view; the panel draws on the surface after it.
pub(super) struct Relay {
    blitter: wgpu::util::TextureBlitter,
    view: Option<wgpu::TextureView>,
}

impl Relay {
    fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        Self {
            blitter: wgpu::util::TextureBlitter::new(device, format),
            view: None,
        }
    }

    /// A texture of the surface's size and draw format to draw into
    /// (through [`Gpu::allocate`], so running out of memory is an error).
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32, format: wgpu::TextureFormat) -> Result<(), RenderError> {
        let view = gpu.allocate(&|| format!("a {width}x{height} relay texture"), || {
            let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("tickwork relay"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            Ok(texture.create_view(&wgpu::TextureViewDescriptor::default()))
        })?;
        self.view = Some(view);
        Ok(())
    }

    /// The view to draw the frame into, if the relay has been sized.
    pub(super) fn view(&self) -> Option<&wgpu::TextureView> {
        self.view.as_ref()
    }

    /// Copies the drawn frame onto the surface's view.
    pub(super) fn copy_to(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
    ) {
        if let Some(view) = &self.view {
            self.blitter.copy(device, encoder, view, target);
        }
    }
}

/// A window with its surface, waiting for the GPU ([`Opening::connect`]).
pub(super) struct Opening {
    window: Arc<Window>,
    instance: wgpu::Instance,
    backends: wgpu::Backends,
    surface: wgpu::Surface<'static>,
}

/// Opens a window titled after `title` as `options` ask (in a page: a
/// canvas, filling the page unless a size is fixed) and its surface; the
/// GPU comes next, from [`Opening::connect`].
pub(super) fn open(event_loop: &ActiveEventLoop, title: &str, options: &WindowOptions) -> Result<Opening, RunError> {
    let attributes = crate::platform::window_attributes(
        Window::default_attributes().with_title(format!("Tickwork - {title}")),
        (!options.fill_page).then_some((options.width, options.height)),
    )
    .map_err(RunError::Window)?;
    let window = Arc::new(
        event_loop
            .create_window(attributes)
            .map_err(|e| RunError::Window(e.to_string()))?,
    );
    // With the display handle, so that the GL backend finds an adapter
    // compatible with the window's surface.
    let mut descriptor =
        wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(event_loop.owned_display_handle()));
    if let Some(backends) = options.backends {
        descriptor.backends = backends;
    }
    let backends = descriptor.backends;
    let instance = wgpu::Instance::new(descriptor);
    let surface = instance
        .create_surface(window.clone())
        .map_err(|e| RenderError::Surface(e.to_string()))?;
    Ok(Opening {
        window,
        instance,
        backends,
        surface,
    })
}

impl Opening {
    /// Finds the GPU for the window's surface (a future the browser
    /// resolves in a page; natively it is ready at once), configures the
    /// surface and makes the renderer and the panel's egui state.
    pub(super) async fn connect(self, options: WindowOptions) -> Result<(WindowState, Panel), RunError> {
        let Self {
            window,
            instance,
            backends,
            surface,
        } = self;
        let gpu = Gpu::request(instance, backends, Some(&surface)).await?;
        let caps = surface.get_capabilities(&gpu.adapter);
        // The renderer blends in linear light and needs an sRGB target. A
        // browser's WebGPU canvas offers only plain formats (bgra8unorm),
        // so there the surface keeps its plain format and is drawn through
        // an sRGB view of it, which WebGPU allows for any canvas format.
        let surface_format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| RenderError::Surface("the surface offers no format for this adapter".into()))?;
        let format = surface_format.add_srgb_suffix();
        let view_formats = if format == surface_format { vec![] } else { vec![format] };
        let present_mode = if options.vsync {
            wgpu::PresentMode::Fifo
        } else {
            [wgpu::PresentMode::Mailbox, wgpu::PresentMode::Immediate]
                .into_iter()
                .find(|m| caps.present_modes.contains(m))
                .unwrap_or(wgpu::PresentMode::Fifo)
        };
        let size = window.inner_size();
        // Copies into the surface let the splat path skip a full-screen pass.
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | (caps.usages & wgpu::TextureUsages::COPY_DST);
        let config = wgpu::SurfaceConfiguration {
            usage,
            format: surface_format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats,
            desired_maximum_frame_latency: 2,
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        let renderer = Renderer::new(&gpu, format, options.renderer.clone())?;
        let relay = (format != surface_format).then(|| Relay::new(&gpu.device, format));
        let panel = Panel::new(&window, &gpu, format);
        let mut state = WindowState {
            gpu,
            surface,
            config,
            format,
            renderer,
            buffers: None,
            relay,
            window,
        };
        state.resize(size.width, size.height)?;
        Ok((state, panel))
    }
}

impl WindowState {
    /// Reconfigures for a new inner size; 0x0 (minimised) keeps the old
    /// surface and draws nothing until the window comes back.
    pub(super) fn resize(&mut self, width: u32, height: u32) -> Result<(), RunError> {
        if width == 0 || height == 0 {
            self.buffers = None;
            return Ok(());
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.gpu.device, &self.config);
        if let Some(relay) = &mut self.relay {
            relay.resize(&self.gpu, width, height, self.format)?;
        }
        self.buffers = Some(FrameBuffers::new(
            &self.gpu,
            width,
            height,
            self.format,
            self.renderer.config().samples,
        )?);
        Ok(())
    }
}

/// Draws the window's current view off-screen at the window's size and
/// saves it as `screenshot_NNNN.png`, never overwriting an existing file.
pub(super) fn screenshot(
    state: &WindowState,
    source: &mut dyn FrameSource,
    options: &WindowOptions,
) -> Result<PathBuf, RunError> {
    let (width, height) = (state.config.width, state.config.height);
    let target = OffscreenTarget::new(&state.gpu, width, height, options.renderer.samples)?;
    let mut renderer = Renderer::new(&state.gpu, OFFSCREEN_FORMAT, options.renderer.clone())?;
    if let Some(interpolation) = source.interpolation() {
        renderer.set_interpolation(interpolation);
    }
    let mut image = None;
    source.with_view(options.hud, (width, height), &mut |view| {
        image = Some(target.render(&state.gpu, &mut renderer, view)?);
        Ok(())
    })?;
    let Some(image) = image else {
        return Err(RenderError::Device("the frame was not drawn".into()).into());
    };
    std::fs::create_dir_all(&options.screenshot_dir).map_err(|e| RunError::io(&options.screenshot_dir, &e))?;
    let path = (0..)
        .map(|k| options.screenshot_dir.join(format!("screenshot_{k:04}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| options.screenshot_dir.join("screenshot.png"));
    image.save(&path).map_err(|e| RunError::io(&path, &e))?;
    Ok(path)
}
