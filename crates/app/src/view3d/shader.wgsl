// The 3D view's shaders: a flat-shaded mesh, and lines (box edges, segments) and translucent
// quads spanned in the vertex shader from instance attributes, so everything runs on WebGL2
// (no storage buffers, no compute). Colours arrive as sRGB bytes and leave sRGB-encoded:
// egui shows the target as an ordinary (not sRGB-aware) texture.

struct Uniforms {
    // World (minus the scene's origin) to clip space.
    view_proj: mat4x4<f32>,
    // Target width and height in pixels, line width in pixels, alpha of hidden lines.
    viewport: vec4<f32>,
    // Direction towards the light (the eye), and the ambient share.
    light: vec4<f32>,
    // x: 1 to draw the mesh's triangle edges (wireframe), 0 not; the rest unused.
    style: vec4<f32>,
};

@group(0) @binding(0) var<uniform> uniforms: Uniforms;

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, c * 12.92, c <= vec3<f32>(0.0031308));
}

// ---- mesh ----

struct MeshOut {
    @builtin(position) position: vec4<f32>,
    @location(0) color: vec4<f32>,
    // The corner's barycentric coordinates: (1,0,0), (0,1,0), (0,0,1), so a fragment's
    // smallest one says how near it lies to an edge.
    @location(1) corner: vec3<f32>,
};

@vertex
fn vs_mesh(
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) color: vec4<f32>,
) -> MeshOut {
    var out: MeshOut;
    out.position = uniforms.view_proj * vec4<f32>(position, 1.0);
    // Triangles are drawn without an index buffer: vertex 3k + i is corner i.
    let corner = index % 3u;
    out.corner = vec3<f32>(f32(corner == 0u), f32(corner == 1u), f32(corner == 2u));
    // Two-sided: a triangle seen from behind is lit like its front.
    let facing = abs(dot(normalize(normal.xyz), uniforms.light.xyz));
    let shade = uniforms.light.w + (1.0 - uniforms.light.w) * facing;
    out.color = vec4<f32>(linear_to_srgb(srgb_to_linear(color.rgb) * shade), color.a);
    return out;
}

@fragment
fn fs_color(in: MeshOut) -> @location(0) vec4<f32> {
    return in.color;
}

// Highlighted triangles behind a surface, drawn faint (x-ray), as hidden lines are.
@fragment
fn fs_color_hidden(in: MeshOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color.rgb, in.color.a * min(1.0, 2.8 * uniforms.viewport.w));
}

// The mesh, with its triangles' edges drawn a pixel wide over it when asked (wireframe): the
// distance to the nearest edge in pixels is the smallest barycentric coordinate over its
// change per pixel (a screen-space derivative, which WebGL2 has too).
@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    let pixels = in.corner / max(fwidth(in.corner), vec3<f32>(1e-6));
    let edge = 1.0 - smoothstep(0.5, 1.5, min(pixels.x, min(pixels.y, pixels.z)));
    let line = vec3<f32>(0.16, 0.2, 0.28);
    return vec4<f32>(mix(in.color.rgb, line, edge * uniforms.style.x * 0.85), in.color.a);
}

// ---- lines and quads from instances (a, b, colour) ----

struct Instance {
    @location(0) a: vec3<f32>,
    @location(1) b: vec3<f32>,
    @location(2) color: vec4<f32>,
};

// A line's end `end` (0 or 1) on side `side` (-1 or 1): a quad `width` pixels wide around
// the segment from a to b, with the segment's part behind the eye cut off.
fn line_vertex(a: vec3<f32>, b: vec3<f32>, end: f32, side: f32) -> vec4<f32> {
    var clip_a = uniforms.view_proj * vec4<f32>(a, 1.0);
    var clip_b = uniforms.view_proj * vec4<f32>(b, 1.0);
    let near = 1e-5;
    if (clip_a.w < near && clip_b.w < near) {
        return vec4<f32>(0.0, 0.0, -2.0, 1.0); // wholly behind: outside the clip volume
    }
    if (clip_a.w < near) {
        clip_a = mix(clip_a, clip_b, (near - clip_a.w) / (clip_b.w - clip_a.w));
    }
    if (clip_b.w < near) {
        clip_b = mix(clip_b, clip_a, (near - clip_b.w) / (clip_a.w - clip_b.w));
    }
    let size = uniforms.viewport.xy;
    let screen_a = clip_a.xy / clip_a.w * size * 0.5;
    let screen_b = clip_b.xy / clip_b.w * size * 0.5;
    var along = screen_b - screen_a;
    if (dot(along, along) < 1e-12) {
        along = vec2<f32>(1.0, 0.0);
    }
    let normal = normalize(vec2<f32>(-along.y, along.x));
    let here = select(clip_a, clip_b, end > 0.5);
    let offset = normal * side * uniforms.viewport.z * 0.5 / (size * 0.5) * here.w;
    // Lines lie on the surfaces they outline: pull them slightly towards the eye.
    let z = max(here.z - 2e-4 * here.w, 0.0);
    return vec4<f32>(here.xy + offset, z, here.w);
}

// The six corners of a quad as (end, side) pairs, two triangles.
fn quad_corner(corner: u32) -> vec2<f32> {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    return corners[corner];
}

struct LineOut {
    @builtin(position) position: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_segment(@builtin(vertex_index) index: u32, instance: Instance) -> LineOut {
    let corner = quad_corner(index % 6u);
    var out: LineOut;
    out.position = line_vertex(instance.a, instance.b, corner.x, corner.y);
    out.color = instance.color;
    return out;
}

// A box's twelve edges (corner numbers: bit 0 x, bit 1 y, bit 2 z), six vertices each.
@vertex
fn vs_box(@builtin(vertex_index) index: u32, instance: Instance) -> LineOut {
    var edges = array<vec2<u32>, 12>(
        vec2<u32>(0u, 1u), vec2<u32>(2u, 3u), vec2<u32>(4u, 5u), vec2<u32>(6u, 7u),
        vec2<u32>(0u, 2u), vec2<u32>(1u, 3u), vec2<u32>(4u, 6u), vec2<u32>(5u, 7u),
        vec2<u32>(0u, 4u), vec2<u32>(1u, 5u), vec2<u32>(2u, 6u), vec2<u32>(3u, 7u),
    );
    let edge = edges[min(index / 6u, 11u)];
    let corner = quad_corner(index % 6u);
    let start = select(instance.a, instance.b, vec3<bool>((edge.x & 1u) != 0u, (edge.x & 2u) != 0u, (edge.x & 4u) != 0u));
    let end = select(instance.a, instance.b, vec3<bool>((edge.y & 1u) != 0u, (edge.y & 2u) != 0u, (edge.y & 4u) != 0u));
    var out: LineOut;
    out.position = line_vertex(start, end, corner.x, corner.y);
    out.color = instance.color;
    return out;
}

// A flat box (one axis with no extent) as a translucent quad.
@vertex
fn vs_quad(@builtin(vertex_index) index: u32, instance: Instance) -> LineOut {
    let extent = abs(instance.b - instance.a);
    var u = vec3<f32>(0.0);
    var v = vec3<f32>(0.0);
    if (extent.x <= extent.y && extent.x <= extent.z) {
        u = vec3<f32>(0.0, instance.b.y - instance.a.y, 0.0);
        v = vec3<f32>(0.0, 0.0, instance.b.z - instance.a.z);
    } else if (extent.y <= extent.z) {
        u = vec3<f32>(instance.b.x - instance.a.x, 0.0, 0.0);
        v = vec3<f32>(0.0, 0.0, instance.b.z - instance.a.z);
    } else {
        u = vec3<f32>(instance.b.x - instance.a.x, 0.0, 0.0);
        v = vec3<f32>(0.0, instance.b.y - instance.a.y, 0.0);
    }
    let corner = quad_corner(index % 6u);
    let point = instance.a + u * corner.x + v * (corner.y * 0.5 + 0.5);
    var out: LineOut;
    out.position = uniforms.view_proj * vec4<f32>(point, 1.0);
    out.color = instance.color;
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}

// Lines behind a surface, drawn faint (x-ray).
@fragment
fn fs_line_hidden(in: LineOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color.rgb, in.color.a * uniforms.viewport.w);
}
