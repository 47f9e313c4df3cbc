//! Headless pictures of a [`Scene`] with wgpu: the cut part flat-shaded in its deviation
//! colours, the toolpath, optional feature edges, the ideal profile on section planes, and a
//! legend (colour bar with mm values, the job, the verdict, the view) in a strip above the
//! part whose height and text follow the picture's size, so it never covers the part.
//!
//! No window and no surface: an offscreen target is drawn and read back, so the same code runs
//! on a GPU or on Mesa's software Vulkan (lavapipe) in CI. The 3D part is drawn by the GPU
//! (`gpu`, `shaders/scene.wgsl`); cameras are plain arithmetic (`camera`); captions, the
//! colour bar and the close-up marker are drawn with plotters in the same embedded font as
//! the pictures that need no GPU ([`crate::output::plot`]).
//!
//! Deterministic: the geometry sent to the GPU does not depend on the thread count, and a
//! picture of the same scene on the same adapter has the same bytes. The PNG's text chunks
//! record the adapter, driver and backend that drew it.

mod camera;
mod gpu;
mod look;

pub use camera::View;

use crate::output::plot::chart::Area;
use crate::output::plot::chart::{legend_row, picture_on, rgb, text_px, Res, Swatch};
use crate::output::plot::chart::{BAND_EDGES, GOUGE_BANDS, LEFTOVER_BANDS, WITHIN};
use crate::output::plot::{BLANK, BODY_RUB, CUT_NOT_COMPARED, IDEAL_COLOUR};
use crate::output::scene::{Mesh, PathKind, Scene};
use camera::Camera;
use glam::DVec3;
use gpu::{Frame, Gpu, Uniforms, Vertex};
use image::RgbImage;
use look::Look;
use plotters::prelude::*;
use std::collections::HashMap;

/// The shader source (WGSL), validated by naga in the tests.
pub const SHADER: &str = include_str!("../../../shaders/scene.wgsl");

/// Background (sRGB).
const BACKGROUND: [u8; 3] = [244, 244, 240];
/// Colour of the material on a section plane (sRGB).
const CAP: [u8; 3] = [168, 176, 190];
/// Toolpath colours (sRGB): feeds and rapids.
/// Feeds are lime green: no colour of the deviation map (the leftover bands are oranges),
/// nor the body rub's violet nor the ideal's teal.
const FEED: [u8; 3] = [100, 175, 0];
const RAPID: [u8; 3] = [90, 90, 90];
/// Feature edges and the ideal profile on a section plane (sRGB).
const EDGE: [u8; 3] = [35, 35, 35];
const IDEAL: [u8; 3] = IDEAL_COLOUR;
/// Edges between faces that meet at more than this angle are drawn with `edges`.
const FEATURE_ANGLE_DEG: f64 = 35.0;

/// A picture that cannot be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No graphics adapter (no GPU and no software Vulkan).
    #[error("no graphics adapter: {0}. Without a GPU install Mesa's software Vulkan (apt-get install -y libvulkan1 mesa-vulkan-drivers)")]
    NoAdapter(String),
    /// The adapter cannot do what is asked (size, multisampling, buffer size).
    #[error("the graphics adapter cannot draw this: {0}")]
    Unsupported(String),
    /// Options out of range.
    #[error("{0}")]
    Options(String),
    /// The device failed while drawing.
    #[error("the graphics device failed: {0}")]
    Device(String),
}

/// What to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// The camera.
    pub view: View,
    /// Image width in pixels: a multiple of 64 (rows are read back in 256-byte units), at
    /// least 256.
    pub width: u32,
    /// Image height in pixels, at least 192.
    pub height: u32,
    /// Draw the feature edges (crests, roots, flank corners) as dark lines.
    pub edges: bool,
    /// How to draw the toolpath (whole-part views only: sections leave it out).
    pub toolpath: ToolpathMode,
}

/// How the whole-part views draw the toolpath.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum ToolpathMode {
    /// As the picture allows: in full while its lines cross at most 12 % of the part's
    /// pixels, translucent up to 30 %, left out beyond (the caption says which and why).
    #[default]
    Auto,
    /// Always in full.
    Full,
    /// Never.
    Off,
}

impl ToolpathMode {
    /// The mode of a command-line name (`auto`, `full`, `off`).
    pub fn from_name(name: &str) -> Option<ToolpathMode> {
        match name {
            "auto" => Some(ToolpathMode::Auto),
            "full" => Some(ToolpathMode::Full),
            "off" => Some(ToolpathMode::Off),
            _ => None,
        }
    }
}

/// Whether the scene is of an internal thread (its views are cut away to show the bore).
pub(crate) fn is_internal(scene: &Scene) -> bool {
    camera::internal(scene)
}

/// Whether a picture of `scene` draws the tool ([`camera::draws_tool`]).
pub(crate) fn draws_tool(scene: &Scene) -> bool {
    camera::draws_tool(scene)
}

/// How the HTML viewer shows the toolpath at first (`full`, `dimmed` or `hidden`: the
/// renders' automatic rule on the iso view at 1024 x 768) and the fraction of the part's
/// pixels its lines cross there.
pub(crate) fn default_toolpath_look(scene: &Scene) -> (&'static str, f64) {
    let cam = camera::camera(scene, View::Iso, 1024, 768 - strip_height(1024, 768));
    let c = look::coverage(scene, &cam);
    (Look::of(c).name(), c)
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            view: View::Iso,
            width: 1024,
            height: 768,
            edges: false,
            toolpath: ToolpathMode::Auto,
        }
    }
}

impl RenderOptions {
    /// The largest picture side vpcut draws (pixels), whatever the adapter allows: 8192 x
    /// 8192 with 4x multisampling already needs about 2.5 GB of graphics memory.
    pub const MAX_SIDE: u32 = 8192;

    /// Whether the size is one vpcut draws: the width a multiple of 64 from 256, the height
    /// from 192, neither over [`RenderOptions::MAX_SIDE`]. Needs no adapter ([`Renderer::check`] also
    /// checks the adapter's limit).
    pub fn validate(&self) -> Result<(), RenderError> {
        const MAX_SIDE: u32 = RenderOptions::MAX_SIDE;
        let (w, h) = (self.width, self.height);
        if w % 64 != 0 || w < 256 || h < 192 || w > MAX_SIDE || h > MAX_SIDE {
            return Err(RenderError::Options(format!(
                "image size {w}x{h}: the width must be a multiple of 64 from 256 to {MAX_SIDE}, the height from 192 to {MAX_SIDE}"
            )));
        }
        Ok(())
    }
}

/// The picture's memory could not be had (a refusal, not an abort).
fn out_of_memory(bytes: usize) -> RenderError {
    RenderError::Device(format!(
        "out of memory for a {} MB picture buffer: draw a smaller picture",
        bytes >> 20
    ))
}

/// A headless renderer on one adapter.
pub struct Renderer {
    gpu: Gpu,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("adapter", &self.adapter())
            .field("samples", &self.gpu.samples)
            .finish()
    }
}

impl Renderer {
    /// A renderer with `samples`x multisampling (1 or 4) on the adapter wgpu picks
    /// (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME` select one).
    pub fn new(samples: u32) -> Result<Renderer, RenderError> {
        if samples != 1 && samples != 4 {
            return Err(RenderError::Options(format!(
                "{samples}x multisampling: 1 or 4 are supported"
            )));
        }
        Ok(Renderer {
            gpu: Gpu::new(samples)?,
        })
    }

    /// The adapter: name, backend and driver, as recorded in the PNGs.
    pub fn adapter(&self) -> String {
        let i = &self.gpu.info;
        format!(
            "{} ({:?}; driver {} {})",
            i.name, i.backend, i.driver, i.driver_info
        )
    }

    /// Whether this adapter can draw pictures of `opts`' size: [`RenderOptions::validate`]
    /// and the adapter's largest texture. Callers check before the work that leads up to
    /// the picture.
    pub fn check(&self, opts: &RenderOptions) -> Result<(), RenderError> {
        opts.validate()?;
        self.gpu.check_size(opts.width, opts.height)
    }

    /// Draw `scene` as `opts` say.
    pub fn render(&self, scene: &Scene, opts: &RenderOptions) -> Result<RgbImage, RenderError> {
        self.check(opts)?;
        // The legend's strip above the part; the GPU draws the rest.
        let strip = strip_height(opts.width, opts.height);
        let gpu_h = opts.height - strip;
        let cam = camera::camera(scene, opts.view, opts.width, gpu_h);
        let stock = vertices(&scene.stock);
        let tool = vertices(&scene.tool);
        let mut lines = Vec::new();
        let mut faint = Vec::new();
        let (path_look, coverage) = toolpath_look(scene, opts, &cam);
        let (alpha, into) = match path_look {
            Look::Dimmed => ((look::DIM_ALPHA * 255.0).round() as u8, &mut faint),
            _ => (255, &mut lines),
        };
        if path_look != Look::Hidden {
            for p in &scene.toolpath {
                let c = match p.kind {
                    PathKind::Feed => FEED,
                    PathKind::Rapid => RAPID,
                };
                for w in p.points.windows(2) {
                    into.push(vertex_a(w[0], c, alpha));
                    into.push(vertex_a(w[1], c, alpha));
                }
            }
        }
        if opts.edges {
            for [a, b] in feature_edges(&scene.stock, FEATURE_ANGLE_DEG) {
                lines.push(vertex(scene.stock.positions[a as usize], EDGE));
                lines.push(vertex(scene.stock.positions[b as usize], EDGE));
            }
        }
        if let (Some(plane), Some(ideal)) = (cam.plane, &scene.ideal) {
            // Just behind the plane, so the cut does not take the line away.
            let n = plane.truncate();
            let nudge = -n * (0.25 * cam.mm_per_px).max(1e-4);
            for [a, b] in plane_section(ideal, n) {
                for p in [a, b] {
                    let q = p + nudge;
                    lines.push(vertex([q.x as f32, q.y as f32, q.z as f32], IDEAL));
                }
            }
        }
        let uniforms = uniforms(&cam);
        let frame = Frame {
            size: (opts.width, gpu_h),
            background: BACKGROUND,
            uniforms,
            // An internal thread's views show the bore: the tool in it would hide the thread.
            meshes: if !draws_tool(scene) {
                vec![(&stock, &scene.stock.indices)]
            } else {
                vec![(&stock, &scene.stock.indices), (&tool, &scene.tool.indices)]
            },
            cap: cam
                .cap_quad()
                .map(|q| q.map(|p| vertex([p.x as f32, p.y as f32, p.z as f32], CAP))),
            lines: &lines,
            faint: &faint,
        };
        let rgba = self.gpu.draw(&frame)?;
        let n = 3 * opts.width as usize * opts.height as usize;
        let top = 3 * opts.width as usize * strip as usize;
        let mut rgb = Vec::new();
        rgb.try_reserve_exact(n).map_err(|_| out_of_memory(n))?;
        rgb.resize(top, 255);
        rgb.extend(
            rgba.chunks_exact(4)
                .take((n - top) / 3)
                .flat_map(|p| [p[0], p[1], p[2]]),
        );
        drop(rgba);
        let path = (path_look, coverage);
        Ok(picture_on(rgb, opts.width, opts.height, |root| {
            overlay(root, scene, opts, &cam, strip, path)
        }))
    }

    /// Draw `scene` and encode it as PNG, with the adapter, the view and vpcut's version in
    /// text chunks (no time stamp: the same picture gives the same bytes).
    pub fn png(&self, scene: &Scene, opts: &RenderOptions) -> Result<Vec<u8>, RenderError> {
        let img = self.render(scene, opts)?;
        let i = &self.gpu.info;
        let text = [
            ("Software", format!("vpcut {}", env!("CARGO_PKG_VERSION"))),
            ("vpcut view", opts.view.name().to_string()),
            ("vpcut adapter", i.name.clone()),
            ("vpcut backend", format!("{:?}", i.backend)),
            ("vpcut driver", format!("{} {}", i.driver, i.driver_info)),
            ("vpcut samples", self.gpu.samples.to_string()),
        ];
        encode_png(&img, &text).map_err(|e| RenderError::Device(format!("PNG encoding: {e}")))
    }
}

/// An RGB image as PNG bytes with Latin-1 text chunks.
pub fn encode_png(img: &RgbImage, text: &[(&str, String)]) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, img.width(), img.height());
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::High);
        for (k, v) in text {
            // tEXt is Latin-1: keep what survives it.
            let v: String = v.chars().filter(|c| (*c as u32) < 256).collect();
            enc.add_text_chunk(k.to_string(), v)?;
        }
        let mut w = enc.write_header()?;
        w.write_image_data(img.as_raw())?;
        w.finish()?;
    }
    Ok(out)
}

fn vertex(p: [f32; 3], c: [u8; 3]) -> Vertex {
    vertex_a(p, c, 255)
}

fn vertex_a(p: [f32; 3], c: [u8; 3], alpha: u8) -> Vertex {
    Vertex {
        position: p,
        colour: [c[0], c[1], c[2], alpha],
    }
}

/// How this picture draws the toolpath, and the fraction of the part's pixels its lines
/// would cross: sections and `Off` leave it out, `Full` draws it, `Auto` follows
/// [`Look::of`].
fn toolpath_look(scene: &Scene, opts: &RenderOptions, cam: &Camera) -> (Look, f64) {
    if cam.section_angle.is_some() || scene.toolpath.is_empty() {
        return (Look::Hidden, 0.0);
    }
    let c = look::coverage(scene, cam);
    let l = match opts.toolpath {
        ToolpathMode::Off => Look::Hidden,
        ToolpathMode::Full => Look::Full,
        ToolpathMode::Auto => Look::of(c),
    };
    (l, c)
}

fn vertices(m: &Mesh) -> Vec<Vertex> {
    m.positions
        .iter()
        .zip(&m.colors)
        .map(|(&p, &c)| vertex(p, c))
        .collect()
}

fn f4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn uniforms(cam: &Camera) -> Uniforms {
    // Key light from the upper right, in front of the part: the iso view's visible end
    // face (+z, to the right) is lit, not only the fill's glancing light.
    let light = (0.35 * cam.right + 0.75 * cam.up + 0.55 * cam.back).normalize();
    let m = cam.view_proj.to_cols_array_2d();
    Uniforms {
        view_proj: m.map(|c| c.map(|x| x as f32)),
        light: f4(light, 0.0),
        eye: f4(cam.back, 0.0),
        plane: cam.plane.map_or([0.0; 4], |p| f4(p.truncate(), p.w)),
        // Lines are pulled 0.2 % of the depth range towards the camera.
        params: [cam.plane.is_some() as u8 as f32, 0.002, 0.0, 0.0],
    }
}

/// Edges where two triangles meet at more than `angle_deg`, and edges with one triangle.
/// Sorted, so the line list does not depend on hash order.
pub(crate) fn feature_edges(m: &Mesh, angle_deg: f64) -> Vec<[u32; 2]> {
    let p = |i: u32| {
        let v = m.positions[i as usize];
        DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
    };
    let normals: Vec<DVec3> = m
        .indices
        .chunks_exact(3)
        .map(|t| {
            (p(t[1]) - p(t[0]))
                .cross(p(t[2]) - p(t[0]))
                .normalize_or_zero()
        })
        .collect();
    let mut first: HashMap<[u32; 2], usize> = HashMap::with_capacity(m.indices.len());
    let mut out = Vec::new();
    let cos = angle_deg.to_radians().cos();
    for (k, t) in m.indices.chunks_exact(3).enumerate() {
        for e in [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]] {
            let key = [e[0].min(e[1]), e[0].max(e[1])];
            match first.remove(&key) {
                Some(o) => {
                    if normals[o].dot(normals[k]) < cos {
                        out.push(key);
                    }
                }
                None => {
                    first.insert(key, k);
                }
            }
        }
    }
    out.extend(first.into_keys());
    out.sort_unstable();
    out
}

/// The segments where the triangles of `m` cross the plane through the axis with normal `n`.
pub(crate) fn plane_section(m: &Mesh, n: DVec3) -> Vec<[DVec3; 2]> {
    let p = |i: u32| {
        let v = m.positions[i as usize];
        DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
    };
    let mut out = Vec::new();
    for t in m.indices.chunks_exact(3) {
        let v = [p(t[0]), p(t[1]), p(t[2])];
        let d = v.map(|q| q.dot(n));
        let mut hits = Vec::with_capacity(2);
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            if (d[a] < 0.0) != (d[b] < 0.0) {
                let s = d[a] / (d[a] - d[b]);
                hits.push(v[a] + (v[b] - v[a]) * s);
            }
        }
        if let [a, b] = hits[..] {
            out.push([a, b]);
        }
    }
    out
}

/// The legend strip's height for a `w` x `h` picture: three rows of its text size.
fn strip_height(w: u32, h: u32) -> u32 {
    ((legend_px(w, h) * 4.6).round() as u32).min(h / 3)
}

/// The renders' text size: the plots' rule, a little smaller.
fn legend_px(w: u32, h: u32) -> f64 {
    text_px(w, h) * 0.9
}

/// What a picture of `scene` says in words (the renderer draws these; plain code, tested
/// without a GPU against the report).
#[derive(Clone, Debug, PartialEq)]
pub struct Captions {
    /// The first line above the part: the job, the verdict, the view (with the section's
    /// angles, a close-up's width), what was cut away or left out (the tool, the toolpath).
    pub title: String,
    /// The close-up's label at the worst finding: its kind, turn, flank, angle, z and
    /// value, as the report writes them.
    pub marker: Option<String>,
    /// Whether the picture draws the tool (the title says when it does not).
    pub tool_drawn: bool,
}

/// The words of a picture of `scene` drawn as `opts` say.
pub fn captions(scene: &Scene, opts: &RenderOptions) -> Captions {
    let strip = strip_height(opts.width, opts.height);
    let cam = camera::camera(scene, opts.view, opts.width, opts.height - strip);
    let path = toolpath_look(scene, opts, &cam);
    Captions {
        title: title_line(scene, opts, &cam, path),
        marker: (opts.view == View::Closeup)
            .then(|| scene.focus.as_ref().map(|f| marker_label(scene, f)))
            .flatten(),
        tool_drawn: draws_tool(scene),
    }
}

/// The title line: the job, the verdict, the view, what was cut away or left out. `path`
/// is how the toolpath was drawn and the fraction of the part its lines cross.
fn title_line(scene: &Scene, opts: &RenderOptions, cam: &Camera, path: (Look, f64)) -> String {
    let summary: serde_json::Value = serde_json::from_str(&scene.summary).unwrap_or_default();
    let job = summary["job"].as_str().unwrap_or("");
    let verdict = summary["verdict"].as_str().unwrap_or("").to_uppercase();
    let w = opts.width as i32;
    let mut caption = match cam.section_angle {
        Some(theta) => format!(
            "{}: section at {:.1}\u{b0} (top) and {:.1}\u{b0}",
            opts.view.name(),
            theta.to_degrees().rem_euclid(360.0),
            (theta.to_degrees() + 180.0).rem_euclid(360.0)
        ),
        None if cam.cutaway => format!(
            "{}, internal thread: near half cut away along the axis",
            opts.view.name()
        ),
        None => opts.view.name().to_string(),
    };
    if !scene.tool.indices.is_empty() && !draws_tool(scene) {
        caption += ", tool not drawn";
    }
    if opts.view == View::Closeup {
        caption += &format!(", {:.2} mm wide", cam.mm_per_px * w as f64);
    }
    let passes = scene
        .toolpath
        .iter()
        .filter(|p| p.kind == PathKind::Feed)
        .count();
    let share = (path.1 * 100.0).round();
    match path.0 {
        Look::Dimmed => {
            caption += &format!(", toolpath faint ({passes} passes over {share:.0} % of the part)")
        }
        Look::Hidden
            if opts.toolpath == ToolpathMode::Auto && cam.section_angle.is_none() && passes > 0 =>
        {
            caption += &format!(
                ", toolpath left out ({passes} passes would cover {share:.0} % of the part)"
            )
        }
        _ => {}
    }
    format!("{job}  {verdict}  \u{2014}  {caption}")
}

/// The close-up's label at the worst finding, in the report's numbers: kind, turn, flank,
/// angle (deg, 0.1), z (mm, 0.001) and value (mm, as the report writes it).
fn marker_label(scene: &Scene, f: &crate::output::scene::Focus) -> String {
    let flank = match f.flank.as_str() {
        "" => String::new(),
        "left" | "right" => format!(" {} flank", f.flank),
        other => format!(" {other}"),
    };
    let tol = scene.legend.tolerance_mm;
    let times = if tol > 0.0 {
        format!(" ({:.1}x tol)", f.value_mm / tol)
    } else {
        String::new()
    };
    format!(
        "worst {}: turn {}{flank}, {:.1}\u{b0}, z {:.3} mm, {} mm{times}",
        f.kind, f.turn, f.angle_deg, f.z_mm, f.value_mm
    )
}

/// Captions, the colour bar and the key in the strip above the part (`strip` rows), and
/// the close-up's marker with its turn, flank, z and value on the part. `path` is how the
/// toolpath was drawn and the fraction of the part its lines cross.
fn overlay(
    root: &Area,
    scene: &Scene,
    opts: &RenderOptions,
    cam: &Camera,
    strip: u32,
    path: (Look, f64),
) -> Res<()> {
    let (w, h) = (opts.width as i32, opts.height as i32);
    let px = legend_px(opts.width, opts.height);
    let font = |k: f64| ("sans-serif", px * k).into_font().color(&BLACK);
    root.draw(&PathElement::new(
        vec![(0, strip as i32 - 1), (w, strip as i32 - 1)],
        RGBColor(180, 180, 180),
    ))?;
    let pad = (px * 0.6) as i32;
    root.draw(&Text::new(
        title_line(scene, opts, cam, path),
        (pad, (px * 0.4) as i32),
        font(1.1),
    ))?;
    // Row 2: the tolerance bands as in the plots (gouge left, leftover right), row 3 the
    // band edges in multiples of the tolerance.
    let tol = scene.legend.tolerance_mm;
    let y_bar = (px * 1.9) as i32;
    let bar_h = (px * 0.9) as i32;
    let gw = root
        .estimate_text_size("gouge", &font(0.9))
        .map_or(0, |s| s.0 as i32);
    let bx0 = pad + gw + (px * 0.4) as i32;
    let bands: Vec<[u8; 3]> = GOUGE_BANDS
        .iter()
        .rev()
        .chain([&WITHIN])
        .chain(LEFTOVER_BANDS.iter())
        .copied()
        .collect();
    let cell = ((w as f64 * 0.33).min(px * 22.0) / bands.len() as f64).round() as i32;
    let bw = cell * bands.len() as i32;
    root.draw(&Text::new(
        "gouge",
        (bx0 - gw - (px * 0.4) as i32, y_bar),
        font(0.9),
    ))?;
    for (k, c) in bands.iter().enumerate() {
        let x = bx0 + k as i32 * cell;
        root.draw(&Rectangle::new(
            [(x, y_bar), (x + cell, y_bar + bar_h)],
            rgb(*c).filled(),
        ))?;
    }
    root.draw(&Rectangle::new(
        [(bx0, y_bar), (bx0 + bw, y_bar + bar_h)],
        RGBColor(120, 120, 120),
    ))?;
    root.draw(&Text::new(
        "leftover",
        (bx0 + bw + (px * 0.4) as i32, y_bar),
        font(0.9),
    ))?;
    let edges: Vec<f64> = BAND_EDGES
        .iter()
        .rev()
        .map(|e| -e)
        .chain(BAND_EDGES.iter().copied())
        .collect();
    let y_val = y_bar + bar_h + (px * 0.35) as i32;
    for (k, e) in edges.iter().enumerate() {
        let x = bx0 + (k as i32 + 1) * cell;
        let label = format!("{}", e.abs());
        let lw = root
            .estimate_text_size(&label, &font(0.8))
            .map_or(0, |s| s.0 as i32);
        root.draw(&PathElement::new(
            vec![(x, y_bar + bar_h), (x, y_bar + bar_h + (px * 0.3) as i32)],
            BLACK,
        ))?;
        root.draw(&Text::new(label, (x - lw / 2, y_val), font(0.8)))?;
    }
    root.draw(&Text::new(
        format!("\u{d7} tolerance {tol} mm"),
        (bx0 + bw + (px * 0.4) as i32, y_val),
        font(0.8),
    ))?;
    // Right of the bar: the lines and the other colours (row 2), the greys (row 3).
    let mut key = Vec::new();
    if path.0 != Look::Hidden {
        key.push((Swatch::Line(FEED), "feed"));
        if scene.toolpath.iter().any(|p| p.kind == PathKind::Rapid) {
            key.push((Swatch::Line(RAPID), "rapid"));
        }
    }
    if cam.plane.is_some() {
        key.push((Swatch::Fill(CAP), "cut face"));
        if scene.ideal.is_some() {
            key.push((Swatch::Line(IDEAL), "ideal profile"));
        }
    }
    if scene.stock.colors.contains(&BODY_RUB) {
        key.push((Swatch::Fill(BODY_RUB), "body rub"));
    }
    let key: Vec<(Swatch, String)> = key.into_iter().map(|(s, n)| (s, n.into())).collect();
    let greys: Vec<(Swatch, String)> = [
        (Swatch::Fill(BLANK), "uncut blank"),
        (Swatch::Fill(CUT_NOT_COMPARED), "not compared"),
    ]
    .into_iter()
    .filter(|(s, _)| match s {
        Swatch::Fill(c) => scene.stock.colors.contains(c),
        _ => false,
    })
    .map(|(s, n)| (s, n.to_string()))
    .collect();
    let lw = root
        .estimate_text_size("leftover", &font(0.9))
        .map_or(0, |s| s.0 as i32);
    let tw = root
        .estimate_text_size(&format!("\u{d7} tolerance {tol} mm"), &font(0.8))
        .map_or(0, |s| s.0 as i32);
    let kx = bx0 + bw + lw.max(tw) + (px * 1.6) as i32;
    legend_row(root, kx, y_bar, px * 0.9, &key)?;
    legend_row(root, kx, y_val, px * 0.8, &greys)?;
    // The close-up marks the worst finding: turn, flank, z, value.
    if opts.view == View::Closeup {
        if let Some(f) = &scene.focus {
            let p = DVec3::new(f.point[0] as f64, f.point[1] as f64, f.point[2] as f64);
            let (fx, fy) = cam.pixel(p);
            let (cx, cy) = (fx.round() as i32, fy.round() as i32 + strip as i32);
            let r = (px * 1.3) as i32;
            root.draw(&Circle::new((cx, cy), r + 1, WHITE.stroke_width(1)))?;
            root.draw(&Circle::new((cx, cy), r, BLACK.stroke_width(2)))?;
            let label = marker_label(scene, f);
            let (tw, th) = root
                .estimate_text_size(&label, &font(1.0))
                .map_or((0, 0), |s| (s.0 as i32, s.1 as i32));
            let lx = (cx + r + (px * 0.5) as i32).clamp(0, (w - tw - 4).max(0));
            let ly = (cy - r - th - 4).clamp(strip as i32 + 2, (h - th - 6).max(0));
            root.draw(&Rectangle::new(
                [(lx - 3, ly - 2), (lx + tw + 3, ly + th + 3)],
                WHITE.mix(0.85).filled(),
            ))?;
            root.draw(&Text::new(label, (lx, ly), font(1.0)))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed prism of `n` sides: its feature edges at 35 deg are the two rims (end faces
    /// meet the sides at 90 deg), none along the sides (360/n deg apart) nor inside the fans.
    #[test]
    fn feature_edges_of_a_prism_are_its_rims() {
        for n in [8usize, 12, 90] {
            let mut m = Mesh::default();
            for z in [0.0f32, 5.0] {
                for k in 0..n {
                    let a = std::f32::consts::TAU * k as f32 / n as f32;
                    m.positions.push([a.cos(), a.sin(), z]);
                }
            }
            m.positions.push([0.0, 0.0, 0.0]);
            m.positions.push([0.0, 0.0, 5.0]);
            let (c0, c1) = (2 * n as u32, 2 * n as u32 + 1);
            for k in 0..n as u32 {
                let k1 = (k + 1) % n as u32;
                let (a0, a1, b0, b1) = (k, k1, n as u32 + k, n as u32 + k1);
                m.indices.extend_from_slice(&[a0, a1, b1, a0, b1, b0]);
                m.indices.extend_from_slice(&[c0, a1, a0, c1, b0, b1]);
            }
            m.colors = vec![[0, 0, 0]; m.positions.len()];
            let e = feature_edges(&m, 35.0);
            let expected = if 360.0 / n as f64 > 35.0 {
                3 * n
            } else {
                2 * n
            };
            assert_eq!(e.len(), expected, "n = {n}");
            for [a, b] in &e {
                assert!(*a < 2 * n as u32 && *b < 2 * n as u32);
            }
        }
    }

    /// A plane through the axis cuts a bar's side quads in two lines along z.
    #[test]
    fn plane_section_of_a_prism_side() {
        let n = 16;
        let mut m = Mesh::default();
        for z in [0.0f32, 5.0] {
            for k in 0..n {
                let a = std::f32::consts::TAU * (k as f32 + 0.5) / n as f32;
                m.positions.push([a.cos(), a.sin(), z]);
            }
        }
        for k in 0..n as u32 {
            let k1 = (k + 1) % n as u32;
            m.indices
                .extend_from_slice(&[k, k1, n as u32 + k1, k, n as u32 + k1, n as u32 + k]);
        }
        let segs = plane_section(&m, DVec3::Y);
        // Two quads are crossed (at x > 0 and x < 0), two triangles each, each giving a
        // segment on the plane y = 0 at |x| = cos(pi/n) ... 1 (the chord's crossing).
        assert_eq!(segs.len(), 4);
        let x = (std::f64::consts::PI / n as f64).cos();
        for s in &segs {
            for p in s {
                assert!(p.y.abs() < 1e-6);
                assert!((p.x.abs() - x).abs() < 1e-6, "{p}");
            }
        }
    }
}
