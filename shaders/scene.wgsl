// vpcut's one shader module: the cut part (flat-shaded triangles with the deviation colours)
// and lines (toolpath, feature edges, the ideal profile on a section plane).
//
// Positions are mm in the part frame. Colours arrive as sRGB bytes (the same bytes the
// legend and the developed view use) and are turned into linear light here; the render
// target is an sRGB format, so a face lit at full strength shows exactly its legend colour.
//
// Section views cut the part with a plane through its axis: fragments on the camera's side
// of it are discarded. The cut face is then capped the classic way: the clipped surface is
// drawn once more into the stencil buffer only, inverting it per fragment, so a pixel whose
// ray crosses the remaining surface an odd number of times starts inside the material; a
// quad on the plane, drawn with `fs_flat` where the stencil is odd, is the solid cut face
// whose outline is the machined profile, and it hides what lies behind it.

struct Uniforms {
    view_proj: mat4x4<f32>,
    // Unit vector towards the light (world).
    light: vec4<f32>,
    // Unit vector towards the camera (world); orthographic views have one.
    eye: vec4<f32>,
    // Section plane (normal xyz, offset w): fragments with dot(n, p) > w are cut away.
    plane: vec4<f32>,
    // x: 1 when the section plane is on; y: how far lines are pulled towards the camera
    // (clip-space depth, so they win against the surface they lie on).
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

fn to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + vec3<f32>(0.055)) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

fn cut_away(p: vec3<f32>) -> bool {
    return u.params.x > 0.5 && dot(u.plane.xyz, p) > u.plane.w;
}

@vertex
fn vs_mesh(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.colour = v.colour;
    return out;
}

@fragment
fn fs_mesh(in: VertexOut) -> @location(0) vec4<f32> {
    // Derivatives first, in uniform control flow: the face normal of flat shading.
    let n0 = cross(dpdx(in.world), dpdy(in.world));
    if cut_away(in.world) {
        discard;
    }
    var n = normalize(n0);
    if dot(n, u.eye.xyz) < 0.0 {
        n = -n;
    }
    // A key light and a weaker fill from the camera, so no visible face goes black.
    let key = max(dot(n, u.light.xyz), 0.0);
    let fill = max(dot(n, u.eye.xyz), 0.0);
    let shade = 0.22 + 0.58 * key + 0.20 * fill;
    return vec4<f32>(to_linear(in.colour.rgb) * min(shade, 1.0), 1.0);
}

// The cap: a quad on the section plane, unshaded, drawn where the stencil says the plane
// lies inside the material.
@fragment
fn fs_flat(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(to_linear(in.colour.rgb), 1.0);
}

@vertex
fn vs_line(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.clip.z = out.clip.z - u.params.y * out.clip.w;
    out.world = v.position;
    out.colour = v.colour;
    return out;
}

// Lines are blended by their alpha: 1 for most, less for a dimmed toolpath.
@fragment
fn fs_line(in: VertexOut) -> @location(0) vec4<f32> {
    if cut_away(in.world) {
        discard;
    }
    return vec4<f32>(to_linear(in.colour.rgb), in.colour.a);
}
