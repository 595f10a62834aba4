//! Drawing the 3D view with wgpu: into the view's own colour and depth textures, shown as an
//! egui image. The same path works on Vulkan, WebGPU, WebGL2 and in the snapshot tests'
//! renderer, whose pass has no depth buffer (rerun's viewer draws its views the same way).
//! Only vertex and instance attributes and one uniform buffer are used: WebGL2 has no
//! storage buffers and no compute.

use std::sync::{Arc, OnceLock};

use eframe::egui_wgpu::RenderState;
use eframe::wgpu;
use glam::{DVec3, Mat4};

/// The colour format egui takes from a native texture.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Bytes of one mesh vertex: position (3 × f32), normal (4 × i8), colour (4 × u8).
const MESH_VERTEX_BYTES: u64 = 20;
/// Bytes of a triangle's three vertices.
const TRIANGLE_BYTES: u64 = 3 * MESH_VERTEX_BYTES;
/// Bytes of one instance: a (3 × f32), b (3 × f32), colour (4 × u8).
const INSTANCE_BYTES: u64 = 28;
const UNIFORM_BYTES: u64 = 112;

/// The GPU, as eframe made it, and the 3D view's pipelines (made when first needed, so the 2D
/// lessons never wait for them).
pub struct Gpu {
    render_state: RenderState,
    pipelines: OnceLock<Pipelines>,
}

impl Gpu {
    /// Keeps eframe's render state for the 3D views of `ctx`.
    pub fn install(ctx: &egui::Context, render_state: RenderState) {
        let gpu = Arc::new(Gpu {
            render_state,
            pipelines: OnceLock::new(),
        });
        ctx.data_mut(|data| data.insert_temp(egui::Id::NULL.with(GPU_KEY), gpu));
    }

    /// The GPU installed for `ctx`, if the app runs on wgpu.
    pub fn of(ctx: &egui::Context) -> Option<Arc<Gpu>> {
        ctx.data(|data| data.get_temp::<Arc<Gpu>>(egui::Id::NULL.with(GPU_KEY)))
    }

    fn pipelines(&self) -> &Pipelines {
        self.pipelines
            .get_or_init(|| Pipelines::new(&self.render_state.device))
    }
}

const GPU_KEY: &str = "accelviz-view3d-gpu";

/// A triangle as drawn: its corners (relative to the scene's origin) and its colour (sRGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawTriangle {
    /// Corners.
    pub corners: [[f32; 3]; 3],
    /// sRGB colour with alpha.
    pub color: [u8; 4],
}

/// An instance: a box (`a` = min, `b` = max), a segment from `a` to `b`, or a flat box drawn
/// as a quad; with its sRGB colour and alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Min corner, or the segment's start.
    pub a: [f32; 3],
    /// Max corner, or the segment's end.
    pub b: [f32; 3],
    /// sRGB colour with alpha.
    pub color: [u8; 4],
}

/// How box edges behind a surface are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HiddenEdges {
    /// Faint (x-ray).
    #[default]
    Dimmed,
    /// Not at all.
    Hidden,
}

/// What one frame of the view shows. Layers carry a revision: a layer whose revision has not
/// changed is not uploaded again.
pub struct Scene3d<'a> {
    /// World to clip space, for world coordinates minus `origin`.
    pub view_proj: Mat4,
    /// Towards the light, in world space.
    pub light: DVec3,
    /// The mesh's triangles and their revision.
    pub mesh: (u64, &'a [DrawTriangle]),
    /// Triangles drawn again over the mesh (highlights), and their revision.
    pub highlights: (u64, &'a [DrawTriangle]),
    /// Boxes outlined, and their revision.
    pub boxes: (u64, &'a [Instance]),
    /// Segments (rays, markers), and their revision.
    pub segments: (u64, &'a [Instance]),
    /// Translucent quads (planes), back to front, and their revision.
    pub quads: (u64, &'a [Instance]),
    /// Line width in pixels.
    pub line_width: f32,
    /// How box edges behind surfaces are drawn.
    pub hidden_edges: HiddenEdges,
    /// Whether the mesh's triangle edges are drawn.
    pub wireframe: bool,
    /// Background colour (sRGB).
    pub background: [u8; 3],
}

/// Most bytes one layer sends to the GPU in a frame. A million-triangle mesh is 60 MB of
/// vertices; made and copied at once, they stalled the frame the mesh arrived in (with the
/// inspector's recount, since fixed, it took 215 ms: `benches/view3d.rs` with
/// `ACCELVIZ_BENCH_MILLION`). In pieces they go up over a few frames and no frame waits on
/// them; the view keeps its last picture until all are there (drawing each part would cost a
/// software GPU as much as drawing the whole).
const UPLOAD_BYTES_PER_FRAME: u64 = 6 << 20;

/// A GPU buffer of one layer: the revision it holds, and how much of it has arrived.
#[derive(Default)]
struct Layer {
    buffer: Option<wgpu::Buffer>,
    /// Items (triangles, instances) of the revision uploaded so far.
    uploaded: u32,
    /// Items the revision has.
    total: u32,
    revision: Option<u64>,
}

impl Layer {
    /// Uploads the next piece of `revision` (`total` items of `item_bytes` each, made by
    /// `bytes` for a range of items) unless it is all there already.
    fn update(
        &mut self,
        gpu: &RenderState,
        revision: u64,
        total: usize,
        item_bytes: u64,
        bytes: impl FnOnce(std::ops::Range<usize>) -> Vec<u8>,
    ) {
        if self.revision != Some(revision) {
            self.revision = Some(revision);
            self.uploaded = 0;
            self.total = total as u32;
            let size = total as u64 * item_bytes;
            let fits = self
                .buffer
                .as_ref()
                .is_some_and(|buffer| buffer.size() >= size);
            if !fits && total > 0 {
                self.buffer = Some(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("accelviz 3d layer"),
                    size: size.next_power_of_two().max(256),
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
            }
        }
        if self.complete() {
            return;
        }
        let Some(buffer) = &self.buffer else { return };
        let piece = (UPLOAD_BYTES_PER_FRAME / item_bytes).max(1) as u32;
        let (start, end) = (self.uploaded, self.total.min(self.uploaded + piece));
        let bytes = bytes(start as usize..end as usize);
        gpu.queue
            .write_buffer(buffer, u64::from(start) * item_bytes, &bytes);
        self.uploaded = end;
    }

    /// Whether the whole revision is on the GPU.
    fn complete(&self) -> bool {
        self.uploaded == self.total
    }

    /// The uploaded items' bytes, and how many items they are.
    fn slice(&self, item_bytes: u64) -> Option<(wgpu::BufferSlice<'_>, u32)> {
        let buffer = self.buffer.as_ref()?;
        (self.uploaded > 0).then(|| {
            (
                buffer.slice(..u64::from(self.uploaded) * item_bytes),
                self.uploaded,
            )
        })
    }
}

/// The textures a view draws into, and what was last drawn there.
struct Target {
    size: [u32; 2],
    color: wgpu::Texture,
    depth_view: wgpu::TextureView,
    texture_id: egui::TextureId,
}

/// One 3D view's GPU state: its target and its layers.
#[derive(Default)]
pub struct ViewGpu {
    target: Option<Target>,
    uniforms: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    mesh: Layer,
    highlights: Layer,
    boxes: Layer,
    segments: Layer,
    quads: Layer,
    /// What the target holds: a frame that would draw the same is not drawn again.
    drawn: Option<u64>,
    /// A copy of the target on its way back from the GPU (for saving the view as a PNG).
    readback: Option<Readback>,
}

/// A copy of the view's picture being read back: the buffer, its layout, and whether the GPU
/// has handed it over.
struct Readback {
    buffer: wgpu::Buffer,
    size: [u32; 2],
    bytes_per_row: u32,
    mapped: std::sync::Arc<std::sync::atomic::AtomicU8>,
}

/// A picture read back: width, height, RGBA pixels row by row from the top.
pub type Picture = (usize, usize, Vec<[u8; 4]>);

/// `Readback::mapped` states.
const MAPPING: u8 = 0;
const MAPPED: u8 = 1;
const FAILED: u8 = 2;

impl ViewGpu {
    /// Starts reading the last picture back from the GPU (see [`ViewGpu::take_picture`]).
    pub fn request_picture(&mut self, gpu: &Gpu) {
        let Some(target) = &self.target else { return };
        let state = &gpu.render_state;
        let [width, height] = target.size;
        // Rows of a texture-to-buffer copy are padded to 256 bytes.
        let bytes_per_row = (width * 4).div_ceil(256) * 256;
        let buffer = state.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("accelviz 3d picture"),
            size: u64::from(bytes_per_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = state
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("accelviz 3d picture"),
            });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target.color,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(bytes_per_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        state.queue.submit(Some(encoder.finish()));
        let mapped = std::sync::Arc::new(std::sync::atomic::AtomicU8::new(MAPPING));
        let flag = mapped.clone();
        buffer.map_async(wgpu::MapMode::Read, .., move |result| {
            let state = if result.is_ok() { MAPPED } else { FAILED };
            flag.store(state, std::sync::atomic::Ordering::Release);
        });
        // On the desktop, wait for it here; in the browser the answer comes in a later frame.
        #[cfg(not(target_arch = "wasm32"))]
        let _ = state.device.poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: Some(std::time::Duration::from_secs(10)),
        });
        self.readback = Some(Readback {
            buffer,
            size: [width, height],
            bytes_per_row,
            mapped,
        });
    }

    /// The picture asked for with [`ViewGpu::request_picture`], once the GPU has handed it
    /// over: (width, height, RGBA pixels); `Some(Err)` if it could not.
    pub fn take_picture(&mut self) -> Option<Result<Picture, String>> {
        let readback = self.readback.as_ref()?;
        match readback.mapped.load(std::sync::atomic::Ordering::Acquire) {
            MAPPING => return None,
            FAILED => {
                self.readback = None;
                return Some(Err("the GPU did not hand the picture back".to_owned()));
            }
            _ => {}
        }
        let readback = self.readback.take()?;
        let [width, height] = readback.size.map(|x| x as usize);
        let picture = {
            let view = match readback.buffer.get_mapped_range(..) {
                Ok(view) => view,
                Err(error) => return Some(Err(error.to_string())),
            };
            let mut pixels = Vec::with_capacity(width * height);
            for row in 0..height {
                let start = row * readback.bytes_per_row as usize;
                pixels.extend(
                    view[start..start + width * 4]
                        .chunks_exact(4)
                        .map(|texel| [texel[0], texel[1], texel[2], 255]),
                );
            }
            pixels
        };
        readback.buffer.unmap();
        Some(Ok((width, height, picture)))
    }

    /// Whether a picture is on its way back.
    pub fn picture_pending(&self) -> bool {
        self.readback.is_some()
    }

    /// Whether every layer of the last frame is on the GPU (if not, the view keeps its last
    /// picture, and needs another frame for the rest).
    pub fn uploaded(&self) -> bool {
        [
            &self.mesh,
            &self.highlights,
            &self.boxes,
            &self.segments,
            &self.quads,
        ]
        .iter()
        .all(|layer| layer.complete())
    }

    /// Draws `scene` into a `size` (pixels) target and returns the egui texture showing it.
    pub fn draw(&mut self, gpu: &Gpu, size: [u32; 2], scene: &Scene3d<'_>) -> egui::TextureId {
        let state = &gpu.render_state;
        let pipelines = gpu.pipelines();
        let size = [size[0].clamp(1, 8192), size[1].clamp(1, 8192)];
        make_target(&mut self.target, state, size);
        let Some(target) = &self.target else {
            return egui::TextureId::default();
        };
        // The same camera, layers and size as the frame before: its picture is still there.
        let frame = super::revision_of((
            scene.view_proj.to_cols_array().map(f32::to_bits),
            [
                scene.mesh.0,
                scene.highlights.0,
                scene.boxes.0,
                scene.segments.0,
                scene.quads.0,
            ],
            [
                scene.mesh.1.len(),
                scene.highlights.1.len(),
                scene.boxes.1.len(),
            ],
            [scene.segments.1.len(), scene.quads.1.len()],
            size,
            scene.line_width.to_bits(),
            scene.hidden_edges,
            scene.wireframe,
            scene.background,
        ));
        if self.drawn == Some(frame) {
            return target.texture_id;
        }
        self.drawn = Some(frame);
        let (color_view, depth_view, texture_id) = (
            target
                .color
                .create_view(&wgpu::TextureViewDescriptor::default()),
            &target.depth_view,
            target.texture_id,
        );

        for (layer, (revision, triangles)) in [
            (&mut self.mesh, scene.mesh),
            (&mut self.highlights, scene.highlights),
        ] {
            layer.update(state, revision, triangles.len(), TRIANGLE_BYTES, |range| {
                mesh_bytes(&triangles[range])
            });
        }
        for (layer, (revision, instances)) in [
            (&mut self.boxes, scene.boxes),
            (&mut self.segments, scene.segments),
            (&mut self.quads, scene.quads),
        ] {
            layer.update(state, revision, instances.len(), INSTANCE_BYTES, |range| {
                instance_bytes(&instances[range])
            });
        }
        if !self.uploaded() {
            // Not all there yet: the picture before stays until it is, rather than drawing a
            // part of a mesh once per piece (on a software GPU each of those draws would cost
            // as much as the whole).
            self.drawn = None;
            return texture_id;
        }

        let (uniform_buffer, bind_group) = self.uniforms.get_or_insert_with(|| {
            let buffer = state.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accelviz 3d uniforms"),
                size: UNIFORM_BYTES,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = state.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("accelviz 3d uniforms"),
                layout: &pipelines.bind_group_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            (buffer, bind_group)
        });
        let light = scene.light.normalize_or_zero().as_vec3();
        let mut uniforms = Vec::with_capacity(UNIFORM_BYTES as usize);
        for value in scene.view_proj.to_cols_array() {
            uniforms.extend_from_slice(&value.to_le_bytes());
        }
        let hidden_alpha = match scene.hidden_edges {
            HiddenEdges::Dimmed => 0.18f32,
            HiddenEdges::Hidden => 0.0,
        };
        for value in [
            size[0] as f32,
            size[1] as f32,
            scene.line_width,
            hidden_alpha,
            light.x,
            light.y,
            light.z,
            0.35,
            f32::from(u8::from(scene.wireframe)),
            0.0,
            0.0,
            0.0,
        ] {
            uniforms.extend_from_slice(&value.to_le_bytes());
        }
        state.queue.write_buffer(uniform_buffer, 0, &uniforms);

        let mut encoder = state
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("accelviz 3d"),
            });
        {
            let [r, g, b] = scene.background.map(srgb_byte_to_linear);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("accelviz 3d"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        // The target holds sRGB-encoded bytes: clear with the encoded value.
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: linear_to_srgb(r),
                            g: linear_to_srgb(g),
                            b: linear_to_srgb(b),
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_bind_group(0, &*bind_group, &[]);
            // Opaque surfaces first, writing depth; then what is seen through or over them.
            if let Some((slice, triangles)) = self.mesh.slice(TRIANGLE_BYTES) {
                pass.set_pipeline(&pipelines.mesh);
                pass.set_vertex_buffer(0, slice);
                pass.draw(0..triangles * 3, 0..1);
            }
            if let Some((slice, triangles)) = self.highlights.slice(TRIANGLE_BYTES) {
                pass.set_vertex_buffer(0, slice);
                // Highlighted triangles behind the surface (a selected cell's at the back, a
                // tested triangle inside) shine through it faintly, as hidden box edges do.
                if scene.hidden_edges == HiddenEdges::Dimmed {
                    pass.set_pipeline(&pipelines.highlight_hidden);
                    pass.draw(0..triangles * 3, 0..1);
                }
                pass.set_pipeline(&pipelines.highlight);
                pass.draw(0..triangles * 3, 0..1);
            }
            if let Some((slice, quads)) = self.quads.slice(INSTANCE_BYTES) {
                pass.set_pipeline(&pipelines.quads);
                pass.set_vertex_buffer(0, slice);
                pass.draw(0..6, 0..quads);
            }
            for (layer, vertices, hidden, visible) in [
                (&self.boxes, 72, &pipelines.boxes_hidden, &pipelines.boxes),
                (
                    &self.segments,
                    6,
                    &pipelines.segments_hidden,
                    &pipelines.segments,
                ),
            ] {
                let Some((slice, instances)) = layer.slice(INSTANCE_BYTES) else {
                    continue;
                };
                pass.set_vertex_buffer(0, slice);
                if scene.hidden_edges == HiddenEdges::Dimmed {
                    pass.set_pipeline(hidden);
                    pass.draw(0..vertices, 0..instances);
                }
                pass.set_pipeline(visible);
                pass.draw(0..vertices, 0..instances);
            }
        }
        state.queue.submit(Some(encoder.finish()));
        texture_id
    }
}

/// The target at `size`, made or remade (and registered with egui) when the size changes.
fn make_target(slot: &mut Option<Target>, state: &RenderState, size: [u32; 2]) {
    if slot.as_ref().is_some_and(|target| target.size == size) {
        return;
    }
    let extent = wgpu::Extent3d {
        width: size[0],
        height: size[1],
        depth_or_array_layers: 1,
    };
    let texture = |label, format, usage| {
        state.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let color = texture(
        "accelviz 3d colour",
        COLOR_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = texture(
        "accelviz 3d depth",
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
    let mut renderer = state.renderer.write();
    let texture_id = match slot.as_ref() {
        Some(old) => {
            renderer.update_egui_texture_from_wgpu_texture(
                &state.device,
                &color_view,
                wgpu::FilterMode::Linear,
                old.texture_id,
            );
            old.texture_id
        }
        None => {
            renderer.register_native_texture(&state.device, &color_view, wgpu::FilterMode::Linear)
        }
    };
    drop(renderer);
    *slot = Some(Target {
        size,
        color,
        depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
        texture_id,
    })
}

fn srgb_byte_to_linear(byte: u8) -> f64 {
    let c = f64::from(byte) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The clear colour's value: wgpu clears an Rgba8Unorm target with the number given, which
/// must be the sRGB-encoded one egui expects.
fn linear_to_srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Triangles as mesh vertices (flat normals: each corner carries its face's normal).
fn mesh_bytes(triangles: &[DrawTriangle]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(triangles.len() * 3 * MESH_VERTEX_BYTES as usize);
    for triangle in triangles {
        let [a, b, c] = triangle.corners.map(glam::Vec3::from_array);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        let normal = [normal.x, normal.y, normal.z, 0.0]
            .map(|x| ((x * 127.0).round() as i8).to_le_bytes()[0]);
        for corner in triangle.corners {
            for value in corner {
                bytes.extend_from_slice(&value.to_le_bytes());
            }
            bytes.extend_from_slice(&normal);
            bytes.extend_from_slice(&triangle.color);
        }
    }
    bytes
}

fn instance_bytes(instances: &[Instance]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(instances.len() * INSTANCE_BYTES as usize);
    for instance in instances {
        for value in instance.a.iter().chain(&instance.b) {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes.extend_from_slice(&instance.color);
    }
    bytes
}

/// The 3D view's pipelines.
struct Pipelines {
    bind_group_layout: wgpu::BindGroupLayout,
    mesh: wgpu::RenderPipeline,
    highlight: wgpu::RenderPipeline,
    highlight_hidden: wgpu::RenderPipeline,
    boxes: wgpu::RenderPipeline,
    boxes_hidden: wgpu::RenderPipeline,
    segments: wgpu::RenderPipeline,
    segments_hidden: wgpu::RenderPipeline,
    quads: wgpu::RenderPipeline,
}

impl Pipelines {
    fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("accelviz 3d"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("accelviz 3d uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(UNIFORM_BYTES),
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("accelviz 3d"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let mesh_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Snorm8x4, 2 => Unorm8x4];
        let instance_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Unorm8x4];
        let mesh_layout = wgpu::VertexBufferLayout {
            array_stride: MESH_VERTEX_BYTES,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attributes,
        };
        let instance_layout = wgpu::VertexBufferLayout {
            array_stride: INSTANCE_BYTES,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &instance_attributes,
        };
        let alpha_blend = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::SrcAlpha,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let pipeline = |label: &str,
                        vertex: &str,
                        fragment: &str,
                        buffer: &wgpu::VertexBufferLayout<'_>,
                        depth_write: bool,
                        compare: wgpu::CompareFunction| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vertex),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[Some(buffer.clone())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(compare),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: COLOR_FORMAT,
                        blend: Some(alpha_blend),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        use wgpu::CompareFunction::{Greater, Less, LessEqual};
        Self {
            mesh: pipeline("mesh", "vs_mesh", "fs_mesh", &mesh_layout, true, Less),
            highlight: pipeline(
                "highlight",
                "vs_mesh",
                "fs_color",
                &mesh_layout,
                false,
                LessEqual,
            ),
            highlight_hidden: pipeline(
                "highlight hidden",
                "vs_mesh",
                "fs_color_hidden",
                &mesh_layout,
                false,
                Greater,
            ),
            boxes: pipeline(
                "boxes",
                "vs_box",
                "fs_line",
                &instance_layout,
                false,
                LessEqual,
            ),
            boxes_hidden: pipeline(
                "boxes hidden",
                "vs_box",
                "fs_line_hidden",
                &instance_layout,
                false,
                Greater,
            ),
            segments: pipeline(
                "segments",
                "vs_segment",
                "fs_line",
                &instance_layout,
                false,
                LessEqual,
            ),
            segments_hidden: pipeline(
                "segments hidden",
                "vs_segment",
                "fs_line_hidden",
                &instance_layout,
                false,
                Greater,
            ),
            quads: pipeline("quads", "vs_quad", "fs_line", &instance_layout, false, Less),
            bind_group_layout,
        }
    }
}
