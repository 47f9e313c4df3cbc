//! The wgpu side of rendering: a headless device (no window, no surface), the two pipelines
//! of `shaders/scene.wgsl`, and one offscreen pass per picture, read back to memory.
//!
//! Target: `Rgba8UnormSrgb`, multisampled (`samples`) and resolved, with a
//! `Depth24PlusStencil8` depth-stencil buffer. Triangles are drawn without culling. A frame
//! with a section plane is capped: the clipped stock is drawn again into the stencil only
//! (inverting it per fragment), then a quad on the plane where the stencil is odd, i.e.
//! where the plane lies inside the material; lines come last, translucent (faint) ones
//! blended once per sample (a stencil bit).

use super::RenderError;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;

/// One vertex: position (mm) and sRGB colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Vertex {
    pub(crate) position: [f32; 3],
    pub(crate) colour: [u8; 4],
}

/// The shader's uniform block (see `shaders/scene.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Uniforms {
    pub(crate) view_proj: [[f32; 4]; 4],
    pub(crate) light: [f32; 4],
    pub(crate) eye: [f32; 4],
    pub(crate) plane: [f32; 4],
    pub(crate) params: [f32; 4],
}

/// What one picture draws.
pub(crate) struct Frame<'a> {
    pub(crate) size: (u32, u32),
    pub(crate) background: [u8; 3],
    pub(crate) uniforms: Uniforms,
    /// Indexed triangle lists; the first is the stock (the one a section caps).
    pub(crate) meshes: Vec<(&'a [Vertex], &'a [u32])>,
    /// The cap quad on the section plane (a triangle strip), for sections.
    pub(crate) cap: Option<[Vertex; 4]>,
    /// Line segments, two vertices each.
    pub(crate) lines: &'a [Vertex],
    /// Translucent line segments (their vertices' alpha), blended at most once per pixel
    /// sample, so that many lines over one pixel stay as faint as one.
    pub(crate) faint: &'a [Vertex],
}

/// A device with its pipelines.
pub(crate) struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    pub(crate) info: wgpu::AdapterInfo,
    pub(crate) samples: u32,
    layout: wgpu::BindGroupLayout,
    mesh: wgpu::RenderPipeline,
    stencil: wgpu::RenderPipeline,
    cap: wgpu::RenderPipeline,
    line: wgpu::RenderPipeline,
    faint: wgpu::RenderPipeline,
    /// An error the device raised outside an error scope, or its loss: wgpu would panic
    /// on it; the next draw returns it instead.
    fault: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

/// The adapter wgpu picks: `WGPU_BACKEND` selects backends (as wgpu documents), and
/// `WGPU_ADAPTER_NAME` an adapter by a part of its name.
fn adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, RenderError> {
    if let Ok(name) = std::env::var("WGPU_ADAPTER_NAME") {
        let name = name.to_lowercase();
        let all = instance.enumerate_adapters(wgpu::Backends::all());
        let names: Vec<String> = all.iter().map(|a| a.get_info().name).collect();
        return all
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&name))
            .ok_or_else(|| {
                RenderError::NoAdapter(format!(
                    "WGPU_ADAPTER_NAME={name} matches none of the adapters found ({})",
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                ))
            });
    }
    pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))
    .map_err(|e| RenderError::NoAdapter(e.to_string()))
}

impl Gpu {
    pub(crate) fn new(samples: u32) -> Result<Gpu, RenderError> {
        let instance = wgpu::Instance::new(&wgpu::InstanceDescriptor::from_env_or_default());
        let adapter = adapter(&instance)?;
        let info = adapter.get_info();
        for f in [FORMAT, DEPTH] {
            if !adapter
                .get_texture_format_features(f)
                .flags
                .sample_count_supported(samples)
            {
                return Err(RenderError::Unsupported(format!(
                    "{} cannot render {samples}x multisampled {f:?}",
                    info.name
                )));
            }
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("vpcut"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::NoAdapter(format!("{}: {e}", info.name)))?;
        let fault = std::sync::Arc::new(std::sync::Mutex::new(None::<String>));
        let record = fault.clone();
        device.on_uncaptured_error(Box::new(move |e| {
            if let Ok(mut f) = record.lock() {
                f.get_or_insert_with(|| e.to_string());
            }
        }));
        let record = fault.clone();
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut f) = record.lock() {
                f.get_or_insert_with(|| format!("device lost ({reason:?}): {message}"));
            }
        });
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(super::SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[&layout],
            push_constant_ranges: &[],
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
        let pipeline = |vs: &str,
                        fs: &str,
                        topology: wgpu::PrimitiveTopology,
                        depth: (bool, wgpu::CompareFunction),
                        stencil: wgpu::StencilState,
                        colour: wgpu::ColorWrites,
                        blend: Option<wgpu::BlendState>| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(vs),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    }],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: depth.0,
                    depth_compare: depth.1,
                    stencil,
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: FORMAT,
                        blend,
                        write_mask: colour,
                    })],
                }),
                multiview: None,
                cache: None,
            })
        };
        let tris = wgpu::PrimitiveTopology::TriangleList;
        let depth_test = (true, wgpu::CompareFunction::LessEqual);
        let face = |compare, op, depth_fail_op| wgpu::StencilFaceState {
            compare,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op,
            pass_op: op,
        };
        // Bit 0 of the stencil is the section's parity, bit 7 marks a sample a faint line
        // has already been blended into.
        let stencil = |compare, op, read_mask, write_mask| wgpu::StencilState {
            front: face(compare, op, op),
            back: face(compare, op, op),
            read_mask,
            write_mask,
        };
        let all = wgpu::ColorWrites::ALL;
        let mesh = pipeline(
            "vs_mesh",
            "fs_mesh",
            tris,
            depth_test,
            Default::default(),
            all,
            None,
        );
        // Every clipped fragment flips the stencil: odd counts start inside the material.
        let stencil_pipeline = pipeline(
            "vs_mesh",
            "fs_line",
            tris,
            (false, wgpu::CompareFunction::Always),
            stencil(
                wgpu::CompareFunction::Always,
                wgpu::StencilOperation::Invert,
                0x01,
                0x01,
            ),
            wgpu::ColorWrites::empty(),
            None,
        );
        let cap = pipeline(
            "vs_mesh",
            "fs_flat",
            wgpu::PrimitiveTopology::TriangleStrip,
            depth_test,
            stencil(
                wgpu::CompareFunction::NotEqual,
                wgpu::StencilOperation::Keep,
                0x01,
                0,
            ),
            all,
            None,
        );
        let line = pipeline(
            "vs_line",
            "fs_line",
            wgpu::PrimitiveTopology::LineList,
            depth_test,
            Default::default(),
            all,
            None,
        );
        // Faint lines: blended by their alpha where bit 7 is clear, which they then set
        // (a hidden line, failing the depth test, leaves it clear).
        let once = face(
            wgpu::CompareFunction::NotEqual,
            wgpu::StencilOperation::Replace,
            wgpu::StencilOperation::Keep,
        );
        let faint = pipeline(
            "vs_line",
            "fs_line",
            wgpu::PrimitiveTopology::LineList,
            depth_test,
            wgpu::StencilState {
                front: once,
                back: once,
                read_mask: 0x80,
                write_mask: 0x80,
            },
            all,
            Some(wgpu::BlendState::ALPHA_BLENDING),
        );
        Ok(Gpu {
            device,
            queue,
            info,
            samples,
            layout,
            mesh,
            stencil: stencil_pipeline,
            cap,
            line,
            faint,
            fault,
        })
    }

    /// Whether the adapter's textures take a `w` x `h` picture.
    pub(crate) fn check_size(&self, w: u32, h: u32) -> Result<(), RenderError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if w > max || h > max {
            return Err(RenderError::Unsupported(format!(
                "{w}x{h} is larger than the adapter's {max} pixels"
            )));
        }
        Ok(())
    }

    /// Draw a frame and read it back: RGBA8 (sRGB) rows, top to bottom. Out of memory and
    /// validation failures of the device come back as [`RenderError::Device`], never as
    /// wgpu's panic.
    pub(crate) fn draw(&self, frame: &Frame<'_>) -> Result<Vec<u8>, RenderError> {
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let drawn = self.draw_scoped(frame);
        let oom = pollster::block_on(self.device.pop_error_scope());
        let invalid = pollster::block_on(self.device.pop_error_scope());
        if let Some(e) = oom {
            return Err(RenderError::Device(format!(
                "out of graphics memory ({e}): draw a smaller picture"
            )));
        }
        if let Some(e) = invalid {
            return Err(RenderError::Device(e.to_string()));
        }
        if let Some(f) = self.fault.lock().ok().and_then(|mut f| f.take()) {
            return Err(RenderError::Device(f));
        }
        drawn
    }

    fn draw_scoped(&self, frame: &Frame<'_>) -> Result<Vec<u8>, RenderError> {
        let (w, h) = frame.size;
        self.check_size(w, h)?;
        let limits = self.device.limits();
        let biggest = frame
            .meshes
            .iter()
            .map(|m| std::mem::size_of_val(m.0).max(std::mem::size_of_val(m.1)))
            .chain([std::mem::size_of_val(frame.lines)])
            .chain([std::mem::size_of_val(frame.faint)])
            .max()
            .unwrap_or(0) as u64;
        if biggest > limits.max_buffer_size {
            return Err(RenderError::Unsupported(format!(
                "the model needs a {biggest}-byte buffer, over the adapter's {}: export it with a coarser mesh tolerance",
                limits.max_buffer_size
            )));
        }
        let d = &self.device;
        let texture = |format, samples, usage| {
            d.create_texture(&wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let resolved = texture(
            FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let msaa = (self.samples > 1)
            .then(|| texture(FORMAT, self.samples, wgpu::TextureUsages::RENDER_ATTACHMENT));
        let depth = texture(DEPTH, self.samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let resolved_view = resolved.create_view(&Default::default());
        let msaa_view = msaa.as_ref().map(|t| t.create_view(&Default::default()));
        let depth_view = depth.create_view(&Default::default());
        let uniforms = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("uniforms"),
            contents: bytemuck::bytes_of(&frame.uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let buffer = |bytes: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: bytes,
                usage,
            })
        };
        let meshes: Vec<(wgpu::Buffer, wgpu::Buffer, u32)> = frame
            .meshes
            .iter()
            .filter(|m| !m.1.is_empty())
            .map(|(v, i)| {
                (
                    buffer(bytemuck::cast_slice(v), wgpu::BufferUsages::VERTEX),
                    buffer(bytemuck::cast_slice(i), wgpu::BufferUsages::INDEX),
                    i.len() as u32,
                )
            })
            .collect();
        let lines = (!frame.lines.is_empty()).then(|| {
            buffer(
                bytemuck::cast_slice(frame.lines),
                wgpu::BufferUsages::VERTEX,
            )
        });
        let faint = (!frame.faint.is_empty()).then(|| {
            buffer(
                bytemuck::cast_slice(frame.faint),
                wgpu::BufferUsages::VERTEX,
            )
        });
        let cap = frame
            .cap
            .map(|q| buffer(bytemuck::cast_slice(&q), wgpu::BufferUsages::VERTEX));
        let row = 4 * w;
        let readback = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: row as u64 * h as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let srgb = |c: u8| {
                let s = c as f64 / 255.0;
                if s <= 0.04045 {
                    s / 12.92
                } else {
                    ((s + 0.055) / 1.055).powf(2.4)
                }
            };
            let bg = frame.background;
            let (view, resolve_target) = match &msaa_view {
                Some(m) => (m, Some(&resolved_view)),
                None => (&resolved_view, None),
            };
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: srgb(bg[0]),
                            g: srgb(bg[1]),
                            b: srgb(bg[2]),
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0),
                        store: wgpu::StoreOp::Discard,
                    }),
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
            });
            pass.set_bind_group(0, &bind, &[]);
            pass.set_pipeline(&self.mesh);
            for (v, i, n) in &meshes {
                pass.set_vertex_buffer(0, v.slice(..));
                pass.set_index_buffer(i.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*n, 0, 0..1);
            }
            if let (Some(quad), Some((v, i, n))) = (&cap, meshes.first()) {
                pass.set_pipeline(&self.stencil);
                pass.set_vertex_buffer(0, v.slice(..));
                pass.set_index_buffer(i.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*n, 0, 0..1);
                pass.set_pipeline(&self.cap);
                pass.set_stencil_reference(0);
                pass.set_vertex_buffer(0, quad.slice(..));
                pass.draw(0..4, 0..1);
            }
            if let Some(l) = &lines {
                pass.set_pipeline(&self.line);
                pass.set_vertex_buffer(0, l.slice(..));
                pass.draw(0..frame.lines.len() as u32, 0..1);
            }
            if let Some(l) = &faint {
                pass.set_pipeline(&self.faint);
                pass.set_stencil_reference(0x80);
                pass.set_vertex_buffer(0, l.slice(..));
                pass.draw(0..frame.faint.len() as u32, 0..1);
            }
        }
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([enc.finish()]);
        let slice = readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::Wait)
            .map_err(|e| RenderError::Device(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Device(e.to_string()))?
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let data = {
            let mapped = slice.get_mapped_range();
            let mut data = Vec::new();
            data.try_reserve_exact(mapped.len())
                .map_err(|_| super::out_of_memory(mapped.len()))?;
            data.extend_from_slice(&mapped);
            data
        };
        readback.unmap();
        Ok(data)
    }
}
